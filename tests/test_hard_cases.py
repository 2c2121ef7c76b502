"""Hard numerical cases: extreme scales, huge triangles, the camera inside a mesh, depth
precision and lighting extremes. Each asserts a precise property, not just "no crash"."""

from __future__ import annotations

import math

import numpy as np
import pytest
import reference as ref
import shadelab_rs as sl

SPHERE_V, SPHERE_F = ref.uv_sphere(24, 48)
MODES = ["flat", "gouraud", "phong"]


def _scene(v, f, material=None, lights=None, ambient=(0.2, 0.2, 0.2)):
    s = sl.Scene(ambient=ambient)
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
