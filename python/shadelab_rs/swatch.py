"""Material swatches: one lit sphere per preset, laid out as a labelled contact sheet."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np

from ._core import (
    Camera,
    DirectionalLight,
    Environment,
    Material,
    Mesh,
    PointLight,
    Scene,
    render,
)

_LABEL_HEIGHT = 14
# Mid grey, so that dark presets (black plastic, obsidian) stand out.
_BACKGROUND = (0.22, 0.22, 0.24)


#: Swatches beyond the presets (names ``material_sheet`` also takes): clear glass, water and
#: diamond (the lectures' indices, Fresnel on) and a mirror, each seen against the sheet's
#: environment with ray-traced reflection and refraction.
OPTICAL_SWATCHES: dict[str, Material] = {
    "glass": Material((0, 0, 0), (0, 0, 0), (1, 1, 1), 200.0, transparency=0.95, ior="glass"),
    "water": Material(
        (0, 0, 0),
        (0, 0, 0),
        (1, 1, 1),
        200.0,
        transparency=0.95,
        ior="water",
        absorption=(0.3, 0.08, 0.05),
    ),
    "diamond": Material((0, 0, 0), (0, 0, 0), (1, 1, 1), 400.0, transparency=0.98, ior="diamond"),
    "mirror": Material((0, 0, 0), (0.05, 0.05, 0.05), (0, 0, 0), 1.0, reflectivity=0.95),
}


def _sheet_sky(h: int = 64) -> Environment:
    """Stripes of colour over a sky gradient: enough structure to see bending and mirroring."""
    v = (np.arange(h) + 0.5) / h
    u = (np.arange(2 * h) + 0.5) / (2 * h)
    vv, uu = np.meshgrid(v, u, indexing="ij")
    sky = np.stack([0.3 + 0.5 * vv, 0.5 + 0.2 * vv, 0.9 - 0.5 * vv], axis=-1)
    stripe = (np.floor(uu * 16) % 2)[..., None] * np.array([0.6, 0.2, -0.3])
    return Environment(np.clip(sky + stripe * (vv[..., None] > 0.5), 0, None).astype(np.float32))


def swatch_scene(material: Material) -> tuple[Scene, Camera]:
    """A unit sphere in ``material`` under a white key light from the upper left and a weak
    fill light, seen from +z: the scene each sheet cell shows."""
    scene = Scene(ambient=(0.3, 0.3, 0.3))
    scene.add(Mesh.uv_sphere(48, 96), material=material)
    scene.add_light(DirectionalLight(direction=(0.6, -0.7, -0.8)))
    scene.add_light(PointLight(position=(4.0, 1.0, 3.0), color=(0.3, 0.3, 0.3)))
    camera = Camera.look_at(eye=(0, 0, 3.2), target=(0, 0, 0), fov_y=40.0, near=1.0, far=10.0)
    return scene, camera


def material_sheet(
    names: Sequence[str] | None = None,
    cell: int = 128,
    columns: int = 6,
    shading: Literal["flat", "gouraud", "phong"] = "phong",
    labels: bool = True,
) -> np.ndarray:
    """An (H, W, 3) uint8 image with one sphere per preset in ``names`` (default: all, in
    table order), ``columns`` per row, each ``cell`` pixels square, with its name underneath
    when ``labels`` is true (drawn with Pillow's default font), on a mid-grey background.
    ``names`` may also hold the optical swatches "glass", "water", "diamond" and "mirror"
    (:data:`OPTICAL_SWATCHES`), drawn against a striped sky with ray-traced reflection and
    refraction."""
    names = list(Material.preset_names() if names is None else names)
    for name in names:
        if name not in OPTICAL_SWATCHES:
            Material.preset(name)  # an unknown name is a ValueError listing the presets
    if not names:
        raise ValueError("names must not be empty")
    if not 16 <= cell <= 2048:
        raise ValueError(f"cell must be between 16 and 2048 pixels, got {cell}")
    if columns < 1:
        raise ValueError(f"columns must be >= 1, got {columns}")
    columns = min(columns, len(names))
    rows = -(-len(names) // columns)
    label_h = _LABEL_HEIGHT if labels else 0
    sheet = np.zeros((rows * (cell + label_h), columns * cell, 3), dtype=np.uint8)
    for i, name in enumerate(names):
        if name in OPTICAL_SWATCHES:
            scene, camera = swatch_scene(OPTICAL_SWATCHES[name])
            scene.environment = _sheet_sky()
            img = render(
                scene,
                camera,
                width=cell,
                height=cell,
                shading=shading,
                background="environment",
                reflections="ray",
                refractions="ray",
            )
        else:
            scene, camera = swatch_scene(Material.preset(name))
            img = render(
                scene, camera, width=cell, height=cell, shading=shading, background=_BACKGROUND
            )
        r, c = divmod(i, columns)
        y, x = r * (cell + label_h), c * cell
        sheet[y : y + cell, x : x + cell] = img
    if labels:
        from PIL import Image, ImageDraw

        pil = Image.fromarray(sheet, "RGB")
        draw = ImageDraw.Draw(pil)
        for i, name in enumerate(names):
            r, c = divmod(i, columns)
            y, x = r * (cell + label_h) + cell, c * cell
            draw.text((x + 3, y + 1), name, fill=(230, 230, 230))
        sheet = np.asarray(pil).copy()
    return sheet
