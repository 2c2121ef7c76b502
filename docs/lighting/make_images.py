#!/usr/bin/env python3
"""Renders the images of docs/LIGHTING.md into docs/lighting/ (``make docs-images``).

Every figure is a row (or grid) of labelled panels; each panel is one ``sl.render`` of a small
scene built by the functions below, which docs/LIGHTING.md quotes. The PNGs are written
palette-free with Pillow's ``optimize`` so the committed set stays small.

    python docs/lighting/make_images.py                 # all figures into docs/lighting/
    python docs/lighting/make_images.py --out DIR --scale 0.25 --only fog   # quick, elsewhere
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import shadelab_rs as sl
from PIL import Image, ImageDraw

HERE = Path(__file__).resolve().parent
PANEL = (320, 240)  # width, height of one panel at scale 1
LABEL_H = 16
BACKGROUND = (0.05, 0.05, 0.07)

# --------------------------------------------------------------------------- building blocks


def translate_scale(t: tuple[float, float, float], s: float | tuple[float, float, float]) -> Any:
    """4x4 model matrix: scale by ``s`` (a number or per axis), then translate by ``t``."""
    m = np.diag([*(s if isinstance(s, tuple) else (s, s, s)), 1.0])
    m[:3, 3] = t
    return m


SPHERE = sl.Mesh.uv_sphere(48, 96)
FLOOR = sl.Material(
    ambient=(0.6, 0.6, 0.6), diffuse=(0.6, 0.6, 0.6), specular=(0.2, 0.2, 0.2), shininess=8
)
WHITE = sl.Material(
    ambient=(0.8, 0.8, 0.8), diffuse=(0.8, 0.8, 0.8), specular=(0.6, 0.6, 0.6), shininess=40
)


def stage(**scene_kw: Any) -> sl.Scene:
    """The common set: a 10x10 floor, a red plastic sphere, a white sphere and a gold cube.
    Global ambient 0.1 unless ``ambient=`` says otherwise."""
    scene = sl.Scene(**{"ambient": (0.1, 0.1, 0.1), **scene_kw})
    scene.add(sl.Mesh.plane(), material=FLOOR, transform=translate_scale((0, 0, 0), (5, 1, 5)))
    scene.add(
        SPHERE,
        material=sl.Material.preset("red plastic"),
        transform=translate_scale((-1.1, 0.7, 0.2), 0.7),
    )
    scene.add(SPHERE, material=WHITE, transform=translate_scale((0.9, 0.5, 0.6), 0.5))
    cube = translate_scale((0.5, 0.4, -1.1), 0.4)
    c, s = math.cos(0.6), math.sin(0.6)
    cube[:3, :3] = cube[:3, :3] @ np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    scene.add(sl.Mesh.cube(), material=sl.Material.preset("gold"), transform=cube)
    return scene


def stage_camera() -> sl.Camera:
    return sl.Camera.look_at(eye=(0.0, 3.2, 5.6), target=(0.0, 0.3, 0.0), fov_y=38.0)


def sphere_camera(dist: float = 3.0, fov: float = 42.0) -> sl.Camera:
    return sl.Camera.look_at(eye=(0.0, 0.0, dist), target=(0.0, 0.0, 0.0), fov_y=fov)


@dataclass
class Panel:
    """One render: its label, scene, camera and extra ``sl.render`` arguments."""

    label: str
    scene: sl.Scene
    camera: sl.Camera
    kw: dict[str, Any] | None = None


@dataclass
class Figure:
    name: str  # file stem
    caption: str
    make: Callable[[], list[Panel]]
    columns: int = 0  # 0: one row


FIGURES: list[Figure] = []


def figure(name: str, caption: str, columns: int = 0) -> Callable:
    def register(make: Callable[[], list[Panel]]) -> Callable[[], list[Panel]]:
        FIGURES.append(Figure(name, caption, make, columns))
        return make

    return register


# --------------------------------------------------------------------------- light kinds


@figure("directional", "DirectionalLight: parallel rays, so the floor is evenly lit")
def _directional() -> list[Panel]:
    scene = stage()
    scene.add_light(sl.DirectionalLight(direction=(-0.5, -1.0, -0.6)))
    return [Panel("DirectionalLight(direction=(-0.5, -1, -0.6))", scene, stage_camera())]


@figure("point", "PointLight without and with distance attenuation")
def _point() -> list[Panel]:
    out = []
    for label, att in (
        ("attenuation=(1, 0, 0) (off)", (1, 0, 0)),
        ("attenuation=(1, 0, 0.3)", (1, 0, 0.3)),
    ):
        scene = stage()
        scene.add_light(sl.PointLight(position=(0.0, 1.4, 1.0), intensity=1.3, attenuation=att))
        out.append(Panel(label, scene, stage_camera()))
    return out


@figure("spot", "SpotLight: a hard cone, then a smooth inner cone with an exponent")
def _spot() -> list[Panel]:
    out = []
    for label, kw in (
        ("cutoff=25", {}),
        ("cutoff=25, inner=12", {"inner": 12.0}),
        ("cutoff=25, exponent=20", {"exponent": 20.0}),
    ):
        scene = stage(ambient=(0.05, 0.05, 0.05))
        scene.add_light(
            sl.SpotLight(
                position=(0.0, 4.0, 1.5),
                direction=(-0.1, -1.0, -0.35),
                cutoff=25.0,
                intensity=1.2,
                **kw,
            )
        )
        out.append(Panel(label, scene, stage_camera()))
    return out


def shiny_scene(light: Any) -> sl.Scene:
    """Two shiny spheres over a dark floor: an area light's samples show as highlights."""
    scene = sl.Scene(ambient=(0.05, 0.05, 0.05))
    scene.add(sl.Mesh.plane(), material=FLOOR, transform=translate_scale((0, -1, 0), (5, 1, 5)))
    shiny = sl.Material(
        ambient=(0.1, 0.1, 0.12), diffuse=(0.25, 0.25, 0.3), specular=(0.9, 0.9, 0.9), shininess=400
    )
    scene.add(SPHERE, material=shiny, transform=translate_scale((0, 0, 0), 1.0))
    scene.add_light(light)
    return scene


