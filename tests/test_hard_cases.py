"""Hard numerical cases: extreme scales, huge triangles, the camera inside a mesh, depth
precision and lighting extremes. Each asserts a precise property, not just "no crash"."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shadelab_rs as sl

from shadelab_ref import reference as ref

SPHERE_V, SPHERE_F = ref.uv_sphere(24, 48)
MODES = ["flat", "gouraud", "phong"]


def _scene(v, f, material=None, lights=None, ambient=(0.2, 0.2, 0.2)):
    # lights=[] means unlit: no default light rig either.
    s = sl.Scene(ambient=ambient, default_lights=lights != [])
    s.add(sl.Mesh(v, f), material=material or sl.Material.preset("gold"))
    for light in lights if lights is not None else [sl.DirectionalLight((-1, -1, -1))]:
        s.add_light(light)
    return s


@pytest.mark.parametrize("mode", MODES)
def test_scale_invariance_from_1e_minus_7_to_1e7(mode):
    """Scaling the scene and the camera together changes nothing but the depth units."""
    results = []
    for scale in (1e-7, 1.0, 1e7):
        s = _scene(SPHERE_V * scale, SPHERE_F, lights=[sl.DirectionalLight((-1, -1, -1))])
        cam = sl.Camera.look_at((0, 0, 3 * scale), (0, 0, 0), near=0.1 * scale, far=10 * scale)
        img, depth = sl.render(s, cam, 96, 72, shading=mode, return_depth=True)
        results.append((img, depth / scale))
    base_img, base_depth = results[1]
    for img, depth in (results[0], results[2]):
        assert np.array_equal(np.isfinite(depth), np.isfinite(base_depth))
        assert np.abs(img.astype(int) - base_img).max() <= 1
        cov = np.isfinite(depth)
        np.testing.assert_allclose(depth[cov], base_depth[cov], rtol=1e-5)


def test_triangle_millions_of_pixels_across():
    """A triangle 2e6 units wide seen from 5 units covers every pixel at exact depth 5."""
    v = np.array([[-1e6, -1e6, -5], [1e6, -1e6, -5], [0, 1e6, -5]], float)
    s = _scene(v, [[0, 1, 2]], lights=[])
    img, depth = sl.render(s, sl.Camera.look_at((0, 0, 0), (0, 0, -1)), 64, 48, return_depth=True)
    np.testing.assert_allclose(depth, 5.0, rtol=1e-6)
    assert (img == img[0, 0]).all()


@pytest.mark.parametrize("mode", MODES)
def test_camera_inside_a_closed_mesh_sees_it_everywhere(mode):
    """From inside a closed sphere of radius 5 every pixel hits it, at a depth matching the
    ray-cast distance, and nothing is NaN (all visible faces are back faces)."""
    s = _scene(SPHERE_V * 5, SPHERE_F)
    cam = sl.Camera.look_at((0.3, 0.2, 0.1), (0, 0, -1), near=0.01, far=100)
    img, depth = sl.render(s, cam, 64, 48, shading=mode, dtype="float32", return_depth=True)
    assert np.isfinite(img).all() and np.isfinite(depth).all()
    r = ref.render_reference(
        SPHERE_V * 5,
        SPHERE_F,
        camera=ref.Camera(eye=(0.3, 0.2, 0.1), target=(0, 0, -1), up=(0, 1, 0), near=0.01),
        width=64,
        height=48,
        material=ref.Material(0.2, 0.8, 0.5, 32),
        lights=[],
    )
    far_from_edges = r.edge_dist > 0.05
    np.testing.assert_allclose(depth[far_from_edges], r.depth[far_from_edges], rtol=1e-4)


@pytest.mark.parametrize("first_is_nearer", [True, False])
def test_depth_precision_near_0001_far_10000(first_is_nearer):
    """Two parallel planes 1e-4 apart at distance 100 with near = 0.001 and far = 1e4: the
    nearer one wins every covered pixel whichever is submitted first (reversed-Z f32)."""
    quad = np.array([[-80, -80, -100], [80, -80, -100], [80, 80, -100], [-80, 80, -100]], float)
    faces = [[0, 1, 2], [0, 2, 3]]

    def flat(rgb):
        return sl.Material(ambient=rgb, diffuse=(0, 0, 0), specular=(0, 0, 0))

    near = (sl.Mesh(quad, faces), flat((0, 1, 0)))
    far = (sl.Mesh(quad - [0, 0, 1e-4], faces), flat((1, 0, 0)))
    s = sl.Scene(ambient=(1, 1, 1))
    for mesh, mat in [near, far] if first_is_nearer else [far, near]:
        s.add(mesh, material=mat)
    cam = sl.Camera.look_at((0, 0, 0), (0, 0, -1), near=0.001, far=1e4)
    img, depth = sl.render(s, cam, 128, 96, return_depth=True)
    assert np.isfinite(depth).all()
    assert (img[..., 1] == 255).all() and (img[..., 0] == 0).all()


def test_coplanar_duplicates_first_submitted_wins():
    quad = np.array([[-9, -9, -3], [9, -9, -3], [9, 9, -3], [-9, 9, -3]], float)
    faces = [[0, 1, 2], [0, 2, 3]]
    s = sl.Scene(ambient=(1, 1, 1))
    for rgb in [(0, 0, 1), (1, 0, 0)]:
        s.add(sl.Mesh(quad, faces), sl.Material(ambient=rgb, diffuse=(0,) * 3, specular=(0,) * 3))
    img = sl.render(s, sl.Camera.look_at((0, 0, 0), (0, 0, -1)), 64, 48)
    assert (img[..., 2] == 255).all() and (img[..., 0] == 0).all()


@pytest.mark.parametrize("shininess", [0.0, 1e-3, 1.0, 1e4])
@pytest.mark.parametrize("mode", MODES)
def test_lighting_extremes_stay_finite_and_hdr(shininess, mode):
    """A light exactly on the surface (distance 0), the eye almost on it, shininess 0..1e4
    and intensity 100: float32 keeps values far above 1 and no NaN; uint8 clamps to 255."""
    m = sl.Material(ambient=(0, 0, 0), diffuse=(1, 1, 1), specular=(1, 1, 1), shininess=shininess)
    lights = [sl.PointLight((0, 0, 1.0)), sl.DirectionalLight((0, 0, -1), intensity=100.0)]
    s = _scene(SPHERE_V, SPHERE_F, material=m, lights=lights, ambient=(0, 0, 0))
    cam = sl.Camera.look_at((0, 0, 1.0 + 1e-6), (0, 0, 0), near=1e-7, far=10)
    img = sl.render(s, cam, 48, 36, shading=mode, dtype="float32")
    assert np.isfinite(img).all()
    assert img.max() >= 99.0  # n·l = 1 at the pole: 100 of diffuse alone
    img8 = sl.render(s, cam, 48, 36, shading=mode)
    assert img8.max() == 255


def test_normal_exactly_perpendicular_to_light_gets_no_light():
    """n·l = 0 exactly: neither diffuse nor specular (specular only where n·l > 0)."""
    quad = np.array([[-5, -5, -3], [5, -5, -3], [5, 5, -3], [-5, 5, -3]], float)
    m = sl.Material(ambient=(0, 0, 0), diffuse=(1, 1, 1), specular=(1, 1, 1), shininess=0.0)
    s = _scene(quad, [[0, 1, 2], [0, 2, 3]], material=m, lights=[sl.DirectionalLight((1, 0, 0))])
    for mode in MODES:
        img = sl.render(s, sl.Camera.look_at((0, 0, 0), (0, 0, -1)), 32, 24, shading=mode)
        assert (img == 0).all()


def test_64_lights_add_up():
    """64 identical directional lights give 64 times the diffuse of one (float32, kd small)."""
    quad = np.array([[-5, -5, -3], [5, -5, -3], [5, 5, -3], [-5, 5, -3]], float)
    m = sl.Material(ambient=(0, 0, 0), diffuse=(0.01, 0.01, 0.01), specular=(0, 0, 0))
    one = _scene(quad, [[0, 1, 2], [0, 2, 3]], material=m, lights=[sl.DirectionalLight((0, 0, -1))])
    many = _scene(
        quad,
        [[0, 1, 2], [0, 2, 3]],
        material=m,
        lights=[sl.DirectionalLight((0, 0, -1)) for _ in range(64)],
    )
    cam = sl.Camera.look_at((0, 0, 0), (0, 0, -1))
    a = sl.render(one, cam, 16, 12, dtype="float32")
    b = sl.render(many, cam, 16, 12, dtype="float32")
    np.testing.assert_allclose(b, 64 * a, rtol=1e-5)
    assert math.isclose(float(a.max()), 0.01, rel_tol=1e-6)


def _degenerate_mesh():
    """A mesh with every kind of degeneracy the hard-cases list names."""
    v = np.array(
        [
            [0, 0, 0],
            [1, 0, 0],
            [0, 1, 0],
            [1, 1, 0],
            [2, 2, 0],  # collinear with 0 and 3
            [0.5, 0.5, 0],  # on the edge 1-2
            [9, 9, 9],  # unreferenced
            [1, 0, 0],  # same position as vertex 1 (repeated vertex)
        ],
        float,
    )
    f = np.array(
        [
            [0, 1, 2],
            [1, 3, 2],
            [0, 3, 4],  # zero area: collinear
            [0, 0, 1],  # zero area: repeated index
            [7, 3, 1],  # zero area: two vertices at one position
            [0, 1, 2],  # duplicate face
            [2, 1, 0],  # the same face, other side (normals cancel at 0, 1, 2)
            [1, 2, 5],  # zero area, non-manifold fan on edge 1-2
            [5, 1, 3],
        ]
    )
    return v, f


@pytest.mark.parametrize("mode", MODES)
def test_degenerate_geometry_gives_no_nan(mode):
    v, f = _degenerate_mesh()
    mesh = sl.Mesh(v, f)
    assert np.isfinite(mesh.normals).all()
    # Cancelling normals fall back to the first face's; unreferenced/degenerate-only get 0.
    np.testing.assert_allclose(mesh.normals[0], [0, 0, 1], atol=1e-6)
    np.testing.assert_array_equal(mesh.normals[6], [0, 0, 0])
    s = sl.Scene()
    s.add(mesh, material=sl.Material.preset("brass"))
    s.add_light(sl.PointLight((0.5, 0.5, 2)))
    cam = sl.Camera.look_at((0.5, 0.5, 3), (0.5, 0.5, 0))
    img, depth = sl.render(s, cam, 64, 64, shading=mode, dtype="float32", return_depth=True)
    assert np.isfinite(img).all()
    assert np.isfinite(depth).sum() > 500
    stats = sl.render_frame(s, cam, 64, 64, shading=mode)["stats"]
    assert stats["triangles_in"] == len(f)
    assert stats["triangles_setup"] < len(f)  # the zero-area ones are skipped


@pytest.mark.parametrize("mode", MODES)
def test_zero_given_normals_fall_back(mode):
    """Zero normals given by the user: Phong uses the face normal, Gouraud gets ambient only;
    no NaN either way."""
    v = np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0]], float)
    s = sl.Scene(ambient=(0.1, 0.1, 0.1))
    mat = sl.Material(ambient=(1, 1, 1), diffuse=(1, 1, 1), specular=(0, 0, 0))
    s.add(sl.Mesh(v, [[0, 1, 2]], normals=np.zeros((3, 3))), material=mat)
    s.add_light(sl.DirectionalLight((0, 0, -1)))
    img = sl.render(
        s, sl.Camera.look_at((0, 0, 3), (0, 0, 0)), 32, 32, shading=mode, dtype="float32"
    )
    assert np.isfinite(img).all()
    centre = img[16, 16]
    want = {"flat": 1.1, "gouraud": 0.1, "phong": 1.1}[mode]
    np.testing.assert_allclose(centre, want, rtol=1e-5)


# --------------------------------------------------------------------------------------------
# Slivers below 1e-4 degrees against the float64 reference
# --------------------------------------------------------------------------------------------

#: Sub-pixel units of the renderer's 16.8 fixed point.
UNIT = 1.0 / 256.0


def _pixel_camera(width, height):
    """Orthographic camera mapping world (x, y) to screen (x, height - y), one unit per pixel,
    for the reference and for shadelab_rs (exact in both for power-of-two sizes)."""
    c = (width / 2, height / 2)
    r = ref.Camera(
        eye=(*c, 10.0), target=(*c, 0.0), up=(0, 1, 0), ortho_height=height, near=1.0, far=100.0
    )
    s = sl.Camera.orthographic(r.eye, r.target, up=r.up, height=height, near=1.0, far=100.0)
    return r, s


def _min_angle_deg(p):
    angles = []
    for k in range(3):
        a, b, c = p[k], p[(k + 1) % 3], p[(k + 2) % 3]
        u, w = b - a, c - a
        angles.append(math.degrees(math.atan2(abs(u[0] * w[1] - u[1] * w[0]), u @ w)))
    return min(angles)


def _edge_values(screen_pts, width, height):
    """Exact integer edge functions (in 1/256-px units, y down) of every pixel centre."""
    q = [(round(x * 256), round(y * 256)) for x, y in screen_pts]
    xs = np.arange(width, dtype=np.int64) * 256 + 128
    ys = np.arange(height, dtype=np.int64) * 256 + 128
    px, py = np.meshgrid(xs, ys)
    out = []
    for k in range(3):
        (ax, ay), (bx, by) = q[k], q[(k + 1) % 3]
        out.append((bx - ax) * (py - ay) - (by - ay) * (px - ax))
    return out


# Slivers in screen pixels (y down), every coordinate a multiple of 1/256 px; the far ends
# differ by 1/256 px, so the apex angle is below 1e-4 degrees. Near-horizontal in a wide
# image and near-vertical in a tall one (x and y are rasterized differently).
SLIVERS = {
    "flat-row": (4096, 32, [(8, 10.5 - 2 * UNIT), (4088, 10.5 + UNIT), (4088, 10.5 + 2 * UNIT)]),
    "rising": (4096, 32, [(8, 4 + 56 * UNIT), (4088, 28 + 72 * UNIT), (4088, 28 + 73 * UNIT)]),
    "steep": (32, 4096, [(10.5 - 2 * UNIT, 8), (10.5 + UNIT, 4088), (10.5 + 2 * UNIT, 4088)]),
}


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("name", list(SLIVERS))
@pytest.mark.parametrize("winding", ["ccw", "cw"])
def test_slivers_below_1e_minus_4_degrees_match_the_float64_reference(name, mode, winding):
    """Coverage equals the reference's pixel-centre test exactly (no centre lies on an edge,
    checked with exact integers, so the fill rule plays no part), colours are within 1 LSB
    (uint8) and 1e-5 (float32). Depth is within 2e-6 of the depth range (far - near = 99):
    the depth plane is stepped in float32 from the tile's first pixel, and a sliver's plane is
    so steep across the sliver that the large terms z0 + dz/dx·i + dz/dy·j cancel, leaving a
    few float32 ulps of them (measured up to 8.4e-7 of the range)."""
    width, height, pts = SLIVERS[name]
    pts = np.array(pts, float)
    assert _min_angle_deg(pts) < 1e-4
    edges = _edge_values(pts, width, height)
    on_edge = np.zeros((height, width), bool)
    inside_closed = np.ones((height, width), bool)
    sign = np.sign(edges[0] + edges[1] + edges[2]).max()  # orientation of the triangle
    for e in edges:
        inside_closed &= e * sign >= 0
    for e in edges:
        on_edge |= inside_closed & (e == 0)
    assert not on_edge.any()
    world = np.stack([pts[:, 0], height - pts[:, 1], [-1.0, -3.0, -3.5]], axis=1)
    normals = np.array([[0, 0, 1], [0.6, 0, 0.8], [0, -0.6, 0.8]], float)
    faces = [[0, 1, 2]] if winding == "ccw" else [[0, 2, 1]]
    r_cam, s_cam = _pixel_camera(width, height)
    mat = sl.Material(ambient=(0.1, 0.2, 0.3), diffuse=(0.8, 0.6, 0.4), specular=(0.5,) * 3)
    light = (0.3, -0.5, -1.0)
    s = sl.Scene(ambient=(0.2, 0.2, 0.2))
    s.add(sl.Mesh(world, faces, normals=normals), material=mat)
    s.add_light(sl.DirectionalLight(light))
    img, depth = sl.render(
        s, s_cam, width, height, shading=mode, dtype="float32", return_depth=True
    )
    img8 = sl.render(s, s_cam, width, height, shading=mode)
    r = ref.render_reference(
        world,
        faces,
        camera=r_cam,
        width=width,
        height=height,
        material=ref.Material(mat.ambient, mat.diffuse, mat.specular, mat.shininess),
        lights=[ref.DirectionalLight(light)],
        normals=normals,
        shading=mode,
    )
    covered = np.isfinite(depth)
    assert np.array_equal(covered, r.mask)
    assert np.array_equal(covered, inside_closed)
    assert covered.sum() >= {"flat-row": 600, "rising": 5, "steep": 600}[name]
    assert np.abs(img[covered] - r.color[covered]).max() <= 1e-5
    assert np.abs(img8.astype(int) - ref.to_uint8(r.color)).max() <= 1
    assert np.abs(depth[covered] - r.depth[covered]).max() <= 2e-6 * (100.0 - 1.0)


# --------------------------------------------------------------------------------------------
# Vertices with w = 0, w ≈ 0 and w < 0 against the clipped float64 reference
# --------------------------------------------------------------------------------------------

#: Pixels whose centre is nearer than this to a (clipped) edge may legitimately differ in
#: coverage: vertices are snapped to 1/256 px (see test_reference_compare.py).
EDGE_PX = 0.05

W_TRIANGLES = {
    # One vertex a hair in front of the eye plane (w = 1e-9, far inside the near plane).
    "w-1e-9": [(-3.0, -1.0, -4.0), (3.0, -1.2, -4.0), (0.2, 0.5, -1e-9)],
    # One vertex exactly in the eye plane (w = 0), off the eye.
    "w-0": [(0.5, -0.3, 0.0), (-2.0, 0.8, -5.0), (2.0, 1.0, -5.0)],
    # One vertex behind the camera (w < 0).
    "w-negative": [(-2.0, 1.0, 1.5), (2.0, 1.5, -6.0), (-1.0, -0.5, -3.0)],
    # Two vertices behind, one in front: only a small piece is visible.
    "two-behind": [(-2.0, -1.0, 2.0), (2.0, -1.0, 3.0), (0.3, 0.2, -2.0)],
}


def _clipped_edges(tri, cam, width, height):
    pts = ref._clip_polygon([tuple(p) for p in tri], cam.near, cam.far)
    s = ref.project_to_screen(np.asarray(pts), cam, width, height)
    return np.stack([s, np.roll(s, -1, axis=0)], axis=1)


def _distance_to_segments(mask, segs):
    rows, cols = np.nonzero(mask)
    c = np.stack([cols + 0.5, rows + 0.5], axis=1)[:, None, :]
    a, b = segs[None, :, 0], segs[None, :, 1]
    ab, ap = b - a, c - a
    t = np.clip(np.sum(ap * ab, -1) / np.sum(ab * ab, -1), 0.0, 1.0)
    d = ap - t[..., None] * ab
    return np.sqrt(np.sum(d * d, -1)).min(axis=1)


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("name", list(W_TRIANGLES))
def test_vertices_at_w_zero_and_behind_match_the_clipped_reference(name, mode):
    """The camera sits at the origin looking down -z (so w = -z): coverage differs from the
    clipped float64 reference only within EDGE_PX of a clipped edge; elsewhere colours are
    within 1 LSB and depth within the snapping bound; no NaN anywhere."""
    tri = np.array(W_TRIANGLES[name], float)
    width, height = 96, 64
    r_cam = ref.Camera(eye=(0, 0, 0), target=(0, 0, -1), up=(0, 1, 0), fov_y=60.0, near=0.01)
    s_cam = sl.Camera.look_at((0, 0, 0), (0, 0, -1), fov_y=60.0, near=0.01, far=100.0)
    mat = sl.Material(ambient=(0.2, 0.1, 0.0), diffuse=(0.6, 0.8, 1.0), specular=(0.5,) * 3)
    normals = np.array([[0, 0, 1], [0.6, 0, 0.8], [0, 0.6, 0.8]], float)
    lights = [(-0.3, -0.5, -1.0)]
    s = sl.Scene(ambient=(0.2, 0.2, 0.2))
    s.add(sl.Mesh(tri, [[0, 1, 2]], normals=normals), material=mat)
    s.add_light(sl.DirectionalLight(lights[0]))
    img, depth = sl.render(
        s, s_cam, width, height, shading=mode, dtype="float32", return_depth=True
    )
    img8 = sl.render(s, s_cam, width, height, shading=mode)
    assert not np.isnan(img).any() and not np.isnan(depth).any()
    r = ref.render_reference(
        tri,
        [[0, 1, 2]],
        camera=r_cam,
        width=width,
        height=height,
        material=ref.Material(mat.ambient, mat.diffuse, mat.specular, mat.shininess),
        lights=[ref.DirectionalLight(lights[0])],
        normals=normals,
        shading=mode,
    )
    covered = np.isfinite(depth)
    assert r.mask.sum() > 100
    differ = covered != r.mask
    if differ.any():
        assert _distance_to_segments(differ, _clipped_edges(tri, r_cam, width, height)).max() < (
            EDGE_PX
        )
    inner = covered & r.mask & (r.edge_dist > EDGE_PX)
    assert np.abs(img8[inner].astype(int) - ref.to_uint8(r.color[inner])).max() <= 1
    # Depth: snapping moves the sample by at most 1/512 px per axis, so the error is bounded
    # by (|dd/dx| + |dd/dy|) / 512 plus float32 rounding. The camera frame is the world frame
    # here, so on the plane n.p = k the ray t·(X, Y, -1) has t = k / n.(X, Y, -1), and
    # dt/dx = t² |nx| dX/dx / |k| (likewise for y).
    n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    k = n @ tri[0]
    tan = math.tan(math.radians(30.0))
    dxdx, dydy = 2 * tan * (width / height) / width, 2 * tan / height
    slope = r.depth**2 * (abs(n[0]) * dxdx + abs(n[1]) * dydy) / abs(k)
    bound = slope / 512 + 1e-5 * r.depth
    assert (np.abs(depth[inner] - r.depth[inner]) <= bound[inner]).all()


# --------------------------------------------------------------------------------------------
# Zero normals and cancelling normals coming from OBJ files
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("mode", MODES)
def test_zero_normals_in_an_obj_file_fall_back(tmp_path, mode):
    """``vn 0 0 0`` in a file gives the same image as zero normals given from Python (Phong:
    face normal, Gouraud: ambient only), and no NaN."""
    p = tmp_path / "zero.obj"
    p.write_text("v -1 -1 0\nv 1 -1 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n")
    from_file = sl.load_obj(p)
    np.testing.assert_array_equal(from_file.normals, np.zeros((3, 3)))
    given = sl.Mesh(from_file.vertices, from_file.faces, normals=np.zeros((3, 3)))
    images = []
    for mesh in (from_file, given):
        s = sl.Scene(ambient=(0.1, 0.1, 0.1))
        s.add(mesh, material=sl.Material(ambient=(1, 1, 1), diffuse=(1, 1, 1), specular=(0, 0, 0)))
        s.add_light(sl.DirectionalLight((0, 0, -1)))
        cam = sl.Camera.look_at((0, 0, 3), (0, 0, 0))
        images.append(sl.render(s, cam, 32, 32, shading=mode, dtype="float32"))
    assert np.isfinite(images[0]).all()
    assert np.array_equal(images[0], images[1])
    want = {"flat": 1.1, "gouraud": 0.1, "phong": 1.1}[mode]
    np.testing.assert_allclose(images[0][16, 16], want, rtol=1e-5)


@pytest.mark.parametrize("mode", MODES)
def test_two_sided_sheet_in_an_obj_file_has_defined_normals(tmp_path, mode):
    """A sheet given twice, once per side, without normals: the generated normals cancel at
    every vertex and fall back to the first face's (+z), so the lit side is the +z side and
    both faces shade identically; no NaN."""
    p = tmp_path / "sheet.obj"
    # Every vertex is used by as many +z as -z triangles, so the unit normals cancel exactly.
    p.write_text("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\nf 3 2 1\nf 4 3 1\n")
    mesh = sl.load_obj(p)
    np.testing.assert_allclose(mesh.normals, [[0, 0, 1]] * len(mesh.normals), atol=0)
    s = sl.Scene(ambient=(0, 0, 0))
    s.add(mesh, material=sl.Material(ambient=(0, 0, 0), diffuse=(1, 1, 1), specular=(0, 0, 0)))
    s.add_light(sl.DirectionalLight((0, 0, -1)))
    front = sl.render(s, sl.Camera.look_at((0, 0, 3), (0, 0, 0)), 16, 16, shading=mode)
    assert (front[4:12, 4:12] == 255).all()
