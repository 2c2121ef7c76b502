"""Every error path: bad values raise ValueError / TypeError / FileNotFoundError / OSError (or
``sl.ObjParseError``, a ValueError) with a message naming the problem, never a Rust panic.

All checks go through :func:`expect_error`, which catches ``BaseException`` so that a pyo3
``PanicException`` (a ``BaseException`` that ``except Exception`` misses) fails the test with
a clear message instead of escaping.
"""

from __future__ import annotations

import re
import time

import numpy as np
import pytest
import shadelab_rs as sl

NAN, INF = float("nan"), float("inf")
TRI_V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
TRI_F = np.array([[0, 1, 2]])
EYE, TARGET = (0.0, 0.0, 3.0), (0.0, 0.0, 0.0)


def expect_error(exc_type, match, fn, *args, **kwargs):
    """Calls ``fn(*args, **kwargs)``; asserts it raises ``exc_type`` (never a pyo3 panic)
    whose message contains the regular expression ``match``. Returns the exception."""
    try:
        fn(*args, **kwargs)
    except BaseException as e:  # a PanicException is a BaseException
        assert type(e).__name__ != "PanicException", f"Rust panic escaped: {e!r}"
        assert isinstance(e, exc_type), f"expected {exc_type}, got {type(e).__name__}: {e}"
        assert re.search(match, str(e)), f"message {str(e)!r} does not match {match!r}"
        return e
    raise AssertionError(f"no exception from {fn.__qualname__}{args}{kwargs}")


def tri_scene(**add_kw):
    scene = sl.Scene()
    scene.add(sl.Mesh(TRI_V, TRI_F), **add_kw)
    scene.add_light(sl.DirectionalLight((0, 0, -1)))
    return scene


CAM = sl.Camera.look_at(EYE, TARGET)


def test_expect_error_sees_through_base_exceptions():
    """The helper itself: it reports a BaseException of the wrong type as a failure."""

    class PanicException(BaseException):  # same name as pyo3's
        pass

    def boom():
        raise PanicException("called `Option::unwrap()` on a `None` value")

    with pytest.raises(AssertionError, match="Rust panic escaped"):
        expect_error(ValueError, "", boom)
    with pytest.raises(AssertionError, match="no exception"):
        expect_error(ValueError, "", lambda: None)


# --------------------------------------------------------------------------------------------
# Non-finite numbers: every float input, with the offending element named
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("bad", [NAN, INF, -INF, 1e39])
def test_non_finite_vertices(bad):
    v = TRI_V.copy()
    v[1, 2] = bad
    expect_error(ValueError, r"vertices\[1, 2\]", sl.Mesh, v, TRI_F)
    v32 = TRI_V.astype(np.float32)
    v32[2, 0] = np.float32(bad) if abs(bad) < 1e38 else np.float32(bad / abs(bad) * INF)
    expect_error(ValueError, r"vertices\[2, 0\]", sl.Mesh, v32, TRI_F)


@pytest.mark.parametrize("bad", [NAN, INF, -INF])
def test_non_finite_normals_and_uvs(bad):
    n = np.tile([0.0, 0.0, 1.0], (3, 1))
    n[2, 1] = bad
    expect_error(ValueError, r"normals\[2, 1\]", sl.Mesh, TRI_V, TRI_F, normals=n)
    uv = np.zeros((3, 2))
    uv[0, 1] = bad
    expect_error(ValueError, r"uvs\[0, 1\]", sl.Mesh, TRI_V, TRI_F, uvs=uv)


@pytest.mark.parametrize("bad", [NAN, INF, 1e39])
def test_non_finite_transform(bad):
    t = np.eye(4)
    t[2, 3] = bad
    mesh = sl.Mesh(TRI_V, TRI_F)
    expect_error(ValueError, r"transform\[2, 3\]", sl.Scene().add, mesh, transform=t)


@pytest.mark.parametrize("bad", [NAN, INF, -INF])
@pytest.mark.parametrize("factory", [sl.Camera.look_at, sl.Camera.orthographic])
def test_non_finite_camera_vectors(factory, bad):
    expect_error(ValueError, r"eye\[2\]", factory, (0, 0, bad), TARGET)
    expect_error(ValueError, r"target\[0\]", factory, EYE, (bad, 0, 0))
    expect_error(ValueError, r"up\[1\]", factory, EYE, TARGET, up=(0, bad, 0))


@pytest.mark.parametrize("bad", [NAN, INF, -INF])
def test_non_finite_camera_scalars(bad):
    expect_error(ValueError, "fov_y", sl.Camera.look_at, EYE, TARGET, fov_y=bad)
    expect_error(ValueError, "near", sl.Camera.look_at, EYE, TARGET, near=bad)
    expect_error(ValueError, "far", sl.Camera.look_at, EYE, TARGET, far=bad)
    expect_error(ValueError, "height", sl.Camera.orthographic, EYE, TARGET, height=bad)
    expect_error(ValueError, "near", sl.Camera.orthographic, EYE, TARGET, near=bad)
    expect_error(ValueError, "far", sl.Camera.orthographic, EYE, TARGET, far=bad)


