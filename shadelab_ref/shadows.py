"""Exact ray-cast shadows for the float64 reference (NumPy only).

A shaded point ``p`` sees a point source when the open segment from ``p`` (moved off its
surface) to the light crosses no triangle of the scene; a directional light is a source at
infinity along ``-direction``. The start is moved along the visible triangle's geometric
normal, turned to the side of the shading normal, by ``offset = 1e-4 * (bounding-box
diagonal of the scene) + 1e-6 * max|p|`` -- the same rule as shadelab_rs's exact shadows
(``crates/raster/src/shadows``), so both answer the same geometric question. A point facing
away from the light (``n.l <= 0``) gets no direct light whatever its visibility (reported as
visible). An area light is its sample points (:func:`reference.area_points`), each with its
own visibility.

:func:`shaded_phong` recombines the reference's Phong colours with these visibilities:
``c = lighting(no lights) + sum_i vis_i * (lighting(light i) - lighting(no lights))``.
"""

from __future__ import annotations

import numpy as np

from . import reference as ref
from .ray_triangle import intersect

#: Triangles tested per vectorised step.
_TRI_CHUNK = 64


def scene_offset(vertices) -> float:
    """The scene-size part of the shadow-ray offset: ``1e-4`` of the bounding-box diagonal."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    return 1e-4 * float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))


def occluded(origin, direction, t_max, vertices, faces) -> np.ndarray:
    """Whether a triangle crosses each open segment ``origin + t*direction``,
    ``0 < t < t_max`` (Moller-Trumbore in float64; edges count as hits)."""
    o = np.asarray(origin, dtype=np.float64).reshape(-1, 3)
    d = np.asarray(direction, dtype=np.float64).reshape(-1, 3)
    t_max = np.broadcast_to(np.asarray(t_max, dtype=np.float64), (o.shape[0],))
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    hit = np.zeros(o.shape[0], dtype=bool)
    for s in range(0, f.shape[0], _TRI_CHUNK):
        tri = f[s : s + _TRI_CHUNK]
        a = v[tri[:, 0]][None]
        e1 = v[tri[:, 1]][None] - a
        e2 = v[tri[:, 2]][None] - a
        todo = ~hit
        if not todo.any():
            break
        t, _, _, ok = intersect(o[todo][:, None], d[todo][:, None], a, e1, e2)
        ok &= t < t_max[todo][:, None]
        hit[np.nonzero(todo)[0]] = ok.any(axis=1)
    return hit


def source_geometry(light):
    """``(toward, is_directional)``: the unit vector toward a directional light, or the
    position of a point or spot light."""
    if isinstance(light, ref.DirectionalLight):
        d = np.asarray(light.direction, dtype=np.float64)
        return -d / np.linalg.norm(d), True
    return np.asarray(light.position, dtype=np.float64), False


def visibility(position, geo_normal, shading_normal, light, vertices, faces, offset):
    """1.0 where the point source ``light`` is visible from each point, else 0.0 (see the
    module docstring for the offset and the points facing away)."""
    p = np.asarray(position, dtype=np.float64).reshape(-1, 3)
    n = np.asarray(shading_normal, dtype=np.float64).reshape(-1, 3)
    g = np.asarray(geo_normal, dtype=np.float64).reshape(-1, 3)
    g = np.where(np.sum(g * n, axis=1, keepdims=True) < 0, -g, g)
    origin = p + g * (offset + 1e-6 * np.abs(p).max(axis=1, keepdims=True))
    toward, directional = source_geometry(light)
    if directional:
        d = np.broadcast_to(toward, p.shape)
        t_max = np.inf
    else:
        d = toward[None] - origin
        t_max = 1.0
    facing = np.sum(n * d, axis=1) > 0
    vis = np.ones(p.shape[0])
    if facing.any():
        sel = np.nonzero(facing)[0]
        vis[sel] = np.where(occluded(origin[sel], d[sel], t_max, vertices, faces), 0.0, 1.0)
    return vis


def phong_normals(img: ref.RefImage, vertices, faces, normals=None) -> np.ndarray:
    """The reference's Phong normal at every visible pixel (``(P, 3)`` for the pixels
    where ``img.tri >= 0``, in row-major order)."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    nv = ref.vertex_normals(v, f) if normals is None else np.asarray(normals, np.float64)
    tri = img.tri.reshape(-1)
    sel = tri >= 0
    b = img.bary.reshape(-1, 3)[sel]
    nrm = np.einsum("pk,pkc->pc", b, nv[f[tri[sel]]])
    nn = np.linalg.norm(nrm, axis=1, keepdims=True)
    fn = ref.face_normals(v, f)[tri[sel]]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(nn > 0, nrm / nn, fn)


