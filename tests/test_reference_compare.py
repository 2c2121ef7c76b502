"""Pixel-by-pixel comparison of the Rust renderer with the float64 NumPy reference.

``shadelab_ref.reference`` renders the same model exactly (a float64 ray cast through every pixel
centre), so every difference is the Rust renderer's approximation error:

* **Vertex snapping.** Screen positions are snapped to 1/256 px (16.8 fixed point), so every
  vertex moves by at most 1/512 px per axis and every edge by at most ``sqrt(2)/512`` ≈ 0.003 px.
  A pixel centre closer than that to an edge may be covered by a different triangle (or by none),
  and flat shading is discontinuous across edges. We therefore compare colours only at pixels
  whose centre is more than ``EDGE_PX = 0.05`` px (about 18 times the snapping bound) from every
  edge of the reference's visible triangle (``RefImage.edge_dist``), and require every
  disagreement in coverage or depth to lie within ``EDGE_PX`` of *some* projected edge.
* **Single precision.** Shading runs in float32: a few 1e-6 relative, far below 1 LSB
  (1/255 ≈ 3.9e-3). Values that fall on a rounding boundary of ``round(c * 255)`` can still
  round the other way, hence "within 1 LSB" rather than "equal".
* **float32 colour.** Colours and normals are interpolated over the *unsnapped* screen
  triangle, whose vertices come from float32 clip coordinates (off by ~1e-7 relative, i.e.
  below ``ATTR_PX = 1/8192`` px at these sizes), so the Gouraud and Phong colour error
  inside a triangle is bounded by ``slope · ATTR_PX`` plus float32 noise, where
  ``slope = |dc/dx| + |dc/dy|`` per pixel. (Slivers whose area snapping changed by more than
  2x use the snapped triangle, away-from-edge pixels of which these meshes do not have.) Fog
  follows the eye depth, which comes from the snapped depth buffer, so with fog the bound is
  ``slope / 512``. We estimate the slope by finite differences of the
  reference image (a factor of 2 covers the estimate's error) and add ``F32_NOISE = 5e-5``:
  float32 rounding of ``n.h`` (~1e-7 relative) is amplified by the shininess exponent (up to
  89.6). Flat colours are constant per triangle, so there only the noise term applies.
* **Depth.** Inside a triangle, snapping shifts the interpolated depth by at most
  ``(|dd/dx| + |dd/dy|) / 512`` (the depth slope in world units per pixel, from the plane of the
  reference's triangle) and float32 adds a few 1e-7 relative; we allow that slope term plus
  ``DEPTH_RTOL = 1e-5`` relative.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import numpy as np
import pytest
import shadelab_rs as sl

from shadelab_ref import reference as ref
from shadelab_ref.to_sl import sl_light

#: Pixels whose centre is nearer than this (in pixels) to an edge are "near an edge".
EDGE_PX = 0.05
#: Required fraction of compared pixels within 1 LSB of the reference (the spec's 99.9 %).
MIN_FRACTION_1LSB = 0.999
#: float32 output: absolute noise term of the colour tolerance (see the module docstring).
F32_NOISE = 5e-5
#: float32 output: no compared pixel may be further than this from the reference (1 LSB).
F32_MAX_ERR = 1.0 / 255.0
#: Relative depth tolerance on top of the snapping slope term (see the module docstring).
DEPTH_RTOL = 1e-5
#: Largest vertex displacement by snapping, per screen axis, in pixels.
SNAP_PX = 1.0 / 512.0
#: Bound on the screen-position error of the attribute interpolation (unsnapped vertices).
ATTR_PX = 1.0 / 8192.0
#: Gouraud/Phong: required fraction of compared pixels exactly equal in uint8 (measured
#: 99.98 % at worst; 99.45 % when attributes were interpolated over the snapped triangle).
MIN_FRACTION_EXACT = 0.999

SHADINGS = ("flat", "gouraud", "phong")
SPECULARS = ("blinn", "phong", "blinn-normalized")


# --------------------------------------------------------------------------------------------
# Scenes, described once with the reference's dataclasses and translated to shadelab_rs
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)  # hashed by identity (for the render caches)
class Case:
    """One scene: a mesh seen by a camera under some lights."""

    label: str
    mesh: str
    camera: ref.Camera
    lights: tuple
    material: str
    transform: tuple | None = None
    ambient: tuple = (0.2, 0.2, 0.2)
    background: tuple = (0.0, 0.0, 0.0)
    width: int = 136
    height: int = 120
    emission: tuple = (0.0, 0.0, 0.0)
    fog: ref.Fog | None = None
    two_sided: bool = False
    local_viewer: bool = True
    back_material: str | None = None  # a preset for back faces (used when two_sided)


def _rotation(axis, degrees):
    a = np.asarray(axis, dtype=np.float64)
    x, y, z = a / np.linalg.norm(a)
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + s * k + (1 - c) * (k @ k)


def _affine(rotation, scale, translation):
    m = np.eye(4)
    m[:3, :3] = rotation @ np.diag(scale)
    m[:3, 3] = translation
    return tuple(map(tuple, m))


# Rotated about an oblique axis, scaled non-uniformly (normals need the inverse transpose).
XFORM = _affine(_rotation((1.0, 1.0, 0.3), 35.0), (1.3, 0.7, 1.0), (0.1, -0.1, 0.2))

PERSP = ref.Camera(
    eye=(0.6, 0.8, 3.2), target=(0.05, -0.05, 0.0), up=(0, 1, 0), fov_y=45.0, near=0.5, far=20.0
)
PERSP_TILTED = ref.Camera(
    eye=(-1.9, 1.1, 2.4), target=(0.1, 0.0, -0.1), up=(0.3, 1.0, 0.2), fov_y=50.0, near=1.0, far=8.0
)
ORTHO = ref.Camera(
    eye=(-2.0, 1.0, 2.5), target=(0.0, 0.0, 0.0), up=(0, 1, 0), ortho_height=2.6, near=0.5, far=10.0
)
# Off-centre principal point, skew and fx != fy, given for half the rendered size (K scales).
PINHOLE = dataclasses.replace(
    PERSP, intrinsics=(62.0, 50.0, 40.5, 27.0, 9.0, 68, 60), eye=(0.4, 0.9, 3.0)
)

SUN = ref.DirectionalLight(direction=(-1.0, -1.2, -0.8))
KEY = ref.DirectionalLight(direction=(0.5, -1.0, -0.6), color=(1.0, 0.95, 0.9), intensity=0.9)
FILL = ref.PointLight(position=(-3.0, 2.0, 4.0), color=(0.35, 0.4, 0.55), intensity=1.5)
BULB = ref.PointLight(position=(2.0, 3.0, 4.0), color=(1.0, 0.9, 0.8), intensity=1.2)

SPHERE_CASES = {
    c.label: c
    for c in (
        Case("persp-directional", "sphere", PERSP, (SUN,), "gold"),
        Case("ortho-point", "sphere", ORTHO, (BULB,), "chrome", background=(0.1, 0.2, 0.3)),
        Case(
            "persp-xform-2lights",
            "sphere",
            PERSP_TILTED,
            (KEY, FILL),
            "polished silver",
            transform=XFORM,
            ambient=(0.3, 0.25, 0.2),
        ),
        # Attenuated point light with its own ambient, a directional light's ambient and
        # material emission: every term of the equation that is not specular or diffuse.
        Case(
            "persp-attenuation-ambient-emission",
            "sphere",
            PERSP,
            (
                ref.DirectionalLight((-1.0, -1.2, -0.8), ambient=(0.1, 0.05, 0.0)),
                ref.PointLight(
                    (1.5, 1.0, 2.0),
                    color=(1.0, 0.9, 0.8),
                    intensity=4.0,
                    attenuation=(0.5, 0.3, 0.4),
                    ambient=(0.2, 0.3, 0.4),
                ),
            ),
            "copper",
            emission=(0.05, 0.0, 0.1),
        ),
        # Two spot lights whose cone edges cross the sphere: a hard one and a smooth one.
        Case(
            "persp-spots",
            "sphere",
            PERSP,
            (
                ref.SpotLight(
                    (0.3, 0.4, 3.0), (-0.1, -0.1, -1.0), cutoff=14.0, exponent=8.0, intensity=1.5
                ),
                ref.SpotLight(
                    (2.5, 1.0, 1.0),
                    (-1.0, -0.3, -0.3),
                    cutoff=20.0,
                    exponent=2.0,
                    color=(0.4, 0.6, 1.0),
                    attenuation=(0.2, 0.1, 0.05),
                    ambient=(0.1, 0.1, 0.1),
                    inner=12.0,
                ),
            ),
            "pewter",
        ),
        # Area lights: a one-sided attenuated rectangle close to the sphere (its points light
        # the surface from visibly different directions) and a two-sided disk.
        Case(
            "persp-area",
            "sphere",
            PERSP,
            (
                ref.AreaLight(
                    (0.8, 1.6, 1.2),
                    (1.5, 0.0, 0.0),
                    (0.0, 0.6, -0.9),
                    samples=5,
                    intensity=3.0,
                    attenuation=(0.5, 0.2, 0.1),
                    ambient=(0.1, 0.1, 0.1),
                    one_sided=True,
                ),
                ref.AreaLight(
                    (-2.0, -0.5, 1.5),
                    (0.0, 1.2, 0.0),
                    (0.6, 0.0, 0.8),
                    shape="disk",
                    samples=3,
                    color=(0.5, 0.6, 1.0),
                ),
            ),
            "jade",
        ),
        # Fog of each kind, by Euclidean eye distance, over an orthographic and a perspective
        # view (the sphere spans distances from about 2.3 to 4.4).
        Case(
            "persp-linear-fog",
            "sphere",
            PERSP,
            (SUN, BULB),
            "gold",
            fog=ref.Fog("linear", start=2.5, end=4.5, color=(0.6, 0.7, 0.8)),
        ),
        Case(
            "pinhole-linear-fog",
            "sphere",
            PINHOLE,
            (SUN, BULB),
            "gold",
            fog=ref.Fog("linear", start=2.2, end=4.2, color=(0.6, 0.7, 0.8)),
        ),
        Case(
            "ortho-exp-fog",
            "sphere",
            ORTHO,
            (SUN,),
            "chrome",
            fog=ref.Fog("exp", density=0.35, color=(0.2, 0.1, 0.0)),
        ),
        Case(
            "persp-exp2-fog",
            "sphere",
            PERSP_TILTED,
            (KEY, FILL),
            "bronze",
            fog=ref.Fog("exp2", density=0.3, color=(1.0, 1.0, 1.0)),
        ),
        # OpenGL's infinite viewer: one view vector for every point.
        Case(
            "persp-infinite-viewer",
            "sphere",
            PERSP_TILTED,
            (KEY, BULB),
            "chrome",
            local_viewer=False,
        ),
        # Intensities > 1 drive channels above 1: float32 keeps them, uint8 clamps.
        Case(
            "ortho-xform-2lights-bright",
            "sphere",
            ORTHO,
            (ref.DirectionalLight((0.2, -0.4, -1.0), (1.0, 1.0, 1.0), 1.8), BULB),
            "brass",
            transform=XFORM,
            background=(1.0, 1.0, 1.0),
        ),
    )
}


@functools.cache
def _mesh_arrays(name):
    """(vertices float64, faces int64, normals float64 or None) of a named test mesh."""
    if name == "sphere":
        v, f = ref.uv_sphere(24, 48)  # 2208 triangles
        return v, f, None
    if name == "spot":
        m = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
        v = m.vertices.astype(np.float64)
        f = m.faces.astype(np.int64)
        return v, f, ref.vertex_normals(v, f)
    if name == "open-sphere":
        # The sphere without its cap toward +z: from the front the outside (front faces) and
        # the inside (back faces) show side by side.
        v, f = ref.uv_sphere(24, 48)
        keep = v[f].mean(axis=1)[:, 2] < 0.55
        return v, f[keep], None
    if name == "floor":
        # A 100 x 100 floor at y = -1 as a 4 x 4 grid of quads, plus a sphere standing on it.
        g = np.linspace(-50.0, 50.0, 5)
        xx, zz = np.meshgrid(g, g)
        fv = np.stack([xx.ravel(), np.full(xx.size, -1.0), zz.ravel()], axis=1)
        ff = []
        for i in range(4):
            for j in range(4):
                a, b, c, d = 5 * i + j, 5 * i + j + 1, 5 * (i + 1) + j, 5 * (i + 1) + j + 1
                ff += [(a, c, d), (a, d, b)]  # counter-clockwise seen from +y
        sv, sf = ref.uv_sphere(12, 24, radius=0.6)
        sv = sv + np.array([0.0, -0.4, -3.0])
        v = np.concatenate([fv, sv])
        f = np.concatenate([np.asarray(ff), sf + len(fv)])
        n = ref.vertex_normals(v, f)
        n[: len(fv)] = (0.0, 1.0, 0.0)
        return v, f, n
    raise KeyError(name)


def _sl_camera(cam):
    if cam.intrinsics is not None:
        fx, fy, cx, cy, skew, w, h = cam.intrinsics
        return sl.Camera.from_intrinsics(
            cam.eye,
            cam.target,
            cam.up,
            fx=fx,
            fy=fy,
            cx=cx,
            cy=cy,
            skew=skew,
            width=w,
            height=h,
            near=cam.near,
            far=cam.far,
        )
    if cam.is_ortho:
        return sl.Camera.orthographic(
            cam.eye, cam.target, up=cam.up, height=cam.ortho_height, near=cam.near, far=cam.far
        )
    return sl.Camera.look_at(
        cam.eye, cam.target, up=cam.up, fov_y=cam.fov_y, near=cam.near, far=cam.far
    )


def _sl_fog(fog):
    if fog is None:
        return None
    return sl.Fog(fog.mode, fog.start, fog.end, fog.density, color=fog.color)


def _sl_material(case):
    m = sl.Material.preset(case.material)
    return sl.Material(m.ambient, m.diffuse, m.specular, m.shininess, emission=case.emission)


def _ref_material(case):
    m = _sl_material(case)
    return ref.Material(m.ambient, m.diffuse, m.specular, m.shininess, m.emission)


def _back_materials(case):
    """(shadelab_rs, reference) back materials of ``case``, or (None, None)."""
    if case.back_material is None:
        return None, None
    m = sl.Material.preset(case.back_material)
    return m, ref.Material(m.ambient, m.diffuse, m.specular, m.shininess, m.emission)


def _world_vertices(case):
    v, _, _ = _mesh_arrays(case.mesh)
    if case.transform is None:
        return v
    m = np.asarray(case.transform)
    return v @ m[:3, :3].T + m[:3, 3]


def render_sl(case, shading, specular, dtype):
    """The Rust renderer's (image, depth) for ``case``."""
    v, f, n = _mesh_arrays(case.mesh)
    scene = sl.Scene(
        ambient=case.ambient,
        fog=_sl_fog(case.fog),
        two_sided=case.two_sided,
        local_viewer=case.local_viewer,
    )
    mesh = sl.Mesh(v, f, normals=n)
    scene.add(
        mesh,
        material=_sl_material(case),
        transform=case.transform,
        back_material=_back_materials(case)[0],
    )
    for light in case.lights:
        scene.add_light(sl_light(light))
    return sl.render(
        scene,
        _sl_camera(case.camera),
        width=case.width,
        height=case.height,
        shading=shading,
        specular=specular,
        background=case.background,
        dtype=dtype,
        return_depth=True,
    )


