"""The Python API: shapes, dtypes and memory layouts, presets, getters, loaders, options."""

from __future__ import annotations

import concurrent.futures
import math
import threading
import time

import numpy as np
import pytest
import shadelab_rs as sl
import trimesh
from PIL import Image

# The nine presets of the spec: ambient RGB, diffuse RGB, specular RGB, shininess.
PRESETS = {
    "black plastic": ((0, 0, 0), (0.01, 0.01, 0.01), (0.5, 0.5, 0.5), 32),
    "brass": (
        (0.329412, 0.223529, 0.027451),
        (0.780392, 0.568627, 0.113725),
        (0.992157, 0.941176, 0.807843),
        27.8974,
    ),
    "bronze": (
        (0.2125, 0.1275, 0.054),
        (0.714, 0.4284, 0.18144),
        (0.393548, 0.271906, 0.166721),
        25.6,
    ),
    "chrome": ((0.25, 0.25, 0.25), (0.4, 0.4, 0.4), (0.774597, 0.774597, 0.774597), 76.8),
    "copper": (
        (0.19125, 0.0735, 0.0225),
        (0.7038, 0.27048, 0.0828),
        (0.256777, 0.137622, 0.086014),
        12.8,
    ),
    "gold": (
        (0.24725, 0.1995, 0.0745),
        (0.75164, 0.60648, 0.22648),
        (0.628281, 0.555802, 0.366065),
        51.2,
    ),
    "pewter": (
        (0.10588, 0.058824, 0.113725),
        (0.427451, 0.470588, 0.541176),
        (0.3333, 0.3333, 0.521569),
        9.84615,
    ),
    "silver": (
        (0.19225, 0.19225, 0.19225),
        (0.50754, 0.50754, 0.50754),
        (0.508273, 0.508273, 0.508273),
        51.2,
    ),
    "polished silver": (
        (0.23125, 0.23125, 0.23125),
        (0.2775, 0.2775, 0.2775),
        (0.773911, 0.773911, 0.773911),
        89.6,
    ),
}

# The rest of the classic table, as published (Kilgard's teapots.c via devernay.free.fr, and
# McReynolds & Blythe 1998 for the polished metals): shininess as a fraction of 128.
CLASSIC_FRACTIONS = {
    "emerald": (
        (0.0215, 0.1745, 0.0215),
        (0.07568, 0.61424, 0.07568),
        (0.633, 0.727811, 0.633),
        0.6,
    ),
    "jade": ((0.135, 0.2225, 0.1575), (0.54, 0.89, 0.63), (0.316228,) * 3, 0.1),
    "obsidian": (
        (0.05375, 0.05, 0.06625),
        (0.18275, 0.17, 0.22525),
        (0.332741, 0.328634, 0.346435),
        0.3,
    ),
    "pearl": ((0.25, 0.20725, 0.20725), (1, 0.829, 0.829), (0.296648,) * 3, 0.088),
    "ruby": (
        (0.1745, 0.01175, 0.01175),
        (0.61424, 0.04136, 0.04136),
        (0.727811, 0.626959, 0.626959),
        0.6,
    ),
    "turquoise": (
        (0.1, 0.18725, 0.1745),
        (0.396, 0.74151, 0.69102),
        (0.297254, 0.30829, 0.306678),
        0.1,
    ),
    "polished bronze": (
        (0.25, 0.148, 0.06475),
        (0.4, 0.2368, 0.1036),
        (0.774597, 0.458561, 0.200621),
        0.6,
    ),
    "polished copper": (
        (0.2295, 0.08825, 0.0275),
        (0.5508, 0.2118, 0.066),
        (0.580594, 0.223257, 0.0695701),
        0.4,
    ),
    "polished gold": (
        (0.24725, 0.2245, 0.0645),
        (0.34615, 0.3143, 0.0903),
        (0.797357, 0.723991, 0.208006),
        0.65,
    ),
    "cyan plastic": ((0, 0.1, 0.06), (0, 0.50980392, 0.50980392), (0.50196078,) * 3, 0.25),
    "green plastic": ((0, 0, 0), (0.1, 0.35, 0.1), (0.45, 0.55, 0.45), 0.25),
    "red plastic": ((0, 0, 0), (0.5, 0, 0), (0.7, 0.6, 0.6), 0.25),
    "white plastic": ((0, 0, 0), (0.55, 0.55, 0.55), (0.7, 0.7, 0.7), 0.25),
    "yellow plastic": ((0, 0, 0), (0.5, 0.5, 0), (0.6, 0.6, 0.5), 0.25),
    "black rubber": ((0.02, 0.02, 0.02), (0.01, 0.01, 0.01), (0.4, 0.4, 0.4), 0.078125),
    "cyan rubber": ((0, 0.05, 0.05), (0.4, 0.5, 0.5), (0.04, 0.7, 0.7), 0.078125),
    "green rubber": ((0, 0.05, 0), (0.4, 0.5, 0.4), (0.04, 0.7, 0.04), 0.078125),
    "red rubber": ((0.05, 0, 0), (0.5, 0.4, 0.4), (0.7, 0.04, 0.04), 0.078125),
    "white rubber": ((0.05, 0.05, 0.05), (0.5, 0.5, 0.5), (0.7, 0.7, 0.7), 0.078125),
    "yellow rubber": ((0.05, 0.05, 0), (0.5, 0.5, 0.4), (0.7, 0.7, 0.04), 0.078125),
}
ALL_PRESETS = {
    **PRESETS,
    **{k: (a, d, s, f * 128) for k, (a, d, s, f) in CLASSIC_FRACTIONS.items()},
}

# render_frame's stats: these counters, and wall times in milliseconds under "*_ms" keys
# (at least these three stages; the set of timed stages may grow).
STATS_COUNTERS = {
    "triangles_in",
    "triangles_setup",
    "triangles_clipped",
    "triangles_culled",
    "triangles_dropped",
    "light_sources",
}
STATS_TIMINGS = {"vertex_ms", "setup_ms", "raster_shade_ms"}