def area(shape: str, samples: int, **kw: Any) -> sl.AreaLight:
    """A 3 x 2 panel (or the ellipse inscribed in it) above and in front of the sphere, facing
    it (u x v points at the sphere)."""
    return sl.AreaLight(
        position=(0.0, 2.2, 2.6),
        u=(3.0, 0.0, 0.0),
        v=(0.0, -1.53, 1.29),
        shape=shape,
        samples=samples,
        intensity=1.2,
        **kw,
    )


@figure("area", "AreaLight: samples² point sources; the highlight shows them", columns=4)
def _area() -> list[Panel]:
    cam = sl.Camera.look_at(eye=(0.0, 0.6, 3.4), target=(0.0, 0.0, 0.0), fov_y=40.0)
    out = []
    for shape in ("rectangle", "disk"):
        for samples in (1, 2, 4, 8):
            scene = shiny_scene(area(shape, samples))
            out.append(Panel(f"{shape}, samples={samples}", scene, cam))
    return out


@figure("area_sides", "AreaLight one_sided: only the side its normal u×v points to emits")
def _area_sides() -> list[Panel]:
    out = []
    for one_sided in (False, True):
        scene = sl.Scene(ambient=(0.05, 0.05, 0.05))
        scene.add(
            sl.Mesh.plane(), material=FLOOR, transform=translate_scale((0, -0.8, 0), (5, 1, 5))
        )
        scene.add(SPHERE, material=WHITE, transform=translate_scale((-1.4, 0, 0), 0.7))
        scene.add(SPHERE, material=WHITE, transform=translate_scale((1.4, 0, 0), 0.7))
        # A vertical panel between the spheres; u x v = (0, 0, 1.2) x (0, 1.2, 0) points to -x.
        scene.add_light(
            sl.AreaLight(
                position=(0, 0, 0),
                u=(0, 0, 1.2),
                v=(0, 1.2, 0),
                samples=4,
                one_sided=one_sided,
                intensity=1.5,
            )
        )
        cam = sl.Camera.look_at(eye=(0.0, 1.6, 4.6), target=(0.0, -0.1, 0.0), fov_y=40.0)
        out.append(Panel(f"one_sided={one_sided}", scene, cam))
    return out


