"""Reflection, refraction and transparency (issue 13) against the float64 reference
(shadelab_ref.reflect) and exact properties.

Tolerances: images are compared in uint8 levels; a pixel "matches" within 1 level. The ray
technique against the reference's Whitted tracer: >= 99.9 % of the pixels whose primary
ray is not within EDGE_PX of a triangle edge (float32 against float64 ray hits can pick
the other triangle there) must match.
"""

from __future__ import annotations

import itertools
import math
import pickle

import numpy as np
import pytest
import shadelab_rs as sl

from shadelab_ref import reference as ref
from shadelab_ref import reflect as rr

SUN = ref.DirectionalLight(direction=(-0.4, -1.0, -0.6), color=(1.0, 1.0, 1.0), intensity=0.9)


def sun() -> sl.DirectionalLight:
    return sl.DirectionalLight(direction=SUN.direction, color=SUN.color, intensity=SUN.intensity)


def sky(h: int = 32) -> np.ndarray:
    """A smooth, asymmetric equirectangular test sky (linear float32)."""
    rows = (np.arange(h) + 0.5) / h
    cols = (np.arange(2 * h) + 0.5) / (2 * h)
    v, u = np.meshgrid(rows, cols, indexing="ij")
    img = np.stack(
        [0.2 + 0.8 * (1 - v), 0.3 + 0.5 * np.sin(2 * np.pi * u) ** 2, 0.2 + 0.6 * v * u], axis=-1
    )
    return img.astype(np.float32)


def quad(center, half_x, half_z, y=0.0):
    """A horizontal square facing +y."""
    cx, cz = center
    v = np.array(
        [
            [cx - half_x, y, cz - half_z],
            [cx - half_x, y, cz + half_z],
            [cx + half_x, y, cz + half_z],
            [cx + half_x, y, cz - half_z],
        ]
    )
    return v, np.array([[0, 1, 2], [0, 2, 3]])


def ref_mat(m: sl.Material) -> ref.Material:
    return ref.Material(m.ambient, m.diffuse, m.specular, m.shininess, m.emission)


# ---------------------------------------------------------------------------------------
# Optics of the reference itself (closed forms)


@pytest.mark.parametrize("name", ["water", "glass", "diamond"])
def test_snell_sweep_and_critical_angles(name):
    n = rr.IOR[name]
    normal = np.array([0.0, 1.0, 0.0])
    for deg in np.linspace(0, 89.5, 180):
        a = math.radians(deg)
        v = np.array([math.sin(a), math.cos(a), 0.0])
        for n1, n2 in ((1.0, n), (n, 1.0)):
            t = rr.refract(normal, v, n1, n2)
            if n1 * math.sin(a) > n2:
                assert np.isnan(t).all()
            else:
                assert abs(np.linalg.norm(t) - 1) < 1e-12
                assert abs(n1 * math.sin(a) - n2 * abs(t[0])) < 1e-12
                assert t[1] < 0 and t[0] <= 0
    want = {"water": 48.75, "glass": 41.81, "diamond": 24.62}[name]
    crit = rr.critical_angle(n, 1.0)
    assert abs(crit - want) < 0.005
    for eps, tir in ((-1e-6, False), (1e-6, True)):
        a = math.radians(crit + eps)
        v = np.array([math.sin(a), math.cos(a), 0.0])
        assert np.isnan(rr.refract(normal, v, n, 1.0)).all() == tir


def test_schlick_and_mirror_formulas():
    for n in rr.IOR.values():
        assert float(rr.schlick(1.0, 1.0, n)) == pytest.approx(((1 - n) / (1 + n)) ** 2)
    assert float(rr.schlick(0.3, 1.0, 1.0)) == 0.0
    n = np.array([0.0, 0.0, 1.0])
    v = rr._unit([0.3, -0.2, 0.9])
    r = rr.reflect(n, v)
    assert np.allclose(r, 2 * np.dot(n, v) * n - v)
    assert np.allclose(r, [-v[0], -v[1], v[2]])
    # A slab: the exact lateral shift (thickness 1, 45 degrees, glass).
    t2 = math.asin(math.sin(math.radians(45)) / 1.5)
    assert rr.lateral_shift(1.0, 45.0, 1.5) == pytest.approx(
        math.sin(math.radians(45) - t2) / math.cos(t2)
    )


# ---------------------------------------------------------------------------------------
# Environment


