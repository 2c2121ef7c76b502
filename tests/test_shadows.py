"""Shadows against the float64 reference's exact ray-cast visibility (shadelab_ref.shadows).

Figures per scene (:func:`shadow_figures`), over the *compared* pixels: visible in the
reference away from triangle edges (``EDGE_PX``) and lit by the light by more than
``MIN_CONTRIB`` when visible (elsewhere a shadow changes nothing):

* ``mismatch``: share whose shadow state (any visible drop in the light's contribution)
  differs from the exact one;
* ``max_dist``: the largest distance in pixels from a mismatch to the exact shadow boundary
  (pixels whose exact state differs from a 4-neighbour's, whose neighbour is not compared --
  silhouettes and terminators -- or belongs to another object: contacts, where a shadow
  map's texel spans both);
* ``acne`` / ``leak``: mismatches farther than ``AWAY_PX`` from that boundary, shadowed where
  the exact answer is lit / lit where it is shadowed.

``shadows="exact"`` must match the reference's colours (within 1 LSB) on >= 99.9 % of the
compared pixels; shadow maps at default settings must show no acne and no leak.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import pickle

import numpy as np
import pytest
import shadelab_rs as sl

from shadelab_ref import reference as ref
from shadelab_ref import shadows as rsh
from shadelab_ref.to_sl import sl_light

EDGE_PX = 0.05
MIN_CONTRIB = 5e-2
AWAY_PX = 3.0
MIN_EXACT_MATCH = 0.999
MAT = ref.Material(
    ambient=(0.2, 0.2, 0.2), diffuse=(0.7, 0.6, 0.5), specular=(0.3, 0.3, 0.3), shininess=20.0
)
AMBIENT = (0.15, 0.15, 0.15)
W, H = 192, 144


# --------------------------------------------------------------------------------------------
# Geometry (world space, CCW-outward faces)
# --------------------------------------------------------------------------------------------


def plane(half: float, y: float = 0.0):
    v = np.array([[-half, y, -half], [-half, y, half], [half, y, half], [half, y, -half]])
    return v, np.array([[0, 1, 2], [0, 2, 3]])


def box(center, half, inward: bool = False):
    """An axis-aligned box (12 triangles, 24 vertices: flat faces) of half-sizes ``half``."""
    c, h = np.asarray(center, float), np.broadcast_to(np.asarray(half, float), (3,))
    verts, faces = [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, w = (axis + 1) % 3, (axis + 2) % 3
            quad = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = np.zeros(3)
                p[axis], p[u], p[w] = sign * h[axis], a * h[u], b * h[w]
                quad.append(c + p)
            k = len(verts)
            verts += quad
            # (u, w) order is CCW seen from +axis; flip for the negative side (and inward).
            if (sign > 0) != inward:
                faces += [[k, k + 1, k + 2], [k, k + 2, k + 3]]
            else:
                faces += [[k, k + 2, k + 1], [k, k + 3, k + 2]]
    return np.array(verts), np.array(faces)


def sphere(center, radius, n_lat=24, n_lon=48):
    v, f = ref.uv_sphere(n_lat, n_lon, radius)
    return np.asarray(v) + np.asarray(center, float), np.asarray(f)


def combine(parts):
    verts, faces, off = [], [], 0
    for v, f in parts:
        verts.append(v)
        faces.append(f + off)
        off += len(v)
    return np.concatenate(verts), np.concatenate(faces)


@dataclasses.dataclass
class Case:
    label: str
    parts: list
    camera: ref.Camera
    lights: list
    cull: bool = False
    size: tuple[int, int] = (W, H)


def sl_camera(c: ref.Camera) -> sl.Camera:
    return sl.Camera.look_at(c.eye, c.target, c.up, fov_y=c.fov_y, near=c.near, far=c.far)


def sl_scene(case: Case, shadows) -> sl.Scene:
    """Each part an object of its own (the BVH and the maps see several objects)."""
    v_all, f_all = combine(case.parts)
    normals = ref.vertex_normals(v_all, f_all)
    scene = sl.Scene(ambient=AMBIENT)
    m = sl.Material(MAT.ambient, MAT.diffuse, MAT.specular, MAT.shininess)
    off = 0
    for v, f in case.parts:
        scene.add(sl.Mesh(v, f, normals=normals[off : off + len(v)]), material=m)
        off += len(v)
    for light in case.lights:
        kwargs = {fl.name: getattr(light, fl.name) for fl in dataclasses.fields(light)}
        scene.add_light(type(sl_light(light))(**kwargs, shadows=shadows))
    return scene


def render(case: Case, shadows, size=None, **kw) -> np.ndarray:
    size = size or case.size
    return sl.render(
        sl_scene(case, shadows),
        sl_camera(case.camera),
        width=size[0],
        height=size[1],
        dtype="float32",
        cull_backfaces=case.cull,
        **kw,
    )


_REF: dict = {}


def reference(case: Case, size=None):
    size = size or case.size
    key = (case.label, size)
    if key not in _REF:
        v, f = combine(case.parts)
        img = ref.render_reference(
            v,
            f,
            camera=case.camera,
            width=size[0],
            height=size[1],
            material=MAT,
            lights=case.lights,
            ambient=AMBIENT,
            cull_backfaces=case.cull,
        )
        color, vis = rsh.shaded_phong(
            img, v, f, camera=case.camera, material=MAT, lights=case.lights, ambient=AMBIENT
        )
        _REF[key] = (img, color, vis)
    return _REF[key]


# --------------------------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------------------------

SPHERE_PLANE = Case(
    "sphere over a plane, directional",
    [plane(2.5), sphere((0.0, 1.0, 0.0), 0.5)],
    ref.Camera(eye=(0.0, 3.5, 4.5), target=(0.0, 0.3, 0.0), up=(0, 1, 0), fov_y=45.0),
    [ref.DirectionalLight(direction=(-0.5, -1.0, -0.3))],
)
CUBE_PLANE = Case(
    "cube on a plane, directional",
    [plane(2.5), box((0.0, 0.5, 0.0), 0.5)],
    ref.Camera(eye=(2.0, 2.6, 3.8), target=(-0.3, 0.2, -0.3), up=(0, 1, 0), fov_y=45.0),
    [ref.DirectionalLight(direction=(-1.0, -1.4, 0.8))],
)
# Six cubes around a point light inside a room, the room's near walls culled: every
# direction from the light has receivers and casters (two views see all six walls).
_RING = [box((0, 0, 0), 4.0, inward=True)] + [
    box(c, 0.4) for c in ((2, 0, 0), (-2, 0, 0), (0, 2, 0), (0, -2, 0), (0, 0, 2), (0, 0, -2))
]
RING_A = Case(
    "point light in a ring, view +++",
    _RING,
    ref.Camera(eye=(9.0, 7.0, 10.0), target=(0.0, 0.0, 0.0), up=(0, 1, 0), fov_y=45.0),
    [ref.PointLight(position=(0.1, 0.2, 0.3), intensity=1.5)],
    cull=True,
)
RING_B = dataclasses.replace(
    RING_A,
    label="point light in a ring, view ---",
    camera=ref.Camera(eye=(-9.0, -7.0, -10.0), target=(0.0, 0.0, 0.0), up=(0, 1, 0), fov_y=45.0),
)
_ELEV = math.radians(1.0)  # 89 degrees from the plane's normal
GRAZING = Case(
    "grazing directional light at 89 degrees",
    [plane(2.5), box((0.8, 0.25, 0.0), 0.25)],
    ref.Camera(eye=(0.0, 3.0, 4.0), target=(0.0, 0.0, 0.0), up=(0, 1, 0), fov_y=50.0),
    [ref.DirectionalLight(direction=(-math.cos(_ELEV), -math.sin(_ELEV), 0.0), intensity=40.0)],
)
SPOT = Case(
    "spot light over a sphere and a cube",
    [plane(2.5), sphere((-0.6, 0.6, 0.0), 0.4), box((0.7, 0.3, 0.2), 0.3)],
    ref.Camera(eye=(0.0, 3.0, 4.0), target=(0.0, 0.2, 0.0), up=(0, 1, 0), fov_y=45.0),
    [ref.SpotLight(position=(0.3, 3.0, 1.0), direction=(-0.1, -1.0, -0.3), cutoff=45.0)],
)
AREA = Case(
    "area light: soft shadow of a sphere",
    [plane(2.5), sphere((0.0, 0.7, 0.0), 0.4, 12, 24)],
    ref.Camera(eye=(0.0, 3.0, 3.5), target=(0.0, 0.2, 0.0), up=(0, 1, 0), fov_y=45.0),
    [
        ref.AreaLight(
            position=(0.3, 2.5, 0.5),
            u=(1.0, 0.0, 0.0),
            v=(0.0, 0.0, 1.0),
            samples=3,
            intensity=1.5,
        )
    ],
)


def torus(center, major, minor, n_major=48, n_minor=24, tilt=0.5):
    """A torus about the y axis tilted by ``tilt`` radians about x (it shadows itself)."""
    u = np.linspace(0, 2 * np.pi, n_major, endpoint=False)
    w = np.linspace(0, 2 * np.pi, n_minor, endpoint=False)
    uu, ww = np.meshgrid(u, w, indexing="ij")
    r = major + minor * np.cos(ww)
    v = np.stack([r * np.cos(uu), minor * np.sin(ww), -r * np.sin(uu)], axis=-1).reshape(-1, 3)
    c, s_ = math.cos(tilt), math.sin(tilt)
    v = v @ np.array([[1, 0, 0], [0, c, s_], [0, -s_, c]]).T + np.asarray(center, float)
    f = []
    for i in range(n_major):
        for j in range(n_minor):
            a, b = i * n_minor + j, ((i + 1) % n_major) * n_minor + j
            c2, d = (
                ((i + 1) % n_major) * n_minor + (j + 1) % n_minor,
                i * n_minor + (j + 1) % n_minor,
            )
            f += [[a, b, c2], [a, c2, d]]
    return v, np.array(f)


def spot_cow(center, scale=1.0):
    mesh = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
    return np.asarray(mesh.vertices, float) * scale + np.asarray(center, float), np.asarray(
        mesh.faces
    )


TORUS = Case(
    "self-shadowing torus",
    [plane(2.5, -0.6), torus((0.0, 0.2, 0.0), 0.8, 0.3)],
    ref.Camera(eye=(0.0, 2.8, 3.6), target=(0.0, 0.0, 0.0), up=(0, 1, 0), fov_y=45.0),
    [ref.DirectionalLight(direction=(-0.6, -1.0, 0.4))],
)
COW = Case(
    "Spot the cow",
    [plane(2.0, -0.737), spot_cow((0.0, 0.0, 0.0))],
    ref.Camera(eye=(1.6, 1.4, 2.6), target=(0.0, -0.1, 0.0), up=(0, 1, 0), fov_y=45.0),
    [ref.DirectionalLight(direction=(-0.8, -1.0, -0.3))],
    size=(128, 96),  # 5856 triangles: the reference's rays take a while
)
# A ground 400 units wide seen from 1.5 units up, cubes from near to far: a map fitted to
# the whole ground would spend 2048 texels on 400 units (a texel as large as the near cube's
# edge); fitted to what the camera sees, and with cascades per slice of the view, it does not.
WIDE = Case(
    "cubes on a wide ground, directional",
    [plane(200.0)]
    + [box((x, 0.25, z), 0.25) for x, z in ((-0.6, 1.5), (0.7, -1.0), (-1.0, -4.0), (2.0, -9.0))],
    ref.Camera(eye=(0.0, 1.5, 4.0), target=(0.0, 0.2, -3.0), up=(0, 1, 0), fov_y=50.0, far=40.0),
    [ref.DirectionalLight(direction=(-1.0, -0.7, 0.5))],
)
HARD = [SPHERE_PLANE, CUBE_PLANE, RING_A, RING_B, GRAZING, SPOT, TORUS, COW]


# --------------------------------------------------------------------------------------------
# Figures
# --------------------------------------------------------------------------------------------


def compared(case: Case, size=None):
    """Mask of compared pixels, the exact shadow state there, and the reference colour."""
    size = size or case.size
    img, color, vis = reference(case, size)
    v, f = combine(case.parts)
    sel = img.tri.reshape(-1) >= 0
    pos = img.position.reshape(-1, 3)[sel]
    n = rsh.phong_normals(img, v, f)
    eye = np.asarray(case.camera.eye, float)
    base = ref.lighting(pos, n, eye, MAT, [], AMBIENT)
    contrib = ref.lighting(pos, n, eye, MAT, case.lights, AMBIENT) - base
    lit = np.zeros(sel.size, bool)
    lit[np.nonzero(sel)[0]] = contrib.max(axis=1) > MIN_CONTRIB
    mask = lit & (img.edge_dist.reshape(-1) > EDGE_PX)
    shadow = np.zeros(sel.size, bool)
    shadow[np.nonzero(sel)[0]] = vis.min(axis=0) < 0.5
    return mask.reshape(size[1], size[0]), shadow.reshape(size[1], size[0]), color


def rust_state(case: Case, shadows, size=None, **kw) -> np.ndarray:
    """Shadowed pixels of a Rust render: the light's contribution visibly drops."""
    size = size or case.size
    lit = render(case, False, size, **kw)
    shaded = render(case, shadows, size, **kw)
    return (lit - shaded).max(axis=2) > 1e-4