def render_mesh(mesh, camera, **kw):
    """Renders ``mesh`` (gold, two lights) at 48 x 40 in float32 with depth."""
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    scene.add(mesh, material=sl.Material.preset("gold"))
    scene.add_light(sl.DirectionalLight(direction=(-1.0, -1.0, -1.0)))
    scene.add_light(sl.PointLight(position=(2.0, 3.0, 4.0), color=(0.4, 0.4, 0.5)))
    kw.setdefault("dtype", "float32")
    return sl.render(scene, camera, width=48, height=40, return_depth=True, **kw)


def assert_same_render(a, b):
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


# --------------------------------------------------------------------------------------------
# render: output shapes, dtypes, layout
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("width", "height"), [(1, 1), (64, 64), (65, 17), (17, 130)])
@pytest.mark.parametrize("dtype", ["uint8", "float32"])
def test_render_shape_dtype_contiguity(sphere_scene, camera, width, height, dtype):
    img = sl.render(sphere_scene, camera, width=width, height=height, dtype=dtype)
    assert isinstance(img, np.ndarray)
    assert img.shape == (height, width, 3)
    assert img.dtype == np.dtype(dtype)
    assert img.flags.c_contiguous
    assert img.flags.writeable


def test_render_defaults(sphere_scene, camera):
    img = sl.render(sphere_scene, camera)
    assert img.shape == (600, 800, 3) and img.dtype == np.uint8
    explicit = sl.render(
        sphere_scene,
        camera,
        width=800,
        height=600,
        shading="phong",
        specular="blinn",
        background=(0, 0, 0),
        dtype="uint8",
        return_depth=False,
        cull_backfaces=False,
        threads=None,
    )
    np.testing.assert_array_equal(img, explicit)


def test_return_depth_tuple(sphere_scene, camera):
    out = sl.render(sphere_scene, camera, width=40, height=30, return_depth=True)
    assert isinstance(out, tuple) and len(out) == 2
    img, depth = out
    assert img.shape == (30, 40, 3) and img.dtype == np.uint8
    assert depth.shape == (30, 40) and depth.dtype == np.float32
    assert depth.flags.c_contiguous
    np.testing.assert_array_equal(img, sl.render(sphere_scene, camera, width=40, height=30))


def test_depth_is_eye_space_distance_along_view_axis():
    """A plane facing the camera at distance 5 has depth exactly 5 in every covered pixel
    (not the Euclidean distance to the pixel's point, which grows towards the corners)."""
    quad = sl.Mesh([[-10, -10, 0], [10, -10, 0], [10, 10, 0], [-10, 10, 0]], [[0, 1, 2], [0, 2, 3]])
    scene = sl.Scene()
    scene.add(quad)
    for cam in (
        sl.Camera.look_at(eye=(1, 2, 5), target=(1, 2, 0), fov_y=60.0, near=1.0, far=20.0),
        sl.Camera.orthographic(eye=(1, 2, 5), target=(1, 2, 0), height=4.0, near=1, far=20),
    ):
        _, depth = sl.render(scene, cam, width=33, height=21, return_depth=True)
        np.testing.assert_allclose(depth, 5.0, rtol=1e-6)
    # A plane beyond the far plane is not drawn: depth +inf everywhere.
    cam = sl.Camera.look_at(eye=(0, 0, 5), target=(0, 0, 0), near=1.0, far=4.0)
    with pytest.warns(sl.EmptyRenderWarning, match="near 1, far 4"):
        img, depth = sl.render(
            scene, cam, width=8, height=8, return_depth=True, background=(1, 0, 0)
        )
    assert np.all(np.isposinf(depth))
    assert np.all(img == [255, 0, 0])


def test_float32_output_is_linear_and_unclamped():
    """A bright light drives the colour above 1: float32 keeps it, uint8 clamps to 255."""
    quad = sl.Mesh([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], [[0, 1, 2], [0, 2, 3]])
    scene = sl.Scene(ambient=(0, 0, 0))
    scene.add(quad, material=sl.Material((0, 0, 0), (0.5, 0.25, 0.1), (0, 0, 0), 1.0))
    scene.add_light(sl.DirectionalLight((0, 0, -1), color=(1, 1, 1), intensity=4.0))
    cam = sl.Camera.orthographic(eye=(0, 0, 2), target=(0, 0, 0), height=1.0)
    f32 = sl.render(scene, cam, width=4, height=4, dtype="float32")
    np.testing.assert_allclose(f32, np.broadcast_to([2.0, 1.0, 0.4], f32.shape), rtol=1e-6)
    u8 = sl.render(scene, cam, width=4, height=4)
    assert np.all(u8 == [255, 255, 102])


@pytest.mark.parametrize(
    "dtype", ["uint8", np.uint8, np.dtype("uint8"), "float32", np.float32, np.dtype("float32")]
)
def test_dtype_accepted_spellings(sphere_scene, camera, dtype):
    img = sl.render(sphere_scene, camera, width=8, height=6, dtype=dtype)
    assert img.dtype == np.dtype(dtype)


@pytest.mark.parametrize("dtype", ["float64", np.float64, "uint16", int, float, "f8", object])
def test_dtype_other_numpy_types_rejected(sphere_scene, camera, dtype):
    with pytest.raises(ValueError, match=r"dtype must be 'uint8' or 'float32'"):
        sl.render(sphere_scene, camera, width=8, height=6, dtype=dtype)


@pytest.mark.parametrize("dtype", ["junk", 3.5, "image"])
def test_dtype_non_dtypes_rejected(sphere_scene, camera, dtype):
    with pytest.raises((TypeError, ValueError), match="dtype"):
        sl.render(sphere_scene, camera, width=8, height=6, dtype=dtype)


# --------------------------------------------------------------------------------------------
# Input arrays: dtypes, memory layouts, read-only
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.float64, np.longdouble])
def test_vertex_float_dtypes(sphere_arrays, camera, dtype):
    v, f = sphere_arrays
    v = v.astype(dtype)
    expected = render_mesh(sl.Mesh(v.astype(np.float64), f), camera)
    assert_same_render(render_mesh(sl.Mesh(v, f), camera), expected)
    assert sl.Mesh(v, f).vertices.dtype == np.float32