def shaded_phong(
    img: ref.RefImage,
    vertices,
    faces,
    *,
    camera: ref.Camera,
    material: ref.Material,
    lights,
    ambient=(0.2, 0.2, 0.2),
    specular: str = "blinn",
    background=(0.0, 0.0, 0.0),
    shadowed=None,
):
    """The Phong image of ``img`` (rendered by :func:`reference.render_reference` from the
    same world-space ``vertices`` and ``faces``, identity transform) with exact shadows.

    ``shadowed``: for each light (after area lights are expanded), whether it casts shadows
    (default: all). Returns ``(color (H, W, 3), visibility (L, P))`` with one row of
    visibilities per expanded light over the visible pixels in row-major order.
    Lights' own ambient terms must be zero (they would not be shadowed).
    """
    lights = ref.expand_area_lights(lights if isinstance(lights, (list, tuple)) else [lights])
    if shadowed is None:
        shadowed = [True] * len(lights)
    for light in lights:
        if np.any(np.asarray(getattr(light, "ambient", (0, 0, 0)), dtype=np.float64) != 0):
            raise ValueError("shaded_phong needs lights without their own ambient term")
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    h, w = img.tri.shape
    tri = img.tri.reshape(-1)
    sel = np.nonzero(tri >= 0)[0]
    pos = img.position.reshape(-1, 3)[sel]
    n = phong_normals(img, v, f)
    g = ref.face_normals(v, f)[tri[sel]]
    eye = np.asarray(camera.eye, dtype=np.float64)
    base = ref.lighting(pos, n, eye, material, [], ambient, specular)
    color = np.broadcast_to(np.asarray(background, np.float64), (h * w, 3)).copy()
    total = base.copy()
    offset = scene_offset(v)
    vis_rows = []
    for light, casts in zip(lights, shadowed):
        contrib = ref.lighting(pos, n, eye, material, [light], ambient, specular) - base
        vis = visibility(pos, g, n, light, v, f, offset) if casts else np.ones(len(sel))
        vis_rows.append(vis)
        total += vis[:, None] * contrib
    color[sel] = total
    return color.reshape(h, w, 3), np.array(vis_rows).reshape(len(lights), len(sel))


def shaded_terms(
    img: ref.RefImage,
    vertices,
    faces,
    normals=None,
    *,
    shading: str,
    camera: ref.Camera,
    lights,
    ambient=(0.2, 0.2, 0.2),
    specular: str = "blinn",
    shininess: float,
    shadowed=None,
    lit_normals=None,
):
    """The unit material's ambient, diffuse and specular terms ``(A, D, S)`` at every visible
    pixel of ``img`` (each ``(P, 3)``, row-major over ``img.tri >= 0``), lit where
    ``shading`` lights -- per pixel (``"phong"``), at each face's centroid with its face
    normal (``"flat"``) or at each vertex with its normal, then interpolated (``"gouraud"``)
    -- with each light's diffuse and specular weighted by its exact visibility from that
    point (:func:`visibility`; flat and Gouraud offset along the shading normal, Phong along
    the face normal). ``img`` is :func:`reference.render_reference`'s image of the same
    world-space ``vertices`` and ``faces`` (identity transform, front faces).

    ``shadowed``: for each light (after area lights are expanded), whether it casts shadows
    (default: all). Lights' own ambient terms must be zero (they are not shadowed).
    ``shininess``: a number, or (Phong) one per visible pixel (a shininess map).
    ``lit_normals``: (Phong) the normal each visible pixel is lit with (a normal or bump
    map's); visibility keeps the interpolated one.
    """
    lights = ref.expand_area_lights(lights if isinstance(lights, (list, tuple)) else [lights])
    if shadowed is None:
        shadowed = [True] * len(lights)
    for light in lights:
        if np.any(np.asarray(getattr(light, "ambient", (0, 0, 0)), dtype=np.float64) != 0):
            raise ValueError("shaded_terms needs lights without their own ambient term")
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    tri = img.tri.reshape(-1)
    sel = np.nonzero(tri >= 0)[0]
    ts = tri[sel]
    fn = ref.face_normals(v, f)
    if shading == "phong":
        pts, n, g = img.position.reshape(-1, 3)[sel], phong_normals(img, v, f, normals), fn[ts]
    elif shading == "flat":
        pts, n = v[f].mean(axis=1), fn
        g = n
    elif shading == "gouraud":
        nv = ref.vertex_normals(v, f) if normals is None else np.asarray(normals, np.float64)
        pts, n = v, nv / np.linalg.norm(nv, axis=1, keepdims=True)
        g = n
    else:
        raise ValueError(f"unknown shading mode {shading!r}")
    eye = np.asarray(camera.eye, dtype=np.float64)
    offset = scene_offset(v)
    vis = [
        visibility(pts, g, n, light, v, f, offset) if casts else np.ones(len(pts))
        for light, casts in zip(lights, shadowed)
    ]
    if lit_normals is not None:
        if shading != "phong":
            raise ValueError("lit_normals need per-pixel lighting (shading='phong')")
        n = np.asarray(lit_normals, np.float64)
    zero, one = (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)
    out = []
    for unit in (
        ref.Material(one, zero, zero, shininess),
        ref.Material(zero, one, zero, shininess),
        ref.Material(zero, zero, one, shininess),
    ):
        base = ref.lighting(pts, n, eye, unit, [], ambient, specular)
        total = base.copy()
        for light, vl in zip(lights, vis):
            lit = ref.lighting(pts, n, eye, unit, [light], ambient, specular)
            total += vl[:, None] * (lit - base)
        if shading == "flat":
            total = total[ts]
        elif shading == "gouraud":
            b = img.bary.reshape(-1, 3)[sel]
            total = np.einsum("pk,pkc->pc", b, total[f[ts]])
        out.append(total)
    return tuple(out)