@pytest.mark.parametrize("bad", [NAN, INF, -INF])
def test_non_finite_lights(bad):
    expect_error(ValueError, r"direction\[1\]", sl.DirectionalLight, (0, bad, 0))
    expect_error(ValueError, r"color\[2\]", sl.DirectionalLight, (0, -1, 0), color=(1, 1, bad))
    expect_error(ValueError, "intensity", sl.DirectionalLight, (0, -1, 0), intensity=bad)
    expect_error(ValueError, r"position\[0\]", sl.PointLight, (bad, 0, 0))
    expect_error(ValueError, r"color\[0\]", sl.PointLight, (0, 1, 0), color=(bad, 1, 1))
    expect_error(ValueError, "intensity", sl.PointLight, (0, 1, 0), intensity=bad)


@pytest.mark.parametrize("bad", [NAN, INF, -INF])
def test_non_finite_material_scene_background(bad):
    expect_error(ValueError, r"ambient\[0\]", sl.Material, ambient=(bad, 0, 0))
    expect_error(ValueError, r"diffuse\[1\]", sl.Material, diffuse=(0, bad, 0))
    expect_error(ValueError, r"specular\[2\]", sl.Material, specular=(0, 0, bad))
    if bad != INF:  # +inf is the perfect mirror (tests/test_lecture.py)
        expect_error(ValueError, "shininess", sl.Material, shininess=bad)
    expect_error(ValueError, r"ambient\[1\]", sl.Scene, ambient=(0, bad, 0))
    expect_error(
        ValueError, r"background\[2\]", sl.render, tri_scene(), CAM, 8, 8, background=(0, 0, bad)
    )


def test_negative_material_light_and_ambient_values():
    expect_error(ValueError, "ambient", sl.Material, ambient=(-0.1, 0, 0))
    expect_error(ValueError, "diffuse", sl.Material, diffuse=(0, -0.1, 0))
    expect_error(ValueError, "specular", sl.Material, specular=(0, 0, -0.1))
    expect_error(ValueError, "shininess", sl.Material, shininess=-1.0)
    expect_error(ValueError, "color", sl.DirectionalLight, (0, -1, 0), color=(1, -1, 1))
    expect_error(ValueError, "intensity", sl.DirectionalLight, (0, -1, 0), intensity=-1.0)
    expect_error(ValueError, "color", sl.PointLight, (0, 1, 0), color=(-1, 1, 1))
    expect_error(ValueError, "intensity", sl.PointLight, (0, 1, 0), intensity=-0.5)
    expect_error(ValueError, "ambient", sl.Scene, ambient=(-1, 0, 0))


def test_light_intensity_overflowing_float32():
    expect_error(ValueError, "intensity", sl.DirectionalLight, (0, -1, 0), intensity=1e39)


# --------------------------------------------------------------------------------------------
# Shapes
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "vertices",
    [np.zeros((3, 2)), np.zeros((3, 4)), np.zeros(9), np.zeros((3, 3, 1)), np.float64(1.0)],
)
def test_vertices_wrong_shape(vertices):
    expect_error(ValueError, r"vertices must have shape \(N, 3\)", sl.Mesh, vertices, TRI_F)


@pytest.mark.parametrize(
    "faces", [np.zeros((1, 2), int), np.zeros((1, 4), int), np.zeros(3, int), np.int64(0)]
)
def test_faces_wrong_shape(faces):
    expect_error(ValueError, r"faces must have shape \(M, 3\)", sl.Mesh, TRI_V, faces)


def test_normals_and_uvs_wrong_shape():
    expect_error(
        ValueError,
        r"normals must have shape \(N, 3\)",
        sl.Mesh,
        TRI_V,
        TRI_F,
        normals=np.zeros((3, 2)),
    )
    expect_error(
        ValueError, r"normals.*2 rows.*3 vertices", sl.Mesh, TRI_V, TRI_F, normals=np.zeros((2, 3))
    )
    expect_error(
        ValueError, r"uvs must have shape \(N, 2\)", sl.Mesh, TRI_V, TRI_F, uvs=np.zeros((3, 3))
    )
    expect_error(
        ValueError, r"uvs.*4 rows.*3 vertices", sl.Mesh, TRI_V, TRI_F, uvs=np.zeros((4, 2))
    )


def test_ragged_vertices():
    expect_error(TypeError, "vertices", sl.Mesh, [[0, 0, 0], [1, 0]], TRI_F)


@pytest.mark.parametrize("t", [np.eye(3), np.eye(4)[:3], np.zeros((4, 4, 1)), np.ones(16)])
def test_transform_wrong_shape(t):
    expect_error(
        ValueError,
        r"transform must have shape \(4, 4\)",
        sl.Scene().add,
        sl.Mesh(TRI_V, TRI_F),
        transform=t,
    )


