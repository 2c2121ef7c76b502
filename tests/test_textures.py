"""Textures: the sampler against its definition, textured renders against the float64
reference (``shadelab_ref.texture``), the Python API's spellings and every bad input.

Reference comparison: as in ``test_reference_compare``, colours are compared at pixels whose
centre is more than ``EDGE_PX`` from every edge of the reference's visible triangle, and
must be within 1 level of uint8 on at least 99.9 % of them. The remaining differences are
texel boundaries (nearest) and level boundaries that float32 barycentrics move by ~1e-6.
"""

from __future__ import annotations

import math
import pickle
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest
import shadelab_rs as sl
from hypothesis import given, settings
from hypothesis import strategies as st

from shadelab_ref import reference as ref
from shadelab_ref import texture as rtex
from shadelab_ref.to_sl import sl_light

EDGE_PX = 0.05
MIN_FRACTION_1LSB = 0.999
SHADINGS = ("flat", "gouraud", "phong")
FILTERS = ("nearest", "bilinear", "trilinear")
WRAPS = ("repeat", "clamp", "mirror")

RNG = np.random.default_rng(11)
#: Non-power-of-two in both axes, so the pyramid's odd sizes are exercised.
IMAGE = RNG.random((23, 37, 3))


def floor_mesh(n: int = 6, x: float = 4.0, z0: float = -30.0, z1: float = 2.0):
    """A floor grid at y = 0 from a camera's feet to the horizon; u = x/2, v = -z/4 run
    well outside [0, 1], so every wrap mode is exercised."""
    xs = np.linspace(-x, x, n + 1)
    zs = np.linspace(z1, z0, n + 1)
    gx, gz = np.meshgrid(xs, zs)
    v = np.stack([gx.ravel(), np.zeros(gx.size), gz.ravel()], axis=1)
    uv = np.stack([gx.ravel() / 2.0, -gz.ravel() / 4.0], axis=1)
    faces = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i, j * (n + 1) + i + 1
            c, d = a + n + 1, b + n + 1
            faces += [[a, b, d], [a, d, c]]
    return v, np.array(faces), np.tile([0.0, 1.0, 0.0], (len(v), 1)), uv


CAMERA = ref.Camera(eye=(0.3, 1.0, 3.0), target=(0.0, 0.0, -6.0), up=(0, 1, 0), fov_y=55.0)
LIGHTS = (
    ref.PointLight(position=(1.0, 2.0, -1.0), color=(1.0, 0.9, 0.8), intensity=1.5),
    ref.DirectionalLight(direction=(-0.3, -1.0, -0.4), color=(0.5, 0.5, 0.6), intensity=0.8),
)
MATERIAL = ref.Material((0.3, 0.3, 0.3), (0.8, 0.7, 0.6), (0.4, 0.4, 0.4), 20.0, (0.02, 0, 0))
W, H = 160, 120


def render_pair(
    shading: str,
    filt: str,
    wrap,
    image=IMAGE,
    size=(W, H),
    anisotropy=1,
    mesh=None,
    shadows=False,
    shininess_image=None,
    specular="blinn",
):
    """Our render and the reference's (uint8) of a textured mesh (the floor by default);
    ``shadows``: every light casts them (the reference's are exact; ours as given);
    ``shininess_image``: a shininess map (same filter and wrap as the diffuse map)."""
    v, f, n, uv = floor_mesh() if mesh is None else mesh
    w, h = size
    color, r = rtex.render_textured_reference(
        v,
        f,
        uv,
        image=image,
        filter=filt,
        wrap=wrap,
        anisotropy=anisotropy,
        material=MATERIAL,
        camera=CAMERA,
        width=w,
        height=h,
        lights=LIGHTS,
        ambient=(0.2, 0.2, 0.2),
        normals=n,
        shading=shading,
        shadows=bool(shadows),
        shininess_image=shininess_image,
        specular=specular,
    )

    def texture(a):
        return sl.Texture(a.astype(np.float32), filter=filt, wrap=wrap, anisotropy=anisotropy)

    m = MATERIAL
    mat = sl.Material(
        m.ambient,
        m.diffuse,
        m.specular,
        m.shininess,
        m.emission,
        diffuse_map=texture(image),
        shininess_map=None if shininess_image is None else texture(shininess_image),
    )
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    scene.add(sl.Mesh(v, f, normals=n, uvs=uv), material=mat)
    for light in LIGHTS:
        scene.add_light(sl_light(light, shadows=shadows))
    cam = sl.Camera.look_at(
        CAMERA.eye,
        CAMERA.target,
        up=CAMERA.up,
        fov_y=CAMERA.fov_y,
        near=CAMERA.near,
        far=CAMERA.far,
    )
    img = sl.render(scene, cam, width=w, height=h, shading=shading, specular=specular)
    return img, ref.to_uint8(color), r


def within_one_level(img, want, r) -> float:
    interior = r.mask & (r.edge_dist > EDGE_PX)
    assert interior.sum() > 0.3 * interior.size  # the floor fills most of the view
    diff = np.abs(img.astype(np.int64) - want.astype(np.int64)).max(axis=2)
    return float((diff[interior] <= 1).mean())


