"""Issue 16: a new user's first pictures. Each test is one finding of the issue, and each
failed on the main branch it was written against (black images, cast errors, faceted STL
spheres, ...)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import shadelab_rs as sl
import trimesh

SPOT = sl.data_path("spot/spot_triangulated.obj")
CUBE = sl.data_path("cube/cube.obj")


def _object_stats(img: np.ndarray, depth: np.ndarray) -> tuple[float, np.ndarray]:
    covered = np.isfinite(depth)
    return float(img[covered].mean()) if covered.any() else 0.0, covered


# ---- 1. Cameras that always see the scene -----------------------------------------------


def test_millimetre_model_is_drawn_with_default_planes():
    """Benchy-sized box (millimetres) seen from (100, -150, 80): the old default far = 100
    drew nothing; the fitted planes draw all of it."""
    box = trimesh.creation.box(extents=(60, 30, 48))
    box.apply_translation((0, 0, 24))
    scene = sl.Scene()
    scene.add(box, material="gold")
    cam = sl.Camera.look_at(eye=(100, -150, 80), target=(0, 0, 24), up=(0, 0, 1))
    assert cam.near is None and cam.far is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        img, depth = sl.render(scene, cam, 96, 72, return_depth=True)
    mean, covered = _object_stats(img, depth)
    assert covered.mean() > 0.05 and mean > 40
    fitted = cam.fitted(scene)
    assert fitted.near < depth[covered].min() and depth[covered].max() < fitted.far


def test_eye_close_to_the_cube_does_not_cut_its_front_face():
    """--eye 1.5,1.5,3 on the unit cube: the fitted near plane keeps the whole front."""
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    cam = sl.Camera.look_at(eye=(1.5, 1.5, 3), target=(0, 0, 0), fov_y=90)
    _, depth = sl.render(scene, cam, 64, 64, return_depth=True)
    generous = sl.Camera.look_at(eye=(1.5, 1.5, 3), target=(0, 0, 0), fov_y=90, near=1e-3, far=1e3)
    _, ref = sl.render(scene, generous, 64, 64, return_depth=True)
    np.testing.assert_array_equal(np.isfinite(depth), np.isfinite(ref))
    np.testing.assert_allclose(depth[np.isfinite(ref)], ref[np.isfinite(ref)], rtol=1e-5)


def test_one_given_plane_is_kept_and_the_other_fitted():
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    cam = sl.Camera.look_at(eye=(0, 0, 10), target=(0, 0, 0), near=2.0)
    f = cam.fitted(scene)
    assert f.near == 2.0 and f.far == pytest.approx(11.0, rel=0.05) and f.far > 11.0
    ortho = sl.Camera.orthographic(eye=(0, 0, 10), target=(0, 0, 0), height=3)
    f = ortho.fitted(scene)
    assert f.near < 9.0 and f.far > 11.0 and f.far - f.near < 2.5


def test_camera_looking_away_warns():
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    cam = sl.Camera.look_at(eye=(0, 0, 5), target=(0, 0, 10))
    with pytest.warns(sl.EmptyRenderWarning, match="12 triangles"):
        img = sl.render(scene, cam, 16, 16)
    assert img.max() == 0


# ---- 2. The default light rig -----------------------------------------------------------


@pytest.mark.parametrize("view", ["front", "back", "left", "right", "top", "bottom", "iso"])
def test_spot_is_lit_from_every_view_by_the_default_rig(view):
    """Spot's face seen from the front was 15/255 under the fixed world light; the rig
    moves with the camera, so every view is lit about alike."""
    spot = sl.load_obj(SPOT)
    scene = sl.Scene()
    scene.add(spot, material="gold")
    img, depth = sl.render(scene, sl.frame_mesh(spot, direction=view), 96, 72, return_depth=True)
    mean, _ = _object_stats(img, depth)
    assert mean > 70


def test_default_lights_only_without_lights_and_can_be_turned_off():
    scene = sl.Scene(ambient=(0, 0, 0))
    scene.add(sl.Mesh.ico_sphere(2))
    cam = sl.frame_mesh(sl.Mesh.ico_sphere(2))
    assert scene.default_lights
    assert sl.render_frame(scene, cam, 32, 32)["stats"]["light_sources"] == 3
    scene.default_lights = False
    assert sl.render(scene, cam, 32, 32).max() == 0
    scene.default_lights = True
    scene.add_light(sl.DirectionalLight((0, 0, -1)))
    assert sl.render_frame(scene, cam, 32, 32)["stats"]["light_sources"] == 1


# ---- 3. Up axis and named views ---------------------------------------------------------


@pytest.mark.parametrize("up", [(0, 1, 0), (0, 0, 1), (1, 0, 0)])
@pytest.mark.parametrize("view", sl.VIEWS)
def test_named_views_work_for_any_up_axis(up, view):
    d, cam_up = sl.view_direction(view, up)
    assert np.linalg.norm(np.cross(d, cam_up)) > 0.5  # never parallel
    cam = sl.frame_mesh(sl.Mesh.cube(), direction=view, up=up)
    _, depth = sl.render(sl.Mesh.cube(), cam, 32, 32, return_depth=True)
    assert np.isfinite(depth).mean() > 0.1


def test_z_up_front_view_shows_the_model_standing():
    """A tall box along z (Z-up): framed with up=(0, 0, 1) it is taller than wide."""
    tall = trimesh.creation.box(extents=(1, 1, 4))
    cam = sl.frame_mesh(tall, direction="front", up=(0, 0, 1))
    _, depth = sl.render(tall, cam, 64, 64, return_depth=True)
    rows, cols = np.nonzero(np.isfinite(depth))
    assert np.ptp(rows) > 2 * np.ptp(cols)
    assert sl.file_up_axis("boat.stl") == (0, 0, 1) and sl.file_up_axis("boat.3MF") == (0, 0, 1)
    assert sl.file_up_axis("boat.glb") == (0, 1, 0) and sl.file_up_axis("boat.obj") == (0, 1, 0)


# ---- 4. Welding and crease-angle normals ------------------------------------------------


def test_stl_sphere_is_welded_and_smooth(tmp_path):
    ico = trimesh.creation.icosphere(subdivisions=2)
    path = tmp_path / "sphere.stl"
    ico.export(path)
    mesh = sl.load_mesh(path)
    assert mesh.n_vertices == 162 and mesh.n_faces == 320
    # Smooth: the normals point along the positions (a unit sphere).
    cos = np.einsum("ij,ij->i", mesh.normals, mesh.vertices)
    assert cos.min() > 0.99


def test_box_keeps_sharp_edges(tmp_path):
    """A box with 8 shared corners (PLY) is split at its 90-degree edges: 24 vertices, each
    with its face's normal, not a pillow."""
    path = tmp_path / "box.ply"
    trimesh.creation.box().export(path)
    mesh = sl.load_mesh(path)
    assert mesh.n_vertices == 24
    assert np.allclose(np.abs(mesh.normals).max(axis=1), 1.0)