@pytest.mark.parametrize("dtype", [np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint64])
def test_vertex_integer_dtypes(camera, dtype):
    # Non-negative coordinates so that the unsigned types hold them too.
    v = np.array([[0, 0, 0], [2, 0, 0], [1, 2, 0]], dtype=dtype)
    mesh = sl.Mesh(v, [[0, 1, 2]])
    np.testing.assert_array_equal(mesh.vertices, v.astype(np.float32))
    expected = render_mesh(sl.Mesh(v.astype(np.float64), [[0, 1, 2]]), camera)
    assert_same_render(render_mesh(mesh, camera), expected)
    assert np.isfinite(expected[1]).any()


def test_vertices_as_nested_lists(camera):
    v = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]]
    mesh = sl.Mesh(v, [[0, 1, 2]])
    np.testing.assert_array_equal(mesh.vertices, np.float32(v))
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2]])


@pytest.mark.parametrize(
    "dtype",
    [
        np.int8,
        np.int16,
        np.int32,
        np.int64,
        np.uint8,
        np.uint16,
        np.uint32,
        np.uint64,
        np.intc,
        np.uintc,
        np.intp,
        np.uintp,
        np.longlong,
        np.ulonglong,
    ],
)
def test_face_integer_dtypes(sphere_arrays, camera, dtype):
    v, f = sphere_arrays
    assert f.max() <= np.iinfo(np.int8).max  # the sphere is small enough for int8
    mesh = sl.Mesh(v, f.astype(dtype))
    assert mesh.faces.dtype == np.uint32
    np.testing.assert_array_equal(mesh.faces, f)
    assert_same_render(render_mesh(mesh, camera), render_mesh(sl.Mesh(v, f), camera))


def _layouts(a):
    """``a`` as C, Fortran, strided (every other row of a bigger array, every other column),
    reversed-twice and read-only arrays: all equal to ``a``."""
    big = np.zeros((2 * a.shape[0], 2 * a.shape[1]), dtype=a.dtype)
    big[::2, ::2] = a
    rev = a[::-1][::-1]
    ro = a.copy()
    ro.setflags(write=False)
    ro_f = np.asfortranarray(a)
    ro_f.setflags(write=False)
    return {
        "C": np.ascontiguousarray(a),
        "F": np.asfortranarray(a),
        "strided": big[::2, ::2],
        "reversed": rev,
        "readonly": ro,
        "readonly-F": ro_f,
    }


@pytest.mark.parametrize("layout", ["C", "F", "strided", "reversed", "readonly", "readonly-F"])
def test_memory_layouts_give_identical_images(sphere_arrays, camera, layout):
    v, f = sphere_arrays
    n = np.asarray(sl.Mesh(v, f).normals, dtype=np.float64) * 0.5  # renormalised per use
    uv = v[:, :2] * 0.5 + 0.5
    expected = render_mesh(sl.Mesh(v, f, normals=n, uvs=uv), camera)
    mesh = sl.Mesh(
        _layouts(v)[layout],
        _layouts(f.astype(np.int32))[layout],
        normals=_layouts(n)[layout],
        uvs=_layouts(uv)[layout],
    )
    assert_same_render(render_mesh(mesh, camera), expected)
    np.testing.assert_array_equal(mesh.uvs, uv.astype(np.float32))


def test_strided_views_of_a_structured_buffer(sphere_arrays, camera):
    """Vertices taken as columns 3..5 of an (N, 8) interleaved buffer (non-unit row stride)."""
    v, f = sphere_arrays
    buf = np.zeros((len(v), 8))
    buf[:, 3:6] = v
    assert not buf[:, 3:6].flags.c_contiguous
    assert_same_render(
        render_mesh(sl.Mesh(buf[:, 3:6], f), camera), render_mesh(sl.Mesh(v, f), camera)
    )


def test_input_arrays_are_not_modified(sphere_arrays, camera):
    v, f = sphere_arrays
    v2, f2 = v.copy(), f.copy()
    n = np.ones_like(v2)
    n2 = n.copy()
    render_mesh(sl.Mesh(v2, f2, normals=n), camera)
    np.testing.assert_array_equal(v2, v)
    np.testing.assert_array_equal(f2, f)
    np.testing.assert_array_equal(n, n2)


def test_transform_layouts_and_dtypes(sphere_arrays, camera):
    v, f = sphere_arrays
    mesh = sl.Mesh(v, f)
    m = np.array([[0.8, 0.1, 0, 0.1], [0, 1.2, 0, -0.2], [0.2, 0, 0.9, 0], [0, 0, 0, 1]])

    def with_transform(t):
        scene = sl.Scene()
        scene.add(mesh, transform=t)
        scene.add_light(sl.DirectionalLight((-1, -1, -1)))
        return sl.render(scene, camera, width=32, height=32, dtype="float32")

    expected = with_transform(m)
    for t in (np.asfortranarray(m), m.astype(np.float32), m.tolist(), _layouts(m)["strided"]):
        np.testing.assert_array_equal(with_transform(t), expected)
    # The transform really applies (column-vector convention: translation in the last column).
    assert not np.array_equal(expected, with_transform(None))
    np.testing.assert_array_equal(with_transform(np.eye(4)), with_transform(None))


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


@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
def test_given_normals_need_not_be_unit(sphere_arrays, camera, shading):
    """Normals are normalised before use (after the model transform), so scaling them by 2
    (exact in binary floating point) changes nothing."""
    v, f = sphere_arrays
    n = sl.Mesh(v, f).normals.astype(np.float64)
    a = render_mesh(sl.Mesh(v, f, normals=n), camera, shading=shading)
    b = render_mesh(sl.Mesh(v, f, normals=2 * n), camera, shading=shading)
    assert_same_render(a, b)


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


# --------------------------------------------------------------------------------------------
# Materials
# --------------------------------------------------------------------------------------------


def test_preset_names():
    names = sl.Material.preset_names()
    assert isinstance(names, list)
    assert names == list(ALL_PRESETS)  # the seed nine first, then the rest of the table


@pytest.mark.parametrize("name", list(ALL_PRESETS))
def test_preset_exact_values(name):
    ambient, diffuse, specular, shininess = ALL_PRESETS[name]
    m = sl.Material.preset(name)
    assert m.ambient == tuple(np.float32(ambient).tolist())
    assert m.diffuse == tuple(np.float32(diffuse).tolist())
    assert m.specular == tuple(np.float32(specular).tolist())
    assert m.shininess == float(np.float32(shininess))
    assert m == sl.Material(ambient, diffuse, specular, shininess)