@figure("light_ambient", "A light's own ambient colour (here a spot's), scaled by its cone")
def _light_ambient() -> list[Panel]:
    out = []
    for amb in ((0, 0, 0), (0.4, 0.3, 0.15)):
        scene = stage(ambient=(0.02, 0.02, 0.02))
        scene.add_light(
            sl.SpotLight(
                position=(0.0, 4.0, 1.5),
                direction=(-0.1, -1.0, -0.35),
                cutoff=30.0,
                inner=20.0,
                ambient=amb,
            )
        )
        out.append(Panel(f"SpotLight(..., ambient={amb})", scene, stage_camera()))
    return out


@figure("light_colors", "A light's own diffuse and specular colours (GL_DIFFUSE, GL_SPECULAR)")
def _light_colors() -> list[Panel]:
    out = []
    for label, kw in (
        ("color=(1, 1, 1)", {}),
        (
            "diffuse=(0.3, 0.5, 1), specular=(1, 1, 1)",
            {"diffuse": (0.3, 0.5, 1.0), "specular": (1.0, 1.0, 1.0)},
        ),
        ("specular=(0, 0, 0)", {"specular": (0.0, 0.0, 0.0)}),
    ):
        scene = stage()
        scene.add_light(sl.DirectionalLight(direction=(-0.5, -1.0, -0.6), **kw))
        out.append(Panel(label, scene, stage_camera()))
    return out


@figure("emission", "Material emission: a constant added to the colour, lit or not")
def _emission() -> list[Panel]:
    out = []
    for e in ((0, 0, 0), (0.6, 0.45, 0.1)):
        scene = stage(ambient=(0.05, 0.05, 0.05))
        glow = sl.Material(
            ambient=(0.2, 0.2, 0.2),
            diffuse=(0.5, 0.5, 0.5),
            specular=(0.3, 0.3, 0.3),
            shininess=30,
            emission=e,
        )
        scene.add(SPHERE, material=glow, transform=translate_scale((-0.2, 0.45, 1.6), 0.45))
        scene.add_light(sl.DirectionalLight(direction=(1.0, -0.6, -0.3), intensity=0.8))
        out.append(Panel(f"emission={e}", scene, stage_camera()))
    return out


# --------------------------------------------------------------------------- light model


FOG_COLOR = (0.6, 0.65, 0.75)


@figure("fog", "Fog by eye distance: linear, exp, exp2; the background is set to the fog colour")
def _fog() -> list[Panel]:
    fogs = (
        ("none", None),
        (
            'Fog("linear", start=4, end=14)',
            sl.Fog("linear", start=4.0, end=14.0, color=FOG_COLOR),
        ),
        ('Fog("exp", density=0.15)', sl.Fog("exp", density=0.15, color=FOG_COLOR)),
        ('Fog("exp2", density=0.12)', sl.Fog("exp2", density=0.12, color=FOG_COLOR)),
    )
    out = []
    for label, fog in fogs:
        scene = sl.Scene(ambient=(0.2, 0.2, 0.2), fog=fog)
        scene.add(
            sl.Mesh.plane(), material=FLOOR, transform=translate_scale((0, -0.5, -10), (16, 1, 14))
        )
        for k in range(7):  # a row of spheres receding from the camera
            scene.add(
                SPHERE,
                material=sl.Material.preset("jade"),
                transform=translate_scale(((-1) ** k * 0.9, 0.0, -2.5 * k), 0.5),
            )
        scene.add_light(sl.DirectionalLight(direction=(-0.4, -1.0, -0.5)))
        cam = sl.Camera.look_at(eye=(0.0, 1.2, 4.0), target=(0.0, 0.0, -6.0), fov_y=45.0)
        # The renderer does not fog the background (nothing is drawn there): set it yourself.
        out.append(Panel(label, scene, cam, {"background": FOG_COLOR} if fog else None))
    return out


def bowl(rings: int = 32, segments: int = 64, keep: float = 0.6) -> sl.Mesh:
    """An open mesh: the lower part of a unit UV sphere (rows with y < ``keep`` are kept), so
    its inside, seen from above, is made of back faces."""
    full = sl.Mesh.uv_sphere(rings, segments)
    v, f, n = full.vertices, full.faces, full.normals
    return sl.Mesh(v, f[np.all(v[f][:, :, 1] < keep, axis=1)], normals=n)