def test_environment_lookup_matches_the_reference():
    img = sky(16)
    env = sl.Environment(img, rotation=30.0, intensity=1.5)
    rng = np.random.default_rng(3)
    d = rng.normal(size=(500, 3))
    got = env.sample(d)
    want = rr.environment(img, d, rotation=30.0, intensity=1.5)
    assert np.abs(got - want).max() < 1e-4
    # Row 0 is straight up; the centre column looks along -z.
    plain = sl.Environment(img)
    assert np.allclose(
        plain.sample([0.0, 1.0, 0.0]), img[0].mean(axis=0) * 0 + img[0, 0], atol=0.05
    )
    assert np.allclose(plain.sample([0.0, 0.0, -1.0]), img[7:9, 15:17].mean(axis=(0, 1)), atol=1e-6)


def test_environment_background_shows_each_view_ray():
    img = sky(16)
    scene = sl.Scene(environment=sl.Environment(img))
    cam = sl.Camera.look_at((0, 0, 0), (0, 0, -1), (0, 1, 0), fov_y=60)
    out = sl.render(scene, cam, width=32, height=24, background="environment", dtype="float32")
    _origin, direction = ref.pixel_rays(ref.Camera((0, 0, 0), (0, 0, -1), (0, 1, 0), 60), 32, 24)
    want = rr.environment(img, direction)
    assert np.abs(out - want).max() < 1e-4


@pytest.mark.parametrize(
    "array, message",
    [
        (np.zeros((4, 4, 3), np.float32), "twice as wide"),
        (np.zeros((4, 8), np.float32), "shape"),
        (np.zeros((4, 8, 4), np.float32), "shape"),
        (np.zeros((0, 0, 3), np.float32), "empty"),
        (np.full((2, 4, 3), np.nan, np.float32), "finite"),
        (np.full((2, 4, 3), np.inf, np.float32), "finite"),
        (np.full((2, 4, 3), -1.0, np.float32), "finite and in"),
        (np.zeros((2, 4, 3), np.int32), "dtype"),
    ],
)
def test_bad_environments_are_refused(array, message):
    with pytest.raises((ValueError, TypeError), match=message) as e:
        sl.Environment(array)
    assert getattr(e.value, "field", "array") == "array"


def test_environment_arguments_and_background_need_an_environment():
    with pytest.raises(ValueError, match="intensity"):
        sl.Environment(sky(4), intensity=-1)
    with pytest.raises(ValueError, match="rotation"):
        sl.Environment(sky(4), rotation=float("nan"))
    u8 = sl.Environment((sky(4) * 255).astype(np.uint8))
    assert u8.array.dtype == np.float32 and u8.array.max() <= 1.0
    scene = sl.Scene()
    scene.add(sl.Mesh.uv_sphere(8, 16))
    cam = sl.Camera.look_at((0, 0, 4), (0, 0, 0), (0, 1, 0))
    with pytest.raises(ValueError, match="environment") as e:
        sl.render(scene, cam, width=8, height=8, background="environment")
    assert e.value.field == "background"
    with pytest.raises(ValueError, match="background"):
        sl.RenderOptions(background="sky")


# ---------------------------------------------------------------------------------------
# Materials


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"reflectivity": 1.5}, "reflectivity"),
        ({"reflectivity": -0.1}, "reflectivity"),
        ({"reflectivity": float("nan")}, "reflectivity"),
        ({"reflectivity": (0.5, 0.5, 2.0)}, "reflectivity"),
        ({"transparency": -0.5}, "transparency"),
        ({"transparency": float("nan")}, "transparency"),
        ({"transparency": 0.6, "reflectivity": 0.6}, "transparency"),
        ({"ior": 0.0}, "ior"),
        ({"ior": -1.5}, "ior"),
        ({"ior": float("inf")}, "ior"),
        ({"ior": "lava"}, "ior"),
        ({"absorption": -1.0}, "absorption"),
    ],
)
def test_bad_optics_name_the_field(kwargs, field):
    with pytest.raises(ValueError) as e:
        sl.Material(**kwargs)
    assert e.value.field == field