@pytest.mark.parametrize("vec", [(0, 0), (0, 0, 0, 1), [[0, 0, 3]], ()])
def test_three_vectors_wrong_length(vec):
    expect_error(ValueError, "eye must be 3 numbers", sl.Camera.look_at, vec, TARGET)
    expect_error(ValueError, "target must be 3 numbers", sl.Camera.orthographic, EYE, vec)
    expect_error(ValueError, "up must be 3 numbers", sl.Camera.look_at, EYE, TARGET, up=vec)
    expect_error(ValueError, "direction must be 3 numbers", sl.DirectionalLight, vec)
    expect_error(ValueError, "position must be 3 numbers", sl.PointLight, vec)
    expect_error(ValueError, "color must be 3 numbers", sl.PointLight, EYE, color=vec)
    expect_error(ValueError, "ambient must be 3 numbers", sl.Material, ambient=vec)
    expect_error(ValueError, "ambient must be 3 numbers", sl.Scene, ambient=vec)
    expect_error(
        ValueError,
        "background must be 3 numbers",
        sl.render,
        tri_scene(),
        CAM,
        8,
        8,
        background=vec,
    )


# --------------------------------------------------------------------------------------------
# Types
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("dtype", [bool, complex, object, str, "datetime64[s]", "V8"])
def test_vertices_bad_dtype(dtype):
    v = TRI_V.astype(dtype) if dtype not in ("datetime64[s]", "V8") else np.zeros((3, 3), dtype)
    e = expect_error(TypeError, "vertices", sl.Mesh, v, TRI_F)
    assert "dtype" in str(e)


@pytest.mark.parametrize("dtype", [bool, complex, object, str])
def test_normals_uvs_bad_dtype(dtype):
    n = np.ones((3, 3)).astype(dtype)
    expect_error(TypeError, "normals", sl.Mesh, TRI_V, TRI_F, normals=n)
    expect_error(TypeError, "uvs", sl.Mesh, TRI_V, TRI_F, uvs=np.ones((3, 2)).astype(dtype))


@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.float64, bool, complex, object])
def test_faces_non_integer_dtype(dtype):
    expect_error(TypeError, "faces must be an integer array", sl.Mesh, TRI_V, TRI_F.astype(dtype))


def test_non_numeric_vector_arguments():
    expect_error(TypeError, "eye", sl.Camera.look_at, "abc", TARGET)
    expect_error(TypeError, "eye", sl.Camera.look_at, None, TARGET)
    expect_error(TypeError, "direction", sl.DirectionalLight, "down")
    expect_error(TypeError, "color", sl.PointLight, (0, 0, 0), color="white")
    expect_error(
        TypeError, "transform", sl.Scene().add, sl.Mesh(TRI_V, TRI_F), transform="identity"
    )
    expect_error(TypeError, "fov_y", sl.Camera.look_at, EYE, TARGET, fov_y="wide")


def test_wrong_object_types():
    mesh = sl.Mesh(TRI_V, TRI_F)
    scene = sl.Scene()
    expect_error(TypeError, "mesh", scene.add, "mesh")
    # A (V, F) pair and a preset name are accepted; other types are named in the error.
    expect_error(TypeError, "pair", scene.add, (TRI_V,))
    expect_error(TypeError, "material", scene.add, mesh, material=3)
    expect_error(ValueError, "unobtainium", scene.add, mesh, material="unobtainium")
    expect_error(
        TypeError, "DirectionalLight, PointLight, SpotLight or AreaLight", scene.add_light, "sun"
    )
    expect_error(
        TypeError, "DirectionalLight, PointLight, SpotLight or AreaLight", scene.add_light, None
    )
    expect_error(
        TypeError, "DirectionalLight, PointLight, SpotLight or AreaLight", scene.add_light, mesh
    )
    expect_error(TypeError, "scene", sl.render, None, CAM)
    expect_error(TypeError, "camera", sl.render, scene, "camera")
    expect_error(TypeError, "camera", sl.render, scene, (EYE, TARGET))
    expect_error(TypeError, "name", sl.Material.preset, 5)
    expect_error(TypeError, "width", sl.render, scene, CAM, width=10.5)
    expect_error(TypeError, "height", sl.render, scene, CAM, height="600")
    expect_error(TypeError, "threads", sl.render, scene, CAM, 8, 8, threads=1.5)
    expect_error(TypeError, "shading", sl.render, scene, CAM, 8, 8, shading=None)
    expect_error(TypeError, "specular", sl.render, scene, CAM, 8, 8, specular=1)


# --------------------------------------------------------------------------------------------
# Face indices and empty meshes
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("faces", "message"),
    [
        (np.array([[0, 1, 3]]), r"faces\[0, 2\] = 3 is out of range for 3 vertices"),
        (np.array([[0, 1, 2], [0, -1, 2]]), r"faces\[1, 1\] = -1 is out of range"),
        (np.array([[0, 1, 2], [2, 1, 0], [9, 0, 0]]), r"faces\[2, 0\] = 9 is out of range"),
        (np.array([[-(2**63), 1, 2]]), r"faces\[0, 0\] = -9223372036854775808 is out of range"),
        (np.array([[0, 1, 2**64 - 1]], np.uint64), r"faces\[0, 2\] = 18446744073709551615"),
        (np.array([[0, 1, 2**32]], np.int64), r"faces\[0, 2\] = 4294967296 is out of range"),
        (np.array([[0, 1, -1]], np.int8), r"faces\[0, 2\] = -1 is out of range"),
        (np.array([[0, 1, 255]], np.uint8), r"faces\[0, 2\] = 255 is out of range"),
    ],
)
def test_face_index_out_of_range(faces, message):
    expect_error(ValueError, message, sl.Mesh, TRI_V, faces)


