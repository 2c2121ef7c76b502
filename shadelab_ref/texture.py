"""Float64 reference of texture mapping: OpenGL 4.6 §8.14-8.15 sampling written out in
NumPy, and textured renders built on :func:`shadelab_ref.reference.render_reference`.

Independent of the renderer's route to the same numbers:

* (u, v) at a pixel centre come from the reference's ray-cast barycentrics;
* their screen-space derivatives from central differences (h = 1e-3 px) of rays cast
  through the triangle's plane beside the pixel centre, not from interpolation planes;
* the lighting's ambient, diffuse and specular parts from the reference's own
  :func:`~shadelab_ref.reference.lighting` with unit materials (the equation is linear in
  ``ka``, ``kd`` and ``ks`` per channel), so a pixel is
  ``ke + ka*T*A + kd*T*D + ks*S`` with T the diffuse map's colour (which also weighs the
  ambient term when no ambient map is given).

Conventions: an image is an (H, W, 3) float64 array with row 0 the top of the picture;
UV (0, 0) is its bottom-left; texel (i, j) (row j from the top) has its centre at
u = (i + 0.5)/W, v = 1 - (j + 0.5)/H. Perspective cameras (``fov_y``) only.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from . import reference as ref
from . import shadows as rsh

__all__ = ["mip_pyramid", "render_textured_reference", "sample", "uv_and_derivatives"]


def mip_pyramid(image) -> list[np.ndarray]:
    """Level 0 (the image, flipped to OpenGL's bottom-up rows) and each smaller level: half
    the size rounded down (at least 1), texel = mean of the 2x2 texels above it (2x1 or
    1x2 where an axis is already 1); an odd last row or column is not read."""
    level = np.asarray(image, dtype=np.float64)[::-1, :, :3]
    levels = [level]
    while level.shape[0] > 1 or level.shape[1] > 1:
        h, w = level.shape[:2]
        nh, nw = max(h // 2, 1), max(w // 2, 1)
        sy, sx = (2 if h > 1 else 1), (2 if w > 1 else 1)
        cut = level[: nh * sy, : nw * sx]
        level = cut.reshape(nh, sy, nw, sx, 3).mean(axis=(1, 3))
        levels.append(level)
    return levels


def _wrap(i: np.ndarray, size: int, mode: str) -> np.ndarray:
    """OpenGL 4.6 Table 8.20 on integer coordinates."""
    if mode == "repeat":
        return np.mod(i, size)
    if mode == "clamp":
        return np.clip(i, 0, size - 1)
    if mode == "mirror":
        a = np.mod(i, 2 * size) - size
        m = np.where(a >= 0, a, -(1 + a))
        return (size - 1) - m
    raise ValueError(f"unknown wrap {mode!r}")


def _nearest(level, u, v, wrap):
    h, w = level.shape[:2]
    i = _wrap(np.floor(u * w), w, wrap[0]).astype(np.int64)
    j = _wrap(np.floor(v * h), h, wrap[1]).astype(np.int64)
    return level[j, i]


def _bilinear(level, u, v, wrap):
    h, w = level.shape[:2]
    x, y = u * w - 0.5, v * h - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    a, b = (x - x0)[..., None], (y - y0)[..., None]
    i0 = _wrap(x0, w, wrap[0]).astype(np.int64)
    i1 = _wrap(x0 + 1, w, wrap[0]).astype(np.int64)
    j0 = _wrap(y0, h, wrap[1]).astype(np.int64)
    j1 = _wrap(y0 + 1, h, wrap[1]).astype(np.int64)
    return (
        (1 - a) * (1 - b) * level[j0, i0]
        + a * (1 - b) * level[j0, i1]
        + (1 - a) * b * level[j1, i0]
        + a * b * level[j1, i1]
    )


def sample(levels, u, v, derivs, filter: str, wrap=("repeat", "repeat"), anisotropy: int = 1):
    """The filtered colour with up to ``anisotropy`` probes: with P_x, P_y the footprint's
    lengths along x and y in texels (as for lambda), N = min(ceil(P_max/P_min), anisotropy)
    probes (anisotropy when P_min = 0) at (u, v) + ((i + 1/2)/N - 1/2)(du, dv) along the
    major axis, each filtered with lambda = log2(P_max/N), averaged."""
    if anisotropy <= 1:
        return _sample(levels, u, v, derivs, filter, wrap)
    u, v = np.asarray(u, np.float64), np.asarray(v, np.float64)
    h, w = levels[0].shape[:2]
    dudx, dvdx, dudy, dvdy = (np.asarray(d, np.float64) for d in derivs)
    px, py = np.hypot(w * dudx, h * dvdx), np.hypot(w * dudy, h * dvdy)
    major_x = px >= py
    pmax, pmin = np.maximum(px, py), np.minimum(px, py)
    du, dv = np.where(major_x, dudx, dudy), np.where(major_x, dvdx, dvdy)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.ceil(pmax / pmin)
    n = np.where(np.isfinite(ratio), np.clip(ratio, 1, anisotropy), anisotropy).astype(np.int64)
    # One isotropic probe with footprint scaled so that its lambda is log2(P_max / N).
    out = np.zeros((*u.shape, 3))
    for k in range(1, anisotropy + 1):
        sel = n == k
        if not sel.any():
            continue
        s = 1.0 / k
        probe = (dudx[sel] * s, dvdx[sel] * s, dudy[sel] * s, dvdy[sel] * s)
        # lambda of the scaled footprint = log2(max(px, py) / k) = log2(P_max / N).
        acc = np.zeros((sel.sum(), 3))
        for i in range(k):
            t = (i + 0.5) / k - 0.5
            acc += _sample(levels, u[sel] + t * du[sel], v[sel] + t * dv[sel], probe, filter, wrap)
        out[sel] = acc / k
    return out


def _sample(levels, u, v, derivs, filter: str, wrap=("repeat", "repeat")) -> np.ndarray:
    """The filtered colour at arrays ``u``, ``v`` with ``derivs`` = (du/dx, dv/dx, du/dy,
    dv/dy): "nearest" and "bilinear" on level 0; "trilinear" bilinear on level 0 when
    lambda <= 0, else the blend of levels floor(lambda) and +1 (the last level beyond it),
    lambda = log2 max(|(W du/dx, H dv/dx)|, |(W du/dy, H dv/dy)|)."""
    if isinstance(wrap, str):
        wrap = (wrap, wrap)
    u, v = np.asarray(u, np.float64), np.asarray(v, np.float64)
    base = levels[0]
    if filter == "nearest":
        return _nearest(base, u, v, wrap)
    if filter == "bilinear":
        return _bilinear(base, u, v, wrap)
    if filter != "trilinear":
        raise ValueError(f"unknown filter {filter!r}")
    h, w = base.shape[:2]
    dudx, dvdx, dudy, dvdy = (np.asarray(d, np.float64) for d in derivs)
    rho = np.maximum(np.hypot(w * dudx, h * dvdx), np.hypot(w * dudy, h * dvdy))
    with np.errstate(divide="ignore"):
        lam = np.log2(rho)
    q = len(levels) - 1
    out = _bilinear(base, u, v, wrap)
    for d in range(q + 1):
        lo = _bilinear(levels[d], u, v, wrap)
        if d == q:
            sel = lam >= q
            out[sel] = lo[sel]
            break
        hi = _bilinear(levels[d + 1], u, v, wrap)
        sel = (lam > 0) & (lam >= d) & (lam < d + 1)
        f = (lam - d)[..., None]
        out[sel] = ((1 - f) * lo + f * hi)[sel]
    return out


def _ray(camera: ref.Camera, width: int, height: int, sx, sy) -> np.ndarray:
    """Eye-space ray directions (z = -1) through screen points (sx, sy)."""
    aspect = width / height
    t = math.tan(math.radians(camera.fov_y) / 2.0)
    xn = sx / width * 2.0 - 1.0
    yn = 1.0 - sy / height * 2.0
    return np.stack([xn * t * aspect, yn * t, -np.ones_like(xn)], axis=-1)


def uv_and_derivatives(r: ref.RefImage, vertices, faces, uvs, camera, transform=None):
    """Per covered pixel (``r.mask``): u, v and (du/dx, dv/dx, du/dy, dv/dy), each an array
    over the masked pixels in row-major order."""
    if camera.is_ortho or camera.intrinsics is not None:
        raise ValueError("the texture reference supports fov_y perspective cameras only")
    height, width = r.tri.shape
    f = np.asarray(faces, np.int64).reshape(-1, 3)
    uv = np.asarray(uvs, np.float64).reshape(-1, 2)
    vw, _ = ref._transform(
        np.asarray(vertices, np.float64).reshape(-1, 3), np.zeros((len(uv), 3)), transform
    )
    ve = ref._world_to_eye(camera, vw)
    ys, xs = np.nonzero(r.mask)
    t = r.tri[ys, xs]
    b = r.bary[ys, xs]
    fuv = uv[f[t]]  # (P, 3, 2)
    u = np.einsum("pk,pk->p", b, fuv[..., 0])
    v = np.einsum("pk,pk->p", b, fuv[..., 1])
    p0, p1, p2 = ve[f[t, 0]], ve[f[t, 1]], ve[f[t, 2]]
    e1, e2 = p1 - p0, p2 - p0

    def uv_at(sx, sy):
        d = _ray(camera, width, height, sx, sy)
        pvec = np.cross(d, e2)
        inv = 1.0 / ref._dot(e1, pvec)
        tvec = -p0
        b1 = ref._dot(tvec, pvec) * inv
        b2 = ref._dot(d, np.cross(tvec, e1)) * inv
        bb = np.stack([1 - b1 - b2, b1, b2], axis=1)
        return np.einsum("pk,pk->p", bb, fuv[..., 0]), np.einsum("pk,pk->p", bb, fuv[..., 1])

    h = 1e-3
    cx, cy = xs + 0.5, ys + 0.5
    ux1, vx1 = uv_at(cx + h, cy)
    ux0, vx0 = uv_at(cx - h, cy)
    uy1, vy1 = uv_at(cx, cy + h)
    uy0, vy0 = uv_at(cx, cy - h)
    derivs = (
        (ux1 - ux0) / (2 * h),
        (vx1 - vx0) / (2 * h),
        (uy1 - uy0) / (2 * h),
        (vy1 - vy0) / (2 * h),
    )
    return u, v, derivs


def render_textured_reference(
    vertices,
    faces,
    uvs,
    *,
    image,
    filter: str,
    wrap=("repeat", "repeat"),
    anisotropy: int = 1,
    material: ref.Material,
    shadows: bool = False,
    shininess_image=None,
    normal_image=None,
    normal_scale: float = 1.0,
    bump_image=None,
    bump_scale: float = 1.0,
    **kwargs,
):
    """A render with ``image`` as the diffuse map (weighing ambient too): the keyword
    arguments of :func:`~shadelab_ref.reference.render_reference` (perspective camera).
    ``shadows``: every light casts exact shadows (:func:`shadows.shaded_terms`: each light's
    diffuse and specular weighted by its visibility where the shading mode lights; the mesh
    is its own occluder, identity transform). ``shininess_image``: a shininess map, sampled
    with the same filter and wrap: the material's shininess times the mean of the sample's
    r, g, b, per pixel (Phong only). ``normal_image`` / ``bump_image`` with their scales:
    normal and bump maps (:func:`normalmap.perturbed_normals`, same filter and wrap; Phong
    only; the mesh's ``normals`` or its vertex normals carry the tangent frame).
    Returns ``(color, refimage)``: (H, W, 3) float64 linear colour (background where empty)
    and the reference's image of the unit ambient term (its mask, edge distances...)."""
    shin = material.shininess
    zero = (0.0, 0.0, 0.0)
    one = (1.0, 1.0, 1.0)
    unit = {
        "a": ref.Material(one, zero, zero, shin),
        "d": ref.Material(zero, one, zero, shin),
        "s": ref.Material(zero, zero, one, shin),
    }
    parts = {
        k: ref.render_reference(vertices, faces, material=m, **kwargs) for k, m in unit.items()
    }
    r = parts["a"]
    u, v, derivs = uv_and_derivatives(
        r, vertices, faces, uvs, kwargs["camera"], kwargs.get("transform")
    )
    tex = sample(mip_pyramid(image), u, v, derivs, filter, wrap, anisotropy)
    ys, xs = np.nonzero(r.mask)
    terms = {k: parts[k].color[ys, xs] for k in unit}
    if shininess_image is not None:
        if kwargs.get("shading", "phong") != "phong":
            raise ValueError("shininess maps need per-pixel lighting (shading='phong')")
        t = sample(mip_pyramid(shininess_image), u, v, derivs, filter, wrap, anisotropy)
        shin = shin * t.mean(axis=1)
    lit_normals = None
    if normal_image is not None or bump_image is not None:
        if kwargs.get("shading", "phong") != "phong":
            raise ValueError("normal and bump maps need per-pixel lighting (shading='phong')")
        from . import normalmap

        nv = kwargs.get("normals")
        if nv is None:
            nv = ref.vertex_normals(vertices, faces)
        lit_normals = normalmap.perturbed_normals(
            r,
            vertices,
            faces,
            uvs,
            nv,
            u,
            v,
            derivs,
            filter=filter,
            wrap=wrap,
            anisotropy=anisotropy,
            normal_image=normal_image,
            normal_scale=normal_scale,
            bump_image=bump_image,
            bump_scale=bump_scale,
        )
    if shadows or shininess_image is not None or lit_normals is not None:
        n_lights = len(ref.expand_area_lights(list(kwargs["lights"])))
        a, d, s = rsh.shaded_terms(
            r,
            vertices,
            faces,
            kwargs.get("normals"),
            shading=kwargs.get("shading", "phong"),
            camera=kwargs["camera"],
            lights=kwargs["lights"],
            ambient=kwargs.get("ambient", (0.2, 0.2, 0.2)),
            specular=kwargs.get("specular", "blinn"),
            shininess=shin,
            shadowed=[bool(shadows)] * n_lights,
            lit_normals=lit_normals,
        )
        terms = {"a": a, "d": d, "s": s}
    ka, kd, ks = (
        np.asarray(c, np.float64) for c in (material.ambient, material.diffuse, material.specular)
    )
    ke = np.asarray(material.emission, np.float64)
    color = parts["a"].color.copy()  # the background where nothing is drawn
    color[ys, xs] = ke + ka * tex * terms["a"] + kd * tex * terms["d"] + ks * terms["s"]
    return color, replace(r, color=color)