def test_optics_presets_getters_and_pickling():
    m = sl.Material(reflectivity=(0.9, 0.6, 0.3), transparency=0.1, ior="diamond", fresnel=False)
    assert m.ior == pytest.approx(2.4) and m.fresnel is False
    assert m.reflectivity == pytest.approx((0.9, 0.6, 0.3))
    for name, n in rr.IOR.items():
        assert sl.Material(ior=name).ior == pytest.approx(n)
    assert pickle.loads(pickle.dumps(m)) == m
    assert m.with_optics() == sl.Material(fresnel=True).with_optics()
    assert "reflectivity" in repr(m)
    env = sl.Environment(sky(4), rotation=10, intensity=2)
    assert pickle.loads(pickle.dumps(env)) == env
    scene = sl.Scene(environment=env)
    scene.add(sl.Mesh.uv_sphere(6, 12), material=m)
    back = pickle.loads(pickle.dumps(scene))
    assert back.environment == env and back.objects[0].material == m
    opts = sl.RenderOptions(reflections="ray", refractions="environment", max_depth=7)
    assert sl.RenderOptions(**opts.to_dict()) == opts
    assert pickle.loads(pickle.dumps(opts)) == opts
    env_bg = sl.RenderOptions(background="environment")
    assert env_bg.background == "environment" and sl.RenderOptions(**env_bg.to_dict()) == env_bg
    for bad, field in (
        ({"reflections": "mirror"}, "reflections"),
        ({"refractions": "snell"}, "refractions"),
        ({"max_depth": -1}, "max_depth"),
        ({"max_depth": 1000}, "max_depth"),
    ):
        with pytest.raises(ValueError) as e:
            sl.RenderOptions(**bad)
        assert e.value.field == field


# ---------------------------------------------------------------------------------------
# Images against the reference tracer


def mirror_scene():
    """A mirror floor (reflectivity 0.8) under a red sphere, a sky around them."""
    sphere = sl.Mesh.uv_sphere(24, 48)
    red = sl.Material((0.2, 0.05, 0.05), (0.8, 0.15, 0.1), (0.4, 0.4, 0.4), 30.0)
    mirror = sl.Material(
        (0.05, 0.05, 0.05), (0.2, 0.2, 0.2), (0.0, 0.0, 0.0), 1.0, reflectivity=0.8
    )
    t = np.eye(4)
    t[:3, :3] *= 0.6
    t[1, 3] = 0.7
    fv, ff = quad((0.0, 0.0), 2.5, 2.5)
    return sphere, red, t, mirror, (fv, ff)


def sl_mirror(reflections="ray", **kw):
    sphere, red, t, mirror, (fv, ff) = mirror_scene()
    scene = sl.Scene(ambient=(0.15, 0.15, 0.15), environment=sl.Environment(sky()))
    scene.add(sphere, material=red, transform=t)
    scene.add(sl.Mesh(fv, ff), material=mirror)
    scene.add_light(sun())
    return scene


CAM = ref.Camera(eye=(0.0, 1.6, 3.4), target=(0.0, 0.3, 0.0), up=(0.0, 1.0, 0.0), fov_y=45.0)


def sl_cam(c=CAM) -> sl.Camera:
    return sl.Camera.look_at(c.eye, c.target, c.up, fov_y=c.fov_y, near=c.near, far=c.far)


def ref_mirror(reflections="ray") -> rr.TracedScene:
    sphere, red, t, mirror, (fv, ff) = mirror_scene()
    sv = sphere.vertices @ t[:3, :3].T + t[:3, 3]
    return rr.TracedScene(
        surfaces=[
            rr.Surface(sv, sphere.faces, ref_mat(red), normals=sphere.normals),
            rr.Surface(fv, ff, ref_mat(mirror), normals=None, reflectivity=(0.8, 0.8, 0.8)),
        ],
        lights=[SUN],
        ambient=(0.15, 0.15, 0.15),
        env=sky(),
        reflections=reflections,
    )


def edge_mask(scene, cam, w, h):
    """Pixels whose primary ray is farther than EDGE_PX from any triangle edge."""
    img = ref.render_reference(
        np.concatenate(
            [o.mesh.vertices @ o.transform[:3, :3].T + o.transform[:3, 3] for o in scene.objects]
        ),
        np.concatenate(
            [
                o.mesh.faces + off
                for o, off in zip(
                    scene.objects,
                    np.cumsum([0] + [len(o.mesh.vertices) for o in scene.objects])[:-1],
                )
            ]
        ),
        camera=cam,
        width=w,
        height=h,
        material=ref.Material((0,) * 3, (0,) * 3, (0,) * 3, 1.0),
        lights=[],
    )
    return ~img.mask | (img.edge_dist > 0.5)


