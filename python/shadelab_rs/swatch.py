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
    Texture,
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


def _tile_normals(n: int = 64, tiles: int = 1) -> np.ndarray:
    """A tangent-space normal map of rounded square tiles (``tiles`` per side, edges
    bevelled), encoded as (n + 1)/2, float32."""
    t = ((np.arange(n) + 0.5) / n * tiles) % 1.0  # position inside a tile, 0..1
    # Height: a plateau with a bevel of 0.15 at each edge; its slope is the normal.
    edge = 0.15
    slope = np.where(t < edge, 1.0, np.where(t > 1 - edge, -1.0, 0.0)) * 1.5
    gx = np.broadcast_to(slope[None, :], (n, n))  # along u (columns)
    gy = np.broadcast_to(-slope[:, None], (n, n))  # along v (rows run down the image)
    nrm = np.stack([-gx, -gy, np.ones((n, n))], axis=-1)
    nrm /= np.linalg.norm(nrm, axis=-1, keepdims=True)
    return ((nrm + 1.0) / 2.0).astype(np.float32)


def _texture_swatches() -> dict[str, Material]:
    warm, cool = (0.9, 0.6, 0.3), (0.2, 0.3, 0.6)
    plain = Material((0.8, 0.55, 0.3), (0.8, 0.55, 0.3), (0.5, 0.5, 0.5), 40.0)

    def diffuse(tex: Texture) -> Material:
        return Material((1.0, 1.0, 1.0), (0.8, 0.8, 0.8), (0.4, 0.4, 0.4), 40.0, diffuse_map=tex)

    return {
        "checker": diffuse(Texture.procedural("checker", 8, color_a=warm, color_b=cool)),
        "grid": diffuse(Texture.procedural("grid", 12)),
        "stripes": diffuse(Texture.procedural("stripes", 10, color_a=warm, color_b=(1, 1, 1))),
        "noise": diffuse(Texture.procedural("noise", 6, color_a=warm, color_b=cool)),
        "bump map": plain.with_maps(
            bump_map=Texture.procedural("noise", 24, octaves=3), bump_scale=0.004
        ),
        "normal map": plain.with_maps(
            normal_map=Texture(_tile_normals(64, 1)).with_uv_transform((8, 4), (0, 0))
        ),
    }


#: Textured swatches (names ``material_sheet`` also takes; ``textures=True`` adds them as
#: rows of their own): procedural diffuse maps (checker, grid, stripes, noise), a bump
#: map of value noise and a normal map of bevelled tiles. Made on first use.
TEXTURE_SWATCH_NAMES: tuple[str, ...] = (
    "checker",
    "grid",
    "stripes",
    "noise",
    "bump map",
    "normal map",
)

_TEXTURE_SWATCHES: dict[str, Material] = {}


def texture_swatch(name: str) -> Material:
    """The textured swatch ``name`` (one of :data:`TEXTURE_SWATCH_NAMES`)."""
    if not _TEXTURE_SWATCHES:
        _TEXTURE_SWATCHES.update(_texture_swatches())
    return _TEXTURE_SWATCHES[name]


def uv_sphere_with_uvs(rings: int = 48, segments: int = 96) -> Mesh:
    """A unit latitude-longitude sphere with UVs (u around from +z, v from the south pole
    up; the seam's vertices doubled) and exact normals."""
    th = np.linspace(0.0, np.pi, rings + 1)[:, None]
    ph = np.linspace(0.0, 2 * np.pi, segments + 1)[None, :]
    x, y, z = np.sin(th) * np.sin(ph), np.cos(th) * np.ones_like(ph), np.sin(th) * np.cos(ph)
    v = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    uu, vv = np.broadcast_arrays(ph / (2 * np.pi), 1.0 - th / np.pi)
    uv = np.stack([uu, vv], axis=-1).reshape(-1, 2)
    i, j = np.meshgrid(np.arange(rings), np.arange(segments), indexing="ij")
    a = (i * (segments + 1) + j).ravel()
    b, c = a + 1, a + segments + 1
    d = c + 1
    faces = np.concatenate([np.stack([a, c, d], 1), np.stack([a, d, b], 1)])
    return Mesh(v, faces, normals=v, uvs=uv)


def _sheet_sky(h: int = 64) -> Environment:
    """Stripes of colour over a sky gradient: enough structure to see bending and mirroring."""
    v = (np.arange(h) + 0.5) / h
    u = (np.arange(2 * h) + 0.5) / (2 * h)
    vv, uu = np.meshgrid(v, u, indexing="ij")
    sky = np.stack([0.3 + 0.5 * vv, 0.5 + 0.2 * vv, 0.9 - 0.5 * vv], axis=-1)
    stripe = (np.floor(uu * 16) % 2)[..., None] * np.array([0.6, 0.2, -0.3])
    return Environment(np.clip(sky + stripe * (vv[..., None] > 0.5), 0, None).astype(np.float32))


def swatch_scene(material: Material, uvs: bool = False) -> tuple[Scene, Camera]:
    """A unit sphere in ``material`` under a white key light from the upper left and a weak
    fill light, seen from +z: the scene each sheet cell shows. ``uvs``: the sphere with
    texture coordinates (:func:`uv_sphere_with_uvs`), for textured materials."""
    scene = Scene(ambient=(0.3, 0.3, 0.3))
    mesh = uv_sphere_with_uvs(48, 96) if uvs else Mesh.uv_sphere(48, 96)
    scene.add(mesh, material=material)
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
    textures: bool = False,
) -> np.ndarray:
    """An (H, W, 3) uint8 image with one sphere per preset in ``names`` (default: all, in
    table order), ``columns`` per row, each ``cell`` pixels square, with its name underneath
    when ``labels`` is true (drawn with Pillow's default font), on a mid-grey background.
    ``names`` may also hold the optical swatches "glass", "water", "diamond" and "mirror"
    (:data:`OPTICAL_SWATCHES`), drawn against a striped sky with ray-traced reflection and
    refraction, and the textured swatches of :data:`TEXTURE_SWATCH_NAMES`; ``textures``:
    the textured swatches are added after ``names``, starting a row of their own. The
    "bump map" and "normal map" swatches are lit per pixel (Phong) whatever ``shading``
    says (flat and Gouraud refuse those maps)."""
    names = list(Material.preset_names() if names is None else names)
    for name in names:
        if name not in OPTICAL_SWATCHES and name not in TEXTURE_SWATCH_NAMES:
            Material.preset(name)  # an unknown name is a ValueError listing the presets
    if textures:
        if columns >= 1 and names:
            names += [""] * (-len(names) % min(columns, len(names) + len(TEXTURE_SWATCH_NAMES)))
        names += TEXTURE_SWATCH_NAMES
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
        if not name:
            continue  # padding before the textured rows
        if name in TEXTURE_SWATCH_NAMES:
            m = texture_swatch(name)
            scene, camera = swatch_scene(m, uvs=True)
            per_pixel = m.normal_map is not None or m.bump_map is not None
            img = render(
                scene,
                camera,
                width=cell,
                height=cell,
                shading="phong" if per_pixel else shading,
                background=_BACKGROUND,
            )
        elif name in OPTICAL_SWATCHES:
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