def test_empty_meshes():
    expect_error(ValueError, "no vertices", sl.Mesh, np.zeros((0, 3)), np.zeros((0, 3), int))
    expect_error(ValueError, "no triangles", sl.Mesh, TRI_V, np.zeros((0, 3), int))
    # An empty list has NumPy's default dtype float64; it still means "no triangles".
    expect_error(ValueError, "no triangles", sl.Mesh, TRI_V, [])
    expect_error(ValueError, "vertices", sl.Mesh, [], TRI_F)


# --------------------------------------------------------------------------------------------
# Cameras, lights, transforms that describe nothing
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("factory", [sl.Camera.look_at, sl.Camera.orthographic])
def test_degenerate_camera_frames(factory):
    expect_error(ValueError, "eye and target", factory, (1, 2, 3), (1, 2, 3))
    expect_error(ValueError, "up", factory, (0, 5, 0), (0, 0, 0))  # up parallel to view
    expect_error(ValueError, "up", factory, (0, -5, 0), (0, 0, 0), up=(0, 1, 0))
    expect_error(ValueError, "up", factory, EYE, TARGET, up=(0, 0, 0))
    expect_error(ValueError, "up", factory, EYE, TARGET, up=(0, 0, 2.5))


@pytest.mark.parametrize("fov", [0.0, -10.0, 180.0, 270.0])
def test_bad_field_of_view(fov):
    expect_error(
        ValueError, r"fov_y must be in \(0, 180\)", sl.Camera.look_at, EYE, TARGET, fov_y=fov
    )


@pytest.mark.parametrize(("near", "far"), [(0.0, 10.0), (-1.0, 10.0), (5.0, 5.0), (5.0, 1.0)])
def test_bad_perspective_depth_range(near, far):
    expect_error(ValueError, "near", sl.Camera.look_at, EYE, TARGET, near=near, far=far)


def test_bad_orthographic_camera():
    expect_error(ValueError, "height", sl.Camera.orthographic, EYE, TARGET, height=0.0)
    expect_error(ValueError, "height", sl.Camera.orthographic, EYE, TARGET, height=-2.0)
    expect_error(ValueError, "near", sl.Camera.orthographic, EYE, TARGET, near=3.0, far=3.0)
    expect_error(ValueError, "near", sl.Camera.orthographic, EYE, TARGET, near=4.0, far=1.0)


def test_zero_light_direction():
    expect_error(ValueError, "direction", sl.DirectionalLight, (0, 0, 0))
    expect_error(ValueError, "direction", sl.DirectionalLight, np.zeros(3, np.float32))


@pytest.mark.parametrize(
    "t",
    [
        np.diag([1.0, 1.0, 0.0, 1.0]),  # flattens z
        np.diag([0.0, 0.0, 0.0, 1.0]),
        np.array([[1, 2, 0, 0], [2, 4, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]),  # rank 2
    ],
)
def test_singular_transform(t):
    expect_error(ValueError, "singular", sl.Scene().add, sl.Mesh(TRI_V, TRI_F), transform=t)


def test_projective_transform():
    t = np.eye(4)
    t[3, 2] = 1.0
    expect_error(ValueError, "affine", sl.Scene().add, sl.Mesh(TRI_V, TRI_F), transform=t)


def test_a_failed_add_leaves_the_scene_unchanged():
    scene = tri_scene()
    expect_error(
        ValueError,
        "singular",
        scene.add,
        sl.Mesh(TRI_V, TRI_F),
        transform=np.diag([0.0, 0.0, 0.0, 1.0]),
    )
    assert (scene.n_objects, scene.n_triangles) == (1, 1)


# --------------------------------------------------------------------------------------------
# render options
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("width", "height", "name"),
    [
        (0, 10, "width"),
        (10, 0, "height"),
        (-1, 10, "width"),
        (10, -5, "height"),
        (sl.MAX_IMAGE_SIZE + 1, 10, "width"),
        (10, sl.MAX_IMAGE_SIZE + 1, "height"),
        (2**40, 1, "width"),
        (1, -(2**40), "height"),
    ],
)
def test_bad_image_size(width, height, name):
    for fn in (sl.render, sl.render_frame):
        e = expect_error(ValueError, name, fn, tri_scene(), CAM, width=width, height=height)
        assert f"1 and {sl.MAX_IMAGE_SIZE}" in str(e)


def test_huge_image_fails_fast_before_allocating():
    """200000 x 200000 (120 GB of uint8) is rejected by the size check, not by the allocator."""
    t0 = time.perf_counter()
    for dtype in ("uint8", "float32"):
        expect_error(
            ValueError,
            "width",
            sl.render,
            tri_scene(),
            CAM,
            width=200_000,
            height=200_000,
            dtype=dtype,
            return_depth=True,
        )
    assert time.perf_counter() - t0 < 1.0