def test_from_trimesh_spot_has_no_seams():
    """trimesh splits Spot at its UV seams; the normals ignore the split: the render
    matches the Rust OBJ loader's (was 795 pixels off by more than 8 levels)."""
    tm = trimesh.load(SPOT, process=False)
    spot = sl.load_obj(SPOT)
    cam = sl.frame_mesh(spot, direction=(0.3, 0.2, -1))
    a = sl.render(spot, cam, 256, 256).astype(int)
    b = sl.render(sl.Mesh.from_trimesh(tm), cam, 256, 256).astype(int)
    assert (np.abs(a - b).max(axis=2) > 8).sum() <= 5


# ---- 5. Interop and a mutable scene ------------------------------------------------------


def test_everything_a_trimesh_user_types_first():
    tm = trimesh.creation.icosphere(subdivisions=2)
    scene = sl.Scene()
    assert scene.add(tm) == 1
    assert scene.add((tm.vertices, tm.faces), material="gold") == 1
    assert scene.objects[1].material == sl.Material.preset("gold")
    mesh = sl.Mesh.from_trimesh(tm)
    cam = sl.frame_mesh(mesh)
    img = sl.render(mesh, cam, 32, 32)
    assert img.shape == (32, 32, 3) and img.max() > 0
    assert sl.render(tm, width=16, height=16).max() > 0  # no camera: framed
    ts = trimesh.Scene()
    ts.add_geometry(tm, transform=trimesh.transformations.translation_matrix((3, 0, 0)))
    s2 = sl.Scene()
    s2.add(ts)
    np.testing.assert_allclose(s2.bounds(), [(2, -1, -1), (4, 1, 1)], atol=1e-6)


