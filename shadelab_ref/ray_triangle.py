"""Ray-triangle intersection for the float64 reference (NumPy only): Moller-Trumbore over
every (ray, triangle) pair of a batch, shared by the exact shadows (:mod:`.shadows`, any hit
on a segment) and the Whitted tracer (:mod:`.reflect`, the closest hit)."""

from __future__ import annotations

import numpy as np


def intersect(o, d, a, e1, e2):
    """``(t, u, v, hit)`` of the rays ``o + t*d`` against the triangles ``a``,
    ``a + e1``, ``a + e2``, broadcast as ``o, d: (R, 1, 3)`` against ``a, e1, e2:
    (1, T, 3)`` to ``(R, T)``. ``hit``: the ray meets the triangle (edges included) at
    ``t > 0``, where ``(u, v)`` are the barycentrics of vertices 1 and 2; elsewhere the
    values are meaningless (a parallel ray divides by zero, silently)."""
    pv = np.cross(d, e2)
    det = np.sum(e1 * pv, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        tv = o - a
        u = np.sum(tv * pv, axis=-1) * inv
        qv = np.cross(tv, e1)
        v = np.sum(d * qv, axis=-1) * inv
        t = np.sum(e2 * qv, axis=-1) * inv
        hit = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    return t, u, v, hit
