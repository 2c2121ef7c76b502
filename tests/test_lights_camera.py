"""Scene, lights (directional, point, spot, area; split colours), fog and camera: getters,
round trips and hand-computed effects."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shadelab_rs as sl

# --------------------------------------------------------------------------------------------
# Scene, lights, camera
# --------------------------------------------------------------------------------------------


def test_scene_getters(sphere_arrays):
    scene = sl.Scene(ambient=(0.1, 0.2, 0.3))
    assert scene.ambient == pytest.approx((0.1, 0.2, 0.3), rel=1e-7)
    assert (scene.n_objects, scene.n_lights, scene.n_triangles) == (0, 0, 0)
    mesh = sl.Mesh(*sphere_arrays)
    scene.add(mesh)
    scene.add(mesh, material=sl.Material.preset("gold"), transform=np.eye(4))
    scene.add_light(sl.DirectionalLight((0, -1, 0)))
    scene.add_light(sl.PointLight((0, 1, 0)))
    assert (scene.n_objects, scene.n_lights, scene.n_triangles) == (2, 2, 2 * mesh.n_faces)
    assert "objects=2" in repr(scene)
    assert sl.Scene().ambient == pytest.approx((0.2, 0.2, 0.2), rel=1e-7)


def test_directional_light_getters():
    light = sl.DirectionalLight(direction=(0, -2, 0), color=(0.5, 0.25, 1.0), intensity=2.0)
    assert light.direction == (0.0, -2.0, 0.0)  # as given; the light uses its unit vector
    assert light.color == (0.5, 0.25, 1.0)
    assert light.intensity == 2.0
    d = sl.DirectionalLight((1, 1, 1))
    assert d.color == (1.0, 1.0, 1.0) and d.intensity == 1.0
    assert d.direction == (1.0, 1.0, 1.0)
    assert "DirectionalLight(" in repr(d)


def test_point_light_getters():
    light = sl.PointLight(position=(1, 2, 3), color=(0.5, 0.25, 1.0), intensity=2.0)
    assert light.position == (1.0, 2.0, 3.0)
    assert light.color == (0.5, 0.25, 1.0)
    assert light.intensity == 2.0
    p = sl.PointLight(np.array([1.0, 2.0, 3.0]))
    assert p.color == (1.0, 1.0, 1.0) and p.intensity == 1.0
    assert "PointLight(" in repr(p)


def test_camera_getters():
    cam = sl.Camera.look_at(
        eye=(1, 2, 3), target=(0, 0.5, 0), up=(0, 0, 1), fov_y=30.0, near=0.25, far=50.0
    )
    assert (cam.eye, cam.target, cam.up) == ((1, 2, 3), (0, 0.5, 0), (0, 0, 1))
    assert (cam.near, cam.far, cam.fov_y, cam.height) == (0.25, 50.0, 30.0, None)
    assert cam.kind == "perspective"
    default = sl.Camera.look_at((0, 0, 3), (0, 0, 0))
    # near/far left out: None, fitted to the scene's bounds when rendering.
    assert (default.up, default.fov_y, default.near, default.far) == ((0, 1, 0), 45.0, None, None)
    ortho = sl.Camera.orthographic(eye=(0, 0, 3), target=(0, 0, 0), height=3.5, near=0.5, far=9.0)
    assert ortho.kind == "orthographic"
    assert (ortho.height, ortho.fov_y, ortho.near, ortho.far) == (3.5, None, 0.5, 9.0)
    d = sl.Camera.orthographic((0, 0, 3), (0, 0, 0))
    assert (d.up, d.height, d.near, d.far) == ((0, 1, 0), 2.0, None, None)
    assert repr(cam).startswith("Camera.look_at(") and repr(ortho).startswith("Camera.ortho")


@pytest.mark.parametrize("kind", ["orthographic", "perspective"])
def test_camera_orientation_and_aspect(kind):
    """A marker up and to the right of the target lands in the top-right of the image, and
    the horizontal extent is the vertical one times width / height (a square stays square).

    Both cameras map the plane z = 0 to 20 pixels per unit around the image centre: the
    orthographic one by its height 4 over 80 rows, the perspective one (eye at distance 5,
    tan(fov_y / 2) = 0.4) because 5 * 0.4 = 2 units span the 40 rows above the centre."""
    scene = sl.Scene(ambient=(1, 1, 1))
    s = 0.25
    square = sl.Mesh(
        [[1 - s, 1 - s, 0], [1 + s, 1 - s, 0], [1 + s, 1 + s, 0], [1 - s, 1 + s, 0]],
        [[0, 1, 2], [0, 2, 3]],
    )
    scene.add(square, material=sl.Material((1, 1, 1), (0, 0, 0), (0, 0, 0), 1))
    if kind == "orthographic":
        cam = sl.Camera.orthographic(eye=(0, 0, 5), target=(0, 0, 0), height=4.0)
    else:
        fov_y = 2 * math.degrees(math.atan(0.4))
        cam = sl.Camera.look_at(eye=(0, 0, 5), target=(0, 0, 0), fov_y=fov_y)
    img = sl.render(scene, cam, width=160, height=80)
    ys, xs = np.nonzero(img[..., 0])
    # The square spans x, y in [0.75, 1.25]: columns 95..104, rows 15..24 (row 0 at the top).
    assert (xs.min(), xs.max() + 1) == (80 + 15, 80 + 25)
    assert (ys.min(), ys.max() + 1) == (40 - 25, 40 - 15)
    assert len(xs) == 100


def test_light_and_material_extras_round_trip():
    p = sl.PointLight((1, 2, 3), attenuation=(1, 0.5, 0.25), ambient=(0.1, 0.2, 0.3))
    assert p.attenuation == (1.0, 0.5, 0.25)
    assert p.ambient == pytest.approx((0.1, 0.2, 0.3))
    assert sl.PointLight((0, 0, 0)).attenuation == (1.0, 0.0, 0.0)
    d = sl.DirectionalLight((0, -1, 0), ambient=(0.5, 0.5, 0.5))
    assert d.ambient == (0.5, 0.5, 0.5)
    m = sl.Material(emission=(0.25, 0.0, 0.5))
    assert m.emission == (0.25, 0.0, 0.5)
    assert sl.Material.preset("gold").emission == (0.0, 0.0, 0.0)
    assert m != sl.Material()


def test_emission_alone_lights_an_unlit_scene():
    """No lights, no ambient: the image is exactly the emission colour where covered."""
    v = np.array([[-5, -5, -3], [5, -5, -3], [5, 5, -3], [-5, 5, -3]], float)
    s = sl.Scene(ambient=(0, 0, 0), default_lights=False)
    s.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=sl.Material(emission=(0.25, 0.5, 1.0)))
    img = sl.render(s, sl.Camera.look_at((0, 0, 0), (0, 0, -1)), 16, 12, dtype="float32")
    np.testing.assert_array_equal(img, np.broadcast_to([0.25, 0.5, 1.0], img.shape))


def test_spot_light_round_trip_and_cone():
    s = sl.SpotLight((0, 0, 2), (0, 0, -3), cutoff=30.0, exponent=2.0, inner=20.0)
    assert s.direction == (0.0, 0.0, -3.0)
    assert (s.cutoff, s.exponent, s.inner) == (30.0, 2.0, 20.0)
    assert sl.SpotLight((0, 0, 2), (0, 0, -1)).inner is None
    # A lit disc on a floor: radius 2·tan(30°) = 1.155 around the spot's foot.
    v = np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], float)
    scene = sl.Scene(ambient=(0, 0, 0))
    scene.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=sl.Material(specular=(0, 0, 0)))
    scene.add_light(sl.SpotLight((0, 0, 2), (0, 0, -1), cutoff=30.0))
    cam = sl.Camera.orthographic((0, 0, 5), (0, 0, 0), height=6.0)
    img = sl.render(scene, cam, 120, 120, dtype="float32")
    lit = img[..., 0] > 0
    area = lit.sum() * (6.0 / 120) ** 2
    assert abs(area - np.pi * (2 * np.tan(np.radians(30))) ** 2) < 0.05


def test_fog_round_trip_and_hand_computed_blend():
    f = sl.Fog("linear", start=2.0, end=6.0, color=(1.0, 0.5, 0.0))
    assert (f.mode, f.start, f.end, f.density) == ("linear", 2.0, 6.0, None)
    assert f.factor(3.0) == 0.75 and f.factor(1.0) == 1.0 and f.factor(9.0) == 0.0
    assert sl.Fog("exp2", density=0.5).density == 0.5
    scene = sl.Scene(ambient=(1, 1, 1), fog=f)
    assert scene.fog is not None and scene.fog.end == 6.0
    # An unlit white wall at distance 3 straight ahead: f = 0.75 at the centre pixel.
    v = np.array([[-9, -9, -3], [9, -9, -3], [9, 9, -3], [-9, 9, -3]], float)
    white = sl.Material(ambient=(1, 1, 1), diffuse=(0, 0, 0), specular=(0, 0, 0))
    scene.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=white)
    cam = sl.Camera.orthographic((0, 0, 0), (0, 0, -1), height=2.0, near=0.5, far=10)
    for mode in ("flat", "gouraud", "phong"):
        img = sl.render(scene, cam, 8, 8, shading=mode, dtype="float32")
        # Orthographic: the pixel at (x, y) sees the wall at distance sqrt(3² + x_e² + y_e²).
        xe = (np.arange(8) + 0.5) / 8 * 2 - 1
        d = np.sqrt(9 + xe[None, :] ** 2 + xe[:, None] ** 2)
        fog_f = np.clip((6 - d) / 4, 0, 1)
        want = fog_f[..., None] * 1 + (1 - fog_f[..., None]) * np.array([1.0, 0.5, 0.0])
        np.testing.assert_allclose(img, want, atol=2e-6)
    scene.fog = None
    assert scene.fog is None
    assert (sl.render(scene, cam, 8, 8, dtype="float32") == 1).all()


def test_two_sided_and_local_viewer_flags():
    s = sl.Scene()
    assert (s.two_sided, s.local_viewer) == (False, True)
    s.two_sided, s.local_viewer = True, False
    assert (s.two_sided, s.local_viewer) == (True, False)
    assert sl.Scene(two_sided=True).two_sided
    # A clockwise (back-facing) wall lit from the front: dark one-sided, lit two-sided.
    v = np.array([[-9, -9, -3], [-9, 9, -3], [9, 9, -3], [9, -9, -3]], float)  # clockwise
    m = sl.Material(ambient=(0, 0, 0), diffuse=(1, 1, 1), specular=(0, 0, 0))
    for mode in ("flat", "gouraud", "phong"):
        out = []
        for two in (False, True):
            scene = sl.Scene(ambient=(0, 0, 0), two_sided=two)
            scene.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=m)
            scene.add_light(sl.DirectionalLight((0, 0, -1)))
            out.append(sl.render(scene, sl.Camera.look_at((0, 0, 0), (0, 0, -1)), 8, 8))
        assert (out[0] == 0).all() and (out[1] == 255).all(), mode


def test_area_light_getters_points_and_repr():
    a = sl.AreaLight((0, 2, 0), (2, 0, 0), (0, 0, 1), samples=3, color=(1, 0.5, 0.25))
    assert (a.position, a.u, a.v) == ((0.0, 2.0, 0.0), (2.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    assert (a.shape, a.samples, a.n_points, a.one_sided) == ("rectangle", 3, 9, False)
    assert a.normal == (0.0, -1.0, 0.0)  # u x v = x x z = -y
    assert (a.color, a.intensity) == ((1.0, 0.5, 0.25), 1.0)
    assert (a.attenuation, a.ambient) == ((1.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    assert sl.AreaLight((0, 0, 0), (1, 0, 0), (0, 1, 0)).samples == 4
    pts = a.points()
    assert pts.shape == (9, 3) and pts.dtype == np.float32
    # Cell centres of a 3 x 3 grid over [-1, 1] x [-0.5, 0.5], u fastest.
    xs, zs = np.array([-2, 0, 2]) / 3, np.array([-1, 0, 1]) / 3
    want = np.array([[x, 2.0, z] for z in zs for x in xs], np.float32)
    np.testing.assert_allclose(pts, want, atol=1e-7)
    disk = sl.AreaLight((1, 1, 1), (2, 0, 0), (0, 2, 0), shape="disk", samples=8, one_sided=True)
    d = disk.points() - np.float32(1)
    assert disk.shape == "disk" and disk.one_sided
    assert d.shape == (64, 3) and np.all(d[:, 2] == 0)
    assert np.all(np.hypot(d[:, 0], d[:, 1]) <= 1 + 1e-6)
    assert "AreaLight(" in repr(disk) and "disk" in repr(disk)
    assert sl.MAX_AREA_SAMPLES == 64


def _floor_scene(light):
    v = np.array([[-4, 0, -4], [4, 0, -4], [4, 0, 4], [-4, 0, 4]], float)
    scene = sl.Scene(ambient=(0, 0, 0))
    scene.add(sl.Mesh(v, [[0, 2, 1], [0, 3, 2]]), material=sl.Material.preset("jade"))
    scene.add_light(light)
    return scene


def test_area_light_of_one_sample_is_its_centre_point_light():
    cam = sl.Camera.look_at((0, 5, 6), (0, 0, 0))
    kw = dict(color=(0.9, 0.8, 0.7), intensity=2.0, attenuation=(1, 0.2, 0.1), ambient=(0.1,) * 3)
    area = sl.AreaLight((0.5, 2, 0), (3, 0, 0), (0, 0, 3), samples=1, **kw)
    point = sl.PointLight((0.5, 2, 0), **kw)
    for shading in ("flat", "gouraud", "phong"):
        a = sl.render(_floor_scene(area), cam, 64, 48, shading=shading, dtype="float32")
        b = sl.render(_floor_scene(point), cam, 64, 48, shading=shading, dtype="float32")
        np.testing.assert_array_equal(a, b)
    frame = sl.render_frame(_floor_scene(area), cam, 8, 8)
    assert frame["stats"]["light_sources"] == 1
    big = sl.AreaLight((0.5, 2, 0), (3, 0, 0), (0, 0, 3), samples=7)
    assert sl.render_frame(_floor_scene(big), cam, 8, 8)["stats"]["light_sources"] == 49


def test_area_light_total_light_does_not_depend_on_samples():
    """Far from a small light, every sample count gives the point light's image (the points
    share the colour); close to a large one, the sampled lights converge as samples grow."""
    cam = sl.Camera.look_at((0, 5, 6), (0, 0, 0))
    far = sl.render(_floor_scene(sl.PointLight((0, 200, 0))), cam, 32, 24, dtype="float32")
    for n in (2, 5, 9):
        small = sl.AreaLight((0, 200, 0), (0.01, 0, 0), (0, 0, 0.01), samples=n)
        img = sl.render(_floor_scene(small), cam, 32, 24, dtype="float32")
        np.testing.assert_allclose(img, far, rtol=1e-4, atol=1e-6)
    big = [
        sl.render(
            _floor_scene(sl.AreaLight((0, 1, 0), (4, 0, 0), (0, 0, 4), samples=n)),
            cam,
            32,
            24,
            dtype="float32",
        )
        for n in (4, 16, 32)
    ]
    assert np.abs(big[2] - big[1]).max() < np.abs(big[1] - big[0]).max()


def test_one_sided_area_light_is_dark_behind():
    cam = sl.Camera.look_at((0, 5, 6), (0, 0, 0))
    # u x v = z x x = +y: emits upward, away from the floor below it.
    up = sl.AreaLight((0, 1, 0), (0, 0, 1), (1, 0, 0), one_sided=True)
    assert up.normal == (0.0, 1.0, 0.0)
    img = sl.render(_floor_scene(up), cam, 32, 24, dtype="float32")
    emission = np.zeros(3, np.float32)
    assert np.all(img == emission)
    down = sl.AreaLight((0, 1, 0), (1, 0, 0), (0, 0, 1), one_sided=True)
    both = sl.AreaLight((0, 1, 0), (1, 0, 0), (0, 0, 1))
    lit = sl.render(_floor_scene(down), cam, 32, 24, dtype="float32")
    full = sl.render(_floor_scene(both), cam, 32, 24, dtype="float32")
    # The cosine fall-off only dims: lit somewhere, never brighter than two-sided.
    assert lit.max() > 0 and np.all(lit <= full + 1e-6)


def test_light_diffuse_and_specular_colours_split_the_shorthand():
    """Hand-computed: n = l = v = +z, so n·l = n·h = 1 and c = kd·Id + ks·Is."""
    v = np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], float)
    mat = sl.Material(ambient=(0, 0, 0), diffuse=(0.5, 0.5, 0.5), specular=(0.25,) * 3)
    cam = sl.Camera.orthographic((0, 0, 5), (0, 0, 0), height=2.0)
    lights = [
        sl.DirectionalLight((0, 0, -1), intensity=2.0, diffuse=(1, 0, 0), specular=(0, 0, 1)),
        sl.PointLight((0, 0, 1e4), intensity=2.0, diffuse=(1, 0, 0), specular=(0, 0, 1)),
        sl.SpotLight((0, 0, 1e4), (0, 0, -1), intensity=2.0, diffuse=(1, 0, 0), specular=(0, 0, 1)),
        sl.AreaLight(
            (0, 0, 1e4), (1, 0, 0), (0, 1, 0), intensity=2.0, diffuse=(1, 0, 0), specular=(0, 0, 1)
        ),
    ]
    for light in lights:
        assert (light.diffuse, light.specular) == ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0))
        assert light.color == (1.0, 1.0, 1.0)
        s = sl.Scene(ambient=(0, 0, 0), local_viewer=False)  # v = +z everywhere
        s.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=mat)
        s.add_light(light)
        img = sl.render(s, cam, 4, 4, shading="phong", dtype="float32")
        np.testing.assert_allclose(img[1, 1], [1.0, 0.0, 0.5], atol=2e-5)
    # Only one of the two set: the other follows color.
    d = sl.DirectionalLight((0, 0, -1), color=(0, 1, 0), specular=(1, 1, 1))
    assert (d.diffuse, d.specular) == (None, (1.0, 1.0, 1.0))
