"""Meshes: properties, normals and UVs, trimesh, OBJ loading (groups, MTL materials),
built-in primitives."""

from __future__ import annotations

import numpy as np
import pytest
import shadelab_rs as sl
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

# --------------------------------------------------------------------------------------------
# Mesh
# --------------------------------------------------------------------------------------------


def test_mesh_properties(sphere_arrays):
    v, f = sphere_arrays
    mesh = sl.Mesh(v, f)
    assert mesh.n_vertices == len(v) and mesh.n_faces == len(f)
    assert mesh.vertices.shape == (len(v), 3) and mesh.vertices.dtype == np.float32
    np.testing.assert_array_equal(mesh.vertices, v.astype(np.float32))
    assert mesh.faces.shape == (len(f), 3) and mesh.faces.dtype == np.uint32
    np.testing.assert_array_equal(mesh.faces, f)
    assert mesh.normals.shape == (len(v), 3) and mesh.normals.dtype == np.float32
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, rtol=1e-6)
    # A sphere's averaged normals point outwards, close to the position itself.
    assert np.all(np.sum(mesh.normals * v, axis=1) > 0.95)
    assert mesh.has_normals is False
    assert mesh.uvs is None
    assert "n_vertices=86" in repr(mesh) and "n_faces=168" in repr(mesh)


def test_mesh_with_normals_and_uvs(sphere_arrays):
    v, f = sphere_arrays
    n = v * 2.0
    uv = np.stack([np.linspace(0, 1, len(v)), np.linspace(1, 0, len(v))], axis=1)
    mesh = sl.Mesh(v, f, normals=n, uvs=uv)
    assert mesh.has_normals is True
    np.testing.assert_array_equal(mesh.normals, n.astype(np.float32))  # as given
    assert mesh.uvs.shape == (len(v), 2) and mesh.uvs.dtype == np.float32
    np.testing.assert_array_equal(mesh.uvs, uv.astype(np.float32))
    # keyword and positional forms agree
    m2 = sl.Mesh(vertices=v, faces=f, normals=n, uvs=uv)
    np.testing.assert_array_equal(m2.normals, mesh.normals)


def test_mesh_getters_return_fresh_arrays(sphere_arrays):
    v, f = sphere_arrays
    mesh = sl.Mesh(v, f)
    a = mesh.vertices
    a[:] = 0
    np.testing.assert_array_equal(mesh.vertices, v.astype(np.float32))


def test_mesh_from_trimesh():
    tm = trimesh.creation.icosphere(subdivisions=1)
    mesh = sl.Mesh.from_trimesh(tm)
    assert (mesh.n_vertices, mesh.n_faces) == (len(tm.vertices), len(tm.faces))
    np.testing.assert_array_equal(mesh.vertices, np.float32(tm.vertices))
    np.testing.assert_array_equal(mesh.faces, tm.faces)
    # Normals by the crease-angle rule on welded positions: on a sphere (no crease) they
    # are the library's own average of the unit face normals.
    assert mesh.has_normals and mesh.uvs is None
    plain = sl.Mesh(tm.vertices, tm.faces)
    np.testing.assert_allclose(mesh.normals, plain.normals, atol=1e-6)
    with_normals = sl.Mesh.from_trimesh(tm, use_normals=True)
    assert with_normals.has_normals
    np.testing.assert_allclose(with_normals.normals, tm.vertex_normals, atol=1e-6)


def test_mesh_from_trimesh_keeps_uvs():
    tm = trimesh.load(sl.data_path("cube/cube.obj"), process=False)
    mesh = sl.Mesh.from_trimesh(tm)
    assert mesh.uvs is not None
    # Vertices are split at the cube's sharp edges, each keeping its (position, UV) pair.
    pairs = zip(np.float32(tm.vertices), np.float32(tm.visual.uv))
    given = {(tuple(p), tuple(t)) for p, t in pairs}
    got = {(tuple(p), tuple(t)) for p, t in zip(mesh.vertices, mesh.uvs)}
    assert got == given


