"""The lecture figures, rendered by the renderer: ``sl.lecture_figures(dir)`` and
``shadelab figures -o DIR`` write each as a small PNG with a caption (``captions.md``)
naming the lecture figure it reproduces and every parameter that differs between its
panels. The scenes are public (``*_scene``) so tests can compare a panel with the float64
reference."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from ._core import Camera, DirectionalLight, Material, Mesh, Scene, render
from .io import save_image

_Shading = Literal["flat", "gouraud", "phong"]

#: Pixels per panel (square).
CELL = 96
_LABEL_HEIGHT = 14
#: Mid grey, so a black sphere (ρ_d = 0) still shows its outline.
BACKGROUND = (0.22, 0.22, 0.24)
#: The one light of every figure: white, travelling from the upper left front.
LIGHT_DIRECTION = (0.6, -0.6, -0.8)
#: ρ_d of the diffuse row (lecture 000).
DIFFUSE_STEPS = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0)
#: ρ_s rows and exponents f columns of the specular grid (lecture 000).
SPECULAR_RHO = (0.1, 0.25, 0.5)
SPECULAR_EXPONENTS = (3.0, 6.0, 9.0, 25.0, 200.0)
#: ρ_d of the specular grid's spheres and the scene ambient of the specular grid and the
#: shading comparison (the diffuse row has none, as the lecture's pure Lambert spheres).
GRID_DIFFUSE = 0.45
AMBIENT = 0.1


def camera() -> Camera:
    """The camera of every panel: a unit sphere at the origin seen from +z."""
    return Camera.look_at(eye=(0, 0, 3.2), target=(0, 0, 0), fov_y=40.0, near=1.0, far=10.0)


def sphere_scene(
    diffuse: float,
    specular: float = 0.0,
    shininess: float = 1.0,
    ambient: float = 0.0,
    mesh: Mesh | None = None,
) -> Scene:
    """A grey sphere (ρ_a = ρ_d = ``diffuse``, ρ_s = ``specular``, exponent ``shininess``)
    under the white directional light, scene ambient ``ambient``."""
    scene = Scene(ambient=(ambient,) * 3)
    m = Material((diffuse,) * 3, (diffuse,) * 3, (specular,) * 3, shininess)
    scene.add(mesh if mesh is not None else Mesh.uv_sphere(48, 96), material=m)
    scene.add_light(DirectionalLight(direction=LIGHT_DIRECTION))
    return scene


def diffuse_scene(rho_d: float) -> Scene:
    """A panel of the diffuse row: Lambert only (no specular, no ambient)."""
    return sphere_scene(rho_d)


def specular_scene(rho_s: float, f: float) -> Scene:
    """A panel of the specular grid."""
    return sphere_scene(GRID_DIFFUSE, rho_s, f, AMBIENT)


def shading_scene() -> Scene:
    """The shading comparison's coarse sphere (8 rings, 16 segments), so that flat facets
    and Gouraud's interpolated highlight show."""
    return sphere_scene(0.5, 0.5, 25.0, AMBIENT, mesh=Mesh.uv_sphere(8, 16))


@dataclass(frozen=True)
class Figure:
    """One written figure: file name, lecture, caption."""

    file: str
    lecture: str
    caption: str


def _sheet(panels: Sequence[np.ndarray], labels: Sequence[str], columns: int) -> np.ndarray:
    """Panels in rows of ``columns``, each with its label underneath."""
    from PIL import Image, ImageDraw

    rows = -(-len(panels) // columns)
    h = CELL + _LABEL_HEIGHT
    sheet = np.zeros((rows * h, columns * CELL, 3), dtype=np.uint8)
    for i, p in enumerate(panels):
        r, c = divmod(i, columns)
        sheet[r * h : r * h + CELL, c * CELL : (c + 1) * CELL] = p
    pil = Image.fromarray(sheet, "RGB")
    draw = ImageDraw.Draw(pil)
    for i, label in enumerate(labels):
        r, c = divmod(i, columns)
        draw.text((c * CELL + 3, r * h + CELL + 1), label, fill=(230, 230, 230))
    return np.asarray(pil)


def _panel(scene: Scene, shading: _Shading = "phong") -> np.ndarray:
    return render(scene, camera(), CELL, CELL, shading=shading, background=BACKGROUND)


def render_figures() -> dict[str, tuple[np.ndarray, Figure]]:
    """Every figure as an image with its caption, by file name."""
    light = "one white directional light travelling (0.6, -0.6, -0.8), Phong shading"
    figures = [
        (
            _sheet(
                [_panel(diffuse_scene(r)) for r in DIFFUSE_STEPS],
                [f"rho_d={r:.1f}" for r in DIFFUSE_STEPS],
                len(DIFFUSE_STEPS),
            ),
            Figure(
                "diffuse_spheres.png",
                "lecture 000, diffuse reflection: spheres with ρ_d from 0 to 1 in steps of 0.2",
                "Lambert's law alone: ρ_d = 0, 0.2, 0.4, 0.6, 0.8, 1.0 left to right; no "
                f"ambient, no specular term; {light}.",
            ),
        ),
        (
            _sheet(
                [_panel(specular_scene(s, f)) for s in SPECULAR_RHO for f in SPECULAR_EXPONENTS],
                [f"rs={s:g} f={f:g}" for s in SPECULAR_RHO for f in SPECULAR_EXPONENTS],
                len(SPECULAR_EXPONENTS),
            ),
            Figure(
                "specular_grid.png",
                "lecture 000, specular reflection: the ρ_s × f grid",
                f"Blinn-Phong highlights: rows ρ_s = {', '.join(f'{s:g}' for s in SPECULAR_RHO)}"
                f"; columns f = {', '.join(f'{f:g}' for f in SPECULAR_EXPONENTS)}; "
                f"ρ_a = ρ_d = {GRID_DIFFUSE}, scene ambient {AMBIENT}; {light}.",
            ),
        ),
        (
            _sheet(
                [_panel(shading_scene(), mode) for mode in ("flat", "gouraud", "phong")],
                ["flat", "Gouraud", "Phong"],
                3,
            ),
            Figure(
                "shading_modes.png",
                "lecture 001, flat, Gouraud and Phong shading of the same polygon mesh",
                "One coarse sphere (8 rings × 16 segments), ρ_a = ρ_d = 0.5, ρ_s = 0.5, "
                f"f = 25, scene ambient {AMBIENT}, shaded flat (face normal at the centroid), "
                "Gouraud (lit at the vertices, colours interpolated) and Phong (normals "
                "interpolated, lit per pixel); one white directional light travelling "
                "(0.6, -0.6, -0.8).",
            ),
        ),
    ]
    return {fig.file: (img, fig) for img, fig in figures}


def lecture_figures(directory: str | os.PathLike[str]) -> list[Path]:
    """Writes the lecture figures into ``directory`` (created if missing) as PNGs, with
    ``captions.md`` beside them; returns the paths written (captions last). Every figure
    is a grid of 96-pixel panels with a label under each."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    lines = ["# Lecture figures", "", "Rendered by `shadelab figures` (shadelab_rs).", ""]
    for name, (img, fig) in render_figures().items():
        path = out / name
        save_image(img, path, compression="high")  # kept in docs: smallest files
        written.append(path)
        lines += [f"## {fig.lecture}", "", f"![{fig.lecture}]({name})", "", fig.caption, ""]
    captions = out / "captions.md"
    captions.write_text("\n".join(lines), encoding="utf-8")
    written.append(captions)
    return written
