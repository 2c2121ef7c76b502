"""Pinhole cameras from pixel intrinsics K (fx, fy, cx, cy, skew): the rendered image is
where K says, checked against float64 projections of known world points."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shadelab_rs as sl

W, H = 160, 120
EYE, TARGET = (0.4, 0.9, 6.0), (0.1, 0.2, 0.0)
#: Off-centre principal point, skew and non-square pixels.
K_GENERAL = np.array([[190.0, 14.0, 97.25], [0.0, 150.0, 51.5], [0.0, 0.0, 1.0]])


def k_pixel(camera: sl.Camera, K: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Where K sees world point p (float64; x right, y down, pixel centres at +0.5)."""
    e = (camera.view_matrix() @ np.append(p, 1.0))[:3]
    x = K @ np.array([e[0], -e[1], -e[2]])
    return x[:2] / x[2]


def camera_axes(camera: sl.Camera) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """World-space right, up and forward of the camera."""
    r = camera.view_matrix()[:3, :3]
    return r[0], r[1], -r[2]


def coverage(mesh: sl.Mesh, camera: sl.Camera, w: int = W, h: int = H) -> np.ndarray:
    scene = sl.Scene(two_sided=True)
    scene.add(mesh)
    _, depth = sl.render(scene, camera, w, h, return_depth=True)
    return np.isfinite(depth)


def marker(camera: sl.Camera, centre: np.ndarray, radius: float) -> sl.Mesh:
    """A small equilateral triangle facing the camera, centred on ``centre``."""
    right, up, _ = camera_axes(camera)
    angles = np.radians([90.0, 210.0, 330.0])
    v = [centre + radius * (math.cos(a) * right + math.sin(a) * up) for a in angles]
    return sl.Mesh(np.array(v), [[0, 1, 2]])


def centroid(mask: np.ndarray) -> np.ndarray:
    rows, cols = np.nonzero(mask)
    assert len(rows) > 0, "nothing drawn"
    return np.array([cols.mean() + 0.5, rows.mean() + 0.5])


def quad(centre: np.ndarray, a: np.ndarray, b: np.ndarray) -> sl.Mesh:
    """The parallelogram centre ± a ± b."""
    v = np.array([centre - a - b, centre + a - b, centre + a + b, centre - a + b])
    return sl.Mesh(v, [[0, 1, 2], [0, 2, 3]])


def test_intrinsics_round_trip_exactly():
    cam = sl.camera_from_intrinsics(K_GENERAL, W, H, EYE, TARGET)
    assert cam.kind == "pinhole" and cam.fov_y is None and cam.height is None
    assert cam.intrinsics == (190.0, 150.0, 97.25, 51.5, 14.0, W, H)
    assert np.array_equal(sl.intrinsics(cam, W, H), K_GENERAL)
    # At twice the size K doubles (pixels are half as big); the aspect may change too.
    np.testing.assert_allclose(sl.intrinsics(cam, 2 * W, 2 * H)[:2], 2 * K_GENERAL[:2])
    K3 = sl.intrinsics(cam, W, 3 * H)
    assert (K3[0, 0], K3[0, 1], K3[1, 1], K3[1, 2]) == (190.0, 14.0, 450.0, 154.5)
    # A look_at camera's K round-trips through a pinhole camera with the same pixels.
    look = sl.Camera.look_at(EYE, TARGET, fov_y=40.0, near=0.5, far=50.0)
    K = sl.intrinsics(look, W, H)
    back = sl.camera_from_intrinsics(K, W, H, EYE, TARGET, near=0.5, far=50.0)
    np.testing.assert_allclose(back.projection_matrix(1.0), look.projection_matrix(W / H))
    assert "from_intrinsics" in repr(cam) and "skew=14" in repr(cam)


@pytest.mark.parametrize("size", [(W, H), (2 * W, 2 * H)])
def test_markers_land_where_k_projects_them(size):
    """Known world points, projected with K in float64, against the rendered markers (at
    the reference size and at twice it, where K scales)."""
    w, h = size
    cam = sl.camera_from_intrinsics(K_GENERAL, W, H, EYE, TARGET, near=0.5, far=50.0)
    K = sl.intrinsics(cam, w, h)
    right, up, fwd = camera_axes(cam)
    points = [
        np.asarray(TARGET),
        np.asarray(TARGET) + 1.2 * right + 0.7 * up,
        np.asarray(TARGET) - 1.5 * right - 0.6 * up + 1.0 * fwd,
        np.asarray(TARGET) + 0.3 * right - 0.9 * up - 2.0 * fwd,
    ]
    for p in points:
        d = float((p - np.asarray(EYE)) @ fwd)
        # About 5 reference pixels across, whatever its depth.
        m = marker(cam, p, 5.0 * d / K_GENERAL[1, 1])
        got = centroid(coverage(m, cam, w, h))
        want = k_pixel(cam, K, p)
        assert np.all(np.abs(got - want) < 0.5 * w / W), (p, got, want)
    # The target is on the optical axis: it is drawn at the principal point.
    np.testing.assert_allclose(k_pixel(cam, K, np.asarray(TARGET)), K[:2, 2], atol=1e-9)