@pytest.mark.parametrize("technique", ["ray", "environment"])
def test_mirror_floor_reflects_the_sphere_like_the_reference(technique):
    w, h = 96, 72
    got = sl.render(
        sl_mirror(), sl_cam(), width=w, height=h, reflections=technique, dtype="float32"
    )
    want = rr.trace(ref_mirror(technique), CAM, w, h)
    keep = edge_mask(sl_mirror(), CAM, w, h)
    diff = np.abs(ref.to_uint8(got).astype(int) - ref.to_uint8(want).astype(int)).max(axis=-1)
    share = float(np.mean(diff[keep] <= 1))
    assert share >= 0.999, (share, int(diff.max()))
    if technique == "ray":
        # The sphere shows in the mirror: red-dominant pixels below the sphere's own.
        floor = got[h * 3 // 4 :, w // 3 : 2 * w // 3]
        assert (floor[..., 0] > 2 * floor[..., 2]).sum() > 20


def test_max_depth_zero_is_the_environment_technique():
    scene = sl_mirror()
    a = sl.render(scene, sl_cam(), width=48, height=36, reflections="ray", max_depth=0)
    b = sl.render(scene, sl_cam(), width=48, height=36, reflections="environment")
    assert np.array_equal(a, b)


def test_parallel_mirrors_stop_at_max_depth():
    # Two facing mirrors (reflectivity 1): every bounce is followed up to max_depth, then
    # the environment; no hang, finite output, and deeper limits change the image.
    scene = sl.Scene(environment=sl.Environment(sky()))
    m = sl.Material((0, 0, 0), (0, 0, 0), (0, 0, 0), 1.0, reflectivity=1.0)
    for y, flip in ((0.0, False), (1.0, True)):
        v, f = quad((0.0, 0.0), 50.0, 50.0, y)
        scene.add(sl.Mesh(v, f[:, ::-1] if flip else f), material=m)
    cam = sl.Camera.look_at((0, 0.5, 0), (1, 0.45, 0), (0, 1, 0), fov_y=50)
    imgs = [
        sl.render(scene, cam, width=32, height=32, reflections="ray", max_depth=d, dtype="float32")
        for d in (1, 2, sl.MAX_TRACE_DEPTH)
    ]
    assert all(np.isfinite(i).all() for i in imgs)
    assert not np.array_equal(imgs[0], imgs[1])


def test_ray_results_do_not_depend_on_threads():
    scene = sl_mirror()
    a = sl.render(scene, sl_cam(), width=64, height=48, reflections="ray", threads=1)
    b = sl.render(scene, sl_cam(), width=64, height=48, reflections="ray", threads=2)
    assert np.array_equal(a, b)


def test_opaque_pixels_are_unchanged_by_the_stage():
    # The same scene with the mirror made opaque: pixels of the sphere (not in the mirror)
    # are bit-identical.
    scene = sl_mirror()
    plain = sl.Scene(ambient=(0.15, 0.15, 0.15))
    for o in scene.objects:
        m = o.material.with_optics()
        plain.add(o.mesh, material=m, transform=o.transform)
    plain.add_light(sun())
    a = sl.render(scene, sl_cam(), width=64, height=48, dtype="float32", return_depth=True)
    b = sl.render(plain, sl_cam(), width=64, height=48, dtype="float32", return_depth=True)
    only = sl.Scene()
    only.add(scene.objects[0].mesh, transform=scene.objects[0].transform)
    _, d = sl.render(only, sl_cam(), width=64, height=48, return_depth=True)
    sphere = d == a[1]  # the sphere's own pixels
    assert sphere.sum() > 300
    assert np.array_equal(a[1], b[1])
    assert np.array_equal(a[0][sphere], b[0][sphere])


# ---------------------------------------------------------------------------------------
# Refraction


def slab_scene(theta_deg: float, ior: float, refractions="ray"):
    """A target plane x < 0 white, x >= 0 black (emissive, unlit) at z = -2, a glass slab
    (thickness 1, tilted by theta about y) between it and an orthographic camera."""
    scene = sl.Scene(ambient=(0, 0, 0), default_lights=False)
    white = sl.Material((0, 0, 0), (0, 0, 0), (0, 0, 0), 1.0, emission=(1, 1, 1))
    black = sl.Material((0, 0, 0), (0, 0, 0), (0, 0, 0), 1.0, emission=(0, 0, 0))
    for x0, m in ((-20.0, white), (0.0, black)):
        v = np.array([[x0, -20, -3.0], [x0 + 20, -20, -3.0], [x0 + 20, 20, -3.0], [x0, 20, -3.0]])
        scene.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=m)
    glass = sl.Material(
        (0, 0, 0), (0, 0, 0), (0, 0, 0), 1.0, transparency=1.0, ior=ior, fresnel=False
    )
    box = sl.Mesh.cube()  # [-1, 1]^3 -> thickness 1 in z, wide in x and y
    t = np.diag([4.0, 0.5, 0.5, 1.0])
    t[:3, :3] = ref_rot_y(theta_deg) @ t[:3, :3]
    t[2, 3] = -1.0
    scene.add(box, material=glass, transform=t)
    return scene