def boundary_distance(mask: np.ndarray, state: np.ndarray, part=None) -> np.ndarray:
    """Distance in pixels from every pixel to the nearest boundary pixel of ``state``
    within ``mask`` (see the module docstring); ``part``: the object of every pixel."""
    h, w = state.shape
    if part is None:
        part = np.zeros(state.shape, np.int64)
    b = np.zeros_like(mask)
    for dy, dx in ((0, 1), (1, 0), (0, -1), (-1, 0)):
        m2 = np.zeros_like(mask)
        s2 = np.zeros_like(state)
        p2 = part.copy()
        ys = slice(max(dy, 0), h + min(dy, 0))
        yd = slice(max(-dy, 0), h + min(-dy, 0))
        xs = slice(max(dx, 0), w + min(dx, 0))
        xd = slice(max(-dx, 0), w + min(-dx, 0))
        m2[yd, xd] = mask[ys, xs]
        s2[yd, xd] = state[ys, xs]
        p2[yd, xd] = part[ys, xs]
        b |= mask & (~m2 | (s2 != state) | (p2 != part))
    by, bx = np.nonzero(b)
    yy, xx = np.mgrid[0:h, 0:w]
    if by.size == 0:
        return np.full((h, w), np.inf)
    dist = np.full((h, w), np.inf)
    for s in range(0, by.size, 256):
        d = np.hypot(yy[..., None] - by[s : s + 256], xx[..., None] - bx[s : s + 256])
        dist = np.minimum(dist, d.min(axis=2))
    return dist


