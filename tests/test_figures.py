"""The lecture figures (issue 19): written with their captions, and their panels against the
float64 reference."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import shadelab_rs as sl
from PIL import Image
from shadelab_rs import figures as fg

from shadelab_ref import reference as ref

FILES = ("diffuse_spheres.png", "specular_grid.png", "shading_modes.png")


def test_lecture_figures_writes_every_figure_with_its_caption(tmp_path):
    written = sl.lecture_figures(tmp_path / "figs")
    assert [p.name for p in written] == [*FILES, "captions.md"]
    captions = (tmp_path / "figs" / "captions.md").read_text(encoding="utf-8")
    cell = fg.CELL + 14
    shapes = {
        "diffuse_spheres.png": (cell, 6 * fg.CELL),
        "specular_grid.png": (3 * cell, 5 * fg.CELL),
        "shading_modes.png": (cell, 3 * fg.CELL),
    }
    for name in FILES:
        path = tmp_path / "figs" / name
        with Image.open(path) as im:
            assert im.mode == "RGB" and (im.height, im.width) == shapes[name]
        assert path.stat().st_size < 64_000  # small enough for the docs
        assert f"]({name})" in captions
    for text in ("lecture 000", "lecture 001", "0, 0.2, 0.4, 0.6, 0.8, 1.0", "3, 6, 9, 25, 200"):
        assert text in captions


def test_figures_command(tmp_path):
    r = subprocess.run(
        [sys.executable, "-m", "shadelab_rs", "figures", "-o", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert r.returncode == 0, r.stderr
    for name in (*FILES, "captions.md"):
        assert (tmp_path / "out" / name).is_file()
        assert name in r.stdout


def reference_panel(scene: sl.Scene, shading: str) -> ref.RefImage:
    o = scene.objects[0]
    m, mesh = o.material, o.mesh
    c = fg.camera()
    cam = ref.Camera(eye=c.eye, target=c.target, up=(0, 1, 0), fov_y=40.0, near=1.0, far=10.0)
    return ref.render_reference(
        mesh.vertices,
        mesh.faces,
        normals=mesh.normals,
        camera=cam,
        width=fg.CELL,
        height=fg.CELL,
        material=ref.Material(m.ambient, m.diffuse, m.specular, m.shininess),
        lights=[ref.DirectionalLight(direction=fg.LIGHT_DIRECTION)],
        ambient=scene.ambient,
        shading=shading,
        background=fg.BACKGROUND,
    )


@pytest.mark.parametrize(
    ("scene", "shading"),
    [
        (fg.diffuse_scene(0.0), "phong"),
        (fg.diffuse_scene(0.6), "phong"),
        (fg.diffuse_scene(1.0), "phong"),
        (fg.specular_scene(0.5, 25.0), "phong"),
        (fg.specular_scene(0.25, 200.0), "phong"),
        (fg.shading_scene(), "flat"),
        (fg.shading_scene(), "gouraud"),
        (fg.shading_scene(), "phong"),
    ],
)
def test_panels_match_the_reference(scene, shading):
    """Each panel within one 8-bit level of the float64 reference at every pixel more
    than 0.05 px from a triangle edge (see test_reference_compare.py for why edges are
    left out)."""
    r = reference_panel(scene, shading)
    got = fg._panel(scene, shading)
    inside = r.mask & (r.edge_dist > 0.05)
    assert inside.sum() > 3000
    diff = np.abs(got[inside].astype(int) - ref.to_uint8(r.color[inside]).astype(int))
    assert diff.max() <= 1, diff.max()
    assert (got[~r.mask] == ref.to_uint8(np.array(fg.BACKGROUND))).all()