def ref_rot_y(deg):
    a = math.radians(deg)
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


@pytest.mark.parametrize("theta", [20.0, 40.0])
def test_glass_slab_shifts_the_view_by_the_exact_lateral_offset(theta):
    w, h = 400, 40
    cam = sl.Camera.orthographic((0, 0, 5), (0, 0, 0), (0, 1, 0), height=1.0, near=0.1, far=20)
    img = sl.render(
        slab_scene(theta, 1.5), cam, width=w, height=h, refractions="ray", dtype="float32"
    )
    px = 10.0 / w  # world units per pixel (width 10 at aspect 10)
    row = img[h // 4, :, 0]  # a row through the slab (|y| < 0.5)
    # The first black pixel near the centre (the slab's end faces are far to the sides).
    lo = w // 2 - 40
    edge = lo + int(np.argmax(row[lo:] < 0.5))
    # Without the slab the edge is at x = 0, the image centre (checked below). Inside a
    # slab turned by +theta about y the ray bends toward -x and leaves parallel to itself
    # moved by d, so the ray through x = +d meets the target's edge: it appears at x = d.
    d = rr.lateral_shift(1.0, theta, 1.5)
    x_edge = (edge - w / 2) * px
    assert abs(x_edge - d) <= px, (x_edge, d)
    straight = sl.render(slab_scene(theta, 1.5), cam, width=w, height=h, dtype="float32")
    edge0 = lo + int(np.argmax(straight[h // 4, lo:, 0] < 0.5))
    assert edge0 == w // 2


def test_ior_one_and_full_transparency_are_invisible():
    # A pane with transparency 1 and ior 1 (ray or none) lets the scene through unchanged.
    base = sl_mirror()
    base_img = sl.render(
        base, sl_cam(), width=64, height=48, reflections="environment", dtype="float32"
    )
    # Rays through the pane that leave the scene read the environment.
    env_bg = sl.render(
        base,
        sl_cam(),
        width=64,
        height=48,
        reflections="environment",
        background="environment",
        dtype="float32",
    )
    for refractions in (None, "ray"):
        s = sl_mirror()
        pane = sl.Material((0, 0, 0), (0, 0, 0), (0, 0, 0), 1.0, transparency=1.0, ior=1.0)
        v = np.array([[-3, -1, 1.5], [3, -1, 1.5], [3, 3, 1.5], [-3, 3, 1.5]], float)
        s.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=pane)
        img = sl.render(
            s,
            sl_cam(),
            width=64,
            height=48,
            reflections="environment",
            refractions=refractions,
            dtype="float32",
        )
        if refractions is None:
            assert np.array_equal(img, base_img)
        else:
            diff = np.abs(ref.to_uint8(img).astype(int) - ref.to_uint8(env_bg).astype(int))
            assert np.mean(diff.max(axis=-1) <= 1) >= 0.99


def test_ior_below_one_and_grazing_views_stay_finite():
    for ior in (0.5, 1.0, 2.4):
        scene = sl.Scene(environment=sl.Environment(sky()))
        m = sl.Material(transparency=0.7, reflectivity=0.2, ior=ior)
        scene.add(sl.Mesh.uv_sphere(16, 32), material=m)
        v, f = quad((0, 0), 3, 3, -1.0)
        scene.add(sl.Mesh(v, f), material=sl.Material(reflectivity=0.5))
        cam = sl.Camera.look_at((0, -0.95, 4), (0, -1.0, 0), (0, 1, 0))  # grazing the floor
        for technique in ("environment", "ray"):
            img = sl.render(
                scene,
                cam,
                width=40,
                height=30,
                reflections=technique,
                refractions=technique,
                dtype="float32",
            )
            assert np.isfinite(img).all() and img.min() >= 0


# ---------------------------------------------------------------------------------------
# Order-independent transparency


def planes_scene(order):
    colors = [(1.0, 0.1, 0.1), (0.1, 1.0, 0.1), (0.1, 0.1, 1.0)]
    zs = [0.0, -0.5, -1.0]
    offsets = [(-0.4, 0.0), (0.0, 0.3), (0.4, 0.0)]
    scene = sl.Scene(ambient=(0, 0, 0), default_lights=False)
    for k in order:
        (cx, cy), z = offsets[k], zs[k]
        v = np.array(
            [
                [cx - 0.8, cy - 0.8, z],
                [cx + 0.8, cy - 0.8, z],
                [cx + 0.8, cy + 0.8, z],
                [cx - 0.8, cy + 0.8, z],
            ]
        )
        m = sl.Material((0, 0, 0), (0, 0, 0), (0, 0, 0), 1.0, emission=colors[k], transparency=0.4)
        scene.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=m)
    return scene, colors, zs, offsets


def test_three_transparent_planes_give_the_same_pixels_in_every_order():
    cam = sl.Camera.look_at((0, 0, 4), (0, 0, 0), (0, 1, 0), fov_y=40)
    imgs = {}
    for order in itertools.permutations(range(3)):
        scene, *_ = planes_scene(order)
        imgs[order] = sl.render(
            scene, cam, width=80, height=60, background=(0.5, 0.5, 0.5), dtype="float32"
        )
    first = next(iter(imgs.values()))
    for img in imgs.values():
        assert np.array_equal(img, first)
    # Against the reference's sorted blend, at pixel centres inside each overlap.
    _, colors, zs, offsets = planes_scene((0, 1, 2))
    rc = ref.Camera((0, 0, 4), (0, 0, 0), (0, 1, 0), 40)
    _origin, direction = ref.pixel_rays(rc, 80, 60)
    checked = 0
    for y in range(60):
        for x in range(80):
            d = direction[y, x]  # eye at origin looking down -z: world = eye + t*d
            layers = []
            for k in range(3):
                t = 4 - zs[k]  # eye depth of plane k
                px, py = d[0] * t, d[1] * t
                (cx, cy) = offsets[k]
                inside = abs(px - cx) < 0.79 and abs(py - cy) < 0.79
                outside = abs(px - cx) > 0.81 or abs(py - cy) > 0.81
                if not (inside or outside):
                    break
                if inside:
                    layers.append(k)
            else:
                want = rr.blend_sorted(
                    [np.array(colors[k]) * 0.6 for k in layers],
                    [0.4] * len(layers),
                    [4 - zs[k] for k in layers],
                    (0.5, 0.5, 0.5),
                )
                assert np.abs(first[y, x] - want).max() < 1e-5, (x, y, layers)
                checked += 1
    assert checked > 3000


def test_transparency_zero_is_opaque_and_thread_count_does_not_matter():
    scene, *_ = planes_scene((2, 0, 1))
    cam = sl.Camera.look_at((0, 0, 4), (0, 0, 0), (0, 1, 0), fov_y=40)
    a = sl.render(scene, cam, width=64, height=48, threads=1)
    b = sl.render(scene, cam, width=64, height=48, threads=2)
    assert np.array_equal(a, b)
    opaque = sl.Scene(ambient=(0, 0, 0), default_lights=False)
    for o in scene.objects:
        opaque.add(o.mesh, material=o.material.with_optics(transparency=0.0), transform=o.transform)
    assert opaque.objects[0].material.transparency == 0.0
    sl.render(opaque, cam, width=16, height=16)
    # Multi-sample anti-aliasing works with transparency (tests/test_reflect_msaa.py), and
    # with any thread count too.
    a4 = sl.render(scene, cam, width=64, height=48, threads=1, samples=4)
    b4 = sl.render(scene, cam, width=64, height=48, threads=2, samples=4)
    assert np.array_equal(a4, b4) and not np.array_equal(a4, a)


# ---------------------------------------------------------------------------------------
# Scene files, to_dict/from_dict, the command line


def test_scene_file_round_trip_with_optics_and_environment(tmp_path):
    np.save(tmp_path / "sky.npy", sky(8))
    env = sl.load_environment(tmp_path / "sky.npy", rotation=15.0, intensity=1.25)
    assert env.path == tmp_path / "sky.npy"
    scene = sl.Scene(environment=env)
    scene.add(
        sl.Mesh.uv_sphere(8, 16),
        material=sl.Material(reflectivity=(0.5, 0.4, 0.3), transparency=0.3, ior="water"),
    )
    scene.add(sl.Mesh.plane(), material="gold")
    cam = sl.Camera.look_at((0, 1, 4), (0, 0, 0), (0, 1, 0))
    opts = {
        "width": 40,
        "height": 30,
        "reflections": "ray",
        "refractions": "ray",
        "max_depth": 3,
        "background": "environment",
    }
    path = tmp_path / "glass.toml"
    sl.save_scene(path, scene, cam, opts)
    text = path.read_text()
    assert "reflectivity" in text and "environment" in text and "max_depth" in text
    sf = sl.load_scene(path)
    assert sf.scene.environment == env
    assert sf.scene.objects[0].material == scene.objects[0].material
    assert sf.scene.objects[1].material == sl.Material.preset("gold")
    assert sf.render().tobytes() == sl.render(scene, cam, **opts).tobytes()
    back = sl.load_scene_dict(sl.scene_to_dict(scene, cam, opts), base_dir=tmp_path)
    assert back.render().tobytes() == sf.render().tobytes()
    # An array-made environment has no file to name.
    scene.environment = sl.Environment(sky(4))
    with pytest.raises(ValueError, match="array"):
        sl.scene_to_dict(scene)
    # Bad values are reported at their key.
    bad = sl.scene_to_dict(sf.scene, cam, opts)
    bad["objects"][0]["material"]["transparency"] = 1.5
    with pytest.raises(sl.SceneFileError) as e:
        sl.load_scene_dict(bad)
    assert "objects[0].material.transparency" in str(e.value)
    bad = sl.scene_to_dict(sf.scene, cam, opts)
    bad["render"]["max_depth"] = 99
    with pytest.raises(sl.SceneFileError) as e:
        sl.load_scene_dict(bad)
    assert "render.max_depth" in str(e.value)


def test_command_line_flags(tmp_path):
    from PIL import Image

    np.save(tmp_path / "sky.npy", sky(8))
    out = tmp_path / "m.png"
    from shadelab_rs import cli

    code = cli.main(
        [
            "render",
            str(sl.data_path("cube/cube.obj")),
            "-o",
            str(out),
            "--size",
            "32x24",
            "--environment",
            str(tmp_path / "sky.npy"),
            "--background",
            "environment",
            "--reflections",
            "ray",
            "--refractions",
            "none",
            "--max-depth",
            "2",
        ]
    )
    assert code == 0
    img = np.asarray(Image.open(out))
    assert img.shape == (24, 32, 3) and img.std() > 0


def test_gallery_is_linked_from_the_lighting_guide():
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    guide = (root / "docs" / "LIGHTING.md").read_text(encoding="utf-8")
    captions = (root / "docs" / "reflect" / "captions.md").read_text(encoding="utf-8")
    for name in ("mirror", "glass", "water", "transparent", "antialiased"):
        png = root / "docs" / "reflect" / f"{name}.png"
        assert png.is_file() and png.stat().st_size < 600_000
        assert f"(reflect/{name}.png)" in guide
        assert f"({name}.png)" in captions and "sl.render(" in captions


def test_material_sheet_has_optical_swatches():
    from shadelab_rs.swatch import OPTICAL_SWATCHES

    sheet = sl.material_sheet(["gold", *OPTICAL_SWATCHES], cell=48, columns=5, labels=False)
    assert sheet.shape == (48, 240, 3)
    cells = [sheet[:, 48 * k : 48 * (k + 1)].astype(int) for k in range(5)]
    # Each optical swatch differs from the others (glass, water and diamond bend the sky
    # differently; the mirror reflects it).
    for a, b in itertools.combinations(cells[1:], 2):
        assert np.abs(a - b).mean() > 1.0
    with pytest.raises(ValueError, match="preset"):
        sl.material_sheet(["unobtainium"])