def test_scene_lists_are_read_only_and_the_scene_is_mutable():
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    scene.add(sl.Mesh.cube(), material="copper")
    scene.add_light(sl.DirectionalLight((0, -1, 0)))
    assert isinstance(scene.objects, tuple) and isinstance(scene.lights, tuple)
    with pytest.raises(AttributeError):
        scene.objects.clear()  # type: ignore[attr-defined]
    t = np.eye(4)
    t[:3, 3] = (5, 0, 0)
    scene.set_transform(-1, t)
    np.testing.assert_array_equal(scene.objects[1].transform, t)
    np.testing.assert_allclose(scene.bounds(), [(-1, -1, -1), (6, 1, 1)])
    scene.set_material(0, "gold")
    assert scene.objects[0].material == sl.Material.preset("gold")
    scene.remove_object(0)
    assert scene.n_objects == 1
    scene.set_light(0, sl.PointLight((0, 5, 0)))
    assert isinstance(scene.lights[0], sl.PointLight)
    scene.clear_lights()
    scene.clear_objects()
    assert (scene.n_objects, scene.n_lights) == (0, 0)
    with pytest.raises(IndexError, match="out of range"):
        scene.remove_object(0)


def test_scene_mutation_keeps_the_light_directions_as_given():
    """remove_light, set_light and clear_lights keep each light's direction as the user gave
    it (float64, not normalised) in step with the lights themselves."""
    scene = sl.Scene()
    given = [(0.1, -0.7, 0.3), (0.0, 0.0, -3.0), (1e-3, -1.0, 2e-7)]
    scene.add_light(sl.DirectionalLight(given[0]))
    scene.add_light(sl.PointLight((0, 5, 0)))
    scene.add_light(sl.SpotLight((0, 3, 0), given[1]))
    scene.add_light(sl.DirectionalLight(given[2]))
    scene.remove_light(1)
    assert [light.direction for light in scene.lights] == given
    scene.set_light(0, sl.SpotLight((1, 1, 1), (0.0, -2.0, 0.0)))
    scene.set_light(-1, sl.PointLight((0, 1, 0)))
    lights = scene.lights
    assert lights[0].direction == (0.0, -2.0, 0.0) and lights[1].direction == given[1]
    assert isinstance(lights[2], sl.PointLight)
    scene.clear_lights()
    scene.add_light(sl.DirectionalLight(given[2]))
    assert scene.lights[0].direction == given[2]


# ---- 6. Outputs ------------------------------------------------------------------------


def test_alpha_is_the_coverage_and_srgb_encodes():
    mesh = sl.Mesh.ico_sphere(2)
    cam = sl.frame_mesh(mesh)
    rgba, depth = sl.render(mesh, cam, 48, 40, alpha=True, return_depth=True)
    assert rgba.shape == (40, 48, 4) and rgba.dtype == np.uint8
    np.testing.assert_array_equal(rgba[..., 3] == 255, np.isfinite(depth))
    assert set(np.unique(rgba[..., 3])) == {0, 255}
    f = sl.render(mesh, cam, 48, 40, dtype="float32", alpha=True)
    assert f.dtype == np.float32 and set(np.unique(f[..., 3])) == {0.0, 1.0}
    lin = sl.render(mesh, cam, 48, 40, dtype="float32")
    srgb = sl.render(mesh, cam, 48, 40, encoding="srgb")
    np.testing.assert_array_equal(srgb, np.floor(sl.srgb_encode(lin) * 255 + 0.5))
    assert srgb.mean() > sl.render(mesh, cam, 48, 40).mean()  # mid-tones brighten
    assert sl.srgb_encode([0.0, 0.0031308, 1.0]) == pytest.approx([0.0, 0.04045, 1.0], abs=1e-5)
    with pytest.raises(ValueError, match="encoding"):
        sl.render(mesh, cam, 8, 8, encoding="gamma")  # type: ignore[arg-type]