def test_principal_point_shifts_the_image_by_whole_pixels():
    base = np.array([[170.0, 0.0, W / 2], [0.0, 170.0, H / 2], [0.0, 0.0, 1.0]])
    shifted = base.copy()
    shifted[0, 2] += 23
    shifted[1, 2] -= 11
    right, up, _ = camera_axes(sl.camera_from_intrinsics(base, W, H, EYE, TARGET))
    m = quad(np.asarray(TARGET) + 0.2 * right, 0.5 * right + 0.1 * up, 0.3 * up)
    a = coverage(m, sl.camera_from_intrinsics(base, W, H, EYE, TARGET))
    b = coverage(m, sl.camera_from_intrinsics(shifted, W, H, EYE, TARGET))
    np.testing.assert_allclose(centroid(b) - centroid(a), (23, -11), atol=0.02)
    moved = np.zeros_like(a)
    moved[: H - 11, 23:] = a[11:, : W - 23]
    assert a.sum() > 300 and np.count_nonzero(moved != b) <= 0.01 * a.sum()


def test_skew_shears_and_unequal_focal_lengths_stretch():
    K = np.array([[180.0, 0.0, W / 2], [0.0, 180.0, H / 2], [0.0, 0.0, 1.0]])
    cam = sl.camera_from_intrinsics(K, W, H, EYE, TARGET)
    right, up, fwd = camera_axes(cam)
    dist = float(np.linalg.norm(np.subtract(TARGET, EYE)))
    # A thin vertical bar through the target: skew s moves row v by s (v - cy) / fy.
    bar = quad(np.asarray(TARGET), 0.03 * right, 0.9 * up)
    skewed = K.copy()
    skewed[0, 1] = 40.0
    mask = coverage(bar, sl.camera_from_intrinsics(skewed, W, H, EYE, TARGET))
    rows = np.nonzero(mask.any(axis=1))[0]
    assert len(rows) > 40
    centres = [np.nonzero(mask[r])[0].mean() + 0.5 for r in rows]
    slope = np.polyfit(rows + 0.5, centres, 1)[0]
    assert slope == pytest.approx(40.0 / 180.0, abs=0.01)
    straight = coverage(bar, cam)
    straight_centres = [np.nonzero(straight[r])[0].mean() for r in rows if straight[r].any()]
    assert np.ptp(straight_centres) <= 1.0
    # A square facing the camera: width / height in pixels = fx / fy.
    side = 0.5
    square = quad(np.asarray(TARGET), side * right, side * up)
    for fx, fy in ((180.0, 180.0), (240.0, 120.0), (100.0, 200.0)):
        k = K.copy()
        k[0, 0], k[1, 1] = fx, fy
        m = coverage(square, sl.camera_from_intrinsics(k, W, H, EYE, TARGET))
        cols, rows_ = np.nonzero(m.any(axis=0))[0], np.nonzero(m.any(axis=1))[0]
        assert len(cols) == pytest.approx(2 * side * fx / dist, abs=1.5)
        assert len(rows_) == pytest.approx(2 * side * fy / dist, abs=1.5)
    assert fwd @ np.subtract(TARGET, EYE) > 0


