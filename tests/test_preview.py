"""Notebook display: sl.preview returns an image whose _repr_png_ is the render as PNG."""

from __future__ import annotations

import io

import numpy as np
import pytest
import shadelab_rs as sl
from PIL import Image


def test_preview_png_is_the_render():
    scene, camera = sl.demo_scene()
    img = sl.preview(scene, camera, width=64, height=48)
    png = img._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    decoded = np.asarray(Image.open(io.BytesIO(png)))
    assert decoded.tobytes() == sl.render(scene, camera, width=64, height=48).tobytes()
    assert np.asarray(img).shape == img.shape == (48, 64, 3)
    assert "64x48" in repr(img)


def test_preview_frames_the_scene_and_converts_float():
    scene, _ = sl.demo_scene()
    img = sl.preview(scene, dtype="float32", width=40, height=30)
    assert img.array.dtype == np.float32
    decoded = np.asarray(Image.open(io.BytesIO(img._repr_png_())))
    assert decoded.tobytes() == sl.to_uint8(img.array).tobytes()
    assert decoded.max() > 0  # the framing camera sees the objects
    with pytest.raises(ValueError, match="without objects"):
        sl.preview(sl.Scene())
    with pytest.raises(ValueError, match="shape"):
        sl.RenderedImage(np.zeros((4, 4)))