def test_save_image_every_kind(tmp_path):
    from PIL import Image

    rng = np.random.default_rng(1)
    grey = rng.integers(0, 256, (5, 7), dtype=np.uint8)
    rgba = rng.integers(0, 256, (5, 7, 4), dtype=np.uint8)
    u16 = rng.integers(0, 65536, (5, 7, 3), dtype=np.uint16)
    f32 = rng.random((5, 7)).astype(np.float32)
    for name, a in (("g.png", grey), ("a.png", rgba), ("g16.png", u16[..., 0])):
        sl.save_image(a, tmp_path / name)
        with Image.open(tmp_path / name) as im:
            np.testing.assert_array_equal(np.asarray(im), a)
    sl.save_image(u16, tmp_path / "c16.png")  # 48-bit PNG: Pillow reads it as 8-bit only
    assert (tmp_path / "c16.png").read_bytes()[24:26] == bytes([16, 2])  # depth 16, RGB
    sl.save_image(f32, tmp_path / "f.tif")
    with Image.open(tmp_path / "f.tif") as im:
        assert im.mode == "F"
        np.testing.assert_array_equal(np.asarray(im), f32)
    sl.save_image(u16, tmp_path / "x.npy")
    np.testing.assert_array_equal(np.load(tmp_path / "x.npy"), u16)
    with pytest.raises(ValueError, match="float colour"):
        sl.save_image(rng.random((5, 7, 3)).astype(np.float32), tmp_path / "c.tif")
    with pytest.raises(ValueError, match="uint16"):
        sl.save_image(u16, tmp_path / "c.jpg")
    with pytest.raises(ValueError, match="JPEG has no alpha"):
        sl.save_image(rgba, tmp_path / "c.jpg")


def test_png_compression_settings_are_lossless(tmp_path):
    from PIL import Image

    rng = np.random.default_rng(2)
    # A smooth gradient with noise: the filters matter, and every sample must come back.
    ramp = np.linspace(0, 200, 64 * 48 * 3).reshape(48, 64, 3) + rng.integers(0, 40, (48, 64, 3))
    rgb = ramp.astype(np.uint8)
    u16 = (rng.integers(0, 65536, (9, 11))).astype(np.uint16)
    sizes = {}
    for c in sl.io.PNG_COMPRESSIONS:
        sl.save_image(rgb, tmp_path / f"{c}.png", compression=c)
        with Image.open(tmp_path / f"{c}.png") as im:
            np.testing.assert_array_equal(np.asarray(im), rgb)
        sizes[c] = (tmp_path / f"{c}.png").stat().st_size
        sl.save_image(u16, tmp_path / f"{c}16.png", compression=c)
        with Image.open(tmp_path / f"{c}16.png") as im:
            np.testing.assert_array_equal(np.asarray(im), u16)
    assert sizes["none"] > sizes["fast"] >= sizes["high"]
    # A strided view is written as the image it shows.
    view = rgb[::2, ::3]
    sl.save_image(view, tmp_path / "view.png")
    with Image.open(tmp_path / "view.png") as im:
        np.testing.assert_array_equal(np.asarray(im), view)
    with pytest.raises(ValueError, match="compression must be one of"):
        sl.save_image(rgb, tmp_path / "x.png", compression="zip")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="uint8 or uint16"):
        sl._core.encode_png(np.zeros((2, 2), np.int32))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="C-contiguous"):
        sl._core.encode_png(view)
    with pytest.raises(ValueError, match="1 to 4 channels"):
        sl._core.encode_png(np.zeros((2, 2, 5), np.uint8))
    with pytest.raises(ValueError, match="compression"):
        sl._core.encode_png(rgb, "zip")  # type: ignore[arg-type]