@pytest.mark.parametrize(
    ("spelling", "name"),
    [
        ("Polished_Silver", "polished silver"),
        ("POLISHED SILVER", "polished silver"),
        ("polished_silver", "polished silver"),
        ("Black_Plastic", "black plastic"),
        ("GOLD", "gold"),
        ("Chrome", "chrome"),
    ],
)
def test_preset_name_variants(spelling, name):
    assert sl.Material.preset(spelling) == sl.Material.preset(name)


def test_material_constructor_and_getters():
    m = sl.Material(
        ambient=(0.1, 0.2, 0.3), diffuse=(0.4, 0.5, 0.6), specular=(0.7, 0.8, 0.9), shininess=12.5
    )
    assert m.ambient == pytest.approx((0.1, 0.2, 0.3), rel=1e-7)
    assert m.diffuse == pytest.approx((0.4, 0.5, 0.6), rel=1e-7)
    assert m.specular == pytest.approx((0.7, 0.8, 0.9), rel=1e-7)
    assert m.shininess == 12.5
    assert m == sl.Material((0.1, 0.2, 0.3), (0.4, 0.5, 0.6), (0.7, 0.8, 0.9), 12.5)
    assert m != sl.Material((0.1, 0.2, 0.3), (0.4, 0.5, 0.6), (0.7, 0.8, 0.9), 12.0)
    assert m == sl.Material(np.array([0.1, 0.2, 0.3]), [0.4, 0.5, 0.6], (0.7, 0.8, 0.9), 12.5)
    assert "shininess=12.5" in repr(m)


def test_material_defaults_are_valid():
    m = sl.Material()
    for v in (*m.ambient, *m.diffuse, *m.specular, m.shininess):
        assert math.isfinite(v) and v >= 0


# --------------------------------------------------------------------------------------------
# Scene, lights, camera
# --------------------------------------------------------------------------------------------


def test_scene_getters(sphere_arrays):
    scene = sl.Scene(ambient=(0.1, 0.2, 0.3))
    assert scene.ambient == pytest.approx((0.1, 0.2, 0.3), rel=1e-7)
    assert (scene.n_objects, scene.n_lights, scene.n_triangles) == (0, 0, 0)
    mesh = sl.Mesh(*sphere_arrays)
    scene.add(mesh)
    scene.add(mesh, material=sl.Material.preset("gold"), transform=np.eye(4))
    scene.add_light(sl.DirectionalLight((0, -1, 0)))
    scene.add_light(sl.PointLight((0, 1, 0)))
    assert (scene.n_objects, scene.n_lights, scene.n_triangles) == (2, 2, 2 * mesh.n_faces)
    assert "objects=2" in repr(scene)
    assert sl.Scene().ambient == pytest.approx((0.2, 0.2, 0.2), rel=1e-7)


def test_directional_light_getters():
    light = sl.DirectionalLight(direction=(0, -2, 0), color=(0.5, 0.25, 1.0), intensity=2.0)
    assert light.direction == (0.0, -1.0, 0.0)  # normalised
    assert light.color == (0.5, 0.25, 1.0)
    assert light.intensity == 2.0
    d = sl.DirectionalLight((1, 1, 1))
    assert d.color == (1.0, 1.0, 1.0) and d.intensity == 1.0
    np.testing.assert_allclose(d.direction, [3**-0.5] * 3, rtol=1e-6)
    assert "DirectionalLight(" in repr(d)


def test_point_light_getters():
    light = sl.PointLight(position=(1, 2, 3), color=(0.5, 0.25, 1.0), intensity=2.0)
    assert light.position == (1.0, 2.0, 3.0)
    assert light.color == (0.5, 0.25, 1.0)
    assert light.intensity == 2.0
    p = sl.PointLight(np.array([1.0, 2.0, 3.0]))
    assert p.color == (1.0, 1.0, 1.0) and p.intensity == 1.0
    assert "PointLight(" in repr(p)


def test_camera_getters():
    cam = sl.Camera.look_at(
        eye=(1, 2, 3), target=(0, 0.5, 0), up=(0, 0, 1), fov_y=30.0, near=0.25, far=50.0
    )
    assert (cam.eye, cam.target, cam.up) == ((1, 2, 3), (0, 0.5, 0), (0, 0, 1))
    assert (cam.near, cam.far, cam.fov_y, cam.height) == (0.25, 50.0, 30.0, None)
    assert cam.kind == "perspective"
    default = sl.Camera.look_at((0, 0, 3), (0, 0, 0))
    # near/far left out: None, fitted to the scene's bounds when rendering.
    assert (default.up, default.fov_y, default.near, default.far) == ((0, 1, 0), 45.0, None, None)
    ortho = sl.Camera.orthographic(eye=(0, 0, 3), target=(0, 0, 0), height=3.5, near=0.5, far=9.0)
    assert ortho.kind == "orthographic"
    assert (ortho.height, ortho.fov_y, ortho.near, ortho.far) == (3.5, None, 0.5, 9.0)
    d = sl.Camera.orthographic((0, 0, 3), (0, 0, 0))
    assert (d.up, d.height, d.near, d.far) == ((0, 1, 0), 2.0, None, None)
    assert repr(cam).startswith("Camera.look_at(") and repr(ortho).startswith("Camera.ortho")


@pytest.mark.parametrize("kind", ["orthographic", "perspective"])
def test_camera_orientation_and_aspect(kind):
    """A marker up and to the right of the target lands in the top-right of the image, and
    the horizontal extent is the vertical one times width / height (a square stays square).

    Both cameras map the plane z = 0 to 20 pixels per unit around the image centre: the
    orthographic one by its height 4 over 80 rows, the perspective one (eye at distance 5,
    tan(fov_y / 2) = 0.4) because 5 * 0.4 = 2 units span the 40 rows above the centre."""
    scene = sl.Scene(ambient=(1, 1, 1))
    s = 0.25
    square = sl.Mesh(
        [[1 - s, 1 - s, 0], [1 + s, 1 - s, 0], [1 + s, 1 + s, 0], [1 - s, 1 + s, 0]],
        [[0, 1, 2], [0, 2, 3]],
    )
    scene.add(square, material=sl.Material((1, 1, 1), (0, 0, 0), (0, 0, 0), 1))
    if kind == "orthographic":
        cam = sl.Camera.orthographic(eye=(0, 0, 5), target=(0, 0, 0), height=4.0)
    else:
        fov_y = 2 * math.degrees(math.atan(0.4))
        cam = sl.Camera.look_at(eye=(0, 0, 5), target=(0, 0, 0), fov_y=fov_y)
    img = sl.render(scene, cam, width=160, height=80)
    ys, xs = np.nonzero(img[..., 0])
    # The square spans x, y in [0.75, 1.25]: columns 95..104, rows 15..24 (row 0 at the top).
    assert (xs.min(), xs.max() + 1) == (80 + 15, 80 + 25)
    assert (ys.min(), ys.max() + 1) == (40 - 25, 40 - 15)
    assert len(xs) == 100