def test_load_obj_bundled_meshes():
    cube = sl.load_obj(sl.data_path("cube/cube.obj"))
    assert (cube.n_faces, cube.has_normals) == (48, True)
    assert cube.uvs is not None and cube.uvs.shape == (cube.n_vertices, 2)
    np.testing.assert_array_equal(cube.vertices.min(axis=0), [-1, -1, -1])
    np.testing.assert_array_equal(cube.vertices.max(axis=0), [1, 1, 1])
    # Given cube normals are axis-aligned unit vectors.
    np.testing.assert_array_equal(np.sort(np.abs(cube.normals), axis=1), [[0, 0, 1]] * 54)
    spot = sl.load_obj(str(sl.data_path("spot/spot_triangulated.obj")))  # str works too
    assert (spot.n_vertices, spot.n_faces) == (3225, 5856)
    assert not spot.has_normals and spot.uvs is not None


def test_load_obj_parts(tmp_path):
    parts = sl.load_obj_parts(sl.data_path("cube/cube.obj"))
    assert isinstance(parts, list) and len(parts) == 1
    name, mesh, mat = parts[0]
    assert isinstance(name, str) and isinstance(mesh, sl.Mesh) and mat is None
    assert mesh.n_faces == 48
    # Two groups, one with an MTL material.
    (tmp_path / "m.mtl").write_text(
        "newmtl red\nKa 0.1 0.0 0.0\nKd 0.8 0.1 0.1\nKs 0.5 0.5 0.5\nNs 20\n"
    )
    (tmp_path / "two.obj").write_text(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
        "o first\nf 2 4 3\no second\nusemtl red\nf 1 2 3\n"
    )
    parts = sl.load_obj_parts(tmp_path / "two.obj")
    assert [p[0] for p in parts] == ["first", "second"]
    assert [p[1].n_faces for p in parts] == [1, 1]
    assert parts[0][2] is None
    red = parts[1][2]
    assert isinstance(red, sl.Material)
    np.testing.assert_array_equal(red.ambient, np.float32([0.1, 0, 0]))
    np.testing.assert_array_equal(red.diffuse, np.float32([0.8, 0.1, 0.1]))
    np.testing.assert_array_equal(red.specular, np.float32([0.5, 0.5, 0.5]))
    assert red.shininess == 20
    merged = sl.load_obj(tmp_path / "two.obj")
    assert merged.n_faces == 2


def test_load_obj_quads_are_triangulated(tmp_path):
    p = tmp_path / "quad.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    mesh = sl.load_obj(p)
    assert mesh.n_faces == 2
    # Fan triangulation keeps the counter-clockwise winding: normals face +z.
    np.testing.assert_allclose(mesh.normals, [[0, 0, 1]] * 4, atol=1e-7)


def test_load_mesh_stl_and_obj(tmp_path):
    tm = trimesh.creation.icosphere(subdivisions=1)
    path = tmp_path / "ico.stl"
    tm.export(path)
    mesh = sl.load_mesh(path)
    assert isinstance(mesh, sl.Mesh)
    assert mesh.n_faces == len(tm.faces)
    lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    np.testing.assert_allclose(lo, tm.bounds[0], atol=1e-6)
    np.testing.assert_allclose(hi, tm.bounds[1], atol=1e-6)
    cube = sl.load_mesh(str(sl.data_path("cube/cube.obj")))  # OBJ through the Rust loader
    assert cube.n_faces == 48 and cube.has_normals