def test_save_depth_states_its_scale(tmp_path):
    from PIL import Image

    mesh = sl.Mesh.ico_sphere(2)
    _, depth = sl.render(mesh, sl.frame_mesh(mesh), 32, 32, return_depth=True)
    sl.save_depth(depth, tmp_path / "d.png")
    with Image.open(tmp_path / "d.png") as im:
        assert im.info["depth_scale"] == "1000.0"
        q = np.asarray(im).astype(np.int64)
    drawn = np.isfinite(depth)
    np.testing.assert_array_equal(q == 0, ~drawn)
    assert np.abs(q[drawn] - depth[drawn] * 1000).max() <= 0.5
    with pytest.raises(ValueError, match="scale <="):
        sl.save_depth(depth, tmp_path / "d.png", scale=1e6)
    sl.save_depth(depth, tmp_path / "d.tif")
    with Image.open(tmp_path / "d.tif") as im:
        np.testing.assert_array_equal(np.asarray(im), depth)


# ---- 7. The command line ------------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--background", "128,128,128"], "divide by 255"),
        (["--background=-1,0,0"], "[0, 1]"),
        (["--view", "0,0,0"], "--view direction must be finite and non-zero"),
        (["--up", "0,0,0"], "--up direction"),
    ],
)
def test_cli_rejects_values_it_used_to_accept(tmp_path, args, message, capsys):
    from shadelab_rs import cli

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no NumPy RuntimeWarning leaks
        code = cli.main(["render", str(CUBE), "-o", str(tmp_path / "x.png"), *args])
    err = capsys.readouterr().err
    assert code == 1 and err.startswith("shadelab: error: ") and message in err


def test_cli_eye_far_away_draws_and_up_target_are_honoured(tmp_path, capsys):
    from PIL import Image
    from shadelab_rs import cli

    def run(*args: str, model=SPOT) -> np.ndarray:
        out = tmp_path / "o.png"
        assert cli.main(["render", str(model), "-o", str(out), "--size", "48x36", *args]) == 0
        with Image.open(out) as im:
            return np.asarray(im)

    far = run("--eye", "15,15,30", model=CUBE)  # was all black: the framing camera's far plane
    assert far.max() > 0
    ups = [run("--up", u) for u in ("0,1,0", "1,0,0", "0,0,1")]
    assert not np.array_equal(ups[0], ups[1]) and not np.array_equal(ups[0], ups[2])
    assert not np.array_equal(run("--target", "0.5,0,0"), run())
    assert run("--view", "top").max() > 0
    assert run("--two-sided").max() > 0
    assert "warning" not in capsys.readouterr().err