# --------------------------------------------------------------------------------------------
# Render options
# --------------------------------------------------------------------------------------------


def test_render_frame(sphere_scene, camera):
    out = sl.render_frame(sphere_scene, camera, width=40, height=30)
    assert set(out) == {"image", "depth", "stats"}
    assert out["depth"] is None
    np.testing.assert_array_equal(out["image"], sl.render(sphere_scene, camera, 40, 30))
    stats = out["stats"]
    timings = {k for k in stats if k.endswith("_ms")}
    assert set(stats) - timings == STATS_COUNTERS
    assert timings >= STATS_TIMINGS
    assert stats["triangles_in"] == sphere_scene.n_triangles
    assert 0 < stats["triangles_setup"] <= stats["triangles_in"]
    assert stats["triangles_clipped"] == stats["triangles_culled"] == 0
    assert stats["triangles_dropped"] == 0
    assert stats["light_sources"] == sphere_scene.n_lights
    for k in STATS_COUNTERS:
        assert isinstance(stats[k], int) and stats[k] >= 0, k
    for k in timings:
        assert isinstance(stats[k], float) and stats[k] >= 0, k
    full = sl.render_frame(
        sphere_scene, camera, width=40, height=30, dtype="float32", return_depth=True
    )
    img, depth = sl.render(sphere_scene, camera, 40, 30, dtype="float32", return_depth=True)
    np.testing.assert_array_equal(full["image"], img)
    np.testing.assert_array_equal(full["depth"], depth)


@pytest.mark.parametrize("dtype", ["uint8", "float32"])
def test_background_colour(sphere_scene, camera, dtype):
    bg = (0.2, 0.4, 1.0)
    img, depth = sl.render(
        sphere_scene, camera, width=40, height=30, background=bg, dtype=dtype, return_depth=True
    )
    empty = np.isinf(depth)
    assert 0 < empty.sum() < empty.size
    expected = [51, 102, 255] if dtype == "uint8" else np.float32(bg)
    np.testing.assert_array_equal(img[empty], np.broadcast_to(expected, (empty.sum(), 3)))
    # Default: black.
    assert np.all(sl.render(sphere_scene, camera, width=40, height=30)[empty] == 0)


def test_empty_scene_is_background(camera):
    img, depth = sl.render(
        sl.Scene(), camera, width=16, height=8, background=(1, 0.5, 0), return_depth=True
    )
    assert np.all(img == [255, 128, 0])
    assert np.all(np.isposinf(depth))


def test_cull_backfaces(camera):
    ccw = [[-1, -1, 0], [1, -1, 0], [0, 1, 0]]
    scene = sl.Scene()
    scene.add(sl.Mesh(ccw, [[0, 2, 1]]))  # clockwise seen from the camera: a back face
    scene.add_light(sl.DirectionalLight((0, 0, -1)))
    drawn = sl.render_frame(scene, camera, width=32, height=32, return_depth=True)
    culled = sl.render_frame(
        scene, camera, width=32, height=32, return_depth=True, cull_backfaces=True
    )
    assert np.isfinite(drawn["depth"]).sum() > 50
    assert np.all(np.isinf(culled["depth"])) and np.all(culled["image"] == 0)
    assert (drawn["stats"]["triangles_culled"], culled["stats"]["triangles_culled"]) == (0, 1)


@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
def test_culling_a_closed_mesh_changes_nothing(sphere_scene, camera, shading):
    """Front faces of a closed convex mesh tile its silhouette exactly (watertight fill rule),
    so culling the back faces hidden behind them gives the same image, pixel for pixel."""
    kw = dict(width=96, height=80, shading=shading, dtype="float32", return_depth=True)
    drawn = sl.render_frame(sphere_scene, camera, **kw)
    culled = sl.render_frame(sphere_scene, camera, cull_backfaces=True, **kw)
    np.testing.assert_array_equal(culled["image"], drawn["image"])
    np.testing.assert_array_equal(culled["depth"], drawn["depth"])
    assert culled["stats"]["triangles_culled"] > 0.3 * sphere_scene.n_triangles


def test_shading_and_specular_names_case_insensitive(sphere_scene, camera):
    a = sl.render(sphere_scene, camera, width=24, height=24, shading="Gouraud", specular="PHONG")
    b = sl.render(sphere_scene, camera, width=24, height=24, shading="gouraud", specular="phong")
    np.testing.assert_array_equal(a, b)


def test_shading_modes_differ(sphere_scene, camera):
    imgs = {
        (sh, sp): sl.render(sphere_scene, camera, width=48, height=48, shading=sh, specular=sp)
        for sh in ("flat", "gouraud", "phong")
        for sp in ("blinn", "phong")
    }
    keys = list(imgs)
    for i, a in enumerate(keys):
        for b in keys[i + 1 :]:
            assert not np.array_equal(imgs[a], imgs[b]), (a, b)


# A one-pixel-wide image may miss the sphere: that render warns that it drew nothing.
@pytest.mark.filterwarnings("ignore::shadelab_rs.EmptyRenderWarning")
def test_max_image_size_boundary(sphere_scene, camera):
    assert sl.MAX_IMAGE_SIZE == 16384
    img = sl.render(sphere_scene, camera, width=sl.MAX_IMAGE_SIZE, height=1)
    assert img.shape == (1, sl.MAX_IMAGE_SIZE, 3)
    img = sl.render(sphere_scene, camera, width=1, height=sl.MAX_IMAGE_SIZE)
    assert img.shape == (sl.MAX_IMAGE_SIZE, 1, 3)