def test_builtin_primitives_have_exact_normals():
    s = sl.Mesh.uv_sphere(8, 16)
    assert s.n_faces == 2 * 16 * 7 and s.n_vertices == 2 + 7 * 16
    assert s.has_normals
    np.testing.assert_allclose(s.normals, s.vertices, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(s.vertices, axis=1), 1.0, atol=1e-6)
    c = sl.Mesh.cube()
    assert (c.n_vertices, c.n_faces) == (24, 12) and c.uvs is not None
    v, f = c.vertices, c.faces
    fn = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    fn /= np.linalg.norm(fn, axis=1, keepdims=True)
    np.testing.assert_allclose(fn, c.normals[f[:, 0]], atol=1e-6)
    assert (np.sum(fn * v[f].mean(axis=1), axis=1) > 0).all()  # outward
    p = sl.Mesh.plane()
    assert p.n_faces == 2 and (p.normals == [0, 1, 0]).all()
    expect = sl.Mesh.uv_sphere()
    assert expect.n_faces == 2 * 32 * 15


def test_builtin_primitive_arguments_are_checked():
    for rings, segments in [(1, 8), (8, 2), (-5, 8)]:
        with pytest.raises(ValueError, match="rings >= 2 and segments >= 3"):
            sl.Mesh.uv_sphere(rings, segments)
    with pytest.raises(ValueError, match="50 million"):
        sl.Mesh.uv_sphere(100_000, 100_000)
    for bad in (-1, 11, 2**40):
        with pytest.raises(ValueError, match=r"0 <= subdivisions <= 10"):
            sl.Mesh.ico_sphere(bad)


@pytest.mark.parametrize("subdivisions", [0, 1, 2, 4])
def test_ico_sphere_is_closed_unit_and_exact(subdivisions):
    m = sl.Mesh.ico_sphere(subdivisions)
    assert m.n_faces == 20 * 4**subdivisions and m.n_vertices == 10 * 4**subdivisions + 2
    v, f = m.vertices.astype(np.float64), m.faces.astype(np.int64)
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1.0, atol=1e-6)
    np.testing.assert_allclose(m.normals, v, atol=1e-6)
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    fn = np.cross(b - a, c - a)
    assert (np.sum(fn * (a + b + c), axis=1) > 0).all()  # outward
    # Closed: every directed edge appears once and its reverse once.
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    fwd = {tuple(x) for x in e.tolist()}
    assert len(fwd) == len(e) and all((j, i) in fwd for i, j in fwd)
    # Nearly uniform: triangle areas within a factor 2 of each other (a UV sphere's are not).
    area = np.linalg.norm(fn, axis=1)
    assert area.max() / area.min() < 2.0


MTL_THREE = """newmtl red
Ka 0.1 0 0
Kd 0.8 0.1 0.1
Ks 0.5 0.5 0.5
Ns 20
illum 2
newmtl matte
Ka 0.1 0.1 0.1
Kd 0.2 0.6 0.2
Ks 0.9 0.9 0.9
illum 1
newmtl glow
Ka 0.3 0.3 0.3
Kd 0.1 0.2 0.9
Ks 1 1 1
Ke 0.1 0 0
illum 0
d 0.5
"""


def _three_group_obj(tmp_path):
    """One group with three usemtl runs (red, matte, glow) and one face before any."""
    (tmp_path / "m.mtl").write_text(MTL_THREE)
    quads = []
    for k in range(4):
        x = 2.0 * k
        quads.append(f"v {x} 0 0\nv {x + 1} 0 0\nv {x + 1} 1 0\nv {x} 1 0\n")
    faces = "f 1 2 3 4\nusemtl red\nf 5 6 7 8\nusemtl matte\nf 9 10 11 12\n"
    faces += "usemtl glow\nf 13 14 15 16\n"
    path = tmp_path / "multi.obj"
    path.write_text("mtllib m.mtl\no thing\n" + "".join(quads) + faces)
    return path