def test_cli_warns_on_stderr_and_writes_png_to_stdout(tmp_path):
    import subprocess
    import sys

    r = subprocess.run(
        [sys.executable, "-m", "shadelab_rs", "render", str(CUBE), "-o", "-", "--size", "8x6"],
        capture_output=True,
        check=True,
    )
    assert r.stdout.startswith(b"\x89PNG") and b"wrote -" in r.stderr
    out = str(tmp_path / "x.png")
    away = ["--size", "8x6", "--eye", "0,0,5", "--target", "0,0,10"]
    r = subprocess.run(
        [sys.executable, "-m", "shadelab_rs", "render", str(CUBE), "-o", out, *away],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "shadelab: warning: render drew no triangle" in r.stderr


# ---- 8. Docs at run time and strict mode names ---------------------------------------------


@pytest.mark.parametrize("fn", [sl.render, sl.render_frame])
def test_runtime_docstrings_name_every_option(fn):
    import inspect

    doc = inspect.getdoc(fn) or ""
    # *args and **kwargs are RenderOptions' arguments: each of those must be named.
    var = (inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD)
    params = [p.name for p in inspect.signature(fn).parameters.values() if p.kind not in var]
    params += list(inspect.signature(sl.RenderOptions).parameters)
    missing = [p for p in params if not p.startswith("_") and f"``{p}``" not in doc]
    if fn is sl.render_frame:  # it refers to render for the arguments
        assert "render" in doc and "stats" in doc
        missing = [p for p in missing if f"``{p}``" not in (inspect.getdoc(sl.render) or "")]
    assert not missing


def test_mypy_rejects_an_unknown_shading_name(tmp_path):
    api = pytest.importorskip("mypy.api")
    src = tmp_path / "user.py"
    src.write_text(
        "import shadelab_rs as sl\n"
        "s = sl.Scene()\n"
        "c = sl.Camera.look_at((0, 0, 3), (0, 0, 0))\n"
        "sl.render(s, c, shading='toon')\n"
        "sl.render(s, c, shading='phong')\n"
    )
    out, _, status = api.run([str(src), "--no-incremental", "--follow-imports=silent"])
    assert status == 1 and "user.py:4:" in out and "user.py:5:" not in out


# ---- Every bundled mesh from six views ---------------------------------------------------


@pytest.mark.parametrize("path", sorted(sl.data_path("").rglob("*.obj")), ids=lambda p: p.name)
@pytest.mark.parametrize("view", ["front", "back", "left", "right", "top", "bottom"])
def test_bundled_meshes_look_right_by_default(path, view):
    """Defaults only (framing, fitted planes, light rig): the object is lit (mean above
    60/255 over its pixels) and whole (its silhouette touches no image border)."""
    scene = sl.Scene()
    scene.add_obj(path, material="gold")
    img, depth = sl.render(scene, sl.frame_scene(scene, direction=view), 80, 64, return_depth=True)
    mean, covered = _object_stats(img, depth)
    assert covered.mean() > 0.05 and mean > 60
    assert not (
        covered[0].any() or covered[-1].any() or covered[:, 0].any() or covered[:, -1].any()
    )


# ---- Scene files and Z-up files on the command line ---------------------------------------

SCENE = {
    "version": 1,
    "camera": {"eye": [0.5, 0.4, 3.0], "target": [0, 0, 0]},
    "render": {"width": 40, "height": 30},
    "objects": [{"mesh": {"primitive": "sphere"}, "material": "gold"}],
}


def _cli_png(args: list[str], out) -> np.ndarray:
    from PIL import Image
    from shadelab_rs import cli

    assert cli.main(["render", *args, "-o", str(out)]) == 0
    with Image.open(out) as im:
        return np.asarray(im).astype(int)


def test_scene_file_without_lights_is_lit_and_can_be_orbited_and_relit(tmp_path):
    """A scene file without lights rendered a black silhouette; --eye, --view and --light
    were refused for scene files."""
    path = tmp_path / "s.toml"
    path.write_text(sl.to_toml(SCENE))
    sf = sl.load_scene(path)
    assert sf.camera.near is None and sf.camera.far is None  # fitted when left out

    def lit(img: np.ndarray) -> float:  # mean over the object's pixels
        return float(img[img.max(axis=2) > 0].mean())

    base = _cli_png([str(path)], tmp_path / "a.png")
    assert lit(base) > 60
    orbit = _cli_png([str(path), "--eye", "0,3,0.5"], tmp_path / "b.png")
    top = _cli_png([str(path), "--view", "top"], tmp_path / "c.png")
    relit = _cli_png([str(path), "--light=0,0,1"], tmp_path / "d.png")  # from behind
    for other in (orbit, relit):
        assert not np.array_equal(other, base)
    assert lit(top) > 60 and relit.mean() < base.mean()


def test_stl_is_framed_z_up_on_the_command_line(tmp_path):
    """A tall box along z saved as STL stands upright in the default CLI picture."""
    path = tmp_path / "tower.stl"
    trimesh.creation.box(extents=(1, 1, 4)).export(path)
    img = _cli_png([str(path), "--size", "64x64", "--view", "front"], tmp_path / "t.png")
    rows, cols = np.nonzero(img.max(axis=2) > 0)
    assert np.ptp(rows) > 2 * np.ptp(cols)


def test_exr_without_openexr_says_what_to_install(tmp_path):
    try:
        import OpenEXR  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="pip install OpenEXR"):
            sl.save_image(np.zeros((2, 2, 3), np.float32), tmp_path / "x.exr")
    else:
        sl.save_image(np.zeros((2, 2, 3), np.float32), tmp_path / "x.exr")
        assert (tmp_path / "x.exr").stat().st_size > 0