# --------------------------------------------------------------------------------------------
# Threads: determinism, concurrency, GIL
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
def test_thread_count_is_bit_identical(make_scene, shading):
    spot = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
    scene = make_scene(spot)
    cam = sl.frame_mesh(spot.vertices)
    kw = dict(width=200, height=150, shading=shading, dtype="float32", return_depth=True)
    ref_img, ref_depth = sl.render(scene, cam, threads=1, **kw)
    for threads in (2, 3, 7, None):
        img, depth = sl.render(scene, cam, threads=threads, **kw)
        assert img.tobytes() == ref_img.tobytes(), threads
        assert depth.tobytes() == ref_depth.tobytes(), threads
    assert np.isfinite(ref_depth).sum() > 0.1 * ref_depth.size


def test_concurrent_python_threads_match_sequential():
    scene, cam = sl.demo_scene()
    jobs = [
        dict(width=160, height=120, shading=sh, dtype=dt, threads=th)
        for sh in ("flat", "gouraud", "phong")
        for dt in ("uint8", "float32")
        for th in (1, None)
    ]
    alone = [sl.render(scene, cam, **j).tobytes() for j in jobs]
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        together = list(pool.map(lambda j: sl.render(scene, cam, **j).tobytes(), jobs * 2))
    assert together == alone * 2


def test_render_releases_the_gil(make_scene):
    """While one thread renders, another keeps running Python code: a busy loop stamps the
    time while the render runs. Were the GIL held, the loop could run only before the render
    began (one 5 ms switch interval at most) and after it returned, so no stamp could fall
    in the second half of the ~0.1 s render. No speed threshold, so load cannot flake it."""
    spot = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
    scene = make_scene(spot)
    cam = sl.frame_mesh(spot.vertices)
    kw = dict(width=2400, height=1800, shading="phong", threads=1)  # ~0.1 s
    started, done = threading.Event(), threading.Event()
    span = []

    def work():
        started.set()
        t0 = time.perf_counter()
        sl.render(scene, cam, **kw)
        span.extend([t0, time.perf_counter()])
        done.set()

    thread = threading.Thread(target=work)
    thread.start()
    started.wait()
    stamps = []
    while not done.is_set():
        stamps.append(time.perf_counter())
    thread.join()
    t0, t1 = span
    second_half = sum((t0 + t1) / 2 < t < t1 for t in stamps)
    assert second_half > 10, (second_half, len(stamps), t1 - t0)


# --------------------------------------------------------------------------------------------
# Package helpers
# --------------------------------------------------------------------------------------------


def test_demo_scene_renders():
    scene, cam = sl.demo_scene()
    assert isinstance(scene, sl.Scene) and isinstance(cam, sl.Camera)
    assert scene.n_objects == 4 and scene.n_lights == 2
    img = sl.render(scene, cam, width=96, height=72)
    assert (img > 0).any(axis=-1).mean() > 0.2


def test_frame_mesh_fits_the_mesh():
    spot = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
    cam = sl.frame_mesh(spot.vertices)
    scene = sl.Scene()
    scene.add(spot)
    _, depth = sl.render(scene, cam, width=64, height=64, return_depth=True)
    covered = np.isfinite(depth)
    assert covered.mean() > 0.1
    # Nothing touches the border: the whole model is in frame.
    assert not covered[0].any() and not covered[-1].any()
    assert not covered[:, 0].any() and not covered[:, -1].any()
    # The planes are fitted at render time around the model.
    assert cam.near is None and cam.far is None
    fitted = cam.fitted(scene)
    assert fitted.near < depth[covered].min() and depth[covered].max() < fitted.far


def test_data_path():
    assert sl.data_path("cube/cube.obj").is_file()
    assert sl.data_path("spot/spot_triangulated.obj").is_file()


def test_to_uint8():
    a = np.array([[-1.0, 0.0, 0.5 / 255], [1.5 / 255, 0.5, 1.0], [2.0, np.nan, 254.5 / 255]])
    np.testing.assert_array_equal(sl.to_uint8(a), [[0, 0, 1], [2, 128, 255], [255, 0, 255]])
    np.testing.assert_array_equal(sl.to_uint8(a.astype(np.float32))[0], [0, 0, 1])
    u = np.array([1, 2, 3], dtype=np.uint8)
    assert sl.to_uint8(u) is u
    with pytest.raises(TypeError, match="dtype"):
        sl.to_uint8(np.array([1, 2, 3]))


@pytest.mark.parametrize("dtype", ["uint8", "float32"])
def test_save_image_round_trip(sphere_scene, camera, tmp_path, dtype):
    img = sl.render(sphere_scene, camera, width=40, height=30, dtype=dtype)
    path = tmp_path / "out.png"
    sl.save_image(img, path)
    with Image.open(path) as im:
        assert im.mode == "RGB" and im.size == (40, 30)
        np.testing.assert_array_equal(np.asarray(im), sl.to_uint8(img))
    with pytest.raises(ValueError, match="shape"):
        sl.save_image(np.zeros((4, 4, 5), img.dtype), tmp_path / "bad.png")


def test_version_and_exports():
    assert isinstance(sl.__version__, str) and sl.__version__
    for name in sl.__all__:
        assert hasattr(sl, name), name
    assert issubclass(sl.ObjParseError, ValueError)


def test_light_and_material_extras_round_trip():
    p = sl.PointLight((1, 2, 3), attenuation=(1, 0.5, 0.25), ambient=(0.1, 0.2, 0.3))
    assert p.attenuation == (1.0, 0.5, 0.25)
    assert p.ambient == pytest.approx((0.1, 0.2, 0.3))
    assert sl.PointLight((0, 0, 0)).attenuation == (1.0, 0.0, 0.0)
    d = sl.DirectionalLight((0, -1, 0), ambient=(0.5, 0.5, 0.5))
    assert d.ambient == (0.5, 0.5, 0.5)
    m = sl.Material(emission=(0.25, 0.0, 0.5))
    assert m.emission == (0.25, 0.0, 0.5)
    assert sl.Material.preset("gold").emission == (0.0, 0.0, 0.0)
    assert m != sl.Material()


