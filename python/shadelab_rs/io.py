"""File helpers: meshes through the Rust OBJ loader or trimesh, images through Pillow."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ._core import Mesh, load_obj


def load_mesh(path: str | os.PathLike[str]) -> Mesh:
    """Loads a mesh file: OBJ through the Rust loader, any other format trimesh reads
    (STL, PLY, GLB, OFF, ...) through trimesh, with scenes flattened into one mesh."""
    p = Path(path)
    if p.is_dir():
        raise IsADirectoryError(f"'{p}' is a directory, not a mesh file")
    if p.suffix.lower() == ".obj":
        return load_obj(p)
    if not p.exists():
        raise FileNotFoundError(f"no such file: '{p}'")
    import trimesh

    try:
        tm = trimesh.load(p, force="mesh", process=False)
    except Exception as e:  # trimesh raises many types for bad files
        raise ValueError(f"{p}: cannot read mesh: {e}") from e
    if not hasattr(tm, "faces") or len(tm.faces) == 0:
        raise ValueError(f"{p}: the file contains no triangles")
    return Mesh.from_trimesh(tm)


def to_uint8(image: np.ndarray) -> np.ndarray:
    """A float image as uint8: round(clamp(c, 0, 1) * 255); uint8 input is returned as is."""
    a = np.asarray(image)
    if a.dtype == np.uint8:
        return a
    if a.dtype.kind != "f":
        raise TypeError(f"image must be uint8 or floating point, got dtype {a.dtype}")
    return np.floor(np.clip(np.nan_to_num(a, nan=0.0), 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)


def save_image(image: np.ndarray, path: str | os.PathLike[str]) -> None:
    """Writes an (H, W, 3) uint8 or float image (PNG, JPEG, ... by extension) with Pillow."""
    from PIL import Image

    a = to_uint8(image)
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"image must have shape (H, W, 3), got {a.shape}")
    Image.fromarray(np.ascontiguousarray(a), "RGB").save(os.fspath(path))