def parts_of(case: Case, size=None) -> np.ndarray:
    """The object (index into ``case.parts``) seen at every pixel; -1 where none is."""
    size = size or case.size
    img, _, _ = reference(case, size)
    ends = np.cumsum([len(f) for _, f in case.parts])
    return np.where(img.tri >= 0, np.searchsorted(ends, img.tri, side="right"), -1)


def shadow_figures(case: Case, shadows, size=None, **kw) -> dict:
    """The figures of a render with ``shadows`` (and render options ``kw``)."""
    size = size or case.size
    mask, exact, _ = compared(case, size)
    got = rust_state(case, shadows, size, **kw)
    dist = boundary_distance(mask, exact, parts_of(case, size))
    bad = mask & (got != exact)
    away = dist > AWAY_PX
    return {
        "compared": int(mask.sum()),
        "shadowed": int((mask & exact).sum()),
        "mismatch": float(bad.sum() / max(mask.sum(), 1)),
        "max_dist": float(dist[bad].max()) if bad.any() else 0.0,
        "acne": int((bad & got & ~exact & away).sum()),
        "leak": int((bad & ~got & exact & away).sum()),
    }


def colour_match(case: Case, size=None) -> float:
    """Share of compared pixels (visible, away from edges) within 1 LSB of the reference."""
    size = size or case.size
    img, color, _ = reference(case, size)
    got = render(case, "exact", size)
    mask = (img.tri >= 0) & (img.edge_dist > EDGE_PX)
    a = np.clip(np.round(got * 255), 0, 255)
    b = np.clip(np.round(color * 255), 0, 255)
    ok = (np.abs(a - b) <= 1).all(axis=2)
    return float(ok[mask].mean())