def test_emission_alone_lights_an_unlit_scene():
    """No lights, no ambient: the image is exactly the emission colour where covered."""
    v = np.array([[-5, -5, -3], [5, -5, -3], [5, 5, -3], [-5, 5, -3]], float)
    s = sl.Scene(ambient=(0, 0, 0), default_lights=False)
    s.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=sl.Material(emission=(0.25, 0.5, 1.0)))
    img = sl.render(s, sl.Camera.look_at((0, 0, 0), (0, 0, -1)), 16, 12, dtype="float32")
    np.testing.assert_array_equal(img, np.broadcast_to([0.25, 0.5, 1.0], img.shape))


def test_spot_light_round_trip_and_cone():
    s = sl.SpotLight((0, 0, 2), (0, 0, -3), cutoff=30.0, exponent=2.0, inner=20.0)
    assert s.direction == (0.0, 0.0, -1.0)
    assert (s.cutoff, s.exponent, s.inner) == (30.0, 2.0, 20.0)
    assert sl.SpotLight((0, 0, 2), (0, 0, -1)).inner is None
    # A lit disc on a floor: radius 2·tan(30°) = 1.155 around the spot's foot.
    v = np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], float)
    scene = sl.Scene(ambient=(0, 0, 0))
    scene.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=sl.Material(specular=(0, 0, 0)))
    scene.add_light(sl.SpotLight((0, 0, 2), (0, 0, -1), cutoff=30.0))
    cam = sl.Camera.orthographic((0, 0, 5), (0, 0, 0), height=6.0)
    img = sl.render(scene, cam, 120, 120, dtype="float32")
    lit = img[..., 0] > 0
    area = lit.sum() * (6.0 / 120) ** 2
    assert abs(area - np.pi * (2 * np.tan(np.radians(30))) ** 2) < 0.05


def test_fog_round_trip_and_hand_computed_blend():
    f = sl.Fog("linear", start=2.0, end=6.0, color=(1.0, 0.5, 0.0))
    assert (f.mode, f.start, f.end, f.density) == ("linear", 2.0, 6.0, None)
    assert f.factor(3.0) == 0.75 and f.factor(1.0) == 1.0 and f.factor(9.0) == 0.0
    assert sl.Fog("exp2", density=0.5).density == 0.5
    scene = sl.Scene(ambient=(1, 1, 1), fog=f)
    assert scene.fog is not None and scene.fog.end == 6.0
    # An unlit white wall at distance 3 straight ahead: f = 0.75 at the centre pixel.
    v = np.array([[-9, -9, -3], [9, -9, -3], [9, 9, -3], [-9, 9, -3]], float)
    white = sl.Material(ambient=(1, 1, 1), diffuse=(0, 0, 0), specular=(0, 0, 0))
    scene.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=white)
    cam = sl.Camera.orthographic((0, 0, 0), (0, 0, -1), height=2.0, near=0.5, far=10)
    for mode in ("flat", "gouraud", "phong"):
        img = sl.render(scene, cam, 8, 8, shading=mode, dtype="float32")
        # Orthographic: the pixel at (x, y) sees the wall at distance sqrt(3² + x_e² + y_e²).
        xe = (np.arange(8) + 0.5) / 8 * 2 - 1
        d = np.sqrt(9 + xe[None, :] ** 2 + xe[:, None] ** 2)
        fog_f = np.clip((6 - d) / 4, 0, 1)
        want = fog_f[..., None] * 1 + (1 - fog_f[..., None]) * np.array([1.0, 0.5, 0.0])
        np.testing.assert_allclose(img, want, atol=2e-6)
    scene.fog = None
    assert scene.fog is None
    assert (sl.render(scene, cam, 8, 8, dtype="float32") == 1).all()


def test_two_sided_and_local_viewer_flags():
    s = sl.Scene()
    assert (s.two_sided, s.local_viewer) == (False, True)
    s.two_sided, s.local_viewer = True, False
    assert (s.two_sided, s.local_viewer) == (True, False)
    assert sl.Scene(two_sided=True).two_sided
    # A clockwise (back-facing) wall lit from the front: dark one-sided, lit two-sided.
    v = np.array([[-9, -9, -3], [-9, 9, -3], [9, 9, -3], [9, -9, -3]], float)  # clockwise
    m = sl.Material(ambient=(0, 0, 0), diffuse=(1, 1, 1), specular=(0, 0, 0))
    for mode in ("flat", "gouraud", "phong"):
        out = []
        for two in (False, True):
            scene = sl.Scene(ambient=(0, 0, 0), two_sided=two)
            scene.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=m)
            scene.add_light(sl.DirectionalLight((0, 0, -1)))
            out.append(sl.render(scene, sl.Camera.look_at((0, 0, 0), (0, 0, -1)), 8, 8))
        assert (out[0] == 0).all() and (out[1] == 255).all(), mode


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