@functools.cache
def render_ref(case, shading, specular):
    """The reference's RefImage for ``case`` (cached: shared by the uint8 and float32 checks)."""
    v, f, n = _mesh_arrays(case.mesh)
    return ref.render_reference(
        v,
        f,
        camera=case.camera,
        width=case.width,
        height=case.height,
        material=_ref_material(case),
        lights=list(case.lights),
        ambient=case.ambient,
        normals=n,
        transform=case.transform,
        shading=shading,
        specular=specular,
        background=case.background,
        fog=case.fog,
        two_sided=case.two_sided,
        local_viewer=case.local_viewer,
        back_material=_back_materials(case)[1],
    )


# --------------------------------------------------------------------------------------------
# Geometry of the comparison: distances to projected edges, depth slopes
# --------------------------------------------------------------------------------------------


def projected_edges(case):
    """Screen-space segments ``(E, 2, 2)`` of every triangle edge after near/far clipping
    (clip lines included), for the distance test of disagreeing pixels."""
    cam = case.camera
    _, f, _ = _mesh_arrays(case.mesh)
    ve = ref._world_to_eye(cam, _world_vertices(case))
    tris = ve[f]  # (F, 3, 3)
    d = -tris[..., 2]
    inside = np.all((d >= cam.near) & (d <= cam.far), axis=1)
    scr = ref.project_to_screen(tris[inside], cam, case.width, case.height)
    segs = [np.stack([scr, np.roll(scr, -1, axis=1)], axis=2).reshape(-1, 2, 2)]
    for t in tris[~inside]:
        pts = ref._clip_polygon([tuple(p) for p in t], cam.near, cam.far)
        if len(pts) >= 3:
            s = ref.project_to_screen(np.asarray(pts), cam, case.width, case.height)
            segs.append(np.stack([s, np.roll(s, -1, axis=0)], axis=1))
    return np.concatenate(segs)


