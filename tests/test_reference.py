"""Tests of the NumPy reference renderer itself (hand-computed values).

These tests must not import shadelab_rs: they validate ``reference.py`` so that
it can in turn be trusted to validate the Rust renderer.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from shadelab_ref import reference as ref

# A triangle in the z = 0 plane, CCW seen from +z, centroid at the origin.
TRI_CENTRED = np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 2.0, 0.0]])
FACE0 = np.array([[0, 1, 2]])

MAT = ref.Material(
    ambient=(0.1, 0.2, 0.3),
    diffuse=(0.5, 0.4, 0.3),
    specular=(0.3, 0.3, 0.3),
    shininess=8,
)
# Id = Is = (1, 0.5, 0.25) * 2 = (2, 1, 0.5); light travels along -z, so l = +z.
LIGHT_Z = ref.DirectionalLight(direction=(0, 0, -1), color=(1.0, 0.5, 0.25), intensity=2.0)
AMB = (0.2, 0.2, 0.2)
# ka*Ia + kd*Id*1 + ks*Is*1
EXPECT_FULL = np.array([0.02 + 1.0 + 0.6, 0.04 + 0.4 + 0.3, 0.06 + 0.15 + 0.15])
# ka*Ia + kd*Id*1 (no specular)
EXPECT_NOSPEC = np.array([0.02 + 1.0, 0.04 + 0.4, 0.06 + 0.15])


def axis_camera(dist=3.0, **kw):
    """Camera on the +z axis looking at the origin."""
    return ref.Camera(eye=(0, 0, dist), target=(0, 0, 0), up=(0, 1, 0), **kw)


def render(vertices, faces, **kw):
    kw.setdefault("camera", axis_camera(fov_y=60.0))
    kw.setdefault("width", 33)
    kw.setdefault("height", 33)
    kw.setdefault("material", MAT)
    kw.setdefault("lights", [LIGHT_Z])
    kw.setdefault("ambient", AMB)
    return ref.render_reference(vertices, faces, **kw)


# --------------------------------------------------------------------------
# Lighting
# --------------------------------------------------------------------------


def test_directional_light_facing_triangle_centre_pixel():
    # 33x33 image: pixel (16, 16) has its centre at the image centre, so its
    # ray is the view axis and hits the origin; n = l = v = h = +z.
    img = render(TRI_CENTRED, FACE0, shading="phong")
    np.testing.assert_allclose(img.color[16, 16], EXPECT_FULL, rtol=0, atol=1e-12)
    assert img.tri[16, 16] == 0
    assert img.depth[16, 16] == pytest.approx(3.0, abs=1e-12)
    np.testing.assert_allclose(img.position[16, 16], [0, 0, 0], atol=1e-12)
    # Origin = centroid -> barycentrics (1/3, 1/3, 1/3).
    np.testing.assert_allclose(img.bary[16, 16], [1 / 3] * 3, atol=1e-12)
    # Background in the corner.
    assert img.tri[0, 0] == -1
    assert np.isinf(img.depth[0, 0]) and np.isinf(img.edge_dist[0, 0])
    np.testing.assert_array_equal(img.color[0, 0], [0, 0, 0])


def test_flat_shading_uses_centroid_and_face_normal():
    # The centroid is the origin, so the flat colour is the on-axis value.
    img = render(TRI_CENTRED, FACE0, shading="flat", background=(9, 9, 9))
    m = img.mask
    assert m.sum() > 50
    np.testing.assert_allclose(img.color[m], np.broadcast_to(EXPECT_FULL, (m.sum(), 3)), atol=1e-12)
    np.testing.assert_array_equal(img.color[~m], 9.0)


@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
def test_no_specular_constant_colour(shading):
    mat = ref.Material(MAT.ambient, MAT.diffuse, (0, 0, 0), 8)
    img = render(TRI_CENTRED, FACE0, shading=shading, material=mat)
    m = img.mask
    np.testing.assert_allclose(
        img.color[m], np.broadcast_to(EXPECT_NOSPEC, (m.sum(), 3)), atol=1e-12
    )


def test_point_light_blinn_and_phong_hand_values():
    # p = 0, n = +z, eye (0,0,5) -> v = +z; light at (3,0,4) -> l = (0.6,0,0.8).
    # n.l = 0.8.  Blinn: h ~ (0.6,0,1.8), n.h = 1.8/sqrt(3.6), (n.h)^2 = 0.9.
    # Phong: r = 2*0.8*n - l = (-0.6,0,0.8), r.v = 0.8, (r.v)^2 = 0.64.
    mat = ref.Material(0.0, 0.5, 0.5, 2)
    light = ref.PointLight(position=(3, 0, 4))
    p, n, eye = np.zeros(3), np.array([0, 0, 1.0]), np.array([0, 0, 5.0])
    blinn = ref.lighting(p, n, eye, mat, [light], 0.0, "blinn")
    phong = ref.lighting(p, n, eye, mat, [light], 0.0, "phong")
    np.testing.assert_allclose(blinn, [0.5 * 0.8 + 0.5 * 0.9] * 3, atol=1e-12)
    np.testing.assert_allclose(phong, [0.5 * 0.8 + 0.5 * 0.64] * 3, atol=1e-12)
    np.testing.assert_allclose(blinn - phong, [0.5 * (0.9 - 0.64)] * 3, atol=1e-12)

    # Same through the renderer at the centre pixel (ray hits the origin).
    big = np.array([[-2.0, -2, 0], [2, -2, 0], [0, 2, 0]])
    for spec, expect in (("blinn", 0.85), ("phong", 0.72)):
        img = render(
            big,
            FACE0,
            camera=axis_camera(5.0, fov_y=50.0),
            material=mat,
            lights=[light],
            ambient=0.0,
            specular=spec,
        )
        np.testing.assert_allclose(img.color[16, 16], [expect] * 3, atol=1e-12)


def test_point_light_colour_intensity_and_multiple_lights():
    # Two lights add up; Id = color * intensity.  p = 0, n = +z, eye on axis.
    mat = ref.Material((1, 1, 1), (1, 1, 1), (0, 0, 0), 1)
    lights = [
        ref.PointLight(position=(0, 0, 2), color=(1, 0, 0), intensity=0.5),  # n.l = 1
        ref.DirectionalLight(
            direction=(0, -1, -1), color=(0, 1, 0), intensity=2.0
        ),  # n.l = 1/sqrt2
    ]
    c = ref.lighting([0, 0, 0], [0, 0, 1], [0, 0, 5], mat, lights, (0.1, 0.2, 0.3))
    np.testing.assert_allclose(c, [0.1 + 0.5, 0.2 + 2 / math.sqrt(2), 0.3], atol=1e-12)


def test_light_behind_surface_gives_ambient_only():
    # l = (0.6, 0, -0.8): n.l < 0 -> no diffuse, no specular (even with shininess 0).
    mat = ref.Material(0.5, 1.0, 1.0, 0)
    c = ref.lighting([0, 0, 0], [0, 0, 1], [0, 0, 5], mat, [ref.PointLight((3, 0, -4))], 0.2)
    np.testing.assert_allclose(c, [0.1] * 3, atol=1e-15)


def test_shininess_zero_and_blinn_zero_half_vector():
    mat = ref.Material(0.0, 1.0, 1.0, 0)
    # numpy power semantics: max(n.h, 0)^0 = 1 wherever n.l > 0.
    c = ref.lighting([0, 0, 0], [0, 0, 1], [0, 0, 5], mat, [ref.PointLight((3, 0, 4))], 0.0)
    np.testing.assert_allclose(c, [0.8 + 1.0] * 3, atol=1e-12)
    # Eye below the plane, light above along the normal: l = +z, v = -z,
    # l + v = 0 -> S = 0 for Blinn even with shininess 0.
    c = ref.lighting([0, 0, 0], [0, 0, 1], [0, 0, -5], mat, [ref.PointLight((0, 0, 5))], 0.0)
    np.testing.assert_allclose(c, [1.0] * 3, atol=1e-15)
    # Phong at the same geometry: r = 2n - l = +z, r.v = -1 -> 0^0 = 1.
    c = ref.lighting(
        [0, 0, 0], [0, 0, 1], [0, 0, -5], mat, [ref.PointLight((0, 0, 5))], 0.0, "phong"
    )
    np.testing.assert_allclose(c, [2.0] * 3, atol=1e-15)


def test_lighting_is_vectorised():
    p = np.random.default_rng(0).normal(size=(4, 5, 3))
    n = ref._normalize(np.random.default_rng(1).normal(size=(4, 5, 3)))
    lights = [LIGHT_Z, ref.PointLight((1, 2, 3))]
    out = ref.lighting(p, n, (0, 0, 5), MAT, lights, AMB, "phong")
    assert out.shape == (4, 5, 3)
    one = ref.lighting(p[2, 3], n[2, 3], (0, 0, 5), MAT, lights, AMB, "phong")
    np.testing.assert_allclose(out[2, 3], one, atol=1e-15)
    # A single shared normal broadcasts against many points.
    out2 = ref.lighting(p, [0, 0, 1], (0, 0, 5), MAT, lights, AMB)
    assert out2.shape == (4, 5, 3)


# --------------------------------------------------------------------------
# Projection, barycentrics, transforms
# --------------------------------------------------------------------------


def test_edge_distance_in_pixels():
    # Triangle (-1,-1,0),(1,-1,0),(0,1,0) seen from d = 3 with fov 60 at 33 px:
    # pixels per world unit at d = 3 is (33/2) / (3 tan 30deg).  The nearest
    # edges from the origin are the slanted ones at distance 1/sqrt(5).
    tri = np.array([[-1.0, -1, 0], [1, -1, 0], [0, 1, 0]])
    img = render(tri, FACE0)
    scale = 16.5 / (3.0 * math.tan(math.radians(30.0)))
    assert img.edge_dist[16, 16] == pytest.approx(scale / math.sqrt(5.0), rel=1e-12)
    np.testing.assert_allclose(img.bary[16, 16], [0.25, 0.25, 0.5], atol=1e-12)


def test_perspective_correct_barycentrics_receding_plane():
    # Camera at the origin looking down -z with fov 90 (tan = 1), 16x16.
    # The triangle recedes from d = 1 (bottom edge) to d = 8 (apex).
    a, b, c = (
        np.array([-0.9, -0.9, -1.0]),
        np.array([0.9, -0.9, -1.0]),
        np.array([0.0, 4.0, -8.0]),
    )
    cam = ref.Camera(eye=(0, 0, 0), target=(0, 0, -1), up=(0, 1, 0), fov_y=90.0, near=0.5, far=50)
    img = render(np.stack([a, b, c]), FACE0, camera=cam, width=16, height=16, shading="gouraud")

    # Pixel (8, 10): x_ndc = 17/16 - 1, y_ndc = 1 - 21/16; ray dir (x, y, -1).
    px, py = 8, 10
    dx, dy = 2 * (px + 0.5) / 16 - 1, 1 - 2 * (py + 0.5) / 16
    # Analytic ray hit: solve alpha*a + beta*b + gamma*c = t*D, sum = 1.
    m = np.array(
        [
            [a[0], b[0], c[0], -dx],
            [a[1], b[1], c[1], -dy],
            [a[2], b[2], c[2], 1.0],
            [1.0, 1.0, 1.0, 0.0],
        ]
    )
    sol = np.linalg.solve(m, [0, 0, 0, 1])
    bary, t = sol[:3], sol[3]
    assert img.tri[py, px] == 0
    np.testing.assert_allclose(img.bary[py, px], bary, atol=1e-12)
    assert img.depth[py, px] == pytest.approx(t, rel=1e-12)
    np.testing.assert_allclose(img.position[py, px], t * np.array([dx, dy, -1]), atol=1e-12)

    # Screen-space formulation: b_i = (lambda_i / w_i) / sum_j (lambda_j / w_j).
    scr = np.array([[(v[0] / -v[2] + 1) * 8, (1 - v[1] / -v[2]) * 8] for v in (a, b, c)])
    pc = np.array([px + 0.5, py + 0.5])

    def area(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    tot = area(*scr)
    lam = (
        np.array(
            [
                area(pc, scr[1], scr[2]),
                area(scr[0], pc, scr[2]),
                area(scr[0], scr[1], pc),
            ]
        )
        / tot
    )
    w = np.array([1.0, 1.0, 8.0])
    persp = (lam / w) / np.sum(lam / w)
    np.testing.assert_allclose(img.bary[py, px], persp, atol=1e-12)
    # ... which is clearly not the affine screen-space interpolation.
    assert np.abs(persp - lam).max() > 0.05

    # Gouraud colour is the perspective-correct blend of the vertex colours.
    nrm = ref.vertex_normals(np.stack([a, b, c]), FACE0)
    vcol = ref.lighting(np.stack([a, b, c]), nrm, (0, 0, 0), MAT, [LIGHT_Z], AMB)
    np.testing.assert_allclose(img.color[py, px], bary @ vcol, atol=1e-12)


def test_orthographic_mapping():
    # Ortho height 4 at 20x10 (aspect 2): x_eye = x_ndc * 4, y_eye = y_ndc * 2.
    cam = axis_camera(5.0, ortho_height=4.0)
    big = np.array([[-10.0, -10, 0], [10, -10, 0], [0, 10, 0]])
    img = render(big, FACE0, camera=cam, width=20, height=10)
    # Pixel (13, 2): x_ndc = 27/20 - 1 = 0.35, y_ndc = 1 - 5/10 = 0.5.
    np.testing.assert_allclose(img.position[2, 13], [0.35 * 4, 0.5 * 2, 0], atol=1e-12)
    assert img.depth[2, 13] == pytest.approx(5.0, abs=1e-12)
    # Phong normal is +z everywhere, but v varies with position (local viewer).
    expect = ref.lighting(img.position[2, 13], [0, 0, 1], cam.eye, MAT, [LIGHT_Z], AMB)
    np.testing.assert_allclose(img.color[2, 13], expect, atol=1e-12)


def test_look_at_orientation():
    # Eye on +x looking at the origin: s = f x up = -z, so world -z is screen
    # right and world +y is screen up.
    cam = ref.Camera(eye=(3, 0, 0), target=(0, 0, 0), up=(0, 1, 0), fov_y=60.0)
    tri = np.array([[0.0, 0.5, -0.8], [0, 0.5, -1.2], [0, 0.9, -1.0]])
    img = render(tri, FACE0, camera=cam, width=32, height=32)
    ys, xs = np.nonzero(img.mask)
    assert len(xs) > 0
    assert xs.min() >= 16 and ys.max() < 16
    view = ref.look_at(cam.eye, cam.target, cam.up)
    np.testing.assert_allclose(view[:3, :3], [[0, 0, -1], [0, 1, 0], [1, 0, 0]], atol=1e-15)
    np.testing.assert_allclose(view @ [0, 0, 0, 1], [0, 0, -3, 1], atol=1e-15)


def test_model_transform_normals_inverse_transpose():
    # Object plane x + z = 0 (normal (1,0,1)/sqrt2), scaled by diag(2,1,1):
    # world plane x + 2z = 0, normal (1,0,2)/sqrt5 (inverse transpose), not
    # (2,0,1)/sqrt5 (which would give n.l = 4/5).
    obj = np.array([[-1.0, -1, 1], [1, -1, -1], [0, 1, 0]])
    m = np.diag([2.0, 1.0, 1.0, 1.0])
    light = ref.DirectionalLight(direction=(-1, 0, -2))
    mat = ref.Material(MAT.ambient, MAT.diffuse, 0.0, 8)
    expect = np.array([0.02, 0.04, 0.06]) + np.array(MAT.diffuse)
    given = np.tile([1 / math.sqrt(2), 0, 1 / math.sqrt(2)], (3, 1))
    for shading in ("flat", "gouraud", "phong"):
        for normals in (None, given):
            img = render(
                obj,
                FACE0,
                camera=axis_camera(5.0, fov_y=50.0),
                material=mat,
                lights=[light],
                transform=m,
                normals=normals,
                shading=shading,
            )
            np.testing.assert_allclose(img.color[16, 16], expect, atol=1e-12)
    # Translation moves the depth.
    t = np.eye(4)
    t[2, 3] = -1.0
    img = render(TRI_CENTRED, FACE0, transform=t)
    assert img.depth[16, 16] == pytest.approx(4.0, abs=1e-12)
    np.testing.assert_allclose(img.position[16, 16], [0, 0, -1], atol=1e-12)


def test_phong_zero_interpolated_normal_uses_face_normal():
    # All vertex normals zero: the interpolated normal is exactly zero, so
    # Phong shading falls back to the world face normal (+z here).
    zeros = np.zeros((3, 3))
    img = render(TRI_CENTRED, FACE0, normals=zeros, shading="phong")
    np.testing.assert_allclose(img.color[16, 16], EXPECT_FULL, atol=1e-12)
    # Gouraud has no such fallback: zero vertex normals -> ambient only.
    img = render(TRI_CENTRED, FACE0, normals=zeros, shading="gouraud")
    np.testing.assert_allclose(img.color[16, 16], [0.02, 0.04, 0.06], atol=1e-15)


# --------------------------------------------------------------------------
# Visibility, culling, near plane
# --------------------------------------------------------------------------


def _two_layers(near_first):
    far_tri = [[-3.0, -3, 0], [3, -3, 0], [0, 3, 0]]
    near_tri = [[-1.0, -1, 1], [1, -1, 1], [0, 1, 1]]
    verts = np.array(near_tri + far_tri if near_first else far_tri + near_tri)
    return verts, np.array([[0, 1, 2], [3, 4, 5]])


@pytest.mark.usefixtures("chunking")
@pytest.mark.parametrize("near_first", [True, False])
def test_nearer_triangle_wins(near_first):
    verts, faces = _two_layers(near_first)
    img = render(verts, faces, camera=axis_camera(5.0, ortho_height=4.0), width=20, height=20)
    near_idx = 0 if near_first else 1
    assert img.tri[10, 10] == near_idx
    assert img.depth[10, 10] == pytest.approx(4.0, abs=1e-12)
    assert img.tri[18, 2] == 1 - near_idx  # only the far one covers this corner
    assert img.depth[18, 2] == pytest.approx(5.0, abs=1e-12)


@pytest.fixture(params=["one_chunk", "chunk_per_triangle"])
def chunking(request, monkeypatch):
    """Run a test with all triangles in one chunk and with one chunk each."""
    if request.param == "chunk_per_triangle":
        monkeypatch.setattr(ref, "_CHUNK_PAIRS", 1)
    return request.param


@pytest.mark.usefixtures("chunking")
def test_equal_depth_lowest_index_wins():
    # Two coplanar overlapping triangles with integer coordinates: the ray
    # depths are exactly equal (d = 5) so the lower index must win.
    up = [[-1.0, -1, 0], [1, -1, 0], [0, 1, 0]]
    down = [[-1.0, 1, 0], [0, -1, 0], [1, 1, 0]]
    cam = axis_camera(5.0, ortho_height=3.0)
    for order in ((up, down), (down, up)):
        verts = np.array(order[0] + order[1])
        img = render(verts, [[0, 1, 2], [3, 4, 5]], camera=cam, width=24, height=24)
        both = img.mask & (img.depth == 5.0)
        assert np.all(img.depth[img.mask] == 5.0)
        # Pixel (12, 12) (ray at x=0.0625, y=-0.0625) lies inside both.
        assert img.tri[12, 12] == 0
        assert np.any(img.tri[both] == 1)  # the non-overlapping part of tri 1
    # Duplicated faces in perspective: identical data -> identical depth.
    img = render(TRI_CENTRED, [[0, 1, 2], [0, 1, 2]])
    assert set(np.unique(img.tri)) == {-1, 0}


def test_backface_culling_and_backface_lighting():
    cw = TRI_CENTRED[[0, 2, 1]]  # clockwise as seen from the camera
    img = render(cw, FACE0, shading="flat")
    assert img.mask.sum() > 50
    # Back face drawn with its own (away-facing) normal: n.l = -1 -> ambient only.
    np.testing.assert_allclose(
        img.color[img.mask],
        np.broadcast_to([0.02, 0.04, 0.06], (img.mask.sum(), 3)),
        atol=1e-15,
    )
    assert not render(cw, FACE0, cull_backfaces=True).mask.any()
    assert render(TRI_CENTRED, FACE0, cull_backfaces=True).mask.sum() == img.mask.sum()


def test_near_plane_crossing_floor():
    # Floor y = -1 crossing the camera plane (two vertices behind the eye).
    # fov 90, 32x32: row r has y_ndc = 1 - (2r+1)/32; a floor hit has
    # d = 1/|y_ndc| = 32/(2k+1) with k = r - 16.  The apex is at d = 20.
    floor = np.array([[-10.0, -1, 5], [10, -1, 5], [0, -1, -20]])
    for near in (2.0, 0.1):
        cam = ref.Camera(
            eye=(0, 0, 0),
            target=(0, 0, -1),
            up=(0, 1, 0),
            fov_y=90.0,
            near=near,
            far=100,
        )
        img = render(floor, FACE0, camera=cam, width=32, height=32)
        col = 15
        assert not img.mask[:17].any()  # horizon (and beyond the apex at row 16)
        for r in range(17, 32):
            d = 32.0 / (2 * (r - 16) + 1)
            if d >= near:
                assert img.tri[r, col] == 0
                assert img.depth[r, col] == pytest.approx(d, rel=1e-12)
                assert img.position[r, col, 1] == pytest.approx(-1.0, abs=1e-12)
            else:
                assert img.tri[r, col] == -1
        if near == 2.0:
            # Near clip line at y_ndc = -0.5 -> sy = 24: row 23's centre is 0.5 px away.
            assert img.edge_dist[23, col] == pytest.approx(0.5, abs=1e-9)
            assert not img.mask[24:].any()
        else:
            assert img.mask[31, col]


def test_outside_depth_range_not_drawn():
    behind = TRI_CENTRED + np.array([0, 0, 10])  # behind the eye at z = 3
    assert not render(behind, FACE0).mask.any()
    cam = axis_camera(3.0, fov_y=60.0, near=0.1, far=2.5)  # triangle at d = 3 > far
    assert not render(TRI_CENTRED, FACE0, camera=cam).mask.any()


# --------------------------------------------------------------------------
# Vertex normals and meshes
# --------------------------------------------------------------------------


def test_vertex_normals_tetrahedron():
    # Regular tetrahedron: each vertex normal points along the vertex.
    v = np.array([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]])
    f = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    fn = ref.face_normals(v, f)
    assert np.all(np.sum(fn * v[f].mean(axis=1), axis=1) > 0)  # outward
    np.testing.assert_allclose(ref.vertex_normals(v, f), v / math.sqrt(3), atol=1e-15)


CUBE_V = np.array(
    [
        [-1.0, -1, -1],
        [1, -1, -1],
        [1, 1, -1],
        [-1, 1, -1],
        [-1, -1, 1],
        [1, -1, 1],
        [1, 1, 1],
        [-1, 1, 1],
    ]
)
CUBE_F = np.array(
    [
        [4, 5, 6], [4, 6, 7],  # +z
        [0, 3, 2], [0, 2, 1],  # -z
        [1, 2, 6], [1, 6, 5],  # +x
        [0, 4, 7], [0, 7, 3],  # -x
        [3, 7, 6], [3, 6, 2],  # +y
        [0, 1, 5], [0, 5, 4],  # -y
    ]
)  # fmt: skip


def test_vertex_normals_cube():
    fn = ref.face_normals(CUBE_V, CUBE_F)
    assert np.all(np.sum(fn * CUBE_V[CUBE_F].mean(axis=1), axis=1) > 0)
    vn = ref.vertex_normals(CUBE_V, CUBE_F)
    s3, s6 = math.sqrt(3), math.sqrt(6)
    # Counts of triangles per axis face touching each corner (see CUBE_F).
    np.testing.assert_allclose(vn[6], np.array([1, 1, 1]) / s3, atol=1e-15)
    np.testing.assert_allclose(vn[0], np.array([-1, -1, -1]) / s3, atol=1e-15)
    np.testing.assert_allclose(vn[5], np.array([1, -2, 1]) / s6, atol=1e-15)
    np.testing.assert_allclose(vn[1], np.array([2, -1, -1]) / s6, atol=1e-15)
    np.testing.assert_allclose(vn[4], np.array([-1, -1, 2]) / s6, atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(vn, axis=1), 1.0, atol=1e-15)


def test_vertex_normals_zero_sum_fallback_and_unused():
    # Two-sided sheet: both windings of the same quad -> every sum is zero.
    v = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [5, 5, 5], [2, 0, 0]])
    f = np.array(
        [
            [0, 1, 2],  # +z (first face for vertices 0, 1, 2)
            [0, 3, 2],  # -z (first face for vertex 3)
            [0, 2, 3],  # +z
            [0, 2, 1],  # -z
            [1, 5, 5],  # degenerate, first face for vertex 5
        ]
    )
    vn = ref.vertex_normals(v, f)
    np.testing.assert_array_equal(vn[:4], [[0, 0, 1], [0, 0, 1], [0, 0, 1], [0, 0, -1]])
    np.testing.assert_array_equal(vn[4], [0, 0, 0])  # unreferenced
    np.testing.assert_array_equal(vn[5], [0, 0, 0])  # only a degenerate face
    # Degenerate faces contribute nothing to a non-zero sum.
    f2 = np.array([[1, 5, 5], [0, 1, 2]])
    np.testing.assert_array_equal(ref.vertex_normals(v, f2)[1], [0, 0, 1])


def test_vertex_normals_scale_invariant_average():
    # Unit (not area-weighted) face normals: a tiny and a huge face count equally.
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 100]])
    f = np.array([[0, 1, 2], [0, 1, 3]])  # normals +z and -y
    fn = ref.face_normals(v, f)
    np.testing.assert_allclose(fn, [[0, 0, 1], [0, -1, 0]], atol=1e-15)
    np.testing.assert_allclose(
        ref.vertex_normals(v, f)[0], np.array([0, -1, 1]) / math.sqrt(2), atol=1e-15
    )


@pytest.mark.parametrize("n_lat,n_lon", [(2, 3), (5, 7), (24, 42)])
def test_uv_sphere_closed_and_outward(n_lat, n_lon):
    v, f = ref.uv_sphere(n_lat, n_lon, radius=2.5)
    assert v.shape == (2 + (n_lat - 1) * n_lon, 3)
    assert f.shape == (2 * n_lon * (n_lat - 1), 3)
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 2.5, atol=1e-12)
    np.testing.assert_allclose(v[0], [0, 2.5, 0])
    # Closed and consistently oriented: every directed edge once, and its reverse once.
    edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    directed = set(map(tuple, edges))
    assert len(directed) == len(edges)
    assert all((b, a) in directed for a, b in directed)
    assert len(v) - len(edges) // 2 + len(f) == 2  # Euler characteristic
    # Outward: face normals point away from the centre, positive volume.
    fn = ref.face_normals(v, f)
    assert np.all(np.sum(fn * v[f].mean(axis=1), axis=1) > 0)
    vol = np.sum(np.einsum("ij,ij->i", v[f[:, 0]], np.cross(v[f[:, 1]], v[f[:, 2]]))) / 6
    assert vol > 0
    # Auto vertex normals of a sphere point outward.
    vn = ref.vertex_normals(v, f)
    assert np.all(np.sum(vn * v, axis=1) > 0)


def test_sphere_render_visibility_and_culling():
    v, f = ref.uv_sphere(12, 16)
    cam = axis_camera(5.0, fov_y=40.0)
    kw = {
        "camera": cam,
        "width": 48,
        "height": 40,
        "lights": [LIGHT_Z, ref.PointLight((2, 3, 4))],
    }
    img = render(v, f, **kw)
    m = img.mask
    assert m.sum() > 200
    # The nearest surface is the front hemisphere: hits have z > 0 (inside the sphere's
    # silhouette) and lie on or inside the unit sphere (inscribed polytope).
    assert np.all(np.linalg.norm(img.position[m], axis=-1) <= 1 + 1e-12)
    inner = m & (img.edge_dist > 1e-6)
    assert np.all(img.position[inner][:, 2] > -1e-12)
    fn = ref.face_normals(v, f)
    front = np.sum(fn[img.tri[inner]] * (np.array(cam.eye) - img.position[inner]), axis=1) > 0
    assert np.all(front)
    culled = render(v, f, cull_backfaces=True, **kw)
    np.testing.assert_array_equal(culled.tri[inner], img.tri[inner])
    np.testing.assert_array_equal(culled.color[inner], img.color[inner])


def test_performance_2k_sphere_128():
    v, f = ref.uv_sphere(24, 42)
    assert 1800 < len(f) < 2100
    t0 = time.perf_counter()
    img = render(v, f, camera=axis_camera(4.0, fov_y=40.0), width=128, height=128)
    assert time.perf_counter() - t0 < 5.0
    assert img.mask.sum() > 3000


def test_to_uint8():
    x = np.array([-1.0, 0.0, 0.5, np.nextafter(0.5, 0.0), 0.25, 0.75, 1.0, 2.0, 1e-9])
    out = ref.to_uint8(x.reshape(1, 3, 3))
    assert out.dtype == np.uint8
    # 0.5 -> 127.5 rounds up to 128; 0.25 -> 63.75 -> 64; 0.75 -> 191.25 -> 191.
    np.testing.assert_array_equal(out.reshape(-1), [0, 0, 128, 127, 64, 191, 255, 255, 0])


def test_empty_mesh_gives_background():
    img = render(np.zeros((0, 3)), np.zeros((0, 3), dtype=int), background=(0.1, 0.2, 0.3))
    assert img.color.shape == (33, 33, 3)
    np.testing.assert_array_equal(img.color[5, 7], [0.1, 0.2, 0.3])
    assert np.all(img.tri == -1)


@pytest.mark.usefixtures("chunking")
def test_ray_casting_matches_screen_space_zbuffer():
    # Independent formulation for triangles fully inside [near, far]: screen
    # edge functions, perspective-correct barycentrics b_i ~ lambda_i / d_i,
    # depth d = 1 / sum(lambda_i / d_i), strict "<" z-test in index order.
    rng = np.random.default_rng(1234)
    n_tri, w, h = 25, 40, 30
    verts = rng.uniform([-2, -1.5, -2], [2, 1.5, 2], size=(n_tri * 3, 3))
    faces = np.arange(n_tri * 3).reshape(-1, 3)
    cam = ref.Camera(eye=(0.5, 1.0, 6.0), target=(0, 0, 0), up=(0, 1, 0), fov_y=45.0)
    img = render(verts, faces, camera=cam, width=w, height=h, shading="phong")

    pe = ref._world_to_eye(cam, verts)
    scr = ref.project_to_screen(pe, cam, w, h)
    dep = -pe[:, 2]
    assert dep.min() > cam.near
    xs, ys = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    zbuf = np.full((h, w), np.inf)
    tbuf = np.full((h, w), -1)
    bbuf = np.zeros((h, w, 3))
    for i, (a, b, c) in enumerate(faces):
        pa, pb, pc = scr[a], scr[b], scr[c]

        def edge(p, q):
            return (q[0] - p[0]) * (ys - p[1]) - (q[1] - p[1]) * (xs - p[0])

        area = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0])
        lam = np.stack([edge(pb, pc), edge(pc, pa), edge(pa, pb)], axis=-1) / area
        inside = np.all(lam >= 0, axis=-1)
        q = lam / dep[[a, b, c]]
        d = 1.0 / q.sum(axis=-1)
        upd = inside & (d < zbuf)
        zbuf[upd] = d[upd]
        tbuf[upd] = i
        bbuf[upd] = (q * d[..., None])[upd]
    ok = img.edge_dist > 1e-6
    assert ok.sum() > 300
    np.testing.assert_array_equal(img.tri[ok], tbuf[ok])
    np.testing.assert_allclose(img.depth[ok], zbuf[ok], rtol=1e-12)
    hit = ok & img.mask
    np.testing.assert_allclose(img.bary[hit], bbuf[hit], atol=1e-11)