def test_area_light_getters_points_and_repr():
    a = sl.AreaLight((0, 2, 0), (2, 0, 0), (0, 0, 1), samples=3, color=(1, 0.5, 0.25))
    assert (a.position, a.u, a.v) == ((0.0, 2.0, 0.0), (2.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    assert (a.shape, a.samples, a.n_points, a.one_sided) == ("rectangle", 3, 9, False)
    assert a.normal == (0.0, -1.0, 0.0)  # u x v = x x z = -y
    assert (a.color, a.intensity) == ((1.0, 0.5, 0.25), 1.0)
    assert (a.attenuation, a.ambient) == ((1.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    assert sl.AreaLight((0, 0, 0), (1, 0, 0), (0, 1, 0)).samples == 4
    pts = a.points()
    assert pts.shape == (9, 3) and pts.dtype == np.float32
    # Cell centres of a 3 x 3 grid over [-1, 1] x [-0.5, 0.5], u fastest.
    xs, zs = np.array([-2, 0, 2]) / 3, np.array([-1, 0, 1]) / 3
    want = np.array([[x, 2.0, z] for z in zs for x in xs], np.float32)
    np.testing.assert_allclose(pts, want, atol=1e-7)
    disk = sl.AreaLight((1, 1, 1), (2, 0, 0), (0, 2, 0), shape="disk", samples=8, one_sided=True)
    d = disk.points() - np.float32(1)
    assert disk.shape == "disk" and disk.one_sided
    assert d.shape == (64, 3) and np.all(d[:, 2] == 0)
    assert np.all(np.hypot(d[:, 0], d[:, 1]) <= 1 + 1e-6)
    assert "AreaLight(" in repr(disk) and "disk" in repr(disk)
    assert sl.MAX_AREA_SAMPLES == 64


def _floor_scene(light):
    v = np.array([[-4, 0, -4], [4, 0, -4], [4, 0, 4], [-4, 0, 4]], float)
    scene = sl.Scene(ambient=(0, 0, 0))
    scene.add(sl.Mesh(v, [[0, 2, 1], [0, 3, 2]]), material=sl.Material.preset("jade"))
    scene.add_light(light)
    return scene


def test_area_light_of_one_sample_is_its_centre_point_light():
    cam = sl.Camera.look_at((0, 5, 6), (0, 0, 0))
    kw = dict(color=(0.9, 0.8, 0.7), intensity=2.0, attenuation=(1, 0.2, 0.1), ambient=(0.1,) * 3)
    area = sl.AreaLight((0.5, 2, 0), (3, 0, 0), (0, 0, 3), samples=1, **kw)
    point = sl.PointLight((0.5, 2, 0), **kw)
    for shading in ("flat", "gouraud", "phong"):
        a = sl.render(_floor_scene(area), cam, 64, 48, shading=shading, dtype="float32")
        b = sl.render(_floor_scene(point), cam, 64, 48, shading=shading, dtype="float32")
        np.testing.assert_array_equal(a, b)
    frame = sl.render_frame(_floor_scene(area), cam, 8, 8)
    assert frame["stats"]["light_sources"] == 1
    big = sl.AreaLight((0.5, 2, 0), (3, 0, 0), (0, 0, 3), samples=7)
    assert sl.render_frame(_floor_scene(big), cam, 8, 8)["stats"]["light_sources"] == 49


def test_area_light_total_light_does_not_depend_on_samples():
    """Far from a small light, every sample count gives the point light's image (the points
    share the colour); close to a large one, the sampled lights converge as samples grow."""
    cam = sl.Camera.look_at((0, 5, 6), (0, 0, 0))
    far = sl.render(_floor_scene(sl.PointLight((0, 200, 0))), cam, 32, 24, dtype="float32")
    for n in (2, 5, 9):
        small = sl.AreaLight((0, 200, 0), (0.01, 0, 0), (0, 0, 0.01), samples=n)
        img = sl.render(_floor_scene(small), cam, 32, 24, dtype="float32")
        np.testing.assert_allclose(img, far, rtol=1e-4, atol=1e-6)
    big = [
        sl.render(
            _floor_scene(sl.AreaLight((0, 1, 0), (4, 0, 0), (0, 0, 4), samples=n)),
            cam,
            32,
            24,
            dtype="float32",
        )
        for n in (4, 16, 32)
    ]
    assert np.abs(big[2] - big[1]).max() < np.abs(big[1] - big[0]).max()


def test_one_sided_area_light_is_dark_behind():
    cam = sl.Camera.look_at((0, 5, 6), (0, 0, 0))
    # u x v = z x x = +y: emits upward, away from the floor below it.
    up = sl.AreaLight((0, 1, 0), (0, 0, 1), (1, 0, 0), one_sided=True)
    assert up.normal == (0.0, 1.0, 0.0)
    img = sl.render(_floor_scene(up), cam, 32, 24, dtype="float32")
    emission = np.zeros(3, np.float32)
    assert np.all(img == emission)
    down = sl.AreaLight((0, 1, 0), (1, 0, 0), (0, 0, 1), one_sided=True)
    both = sl.AreaLight((0, 1, 0), (1, 0, 0), (0, 0, 1))
    lit = sl.render(_floor_scene(down), cam, 32, 24, dtype="float32")
    full = sl.render(_floor_scene(both), cam, 32, 24, dtype="float32")
    # The cosine fall-off only dims: lit somewhere, never brighter than two-sided.
    assert lit.max() > 0 and np.all(lit <= full + 1e-6)


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

    scene = sl.Scene(ambient=(0, 0, 0), default_lights=False)
    assert scene.add_obj(path) == 4
    assert scene.n_objects == 4
    cam = sl.Camera.orthographic((3.5, 0.5, 5), (3.5, 0.5, 0), height=1.2)
    img = sl.render(scene, cam, 160, 24, dtype="float32")  # no lights: emission only
    np.testing.assert_allclose(img[12, 140], [0.2, 0.2, 0.9], atol=1e-6)  # the glow quad
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


def test_light_diffuse_and_specular_colours_split_the_shorthand():
    """Hand-computed: n = l = v = +z, so n·l = n·h = 1 and c = kd·Id + ks·Is."""
    v = np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], float)
    mat = sl.Material(ambient=(0, 0, 0), diffuse=(0.5, 0.5, 0.5), specular=(0.25,) * 3)
    cam = sl.Camera.orthographic((0, 0, 5), (0, 0, 0), height=2.0)
    lights = [
        sl.DirectionalLight((0, 0, -1), intensity=2.0, diffuse=(1, 0, 0), specular=(0, 0, 1)),
        sl.PointLight((0, 0, 1e4), intensity=2.0, diffuse=(1, 0, 0), specular=(0, 0, 1)),
        sl.SpotLight((0, 0, 1e4), (0, 0, -1), intensity=2.0, diffuse=(1, 0, 0), specular=(0, 0, 1)),
        sl.AreaLight(
            (0, 0, 1e4), (1, 0, 0), (0, 1, 0), intensity=2.0, diffuse=(1, 0, 0), specular=(0, 0, 1)
        ),
    ]
    for light in lights:
        assert (light.diffuse, light.specular) == ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0))
        assert light.color == (1.0, 1.0, 1.0)
        s = sl.Scene(ambient=(0, 0, 0), local_viewer=False)  # v = +z everywhere
        s.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=mat)
        s.add_light(light)
        img = sl.render(s, cam, 4, 4, shading="phong", dtype="float32")
        np.testing.assert_allclose(img[1, 1], [1.0, 0.0, 0.5], atol=2e-5)
    # Only one of the two set: the other follows color.
    d = sl.DirectionalLight((0, 0, -1), color=(0, 1, 0), specular=(1, 1, 1))
    assert (d.diffuse, d.specular) == (None, (1.0, 1.0, 1.0))
