"""render and render_frame: output shapes, dtypes and layout, depth, background, culling,
shading and specular names, frame statistics."""

from __future__ import annotations

import numpy as np
import pytest
import shadelab_rs as sl

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
    assert stats["triangles_clipped"] == 0
    # The sphere is a closed solid seen from outside: its hidden back faces are skipped.
    assert 0 < stats["triangles_culled"] < stats["triangles_in"]
    assert stats["triangles_setup"] + stats["triangles_culled"] <= stats["triangles_in"]
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
    drawn = sl.render_frame(sphere_scene, camera, cull_hidden=False, **kw)
    culled = sl.render_frame(sphere_scene, camera, cull_backfaces=True, **kw)
    hidden = sl.render_frame(sphere_scene, camera, **kw)  # cull_hidden=True, the default
    for f in (culled, hidden):
        np.testing.assert_array_equal(f["image"], drawn["image"])
        np.testing.assert_array_equal(f["depth"], drawn["depth"])
        assert f["stats"]["triangles_culled"] > 0.3 * sphere_scene.n_triangles
    assert drawn["stats"]["triangles_culled"] == 0


def test_hidden_back_faces_are_drawn_where_they_may_show(camera):
    """The default skips a solid's back faces only where they cannot show: a sphere wound
    inward (seen from outside, its back faces are what shows) and an open one keep them."""
    m = sl.Mesh.uv_sphere(12, 24)
    inward = sl.Mesh(m.vertices, m.faces[:, ::-1])
    open_sphere = sl.Mesh(m.vertices, m.faces[1:])
    for mesh, skipped in ((m, True), (inward, False), (open_sphere, False)):
        scene = sl.Scene()
        scene.add(mesh, sl.Material.preset("gold"))
        scene.add_light(sl.DirectionalLight((-1, -1, -1)))
        kw = dict(width=64, height=48, dtype="float32")
        on = sl.render_frame(scene, camera, **kw)
        off = sl.render_frame(scene, camera, cull_hidden=False, **kw)
        np.testing.assert_array_equal(on["image"], off["image"])
        assert (on["stats"]["triangles_culled"] > 0) == skipped
        assert off["stats"]["triangles_culled"] == 0


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


@pytest.mark.parametrize(
    "extra",
    [
        {"samples": 4},
        {"samples": 8, "shading": "gouraud"},
        {"edges": "visible"},
        {"edges": "features", "samples": 4},
        {"supersample": 2, "shading": "flat"},
    ],
)
def test_hidden_back_faces_change_nothing_with_samples_lines_or_supersampling(camera, extra):
    """Skipping a solid's hidden back faces leaves every colour and depth the same with
    multi-sampling (each sample point is covered by front and back faces alike), lines and
    supersampling."""
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    scene.add(sl.Mesh.uv_sphere(30, 60), sl.Material.preset("gold"))
    cube = np.diag([0.5, 0.5, 0.5, 1.0])
    cube[:3, 3] = (1.2, 0.0, -0.5)
    scene.add(sl.Mesh.cube(), sl.Material.preset("jade"), transform=cube)
    scene.add_light(sl.DirectionalLight((-1, -1, -1)))
    kw = dict(width=120, height=90, dtype="float32", return_depth=True, **extra)
    on = sl.render_frame(scene, camera, **kw)
    off = sl.render_frame(scene, camera, cull_hidden=False, **kw)
    np.testing.assert_array_equal(on["image"], off["image"])
    np.testing.assert_array_equal(on["depth"], off["depth"])
    assert on["stats"]["triangles_culled"] > 0 and off["stats"]["triangles_culled"] == 0