# --------------------------------------------------------------------------------------------
# Tests
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", [*HARD, AREA], ids=lambda c: c.label)
def test_exact_matches_the_reference(case):
    share = colour_match(case)
    assert share >= MIN_EXACT_MATCH, f"{case.label}: {share:.5f}"
    if case is not AREA:
        fig = shadow_figures(case, "exact")
        assert fig["shadowed"] > 50, fig  # the scene does show a shadow
        assert fig["mismatch"] <= 1e-3, fig
        assert fig["acne"] == 0 and fig["leak"] == 0, fig


@pytest.mark.parametrize("case", HARD, ids=lambda c: c.label)
def test_shadow_maps_default_no_acne_no_leak(case):
    fig = shadow_figures(case, True)
    assert fig["acne"] == 0 and fig["leak"] == 0, fig
    assert fig["mismatch"] <= 0.02, fig


@pytest.mark.parametrize("case", [SPHERE_PLANE, CUBE_PLANE], ids=lambda c: c.label)
def test_plain_comparison_and_pcf_kernels(case):
    for settings in (
        sl.ShadowSettings(filter="none"),
        sl.ShadowSettings(kernel=5),
        sl.ShadowSettings(resolution=4096, kernel=3),
    ):
        fig = shadow_figures(case, settings)
        assert fig["acne"] == 0 and fig["leak"] == 0, (settings, fig)


