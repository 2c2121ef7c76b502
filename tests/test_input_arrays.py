"""Input arrays: dtypes, memory layouts, strided and read-only arrays, nested lists."""

from __future__ import annotations

import numpy as np
import pytest
import shadelab_rs as sl


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


@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
def test_given_normals_need_not_be_unit(sphere_arrays, camera, shading):
    """Normals are normalised before use (after the model transform), so scaling them by 2
    (exact in binary floating point) changes nothing."""
    v, f = sphere_arrays
    n = sl.Mesh(v, f).normals.astype(np.float64)
    a = render_mesh(sl.Mesh(v, f, normals=n), camera, shading=shading)
    b = render_mesh(sl.Mesh(v, f, normals=2 * n), camera, shading=shading)
    assert_same_render(a, b)