def distance_to_edges(pixels, segments):
    """Distance in pixels from the centres of ``pixels`` ((P, 2) as (row, col)) to the
    nearest of ``segments`` ((E, 2, 2) screen points)."""
    c = np.stack([pixels[:, 1] + 0.5, pixels[:, 0] + 0.5], axis=1)[:, None, :]
    a, b = segments[None, :, 0], segments[None, :, 1]
    ab, ap = b - a, c - a
    ab2 = np.sum(ab * ab, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.clip(np.where(ab2 > 0, np.sum(ap * ab, axis=-1) / ab2, 0.0), 0.0, 1.0)
    diff = ap - s[..., None] * ab
    return np.sqrt(np.sum(diff * diff, axis=-1)).min(axis=1)


def depth_slope(case, r):
    """``|dd/dx| + |dd/dy|`` (world units per pixel) of the reference's visible plane."""
    cam, w, h = case.camera, case.width, case.height
    _, f, _ = _mesh_arrays(case.mesh)
    ve = ref._world_to_eye(cam, _world_vertices(case))
    p0, p1, p2 = ve[f[:, 0]], ve[f[:, 1]], ve[f[:, 2]]
    n = np.cross(p1 - p0, p2 - p0)
    out = np.zeros(r.tri.shape)
    m = r.mask
    t = r.tri[m]
    if cam.is_ortho:
        # n . (X, Y, -d) = n . p0 with X, Y linear in the pixel coordinates.
        sx, sy = cam.ortho_height * w / h / w, cam.ortho_height / h
        out[m] = (np.abs(n[t, 0] * sx) + np.abs(n[t, 1] * sy)) / np.abs(n[t, 2])
    elif cam.intrinsics is not None:
        # As below with X = x/d, Y = y/d: dX/du = 1/fx, dX/dv = -skew/(fx fy), dY/dv = -1/fy.
        fx, fy, _, _, skew = cam.k_for(w, h)
        k = np.sum(n * p0, axis=1)[t]
        d = r.depth[m]
        du = np.abs(n[t, 0] / fx)
        dv = np.abs(n[t, 0] * skew / (fx * fy) + n[t, 1] / fy)
        out[m] = d * d * (du + dv) / np.abs(k)
    else:
        # 1/d is affine in screen space: 1/d = (nx X + ny Y - nz) / (n . p0), X = x/d, Y = y/d.
        tn = math.tan(math.radians(cam.fov_y) / 2.0)
        sx, sy = 2.0 / w * tn * w / h, 2.0 / h * tn
        k = np.sum(n * p0, axis=1)[t]
        d = r.depth[m]
        out[m] = d * d * (np.abs(n[t, 0] * sx) + np.abs(n[t, 1] * sy)) / np.abs(k)
    return out


def color_slope(r):
    """Finite-difference estimate of ``|dc/dx| + |dc/dy|`` (max over RGB) of the reference
    colour: central differences where both neighbours are covered, else one-sided."""
    c, m = r.color, r.mask
    out = np.zeros(m.shape)
    for axis in (0, 1):
        nxt = np.zeros_like(m)
        prv = np.zeros_like(m)
        if axis == 0:
            nxt[:-1], prv[1:] = m[1:], m[:-1]
        else:
            nxt[:, :-1], prv[:, 1:] = m[:, 1:], m[:, :-1]
        cn, cp = np.roll(c, -1, axis), np.roll(c, 1, axis)
        central = np.abs(cn - cp).max(axis=-1) / 2
        forward = np.abs(cn - c).max(axis=-1)
        backward = np.abs(c - cp).max(axis=-1)
        out += np.where(nxt & prv, central, np.where(nxt, forward, np.where(prv, backward, 0)))
    return out


# --------------------------------------------------------------------------------------------
# The comparison
# --------------------------------------------------------------------------------------------


def compare(case, shading, specular):
    """Renders ``case`` with both renderers and asserts the documented agreement; returns
    the measured figures (also printed, shown by ``pytest -s`` or on failure)."""
    r = render_ref(case, shading, specular)
    img8, depth8 = render_sl(case, shading, specular, "uint8")
    img32, depth = render_sl(case, shading, specular, "float32")
    h, w = case.height, case.width
    assert img8.shape == img32.shape == (h, w, 3) and depth.shape == (h, w)
    assert img8.dtype == np.uint8 and img32.dtype == np.float32 and depth.dtype == np.float32
    # The colour format changes nothing but the final store.
    np.testing.assert_array_equal(depth8, depth)
    np.testing.assert_array_equal(img8, sl.to_uint8(img32))

    covered = np.isfinite(depth)
    assert np.all(depth[covered] > 0)
    assert np.all(np.isposinf(depth[~covered]))
    segments = projected_edges(case)

    # Coverage: every pixel covered by exactly one of the two lies on an edge.
    differ = np.argwhere(covered != r.mask)
    if len(differ):
        dist = distance_to_edges(differ, segments)
        assert dist.max() <= EDGE_PX, (
            f"coverage differs {EDGE_PX} px or more from any edge at (row, col) "
            f"{differ[dist > EDGE_PX][:5].tolist()}"
        )
    # Background: exact where neither covers.
    empty = ~covered & ~r.mask
    assert empty.sum() > 0 or r.mask.all()
    np.testing.assert_array_equal(
        img8[empty], np.broadcast_to(ref.to_uint8(case.background), (empty.sum(), 3))
    )
    np.testing.assert_array_equal(
        img32[empty], np.broadcast_to(np.float32(case.background), (empty.sum(), 3))
    )

    # Depth where both cover: the snapping slope term + DEPTH_RTOL, or near some edge.
    both = covered & r.mask
    tol = DEPTH_RTOL * r.depth + SNAP_PX * depth_slope(case, r)
    with np.errstate(invalid="ignore"):
        bad_depth = both & ~(np.abs(depth - r.depth) <= tol)
    if bad_depth.any():
        where = np.argwhere(bad_depth)
        dist = distance_to_edges(where, segments)
        assert dist.max() <= EDGE_PX, (
            f"depth differs away from edges at {where[dist > EDGE_PX][:5].tolist()}: "
            f"{depth[bad_depth][dist > EDGE_PX][:5]} vs {r.depth[bad_depth][dist > EDGE_PX][:5]}"
        )
    depth_rel = np.abs(depth[both] - r.depth[both]) / r.depth[both]

    # Colour at pixels covered by the reference and away from its triangle's edges.
    away = r.edge_dist > EDGE_PX
    n_cmp = int(away.sum())
    assert n_cmp > 0.2 * r.mask.sum(), "too few pixels away from edges to compare"
    ref8 = ref.to_uint8(r.color)
    lsb = np.abs(img8.astype(np.int16) - ref8.astype(np.int16)).max(axis=-1)[away]
    err32 = np.abs(img32.astype(np.float64) - r.color).max(axis=-1)[away]
    # Flat colours are constant per triangle, except under fog, which varies per pixel with
    # the (snapped) depth like any interpolated attribute.
    constant = shading == "flat" and case.fog is None
    shift_px = SNAP_PX if case.fog is not None else ATTR_PX
    tol32 = F32_NOISE + (0.0 if constant else 2 * shift_px * color_slope(r)[away])
    figures = {
        "compared": n_cmp,
        "within_1lsb": float(np.mean(lsb <= 1)),
        "exact_u8": float(np.mean(lsb == 0)),
        "max_lsb": int(lsb.max()),
        "f32_within_tol": float(np.mean(err32 <= tol32)),
        "f32_max_err": float(err32.max()),
        "f32_p999_err": float(np.quantile(err32, 0.999)),
        "coverage_diff": len(differ),
        "depth_rel_median": float(np.median(depth_rel)),
    }
    print(f"{case.label} {shading}/{specular}: {figures}")
    assert figures["within_1lsb"] >= MIN_FRACTION_1LSB, figures
    assert figures["f32_within_tol"] >= MIN_FRACTION_1LSB, figures
    assert figures["f32_max_err"] <= F32_MAX_ERR, figures
    if shading != "flat":
        assert figures["exact_u8"] >= MIN_FRACTION_EXACT, figures
    return figures


@pytest.mark.parametrize("specular", SPECULARS)
@pytest.mark.parametrize("shading", SHADINGS)
@pytest.mark.parametrize("case_name", list(SPHERE_CASES))
def test_sphere_matches_reference(case_name, shading, specular):
    compare(SPHERE_CASES[case_name], shading, specular)


SPOT = Case(
    "spot",
    "spot",
    ref.Camera(
        eye=(1.6, 0.9, 2.6), target=(0.0, 0.05, 0.0), up=(0, 1, 0), fov_y=40.0, near=0.5, far=10.0
    ),
    (KEY, FILL),
    "copper",
    width=144,
    height=144,
)


@pytest.mark.parametrize("shading", SHADINGS)
def test_spot_with_given_normals_matches_reference(shading):
    """A non-convex mesh with its own (explicitly passed) normals and self-occlusion."""
    compare(SPOT, shading, "blinn")


# The camera stands 1.5 above a 100 x 100 floor, looking down the -z axis and slightly down:
# the floor crosses the near plane (under the camera) and the far plane (towards the horizon).
FLOOR = Case(
    "floor",
    "floor",
    ref.Camera(
        eye=(0.3, 0.5, 2.0), target=(0.0, -0.6, -3.0), up=(0, 1, 0), fov_y=70.0, near=0.8, far=30.0
    ),
    (ref.PointLight((1.0, 2.0, -1.0), (1.0, 1.0, 1.0), 1.0), SUN),
    "pewter",
    background=(0.0, 0.0, 0.4),
)


@pytest.mark.parametrize("shading", SHADINGS)
def test_floor_crossing_near_and_far_planes_matches_reference(shading):
    figures = compare(FLOOR, shading, "phong")
    # Both planes really cut the floor: the bottom row is floor, the far end is background.
    r = render_ref(FLOOR, shading, "phong")
    assert r.mask[-1].all()
    assert not r.mask[FLOOR.height // 3].all()
    assert figures["compared"] > 0.5 * FLOOR.width * FLOOR.height


# Inside a sphere every visible face is a back face, lit with its outward normal as given (no
# two-sided lighting): the directional light reaches the far half of the view through the
# shell, the point light inside lights nothing but with ambient.
INSIDE = Case(
    "inside-sphere",
    "sphere",
    ref.Camera(
        eye=(0.1, 0.05, 0.2), target=(0.0, 0.0, -1.0), up=(0, 1, 0), fov_y=90.0, near=0.05, far=5.0
    ),
    (ref.DirectionalLight((-0.3, -0.2, 1.0)), ref.PointLight((0.0, 0.3, -0.2))),
    "bronze",
)


INSIDE_TWO_SIDED = dataclasses.replace(INSIDE, label="inside-sphere-two-sided", two_sided=True)


@pytest.mark.parametrize("shading", SHADINGS)
def test_inside_a_sphere_two_sided_lights_back_faces_with_flipped_normals(shading):
    """From inside a closed sphere every visible face is a back face: two-sided lighting
    lights them with the flipped (inward) normal, so the image differs from one-sided and
    matches the reference."""
    compare(INSIDE_TWO_SIDED, shading, "blinn")
    one, _ = render_sl(INSIDE, shading, "blinn", "float32")
    two, _ = render_sl(INSIDE_TWO_SIDED, shading, "blinn", "float32")
    assert two.mean() > one.mean() + 0.05


@pytest.mark.parametrize("shading", SHADINGS)
# The culled render draws nothing, and warns so.
@pytest.mark.filterwarnings("ignore::shadelab_rs.EmptyRenderWarning")
def test_inside_a_sphere_back_faces_match_reference(shading):
    compare(INSIDE, shading, "blinn")
    r = render_ref(INSIDE, shading, "blinn")
    assert r.mask.all()
    # Culling removes everything.
    v, f, _ = _mesh_arrays("sphere")
    scene = sl.Scene()
    scene.add(sl.Mesh(v, f))
    _, depth = sl.render(
        scene,
        _sl_camera(INSIDE.camera),
        width=32,
        height=32,
        return_depth=True,
        cull_backfaces=True,
    )
    assert np.isinf(depth).all()


def test_floor_is_clipped_not_dropped():
    v, f, n = _mesh_arrays("floor")
    scene = sl.Scene()
    scene.add(sl.Mesh(v, f, normals=n))
    scene.add_light(sl.DirectionalLight((0, -1, 0)))
    out = sl.render_frame(scene, _sl_camera(FLOOR.camera), width=64, height=48)
    assert out["stats"]["triangles_clipped"] > 0
    assert out["stats"]["triangles_dropped"] == 0


def test_generated_normals_match_reference_rule():
    """Without normals the renderer averages unit face normals like ``ref.vertex_normals``."""
    for name in ("sphere", "spot"):
        v, f, _ = _mesh_arrays(name)
        mesh = sl.Mesh(v, f)
        assert not mesh.has_normals
        np.testing.assert_allclose(mesh.normals, ref.vertex_normals(v, f), atol=2e-6)


# An open sphere seen into its opening: outside (front faces) and inside (back faces) at once,
# the inside with its own material under two-sided lighting.
OPEN = Case(
    "open-sphere-back-material",
    "open-sphere",
    ref.Camera(eye=(0.6, 0.9, 3.2), target=(0.0, 0.0, 0.0), up=(0, 1, 0), fov_y=45.0),
    (ref.DirectionalLight((-0.4, -0.6, -1.0)), ref.PointLight((0.2, 0.3, 0.4), intensity=0.6)),
    "gold",
    two_sided=True,
    back_material="ruby",
)


@pytest.mark.parametrize("shading", SHADINGS)
def test_back_material_lights_back_faces_under_two_sided_lighting(shading):
    """Back faces take the back material (and the flipped normal), front faces keep theirs;
    without two-sided lighting the back material is ignored, as in OpenGL."""
    compare(OPEN, shading, "blinn")
    plain = dataclasses.replace(OPEN, label="open-sphere-two-sided", back_material=None)
    compare(plain, shading, "blinn")
    a, _ = render_sl(OPEN, shading, "blinn", "float32")
    b, _ = render_sl(plain, shading, "blinn", "float32")
    r = render_ref(OPEN, shading, "blinn")
    _, f, _ = _mesh_arrays("open-sphere")
    w = _world_vertices(OPEN)[f]
    normal = np.cross(w[:, 1] - w[:, 0], w[:, 2] - w[:, 0])
    front = np.einsum("ij,ij->i", normal, np.asarray(OPEN.camera.eye) - w[:, 0]) > 0
    seen = r.tri[r.tri >= 0]
    assert front[seen].sum() > 500 and (~front[seen]).sum() > 500, "both sides in view"
    assert not np.array_equal(a, b)
    one_sided = dataclasses.replace(OPEN, two_sided=False)
    no_back = dataclasses.replace(OPEN, two_sided=False, back_material=None)
    np.testing.assert_array_equal(
        render_sl(one_sided, shading, "blinn", "float32")[0],
        render_sl(no_back, shading, "blinn", "float32")[0],
    )