def test_scene_file_reports_every_error_at_once(tmp_path):
    doc = {
        "version": 1,
        "ambient": [2, -1],
        "camera": {"eye": [0, 0, 3], "target": [0, 0, 3]},
        "lights": [{"type": "directional", "direction": [0, 0, 0]}, {"type": "laser"}],
        "objects": [{"mesh": {"primitive": "sphere"}, "material": "unobtainium"}],
    }
    path = tmp_path / "bad.toml"
    path.write_text(sl.to_toml(doc))
    with pytest.raises(sl.SceneFileError) as info:
        sl.load_scene(path)
    e = info.value
    keys = [e.key] + [m.key for m in e.more]
    # Shape errors (lights[1].type) and the core's own field errors mapped to key paths
    # (ambient, camera.target, lights[0].direction) are collected alike.
    assert keys[0] == "ambient" and len(keys) == 5
    assert {"camera.target", "lights[0].direction", "lights[1].type"} <= set(keys)
    assert any(k.startswith("objects[0]") for k in keys)
    lines = str(e).splitlines()
    assert len(lines) == 5 and all(line.startswith(f"{path}: ") for line in lines)


def test_orbit_moves_the_eye_around_the_target():
    cam = sl.Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=40)
    right = sl.orbit(cam, azimuth=90)
    np.testing.assert_allclose(right.eye, (5, 0, 0), atol=1e-12)
    assert (right.fov_y, right.near, right.far) == (40, None, None)
    np.testing.assert_allclose(sl.orbit(cam, azimuth=360).eye, cam.eye, atol=1e-12)
    above = sl.orbit(cam, elevation=90)  # over the pole: a top view, never an error
    np.testing.assert_allclose(above.eye, (0, 5, 0), atol=1e-12)
    ortho = sl.Camera.orthographic((0, 0, 5), (0, 0, 0), height=3, near=1, far=9)
    o = sl.orbit(ortho, azimuth=-90, elevation=30)
    assert (o.kind, o.height, o.near, o.far) == ("orthographic", 3, 1, 9)
    np.testing.assert_allclose(np.linalg.norm(o.eye), 5)
    assert o.eye[0] < 0 and o.eye[1] == pytest.approx(2.5)


def test_glb_is_loaded_y_up(tmp_path):
    path = tmp_path / "box.glb"
    trimesh.creation.box(extents=(1, 2, 3)).export(path)
    mesh = sl.load_mesh(path)
    assert mesh.n_faces == 12 and sl.file_up_axis(path) == (0, 1, 0)
    np.testing.assert_allclose(np.ptp(mesh.vertices, axis=0), (1, 2, 3), atol=1e-6)


