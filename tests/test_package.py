"""Package helpers: demo scene, framing, data files, image conversion and saving, exports."""

from __future__ import annotations

import numpy as np
import pytest
import shadelab_rs as sl
from PIL import Image

# --------------------------------------------------------------------------------------------
# Package helpers
# --------------------------------------------------------------------------------------------


def test_demo_scene_renders():
    scene, cam = sl.demo_scene()
    assert isinstance(scene, sl.Scene) and isinstance(cam, sl.Camera)
    assert scene.n_objects == 4 and scene.n_lights == 2
    img = sl.render(scene, cam, width=96, height=72)
    assert (img > 0).any(axis=-1).mean() > 0.2


def test_frame_mesh_fits_the_mesh():
    spot = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
    cam = sl.frame_mesh(spot.vertices)
    scene = sl.Scene()
    scene.add(spot)
    _, depth = sl.render(scene, cam, width=64, height=64, return_depth=True)
    covered = np.isfinite(depth)
    assert covered.mean() > 0.1
    # Nothing touches the border: the whole model is in frame.
    assert not covered[0].any() and not covered[-1].any()
    assert not covered[:, 0].any() and not covered[:, -1].any()
    # The planes are fitted at render time around the model.
    assert cam.near is None and cam.far is None
    fitted = cam.fitted(scene)
    assert fitted.near < depth[covered].min() and depth[covered].max() < fitted.far


def test_data_path():
    assert sl.data_path("cube/cube.obj").is_file()
    assert sl.data_path("spot/spot_triangulated.obj").is_file()


def test_to_uint8():
    a = np.array([[-1.0, 0.0, 0.5 / 255], [1.5 / 255, 0.5, 1.0], [2.0, np.nan, 254.5 / 255]])
    np.testing.assert_array_equal(sl.to_uint8(a), [[0, 0, 1], [2, 128, 255], [255, 0, 255]])
    np.testing.assert_array_equal(sl.to_uint8(a.astype(np.float32))[0], [0, 0, 1])
    u = np.array([1, 2, 3], dtype=np.uint8)
    assert sl.to_uint8(u) is u
    with pytest.raises(TypeError, match="dtype"):
        sl.to_uint8(np.array([1, 2, 3]))


@pytest.mark.parametrize("dtype", ["uint8", "float32"])
def test_save_image_round_trip(sphere_scene, camera, tmp_path, dtype):
    img = sl.render(sphere_scene, camera, width=40, height=30, dtype=dtype)
    path = tmp_path / "out.png"
    sl.save_image(img, path)
    with Image.open(path) as im:
        assert im.mode == "RGB" and im.size == (40, 30)
        np.testing.assert_array_equal(np.asarray(im), sl.to_uint8(img))
    with pytest.raises(ValueError, match="shape"):
        sl.save_image(np.zeros((4, 4, 5), img.dtype), tmp_path / "bad.png")


def test_version_and_exports():
    assert isinstance(sl.__version__, str) and sl.__version__
    for name in sl.__all__:
        assert hasattr(sl, name), name
    assert issubclass(sl.ObjParseError, ValueError)