def test_unknown_shading_and_specular():
    e = expect_error(ValueError, "toon", sl.render, tri_scene(), CAM, 8, 8, shading="toon")
    assert "shading" in str(e) and "phong" in str(e)
    e = expect_error(ValueError, "cook", sl.render, tri_scene(), CAM, 8, 8, specular="cook")
    assert "specular" in str(e) and "blinn" in str(e)
    expect_error(ValueError, "shading", sl.render_frame, tri_scene(), CAM, 8, 8, shading="")


@pytest.mark.parametrize("threads", [0, -1, -(2**40), 10**6])
def test_bad_thread_count(threads):
    expect_error(ValueError, "threads", sl.render, tri_scene(), CAM, 8, 8, threads=threads)


@pytest.mark.parametrize("dtype", ["float64", "uint16", np.int32, object, "bogus", 1.5])
def test_bad_output_dtype(dtype):
    expect_error((ValueError, TypeError), "dtype", sl.render, tri_scene(), CAM, 8, 8, dtype=dtype)


def test_unknown_preset():
    e = expect_error(ValueError, "unobtainium", sl.Material.preset, "unobtainium")
    for name in sl.Material.preset_names():
        assert name in str(e)  # the message lists the valid names
    expect_error(ValueError, "preset", sl.Material.preset, "")


# --------------------------------------------------------------------------------------------
# Files
# --------------------------------------------------------------------------------------------

LOADERS = [sl.load_obj, sl.load_obj_parts, sl.load_mesh]


@pytest.mark.parametrize("load", LOADERS)
def test_missing_file(load, tmp_path):
    path = tmp_path / "nope.obj"
    e = expect_error(FileNotFoundError, "nope.obj", load, path)
    assert str(tmp_path) in str(e)
    expect_error(FileNotFoundError, "nope.obj", load, str(path))


def test_missing_non_obj_file(tmp_path):
    expect_error(FileNotFoundError, "nope.stl", sl.load_mesh, tmp_path / "nope.stl")


@pytest.mark.parametrize("load", LOADERS)
def test_directory(load, tmp_path):
    d = tmp_path / "dir.obj"
    d.mkdir()
    expect_error(OSError, "dir.obj", load, d)


def _write(tmp_path, name, content):
    p = tmp_path / name
    if isinstance(content, bytes):
        p.write_bytes(content)
    else:
        p.write_text(content)
    return p


TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"

BAD_OBJS = {
    # name: (content, regular expression the message must contain after "<path>")
    "empty.obj": ("", r": the file contains no triangles"),
    "comments.obj": ("# nothing here\n\n", r": the file contains no triangles"),
    "no_faces.obj": (TRIANGLE_OBJ, r": the file contains no triangles"),
    "garbage.obj": (bytes(range(256)) * 8, r": "),
    "truncated_vertex.obj": (TRIANGLE_OBJ + "f 1 2 3\nv 1 2", r":5: .*vertex"),
    "bad_number.obj": ("v 0 0 0\nv 1 0 0\nv 0 abc 0\nf 1 2 3\n", r":3: .*vertex"),
    "index_too_big.obj": (TRIANGLE_OBJ + "f 1 2 4\n", r":4: face vertex index out of range"),
    "index_zero.obj": (TRIANGLE_OBJ + "f 1 2 0\n", r":4: face vertex index out of range"),
    "index_negative.obj": (TRIANGLE_OBJ + "f 1 2 -4\n", r":4: face vertex index out of range"),
    "bad_face.obj": (TRIANGLE_OBJ + "f 1 2 3\nf 1 x 3\n", r":5: malformed face"),
    "bad_normal_index.obj": (TRIANGLE_OBJ + "vn 0 0 1\nf 1//1 2//1 3//7\n", r":5: .*normal"),
    "nan_vertex.obj": ("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", r": .*vertex 1 .*non-finite"),
    # Faces with missing indices (fewer than three) were silently dropped by the parser.
    "two_index_face.obj": (
        TRIANGLE_OBJ + "f 1 2 3\nf 1 2\n",
        r":5: face with 2 vertex indices; a face needs at least 3",
    ),
    "one_index_face.obj": (TRIANGLE_OBJ + "f 3\nf 1 2 3\n", r":4: face with 1 vertex indices"),
    "empty_face.obj": (TRIANGLE_OBJ + "f\n", r":4: face with 0 vertex indices"),
    "truncated_face.obj": (TRIANGLE_OBJ + "f 1 2", r":4: face with 2 vertex indices"),
}


@pytest.mark.parametrize("load", LOADERS)
@pytest.mark.parametrize("name", list(BAD_OBJS))
def test_malformed_obj(tmp_path, name, load):
    content, message = BAD_OBJS[name]
    path = _write(tmp_path, name, content)
    e = expect_error(sl.ObjParseError, re.escape(str(path)) + message, load, path)
    assert isinstance(e, ValueError)


def _obj_triangles(mesh):
    return mesh.vertices[mesh.faces].tolist()


