"""Inline display in Jupyter and IPython: ``sl.preview(scene)`` renders a small image whose
``_repr_png_`` the notebook shows. CPU only: no GL context and no display are needed."""

from __future__ import annotations

import io
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core import Camera, RenderOptions, Scene
from .io import to_uint8
from .rendering import render


class RenderedImage:
    """An (H, W, 3) image that notebooks display inline (``_repr_png_``).

    ``array`` is the image (uint8, or float32 when rendered so); ``np.asarray(img)`` gives
    it too; ``save(path)`` writes it with Pillow."""

    def __init__(self, array: NDArray[Any]):
        a = np.asarray(array)
        if a.ndim != 3 or a.shape[2] != 3:
            raise ValueError(f"image must have shape (H, W, 3), got {a.shape}")
        self.array = a

    def __array__(self, dtype: Any = None, copy: Any = None) -> NDArray[Any]:
        return self.array if dtype is None else self.array.astype(dtype)

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(self.array.shape)

    def _repr_png_(self) -> bytes:
        from PIL import Image

        buf = io.BytesIO()
        Image.fromarray(to_uint8(self.array)).save(buf, format="PNG")
        return buf.getvalue()

    def save(self, path: str) -> None:
        from .io import save_image

        save_image(self.array, path)

    def __repr__(self) -> str:
        h, w, _ = self.array.shape
        return f"RenderedImage({w}x{h}, dtype={self.array.dtype})"


def preview(
    scene: Scene,
    camera: Camera | None = None,
    *,
    width: int | None = None,
    height: int | None = None,
    options: RenderOptions | None = None,
    **render_options: Any,
) -> RenderedImage:
    """Renders ``scene`` (through ``camera``, or a camera framing every object) into a
    :class:`RenderedImage` that Jupyter shows inline. The options are :func:`render`'s;
    the size is 320 x 240 unless given (or set by ``options``)."""
    if camera is None:
        from .scene_file import frame_scene

        camera = frame_scene(scene)
    if options is None:
        width = 320 if width is None else width
        height = 240 if height is None else height
    size: dict[str, Any] = {
        k: v for k, v in (("width", width), ("height", height)) if v is not None
    }
    image = render(scene, camera, options=options, **size, **render_options)
    return RenderedImage(image)