def test_usemtl_groups_keep_their_materials_and_illum_is_mapped(tmp_path):
    path = _three_group_obj(tmp_path)
    parts = sl.load_obj_parts(path)
    assert [p[1].n_faces for p in parts] == [2, 2, 2, 2]
    mats = [p[2] for p in parts]
    assert mats[0] is None
    red, matte, glow = mats[1:]
    assert red.specular == (0.5, 0.5, 0.5) and red.shininess == 20
    # illum 1: no highlights; illum 0: the diffuse colour, unlit (added to Ke).
    assert matte.specular == (0.0, 0.0, 0.0) and matte.diffuse == pytest.approx((0.2, 0.6, 0.2))
    assert glow.ambient == glow.diffuse == glow.specular == (0.0, 0.0, 0.0)
    assert glow.emission == pytest.approx((0.2, 0.2, 0.9))
    # d 0.5: half transparent (MTL dissolve), blended over what is behind it.
    assert glow.transparency == 0.5 and red.transparency == 0.0

    scene = sl.Scene(ambient=(0, 0, 0), default_lights=False)
    assert scene.add_obj(path) == 4
    assert scene.n_objects == 4
    cam = sl.Camera.orthographic((3.5, 0.5, 5), (3.5, 0.5, 0), height=1.2)
    img = sl.render(scene, cam, 160, 24, dtype="float32")  # no lights: emission only
    # The glow quad: its emission at half opacity over the black background.
    np.testing.assert_allclose(img[12, 140], [0.1, 0.1, 0.45], atol=1e-6)
    assert (img[12, 20] == 0).all() and (img[12, 60] == 0).all()
    # Lit: each quad shows its own material; a preset overrides them all.
    scene.add_light(sl.DirectionalLight((0, 0, -1)))
    lit = sl.render(scene, cam, 160, 24, dtype="float32")
    centres = lit[12, [20, 60, 100, 140]]
    assert len({tuple(c) for c in centres.round(5).tolist()}) == 4
    gold = sl.Scene(ambient=(0, 0, 0))
    assert gold.add_obj(path, material=sl.Material.preset("gold")) == 4
    gold.add_light(sl.DirectionalLight((0, 0, -1)))
    merged = sl.Scene(ambient=(0, 0, 0))
    merged.add(sl.load_obj(path), material=sl.Material.preset("gold"))
    merged.add_light(sl.DirectionalLight((0, 0, -1)))
    np.testing.assert_array_equal(
        sl.render(gold, cam, 160, 24, dtype="float32"),
        sl.render(merged, cam, 160, 24, dtype="float32"),
    )
    # Same as adding the parts by hand.
    by_hand = sl.Scene(ambient=(0, 0, 0))
    for _, mesh, mat in parts:
        by_hand.add(mesh, material=mat)
    by_hand.add_light(sl.DirectionalLight((0, 0, -1)))
    np.testing.assert_array_equal(sl.render(by_hand, cam, 160, 24, dtype="float32"), lit)


def test_add_obj_transform_and_back_material(tmp_path):
    path = _three_group_obj(tmp_path)
    t = np.eye(4)
    t[:3, 3] = (0, 0, -1)
    cam = sl.Camera.orthographic((3.5, 0.5, -5), (3.5, 0.5, 0), height=1.2)  # from behind
    out = []
    for back in (None, sl.Material(ambient=(1, 0, 0), diffuse=(0, 0, 0), specular=(0, 0, 0))):
        s = sl.Scene(ambient=(1, 1, 1), two_sided=True)
        s.add_obj(path, material=sl.Material.preset("chrome"), transform=t, back_material=back)
        out.append(sl.render(s, cam, 160, 24, dtype="float32", return_depth=True))
    (img0, depth0), (img1, _) = out
    np.testing.assert_allclose(depth0[12, 20], 4.0, rtol=1e-6)  # moved to z = -1
    np.testing.assert_allclose(img1[12, 20], [1, 0, 0], atol=1e-6)  # back material's ka·Ia
    assert not np.allclose(img0[12, 20], [1, 0, 0])


# ---- Mesh.with_normals ---------------------------------------------------------------------


def _shared_cube():
    c = sl.Mesh.cube()
    pos, inv = np.unique(c.vertices, axis=0, return_inverse=True)
    return sl.Mesh(pos, inv.reshape(-1)[c.faces])