@figure("two_sided", "two_sided lighting on an open bowl: its inside is back faces")
def _two_sided() -> list[Panel]:
    out = []
    for two, back in ((False, None), (True, None), (True, "gold")):
        scene = sl.Scene(ambient=(0.1, 0.1, 0.1), two_sided=two)
        scene.add(
            bowl(),
            material=sl.Material.preset("turquoise"),
            back_material=sl.Material.preset(back) if back else None,
        )
        scene.add_light(sl.DirectionalLight(direction=(0.4, -1.0, -0.5)))
        cam = sl.Camera.look_at(eye=(0.0, 2.6, 2.2), target=(0.0, -0.1, 0.0), fov_y=45.0)
        label = f"two_sided={two}" + (f', back_material="{back}"' if back else "")
        out.append(Panel(label, scene, cam))
    return out


@figure("viewer", "Local viewer (default) and the infinite viewer on a shiny floor")
def _viewer() -> list[Panel]:
    out = []
    for local in (True, False):
        scene = sl.Scene(ambient=(0.1, 0.1, 0.1), local_viewer=local)
        shiny_floor = sl.Material(
            ambient=(0.1, 0.1, 0.1),
            diffuse=(0.3, 0.3, 0.35),
            specular=(0.7, 0.7, 0.7),
            shininess=60,
        )
        scene.add(
            sl.Mesh.plane(), material=shiny_floor, transform=translate_scale((0, 0, 0), (5, 1, 5))
        )
        scene.add(
            SPHERE,
            material=sl.Material.preset("chrome"),
            transform=translate_scale((0, 0.6, 0), 0.6),
        )
        scene.add_light(sl.DirectionalLight(direction=(0.0, -0.55, 1.0)))
        out.append(Panel(f"Scene(local_viewer={local})", scene, stage_camera()))
    return out


# --------------------------------------------------------------------------- shading modes


def lone_sphere(mesh: sl.Mesh, material: sl.Material) -> sl.Scene:
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    scene.add(mesh, material=material)
    scene.add_light(sl.DirectionalLight(direction=(-0.6, -0.7, -0.8)))
    return scene


@figure(
    "shading", "flat, Gouraud and Phong on a coarse (224 triangles) and a fine sphere", columns=3
)
def _shading() -> list[Panel]:
    out = []
    for label, mesh in (("8x16", sl.Mesh.uv_sphere(8, 16)), ("48x96", SPHERE)):
        scene = lone_sphere(mesh, sl.Material.preset("gold"))
        for mode in ("flat", "gouraud", "phong"):
            out.append(
                Panel(
                    f"{mode}, uv_sphere({label.replace('x', ', ')})",
                    scene,
                    sphere_camera(),
                    {"shading": mode},
                )
            )
    return out


def three_spheres() -> sl.Scene:
    """A coarse shiny sphere, a medium and a fine matte one, side by side."""
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    shiny = sl.Material(
        ambient=(0.05, 0.05, 0.1), diffuse=(0.2, 0.25, 0.6), specular=(0.6, 0.6, 0.6), shininess=64
    )
    matte = sl.Material(
        ambient=(0.05, 0.05, 0.05), diffuse=(0.7, 0.55, 0.4), specular=(0, 0, 0), shininess=1
    )
    for x, rings, mat in ((-2.3, 10, shiny), (0.0, 22, matte), (2.3, 158, matte)):
        scene.add(
            sl.Mesh.uv_sphere(rings, 2 * rings),
            material=mat,
            transform=translate_scale((x, 0, 0), 1),
        )
    scene.add_light(sl.DirectionalLight(direction=(-0.6, -0.7, -0.8)))
    return scene


def three_spheres_camera() -> sl.Camera:
    return sl.Camera.look_at((0.0, 1.0, 7.5), (0.0, 0.0, 0.0), (0, 1, 0), fov_y=40.0)


