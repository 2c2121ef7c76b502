"""Reflection, refraction and transparency for the float64 reference (NumPy only).

Independent of shadelab_rs: the formulas are written out here from their definitions.

- :func:`reflect`: the mirror direction ``r = 2(n.v)n - v``;
- :func:`refract`: Snell's law ``n1 sin t1 = n2 sin t2`` (NaN under total internal
  reflection, ``sin t2 > 1``); :func:`critical_angle`;
- :func:`schlick`: ``F = F0 + (1 - F0)(1 - c)^5``, ``F0 = ((n1 - n2)/(n1 + n2))^2``, with
  ``c`` the cosine on the less dense side, 0 when ``n1 == n2``, 1 under total internal
  reflection;
- :func:`environment`: the equirectangular lookup (``u = 0.5 + atan2(d.x, -d.z)/(2 pi)``,
  ``v = acos(d.y)/pi``, bilinear with texel centres at half-integers, wrapping in u and
  clamped in v);
- :func:`lateral_shift`: the sideways shift of a ray through a slab;
- :func:`trace`: a Whitted ray tracer over world-space triangle meshes (mirror and
  refraction rays, the mix ``c = (1 - R - T)*local + R'*reflected + T'*transmitted``);
- :func:`blend_sorted`: front-to-back compositing of transparent layers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import reference as ref
from .ray_triangle import intersect

#: The lectures' indices of refraction.
IOR = {"air": 1.0, "water": 1.33, "glass": 1.5, "diamond": 2.4}


def _unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def reflect(n, v) -> np.ndarray:
    """``2(n.v)n - v`` (``v`` points away from the surface)."""
    n = np.asarray(n, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    return 2.0 * np.sum(n * v, axis=-1, keepdims=True) * n - v


def refract(n, v, n1: float, n2: float) -> np.ndarray:
    """The refracted direction of light arriving against ``v`` (unit, on the side of the
    unit normal ``n``) from index ``n1`` into ``n2``: built from Snell's law by angles
    (the tangential part scaled by ``n1/n2``), NaN under total internal reflection."""
    n = np.asarray(n, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    cos1 = np.clip(np.sum(n * v, axis=-1, keepdims=True), 0.0, 1.0)
    tangent = v - cos1 * n  # |tangent| = sin t1, along the surface
    sin2 = (n1 / n2) * np.sqrt(np.maximum(1.0 - cos1**2, 0.0))
    with np.errstate(invalid="ignore"):
        cos2 = np.sqrt(1.0 - sin2**2)  # NaN beyond the critical angle
    # Refracted: opposite tangent direction, into the surface.
    tl = np.linalg.norm(tangent, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        tdir = np.where(tl > 0, tangent / np.where(tl > 0, tl, 1.0), 0.0)
    return -sin2 * tdir - cos2 * n


def critical_angle(n1: float, n2: float) -> float:
    """Degrees beyond which light from ``n1`` into ``n2`` (``n1 > n2``) is totally
    reflected: ``asin(n2/n1)``."""
    return math.degrees(math.asin(n2 / n1))


def schlick(cos1, n1: float, n2: float) -> np.ndarray:
    """Schlick's Fresnel reflectance at incidence cosine ``cos1`` from ``n1`` into ``n2``."""
    cos1 = np.asarray(cos1, dtype=np.float64)
    if n1 == n2:
        return np.zeros_like(cos1)
    f0 = ((n1 - n2) / (n1 + n2)) ** 2
    sin2 = (n1 / n2) * np.sqrt(np.maximum(1.0 - cos1**2, 0.0))
    tir = sin2 > 1.0
    cos2 = np.sqrt(np.maximum(1.0 - sin2**2, 0.0))
    c = cos1 if n1 <= n2 else cos2
    f = f0 + (1.0 - f0) * (1.0 - np.clip(c, 0.0, 1.0)) ** 5
    return np.where(tir, 1.0, f)