def test_directional_maps_fit_the_view_and_cascades_refine_it():
    """On the wide ground, a map fitted to what the camera sees is finer than one over the
    whole scene box (what Phong gets with Whitted rays on, and flat and Gouraud, whose
    shaded points may lie off the view), and cascades, a map per slice of the view, finer
    still near the camera: the mismatch with the exact shadow falls at each step, and the
    cascaded maps show no acne and no leak."""
    whole = shadow_figures(WIDE, True, reflections="ray")
    fitted = shadow_figures(WIDE, True)
    cascaded = shadow_figures(WIDE, sl.ShadowSettings(cascades=3))
    assert whole["shadowed"] > 500, whole
    assert cascaded["mismatch"] < fitted["mismatch"] < whole["mismatch"], (
        whole,
        fitted,
        cascaded,
    )
    assert cascaded["acne"] == 0 and cascaded["leak"] == 0, cascaded
    assert cascaded["mismatch"] <= 0.02, cascaded
    # The exact rays themselves agree with the reference here too.
    exact = shadow_figures(WIDE, "exact")
    assert exact["mismatch"] <= 1e-3 and exact["acne"] == 0 and exact["leak"] == 0, exact


def test_sphere_shadow_is_the_exact_ellipse():
    """On the plane, the exact shadow of the tessellated sphere is within a pixel of the
    analytic one (the ray toward the light meets the true sphere)."""
    mask, exact, _ = compared(SPHERE_PLANE)
    img, _, _ = reference(SPHERE_PLANE)
    on_plane = mask & (img.tri < 2)  # the plane's two triangles come first
    p = img.position[on_plane]
    d = -np.array([-0.5, -1.0, -0.3]) / np.linalg.norm([-0.5, -1.0, -0.3])
    oc = p - np.array([0.0, 1.0, 0.0])
    b = oc @ d
    disc = b * b - (np.sum(oc * oc, axis=1) - 0.25)
    analytic = (disc > 0) & (-b + np.sqrt(np.maximum(disc, 0)) > 0)
    got = rust_state(SPHERE_PLANE, "exact")[on_plane]
    dist = boundary_distance(mask, exact)[on_plane]
    differ = got != analytic
    assert analytic.sum() > 200
    assert differ.mean() < 0.01 and (dist[differ] <= 1.5).all()


def test_contact_shadow_starts_at_the_cube():
    """Shadow maps: the plane pixels touching the cube on its shadow side are shadowed as
    the exact answer says (no peter-panning gap at the contact)."""
    mask, exact, _ = compared(CUBE_PLANE)
    img, _, _ = reference(CUBE_PLANE)
    on_plane = img.tri < 2
    cube = img.tri >= 2
    near_cube = np.zeros_like(cube)
    for dy in (-2, -1, 0, 1, 2):
        for dx in (-2, -1, 0, 1, 2):
            near_cube |= np.roll(np.roll(cube, dy, 0), dx, 1)
    contact = mask & on_plane & near_cube & exact
    assert contact.sum() > 20
    for shadows in ("exact", True):
        got = rust_state(CUBE_PLANE, shadows)
        assert got[contact].mean() >= 0.97, (shadows, got[contact].mean())


def test_point_light_uses_all_six_cube_faces():
    """The ring's shadowed pixels lie in every one of the six directions from the light
    (so every cube-map face is compared)."""
    faces: set[int] = set()
    for case in (RING_A, RING_B):
        mask, exact, _ = compared(case)
        img, _, _ = reference(case)
        d = img.position[mask & exact] - np.array(case.lights[0].position)
        axis = np.abs(d).argmax(axis=1)
        negative = d[np.arange(len(d)), axis] < 0
        faces |= {int(a) for a in np.unique(axis * 2 + negative)}
        fig = shadow_figures(case, True)
        assert fig["acne"] == 0 and fig["leak"] == 0, fig
    assert faces == set(range(6)), faces


