"""Float64 reference of normal and bump mapping (tangent space), written from the
definitions in docs/USER_GUIDE.md ("Normal and bump maps"), not from the renderer's code:

* per-vertex tangents: for each face, dP/du and dP/dv from the 2x2 system of its edges and
  UV differences; at each corner both are projected onto the plane of the vertex normal,
  normalised and added weighted by the corner's angle; the vertex's sum is projected and
  normalised again (a vertex with none: any perpendicular of its normal). Handedness
  w = +1 where the summed bitangent lies on the side of N x T, else -1;
* at a pixel: N the interpolated normal (normalised), T the interpolated tangent made
  perpendicular to N (Gram-Schmidt) and normalised, B = sign(w) N x T (w interpolated);
* a normal map's texel t gives the tangent-space normal (s(2r-1), s(2g-1), 2b-1); a bump
  map's height h (mean of r, g, b) gives (-s dh/du, -s dh/dv, 1) with the derivatives by
  central differences of one texel of level 0 (each sample filtered with the pixel's
  footprint); the lit normal is normalize(x T + y B + z N). With both maps, the bump map
  acts in the frame the normal map made.
"""

from __future__ import annotations

import numpy as np

from . import reference as ref
from . import texture as rtex

__all__ = ["perturbed_normals", "vertex_tangents"]


def _unit(a: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(n > 0, a / np.where(n > 0, n, 1.0), 0.0)


def _reject(a: np.ndarray, n: np.ndarray) -> np.ndarray:
    """The unit component of ``a`` perpendicular to the unit ``n`` (zero if none)."""
    return _unit(a - n * np.sum(a * n, axis=-1, keepdims=True))


def vertex_tangents(vertices, faces, uvs, normals) -> np.ndarray:
    """``(N, 4)``: unit tangent (xyz) and handedness (w = +-1) per vertex."""
    v = np.asarray(vertices, np.float64).reshape(-1, 3)
    f = np.asarray(faces, np.int64).reshape(-1, 3)
    uv = np.asarray(uvs, np.float64).reshape(-1, 2)
    nv = _unit(np.asarray(normals, np.float64).reshape(-1, 3))
    tan = np.zeros_like(v)
    bit = np.zeros_like(v)
    for tri in f:
        p, t = v[tri], uv[tri]
        m = np.array([t[1] - t[0], t[2] - t[0]])  # rows (du, dv) of the two edges
        if abs(np.linalg.det(m)) <= 1e-20:
            continue
        dp = np.linalg.solve(m, np.array([p[1] - p[0], p[2] - p[0]]))  # rows dP/du, dP/dv
        for c in range(3):
            a, b = p[(c + 1) % 3] - p[c], p[(c + 2) % 3] - p[c]
            na, nb = np.linalg.norm(a), np.linalg.norm(b)
            if na == 0 or nb == 0:
                continue
            angle = np.arccos(np.clip(a @ b / (na * nb), -1.0, 1.0))
            n = nv[tri[c]]
            tan[tri[c]] += _reject(dp[0], n) * angle
            bit[tri[c]] += _reject(dp[1], n) * angle
    out = np.zeros((len(v), 4))
    for i in range(len(v)):
        n = nv[i]
        if not n.any():
            out[i] = (1, 0, 0, 1)
            continue
        t = _reject(tan[i], n)
        if not t.any():
            a = np.eye(3)[0] if abs(n[0]) < 0.9 else np.eye(3)[1]
            t = _reject(a, n)
        out[i, :3] = t
        out[i, 3] = -1.0 if np.cross(n, t) @ bit[i] < 0 else 1.0
    return out


def _height(levels, u, v, derivs, filt, wrap, aniso) -> np.ndarray:
    return rtex.sample(levels, u, v, derivs, filt, wrap, aniso).mean(axis=1)


def perturbed_normals(
    img: ref.RefImage,
    vertices,
    faces,
    uvs,
    normals,
    u,
    v,
    derivs,
    *,
    filter: str,
    wrap=("repeat", "repeat"),
    anisotropy: int = 1,
    normal_image=None,
    normal_scale: float = 1.0,
    bump_image=None,
    bump_scale: float = 1.0,
) -> np.ndarray:
    """The lit normal ``(P, 3)`` at each visible pixel of ``img`` (row-major over
    ``img.tri >= 0``; ``u, v, derivs`` from :func:`texture.uv_and_derivatives`), the maps
    sampled with ``filter``, ``wrap`` and ``anisotropy``. World space = object space
    (identity transform), front faces."""
    from . import shadows as rsh

    f = np.asarray(faces, np.int64).reshape(-1, 3)
    n = rsh.phong_normals(img, vertices, f, normals)
    tv = vertex_tangents(vertices, f, uvs, normals)
    tri = img.tri.reshape(-1)
    sel = tri >= 0
    b = img.bary.reshape(-1, 3)[sel]
    ti = np.einsum("pk,pkc->pc", b, tv[f[tri[sel]]])
    w = np.where(ti[:, 3] < 0, -1.0, 1.0)[:, None]
    t = _reject(ti[:, :3], n)
    frame = (t, w * np.cross(n, t), n)
    out = n
    if normal_image is not None:
        c = rtex.sample(rtex.mip_pyramid(normal_image), u, v, derivs, filter, wrap, anisotropy)
        ts = np.stack(
            [normal_scale * (2 * c[:, 0] - 1), normal_scale * (2 * c[:, 1] - 1), 2 * c[:, 2] - 1],
            axis=1,
        )
        out = _apply(frame, ts, out)
        t2 = _reject(frame[0], out)
        frame = (t2, w * np.cross(out, t2), out)
    if bump_image is not None:
        levels = rtex.mip_pyramid(bump_image)
        hgt, wid = np.asarray(bump_image).shape[:2]
        du, dv = 1.0 / wid, 1.0 / hgt
        args = (derivs, filter, wrap, anisotropy)
        hu = (_height(levels, u + du, v, *args) - _height(levels, u - du, v, *args)) / (2 * du)
        hv = (_height(levels, u, v + dv, *args) - _height(levels, u, v - dv, *args)) / (2 * dv)
        ts = np.stack([-bump_scale * hu, -bump_scale * hv, np.ones_like(hu)], axis=1)
        out = _apply(frame, ts, out)
    return out


def _apply(frame, ts: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    t, b, n = frame
    p = _unit(ts[:, :1] * t + ts[:, 1:2] * b + ts[:, 2:3] * n)
    return np.where(np.any(p != 0, axis=1, keepdims=True), p, fallback)