@figure(
    "auto",
    'shading="auto": each object its cheapest mode within the tolerance (labels: the modes '
    "chosen, left to right), and Phong everywhere",
)
def _auto() -> list[Panel]:
    scene, cam = three_spheres(), three_spheres_camera()
    out = []
    for tol in (1.0, 4.0):
        modes = sl.explain(scene, cam, *PANEL, tolerance=tol)["shading"]
        out.append(
            Panel(
                f"auto, tolerance {tol:g}: {', '.join(modes)}",
                scene,
                cam,
                {"shading": "auto", "tolerance": tol},
            )
        )
    out.append(Panel("phong everywhere", scene, cam, {"shading": "phong"}))
    return out


@figure(
    "specular",
    "Specular lobes at shininess 8, 32, 128: rows blinn, phong, blinn-normalized",
    columns=3,
)
def _specular() -> list[Panel]:
    out = []
    for model in ("blinn", "phong", "blinn-normalized"):
        for f in (8.0, 32.0, 128.0):
            mat = sl.Material(
                ambient=(0.05, 0.05, 0.1),
                diffuse=(0.2, 0.25, 0.6),
                specular=(0.6, 0.6, 0.6),
                shininess=f,
            )
            out.append(
                Panel(
                    f'specular="{model}", f={f:g}',
                    lone_sphere(SPHERE, mat),
                    sphere_camera(),
                    {"specular": model},
                )
            )
    return out


# --------------------------------------------------------------------------- shadows

SUN = (-0.5, -1.0, -0.6)


@figure("shadows", "Shadows of a directional light: none, shadow map (default), exact rays")
def _shadows() -> list[Panel]:
    out = []
    for label, shadows in (
        ("shadows=False", False),
        ("shadows=True (map)", True),
        ('shadows="exact"', "exact"),
    ):
        scene = stage()
        scene.add_light(sl.DirectionalLight(direction=SUN, shadows=shadows))
        out.append(Panel(label, scene, stage_camera()))
    return out


@figure("shadow_kinds", "Every light kind casts shadows; an area light's are soft")
def _shadow_kinds() -> list[Panel]:
    spot = sl.SpotLight(
        position=(1.5, 3.5, 2.0), direction=(-0.4, -1.0, -0.5), cutoff=40.0, shadows=True
    )
    point = sl.PointLight(position=(0.0, 1.6, 0.6), intensity=0.9, shadows=True)
    panel = dict(position=(-0.5, 3.0, 1.0), u=(1.6, 0, 0), v=(0, 0, 1.6), samples=6)
    out = []
    for label, light in (
        ("SpotLight, map", spot),
        ("PointLight, cube map", point),
        ("AreaLight 6x6, exact", sl.AreaLight(**panel, intensity=1.2, shadows="exact")),
        ("AreaLight 6x6, maps", sl.AreaLight(**panel, intensity=1.2, shadows=True)),
    ):
        scene = stage()
        scene.add_light(light)
        out.append(Panel(label, scene, stage_camera()))
    return out


@figure("shadow_filters", "A coarse map (256 texels): plain comparison, PCF 3x3 and 7x7, exact")
def _shadow_filters() -> list[Panel]:
    out = []
    for label, shadows in (
        ('256, filter="none"', sl.ShadowSettings(256, "none")),
        ("256, pcf 3x3", sl.ShadowSettings(256, "pcf", 3)),
        ("256, pcf 7x7", sl.ShadowSettings(256, "pcf", 7)),
        ('"exact"', "exact"),
    ):
        scene = stage()
        scene.add_light(sl.DirectionalLight(direction=SUN, shadows=shadows))
        cam = sl.Camera.look_at(eye=(0.2, 1.6, 2.6), target=(0.2, 0.2, -0.6), fov_y=40.0)
        out.append(Panel(label, scene, cam))
    return out


