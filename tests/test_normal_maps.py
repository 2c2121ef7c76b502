"""Normal and bump maps: renders against the float64 reference (``shadelab_ref.normalmap``),
their exact properties, the API's spellings and bad input.

Reference comparison as in ``test_textures``: colours at pixels whose centre is more than
``EDGE_PX`` from every edge of the visible triangle, within 1 level of uint8 on at least
99.9 % of them (float32 against float64 arithmetic moves a value across a rounding
boundary now and then; a texel or mip-level boundary moved by ~1e-6 does the same).
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
import shadelab_rs as sl
from test_textures import (
    CAMERA,
    EDGE_PX,
    IMAGE,
    LIGHTS,
    MATERIAL,
    MIN_FRACTION_1LSB,
    H,
    W,
    floor_and_box,
    floor_mesh,
    within_one_level,
)

from shadelab_ref import reference as ref
from shadelab_ref import texture as rtex
from shadelab_ref.to_sl import sl_light

RNG = np.random.default_rng(12)


def random_normal_map(h: int, w: int, tilt: float = 0.6) -> np.ndarray:
    """Unit tangent-space normals in the upper hemisphere, encoded as (n + 1)/2."""
    xy = RNG.uniform(-tilt, tilt, (h, w, 2))
    n = np.concatenate([xy, np.ones((h, w, 1))], axis=2)
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    return (n + 1.0) / 2.0


#: Non-power-of-two maps, so the pyramid's odd sizes are exercised.
NORMALS = random_normal_map(19, 29)
HEIGHTS = RNG.random((17, 13, 3))


def sphere_mesh(rings: int = 24, segments: int = 48):
    """A latitude-longitude unit sphere with UVs (u around, v up; the seam's vertices
    doubled): per-vertex tangents that turn from vertex to vertex."""
    th = np.linspace(0.0, math.pi, rings + 1)[:, None]
    ph = np.linspace(0.0, 2 * math.pi, segments + 1)[None, :]
    x, y, z = np.sin(th) * np.sin(ph), np.cos(th) * np.ones_like(ph), np.sin(th) * np.cos(ph)
    v = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    uv = np.stack(np.broadcast_arrays(ph / (2 * math.pi), 1 - th / math.pi), -1).reshape(-1, 2)
    faces = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * (segments + 1) + j, i * (segments + 1) + j + 1
            c, d = a + segments + 1, b + segments + 1
            faces += [[a, c, d], [a, d, b]]
    return v, np.array(faces), v.copy(), uv


SPHERE_CAMERA = ref.Camera(eye=(0.4, 0.9, 3.2), target=(0, 0, 0), up=(0, 1, 0), fov_y=45.0)


def render_pair(
    filt: str = "trilinear",
    *,
    mesh=None,
    camera=CAMERA,
    normal_image=None,
    normal_scale: float = 1.0,
    bump_image=None,
    bump_scale: float = 1.0,
    shadows=False,
):
    """Our render and the reference's (uint8) of the textured floor (or ``mesh``) with
    these maps (every map with filter ``filt``, wrap repeat), Phong."""
    v, f, n, uv = floor_mesh() if mesh is None else mesh
    color, r = rtex.render_textured_reference(
        v,
        f,
        uv,
        image=IMAGE,
        filter=filt,
        material=MATERIAL,
        camera=camera,
        width=W,
        height=H,
        lights=LIGHTS,
        ambient=(0.2, 0.2, 0.2),
        normals=n,
        shading="phong",
        shadows=bool(shadows),
        normal_image=normal_image,
        normal_scale=normal_scale,
        bump_image=bump_image,
        bump_scale=bump_scale,
    )
    img = ours(
        filt,
        mesh=(v, f, n, uv),
        camera=camera,
        normal_image=normal_image,
        normal_scale=normal_scale,
        bump_image=bump_image,
        bump_scale=bump_scale,
        shadows=shadows,
    )
    return img, ref.to_uint8(color), r


def ours(
    filt="trilinear",
    *,
    mesh=None,
    camera=CAMERA,
    normal_image=None,
    normal_scale=1.0,
    bump_image=None,
    bump_scale=1.0,
    shadows=False,
    shading="phong",
    dtype="uint8",
):
    v, f, n, uv = floor_mesh() if mesh is None else mesh

    def tex(a):
        return None if a is None else sl.Texture(np.asarray(a, np.float32), filter=filt)

    m = MATERIAL
    mat = sl.Material(
        m.ambient,
        m.diffuse,
        m.specular,
        m.shininess,
        m.emission,
        diffuse_map=tex(IMAGE),
        normal_map=tex(normal_image),
        normal_scale=normal_scale,
        bump_map=tex(bump_image),
        bump_scale=bump_scale,
    )
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    scene.add(sl.Mesh(v, f, normals=n, uvs=uv), material=mat)
    for light in LIGHTS:
        scene.add_light(sl_light(light, shadows=shadows))
    cam = sl.Camera.look_at(
        camera.eye, camera.target, up=camera.up, fov_y=camera.fov_y, near=camera.near
    )
    return sl.render(scene, cam, width=W, height=H, shading=shading, dtype=dtype)


def changed(a, b, levels: int = 2) -> float:
    return float((np.abs(a.astype(int) - b.astype(int)).max(axis=2) > levels).mean())


# ---- against the reference -----------------------------------------------------------------


@pytest.mark.parametrize("filt", ["nearest", "bilinear", "trilinear"])
def test_normal_maps_match_the_reference(filt):
    img, want, r = render_pair(filt, normal_image=NORMALS)
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{filt}: {frac:.5f} within 1 level"
    assert changed(img, ours(filt)) > 0.3  # the map shows (measured 0.47 to 0.51)


@pytest.mark.parametrize("scale", [0.4, 2.5])
def test_normal_scale_matches_the_reference(scale):
    img, want, r = render_pair(normal_image=NORMALS, normal_scale=scale)
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{scale}: {frac:.5f} within 1 level"


def test_normal_maps_on_a_sphere_match_the_reference():
    """Per-vertex tangents that turn over the surface (the UV sphere), interpolated and
    made perpendicular to the normal per pixel."""
    mesh = sphere_mesh()
    img, want, r = render_pair(mesh=mesh, camera=SPHERE_CAMERA, normal_image=NORMALS)
    interior = r.mask & (r.edge_dist > EDGE_PX)
    diff = np.abs(img.astype(np.int64) - want.astype(np.int64)).max(axis=2)
    frac = float((diff[interior] <= 1).mean())
    assert interior.sum() > 2000
    assert frac >= MIN_FRACTION_1LSB, f"{frac:.5f} within 1 level"


@pytest.mark.parametrize("filt", ["nearest", "bilinear", "trilinear"])
@pytest.mark.parametrize("scale", [0.02, 0.1])
def test_bump_maps_match_the_reference(filt, scale):
    img, want, r = render_pair(filt, bump_image=HEIGHTS, bump_scale=scale)
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{filt} {scale}: {frac:.5f} within 1 level"
    assert changed(img, ours(filt)) > 0.05


def test_normal_and_bump_maps_together_match_the_reference():
    img, want, r = render_pair(normal_image=NORMALS, bump_image=HEIGHTS, bump_scale=0.05)
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{frac:.5f} within 1 level"


def test_normal_maps_with_shadows_match_the_reference():
    """Shadows keep the geometric visibility; lighting takes the mapped normal."""
    img, want, r = render_pair(mesh=floor_and_box(), normal_image=NORMALS, shadows="exact")
    frac = within_one_level(img, want, r)
    assert frac >= MIN_FRACTION_1LSB, f"{frac:.5f} within 1 level"


# ---- exact properties ----------------------------------------------------------------------


def test_a_flat_normal_map_and_a_constant_bump_map_change_nothing():
    """(0.5, 0.5, 1) decodes to exactly (0, 0, 1) and a constant height has a zero gradient:
    the lit normal is the interpolated one renormalised, which moves float32 results by
    at most a few ulps (measured: max 1.2e-7 in float32 output on this floor, uint8
    identical; 1.8e-6 with gold's specular in crates/raster/tests/textures.rs)."""
    flat = np.broadcast_to(np.array([0.5, 0.5, 1.0]), (4, 4, 3))
    const = np.full((4, 4, 3), 0.7)
    for kw in ({"normal_image": flat}, {"bump_image": const, "bump_scale": 3.0}):
        plain = ours(dtype="float32")
        mapped = ours(dtype="float32", **kw)
        assert np.abs(plain - mapped).max() < 1e-6, kw
        assert np.array_equal(ours(), ours(**kw)), kw


def test_a_normal_map_tilted_toward_the_light_brightens():
    """One directional light from 45 degrees over +x on the floor (normal +y, tangent +x as
    u = x/2, bitangent -z as v = -z/4, so tangent-space (x, y, z) is world (x, -z, y)):
    unmapped, n.l = cos 45; a map whose normal is the light direction in tangent space,
    (sin 45, 0, cos 45), lights every pixel with n.l = 1; tilted half-way, cos 22.5. Diffuse
    only, float32 output, up to float32 rounding."""
    v, f, n, uv = floor_mesh()
    cam = sl.Camera.look_at(CAMERA.eye, CAMERA.target, fov_y=CAMERA.fov_y)

    def render(angle_deg):
        a = math.radians(angle_deg)
        t = np.array([math.sin(a), 0.0, math.cos(a)])
        tex = sl.Texture(np.broadcast_to((t + 1) / 2, (2, 2, 3)).astype(np.float32))
        mat = sl.Material((0, 0, 0), (1, 1, 1), (0, 0, 0), 1.0, normal_map=tex)
        scene = sl.Scene(ambient=(0, 0, 0))
        scene.add(sl.Mesh(v, f, normals=n, uvs=uv), material=mat)
        scene.add_light(sl.DirectionalLight(direction=(-1.0, -1.0, 0.0)))
        return sl.render(scene, cam, width=W, height=H, shading="phong", dtype="float32")

    base, half, toward = render(0.0), render(22.5), render(45.0)
    lit = base[..., 0] > 0
    assert lit.mean() > 0.3
    assert np.allclose(base[lit], math.cos(math.radians(45)), atol=1e-6)
    assert np.allclose(half[lit], math.cos(math.radians(22.5)), atol=1e-6)
    assert np.allclose(toward[lit], 1.0, atol=1e-6)


def test_bump_gradient_points_the_normal_downhill():
    """A height ramp rising along u: the lit normal leans toward -u (-x on the floor), so a
    light coming from -x (travelling along +x) brightens the floor, one from +x darkens it."""
    ramp = np.broadcast_to(np.linspace(0.0, 1.0, 16)[None, :, None], (4, 16, 3)).copy()
    v, f, n, uv = floor_mesh()
    cam = sl.Camera.look_at(CAMERA.eye, CAMERA.target, fov_y=CAMERA.fov_y)

    def render(light_x, bump):
        tex = sl.Texture(ramp.astype(np.float32), wrap="clamp", filter="bilinear")
        mat = sl.Material((0, 0, 0), (1, 1, 1), (0, 0, 0), 1.0)
        if bump:
            mat = mat.with_maps(bump_map=tex, bump_scale=0.05)
        scene = sl.Scene(ambient=(0, 0, 0))
        scene.add(sl.Mesh(v, f, normals=n, uvs=uv), material=mat)
        scene.add_light(sl.DirectionalLight(direction=(light_x, -1.0, 0.0)))
        return sl.render(scene, cam, width=W, height=H, shading="phong", dtype="float32")

    # Inside the texture's u range (clamped outside: zero gradient there).
    for lx, sign in ((1.0, 1), (-1.0, -1)):
        a, b = render(lx, False), render(lx, True)
        d = (b - a)[..., 0]
        moved = np.abs(d) > 1e-4
        assert moved.mean() > 0.05
        assert (np.sign(d[moved]) == sign).all(), lx


# ---- API, modes, bad input -----------------------------------------------------------------


def test_flat_and_gouraud_refuse_normal_and_bump_maps():
    for key in ("normal_image", "bump_image"):
        for shading in ("flat", "gouraud"):
            with pytest.raises(ValueError, match="per-pixel lighting") as e:
                ours(shading=shading, **{key: NORMALS})
            assert getattr(e.value, "field", None) == key.replace("image", "map")


def test_maps_need_uvs_and_finite_scales():
    tex = sl.Texture(NORMALS.astype(np.float32))
    scene = sl.Scene()
    mesh = sl.Mesh(np.eye(3), [[0, 1, 2]])
    for kw, field in (({"normal_map": tex}, "normal_map"), ({"bump_map": tex}, "bump_map")):
        with pytest.raises(ValueError, match="no UVs") as e:
            scene.add(mesh, material=sl.Material(**kw))
        assert getattr(e.value, "field", None) == field
    for field in ("normal_scale", "bump_scale"):
        for bad in (math.nan, math.inf):
            with pytest.raises(ValueError, match=field) as e:
                sl.Material(normal_map=tex, **{field: bad})
            assert getattr(e.value, "field", None) == field


def test_spellings_repr_pickle_and_scene_files(tmp_path):
    from PIL import Image
    from shadelab_rs import scene_file

    path = tmp_path / "n.png"
    Image.fromarray((NORMALS * 255).round().astype(np.uint8)).save(path)
    tex = sl.Texture.load(path)
    m = sl.Material(normal_map=tex, normal_scale=0.5, bump_map=tex, bump_scale=0.25)
    assert m.normal_map is not None and m.bump_map is not None
    assert (m.normal_scale, m.bump_scale) == (0.5, 0.25)
    assert "normal_map=Texture(...)" in repr(m) and "bump_scale=0.25" in repr(m)
    back = pickle.loads(pickle.dumps(m))
    assert (back.normal_scale, back.bump_scale) == (0.5, 0.25)
    assert back.normal_map is not None and back.bump_map is not None
    plain = sl.Material()
    assert (plain.normal_map, plain.normal_scale, plain.bump_scale) == (None, 1.0, 1.0)
    d = scene_file.material_to_dict(m)
    assert d["normal_scale"] == 0.5 and d["bump_map"]["file"] == str(path)
    assert "normal_scale" not in scene_file.material_to_dict(sl.Material(normal_map=tex))
    scene = sl.Scene()
    scene.add(sl.Mesh.plane(), material=m)
    again = sl.Scene.from_dict(scene.to_dict())
    m2 = again.objects[0].material
    assert (m2.normal_scale, m2.bump_scale) == (0.5, 0.25)
    assert pickle.loads(pickle.dumps(scene)).objects[0].material.bump_scale == 0.25


def test_mtl_norm_and_bump_are_loaded(tmp_path):
    from PIL import Image

    Image.fromarray((NORMALS * 255).round().astype(np.uint8)).save(tmp_path / "n.png")
    Image.fromarray((HEIGHTS * 255).round().astype(np.uint8)).save(tmp_path / "h.png")
    (tmp_path / "m.mtl").write_text(
        "newmtl a\nKd 0.8 0.8 0.8\nnorm n.png\nmap_bump -bm 0.05 -s 2 2 h.png\n"
    )
    (tmp_path / "q.obj").write_text(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
        "vn 0 0 1\nusemtl a\nf 1/1/1 2/2/1 3/3/1\n"
    )
    parts = sl.load_obj_parts(tmp_path / "q.obj")
    m = parts[0][2]
    assert m is not None and m.normal_map is not None and m.bump_map is not None
    assert m.bump_scale == pytest.approx(0.05)
    assert m.bump_map.uv_transform == ((2.0, 2.0), (0.0, 0.0))