def test_obj_polygons_and_relative_indices_load_as_documented(tmp_path):
    """A pentagon given with negative (relative) indices is fan-triangulated in order."""
    pts = [[0, 0, 0], [2, 0, 0], [3, 1, 0], [1, 2, 0], [-1, 1, 0]]
    text = "".join(f"v {x} {y} {z}\n" for x, y, z in pts) + "f -5 -4 -3 -2 -1\n"
    mesh = sl.load_obj(_write(tmp_path, "penta.obj", text))
    p = pts
    assert _obj_triangles(mesh) == [[p[0], p[1], p[2]], [p[0], p[2], p[3]], [p[0], p[3], p[4]]]


@pytest.mark.parametrize(
    "mtl",
    [
        None,  # the MTL file named by mtllib does not exist
        "newmtl red\nKd 0.5 zero 0\n",  # malformed MTL
    ],
)
def test_obj_with_missing_or_broken_mtl_loads_the_geometry(tmp_path, mtl):
    """Documented recovery: a missing or malformed MTL leaves the part without material."""
    if mtl is not None:
        (tmp_path / "m.mtl").write_text(mtl)
    text = "mtllib m.mtl\n" + TRIANGLE_OBJ + "usemtl red\nf 1 2 3\n"
    [(_name, mesh, material)] = sl.load_obj_parts(_write(tmp_path, "x.obj", text))
    assert mesh.n_faces == 1
    assert material is None


def test_obj_whose_mtl_names_a_missing_texture_is_an_error(tmp_path):
    """A texture map the MTL names must load: no silent fallback (file and line named)."""
    (tmp_path / "m.mtl").write_text("newmtl red\nKd 0.5 0.25 0\nmap_Kd missing-texture.png\n")
    text = "mtllib m.mtl\n" + TRIANGLE_OBJ + "usemtl red\nf 1 2 3\n"
    with pytest.raises(sl.ObjParseError, match=r"m\.mtl:3: .*missing-texture\.png"):
        sl.load_obj_parts(_write(tmp_path, "x.obj", text))


def test_lighting_beyond_float32_range_is_an_error():
    """Lighting whose sum could overflow float32 is refused (it used to give inf, and NaN
    where the inf met a zero fog factor or barycentric)."""
    s = sl.Scene(ambient=(0, 0, 0), fog=sl.Fog("exp", density=100.0))
    s.add(sl.Mesh([[-1, -1, 0], [1, -1, 0], [0, 1, 0]], [[0, 1, 2]]))
    for _ in range(2):
        s.add_light(sl.DirectionalLight((0, 0, -1), intensity=3e38))
    cam = sl.Camera.look_at((0, 0, 3), (0, 0, 0))
    for shading in ("flat", "gouraud", "phong"):
        expect_error(
            ValueError,
            r"object 0: its lighting can reach .*e38, beyond the 1e37",
            sl.render,
            s,
            cam,
            8,
            8,
            shading=shading,
            dtype="float32",
        )


def test_garbage_non_obj_file(tmp_path):
    for name, content in (("junk.stl", b"\x00\x01garbage" * 20), ("empty.ply", b"")):
        path = _write(tmp_path, name, content)
        expect_error(ValueError, name, sl.load_mesh, path)


# --------------------------------------------------------------------------------------------
# Hard but valid inputs: no error, no NaN
# --------------------------------------------------------------------------------------------


def _render_all_modes(scene, cam):
    for shading in ("flat", "gouraud", "phong"):
        for specular in ("blinn", "phong"):
            out = sl.render_frame(
                scene,
                cam,
                width=24,
                height=24,
                shading=shading,
                specular=specular,
                dtype="float32",
                return_depth=True,
            )
            assert not np.isnan(out["image"]).any()
            assert not np.isnan(out["depth"]).any()
            yield out


@pytest.mark.parametrize(
    "case",
    [
        "degenerate",
        "zero_normals",
        "light_on_surface",
        "eye_in_plane",
        "huge",
        "tiny",
        "behind_eye",
        "shininess_zero",
    ],
)
# Some hard inputs draw nothing (degenerate, behind the eye): that warns, and is fine here.
@pytest.mark.filterwarnings("ignore::shadelab_rs.EmptyRenderWarning")
def test_hard_inputs_render_without_nan(case):
    v, f, normals = TRI_V, TRI_F, None
    cam = sl.Camera.look_at((0.3, 0.2, 3.0), TARGET)
    lights = [sl.DirectionalLight((-1, -1, -1)), sl.PointLight((2, 2, 2))]
    material = sl.Material.preset("gold")
    if case == "degenerate":  # collinear and repeated vertices
        v = np.array([[0, 0, 0], [1, 1, 1], [2, 2, 2.0]])
        f = np.array([[0, 1, 2], [0, 0, 1], [1, 1, 1]])
    elif case == "zero_normals":
        normals = np.zeros((3, 3))
    elif case == "light_on_surface":
        lights = [sl.PointLight((0, 0, 0)), sl.PointLight((0.25, 0.25, 0))]
    elif case == "eye_in_plane":
        cam = sl.Camera.look_at((0.25, 0.25, 0), (0.25, 0.25, -1))
    elif case == "huge":
        v = TRI_V * 1e30
    elif case == "tiny":
        v = TRI_V * 1e-30
        cam = sl.Camera.look_at((0, 0, 1e-29), TARGET, near=1e-31, far=1e-28)
    elif case == "behind_eye":
        v = TRI_V + np.array([0.0, 0.0, 10.0])
    elif case == "shininess_zero":
        material = sl.Material(shininess=0.0)
        cam = sl.Camera.look_at((0.2, 0.2, -3), (0.2, 0.2, 0))  # sees the back face
        lights = [sl.PointLight((0.2, 0.2, 1))]
    scene = sl.Scene()
    scene.add(sl.Mesh(v, f, normals=normals), material=material)
    for light in lights:
        scene.add_light(light)
    outs = list(_render_all_modes(scene, cam))
    assert len(outs) == 6