@figure(
    "shadow_cascades",
    "A 400-unit ground seen to 60 units, 1024-texel maps: over the whole ground, fitted to "
    "the view, 3 cascades, exact",
)
def _shadow_cascades() -> list[Panel]:
    out = []
    for label, shadows, kw in (
        ("whole ground (flat, Gouraud, rays)", sl.ShadowSettings(1024), {"reflections": "ray"}),
        ("fitted to the view", sl.ShadowSettings(1024), {}),
        ("3 cascades", sl.ShadowSettings(1024, cascades=3), {}),
        ('"exact"', "exact", {}),
    ):
        scene = sl.Scene(ambient=(0.25, 0.25, 0.25))
        scene.add(sl.Mesh.plane(), material=FLOOR, transform=translate_scale((0, 0, 0), 200.0))
        for i, z in enumerate((1.0, -2.0, -6.0, -12.0, -20.0)):
            x = (-1.0) ** i * (0.6 + 0.1 * i)
            scene.add(
                sl.Mesh.cube(),
                material=sl.Material.preset("gold"),
                transform=translate_scale((x, 0.3, z), 0.3),
            )
        scene.add_light(sl.DirectionalLight(direction=(-1.0, -0.8, 0.4), shadows=shadows))
        cam = sl.Camera.look_at(
            eye=(0.0, 1.4, 4.0), target=(0.0, 0.3, -4.0), fov_y=50.0, near=0.1, far=60.0
        )
        out.append(Panel(label, scene, cam, kw))
    return out


# --------------------------------------------------------------------------- output


def _label(img: np.ndarray, text: str) -> np.ndarray:
    """The panel with a dark caption strip on top."""
    h, w, _ = img.shape
    pil = Image.new("RGB", (w, h + LABEL_H), (24, 24, 28))
    pil.paste(Image.fromarray(img, "RGB"), (0, LABEL_H))
    ImageDraw.Draw(pil).text((4, 2), text, fill=(235, 235, 235))
    return np.asarray(pil)


def render_figure(fig: Figure, scale: float) -> np.ndarray:
    """Renders a figure's panels and lays them out: one row, or ``fig.columns`` per row."""
    w, h = max(16, round(PANEL[0] * scale)), max(16, round(PANEL[1] * scale))
    tiles = []
    for p in fig.make():
        kw = {"background": BACKGROUND, **(p.kw or {})}
        img = sl.render(p.scene, p.camera, width=w, height=h, **kw)
        tiles.append(_label(img, p.label) if scale >= 0.5 else img)
    cols = fig.columns or len(tiles)
    rows = [tiles[i : i + cols] for i in range(0, len(tiles), cols)]
    rows[-1] += [np.zeros_like(tiles[0])] * (cols - len(rows[-1]))
    grid = [_join(r, axis=1) for r in rows]
    return _join(grid, axis=0)


def _join(tiles: list[np.ndarray], axis: int, gap: int = 2) -> np.ndarray:
    """Concatenates images along ``axis`` with a black ``gap`` between them."""
    parts = [tiles[0]]
    for t in tiles[1:]:
        shape = list(t.shape)
        shape[axis] = gap
        parts += [np.zeros(shape, np.uint8), t]
    return np.concatenate(parts, axis=axis)


def presets_sheet(scale: float) -> np.ndarray:
    """Every material preset (sl.material_sheet), 96-pixel cells at scale 1."""
    return sl.material_sheet(cell=max(16, round(96 * scale)), columns=8, labels=scale >= 0.5)


def save_png(img: np.ndarray, path: Path) -> None:
    Image.fromarray(img, "RGB").save(path, optimize=True)


def names() -> list[str]:
    """File stems of every image the script writes."""
    return [f.name for f in FIGURES] + ["presets"]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=HERE, help="output directory (docs/lighting)")
    ap.add_argument("--scale", type=float, default=1.0, help="panel size factor (tests: 0.25)")
    ap.add_argument("--only", nargs="*", help="figure names (default: all)")
    a = ap.parse_args(argv)
    a.out.mkdir(parents=True, exist_ok=True)
    wanted = set(a.only or names())
    unknown = wanted - set(names())
    if unknown:
        ap.error(f"unknown figure(s) {sorted(unknown)}; known: {names()}")
    for fig in FIGURES:
        if fig.name in wanted:
            save_png(render_figure(fig, a.scale), a.out / f"{fig.name}.png")
            print(f"{fig.name}.png: {fig.caption}")
    if "presets" in wanted:
        save_png(presets_sheet(a.scale), a.out / "presets.png")
        print("presets.png: every material preset")
    return 0


if __name__ == "__main__":
    sys.exit(main())