def test_intrinsics_and_view_matrix_round_trip():
    cam = sl.Camera.look_at((1, 2, 5), (0, 0.5, 0), up=(0, 1, 0), fov_y=50)
    K = sl.intrinsics(cam, 640, 480)
    assert K[0, 2] == 320 and K[1, 2] == 240 and K[0, 0] == K[1, 1]
    back = sl.camera_from_intrinsics(K, 640, 480, cam.eye, cam.target)
    assert back.kind == "pinhole" and np.array_equal(sl.intrinsics(back, 640, 480), K)
    # A small sphere off-centre is drawn where K projects its centre (to half a pixel).
    centre = np.array([0.8, 1.1, 0.3])
    scene = sl.Scene()
    scene.add(sl.Mesh.ico_sphere(3), transform=np.diag([0.05, 0.05, 0.05, 1.0]))
    scene.set_transform(0, np.block([[np.eye(3) * 0.05, centre[:, None]], [np.zeros((1, 3)), 1]]))
    _, depth = sl.render(scene, cam, 640, 480, return_depth=True)
    rows, cols = np.nonzero(np.isfinite(depth))
    x_eye = (cam.view_matrix() @ np.append(centre, 1.0))[:3]
    u = K @ np.array([x_eye[0], -x_eye[1], -x_eye[2]])
    assert cols.mean() + 0.5 == pytest.approx(u[0] / u[2], abs=0.5)
    assert rows.mean() + 0.5 == pytest.approx(u[1] / u[2], abs=0.5)
    again = sl.camera_from_matrix(cam.view_matrix(), fov_y=50)
    np.testing.assert_allclose(again.view_matrix(), cam.view_matrix(), atol=1e-12)
    # Any K is taken as it is (tests/test_intrinsics.py checks where it draws).
    general = [[500.0, 3.0, 300.0], [0.0, 450.0, 250.0], [0.0, 0.0, 1.0]]
    odd = sl.camera_from_intrinsics(general, 640, 480, (0, 0, 5), (0, 0, 0))
    assert np.array_equal(sl.intrinsics(odd, 640, 480), general)
    with pytest.raises(ValueError, match="rigid"):
        sl.camera_from_matrix(np.diag([2.0, 1, 1, 1]))


def test_pyvista_polydata_is_accepted_when_present():
    """PyVista is optional; an object shaped like its PolyData goes the same way."""

    class PolyData:
        points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
        faces = np.array([4, 0, 1, 2, 3])

        def triangulate(self):
            tri = PolyData()
            tri.faces = np.array([3, 0, 1, 2, 3, 0, 2, 3])
            return tri

    PolyData.__module__ = "pyvista.core.pointset"
    scene = sl.Scene()
    assert scene.add(PolyData()) == 1
    assert scene.objects[0].mesh.n_faces == 2


def test_the_wrapper_and_the_binding_take_the_same_options():
    """sl.render wraps _core.render: the same parameters of the same kinds in the same
    order (the render options positionally, options= and RenderOptions' keywords passed
    through), plus its own keyword-only alpha (render_frame's binding has it: the coverage)
    and encoding, so the two cannot drift apart; the stub's overloads spell the binding's
    parameters the same way."""
    import ast
    import inspect
    from pathlib import Path

    from shadelab_rs import _core

    stub = ast.parse((Path(sl.__file__).parent / "_core.pyi").read_text())
    for public, core in ((sl.render, _core.render), (sl.render_frame, _core.render_frame)):
        params = list(inspect.signature(public).parameters.values())
        core_params = list(inspect.signature(core).parameters.values())
        # The binding's **kwargs (RenderOptions' keywords) stays last.
        assert core_params[-1].kind is inspect.Parameter.VAR_KEYWORD
        own = [("encoding", inspect.Parameter.KEYWORD_ONLY)]
        if "alpha" not in [p.name for p in core_params]:
            own.insert(0, ("alpha", inspect.Parameter.KEYWORD_ONLY))
        assert [(p.name, p.kind) for p in params] == [
            (p.name, p.kind) for p in core_params[:-1]
        ] + [*own, (core_params[-1].name, inspect.Parameter.VAR_KEYWORD)]
        for p, c in zip(params[2:], core_params[2:-1]):
            assert p.default == c.default, p.name
        stubs = [n for n in stub.body if isinstance(n, ast.FunctionDef) and n.name == core.__name__]
        assert stubs
        for f in stubs:
            a = f.args
            assert [x.arg for x in a.args] == [p.name for p in core_params[:2]]
            assert a.vararg is not None and a.vararg.arg == core_params[2].name
            assert [x.arg for x in a.kwonlyargs] == [p.name for p in core_params[3:-1]]
            assert a.kwarg is not None and a.kwarg.arg == core_params[-1].name