def test_area_light_penumbra_is_graded():
    """Soft shadows: partial visibilities appear, and the share per pixel is each sample
    point's exact visibility (the colour test above checks the values)."""
    _, _, vis = reference(AREA)
    share = vis.mean(axis=0)
    assert ((share > 0) & (share < 1)).sum() > 100
    got = render(AREA, "exact")
    lit = render(AREA, False)
    drop = (lit - got).max(axis=2)
    assert np.unique(np.round(drop[drop > 1e-4], 3)).size > 5


def test_no_shadow_lights_render_as_before():
    scene = sl_scene(SPHERE_PLANE, False)
    cam = sl_camera(SPHERE_PLANE.camera)
    a = sl.render(scene, cam, width=64, height=48)
    scene2 = sl_scene(SPHERE_PLANE, None)
    assert np.array_equal(a, sl.render(scene2, cam, width=64, height=48))


def test_shadows_argument_spellings_and_round_trips():
    for cls, args in (
        (sl.DirectionalLight, {"direction": (0, -1, 0)}),
        (sl.PointLight, {"position": (0, 2, 0)}),
        (sl.SpotLight, {"position": (0, 2, 0), "direction": (0, -1, 0)}),
        (sl.AreaLight, {"position": (0, 2, 0), "u": (1, 0, 0), "v": (0, 0, 1)}),
    ):
        assert cls(**args).shadows is False
        assert cls(**args, shadows=False).shadows is False
        assert cls(**args, shadows=True).shadows is True
        assert cls(**args, shadows="exact").shadows == "exact"
        s = sl.ShadowSettings(resolution=512, filter="none", bias=2.0)
        light = cls(**args, shadows=s)
        assert light.shadows == s
        for other in (pickle.loads(pickle.dumps(light)), copy.copy(light), copy.deepcopy(light)):
            assert other.shadows == s
        assert pickle.loads(pickle.dumps(cls(**args, shadows="exact"))).shadows == "exact"
        assert pickle.loads(pickle.dumps(cls(**args, shadows=True))).shadows is True
        with pytest.raises(ValueError, match="shadows"):
            cls(**args, shadows="soft")
        with pytest.raises(TypeError, match="shadows"):
            cls(**args, shadows=3)


def test_shadow_settings_errors_name_the_field():
    s = sl.ShadowSettings()
    assert (s.resolution, s.filter, s.kernel, s.bias, s.cascades) == (2048, "pcf", 3, 1.0, 1)
    assert pickle.loads(pickle.dumps(s)) == s
    c = sl.ShadowSettings(cascades=3)
    assert c.cascades == 3 and pickle.loads(pickle.dumps(c)) == c and c != s
    assert repr(c).endswith("cascades=3)")
    assert sl.ShadowSettings(filter="none").kernel == 1
    for kwargs, field in (
        ({"resolution": sl.MAX_SHADOW_RESOLUTION + 1}, "resolution"),
        ({"resolution": -5}, "resolution"),
        ({"resolution": 8}, "resolution"),
        ({"filter": "gauss"}, "filter"),
        ({"kernel": 4}, "kernel"),
        ({"kernel": -3}, "kernel"),
        ({"bias": float("nan")}, "bias"),
        ({"bias": float("inf")}, "bias"),
        ({"bias": -1.0}, "bias"),
        ({"cascades": 0}, "cascades"),
        ({"cascades": 5}, "cascades"),
        ({"cascades": -1}, "cascades"),
    ):
        with pytest.raises(ValueError, match=field):
            sl.ShadowSettings(**kwargs)


def grid(half: float, n: int):
    """The plane y = 0 as ``n`` x ``n`` quads (for shading that lights at faces or vertices)."""
    xs = np.linspace(-half, half, n + 1)
    v = np.array([[x, 0.0, z] for x in xs for z in xs])
    f = []
    for i in range(n):
        for j in range(n):
            a, b, c = i * (n + 1) + j, i * (n + 1) + j + 1, (i + 1) * (n + 1) + j + 1
            d = (i + 1) * (n + 1) + j
            f += [[a, b, c], [a, c, d]]
    return v, np.array(f)