def environment(array, d, rotation: float = 0.0, intensity: float = 1.0) -> np.ndarray:
    """The equirectangular ``array`` (H, 2H, 3) seen along directions ``d`` (..., 3)."""
    img = np.asarray(array, dtype=np.float64)
    h, w = img.shape[:2]
    d = _unit(d)
    r = math.radians(rotation)
    c, s = math.cos(r), math.sin(r)
    x = c * d[..., 0] - s * d[..., 2]
    z = s * d[..., 0] + c * d[..., 2]
    u = 0.5 + np.arctan2(x, -z) / (2 * math.pi)
    v = np.arccos(np.clip(d[..., 1], -1.0, 1.0)) / math.pi
    fx = u * w - 0.5
    fy = np.clip(v * h - 0.5, 0.0, h - 1.0)
    x0 = np.floor(fx)
    y0 = np.floor(fy)
    ax = (fx - x0)[..., None]
    ay = (fy - y0)[..., None]
    c0 = np.mod(x0, w).astype(np.int64)
    c1 = np.mod(x0 + 1, w).astype(np.int64)
    r0 = y0.astype(np.int64)
    r1 = np.minimum(r0 + 1, h - 1)
    top = img[r0, c0] * (1 - ax) + img[r0, c1] * ax
    bottom = img[r1, c0] * (1 - ax) + img[r1, c1] * ax
    return (top * (1 - ay) + bottom * ay) * intensity


#: Per cube face (+X, -X, +Y, -Y, +Z, -Z): the axis of ``ma`` and, as (axis, sign), the
#: components ``sc`` and ``tc`` read (OpenGL 4.6 table 8.19).
CUBE_TABLE = [
    (0, (2, -1), (1, -1)),
    (0, (2, 1), (1, -1)),
    (1, (0, 1), (2, 1)),
    (1, (0, 1), (2, -1)),
    (2, (0, 1), (1, -1)),
    (2, (0, -1), (1, -1)),
]