@pytest.mark.parametrize("shading", SHADINGS)
@pytest.mark.parametrize("filt", FILTERS)
def test_textured_renders_match_the_reference(shading, filt):
    img, want, r = render_pair(shading, filt, "repeat")
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{shading} {filt}: {frac:.5f} within 1 level"


@pytest.mark.parametrize("wrap", [("clamp", "clamp"), ("mirror", "mirror"), ("mirror", "clamp")])
@pytest.mark.parametrize("filt", FILTERS)
def test_wrap_modes_match_the_reference(wrap, filt):
    img, want, r = render_pair("phong", filt, wrap)
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{wrap} {filt}: {frac:.5f} within 1 level"


@pytest.mark.parametrize("shading", ["flat", "phong"])
@pytest.mark.parametrize("anisotropy", [2, 4, 16])
@pytest.mark.parametrize("filt", ["bilinear", "trilinear"])
def test_anisotropic_renders_match_the_reference(shading, anisotropy, filt):
    img, want, r = render_pair(shading, filt, "repeat", anisotropy=anisotropy)
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{shading} x{anisotropy}: {frac:.5f} within 1 level"


def test_anisotropy_sharpens_the_grazing_floor():
    """More probes along the major axis: the trilinear floor keeps more contrast."""
    checker = ((np.indices((16, 16)) // 4).sum(axis=0) % 2)[..., None] * np.ones(3)
    iso, _, r = render_pair("phong", "trilinear", "repeat", image=checker)
    aniso, _, _ = render_pair("phong", "trilinear", "repeat", image=checker, anisotropy=16)
    far = r.mask.copy()
    far[int(0.45 * H) :] = False  # the far half of the floor
    assert aniso[far].std() > 1.2 * iso[far].std()


def test_minification_reaches_coarse_levels():
    """The grazing floor really is minified: the trilinear render differs from the
    bilinear one (so the comparison above tests the pyramid, not only level 0)."""
    a, _, r = render_pair("phong", "bilinear", "repeat")
    b, _, _ = render_pair("phong", "trilinear", "repeat")
    differ = (np.abs(a.astype(int) - b.astype(int)).max(axis=2) > 8) & r.mask
    assert differ.mean() > 0.1  # measured 0.16


# ---- textures with shadows ----------------------------------------------------------------


def box_mesh(center, half: float):
    """An axis-aligned cube: 6 faces of 4 vertices (face normals, each face's UVs 0..1)."""
    c = np.asarray(center, float)
    verts, faces, normals, uvs = [], [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            a, b = (axis + 1) % 3, (axis + 2) % 3
            k = len(verts)
            for s, t in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = np.zeros(3)
                p[axis], p[a], p[b] = sign * half, s * half, t * half
                verts.append(c + p)
                uvs.append(((s + 1) / 2, (t + 1) / 2))
                normals.append(np.eye(3)[axis] * sign)
            # (a, b) order is counter-clockwise seen from +axis.
            if sign > 0:
                faces += [[k, k + 1, k + 2], [k, k + 2, k + 3]]
            else:
                faces += [[k, k + 2, k + 1], [k, k + 3, k + 2]]
    return np.array(verts), np.array(faces), np.array(normals), np.array(uvs)


def floor_and_box():
    """The textured floor (finer, so Gouraud's vertices see the shadow) and a textured cube
    floating above it, casting shadows from both LIGHTS onto it: one mesh, as the
    reference's occluders are its own triangles."""
    parts = [floor_mesh(24), box_mesh((0.3, 0.6, -1.6), 0.35)]
    off = np.cumsum([0] + [len(p[0]) for p in parts[:-1]])
    return (
        np.concatenate([p[0] for p in parts]),
        np.concatenate([p[1] + o for p, o in zip(parts, off)]),
        np.concatenate([p[2] for p in parts]),
        np.concatenate([p[3] for p in parts]),
    )


@pytest.mark.parametrize("shading", SHADINGS)
def test_textured_shadows_match_the_reference(shading):
    """Textured shading reads each light's visibility where its mode lights (per pixel,
    face centroid, vertex), as untextured shading does: exact shadows within 1 level of
    the reference on >= 99.9 % of interior pixels, and the shadow really darkens the floor."""
    mesh = floor_and_box()
    img, want, r = render_pair(shading, "trilinear", "repeat", mesh=mesh, shadows="exact")
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{shading}: {frac:.5f} within 1 level"
    plain, _, _ = render_pair(shading, "trilinear", "repeat", mesh=mesh)
    interior = r.mask & (r.edge_dist > EDGE_PX)
    darker = (plain.astype(int) - img.astype(int)).max(axis=2) > 8
    assert darker[interior].sum() > 200, darker[interior].sum()
    assert (img.astype(int) <= plain.astype(int) + 1).all()  # shadows only remove light


@pytest.mark.parametrize("shading", SHADINGS)
def test_textured_shadow_maps_agree_with_exact_shadows(shading):
    """Shadow maps at default settings on a textured scene: the exact render's shadow
    state except on a thin band along the boundaries; under 4 samples too."""
    mesh = floor_and_box()
    exact, _, r = render_pair(shading, "bilinear", "repeat", mesh=mesh, shadows="exact")
    mapped, _, _ = render_pair(shading, "bilinear", "repeat", mesh=mesh, shadows=True)
    interior = r.mask & (r.edge_dist > EDGE_PX)
    differ = np.abs(exact.astype(int) - mapped.astype(int)).max(axis=2) > 8
    assert differ[interior].mean() < 0.01, differ[interior].mean()
    v, f, n, uv = mesh
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    mat = sl.Material(diffuse_map=sl.Texture(IMAGE.astype(np.float32)))
    scene.add(sl.Mesh(v, f, normals=n, uvs=uv), material=mat)
    for light in LIGHTS:
        scene.add_light(sl_light(light, shadows="exact"))
    cam = sl.Camera.look_at(CAMERA.eye, CAMERA.target, fov_y=CAMERA.fov_y)
    one = sl.render(scene, cam, width=W, height=H, shading=shading, dtype="float32")
    four = sl.render(scene, cam, width=W, height=H, shading=shading, dtype="float32", samples=4)
    # Multi-sample tiles shade their layers through the same texture stage: a pixel whose
    # samples share one triangle keeps its single-sample colour (most of them), the others
    # blend their edges.
    diff = np.abs(one - four).max(axis=2)
    assert (diff < 1e-6).mean() > 0.5
    assert diff.mean() < 0.01


# ---- shininess maps ------------------------------------------------------------------------

#: Shininess scales from 0.25 to 3 (the material's 20 becomes 5 to 60), non-power-of-two.
SHINY = 0.25 + 2.75 * RNG.random((13, 19, 3))


@pytest.mark.parametrize("specular", ["blinn", "phong", "blinn-normalized"])
@pytest.mark.parametrize("shadows", [False, "exact"])
def test_shininess_maps_match_the_reference(specular, shadows):
    """shininess x mean(r, g, b) of the map, per pixel (through the same fast pow as a
    constant shininess): within 1 level of the reference on >= 99.9 % of interior pixels,
    with and without shadows, for every specular model."""
    mesh = floor_and_box() if shadows else None
    img, want, r = render_pair(
        "phong",
        "trilinear",
        "repeat",
        mesh=mesh,
        shadows=shadows,
        shininess_image=SHINY,
        specular=specular,
    )
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{specular} {shadows}: {frac:.5f} within 1 level"
    plain, _, _ = render_pair("phong", "trilinear", "repeat", mesh=mesh, specular=specular)
    assert (np.abs(plain.astype(int) - img).max(axis=2) > 2).mean() > 0.01  # the map shows


@pytest.mark.parametrize("specular", ["blinn", "phong", "blinn-normalized"])
def test_constant_shininess_map_scales_the_shininess(specular):
    """A map of constant value t is the material with shininess x t (the normalised lobe's
    scale follows it), exactly up to float rounding."""
    half = sl.Texture(np.full((2, 2, 3), 0.5, np.float32))
    spec = (0.6, 0.6, 0.6)

    def draw(material):
        v, f, n, uv = floor_mesh(2, x=1.0, z0=-2.0, z1=0.0)
        scene = sl.Scene()
        scene.add(sl.Mesh(v, f, n, uv), material=material)
        scene.add_light(sl.PointLight((0.2, 1.0, -0.5)))
        cam = sl.Camera.look_at((0, 1.5, 1.0), (0, 0, -1))
        return sl.render(scene, cam, width=48, height=36, dtype="float32", specular=specular)

    a = draw(sl.Material((0.2,) * 3, (0.5,) * 3, spec, 40, shininess_map=half))
    b = draw(sl.Material((0.2,) * 3, (0.5,) * 3, spec, 20))
    np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-6)
    zero = draw(
        sl.Material(
            (0.2,) * 3,
            (0.5,) * 3,
            spec,
            40,
            shininess_map=sl.Texture(np.zeros((2, 2, 3), np.float32)),
        )
    )
    assert np.isfinite(zero).all()
    if specular != "blinn-normalized":  # which refuses an infinite shininess
        # inf x 0.5 is still the mirror.
        mirror = draw(sl.Material((0.2,) * 3, (0.5,) * 3, spec, math.inf, shininess_map=half))
        want = draw(sl.Material((0.2,) * 3, (0.5,) * 3, spec, math.inf))
        np.testing.assert_allclose(mirror, want, rtol=1e-5, atol=1e-6)


def test_shininess_maps_need_phong_and_round_trip(tmp_path):
    """Flat and Gouraud light at faces and vertices: a shininess map is refused there with
    an error naming it. The map pickles, goes through scene files and loads from MTL."""
    tex = sl.Texture.procedural("checker", scale=4, color_a=(2, 2, 2), color_b=(0.25,) * 3)
    m = sl.Material(shininess_map=tex)
    assert m.shininess_map is not None and "shininess_map" in repr(m)
    v, f, n, uv = floor_mesh(2)
    scene = sl.Scene()
    scene.add(sl.Mesh(v, f, n, uv), material=m)
    scene.add_light(sl.PointLight((0.2, 1.0, -0.5)))
    cam = sl.Camera.look_at((0, 1.5, 1.0), (0, 0, -1))
    for shading in ("flat", "gouraud"):
        with pytest.raises(ValueError, match="shininess map") as e:
            sl.render(scene, cam, width=32, height=24, shading=shading)
        assert getattr(e.value, "field", None) == "shininess_map"
    want = sl.render(scene, cam, width=32, height=24)
    back = pickle.loads(pickle.dumps(scene))
    assert back.objects[0].material.shininess_map is not None
    assert sl.render(back, cam, width=32, height=24).tobytes() == want.tobytes()
    again = sl.Scene.from_dict(sl.scene_file.tomllib.loads(sl.to_toml(scene.to_dict())))
    assert sl.render(again, cam, width=32, height=24).tobytes() == want.tobytes()
    obj = write_obj(tmp_path, "newmtl a\nNs 30\nmap_Ns -imfchan l t.png\n")
    [(_name, _mesh, mat)] = sl.load_obj_parts(obj)
    assert mat.shininess_map is not None and mat.diffuse_map is None


# ---- the sampler ---------------------------------------------------------------------------


def test_texel_centres_read_their_texel_in_every_filter():
    img = RNG.random((5, 7, 3)).astype(np.float32)
    u, v = sl.texel_centres(7, 5)
    for filt in FILTERS:
        t = sl.Texture(img, filter=filt)
        for j in range(5):
            for i in range(7):
                got = t.sample(float(u[j, i]), float(v[j, i]))
                np.testing.assert_array_equal(got, img[j, i])


def test_array_row_zero_is_the_top_of_the_image():
    img = np.zeros((2, 1, 3), np.uint8)
    img[0] = 255  # top row white
    t = sl.Texture(img, filter="nearest")
    assert t.sample(0.5, 0.9) == (1.0, 1.0, 1.0)
    assert t.sample(0.5, 0.1) == (0.0, 0.0, 0.0)


@settings(max_examples=200, deadline=None)
@given(
    u=st.floats(-3, 3),
    v=st.floats(-3, 3),
    scale=st.floats(-6, 4),
    aniso=st.floats(0.2, 5),
    filt=st.sampled_from(FILTERS),
    wrap=st.sampled_from(WRAPS),
    probes=st.sampled_from([1, 1, 2, 5, 16]),
)
def test_sampler_equals_the_reference_definition(u, v, scale, aniso, filt, wrap, probes):
    levels = rtex.mip_pyramid(IMAGE)
    d = (2.0**scale / 37, 0.0, 0.0, aniso * 2.0**scale / 23)
    arrays = [np.array([x]) for x in d]
    want = rtex.sample(levels, np.array([u]), np.array([v]), arrays, filt, wrap, probes)[0]
    t = sl.Texture(IMAGE.astype(np.float32), filter=filt, wrap=wrap, anisotropy=probes)
    got = np.array(t.sample(u, v, d))
    # The probe positions (the definition's), for the boundary test of nearest.
    px, py = 37 * d[0], 23 * d[3]
    n = min(math.ceil(max(px, py) / min(px, py)), probes)
    du, dv = (d[0], 0.0) if px >= py else (0.0, d[3])
    ts = [(i + 0.5) / n - 0.5 for i in range(n)]
    pts = [(u + t_ * du, v + t_ * dv) for t_ in ts]
    # f32 texels and weights; a texel boundary hit within 1e-9 may go either way.
    near_boundary = filt == "nearest" and any(
        min(abs(x * k - round(x * k)) for x, k in ((a, 37), (b, 23))) < 1e-9 for a, b in pts
    )
    if not near_boundary:
        np.testing.assert_allclose(got, want, atol=2e-6)


def test_mip_levels_are_box_means():
    t = sl.Texture(IMAGE.astype(np.float32), filter="trilinear")
    assert t.levels == len(rtex.mip_pyramid(IMAGE)) == 6  # 37x23 -> 18x11 ... -> 1x1


def test_nan_and_huge_uvs_render_finite_and_fast():
    v, f, n, uv = floor_mesh(2)
    for bad in (1e30, -1e30, 4e37):
        scene = sl.Scene()
        tex = sl.Texture(IMAGE.astype(np.float32), wrap="mirror")
        uvs = uv * bad
        scene.add(sl.Mesh(v, f, n, uvs), material=sl.Material(diffuse_map=tex))
        scene.add_light(sl.DirectionalLight((0, -1, 0)))
        cam = sl.Camera.look_at((0, 2, 3), (0, 0, -3))
        img = sl.render(scene, cam, width=64, height=48, dtype="float32")
        assert np.isfinite(img).all()
    assert all(
        np.isfinite(tex.sample(x, x, (x, x, x, x))).all() for x in (math.nan, 1e30, math.inf)
    )


# ---- procedural and baked -------------------------------------------------------------------


@pytest.mark.parametrize("name", ["checker", "grid", "stripes", "noise"])
def test_procedural_textures_render_in_every_mode(name):
    v, f, n, uv = floor_mesh(4)
    tex = sl.Texture.procedural(name, scale=4, color_a=(1, 0.5, 0), color_b=(0, 0, 1))
    assert tex.kind == name and tex.width is None
    scene = sl.Scene()
    scene.add(sl.Mesh(v, f, n, uv), material=sl.Material(diffuse_map=tex))
    scene.add_light(sl.DirectionalLight((0, -1, 0)))
    cam = sl.Camera.look_at((0, 2, 3), (0, 0, -3))
    for shading in SHADINGS:
        img = sl.render(scene, cam, width=64, height=48, shading=shading)
        # Both colours show: red-orange pixels and blue ones.
        assert (img[..., 0] > 2 * img[..., 2] + 10).any()
        assert (img[..., 2] > 2 * img[..., 0] + 10).any()


def test_checker_values_and_origin():
    t = sl.Texture.procedural("checker", scale=2)
    assert t.sample(0.25, 0.25) == (1.0, 1.0, 1.0)
    assert t.sample(0.75, 0.25) == (0.0, 0.0, 0.0)


def test_bake_texture_samples_the_function_at_texel_centres():
    t = sl.bake_texture(lambda u, v: np.stack([u, v, u * v], axis=-1), 8, 4, filter="nearest")
    u, v = sl.texel_centres(8, 4)
    np.testing.assert_allclose(t.to_array(), np.stack([u, v, u * v], -1), atol=1e-7)
    grey = sl.bake_texture(lambda u, v: u, 4, 4)
    assert grey.to_array().shape == (4, 4, 3)
    with pytest.raises(ValueError, match="shape"):
        sl.bake_texture(lambda u, v: np.zeros(3)[:2], 4, 4)
    with pytest.raises(ValueError, match="non-finite"):
        sl.bake_texture(lambda u, v: np.where(u > 0.5, np.inf, u), 4, 4)
    with pytest.raises(ValueError, match="width"):
        sl.bake_texture(lambda u, v: u, 0, 4)


# ---- materials, vertex colours, meshes --------------------------------------------------------


def lit_plane(material, colors=None, shading="phong"):
    v, f, n, uv = floor_mesh(2, x=1.0, z0=-2.0, z1=0.0)
    scene = sl.Scene()
    scene.add(sl.Mesh(v, f, n, uv, colors=colors), material=material)
    scene.add_light(sl.PointLight((0.2, 1.0, -0.5)))
    cam = sl.Camera.look_at((0, 1.5, 1.0), (0, 0, -1))
    return sl.render(scene, cam, width=48, height=36, shading=shading, dtype="float32")


@pytest.mark.parametrize("shading", SHADINGS)
def test_vertex_colors_replace_ambient_and_diffuse(shading):
    c = (0.2, 0.5, 0.7)
    nv = len(floor_mesh(2)[0])
    a = lit_plane(sl.Material((1, 1, 1), (1, 1, 1), (0.3, 0.3, 0.3), 10), [c] * nv, shading)
    b = lit_plane(sl.Material(c, c, (0.3, 0.3, 0.3), 10), None, shading)
    np.testing.assert_allclose(a, b, atol=1e-5)
    u8 = lit_plane(sl.Material(), np.full((nv, 4), 128, np.uint8), shading)
    assert np.isfinite(u8).all()


@pytest.mark.parametrize("shading", SHADINGS)
def test_specular_is_added_after_the_texture(shading):
    black = sl.Texture(np.zeros((2, 2, 3), np.float32))
    spec_only = sl.Material((0, 0, 0), (0, 0, 0), (0.6, 0.6, 0.6), 8)
    with_map = sl.Material((0.3, 0.3, 0.3), (0.8, 0.8, 0.8), (0.6, 0.6, 0.6), 8, diffuse_map=black)
    np.testing.assert_allclose(
        lit_plane(with_map, shading=shading), lit_plane(spec_only, shading=shading), atol=1e-6
    )


def test_each_map_weighs_its_own_term():
    red = sl.Texture(np.array([[[1.0, 0.0, 0.0]]], np.float32))
    plain = sl.Material(
        (0.3, 0.3, 0.3), (0.6, 0.6, 0.6), (0.5, 0.5, 0.5), 8, emission=(0.1, 0.1, 0.1)
    )
    for key in ("diffuse_map", "ambient_map", "specular_map", "emission_map"):
        m = plain.with_maps(**{key: red})
        img = lit_plane(m)
        base = lit_plane(plain)
        assert getattr(m, key) is not None
        np.testing.assert_allclose(img[..., 0], base[..., 0], atol=1e-6)  # red untouched
        assert (img[..., 1] < base[..., 1] - 1e-3).any(), key  # green lost a term


def test_material_repr_eq_and_pickle():
    tex = sl.Texture(IMAGE.astype(np.float32))
    a = sl.Material(diffuse_map=tex)
    assert a == sl.Material(diffuse_map=tex)
    assert a != sl.Material(diffuse_map=sl.Texture(IMAGE.astype(np.float32)))
    assert a != sl.Material()
    assert "diffuse_map" in repr(a)
    back = pickle.loads(pickle.dumps(a))
    np.testing.assert_array_equal(back.diffuse_map.to_array(), tex.to_array())
    assert back.ambient_map is None
    v, f, n, uv = floor_mesh(1)
    mesh = sl.Mesh(v, f, n, uv, colors=np.ones((len(v), 3)))
    again = pickle.loads(pickle.dumps(mesh))
    np.testing.assert_array_equal(again.colors, mesh.colors)


def test_textured_scene_pickles_and_renders_identically():
    v, f, n, uv = floor_mesh(2)
    scene = sl.Scene()
    tex = sl.Texture(IMAGE.astype(np.float32), srgb=True, wrap=("mirror", "repeat"))
    scene.add(sl.Mesh(v, f, n, uv), material=sl.Material(diffuse_map=tex))
    scene.add(
        sl.Mesh(v, f, n, uv, colors=np.full((len(v), 3), 0.5)), transform=np.diag([1, 1, 2, 1.0])
    )
    scene.add_light(sl.PointLight((0, 2, -1)))
    scene.set_transform(0, np.eye(4))
    assert scene.objects[0].material.diffuse_map is not None
    back = pickle.loads(pickle.dumps(scene))
    cam = sl.Camera.look_at((0, 2, 3), (0, 0, -3))
    for shading in SHADINGS:
        a = sl.render(scene, cam, width=64, height=48, shading=shading)
        b = sl.render(back, cam, width=64, height=48, shading=shading)
        assert a.tobytes() == b.tobytes()
    obj = pickle.loads(pickle.dumps(scene.objects[0]))
    assert obj.material.diffuse_map is not None


# ---- files: Texture.load, MTL maps, Spot -----------------------------------------------------


def png16(path: Path, rgb: np.ndarray) -> None:
    """A 16-bit RGB PNG (Pillow writes 16-bit grey only)."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[j].astype(">u2").tobytes() for j in range(h))

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    ihdr = struct.pack(">IIBBBBB", w, h, 16, 2, 0, 0, 0)
    path.write_bytes(
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", ihdr)
        + chunk(b"IDAT", zlib.compress(raw))
        + chunk(b"IEND", b"")
    )


def test_load_png8_png16_jpeg_and_pillow(tmp_path):
    from PIL import Image

    img8 = (RNG.random((5, 6, 3)) * 255).astype(np.uint8)
    Image.fromarray(img8).save(tmp_path / "a.png")
    t = sl.Texture.load(tmp_path / "a.png")
    np.testing.assert_allclose(t.to_array(), img8 / 255.0, atol=1e-7)
    assert sl.Texture(Image.fromarray(img8)).to_array().shape == (5, 6, 3)
    img16 = (RNG.random((3, 4, 3)) * 65535).astype(np.uint16)
    png16(tmp_path / "b.png", img16)
    np.testing.assert_allclose(
        sl.Texture.load(tmp_path / "b.png").to_array(), img16 / 65535.0, atol=1e-7
    )
    Image.fromarray(img8).save(tmp_path / "c.jpg")
    assert sl.Texture.load(tmp_path / "c.jpg", srgb=True).width == 6


def test_srgb_decodes_to_linear():
    t = sl.Texture(np.full((1, 1, 3), 0.5, np.float32), srgb=True)
    assert abs(t.sample(0.5, 0.5)[0] - 0.21404114) < 1e-6


def write_obj(tmp_path: Path, mtl: str, with_png: bool = True) -> Path:
    from PIL import Image

    if with_png:
        Image.fromarray(np.full((2, 2, 3), 200, np.uint8)).save(tmp_path / "t.png")
    (tmp_path / "m.mtl").write_text(mtl)
    obj = tmp_path / "m.obj"
    obj.write_text(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl a\nf 1/1 2/2 3/3\n"
    )
    return obj


def test_mtl_maps_load_with_the_obj(tmp_path):
    obj = write_obj(tmp_path, "newmtl a\nKd 1 1 1\nmap_Kd -s 2 2 t.png\nmap_Ks t.png\n")
    [(_name, _mesh, mat)] = sl.load_obj_parts(obj)
    assert mat.diffuse_map is not None and mat.specular_map is not None
    assert mat.ambient_map is None
    scene = sl.Scene()
    assert scene.add_obj(obj) == 1
    assert scene.objects[0].material.diffuse_map is not None


@pytest.mark.parametrize(
    ("mtl", "png", "match"),
    [
        ("newmtl a\nmap_Kd missing.png\n", True, r"m\.mtl:2:.*missing\.png"),
        ("newmtl a\nKd 1 1 1\nmap_Kd bad.png\n", True, r"m\.mtl:3:.*bad\.png"),
        ("newmtl a\nmap_Kd -s x t.png\n", True, r"m\.mtl:2:.*-s"),
        ("newmtl a\nmap_Kd -q 1 t.png\n", True, r"m\.mtl:2:.*unknown option"),
        ("newmtl a\nmap_Kd\n", True, r"m\.mtl:2:.*no texture file"),
    ],
)
def test_bad_mtl_maps_name_the_file_and_line(tmp_path, mtl, png, match):
    obj = write_obj(tmp_path, mtl, png)
    (tmp_path / "bad.png").write_bytes(b"not a png at all")
    with pytest.raises((ValueError, OSError), match=match):
        sl.load_obj_parts(obj)


def test_spot_renders_with_its_own_texture(tmp_path):
    out = tmp_path / "spot.png"
    path = sl.data_path("spot/spot_triangulated.obj")
    subprocess.run(
        [
            sys.executable,
            "-m",
            "shadelab_rs",
            "render",
            str(path),
            "-o",
            str(out),
            "--size",
            "200x150",
        ],
        check=True,
        capture_output=True,
    )
    from PIL import Image

    img = np.asarray(Image.open(out))[..., :3].astype(int)
    cow = img.sum(axis=2) > 0
    grey = np.abs(img - img.mean(axis=2, keepdims=True)).max(axis=2) < 12
    # The texture's black patches and white coat, not the gold fallback.
    assert (cow & grey & (img.mean(axis=2) < 60)).sum() > 100
    assert (cow & grey & (img.mean(axis=2) > 200)).sum() > 100
    [(_, _, mat)] = sl.load_obj_parts(path)
    assert mat.diffuse_map.width == 1024


# ---- bad input -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("array", "exc", "match"),
    [
        (np.zeros((4, 4), np.uint8), ValueError, r"shape \(H, W, 3\)"),
        (np.zeros((4, 4, 2), np.uint8), ValueError, "shape"),
        (np.zeros((4, 4, 3), np.int32), TypeError, "dtype int32"),
        (np.zeros((4, 4, 3), bool), TypeError, "dtype bool"),
        (np.full((2, 2, 3), np.nan, np.float32), ValueError, r"array\[0, 0, 0\] = NaN"),
        (np.array([[[0, np.inf, 0]]]), ValueError, "not finite"),
        (np.zeros((0, 4, 3), np.uint8), ValueError, "at least one texel"),
        (np.full((2, 2, 3), -0.5, np.float32), ValueError, r"must be in \[0, 1e6\]"),
        (np.full((2, 2, 3), 2e6, np.float32), ValueError, r"must be in \[0, 1e6\]"),
        (np.zeros((1, sl.MAX_TEXTURE_SIZE + 1, 3), np.uint8), ValueError, "per side"),
        ("not an image", TypeError, "dtype"),
    ],
)
def test_bad_texture_arrays_are_named(array, exc, match):
    with pytest.raises(exc, match=match):
        sl.Texture(array)


def test_bad_texture_options_and_files(tmp_path):
    img = np.zeros((2, 2, 3), np.float32)
    with pytest.raises(ValueError, match="filter"):
        sl.Texture(img, filter="cubic")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="wrap"):
        sl.Texture(img, wrap="border")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="wrap"):
        sl.Texture(img, wrap=3)  # type: ignore[arg-type]
    for bad in (0, 17, -1):
        with pytest.raises(ValueError, match="anisotropy must be 1"):
            sl.Texture(img, anisotropy=bad)
    with pytest.raises(FileNotFoundError, match=r"nope\.png"):
        sl.Texture.load(tmp_path / "nope.png")
    (tmp_path / "bad.png").write_bytes(b"\x89PNG garbage")
    with pytest.raises(ValueError, match=r"bad\.png"):
        sl.Texture.load(tmp_path / "bad.png")
    with pytest.raises(ValueError, match="procedural texture must be"):
        sl.Texture.procedural("marble")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="octaves"):
        sl.Texture.procedural("noise", octaves=0)
    with pytest.raises(ValueError, match="scale"):
        sl.Texture.procedural("checker", scale=-1)
    with pytest.raises(ValueError, match="width"):
        sl.Texture.procedural("grid", width=2)


def test_bad_vertex_colors_and_maps_without_uvs():
    v, f, _n, _uv = floor_mesh(1)
    with pytest.raises(ValueError, match="colors must have shape"):
        sl.Mesh(v, f, colors=np.zeros((len(v), 2)))
    with pytest.raises(ValueError, match="colors has"):
        sl.Mesh(v, f, colors=np.zeros((len(v) + 1, 3)))
    with pytest.raises(ValueError, match="finite"):
        sl.Mesh(v, f, colors=np.full((len(v), 3), np.nan))
    with pytest.raises(ValueError, match=">= 0"):
        sl.Mesh(v, f, colors=np.full((len(v), 3), -1.0))
    with pytest.raises(TypeError, match="uint8 or float"):
        sl.Mesh(v, f, colors=np.zeros((len(v), 3), np.int64))
    scene = sl.Scene()
    tex = sl.Texture(np.zeros((1, 1, 3), np.float32))
    with pytest.raises(ValueError, match="no UVs"):
        scene.add(sl.Mesh(v, f), material=sl.Material(diffuse_map=tex))
    assert len(scene.objects) == 0


def test_face_intensities_gouraud_refuses_textures():
    v, f, n, uv = floor_mesh(1)
    scene = sl.Scene()
    scene.add(
        sl.Mesh(v, f, n, uv), material=sl.Material(diffuse_map=sl.Texture.procedural("checker"))
    )
    with pytest.raises(ValueError, match="face-intensities"):
        sl.render(
            scene,
            sl.Camera.look_at((0, 2, 3), (0, 0, 0)),
            width=8,
            height=8,
            shading="gouraud",
            gouraud="face-intensities",
        )


# ---- trimesh -------------------------------------------------------------------------------


def test_trimesh_vertex_colors_and_texture_visuals():
    trimesh = pytest.importorskip("trimesh")
    from PIL import Image

    box = trimesh.creation.box()
    box.visual.vertex_colors = np.tile([255, 0, 0, 255], (len(box.vertices), 1))
    mesh = sl.Mesh.from_trimesh(box)
    assert mesh.colors is not None and np.allclose(mesh.colors, [1, 0, 0])
    v, f, _n, uv = floor_mesh(1)
    tm = trimesh.Trimesh(v, f, process=False)
    img = Image.fromarray(np.full((4, 4, 3), 255, np.uint8))
    tm.visual = trimesh.visual.TextureVisuals(uv=uv, image=img)
    scene = sl.Scene()
    scene.add(tm)
    assert scene.objects[0].material.diffuse_map is not None


def test_cli_texture_flag(tmp_path):
    from PIL import Image

    red = tmp_path / "red.png"
    Image.fromarray(np.tile(np.uint8([255, 0, 0]), (4, 4, 1))).save(red)
    spot = sl.data_path("spot/spot_triangulated.obj")
    out = tmp_path / "red_spot.png"
    cmd = [sys.executable, "-m", "shadelab_rs", "render", str(spot), "--size", "80x60"]
    r = subprocess.run(
        [*cmd, "--texture", str(red), "-o", str(out)], capture_output=True, text=True
    )
    assert r.returncode == 0, r.stderr
    img = np.asarray(Image.open(out))[..., :3].astype(int)
    cow = img.sum(axis=2) > 0
    # A white material under a red map: no green where there is no highlight.
    assert (img[cow][:, 0] > img[cow][:, 1]).mean() > 0.9
    # A model without UVs, a missing image, a scene file: one-line errors, exit status 1.
    stl = tmp_path / "box.obj"
    stl.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    for args, match in (
        ([str(stl), "--texture", str(red)], "no UVs"),
        ([str(spot), "--texture", str(tmp_path / "nope.png")], "nope.png"),
    ):
        r = subprocess.run(
            [sys.executable, "-m", "shadelab_rs", "render", *args, "-o", str(out)],
            capture_output=True,
            text=True,
        )
        assert r.returncode == 1 and match in r.stderr, r.stderr
    toml = tmp_path / "s.toml"
    toml.write_text('version = 1\n[[objects]]\nmesh = "cube"\n')
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "shadelab_rs",
            "render",
            str(toml),
            "--texture",
            str(red),
            "-o",
            str(out),
        ],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 1 and "--texture" in r.stderr, r.stderr


def test_scene_files_hold_textures_and_vertex_colors(tmp_path):
    from PIL import Image

    Image.fromarray((IMAGE * 255).astype(np.uint8)).save(tmp_path / "img.png")
    doc = "\n".join(
        [
            "version = 2",
            "[materials.wood]",
            "diffuse = [1, 1, 1]",
            'diffuse_map = { file = "img.png", filter = "bilinear", wrap = ["mirror", "clamp"],'
            " uv_scale = [2, 2] }",
            'specular_map = { procedural = "grid", scale = 4, width = 0.2, color_a = [1, 0, 0] }',
            "[[lights]]",
            'type = "point"',
            "position = [0, 2, 0]",
            "[[objects]]",
            "mesh = { vertices = [[-1, 0, 1], [1, 0, 1], [1, 0, -1]], faces = [[0, 1, 2]],"
            " uvs = [[0, 0], [1, 0], [1, 1]], colors = [[1, 0, 0], [0, 1, 0], [0, 0, 1]] }",
            'material = "wood"',
        ]
    )
    (tmp_path / "s.toml").write_text(doc)
    scene = sl.Scene.from_file(tmp_path / "s.toml")
    m = scene.objects[0].material
    assert m.diffuse_map.filter == "bilinear" and m.diffuse_map.wrap == ("mirror", "clamp")
    assert m.diffuse_map.uv_transform == ((2.0, 2.0), (0.0, 0.0))
    assert m.specular_map.kind == "grid"
    assert scene.objects[0].mesh.colors is not None
    d = scene.to_dict()
    assert d["version"] == 2
    back = sl.Scene.from_dict(sl.scene_file.tomllib.loads(sl.to_toml(d)))
    cam = sl.Camera.look_at((0, 2, 2), (0, 0, 0))
    for shading in SHADINGS:
        a = sl.render(scene, cam, width=48, height=36, shading=shading)
        b = sl.render(back, cam, width=48, height=36, shading=shading)
        assert a.tobytes() == b.tobytes()
    # Version 1 files still load; a missing texture file names its key; arrays cannot be written.
    assert sl.Scene.from_dict({"version": 1, "objects": [{"mesh": {"primitive": "cube"}}]})
    bad = {"version": 2, "materials": {"m": {"diffuse_map": {"file": "nope.png"}}}}
    with pytest.raises(sl.SceneFileError, match=r"materials\.m\.diffuse_map\.file.*nope\.png"):
        sl.Scene.from_dict(bad, base_dir=tmp_path)
    bad = {"version": 2, "materials": {"m": {"diffuse_map": {"procedural": "marble"}}}}
    with pytest.raises(sl.SceneFileError, match="procedural"):
        sl.Scene.from_dict(bad)
    s2 = sl.Scene()
    v, f, n, uv = floor_mesh(1)
    s2.add(
        sl.Mesh(v, f, n, uv), material=sl.Material(diffuse_map=sl.Texture(IMAGE.astype(np.float32)))
    )
    with pytest.raises(ValueError, match="array cannot be written"):
        s2.to_dict()


def test_textured_lighting_beyond_float32_is_refused():
    """Texture values weigh the lighting: a bright light times a bright map that could
    overflow float32 is an error, as for untextured scenes."""
    v, f, n, uv = floor_mesh(1)
    scene = sl.Scene()
    tex = sl.Texture(np.full((1, 1, 3), 1e6, np.float32))
    scene.add(sl.Mesh(v, f, n, uv), material=sl.Material(diffuse_map=tex))
    scene.add_light(sl.DirectionalLight((0, -1, 0), intensity=1e33))
    with pytest.raises(ValueError, match="textured lighting can reach"):
        sl.render(scene, sl.Camera.look_at((0, 2, 3), (0, 0, 0)), width=8, height=8)