def test_huge_and_non_integer_sizes_name_the_argument():
    scene = sl.Scene()
    cam = sl.Camera.look_at((0, 0, 3), (0, 0, 0))
    expect_error(ValueError, "width must be between", sl.render, scene, cam, width=2**70)
    expect_error(ValueError, "height must be between", sl.render, scene, cam, height=-(2**70))
    expect_error(ValueError, "threads must be between", sl.render, scene, cam, 8, 8, threads=2**70)
    expect_error(TypeError, "width must be an integer", sl.render, scene, cam, width=8.0)
    expect_error(TypeError, "threads must be an integer", sl.render, scene, cam, 8, 8, threads="2")


def test_from_trimesh_rejects_non_meshes():
    expect_error(TypeError, "from_trimesh expects a trimesh.Trimesh", sl.Mesh.from_trimesh, "x")


def test_directories_are_not_mesh_files(tmp_path):
    expect_error(IsADirectoryError, "", sl.load_obj, tmp_path)
    expect_error(IsADirectoryError, "directory", sl.load_mesh, tmp_path)


def test_attenuation_ambient_and_emission_are_validated():
    expect_error(ValueError, "attenuation", sl.PointLight, (0, 0, 0), attenuation=(0, 0, 0))
    expect_error(ValueError, "attenuation", sl.PointLight, (0, 0, 0), attenuation=(1, -1, 0))
    expect_error(
        ValueError, r"attenuation\[2\]", sl.PointLight, (0, 0, 0), attenuation=(1, 0, np.inf)
    )
    expect_error(ValueError, "attenuation must be 3", sl.PointLight, (0, 0, 0), attenuation=(1, 0))
    expect_error(ValueError, "ambient", sl.PointLight, (0, 0, 0), ambient=(-1, 0, 0))
    expect_error(ValueError, "ambient", sl.DirectionalLight, (0, 0, -1), ambient=(0, np.nan, 0))
    expect_error(ValueError, "emission", sl.Material, emission=(0, -0.5, 0))
    expect_error(ValueError, r"emission\[0\]", sl.Material, emission=(np.inf, 0, 0))


def test_spot_light_parameters_are_validated():
    p, d = (0, 0, 2), (0, 0, -1)
    expect_error(ValueError, "cutoff", sl.SpotLight, p, d, cutoff=95.0)
    expect_error(ValueError, "cutoff", sl.SpotLight, p, d, cutoff=0.0)
    expect_error(ValueError, "cutoff", sl.SpotLight, p, d, cutoff=float("nan"))
    expect_error(ValueError, "exponent", sl.SpotLight, p, d, exponent=-1.0)
    expect_error(ValueError, "spot direction", sl.SpotLight, p, (0, 0, 0))
    expect_error(ValueError, "inner", sl.SpotLight, p, d, cutoff=30.0, inner=30.0)
    expect_error(ValueError, "inner", sl.SpotLight, p, d, cutoff=180.0, inner=10.0)
    expect_error(ValueError, r"position\[0\]", sl.SpotLight, (np.nan, 0, 0), d)
    expect_error(TypeError, "SpotLight", sl.Scene().add_light, "a lamp")


def test_fog_parameters_are_validated():
    expect_error(ValueError, "unknown fog mode 'fast'", sl.Fog, "fast")
    expect_error(ValueError, "start < end", sl.Fog, "linear", start=5.0, end=5.0)
    expect_error(ValueError, "start < end", sl.Fog, "linear", start=np.nan, end=5.0)
    expect_error(ValueError, "density", sl.Fog, "exp", density=-0.1)
    expect_error(ValueError, "density", sl.Fog, "exp2", density=np.inf)
    expect_error(ValueError, r"color\[1\]", sl.Fog, color=(0, np.nan, 0))
    expect_error(TypeError, "fog", sl.Scene, fog="thick")


