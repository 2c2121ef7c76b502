"""Exact pixel coverage of screen-space triangles, in float64: the truth that anti-aliasing
is measured against.

Screen space as the renderer's: pixel (x, y) is the unit square [x, x+1) x [y, y+1), y
down, its centre at (x + 0.5, y + 0.5).
"""

from __future__ import annotations

import numpy as np

#: The standard sample positions (Direct3D 11 / Vulkan), in 1/16 pixel from the centre.
STANDARD_SAMPLES: dict[int, list[tuple[int, int]]] = {
    1: [(0, 0)],
    2: [(4, 4), (-4, -4)],
    4: [(-2, -6), (6, -2), (-6, 2), (2, 6)],
    8: [(1, -3), (-1, 3), (5, 1), (-3, -5), (-5, 5), (-7, -1), (3, 7), (7, -7)],
    16: [
        (1, 1), (-1, -3), (-3, 2), (4, -1), (-5, -2), (2, 5), (5, 3), (3, -5),
        (-2, 6), (0, -7), (-4, -6), (-6, 4), (-8, 0), (7, -4), (6, 7), (-7, -8),
    ],
}  # fmt: skip


def _ccw(tri: np.ndarray) -> np.ndarray:
    t = np.asarray(tri, dtype=np.float64)
    area = (t[1, 0] - t[0, 0]) * (t[2, 1] - t[0, 1]) - (t[1, 1] - t[0, 1]) * (t[2, 0] - t[0, 0])
    return t if area > 0 else t[[0, 2, 1]]


def _clip(poly: list[tuple[float, float]], a, b) -> list[tuple[float, float]]:
    """Sutherland-Hodgman: the part of ``poly`` on the left of a -> b (cross >= 0)."""

    def side(p):
        return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])

    out = []
    for i, p in enumerate(poly):
        q = poly[(i + 1) % len(poly)]
        sp, sq = side(p), side(q)
        if sp >= 0:
            out.append(p)
        if (sp >= 0) != (sq >= 0):
            s = sp / (sp - sq)
            out.append((p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])))
    return out


def _area(poly: list[tuple[float, float]]) -> float:
    a = 0.0
    for i, p in enumerate(poly):
        q = poly[(i + 1) % len(poly)]
        a += p[0] * q[1] - q[0] * p[1]
    return abs(a) / 2.0


def area_coverage(triangles, width: int, height: int) -> np.ndarray:
    """(height, width) float64: the exact area of each pixel inside the union of
    ``triangles`` (an (N, 3, 2) array of screen points), assuming they do not overlap."""
    cov = np.zeros((height, width))
    for tri in np.asarray(triangles, dtype=np.float64):
        t = _ccw(tri)
        x0, y0 = np.floor(t.min(axis=0)).astype(int)
        x1, y1 = np.ceil(t.max(axis=0)).astype(int)
        for y in range(max(y0, 0), min(y1, height)):
            for x in range(max(x0, 0), min(x1, width)):
                poly = [(x, y), (x + 1, y), (x + 1, y + 1), (x, y + 1)]
                for k in range(3):
                    poly = _clip(poly, t[k], t[(k + 1) % 3])
                    if not poly:
                        break
                if poly:
                    cov[y, x] += _area(poly)
    return cov


def sample_coverage(triangles, width: int, height: int, samples: int) -> np.ndarray:
    """(height, width) float64: the share of each pixel's standard sample positions strictly
    inside one of ``triangles``, and NaN where a sample lies within ``1/64`` px of an edge
    (where the fill rule and vertex snapping decide)."""
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float64)
    inside = np.zeros((height, width))
    unsure = np.zeros((height, width), dtype=bool)
    for dx, dy in STANDARD_SAMPLES[samples]:
        px, py = xs + 0.5 + dx / 16.0, ys + 0.5 + dy / 16.0
        hit = np.zeros((height, width), dtype=bool)
        for tri in np.asarray(triangles, dtype=np.float64):
            t = _ccw(tri)
            ok = np.ones((height, width), dtype=bool)
            for k in range(3):
                a, b = t[k], t[(k + 1) % 3]
                e = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0])
                dist = e / np.hypot(b[0] - a[0], b[1] - a[1])
                unsure |= np.abs(dist) < 1.0 / 64.0
                ok &= dist > 0
            hit |= ok
        inside += hit
    share = inside / samples
    share[unsure] = np.nan
    return share