@pytest.mark.parametrize("size", [(W, H), (W, 2 * H)])
def test_fog_distance_of_an_off_centre_camera(size):
    """Linear fog over a tilted plane seen by the general K: each pixel's fog factor is that
    of its Euclidean distance, from its eye depth along K's ray through the pixel centre."""
    w, h = size
    cam = sl.camera_from_intrinsics(K_GENERAL, W, H, EYE, TARGET, near=0.5, far=50.0)
    K = sl.intrinsics(cam, w, h)
    right, up, fwd = camera_axes(cam)
    fog = sl.Fog(mode="linear", start=3.0, end=12.0, color=(0.0, 0.0, 0.0))
    scene = sl.Scene(ambient=(0, 0, 0), fog=fog, default_lights=False)
    plane = quad(np.asarray(TARGET) + 2.0 * fwd, 9.0 * right + 3.0 * fwd, 9.0 * up)
    white = sl.Material(
        ambient=(0, 0, 0), diffuse=(0, 0, 0), specular=(0, 0, 0), emission=(1, 1, 1)
    )
    scene.add(plane, material=white)
    img, depth = sl.render(scene, cam, w, h, dtype="float32", return_depth=True)
    hit = np.isfinite(depth)
    assert hit.mean() > 0.9
    xs, ys = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    rays = np.linalg.solve(K, np.stack([xs, ys, np.ones_like(xs)]).reshape(3, -1))
    dist = depth.astype(np.float64) * np.linalg.norm(rays, axis=0).reshape(h, w)
    want = np.clip((12.0 - dist) / 9.0, 0.0, 1.0)
    assert np.ptp(want[hit]) > 0.2  # the fog varies over the image
    np.testing.assert_allclose(img[..., 0][hit], want[hit], atol=2e-5)
    # A centred frustum's distance would be wrong by far more than that here.
    centred = np.array([[K[0, 0], 0, w / 2], [0, K[1, 1], h / 2], [0, 0, 1]])
    rays_c = np.linalg.solve(centred, np.stack([xs, ys, np.ones_like(xs)]).reshape(3, -1))
    dist_c = depth * np.linalg.norm(rays_c, axis=0).reshape(h, w)
    assert np.abs(np.clip((12.0 - dist_c) / 9.0, 0, 1) - want)[hit].max() > 1e-2


def test_camera_helpers_keep_the_intrinsics():
    cam = sl.camera_from_intrinsics(K_GENERAL, W, H, EYE, TARGET)
    assert cam.near is None and cam.far is None
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    fitted = cam.fitted(scene)
    assert fitted.intrinsics == cam.intrinsics and 0 < fitted.near < fitted.far
    o = sl.orbit(cam, azimuth=30, elevation=10)
    assert o.kind == "pinhole" and o.intrinsics == cam.intrinsics
    d = sl.scene_to_dict(scene, cam)
    assert d["camera"]["type"] == "pinhole"
    assert d["camera"]["fx"] == 190.0 and d["camera"]["width"] == W
    back = sl.load_scene_dict(d).camera
    assert back is not None and back.intrinsics == cam.intrinsics


@pytest.mark.parametrize(
    ("change", "key", "message"),
    [
        ({"fx": 0.0}, "fx", "fx must be > 0"),
        ({"fy": -2.0}, "fy", "fy must be > 0"),
        ({"width": 0}, "width", "width"),
        ({"height": 12.5}, "height", "integer"),
        ({"cx": "a"}, "cx", "number"),
    ],
)
def test_scene_file_errors_name_the_key(change, key, message):
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    d = sl.scene_to_dict(scene, sl.camera_from_intrinsics(K_GENERAL, W, H, EYE, TARGET))
    d["camera"].update(change)
    with pytest.raises(sl.SceneFileError, match=message) as e:
        sl.load_scene_dict(d)
    assert e.value.key == f"camera.{key}"


def test_bad_intrinsics_are_value_errors_naming_the_value():
    kw = dict(fx=100.0, fy=100.0, cx=50.0, cy=40.0, width=100, height=80)
    for name, bad in (("fx", 0.0), ("fy", math.nan), ("cx", math.inf), ("skew", math.nan)):
        with pytest.raises(ValueError, match=name) as e:
            sl.Camera.from_intrinsics(EYE, TARGET, **{**kw, name: bad})
        assert e.value.field == name
    for name in ("width", "height"):
        with pytest.raises(ValueError, match=name) as e:
            sl.Camera.from_intrinsics(EYE, TARGET, **{**kw, name: 0})
        assert e.value.field == name
    with pytest.raises(ValueError, match=r"K\[1, 0\]"):
        sl.camera_from_intrinsics([[100, 0, 50], [3, 100, 40], [0, 0, 1]], 100, 80, EYE, TARGET)
    with pytest.raises(ValueError, match="3x3"):
        sl.camera_from_intrinsics(np.eye(4), 100, 80, EYE, TARGET)
    with pytest.raises(ValueError, match="fx"):
        sl.camera_from_intrinsics([[-1, 0, 50], [0, 100, 40], [0, 0, 1]], 100, 80, EYE, TARGET)
