"""The command line, run as ``python -m shadelab_rs`` in a subprocess."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import shadelab_rs as sl
from PIL import Image
from shadelab_rs import cli

CUBE = str(sl.data_path("cube/cube.obj"))


def run(*args, cwd=None):
    """``python -m shadelab_rs *args`` -> CompletedProcess (text output)."""
    return subprocess.run(
        [sys.executable, "-m", "shadelab_rs", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=120,
        check=False,
    )


def read_png(path):
    with Image.open(path) as im:
        assert im.mode == "RGB"
        return np.asarray(im)


def test_demo(tmp_path):
    out = tmp_path / "demo.png"
    r = run("demo", "-o", out, "--size", "160x120")
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    assert str(out) in r.stdout and "160x120" in r.stdout
    img = read_png(out)
    assert img.shape == (120, 160, 3)
    # The same picture as the Python API draws.
    scene, cam = sl.demo_scene()
    np.testing.assert_array_equal(img, sl.render(scene, cam, width=160, height=120))


def test_png_compression_flag(tmp_path):
    scene, cam = sl.demo_scene()
    want = sl.render(scene, cam, width=64, height=48)
    sizes = {}
    for c in ("none", "high"):
        out = tmp_path / f"{c}.png"
        assert cli.main(["demo", "-o", str(out), "--size", "64x48", "--compression", c]) in (
            0,
            None,
        )
        np.testing.assert_array_equal(read_png(out), want)  # lossless either way
        sizes[c] = out.stat().st_size
    assert sizes["high"] < sizes["none"]


def test_demo_default_output_name(tmp_path):
    r = run("demo", "--size", "32x24", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert read_png(tmp_path / "demo.png").shape == (24, 32, 3)


def test_render_cube_chrome_flat(tmp_path):
    out = tmp_path / "cube.png"
    r = run(
        "render", CUBE, "--material", "chrome", "--shading", "flat", "-o", out, "--size", "96x64"
    )
    assert r.returncode == 0, r.stderr
    img = read_png(out)
    assert img.shape == (64, 96, 3)
    covered = img.any(axis=-1)
    assert 0.1 < covered.mean() < 0.9  # the cube is framed, with background around it
    # Flat shading of a cube: few distinct colours (one per visible face direction).
    assert len(np.unique(img[covered].reshape(-1, 3), axis=0)) <= 6
    # chrome is grey: equal channels.
    assert np.all(img[..., 0] == img[..., 1]) and np.all(img[..., 1] == img[..., 2])


def test_render_options(tmp_path):
    out = tmp_path / "opts.jpg"
    r = run(
        "render",
        CUBE,
        "-o",
        out,
        "--size",
        "40x30",
        "--shading",
        "gouraud",
        "--specular",
        "phong",
        "--background",
        "0,0,1",
        "--threads",
        "1",
        "--cull-backfaces",
        "--draw-hidden",
        "--light",
        "0,-1,0",
        "--light=-1,0,0",  # a leading "-" needs "=" (argparse)
        "--eye",
        "3,2,4",
        "--target",
        "0,0,0",
        "--fov",
        "50",
        "--ambient",
        "0.1,0.1,0.1",
        "--material",
        "Polished_Silver",
    )
    assert r.returncode == 0, r.stderr
    with Image.open(out) as im:
        assert im.format == "JPEG" and im.size == (40, 30)
        corner = np.asarray(im)[0, 0].astype(int)
    assert corner[2] > 200 and corner[0] < 60  # blue background (JPEG is lossy)


def test_render_stl_through_trimesh(tmp_path):
    import trimesh

    stl = tmp_path / "ico.stl"
    trimesh.creation.icosphere(subdivisions=2).export(stl)
    out = tmp_path / "ico.png"
    r = run("render", stl, "-o", out, "--size", "48x48")
    assert r.returncode == 0, r.stderr
    assert read_png(out).any()


def test_materials():
    r = run("materials")
    assert r.returncode == 0, r.stderr
    rows = r.stdout.strip().splitlines()
    assert len(rows) == len(sl.Material.preset_names()) == 29
    names = sl.Material.preset_names()
    for row, name in zip(rows, names):
        assert row.startswith(name)
    gold = next(row for row in rows if row.startswith("gold"))
    for value in ("0.24725", "0.75164", "0.628281", "51.2"):
        assert value in gold


def test_materials_sheet(tmp_path):
    out = tmp_path / "sheet.png"
    r = run("materials", "--sheet", out, "--cell", "32", "--columns", "10")
    assert r.returncode == 0, r.stderr
    img = read_png(out)
    label = 14
    assert img.shape == (3 * (32 + label), 10 * 32, 3)  # 29 presets: 3 rows of 10
    # Every swatch shows a sphere: its centre pixel differs from the cell's corner (the grey
    # background); the unused 30th cell stays black.
    for i in range(29):
        y, x = divmod(i, 10)
        y, x = y * (32 + label), x * 32
        assert img[y + 16, x + 16].tolist() != img[y, x].tolist(), sl.Material.preset_names()[i]
        assert img[y, x].tolist() == [56, 56, 61]
    assert not img[2 * (32 + label) : 2 * (32 + label) + 32, 9 * 32 :].any()


def test_materials_sheet_matches_swatch_scene():
    from shadelab_rs.swatch import material_sheet, swatch_scene

    sheet = material_sheet(["ruby", "jade"], cell=40, labels=False)
    assert sheet.shape == (40, 80, 3)
    for k, name in enumerate(["ruby", "jade"]):
        scene, camera = swatch_scene(sl.Material.preset(name))
        alone = sl.render(scene, camera, width=40, height=40, background=(0.22, 0.22, 0.24))
        np.testing.assert_array_equal(sheet[:, 40 * k : 40 * (k + 1)], alone)
    with pytest.raises(ValueError, match="cell"):
        material_sheet(cell=4)


def test_materials_sheet_with_textures(tmp_path):
    """--textures: the presets, padding to the end of their row, then a row of textured
    swatches, each a lit sphere (its centre differs from the grey corner)."""
    from shadelab_rs.swatch import (
        TEXTURE_SWATCH_NAMES,
        material_sheet,
        swatch_scene,
        texture_swatch,
    )

    out = tmp_path / "sheet.png"
    r = run("materials", "--sheet", out, "--cell", "32", "--columns", "10", "--textures")
    assert r.returncode == 0, r.stderr
    img = read_png(out)
    label = 14
    assert img.shape == (4 * (32 + label), 10 * 32, 3)  # 29 presets + 1 blank, then 6
    y = 3 * (32 + label)
    for k in range(len(TEXTURE_SWATCH_NAMES)):
        x = 32 * k
        assert img[y + 16, x + 16].tolist() != img[y, x].tolist(), TEXTURE_SWATCH_NAMES[k]
        assert img[y, x].tolist() == [56, 56, 61]
    assert not img[y : y + 32, 6 * 32 :].any()
    # By name, as the scene alone renders it (normal and bump swatches: Phong always).
    sheet = material_sheet(["normal map"], cell=40, labels=False, shading="gouraud")
    scene, camera = swatch_scene(texture_swatch("normal map"), uvs=True)
    alone = sl.render(scene, camera, width=40, height=40, background=(0.22, 0.22, 0.24))
    np.testing.assert_array_equal(sheet, alone)
    plain = material_sheet(["checker"], cell=40, labels=False)
    assert plain.std() > 10  # the checks show


def test_render_normal_and_bump_map_flags(tmp_path):
    from PIL import Image

    nm = tmp_path / "n.png"
    Image.fromarray(np.full((8, 8, 3), (200, 128, 230), np.uint8)).save(nm)
    spot = sl.data_path("spot/spot_triangulated.obj")
    outs = []
    for extra in ([], ["--normal-map", nm, "--normal-scale", "2"], ["--bump-map", nm]):
        out = tmp_path / f"o{len(outs)}.png"
        r = run("render", spot, "--size", "64x48", "-o", out, *extra)
        assert r.returncode == 0, r.stderr
        outs.append(read_png(out))
    assert np.abs(outs[0].astype(int) - outs[1]).max() > 10  # the tilted normals show
    np.testing.assert_array_equal(outs[0], outs[2])  # a constant height: no gradient
    r = run(
        "render",
        spot,
        "--size",
        "64x48",
        "-o",
        tmp_path / "x.png",
        "--shading",
        "flat",
        "--normal-map",
        nm,
    )
    assert r.returncode == 1 and "normal map" in r.stderr and "phong" in r.stderr


def test_version():
    r = run("--version")
    assert r.returncode == 0
    assert r.stdout.strip() == sl.__version__


def test_missing_file_is_an_error(tmp_path):
    out = tmp_path / "x.png"
    r = run("render", tmp_path / "missing.obj", "-o", out)
    assert r.returncode == 1
    assert r.stdout == ""
    assert r.stderr.startswith("shadelab: error: ")
    assert "no such file" in r.stderr and "missing.obj" in r.stderr
    assert "Traceback" not in r.stderr
    assert not out.exists()


def test_unknown_material_is_an_error(tmp_path):
    out = tmp_path / "x.png"
    r = run("render", CUBE, "--material", "vibranium", "-o", out)
    assert r.returncode == 1
    assert "vibranium" in r.stderr and "gold" in r.stderr  # names the valid presets
    assert "Traceback" not in r.stderr
    assert not out.exists()


def test_malformed_obj_is_an_error(tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    r = run("render", bad, "-o", tmp_path / "x.png")
    assert r.returncode == 1
    assert f"{bad}:4:" in r.stderr and "Traceback" not in r.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--size", "0x10"], "width"),
        (["--size", "10x99999"], "height"),
        (["--background", "nan,0,0"], "background"),
        (["--threads", "0"], "threads"),
        (["--eye", "0,0,0", "--target", "0,0,0"], "eye and target"),
        (["--light", "0,0,0"], "direction"),
    ],
)
def test_bad_values_exit_1_with_a_message(tmp_path, args, message, capsys):
    """In-process (fast): value errors print one line and return 1."""
    code = cli.main(["render", CUBE, "-o", str(tmp_path / "x.png"), *args])
    captured = capsys.readouterr()
    assert code == 1
    assert captured.err.startswith("shadelab: error: ") and message in captured.err
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize(
    "args",
    [
        ["render"],  # no model
        ["render", CUBE, "--size", "big"],
        ["render", CUBE, "--shading", "toon"],
        ["render", CUBE, "--background", "1,2"],
        ["teleport"],
        [],
        ["demo", "--compression", "zip"],
    ],
)
def test_usage_errors_exit_2(args, capsys):
    with pytest.raises(SystemExit) as e:
        cli.main(args)
    assert e.value.code == 2
    assert "usage: shadelab" in capsys.readouterr().err


def test_usage_error_through_subprocess():
    r = run("render", CUBE, "--size", "big")
    assert r.returncode == 2
    assert "size must look like 800x600" in r.stderr


def test_render_obj_uses_its_mtl_materials_unless_a_preset_is_given(tmp_path):
    (tmp_path / "m.mtl").write_text("newmtl blue\nKa 0 0 0.2\nKd 0 0 0.8\nKs 0 0 0\n")
    obj = tmp_path / "two.obj"
    obj.write_text(
        "mtllib m.mtl\nv -2 0 0\nv -1 0 0\nv -1 1 0\nv -2 1 0\nv 1 0 0\nv 2 0 0\nv 2 1 0\n"
        "v 1 1 0\nf 1 2 3 4\nusemtl blue\nf 5 6 7 8\n"
    )
    args = ("--view", "0,0,1", "--light", "0,0,-1", "--size", "96x48")
    r = run("render", obj, "-o", tmp_path / "a.png", *args)
    assert r.returncode == 0, r.stderr
    img = read_png(tmp_path / "a.png").astype(int)
    left, right = img[24, 10:40], img[24, 56:86]
    covered_l, covered_r = left.any(axis=-1), right.any(axis=-1)
    assert covered_l.any() and covered_r.any()
    # Left quad has no material: gold (red > blue); right one is the MTL's pure blue.
    assert (left[covered_l, 0] > left[covered_l, 2]).all()
    assert (right[covered_r, :2] == 0).all() and (right[covered_r, 2] > 0).all()
    r = run("render", obj, "-o", tmp_path / "b.png", "--material", "chrome", *args)
    assert r.returncode == 0, r.stderr
    img = read_png(tmp_path / "b.png")
    assert (img[..., 0] == img[..., 2]).all()  # chrome everywhere: grey


def test_turntable_views_write_numbered_images(tmp_path):
    out = tmp_path / "turn.png"
    r = run("demo", "--views", 4, "--size", "48x36", "-o", out)
    assert r.returncode == 0, r.stderr
    assert "wrote 4 views" in r.stdout
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == [f"turn_{i:04d}.png" for i in range(4)]
    scene, camera = sl.demo_scene()
    cams = cli.turntable(camera, 4)
    # View 0 is the camera itself; view 2 looks from the opposite side.
    assert np.allclose(cams[0].eye, camera.eye)
    tgt = np.array(camera.target)
    assert np.allclose(np.array(cams[2].eye) - tgt, (np.array(camera.eye) - tgt) * [-1, 1, -1])
    for i, cam in enumerate(cams):
        want = sl.render(scene, cam, width=48, height=36)
        assert read_png(tmp_path / f"turn_{i:04d}.png").tobytes() == want.tobytes(), i
    assert len({read_png(tmp_path / n).tobytes() for n in names}) == 4


def test_turntable_pattern_and_errors(tmp_path):
    r = run("render", CUBE, "--views", 3, "--size", "16x12", "-o", tmp_path / "f" / "{:03d}.png")
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in (tmp_path / "f").iterdir()) == ["000.png", "001.png", "002.png"]
    r = run("demo", "--views", 0, "-o", tmp_path / "x.png")
    assert r.returncode == 1 and "--views must be >= 1" in r.stderr
    r = run("demo", "--views", 2, "-o", tmp_path / "same{{}}.png")
    assert r.returncode == 1 and "same name" in r.stderr


def test_cameras_file_renders_numbered_images(tmp_path):
    scene, camera = sl.demo_scene()
    cams = cli.turntable(camera, 3)
    toml = tmp_path / "cams.toml"
    lines = []
    for c in cams:
        lines += ["[[cameras]]", f"eye = {list(c.eye)}", f"target = {list(c.target)}"]
        lines += [f"fov_y = {c.fov_y}", f"near = {c.near}", f"far = {c.far}", ""]
    lines += ["[[cameras]]", 'type = "orthographic"', "eye = [0, 5, 0.1]", "target = [0, 0, 0]"]
    toml.write_text("\n".join(lines))
    r = run("demo", "--cameras", toml, "--size", "40x30", "-o", tmp_path / "v{:02d}.png")
    assert r.returncode == 0, r.stderr
    want = sl.render_batch(
        scene, [*cams, sl.Camera.orthographic((0, 5, 0.1), (0, 0, 0))], width=40, height=30
    )
    for i in range(4):
        assert read_png(tmp_path / f"v{i:02d}.png").tobytes() == want[i].tobytes(), i
    js = tmp_path / "cams.json"
    good = {"eye": [0, 0, 3], "target": [0, 0, 0]}
    js.write_text(json.dumps([good, {**good, "fov_y": 500}]))
    r = run("demo", "--cameras", js, "-o", tmp_path / "j.png")
    assert r.returncode == 1 and "cams.json: cameras[1].fov_y" in r.stderr
    r = run("render", CUBE, "--cameras", js, "--eye", "1,2,3", "-o", tmp_path / "k.png")
    assert r.returncode == 1 and "--eye cannot be used with --cameras" in r.stderr
    r = run("demo", "--cameras", js, "--views", 3, "-o", tmp_path / "k.png")
    assert r.returncode == 1 and "cannot be used together" in r.stderr
    r = run("demo", "--cameras", tmp_path / "missing.toml", "-o", tmp_path / "k.png")
    assert r.returncode == 1 and "missing.toml" in r.stderr


def test_views_take_the_single_render_flags(tmp_path):
    """--alpha, --encoding and --depth apply to every view of --views as to one render."""
    r = run(
        "demo",
        "--views",
        2,
        "--size",
        "32x24",
        "--alpha",
        "--encoding",
        "srgb",
        "--shading",
        "gouraud",
        "--depth",
        tmp_path / "d.npy",
        "-o",
        tmp_path / "v.png",
    )
    assert r.returncode == 0, r.stderr
    scene, camera = sl.demo_scene()
    for i, cam in enumerate(cli.turntable(camera, 2)):
        want, depth = sl.render(
            scene,
            cam,
            width=32,
            height=24,
            shading="gouraud",
            alpha=True,
            encoding="srgb",
            return_depth=True,
        )
        with Image.open(tmp_path / f"v_{i:04d}.png") as im:
            assert im.mode == "RGBA"
            assert np.asarray(im).tobytes() == want.tobytes(), i
        assert np.load(tmp_path / f"d_{i:04d}.npy").tobytes() == depth.tobytes(), i
    r = run("demo", "--views", 2, "-o", "-")
    assert r.returncode == 1 and "stdout" in r.stderr


def test_cameras_file_with_a_scene_file_rejects_camera_flags(tmp_path):
    js = tmp_path / "cams.json"
    js.write_text(json.dumps([{"eye": [0, 0, 3], "target": [0, 0, 0]}]))
    scene_file = tmp_path / "s.toml"
    sl.save_scene(scene_file, *sl.demo_scene())
    r = run("render", scene_file, "--cameras", js, "--fov", 30, "-o", tmp_path / "k.png")
    assert r.returncode == 1 and "--fov cannot be used with --cameras" in r.stderr
    r = run("render", scene_file, "--cameras", js, "--size", "16x12", "-o", tmp_path / "k.png")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "k_0000.png").exists()