def _cube_face(d: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Face index and (s, t) in [0, 1] of directions ``d`` (N, 3); ties go to x, then y."""
    a = np.abs(d)
    axis = np.where(
        (a[:, 0] >= a[:, 1]) & (a[:, 0] >= a[:, 2]), 0, np.where(a[:, 1] >= a[:, 2], 1, 2)
    )
    positive = d[np.arange(len(d)), axis] > 0
    face = 2 * axis + np.where(positive, 0, 1)
    s = np.empty(len(d))
    t = np.empty(len(d))
    for f, (ma, (sa, ss), (ta, ts)) in enumerate(CUBE_TABLE):
        m = face == f
        mag = np.abs(d[m, ma])
        s[m] = (ss * d[m, sa] / mag + 1) / 2
        t[m] = (ts * d[m, ta] / mag + 1) / 2
    return face, s, t


def _face_direction(face: np.ndarray, s: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Directions through (s, t) of each face: the inverse of :func:`_cube_face`."""
    d = np.zeros((len(face), 3))
    for f, (ma, (sa, ss), (ta, ts)) in enumerate(CUBE_TABLE):
        m = face == f
        d[m, ma] = 1.0 if f % 2 == 0 else -1.0
        d[m, sa] = ss * (2 * s[m] - 1)
        d[m, ta] = ts * (2 * t[m] - 1)
    return d


def cube_environment(faces, d, rotation: float = 0.0, intensity: float = 1.0) -> np.ndarray:
    """The cube ``faces`` (6, N, N, 3; +X, -X, +Y, -Y, +Z, -Z, OpenGL orientation) seen
    along directions ``d`` (..., 3): bilinear, seamless (a tap beyond a face's border reads
    the face its texel-centre direction falls on)."""
    img = np.asarray(faces, dtype=np.float64)
    n = img.shape[1]
    shape = np.shape(d)[:-1]
    d = _unit(np.asarray(d, dtype=np.float64).reshape(-1, 3))
    r = math.radians(rotation)
    c, sn = math.cos(r), math.sin(r)
    d = np.stack([c * d[:, 0] - sn * d[:, 2], d[:, 1], sn * d[:, 0] + c * d[:, 2]], axis=-1)
    face, s, t = _cube_face(d)
    fx = s * n - 0.5
    fy = t * n - 0.5
    x0 = np.floor(fx)
    y0 = np.floor(fy)

    def tap(i: np.ndarray, j: np.ndarray) -> np.ndarray:
        inside = (i >= 0) & (j >= 0) & (i < n) & (j < n)
        f2, s2, t2 = _cube_face(_face_direction(face, (i + 0.5) / n, (j + 0.5) / n))
        f2 = np.where(inside, face, f2)
        col = np.where(inside, i, np.clip(np.floor(s2 * n), 0, n - 1)).astype(np.int64)
        row = np.where(inside, j, np.clip(np.floor(t2 * n), 0, n - 1)).astype(np.int64)
        return img[f2, row, col]

    ax = (fx - x0)[:, None]
    ay = (fy - y0)[:, None]
    top = tap(x0, y0) * (1 - ax) + tap(x0 + 1, y0) * ax
    bottom = tap(x0, y0 + 1) * (1 - ax) + tap(x0 + 1, y0 + 1) * ax
    return ((top * (1 - ay) + bottom * ay) * intensity).reshape(*shape, 3)


def lateral_shift(thickness: float, theta_deg: float, n: float) -> float:
    """Sideways offset of a ray crossing a slab of index ``n`` in air at incidence
    ``theta``: ``d = t sin(theta - theta2) / cos(theta2)``."""
    t1 = math.radians(theta_deg)
    t2 = math.asin(math.sin(t1) / n)
    return thickness * math.sin(t1 - t2) / math.cos(t2)


def blend_sorted(colors, transmits, depths, behind) -> np.ndarray:
    """Front-to-back compositing of layers (any order given): nearest first,
    ``c = sum_i (prod_{j<i} T_j) a_i + (prod_i T_i) behind``."""
    order = np.argsort(np.asarray(depths, dtype=np.float64), kind="stable")
    acc = np.zeros(3)
    through = 1.0
    for i in order:
        acc = acc + through * np.asarray(colors[i], dtype=np.float64)
        through *= float(transmits[i])
    return acc + through * np.asarray(behind, dtype=np.float64)


@dataclass
class Surface:
    """One mesh of a traced scene, in world space."""

    vertices: np.ndarray
    faces: np.ndarray
    material: ref.Material
    normals: np.ndarray | None = None  # per vertex; None: face normals (flat)
    reflectivity: tuple = (0.0, 0.0, 0.0)
    transparency: float = 0.0
    ior: float = 1.0
    fresnel: bool = True


@dataclass
class TracedScene:
    surfaces: list
    lights: list
    ambient: tuple = (0.2, 0.2, 0.2)
    env: np.ndarray | None = None
    background: tuple = (0.0, 0.0, 0.0)
    max_depth: int = 5
    reflections: str = "ray"
    refractions: str | None = "ray"
    _tris: np.ndarray = field(default=None, repr=False)  # type: ignore[assignment]

    def __post_init__(self):
        tris, owner, idx = [], [], []
        for k, s in enumerate(self.surfaces):
            v = np.asarray(s.vertices, dtype=np.float64)
            f = np.asarray(s.faces, dtype=np.int64)
            tris.append(v[f])
            owner.append(np.full(len(f), k))
            idx.append(np.arange(len(f)))
        self._tris = np.concatenate(tris)
        self._owner = np.concatenate(owner)
        self._index = np.concatenate(idx)
        lo = self._tris.reshape(-1, 3).min(axis=0)
        hi = self._tris.reshape(-1, 3).max(axis=0)
        self.offset = 1e-4 * float(np.linalg.norm(hi - lo))

    def sky(self, d):
        if self.env is not None:
            return environment(self.env, d)
        return np.broadcast_to(np.asarray(self.background, dtype=np.float64), d.shape).copy()

    def closest(self, o, d):
        """(t, triangle, u, v) of each ray's nearest hit (t = inf: none)."""
        n = o.shape[0]
        best = np.full(n, np.inf)
        tri = np.full(n, -1)
        bu = np.zeros(n)
        bv = np.zeros(n)
        a = self._tris[:, 0][None]
        e1 = self._tris[:, 1][None] - a
        e2 = self._tris[:, 2][None] - a
        for s in range(0, n, 256):
            t, u, v, ok = intersect(o[s : s + 256, None], d[s : s + 256, None], a, e1, e2)
            t = np.where(ok, t, np.inf)
            k = np.argmin(t, axis=1)
            rows = np.arange(len(k))
            best[s : s + 256] = t[rows, k]
            tri[s : s + 256] = np.where(np.isfinite(t[rows, k]), k, -1)
            bu[s : s + 256] = u[rows, k]
            bv[s : s + 256] = v[rows, k]
        return best, tri, bu, bv

    def radiance(self, o, d, depth: int) -> np.ndarray:
        """Colour arriving at ``o`` against each unit ray ``d`` (Whitted)."""
        out = self.sky(d)
        t, tri, u, v = self.closest(o, d)
        hit = tri >= 0
        if not hit.any():
            return out
        for k, s in enumerate(self.surfaces):
            sel = hit & (self._owner[np.maximum(tri, 0)] == k)
            if not sel.any():
                continue
            fi = self._index[tri[sel]]
            f = np.asarray(s.faces)[fi]
            vv = np.asarray(s.vertices, dtype=np.float64)
            p = o[sel] + d[sel] * t[sel, None]
            face = _unit(np.cross(vv[f[:, 1]] - vv[f[:, 0]], vv[f[:, 2]] - vv[f[:, 0]]))
            view = -d[sel]
            entering = np.sum(face * d[sel], axis=-1) < 0
            g = np.where(entering[:, None], face, -face)
            if s.normals is None:
                n = g
            else:
                nn = np.asarray(s.normals, dtype=np.float64)
                w0 = (1 - u[sel] - v[sel])[:, None]
                ni = _unit(
                    nn[f[:, 0]] * w0 + nn[f[:, 1]] * u[sel, None] + nn[f[:, 2]] * v[sel, None]
                )
                ni = np.where(entering[:, None], ni, -ni)
                n = np.where((np.sum(ni * view, axis=-1) > 0)[:, None], ni, g)
            lit_n = np.where(entering[:, None], n, -n)
            local = ref.lighting(
                p, lit_n, p[0], s.material, self.lights, self.ambient, view_dir=view
            )
            out[sel] = self.mix(s, p, n, g, view, entering, local, depth)
        return out

    def mix(self, s: Surface, p, n, g, view, entering, local, depth):
        """``(1 - R - T)*local + R'*reflected + T'*transmitted`` at points ``p``."""
        r_w = np.broadcast_to(np.asarray(s.reflectivity, dtype=np.float64), p.shape)
        t_w = s.transparency
        c = local * (1.0 - r_w - t_w)
        refl = r_w.copy()
        trans = np.zeros(p.shape[0])
        tdir = np.full(p.shape, np.nan)
        if t_w > 0:
            n1 = np.where(entering, 1.0, s.ior)
            n2 = np.where(entering, s.ior, 1.0)
            for e in (True, False):
                m = entering == e
                if not m.any():
                    continue
                a, b = (1.0, s.ior) if e else (s.ior, 1.0)
                if self.refractions is None:
                    a = b = 1.0
                tdir[m] = refract(n[m], view[m], a, b)
                cos1 = np.clip(np.sum(n[m] * view[m], axis=-1), 0, 1)
                f = schlick(cos1, a, b) if s.fresnel else np.zeros(m.sum())
                tir = np.isnan(tdir[m][:, 0])
                f = np.where(tir, 1.0, f)
                refl[m] = refl[m] + (t_w * f)[:, None]
                trans[m] = t_w * (1 - f)
            del n1, n2
        if np.any(refl > 0):
            rd = reflect(n, view)
            c = c + refl * self.follow(self.reflections, p, g, rd, depth)
        go = trans > 0
        if go.any() and self.refractions is not None:
            c[go] = c[go] + trans[go, None] * self.follow(
                self.refractions, p[go], g[go], tdir[go], depth
            )
        return c

    def follow(self, tech: str, p, g, d, depth: int):
        d = _unit(d)
        if tech == "environment" or depth >= self.max_depth:
            return self.sky(d)
        side = np.where((np.sum(g * d, axis=-1) < 0)[:, None], -g, g)
        o = p + side * (self.offset + 1e-6 * np.abs(p).max(axis=-1, keepdims=True))
        return self.radiance(o, d, depth + 1)


def trace(
    scene: TracedScene,
    camera: ref.Camera,
    width: int,
    height: int,
    env_background: bool = False,
) -> np.ndarray:
    """The traced image (H, W, 3) float64 of a perspective ``camera``: primary rays through
    the pixel centres, then :meth:`TracedScene.radiance` (the first surface at depth 0).
    Pixels whose ray hits nothing show ``scene.background`` (the environment with
    ``env_background``)."""
    _origin, direction = ref.pixel_rays(camera, width, height)
    view = ref.look_at(camera.eye, camera.target, camera.up)
    rot = np.linalg.inv(view[:3, :3])
    eye = np.asarray(camera.eye, dtype=np.float64)
    d = _unit(direction.reshape(-1, 3) @ rot.T)
    o = np.broadcast_to(eye, d.shape).copy()
    c = scene.radiance(o, d, 0)
    if not env_background:
        c[scene.closest(o, d)[1] < 0] = np.asarray(scene.background, dtype=np.float64)
    return c.reshape(height, width, 3)