def test_area_light_parameters_are_validated():
    p, u, v = (0, 2, 0), (1, 0, 0), (0, 0, 1)
    expect_error(ValueError, "unknown area light shape 'circle'", sl.AreaLight, p, u, v, "circle")
    expect_error(ValueError, "not parallel", sl.AreaLight, p, u, (2, 0, 0))
    expect_error(ValueError, "not parallel", sl.AreaLight, p, (0, 0, 0), v)
    expect_error(ValueError, r"u\[1\]", sl.AreaLight, p, (1, np.nan, 0), v)
    expect_error(ValueError, r"position\[2\]", sl.AreaLight, (0, 0, np.inf), u, v)
    expect_error(ValueError, "v must be 3", sl.AreaLight, p, u, (0, 1))
    for bad in (0, -1, 65, 2**40, 2**80):
        expect_error(ValueError, "between 1 and 64", sl.AreaLight, p, u, v, samples=bad)
    for bad in (2.0, True, "4", None.__class__):
        expect_error(TypeError, "samples must be an integer", sl.AreaLight, p, u, v, samples=bad)
    expect_error(ValueError, "intensity", sl.AreaLight, p, u, v, intensity=-1.0)
    expect_error(ValueError, "intensity", sl.AreaLight, p, u, v, intensity=np.nan)
    expect_error(ValueError, r"color\[0\]", sl.AreaLight, p, u, v, color=(np.nan, 0, 0))
    expect_error(ValueError, "attenuation", sl.AreaLight, p, u, v, attenuation=(0, 0, 0))
    expect_error(ValueError, "ambient", sl.AreaLight, p, u, v, ambient=(-1, 0, 0))


def test_back_material_and_add_obj_arguments_are_checked(tmp_path):
    scene = sl.Scene()
    mesh = sl.Mesh(TRI_V, TRI_F)
    expect_error(TypeError, "back_material", scene.add, mesh, back_material=3)
    expect_error(ValueError, "unobtainium", scene.add, mesh, back_material="unobtainium")
    expect_error(FileNotFoundError, "nope.obj", scene.add_obj, tmp_path / "nope.obj")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 x\n")
    expect_error(sl.ObjParseError, "bad.obj:2", scene.add_obj, bad)
    good = tmp_path / "good.obj"
    good.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    expect_error(TypeError, "material", scene.add_obj, good, material=3)
    expect_error(TypeError, "back_material", scene.add_obj, good, back_material=1)
    expect_error(ValueError, "transform", scene.add_obj, good, transform=np.zeros((4, 4)))
    assert scene.n_objects == 0  # nothing half-added
    assert scene.add_obj(good) == 1


@pytest.mark.parametrize(
    "make",
    [
        lambda **kw: sl.DirectionalLight((0, 0, -1), **kw),
        lambda **kw: sl.PointLight((0, 0, 1), **kw),
        lambda **kw: sl.SpotLight((0, 0, 1), (0, 0, -1), **kw),
        lambda **kw: sl.AreaLight((0, 0, 1), (1, 0, 0), (0, 1, 0), **kw),
    ],
)
def test_light_diffuse_and_specular_colours_are_validated(make):
    expect_error(ValueError, "diffuse colour must be finite and >= 0", make, diffuse=(-1, 0, 0))
    expect_error(ValueError, r"specular\[1\]", make, specular=(0, np.nan, 0))
    expect_error(ValueError, "diffuse must be 3", make, diffuse=(1, 1))
    expect_error(TypeError, "specular", make, specular="white")


def test_a_forced_internal_panic_arrives_as_runtime_error():
    """The guard every entry point runs behind turns a Rust panic into ``RuntimeError``
    (never pyo3's ``PanicException``): forced here through a test hook that panics."""
    from shadelab_rs import _core

    expect_error(
        RuntimeError,
        r"internal error in _panic_for_tests \(please report it\): forced by the test suite",
        _core._panic_for_tests,
    )


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda: sl.SpotLight((0, 0, 0), (0, 0, 1), cutoff=100), "cutoff"),
        (lambda: sl.SpotLight((0, 0, 0), (0, 0, 1), cutoff=30, inner=40), "inner"),
        (lambda: sl.PointLight((0, 0, 0), intensity=-1), "intensity"),
        (lambda: sl.PointLight((0, 0, 0), attenuation=(0, 0, 0)), "attenuation"),
        (lambda: sl.DirectionalLight((0, 0, 0)), "direction"),
        (lambda: sl.DirectionalLight((0, 1), color=(1, 1, 1)), "direction"),
        (lambda: sl.Material(shininess=-1), "shininess"),
        (lambda: sl.Material(emission=(0, -1, 0)), "emission"),
        (lambda: sl.Fog("exp", density=-1), "density"),
        (lambda: sl.Fog("linear", start=2, end=1), "end"),
        (lambda: sl.Camera.look_at((0, 0, 1), (0, 0, 1)), "target"),
        (lambda: sl.Camera.look_at((0, 0, 1), (0, 0, 0), near=0), "near"),
        (lambda: sl.AreaLight((0, 0, 0), (1, 0, 0), (2, 0, 0)), "v"),
        (lambda: sl.AreaLight((0, 0, 0), (1, 0, 0), (0, 1, 0), samples=0), "samples"),
        (lambda: sl.Scene(ambient=(0, -1, 0)), "ambient"),
        (lambda: sl.Mesh([[0, 0, 0]], [[0, 0, 1]]), "faces"),
    ],
)
def test_value_errors_name_their_argument(make, field):
    # The scene-file reader maps `field` to a key path instead of checking values again.
    with pytest.raises(ValueError) as e:
        make()
    assert e.value.field == field