def test_with_normals_splits_a_cube_and_keeps_a_sphere_smooth():
    cube = _shared_cube()
    assert cube.n_vertices == 8
    flat = cube.with_normals(crease_angle=30)
    assert flat.n_vertices == 24 and flat.n_faces == 12 and flat.has_normals
    v, f, n = flat.vertices, flat.faces, flat.normals
    fn = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    fn /= np.linalg.norm(fn, axis=1, keepdims=True)
    for k in range(3):
        np.testing.assert_allclose(n[f[:, k]], fn, atol=1e-7)  # each face flat, exactly
    smooth = cube.with_normals(crease_angle=None)
    assert smooth.n_vertices == 8
    unit = smooth.vertices / np.linalg.norm(smooth.vertices, axis=1, keepdims=True)
    np.testing.assert_allclose(smooth.normals, unit, atol=1e-6)
    ball = sl.Mesh.ico_sphere(3)
    again = ball.with_normals(crease_angle=30)
    assert again.n_vertices == ball.n_vertices
    np.testing.assert_array_equal(again.faces, ball.faces)
    assert np.abs(again.normals - ball.vertices).max() < 0.02


def test_with_normals_keeps_uvs_colours_and_renders_a_box_as_a_box():
    cube = _shared_cube()
    uv = np.random.default_rng(0).random((8, 2))
    col = np.random.default_rng(1).random((8, 3))
    m = sl.Mesh(cube.vertices, cube.faces, uvs=uv, colors=col).with_normals(crease_angle=45)
    # Every split vertex carries its source's position, UV and colour.
    src = [int(np.flatnonzero((cube.vertices == p).all(axis=1))[0]) for p in m.vertices]
    np.testing.assert_array_equal(m.uvs, uv.astype(np.float32)[src])
    np.testing.assert_allclose(m.colors, col.astype(np.float32)[src])
    # Phong on the split box, diffuse only under a directional light: each visible face is
    # one flat colour (3 faces and the background); the 8-corner box shades like a pillow.
    cam = sl.Camera.look_at((2.0, 1.6, 2.6), (0, 0, 0), fov_y=40)

    def colours(mesh):
        scene = sl.Scene()
        scene.add(mesh, material=sl.Material(specular=(0, 0, 0)))
        scene.add_light(sl.DirectionalLight(direction=(-0.3, -1.0, -0.5)))
        img = sl.render(scene, cam, width=64, height=64, shading="phong")
        return len(np.unique(img.reshape(-1, 3), axis=0))

    assert colours(cube.with_normals(crease_angle=30)) <= 4
    assert colours(cube) > 50


def test_with_normals_bad_angles_name_the_field():
    for bad in (-1.0, 181.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="crease_angle") as e:
            sl.Mesh.cube().with_normals(crease_angle=bad)
        assert getattr(e.value, "field", None) == "crease_angle"


@settings(max_examples=40, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.one_of(st.none(), st.floats(0.0, 180.0)),
)
def test_with_normals_invariants(seed, angle):
    """For random meshes (shared, duplicated and degenerate vertices included): faces keep
    their count, every output vertex is a copy of an input vertex (position and UV), no
    input vertex disappears, and every normal is unit or zero, never NaN."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 12))
    v = rng.integers(-2, 3, (n, 3)).astype(np.float64)  # small integer grid: duplicates
    f = rng.integers(0, n, (int(rng.integers(1, 16)), 3))
    uv = rng.random((n, 2))
    m = sl.Mesh(v, f, uvs=uv)
    out = m.with_normals(crease_angle=angle)
    assert out.n_faces == m.n_faces and out.n_vertices >= m.n_vertices
    src = out.vertices[out.faces]  # each corner's position equals the input corner's
    np.testing.assert_array_equal(src, m.vertices[m.faces])
    np.testing.assert_array_equal(out.uvs[out.faces], m.uvs[m.faces])
    kept = [(out.vertices == p).all(axis=1).any() for p in m.vertices]
    assert all(kept)
    length = np.linalg.norm(out.normals, axis=1)
    assert np.isfinite(out.normals).all()
    assert (np.isclose(length, 1.0, atol=1e-5) | (length == 0)).all()
