"""Textures made in Python: :func:`bake_texture` samples a user's function ``f(u, v)`` at
the texel centres of an image (the lectures' "any function" as a texture), which the
renderer then filters like any image."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Literal

import numpy as np

from ._core import MAX_TEXTURE_SIZE, Texture

_Wrap = Literal["repeat", "clamp", "mirror"]


def texel_centres(width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """The (u, v) of every texel centre of a ``width`` x ``height`` image, each an
    (height, width) array with row 0 the top of the image: u = (i + 0.5) / width,
    v = 1 - (j + 0.5) / height."""
    u = (np.arange(width) + 0.5) / width
    v = 1.0 - (np.arange(height) + 0.5) / height
    uu, vv = np.meshgrid(u, v)
    return uu, vv


def bake_texture(
    func: Callable[[np.ndarray, np.ndarray], Any],
    width: int,
    height: int,
    filter: Literal["nearest", "bilinear", "trilinear"] = "trilinear",
    wrap: _Wrap | tuple[_Wrap, _Wrap] = "repeat",
    srgb: bool = False,
) -> Texture:
    """A texture from ``func(u, v)``, called once with the (height, width) arrays of
    :func:`texel_centres`; it returns linear RGB as an (height, width, 3) array (or
    anything that broadcasts to it: a grey (height, width) array is repeated on the three
    channels)."""
    for name, n in (("width", width), ("height", height)):
        if not isinstance(n, (int, np.integer)) or isinstance(n, bool):
            raise TypeError(f"{name} must be an int, got {type(n).__name__}")
        if not 1 <= n <= MAX_TEXTURE_SIZE:
            raise ValueError(f"{name} must be 1 to {MAX_TEXTURE_SIZE}, got {n}")
    u, v = texel_centres(int(width), int(height))
    out = np.asarray(func(u, v), dtype=np.float64)
    if out.shape == u.shape:
        out = np.repeat(out[:, :, None], 3, axis=2)
    try:
        out = np.broadcast_to(out, (height, width, 3))
    except ValueError:
        raise ValueError(
            f"bake_texture: func returned shape {out.shape}, expected ({height}, {width}, 3) "
            f"or ({height}, {width})"
        ) from None
    if not np.isfinite(out).all():
        raise ValueError("bake_texture: func returned a non-finite value")
    return Texture(np.ascontiguousarray(out, dtype=np.float32), filter=filter, wrap=wrap, srgb=srgb)
