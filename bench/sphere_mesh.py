"""The unit UV sphere the benchmarks draw, in NumPy only: `bench_features.py` imports
shadelab_rs lazily (its ``--worker`` may run an older build) and must not pull it in."""

from __future__ import annotations

import numpy as np


def uv_sphere(n_lat: int, n_lon: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit UV sphere at the origin: single-vertex poles, ``n_lat - 1`` rings of ``n_lon``
    vertices, counter-clockwise faces seen from outside. Returns float32 vertices
    ``(2 + (n_lat-1)*n_lon, 3)`` and int32 faces ``(2*n_lon*(n_lat-1), 3)``."""
    if n_lat < 2 or n_lon < 3:
        raise ValueError("uv_sphere needs n_lat >= 2 and n_lon >= 3")
    theta = np.pi * np.arange(1, n_lat) / n_lat
    phi = 2.0 * np.pi * np.arange(n_lon) / n_lon
    st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
    ring = np.stack(
        [st * np.sin(phi), np.broadcast_to(ct, (n_lat - 1, n_lon)), st * np.cos(phi)], axis=-1
    ).reshape(-1, 3)
    verts = np.concatenate([[[0.0, 1.0, 0.0]], ring, [[0.0, -1.0, 0.0]]])
    south = len(verts) - 1

    j = np.arange(n_lon)
    j1 = (j + 1) % n_lon
    north_cap = np.stack([np.zeros(n_lon, dtype=np.int64), 1 + j, 1 + j1], axis=-1)
    i = np.arange(n_lat - 2)[:, None]
    a, b = 1 + i * n_lon + j, 1 + i * n_lon + j1
    c, d = a + n_lon, b + n_lon
    bands = np.stack([np.stack([a, c, d], -1), np.stack([a, d, b], -1)], axis=2).reshape(-1, 3)
    last = 1 + (n_lat - 2) * n_lon
    south_cap = np.stack([last + j, np.full(n_lon, south), last + j1], axis=-1)
    faces = np.concatenate([north_cap, bands, south_cap])
    return verts.astype(np.float32), faces.astype(np.int32)