def test_flat_shadows_are_the_exact_visibility_at_each_face_centroid():
    """Flat shading finds visibility where it lights, at the centroid (offset along the face
    normal): every pixel's shadow state is that of its face, exactly as the reference says;
    Gouraud's (per vertex) darkens the shadow's vertices."""
    case = dataclasses.replace(
        SPHERE_PLANE,
        label="sphere over a grid",
        parts=[grid(2.5, 30), sphere((0.0, 1.0, 0.0), 0.5)],
    )
    img, _, _ = reference(case)
    v, f = combine(case.parts)
    fn = ref.face_normals(v, f)
    cent = v[f].mean(axis=1)
    vis = rsh.visibility(cent, fn, fn, case.lights[0], v, f, rsh.scene_offset(v))
    cam = sl_camera(case.camera)
    for shading in ("flat", "gouraud"):
        got = {}
        for shadows in (False, "exact", True):
            got[shadows] = sl.render(
                sl_scene(case, shadows), cam, width=W, height=H, dtype="float32", shading=shading
            )
        mask = (img.tri >= 0) & (img.edge_dist > EDGE_PX)
        state = (got[False] - got["exact"]).max(axis=2) > 1e-4
        if shading == "flat":
            want = vis[img.tri] < 0.5
            assert np.array_equal(state[mask], want[mask])
            assert want[mask].sum() > 100
        else:
            assert state[mask].sum() > 100
        mapped = (got[False] - got[True]).max(axis=2) > 1e-4
        assert (mapped[mask] != state[mask]).mean() < 0.01


@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_huge_and_tiny_scenes(scale):
    """The offsets and the maps scale with the scene: the same picture at any size."""
    parts = [(v * scale, f) for v, f in CUBE_PLANE.parts]
    c = CUBE_PLANE.camera
    cam = ref.Camera(
        eye=tuple(np.array(c.eye) * scale),
        target=tuple(np.array(c.target) * scale),
        up=c.up,
        fov_y=c.fov_y,
        near=c.near * scale,
        far=c.far * scale,
    )
    case = dataclasses.replace(CUBE_PLANE, label=f"cube x{scale}", parts=parts, camera=cam)
    base = rust_state(CUBE_PLANE, "exact", (96, 72))
    for shadows in ("exact", True):
        got = rust_state(case, shadows, (96, 72))
        assert (got != base).mean() < 0.01, (shadows, (got != base).mean())


def test_hard_cases_stay_finite():
    """Light inside geometry, light at the camera, a light parallel to the plane, and
    zero-area casters: finite images, no panic."""
    zero = (np.array([[0, 1, 0], [0, 1, 0], [1, 1, 1]], float), np.array([[0, 1, 2]]))
    case = dataclasses.replace(CUBE_PLANE, parts=[*CUBE_PLANE.parts, zero])
    cam = CUBE_PLANE.camera
    for light in (
        ref.PointLight(position=(0.0, 0.5, 0.0)),  # inside the cube
        ref.PointLight(position=cam.eye),
        ref.DirectionalLight(direction=(1.0, 0.0, 0.0)),  # parallel to the plane
        ref.SpotLight(position=cam.eye, direction=(-1.0, -1.0, -1.0), cutoff=89.0),
    ):
        c = dataclasses.replace(case, lights=[light])
        for shadows in ("exact", True, sl.ShadowSettings(filter="none")):
            img = render(c, shadows, (48, 36))
            assert np.isfinite(img).all()
    inside = dataclasses.replace(case, lights=[ref.PointLight(position=(0.0, 0.5, 0.0))])
    # The light is enclosed by the cube: everything seen is lit by the ambient term alone.
    img, _, _ = reference(inside, (48, 36))
    for shadows in ("exact", True):
        dark = render(inside, shadows, (48, 36))
        seen = img.tri >= 0
        np.testing.assert_allclose(dark[seen], 0.2 * 0.15, atol=1e-6)


