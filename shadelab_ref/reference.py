"""Independent float64 NumPy reference renderer for shadelab_rs.

This module is deliberately self-contained (NumPy only) and written for
clarity and exactness rather than speed.  The tests use it to check the Rust
rasterizer pixel by pixel.

Conventions (the project's contract):

* World space is right-handed with y up.  The camera looks down -z in eye
  space; the view matrix is OpenGL's ``gluLookAt(eye, target, up)``.
* Perspective projection: ``x_ndc = (1/tan(fov_y/2))/aspect * x_eye/d`` and
  ``y_ndc = 1/tan(fov_y/2) * y_eye/d`` with ``d = -z_eye`` (eye depth).
  Orthographic: ``x_ndc = x_eye/(h*aspect/2)``, ``y_ndc = y_eye/(h/2)``.
  Visible depth range ``near <= d <= far``.
* Screen: ``sx = (x_ndc+1)/2*W``, ``sy = (1-y_ndc)/2*H``; pixel ``(x, y)`` has
  its centre at ``(x+0.5, y+0.5)``; images are ``(H, W, 3)`` arrays.
* Counter-clockwise (seen from the front) is front.  Lighting is OpenGL 2.1
  style with a local viewer, evaluated in world space.

Coverage, depth and perspective-correct barycentrics are obtained by casting
a ray from the eye through each pixel centre and intersecting it with the
eye-space triangle (Moller-Trumbore in float64).  The ray barycentrics are the
perspective-correct ones, and triangles crossing the near plane need no
special treatment beyond accepting hits with ``near <= d <= far``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # annotations only (kept as strings at runtime, Python 3.9 safe)
    from collections.abc import Sequence

    Vec3 = Sequence[float] | np.ndarray

__all__ = [
    "Camera",
    "DirectionalLight",
    "Material",
    "PointLight",
    "RefImage",
    "face_normals",
    "lighting",
    "look_at",
    "pixel_rays",
    "project_to_screen",
    "render_reference",
    "to_uint8",
    "uv_sphere",
    "vertex_normals",
]

#: Threshold below which the sum of unit face normals at a vertex is treated
#: as zero by :func:`vertex_normals` (the sum of k unit vectors that cancel
#: exactly in real arithmetic has a float64 rounding residue of ~k*1e-16).
VERTEX_NORMAL_ZERO_EPS = 1e-12

# Maximum number of (triangle, pixel) candidate pairs processed at once.
_CHUNK_PAIRS = 400_000


# --------------------------------------------------------------------------
# Scene description
# --------------------------------------------------------------------------


@dataclass
class DirectionalLight:
    """Light travelling along ``direction``; the vector towards it is ``-direction``."""

    direction: Vec3
    color: Vec3 = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    ambient: Vec3 = (0.0, 0.0, 0.0)
    diffuse: Vec3 | None = None  # own diffuse colour in place of ``color``
    specular: Vec3 | None = None  # own specular colour in place of ``color``


@dataclass
class PointLight:
    """Point light at world ``position``; ``attenuation=(kc, kl, kq)`` divides the light
    (its ambient too) by ``kc + kl*d + kq*d**2``."""

    position: Vec3
    color: Vec3 = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    attenuation: Vec3 = (1.0, 0.0, 0.0)
    ambient: Vec3 = (0.0, 0.0, 0.0)
    diffuse: Vec3 | None = None
    specular: Vec3 | None = None


@dataclass
class SpotLight:
    """Spot light: a :class:`PointLight` restricted to a cone. Spot factor
    ``max(-l.d, 0)**exponent`` where ``-l.d >= cos(cutoff)`` (degrees), else 0; ``cutoff``
    180 means no cone. With ``inner`` (degrees) the factor is further multiplied by
    ``smoothstep(cos(cutoff), cos(inner), -l.d)``."""

    position: Vec3
    direction: Vec3
    cutoff: float = 30.0
    exponent: float = 0.0
    color: Vec3 = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    attenuation: Vec3 = (1.0, 0.0, 0.0)
    ambient: Vec3 = (0.0, 0.0, 0.0)
    inner: float | None = None
    diffuse: Vec3 | None = None
    specular: Vec3 | None = None


@dataclass
class AreaLight:
    """Rectangle or disk centred at ``position`` spanned by edges ``u`` and ``v``, standing
    for ``samples**2`` point lights (see :func:`area_points`) that share the colour and
    ambient equally; ``one_sided`` points are Lambertian emitters along ``u x v``."""

    position: Vec3
    u: Vec3
    v: Vec3
    shape: str = "rectangle"
    samples: int = 4
    color: Vec3 = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    attenuation: Vec3 = (1.0, 0.0, 0.0)
    ambient: Vec3 = (0.0, 0.0, 0.0)
    one_sided: bool = False
    diffuse: Vec3 | None = None
    specular: Vec3 | None = None


def area_points(light: AreaLight) -> np.ndarray:
    """``(samples**2, 3)`` sample positions: rectangle cell centres (row-major, ``u`` fastest)
    or a golden-angle spiral with equal-area radii ``sqrt((k + 1/2) / N)`` over the inscribed
    ellipse."""
    c, u, v = (np.asarray(x, dtype=np.float64) for x in (light.position, light.u, light.v))
    n = int(light.samples)
    if light.shape == "rectangle":
        t, s = np.meshgrid(
            (np.arange(n) + 0.5) / n - 0.5, (np.arange(n) + 0.5) / n - 0.5, indexing="ij"
        )
        s, t = s.ravel(), t.ravel()
    elif light.shape == "disk":
        k = np.arange(n * n, dtype=np.float64)
        r = np.sqrt((k + 0.5) / (n * n))
        a = k * np.pi * (3.0 - np.sqrt(5.0))
        s, t = 0.5 * r * np.cos(a), 0.5 * r * np.sin(a)
    else:
        raise ValueError(f"unknown area shape {light.shape!r}")
    return c + s[:, None] * u + t[:, None] * v


def expand_area_lights(lights) -> list:
    """``lights`` with every :class:`AreaLight` replaced by its point (or spot) lights."""
    out = []
    for light in lights:
        if not isinstance(light, AreaLight):
            out.append(light)
            continue
        pts = area_points(light)
        share = 1.0 / len(pts)
        normal = np.cross(light.u, light.v)
        normal = tuple(normal / np.linalg.norm(normal))
        amb = tuple(np.asarray(light.ambient, dtype=np.float64) * share)
        for p in pts:
            common = dict(
                color=light.color,
                intensity=light.intensity * share,
                diffuse=light.diffuse,
                specular=light.specular,
                attenuation=light.attenuation,
                ambient=amb,
            )
            if light.one_sided:
                out.append(SpotLight(tuple(p), normal, cutoff=90.0, exponent=1.0, **common))
            else:
                out.append(PointLight(tuple(p), **common))
    return out


@dataclass
class Fog:
    """Depth cueing by Euclidean eye distance d: f = (end - d)/(end - start) ("linear"),
    exp(-density*d) ("exp"), exp(-(density*d)**2) ("exp2"), clamped to [0, 1]; the pixel
    becomes f*c + (1 - f)*color."""

    mode: str = "linear"
    start: float = 0.0
    end: float = 1.0
    density: float = 1.0
    color: Vec3 = (0.5, 0.5, 0.5)

    def factor(self, d):
        d = np.asarray(d, dtype=np.float64)
        if self.mode == "linear":
            f = (self.end - d) / (self.end - self.start)
        elif self.mode == "exp":
            f = np.exp(-self.density * d)
        elif self.mode == "exp2":
            f = np.exp(-((self.density * d) ** 2))
        else:
            raise ValueError(f"unknown fog mode {self.mode!r}")
        return np.clip(f, 0.0, 1.0)


@dataclass
class Material:
    """Phong material: RGB ambient/diffuse/specular reflectances, shininess, emission."""

    ambient: Vec3
    diffuse: Vec3
    specular: Vec3
    shininess: float
    emission: Vec3 = (0.0, 0.0, 0.0)


@dataclass
class Camera:
    """Look-at camera; perspective unless ``ortho_height`` is given.

    ``fov_y`` is the full vertical field of view in degrees (perspective).
    ``ortho_height`` is the vertical extent of the orthographic view volume in
    world units.  ``near``/``far`` bound the visible eye depth ``d = -z_eye``.
    ``intrinsics`` ``(fx, fy, cx, cy, skew, width, height)``, when given, replaces
    ``fov_y``: a pinhole camera whose K (pixels of a ``width`` x ``height`` image,
    y down, pixel centres at +0.5) is scaled by the size ratio for other sizes.
    """

    eye: Vec3
    target: Vec3
    up: Vec3
    fov_y: float = 45.0
    near: float = 0.1
    far: float = 100.0
    ortho_height: float | None = None
    intrinsics: tuple | None = None

    def k_for(self, width: int, height: int) -> tuple[float, float, float, float, float]:
        """``(fx, fy, cx, cy, skew)`` of a pinhole camera for a ``width`` x ``height``
        image."""
        fx, fy, cx, cy, skew, w0, h0 = self.intrinsics
        sx, sy = width / w0, height / h0
        return fx * sx, fy * sy, cx * sx, cy * sy, skew * sx

    @property
    def is_ortho(self) -> bool:
        """True for an orthographic camera."""
        return self.ortho_height is not None


@dataclass
class RefImage:
    """Result of :func:`render_reference`.

    Attributes:
        color: ``(H, W, 3)`` float64 linear colour, unclamped.
        tri: ``(H, W)`` int64 index of the visible triangle, ``-1`` if empty.
        depth: ``(H, W)`` float64 eye depth ``d = -z_eye``, ``inf`` if empty.
        edge_dist: ``(H, W)`` float64 distance in pixels from the pixel centre
            to the nearest edge of the visible triangle's screen projection
            (after clipping to ``near <= d <= far``; clip lines count as edges),
            ``inf`` if empty.
        bary: ``(H, W, 3)`` perspective-correct barycentrics of the visible
            triangle's vertices ``(b0, b1, b2)``, NaN if empty.
        position: ``(H, W, 3)`` world-space surface point, NaN if empty.
    """

    color: np.ndarray
    tri: np.ndarray
    depth: np.ndarray
    edge_dist: np.ndarray
    bary: np.ndarray
    position: np.ndarray

    @property
    def mask(self) -> np.ndarray:
        """``(H, W)`` bool array, True where a triangle is visible."""
        return self.tri >= 0


# --------------------------------------------------------------------------
# Small helpers
# --------------------------------------------------------------------------


def _vec3(x, name: str = "value") -> np.ndarray:
    a = np.asarray(x, dtype=np.float64)
    if a.ndim == 0:
        a = np.full(3, float(a))
    if a.shape != (3,):
        raise ValueError(f"{name} must be a 3-vector, got shape {a.shape}")
    return a


def _normalize(v: np.ndarray) -> np.ndarray:
    """Normalise along the last axis; zero vectors stay zero."""
    v = np.asarray(v, dtype=np.float64)
    n = np.sqrt(np.sum(v * v, axis=-1, keepdims=True))
    with np.errstate(invalid="ignore", divide="ignore"):
        out = v / n
    return np.where(n > 0, out, 0.0)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.sum(a * b, axis=-1)


def to_uint8(img) -> np.ndarray:
    """Convert linear float colour to uint8: ``floor(clip(img, 0, 1) * 255 + 0.5)``."""
    a = np.clip(np.asarray(img, dtype=np.float64), 0.0, 1.0)
    return np.floor(a * 255.0 + 0.5).astype(np.uint8)


def look_at(eye: Vec3, target: Vec3, up: Vec3) -> np.ndarray:
    """Return the 4x4 OpenGL ``gluLookAt`` view matrix (world -> eye).

    ``f = normalize(target - eye)``, ``s = normalize(f x up)``, ``u = s x f``;
    rows of the rotation are ``s``, ``u``, ``-f``.
    """
    eye = _vec3(eye, "eye")
    f = _vec3(target, "target") - eye
    fn = np.linalg.norm(f)
    if fn == 0:
        raise ValueError("camera eye and target coincide")
    f = f / fn
    s = np.cross(f, _vec3(up, "up"))
    sn = np.linalg.norm(s)
    if sn == 0:
        raise ValueError("camera up vector is parallel to the view direction")
    s = s / sn
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3] = s
    m[1, :3] = u
    m[2, :3] = -f
    m[:3, 3] = -(m[:3, :3] @ eye)
    return m


def _world_to_eye(camera: Camera, p: np.ndarray) -> np.ndarray:
    """Eye-space coordinates, computed as in the spec: ``R @ (p - eye)``."""
    view = look_at(camera.eye, camera.target, camera.up)
    return (np.asarray(p, dtype=np.float64) - _vec3(camera.eye)) @ view[:3, :3].T


def project_to_screen(p_eye: np.ndarray, camera: Camera, width: int, height: int) -> np.ndarray:
    """Project eye-space points ``(..., 3)`` to screen pixels ``(..., 2)``.

    Uses the contract formulas; for perspective the points must have ``d > 0``.
    """
    p_eye = np.asarray(p_eye, dtype=np.float64)
    aspect = width / height
    x, y, d = p_eye[..., 0], p_eye[..., 1], -p_eye[..., 2]
    if camera.is_ortho:
        h = float(camera.ortho_height)
        xn = x / (h * aspect / 2.0)
        yn = y / (h / 2.0)
    elif camera.intrinsics is not None:
        fx, fy, cx, cy, skew = camera.k_for(width, height)
        # Computer-vision camera coordinates (x, -y, d): u, v directly in pixels.
        u = (fx * x - skew * y) / d + cx
        v = -fy * y / d + cy
        return np.stack([u, v], axis=-1)
    else:
        g = 1.0 / math.tan(math.radians(camera.fov_y) / 2.0)
        xn = g / aspect * x / d
        yn = g * y / d
    sx = (xn + 1.0) / 2.0 * width
    sy = (1.0 - yn) / 2.0 * height
    return np.stack([sx, sy], axis=-1)


def pixel_rays(camera: Camera, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """Eye-space rays through all pixel centres.

    Returns ``(origin, direction)``, each ``(H, W, 3)``.  Directions have
    ``z = -1`` so the ray parameter ``t`` equals the eye depth ``d``.
    Perspective rays start at the eye-space origin; orthographic rays start on
    the ``z = 0`` plane.
    """
    aspect = width / height
    xs = (np.arange(width, dtype=np.float64) + 0.5) / width * 2.0 - 1.0
    ys = 1.0 - (np.arange(height, dtype=np.float64) + 0.5) / height * 2.0
    xn, yn = np.meshgrid(xs, ys)  # (H, W)
    origin = np.zeros((height, width, 3))
    direction = np.zeros((height, width, 3))
    direction[..., 2] = -1.0
    if camera.is_ortho:
        h = float(camera.ortho_height)
        origin[..., 0] = xn * (h * aspect / 2.0)
        origin[..., 1] = yn * (h / 2.0)
    elif camera.intrinsics is not None:
        fx, fy, cx, cy, skew = camera.k_for(width, height)
        u, v = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
        yc = (v - cy) / fy  # y down
        direction[..., 0] = (u - cx - skew * yc) / fx
        direction[..., 1] = -yc
    else:
        t = math.tan(math.radians(camera.fov_y) / 2.0)
        direction[..., 0] = xn * t * aspect
        direction[..., 1] = yn * t
    return origin, direction


# --------------------------------------------------------------------------
# Normals
# --------------------------------------------------------------------------


def face_normals(vertices, faces) -> np.ndarray:
    """Unit face normals ``normalize((p1-p0) x (p2-p0))`` as ``(F, 3)``.

    Degenerate (zero-area) faces get the zero vector.
    """
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    p0, p1, p2 = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    return _normalize(np.cross(p1 - p0, p2 - p0))


def vertex_normals(vertices, faces) -> np.ndarray:
    """Per-vertex normals ``(N, 3)`` float64 from the mesh (object space).

    For each vertex: the sum of the unit face normals of the faces that use
    it, renormalised.  If that sum is zero (norm <= ``VERTEX_NORMAL_ZERO_EPS``)
    the unit normal of the first face (lowest face index) using the vertex is
    used instead; that is the zero vector when the face is degenerate, and
    unreferenced vertices get the zero vector.  Degenerate faces contribute a
    zero vector.  A face listing a vertex several times (necessarily
    degenerate) contributes zero.
    """
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    nv = v.shape[0]
    fn = face_normals(v, f)
    acc = np.zeros((nv, 3))
    for k in range(3):
        np.add.at(acc, f[:, k], fn)
    # First face using each vertex (faces in index order, corners in order).
    first = np.full(nv, -1, dtype=np.int64)
    if f.shape[0]:
        flat_v = f.reshape(-1)
        flat_f = np.repeat(np.arange(f.shape[0]), 3)
        uniq, idx = np.unique(flat_v, return_index=True)
        first[uniq] = flat_f[idx]
    fallback = np.zeros((nv, 3))
    used = first >= 0
    fallback[used] = fn[first[used]]
    norm = np.linalg.norm(acc, axis=1)
    out = fallback.copy()
    good = norm > VERTEX_NORMAL_ZERO_EPS
    out[good] = acc[good] / norm[good, None]
    return out


# --------------------------------------------------------------------------
# Lighting
# --------------------------------------------------------------------------


def lighting(
    p,
    n,
    eye,
    material: Material,
    lights,
    ambient=(0.2, 0.2, 0.2),
    specular: str = "blinn",
    view_dir=None,
) -> np.ndarray:
    """Evaluate the OpenGL 2.1 local-viewer lighting equation (world space).

    ``c = ke + ka*Ia + sum_lights att*[ka*Ia_i + kd*Id*max(n.l, 0) + ks*Is*S]`` with
    ``att = 1 / max(kc + kl*d + kq*d**2, 1e-6)`` for point lights (1 for directional) and
    ``Id = diffuse*intensity``, ``Is = specular*intensity`` (each ``color`` when not
    given), ``v = normalize(eye - p)`` and ``S = 0``
    unless ``n.l > 0``.  ``specular="blinn"``: ``S = max(n.h, 0)**shininess``,
    ``h = normalize(l + v)`` (``S = 0`` if ``l + v`` is zero);
    ``specular="phong"``: ``S = max(r.v, 0)**shininess``, ``r = 2(n.l)n - l``.
    NumPy power semantics (``0**0 = 1``).  Zero-length ``l`` or ``v`` vectors
    (point light / eye exactly at ``p``) are used as zero vectors.

    Args:
        p: surface points ``(..., 3)``.
        n: unit normals ``(..., 3)`` (broadcast against ``p``; not renormalised).
        eye: world eye position (3,).
        material: the :class:`Material`.
        lights: a sequence of :class:`DirectionalLight` / :class:`PointLight`
            (a single light is accepted too).
        ambient: scene ambient RGB ``Ia``.
        specular: ``"blinn"`` or ``"phong"``.

    Returns:
        ``(..., 3)`` float64 colours, unclamped.
    """
    if specular not in ("blinn", "phong", "blinn-normalized"):
        raise ValueError(f"unknown specular model {specular!r}")
    if isinstance(lights, (DirectionalLight, PointLight, SpotLight, AreaLight)):
        lights = [lights]
    lights = expand_area_lights(lights)
    p = np.asarray(p, dtype=np.float64)
    n = np.asarray(n, dtype=np.float64)
    p, n = np.broadcast_arrays(p, n)
    shape = p.shape
    ka = _vec3(material.ambient, "ambient")
    kd = _vec3(material.diffuse, "diffuse")
    ks = _vec3(material.specular, "specular")
    # A number, or one per point (a shininess map: broadcast against p[..., 0]).
    shin = np.asarray(material.shininess, dtype=np.float64)
    ia = _vec3(ambient, "ambient")
    ke = _vec3(getattr(material, "emission", (0.0, 0.0, 0.0)), "emission")
    color = np.broadcast_to(ke + ka * ia, shape).copy()
    if view_dir is None:
        v = _normalize(_vec3(eye, "eye") - p)
    else:  # infinite viewer: one direction toward the eye (or one per point) for every point
        v = np.broadcast_to(_normalize(np.asarray(view_dir, dtype=np.float64)), shape)
    for light in lights:
        att = np.ones(shape[:-1])
        if isinstance(light, DirectionalLight):
            lv = np.broadcast_to(_normalize(-_vec3(light.direction)), shape)
        elif isinstance(light, (PointLight, SpotLight)):
            to_light = _vec3(light.position) - p
            lv = _normalize(to_light)
            kc, kl, kq = (float(k) for k in light.attenuation)
            d = np.sqrt(_dot(to_light, to_light))
            att = 1.0 / np.maximum(kc + kl * d + kq * d * d, 1e-6)
            if isinstance(light, SpotLight) and light.cutoff != 180:
                cos_a = -_dot(lv, _normalize(_vec3(light.direction)))
                cos_c = np.cos(np.radians(light.cutoff))
                spot = np.where(
                    cos_a >= cos_c, np.power(np.maximum(cos_a, 0.0), light.exponent), 0.0
                )
                if light.inner is not None:
                    cos_i = np.cos(np.radians(light.inner))
                    t = np.clip((cos_a - cos_c) / (cos_i - cos_c), 0.0, 1.0)
                    spot = spot * t * t * (3 - 2 * t)
                att = att * spot
        else:
            raise TypeError(f"unsupported light {light!r}")
        color_d = light.color if light.diffuse is None else light.diffuse
        color_s = light.color if light.specular is None else light.specular
        i_d = _vec3(color_d, "diffuse") * float(light.intensity)
        i_s = _vec3(color_s, "specular") * float(light.intensity)
        ndotl = _dot(n, lv)
        diff = np.maximum(ndotl, 0.0)
        if specular in ("blinn", "blinn-normalized"):
            hsum = lv + v
            h = _normalize(hsum)
            s = np.power(np.maximum(_dot(n, h), 0.0), shin)
            s = np.where(np.any(hsum != 0, axis=-1), s, 0.0)
        else:
            r = 2.0 * ndotl[..., None] * n - lv
            s = np.power(np.maximum(_dot(r, v), 0.0), shin)
        if specular == "blinn-normalized":  # energy-normalised lobe: (f + 8) / 8 pi
            s = s * (shin + 8.0) / (8.0 * np.pi)
        s = np.where(ndotl > 0, s, 0.0)
        lit = ka * _vec3(light.ambient, "ambient") + kd * i_d * diff[..., None]
        color += att[..., None] * (lit + ks * i_s * s[..., None])
    return color


# --------------------------------------------------------------------------
# Geometry helpers
# --------------------------------------------------------------------------


def uv_sphere(n_lat: int, n_lon: int, radius: float = 1.0):
    """Closed UV sphere centred at the origin with CCW-outward faces.

    The poles are single vertices at ``(0, +-radius, 0)``; there are
    ``n_lat - 1`` rings of ``n_lon`` vertices at polar angles
    ``pi*i/n_lat`` and azimuths ``2*pi*j/n_lon`` (``x = r sin(th) cos(ph)``,
    ``y = r cos(th)``, ``z = -r sin(th) sin(ph)``).  Returns
    ``(vertices (2 + (n_lat-1)*n_lon, 3) float64, faces (2*n_lon*(n_lat-1), 3) int64)``.
    """
    if n_lat < 2 or n_lon < 3:
        raise ValueError("uv_sphere needs n_lat >= 2 and n_lon >= 3")
    th = np.pi * np.arange(1, n_lat) / n_lat
    ph = 2.0 * np.pi * np.arange(n_lon) / n_lon
    st, ct = np.sin(th)[:, None], np.cos(th)[:, None]
    ring = np.stack(
        [
            st * np.cos(ph)[None, :],
            np.broadcast_to(ct, (n_lat - 1, n_lon)),
            -st * np.sin(ph)[None, :],
        ],
        axis=-1,
    ).reshape(-1, 3)
    verts = np.concatenate([[[0.0, 1.0, 0.0]], ring, [[0.0, -1.0, 0.0]]]) * radius
    north, south = 0, 1 + (n_lat - 1) * n_lon

    def idx(i, j):
        return 1 + i * n_lon + (j % n_lon)

    faces = []
    for j in range(n_lon):
        faces.append((north, idx(0, j), idx(0, j + 1)))
    for i in range(n_lat - 2):
        for j in range(n_lon):
            a, b = idx(i, j), idx(i, j + 1)
            c, d = idx(i + 1, j), idx(i + 1, j + 1)
            faces.append((a, c, d))
            faces.append((a, d, b))
    for j in range(n_lon):
        faces.append((south, idx(n_lat - 2, j + 1), idx(n_lat - 2, j)))
    return verts, np.asarray(faces, dtype=np.int64)


def _clip_polygon(poly: list, near: float, far: float) -> list:
    """Sutherland-Hodgman clip of an eye-space polygon to ``near <= -z <= far``."""

    def clip(pts, inside, plane_d):
        out = []
        m = len(pts)
        for i in range(m):
            a, b = pts[i], pts[(i + 1) % m]
            ia, ib = inside(a), inside(b)
            if ia:
                out.append(a)
            if ia != ib:
                da, db = -a[2], -b[2]
                s = (plane_d - da) / (db - da)
                q = [a[k] + s * (b[k] - a[k]) for k in range(3)]
                q[2] = -plane_d
                out.append(tuple(q))
        return out

    pts = clip(poly, lambda q: -q[2] >= near, near)
    if pts:
        pts = clip(pts, lambda q: -q[2] <= far, far)
    return pts


def _transform(vertices, normals, transform):
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    if transform is None:
        m = np.eye(4)
    else:
        m = np.asarray(transform, dtype=np.float64)
        if m.shape != (4, 4):
            raise ValueError("transform must be a 4x4 matrix")
    hv = np.concatenate([v, np.ones((v.shape[0], 1))], axis=1) @ m.T
    w = hv[:, 3:4]
    vw = hv[:, :3] if np.all(w == 1.0) else hv[:, :3] / w
    normal_mat = np.linalg.inv(m[:3, :3]).T
    nw = _normalize(np.asarray(normals, dtype=np.float64).reshape(-1, 3) @ normal_mat.T)
    return vw, nw


# --------------------------------------------------------------------------
# Renderer
# --------------------------------------------------------------------------


def render_reference(
    vertices,
    faces,
    *,
    camera: Camera,
    width: int,
    height: int,
    material: Material,
    lights,
    ambient=(0.2, 0.2, 0.2),
    normals=None,
    transform=None,
    shading: str = "phong",
    specular: str = "blinn",
    background=(0.0, 0.0, 0.0),
    cull_backfaces: bool = False,
    fog: Fog | None = None,
    two_sided: bool = False,
    local_viewer: bool = True,
    back_material: Material | None = None,
) -> RefImage:
    """Render a triangle mesh exactly (float64 ray casting per pixel centre).

    Args:
        vertices: ``(N, 3)`` object-space positions.
        faces: ``(F, 3)`` vertex indices, CCW = front.
        camera: the :class:`Camera`.
        width, height: image size in pixels.
        material: the :class:`Material` (one for the whole mesh).
        lights: sequence of :class:`DirectionalLight` / :class:`PointLight`.
        ambient: scene ambient RGB.
        normals: optional ``(N, 3)`` object-space vertex normals; defaults to
            :func:`vertex_normals`.  They are transformed by the inverse
            transpose of the model matrix and renormalised.
        transform: optional 4x4 model matrix (column-vector convention).
        shading: ``"flat"``, ``"gouraud"`` or ``"phong"``.
        specular: ``"blinn"`` or ``"phong"``.
        background: RGB colour of empty pixels.
        cull_backfaces: skip triangles seen clockwise (normal facing away from
            the viewer).
        two_sided: light back faces (clockwise on screen) with the flipped normal
            and, when given, ``back_material`` (OpenGL's ``GL_BACK`` material; it is
            ignored without two-sided lighting, as in OpenGL).

    Returns:
        A :class:`RefImage`.  Visibility: the smallest eye depth ``d`` within
        ``[near, far]`` wins; exact ties go to the lowest triangle index.
        Pixel centres exactly on a triangle edge count as covered.
    """
    if shading not in ("flat", "gouraud", "phong"):
        raise ValueError(f"unknown shading mode {shading!r}")
    if specular not in ("blinn", "phong", "blinn-normalized"):
        raise ValueError(f"unknown specular model {specular!r}")
    width, height = int(width), int(height)
    if width <= 0 or height <= 0:
        raise ValueError("width and height must be positive")
    near, far = float(camera.near), float(camera.far)
    if not camera.is_ortho and near <= 0:
        raise ValueError("perspective near plane must be > 0")
    if isinstance(lights, (DirectionalLight, PointLight, SpotLight, AreaLight)):
        lights = [lights]
    lights = expand_area_lights(lights)

    v_obj = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if f.size and (f.min() < 0 or f.max() >= v_obj.shape[0]):
        raise ValueError("face index out of range")
    n_obj = vertex_normals(v_obj, f) if normals is None else normals
    n_obj = np.asarray(n_obj, dtype=np.float64).reshape(-1, 3)
    if n_obj.shape != v_obj.shape:
        raise ValueError("normals must have the same shape as vertices")
    vw, nw = _transform(v_obj, n_obj, transform)
    fnw = face_normals(vw, f)  # world unit face normals
    eye_w = _vec3(camera.eye, "eye")
    ve = _world_to_eye(camera, vw)  # eye-space vertices

    npix = width * height
    bg = _vec3(background, "background")
    depth = np.full(npix, np.inf)
    tri = np.full(npix, -1, dtype=np.int64)
    bu = np.zeros(npix)
    bv = np.zeros(npix)

    nf = f.shape[0]
    origin, direction = pixel_rays(camera, width, height)
    origin = origin.reshape(-1, 3)
    direction = direction.reshape(-1, 3)

    # ---- per-triangle setup: facing, clipping, screen polygon, bbox -------
    p0, p1, p2 = ve[f[:, 0]], ve[f[:, 1]], ve[f[:, 2]]
    n_eye = np.cross(p1 - p0, p2 - p0)
    # Orthographic: n . view axis; perspective: n . (eye_origin - p0).
    facing = n_eye[:, 2] if camera.is_ortho else -_dot(n_eye, p0)
    active = facing != 0  # edge-on / degenerate triangles cover nothing
    if cull_backfaces:
        active &= facing > 0
    d_all = -np.stack([p0[:, 2], p1[:, 2], p2[:, 2]], axis=1)
    active &= (d_all.max(axis=1) >= near) & (d_all.min(axis=1) <= far)
    need_clip = active & ((d_all.min(axis=1) < near) | (d_all.max(axis=1) > far))

    polys = np.zeros((nf, 6, 2))  # screen polygon, padded by repeating vertex 0
    with np.errstate(all="ignore"):
        tri_scr = project_to_screen(np.stack([p0, p1, p2], axis=1), camera, width, height)
        polys[:, :3] = tri_scr
        polys[:, 3:] = tri_scr[:, :1]
    for i in np.nonzero(need_clip)[0]:
        pts = _clip_polygon([tuple(p0[i]), tuple(p1[i]), tuple(p2[i])], near, far)
        if len(pts) < 3:
            active[i] = False
            continue
        scr = project_to_screen(np.asarray(pts), camera, width, height)
        polys[i, : len(pts)] = scr
        polys[i, len(pts) :] = scr[0]

    ids = np.nonzero(active)[0]
    x_lo = np.clip(np.ceil(polys[ids, :, 0].min(axis=1) - 0.5) - 1, 0, width)
    x_hi = np.clip(np.floor(polys[ids, :, 0].max(axis=1) - 0.5) + 1, -1, width - 1)
    y_lo = np.clip(np.ceil(polys[ids, :, 1].min(axis=1) - 0.5) - 1, 0, height)
    y_hi = np.clip(np.floor(polys[ids, :, 1].max(axis=1) - 0.5) + 1, -1, height - 1)
    x_lo, x_hi = x_lo.astype(np.int64), x_hi.astype(np.int64)
    y_lo, y_hi = y_lo.astype(np.int64), y_hi.astype(np.int64)
    nx = np.maximum(x_hi - x_lo + 1, 0)
    ny = np.maximum(y_hi - y_lo + 1, 0)
    counts = nx * ny
    keep = counts > 0
    ids, x_lo, y_lo, nx, counts = (
        ids[keep],
        x_lo[keep],
        y_lo[keep],
        nx[keep],
        counts[keep],
    )

    # ---- chunked ray/triangle intersection + depth test ------------------
    start = 0
    while start < len(ids):
        stop = start + 1
        total = int(counts[start])
        while stop < len(ids) and total + counts[stop] <= _CHUNK_PAIRS:
            total += int(counts[stop])
            stop += 1
        c_ids = ids[start:stop]
        c_cnt = counts[start:stop]
        rep = np.repeat(np.arange(stop - start), c_cnt)
        offs = np.concatenate([[0], np.cumsum(c_cnt)[:-1]])
        k = np.arange(total) - offs[rep]
        px = x_lo[start:stop][rep] + k % nx[start:stop][rep]
        py = y_lo[start:stop][rep] + k // nx[start:stop][rep]
        pix = py * width + px
        t_id = c_ids[rep]
        start = stop

        o = origin[pix]
        dvec = direction[pix]
        a = p0[t_id]
        e1 = p1[t_id] - a
        e2 = p2[t_id] - a
        pvec = np.cross(dvec, e2)
        det = _dot(e1, pvec)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            tvec = o - a
            u = _dot(tvec, pvec) * inv
            qvec = np.cross(tvec, e1)
            v = _dot(dvec, qvec) * inv
            t = _dot(e2, qvec) * inv
            hit = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= near) & (t <= far)
        if not np.any(hit):
            continue
        pix, t_id, u, v, t = pix[hit], t_id[hit], u[hit], v[hit], t[hit]
        order = np.lexsort((t_id, t, pix))
        pix, t_id, u, v, t = pix[order], t_id[order], u[order], v[order], t[order]
        first = np.ones(len(pix), dtype=bool)
        first[1:] = pix[1:] != pix[:-1]
        pix, t_id, u, v, t = pix[first], t_id[first], u[first], v[first], t[first]
        # Earlier chunks hold lower triangle indices, so ties keep the old one.
        win = t < depth[pix]
        pix = pix[win]
        depth[pix] = t[win]
        tri[pix] = t_id[win]
        bu[pix] = u[win]
        bv[pix] = v[win]

    # ---- shading ---------------------------------------------------------
    color = np.broadcast_to(bg, (npix, 3)).copy()
    bary = np.full((npix, 3), np.nan)
    position = np.full((npix, 3), np.nan)
    edge_dist = np.full(npix, np.inf)
    sel = np.nonzero(tri >= 0)[0]
    if sel.size:
        ts = tri[sel]
        b = np.stack([1.0 - bu[sel] - bv[sel], bu[sel], bv[sel]], axis=1)
        fv = f[ts]  # (P, 3)
        pos = np.einsum("pk,pkc->pc", b, vw[fv])
        bary[sel] = b
        position[sel] = pos
        # Two-sided lighting: back faces (clockwise on screen) use the flipped normal.
        flip = np.where(two_sided & (facing[ts] < 0), -1.0, 1.0)[:, None]
        view_dir = None
        if not local_viewer:
            view_dir = np.asarray(camera.eye, float) - np.asarray(camera.target, float)
        args = (eye_w, material, lights, ambient, specular, view_dir)
        back_mat = back_material if (two_sided and back_material is not None) else material
        args_back = (eye_w, back_mat, lights, ambient, specular, view_dir)
        if shading == "flat":
            uniq, inv_idx = np.unique(ts, return_inverse=True)
            cent = vw[f[uniq]].mean(axis=1)
            fcol = lighting(cent, fnw[uniq], *args)
            fcol_back = lighting(cent, -fnw[uniq], *args_back)
            inv_idx = inv_idx.reshape(-1)
            color[sel] = np.where(flip > 0, fcol[inv_idx], fcol_back[inv_idx])
        elif shading == "gouraud":
            vcol = lighting(vw, nw, *args)
            vcol_back = lighting(vw, -nw, *args_back)
            front = np.einsum("pk,pkc->pc", b, vcol[fv])
            back = np.einsum("pk,pkc->pc", b, vcol_back[fv])
            color[sel] = np.where(flip > 0, front, back)
        else:
            nrm = np.einsum("pk,pkc->pc", b, nw[fv])
            nn = np.linalg.norm(nrm, axis=1)
            with np.errstate(divide="ignore", invalid="ignore"):
                nrm = np.where(nn[:, None] > 0, nrm / nn[:, None], fnw[ts])
            front = lighting(pos, nrm, *args)
            back = lighting(pos, -nrm, *args_back)
            color[sel] = np.where(flip > 0, front, back)

        # Distance (pixels) from the pixel centre to the clipped screen polygon.
        cx = (sel % width).astype(np.float64) + 0.5
        cy = (sel // width).astype(np.float64) + 0.5
        c = np.stack([cx, cy], axis=1)[:, None, :]
        poly = polys[ts]
        sa, sb = poly[:, :5], poly[:, 1:]
        ab = sb - sa
        ap = c - sa
        ab2 = _dot(ab, ab)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.where(ab2 > 0, _dot(ap, ab) / ab2, 0.0)
        s = np.clip(s, 0.0, 1.0)
        diff = ap - s[..., None] * ab
        edge_dist[sel] = np.sqrt(_dot(diff, diff)).min(axis=1)

    if fog is not None:
        hit = np.isfinite(position[:, 0])
        dist = np.linalg.norm(position[hit] - np.asarray(camera.eye, dtype=np.float64), axis=1)
        f = fog.factor(dist)[:, None]
        color[hit] = f * color[hit] + (1.0 - f) * _vec3(fog.color, "fog color")

    return RefImage(
        color=color.reshape(height, width, 3),
        tri=tri.reshape(height, width),
        depth=depth.reshape(height, width),
        edge_dist=edge_dist.reshape(height, width),
        bary=bary.reshape(height, width, 3),
        position=position.reshape(height, width, 3),
    )
