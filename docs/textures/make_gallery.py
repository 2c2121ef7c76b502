#!/usr/bin/env python3
"""Renders the texture gallery of docs/USER_GUIDE.md ("Textures") into docs/textures/.

One script for every picture; each is a row of labelled panels, and each panel is one
``sl.render`` of a scene built below (the Spot picture is the command line's own render).

    python docs/textures/make_gallery.py              # all pictures into docs/textures/
    python docs/textures/make_gallery.py --out DIR    # elsewhere
    python docs/textures/make_gallery.py --only normal_maps crease   # some of them
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import shadelab_rs as sl
from PIL import Image, ImageDraw

HERE = Path(__file__).resolve().parent
PANEL = (280, 210)
LABEL_H = 16


def sphere(rings: int = 48, segments: int = 96) -> sl.Mesh:
    """A unit sphere with UVs (u around from -z through +x, v from the south pole up),
    its seam column duplicated so u runs 0..1 without wrapping back."""
    th = np.linspace(0, np.pi, rings + 1)
    ph = np.linspace(0, 2 * np.pi, segments + 1)
    t, p = np.meshgrid(th, ph, indexing="ij")
    v = np.stack([np.sin(t) * np.sin(p), np.cos(t), -np.sin(t) * np.cos(p)], -1).reshape(-1, 3)
    uv = np.stack([p / (2 * np.pi), 1 - t / np.pi], -1).reshape(-1, 2)
    faces = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * (segments + 1) + j, i * (segments + 1) + j + 1
            c, d = a + segments + 1, b + segments + 1
            faces += [[a, d, c], [a, b, d]]  # counter-clockwise seen from outside
    return sl.Mesh(v, np.array(faces), normals=v, uvs=uv)


def floor(extent: float = 40.0, uv_scale: float = 0.5) -> sl.Mesh:
    """A floor quad at y = 0 running to the horizon, one UV unit per 1/uv_scale metres."""
    v = np.array(
        [[-extent, 0, 2], [extent, 0, 2], [extent, 0, -2 * extent], [-extent, 0, -2 * extent]]
    )
    uv = v[:, [0, 2]] * [uv_scale, -uv_scale]
    return sl.Mesh(v, [[0, 1, 2], [0, 2, 3]], normals=np.tile([0, 1, 0], (4, 1)), uvs=uv)


def checker_image(n: int = 8, texels: int = 8) -> np.ndarray:
    """An n x n checkerboard image, ``texels`` texels per check."""
    k = (np.indices((n * texels, n * texels)) // texels).sum(axis=0) % 2
    return np.where(k[..., None] == 0, 0.9, 0.1).astype(np.float32) * np.ones(3, np.float32)


def lit(scene: sl.Scene) -> sl.Scene:
    scene.add_light(sl.DirectionalLight((-0.4, -1.0, -0.6), intensity=0.9))
    scene.add_light(sl.PointLight((2.5, 2.0, 3.0), intensity=0.6))
    return scene


def render(scene: sl.Scene, camera: sl.Camera, **kw: Any) -> np.ndarray:
    return sl.render(
        scene, camera, width=PANEL[0], height=PANEL[1], background=(0.05, 0.05, 0.07), **kw
    )


def labelled_row(panels: list[tuple[str, np.ndarray]]) -> Image.Image:
    w, h = PANEL
    out = Image.new("RGB", (w * len(panels), h + LABEL_H), (255, 255, 255))
    draw = ImageDraw.Draw(out)
    for k, (label, img) in enumerate(panels):
        out.paste(Image.fromarray(img), (k * w, LABEL_H))
        draw.text((k * w + 4, 2), label, fill=(0, 0, 0))
    return out


SPHERE_CAM = sl.Camera.look_at((0, 0.6, 3.2), (0, 0, 0), fov_y=40)
FLOOR_CAM = sl.Camera.look_at((0, 1.0, 2.0), (0, 0, -8), fov_y=60)


def filters() -> Image.Image:
    """A checkerboard floor to the horizon: nearest and bilinear alias, trilinear greys,
    anisotropic filtering keeps the checks further."""
    panels = []
    for f, aniso in (("nearest", 1), ("bilinear", 1), ("trilinear", 1), ("trilinear", 16)):
        tex = sl.Texture(checker_image(), filter=f, anisotropy=aniso)
        scene = lit(sl.Scene())
        scene.add(
            floor(), material=sl.Material((0.3,) * 3, (0.8,) * 3, (0, 0, 0), 1, diffuse_map=tex)
        )
        label = f'filter="{f}"' + (f", anisotropy={aniso}" if aniso > 1 else "")
        panels.append((label, render(scene, FLOOR_CAM)))
    return labelled_row(panels)


def wraps() -> Image.Image:
    """A picture on a square whose UVs run from -1 to 2: repeat, clamp, mirror."""
    img = np.zeros((32, 32, 3), np.float32)
    img[..., 0] = np.linspace(0, 1, 32)[None, :]
    img[..., 2] = np.linspace(1, 0, 32)[:, None]
    img[:6, :6] = 1.0  # a white corner at the top-left (u = 0, v = 1)
    v = np.array([[-1.5, -1.5, 0], [1.5, -1.5, 0], [1.5, 1.5, 0], [-1.5, 1.5, 0]], float)
    mesh = sl.Mesh(v, [[0, 1, 2], [0, 2, 3]], uvs=[[-1, -1], [2, -1], [2, 2], [-1, 2]])
    cam = sl.Camera.look_at((0, 0, 4.2), (0, 0, 0), fov_y=45)
    panels = []
    for w in ("repeat", "clamp", "mirror"):
        tex = sl.Texture(img, filter="bilinear", wrap=w)
        scene = sl.Scene(ambient=(1, 1, 1))
        scene.add(mesh, material=sl.Material((1,) * 3, (0,) * 3, (0,) * 3, 1, diffuse_map=tex))
        panels.append((f'wrap="{w}"', render(scene, cam)))
    return labelled_row(panels)


def procedural() -> Image.Image:
    """The procedural textures on spheres."""
    mesh = sphere()
    panels = []
    for name, kw in (
        ("checker", {"scale": 8}),
        ("grid", {"scale": 8, "width": 0.12}),
        ("stripes", {"scale": 10}),
        ("noise", {"scale": 6, "octaves": 5}),
    ):
        tex = sl.Texture.procedural(name, color_a=(0.95, 0.9, 0.8), color_b=(0.1, 0.25, 0.6), **kw)
        scene = lit(sl.Scene())
        scene.add(mesh, material=sl.Material(diffuse_map=tex, specular=(0.4,) * 3, shininess=40))
        panels.append((f'procedural("{name}")', render(scene, SPHERE_CAM)))
    return labelled_row(panels)


def maps() -> Image.Image:
    """One material, maps added: the specular highlight stays the light's colour; a
    shininess map scales the exponent per pixel."""
    mesh = sphere()
    stripes = sl.Texture.procedural(
        "stripes", scale=10, color_a=(1, 0.2, 0.1), color_b=(0.2, 0.4, 1)
    )
    spots = sl.Texture.procedural("checker", scale=6, color_a=(1, 1, 1), color_b=(0, 0, 0))
    glow = sl.Texture.procedural(
        "grid", scale=8, width=0.08, color_a=(0, 0, 0), color_b=(1, 0.8, 0.2)
    )
    # Shininess x 0.1 (a broad sheen) on one half of each check, x 4 (a tight spark) on the other.
    rough = sl.Texture.procedural("checker", scale=6, color_a=(0.1,) * 3, color_b=(4.0,) * 3)
    base = sl.Material((0.3,) * 3, (0.9,) * 3, (0.7,) * 3, 40, emission=(1, 1, 1))
    panels = []
    for label, m in (
        (
            "diffuse_map",
            base.with_maps(
                diffuse_map=stripes, emission_map=sl.Texture(np.zeros((1, 1, 3), np.float32))
            ),
        ),
        (
            "+ specular_map",
            base.with_maps(
                diffuse_map=stripes,
                specular_map=spots,
                emission_map=sl.Texture(np.zeros((1, 1, 3), np.float32)),
            ),
        ),
        (
            "+ emission_map",
            base.with_maps(diffuse_map=stripes, specular_map=spots, emission_map=glow),
        ),
        (
            "diffuse_map + shininess_map (x0.1 | x4)",
            base.with_maps(
                diffuse_map=stripes,
                shininess_map=rough,
                emission_map=sl.Texture(np.zeros((1, 1, 3), np.float32)),
            ),
        ),
    ):
        scene = lit(sl.Scene())
        scene.add(mesh, material=m)
        panels.append((label, render(scene, SPHERE_CAM)))
    return labelled_row(panels)


def modes() -> Image.Image:
    """Every shading mode samples per pixel: the texture is as sharp in each."""
    tex = sl.bake_texture(
        lambda u, v: np.stack(
            [0.5 + 0.5 * np.sin(40 * u), 0.5 + 0.5 * np.sin(20 * v), 0.6 + 0 * u], -1
        ),
        512,
        256,
    )
    mesh = sphere(12, 24)
    panels = []
    for shading in ("flat", "gouraud", "phong"):
        scene = lit(sl.Scene())
        scene.add(mesh, material=sl.Material(diffuse_map=tex, specular=(0.5,) * 3, shininess=30))
        panels.append(
            (f'shading="{shading}" (bake_texture)', render(scene, SPHERE_CAM, shading=shading))
        )
    return labelled_row(panels)


def vertex_colors() -> Image.Image:
    """Vertex colours (Mesh(..., colors=)) replace ambient and diffuse, in each mode."""
    base = sl.Mesh.ico_sphere(2)
    v = base.vertices
    colors = 0.5 + 0.5 * v  # the normal as a colour
    mesh = sl.Mesh(v, base.faces, normals=v, colors=colors)
    panels = []
    for shading in ("flat", "gouraud", "phong"):
        scene = lit(sl.Scene())
        scene.add(mesh, material=sl.Material(specular=(0.5,) * 3, shininess=30))
        panels.append((f"colors=, {shading}", render(scene, SPHERE_CAM, shading=shading)))
    return labelled_row(panels)


def shadows() -> Image.Image:
    """Spot with its own texture (its MTL's map_Kd) casting a shadow on a checkerboard
    floor: textured surfaces read each light's visibility like untextured ones."""
    parts = sl.load_obj_parts(sl.data_path("spot/spot_triangulated.obj"))
    lo = np.min([m.vertices.min(axis=0) for _, m, _ in parts], axis=0)
    hi = np.max([m.vertices.max(axis=0) for _, m, _ in parts], axis=0)
    y0, size = float(lo[1]), float((hi - lo).max())
    ground = np.array([[-1, 0, 1], [1, 0, 1], [1, 0, -1], [-1, 0, -1]]) * 3 * size + [0, y0, 0]
    floor_mesh = sl.Mesh(
        ground,
        [[0, 1, 2], [0, 2, 3]],
        normals=np.tile([0, 1, 0], (4, 1)),
        uvs=ground[:, [0, 2]] * 0.25,
    )
    light_grey = np.where(checker_image(8, 8) > 0.5, 0.8, 0.55).astype(np.float32)
    board = sl.Texture(light_grey)
    centre = (lo + hi) / 2
    cam = sl.Camera.look_at(
        centre + np.array([1.5, 0.8, 0.9]) * size, centre - [0, 0.2 * size, 0], fov_y=45
    )
    panels = []
    for label, casts in (
        ("shadows=False", False),
        ("shadows=True (map)", True),
        ('shadows="exact"', "exact"),
    ):
        scene = sl.Scene(ambient=(0.25, 0.25, 0.25))
        for _, mesh, mtl in parts:
            scene.add(mesh, material=mtl)
        scene.add(floor_mesh, material=sl.Material(diffuse=(0.8,) * 3, diffuse_map=board))
        scene.add_light(sl.DirectionalLight((0.4, -1.0, -0.5), intensity=0.9, shadows=casts))
        panels.append((label, render(scene, cam)))
    return labelled_row(panels)


def tile_normals(n: int = 256, tiles: int = 4, bevel: float = 0.12) -> np.ndarray:
    """A tangent-space normal map of bevelled square tiles, encoded as (n + 1)/2."""
    t = ((np.arange(n) + 0.5) / n * tiles) % 1.0
    slope = np.where(t < bevel, 1.0, np.where(t > 1 - bevel, -1.0, 0.0)) * 1.5
    gx = np.broadcast_to(slope[None, :], (n, n))  # height rises along u into a tile
    gy = np.broadcast_to(-slope[:, None], (n, n))  # rows run down the image (v falls)
    nrm = np.stack([-gx, -gy, np.ones((n, n))], -1)
    nrm /= np.linalg.norm(nrm, axis=-1, keepdims=True)
    return ((nrm + 1) / 2).astype(np.float32)


def normal_maps() -> Image.Image:
    """Tangent-space normal maps and bump maps on a sphere (Phong): the silhouette stays
    round, the lighting follows the map."""
    mesh = sphere()
    # One tile per texture, 12 around and 6 from pole to pole (the UVs span 2:1).
    tiles = sl.Texture(tile_normals(tiles=1, bevel=0.1)).with_uv_transform((12, 6), (0, 0))
    noise = sl.Texture.procedural("noise", scale=24, octaves=3)
    base = sl.Material((0.8, 0.55, 0.3), (0.8, 0.55, 0.3), (0.5,) * 3, 40)
    panels = []
    for label, kw in (
        ("no map", {}),
        ("normal_map=tiles", {"normal_map": tiles}),
        ("normal_map=tiles, normal_scale=-1", {"normal_map": tiles, "normal_scale": -1.0}),
        ("bump_map=noise, bump_scale=0.004", {"bump_map": noise, "bump_scale": 0.004}),
    ):
        scene = lit(sl.Scene())
        scene.add(mesh, material=base.with_maps(**kw))
        panels.append((label, render(scene, SPHERE_CAM, shading="phong")))
    return labelled_row(panels)


def crease() -> Image.Image:
    """A box with 8 shared corners: smooth normals make a pillow, a crease angle keeps
    it a box; a sphere stays smooth at the same angle."""
    c = sl.Mesh.cube()
    pos, inv = np.unique(c.vertices, axis=0, return_inverse=True)
    box = sl.Mesh(pos, inv.reshape(-1)[c.faces])  # 8 corners, normals averaged
    ball = sl.Mesh.ico_sphere(2)
    cam = sl.Camera.look_at((2.2, 1.8, 3.0), (0, 0, 0), fov_y=35)
    panels = []
    for label, mesh in (
        ("8-corner box", box),
        ("box.with_normals(crease_angle=30)", box.with_normals(crease_angle=30)),
        ("ico_sphere(2).with_normals(crease_angle=30)", ball.with_normals(crease_angle=30)),
    ):
        scene = lit(sl.Scene())
        scene.add(mesh, material=sl.Material.preset("pewter"))
        panels.append((label, render(scene, cam, shading="phong")))
    return labelled_row(panels)


FIGURES = {
    "filters": filters,
    "wrap": wraps,
    "procedural": procedural,
    "maps": maps,
    "modes": modes,
    "vertex_colors": vertex_colors,
    "shadows": shadows,
    "normal_maps": normal_maps,
    "crease": crease,
}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=HERE)
    p.add_argument("--only", nargs="+", choices=[*FIGURES, "spot"], help="these pictures only")
    args = p.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for name, make in FIGURES.items():
        if args.only and name not in args.only:
            continue
        make().save(args.out / f"{name}.png", optimize=True)
        print(f"wrote {args.out / name}.png")
    if args.only and "spot" not in args.only:
        return
    # Spot, by the command line on the bundled OBJ: its MTL names its texture.
    spot = sl.data_path("spot/spot_triangulated.obj")
    cmd = [sys.executable, "-m", "shadelab_rs", "render", str(spot), "--view", "left"]
    cmd += ["--size", "480x360", "-o", str(args.out / "spot.png")]
    subprocess.run(cmd, check=True)


if __name__ == "__main__":
    main()