def test_scene_files_and_dicts_keep_shadows(tmp_path):
    scene = sl.Scene(ambient=(0.1, 0.1, 0.1))
    scene.add(sl.Mesh(*box((0, 0.5, 0), 0.5)), material="gold")
    scene.add(sl.Mesh(*plane(2.0)), material="pewter")
    settings = sl.ShadowSettings(resolution=512, filter="none", bias=2.0, cascades=2)
    scene.add_light(sl.DirectionalLight((-1, -2, -1), shadows=True))
    scene.add_light(sl.PointLight((1, 3, 1), shadows="exact"))
    scene.add_light(sl.SpotLight((0, 3, 0), (0, -1, 0), shadows=settings))
    scene.add_light(sl.AreaLight((0, 3, 1), (1, 0, 0), (0, 0, 1)))
    d = sl.scene_to_dict(scene)
    assert [light.get("shadows") for light in d["lights"]] == [
        True,
        "exact",
        {"resolution": 512, "filter": "none", "kernel": 1, "bias": 2.0, "cascades": 2},
        None,  # off: not written
    ]
    back = sl.load_scene_dict(d).scene
    assert [light.shadows for light in back.lights] == [True, "exact", settings, False]
    path = tmp_path / "s.toml"
    sl.save_scene(path, scene)
    assert [light.shadows for light in sl.load_scene(path).scene.lights][:3] == [
        True,
        "exact",
        settings,
    ]
    cam = sl.Camera.look_at((3, 3, 4), (0, 0, 0))
    assert np.array_equal(
        sl.render(scene, cam, width=48, height=36), sl.render(back, cam, width=48, height=36)
    )
    bad = copy.deepcopy(d)
    bad["lights"][2]["shadows"]["resolution"] = 100000
    with pytest.raises(sl.SceneFileError, match="resolution") as e:
        sl.load_scene_dict(bad)
    assert e.value.key == "lights[2].shadows.resolution"
    bad["lights"][2]["shadows"] = "soft"
    with pytest.raises(sl.SceneFileError, match="shadows"):
        sl.load_scene_dict(bad)


def test_cli_shadows_flag(tmp_path):
    from shadelab_rs import cli

    out = {}
    for flag in ("off", "map", "exact"):
        path = tmp_path / f"{flag}.npy"
        assert cli.main(["demo", "--shadows", flag, "--size", "96x72", "-o", str(path)]) == 0
        out[flag] = np.load(path)
    assert out["off"].sum() > out["exact"].sum()
    assert (np.abs(out["map"].astype(int) - out["exact"]).max(axis=2) > 8).mean() < 0.01


def test_shadow_map_memory_is_bounded():
    """An area light's points share its maps (resolution / samples each); beyond 2^28
    texels in all (1 GiB) a render is refused with a clear error naming shadows."""
    scene = sl_scene(CUBE_PLANE, False)
    scene.clear_lights()
    scene.add_light(sl.AreaLight((0, 3, 0), (1, 0, 0), (0, 0, 1), samples=8, shadows=True))
    cam = sl_camera(CUBE_PLANE.camera)
    assert np.isfinite(sl.render(scene, cam, width=32, height=24, dtype="float32")).all()
    scene.clear_lights()
    scene.add_light(sl.PointLight((0, 3, 0), shadows=sl.ShadowSettings(resolution=8192)))
    with pytest.raises(ValueError, match="texels") as e:
        sl.render(scene, cam, width=32, height=24)
    assert getattr(e.value, "field", None) == "shadows"


@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
@pytest.mark.parametrize("shadows", ["exact", True])
def test_textured_scenes_cast_the_untextured_shadows(shading, shadows):
    """The texture stage reads visibility where each mode lights, as the untextured loops
    do: vertex colours c under a white material give the shadows (and colours) of the
    material c without them, in every mode and for maps and exact shadows alike."""
    c = (0.7, 0.6, 0.5)
    cam = sl_camera(SPHERE_PLANE.camera)
    # The plane as a grid, so flat's centroids and Gouraud's vertices see the shadow.
    parts = [grid(2.5, 30), sphere((0.0, 1.0, 0.0), 0.5)]

    def draw(textured: bool, casts) -> np.ndarray:
        scene = sl.Scene(ambient=AMBIENT)
        for v, f in parts:
            colors = np.tile(c, (len(v), 1)) if textured else None
            m = sl.Material((1, 1, 1) if textured else c, (1, 1, 1) if textured else c)
            scene.add(sl.Mesh(v, f, normals=ref.vertex_normals(v, f), colors=colors), material=m)
        scene.add_light(sl_light(SPHERE_PLANE.lights[0], shadows=casts))
        return sl.render(scene, cam, width=W, height=H, dtype="float32", shading=shading)

    shadowed = draw(True, shadows)
    np.testing.assert_allclose(shadowed, draw(False, shadows), atol=2e-5)
    dark = (draw(True, False) - shadowed).max(axis=2) > 0.1
    assert dark.sum() > 300  # the sphere's shadow on the plane
