"""Command line: ``shadelab render``, ``shadelab demo``, ``shadelab materials``."""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from . import _core as core
from .demo import demo_scene, frame_mesh
from .io import load_mesh, save_image
from .scene_file import frame_scene, load_scene
from .swatch import material_sheet


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 800x600, got '{text}'") from None
    return w, h


def _triple(text: str) -> tuple[float, float, float]:
    try:
        vals = tuple(float(v) for v in text.split(","))
    except ValueError:
        vals = ()
    if len(vals) != 3:
        raise argparse.ArgumentTypeError(f"expected three comma-separated numbers, got '{text}'")
    return vals  # type: ignore[return-value]


def _render_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("-o", "--output", default="out.png", help="image file to write (PNG, JPEG)")
    p.add_argument("--size", type=_size, default=None, help="WIDTHxHEIGHT (800x600)")
    p.add_argument("--shading", choices=core.RenderOptions.shading_names, default=None)
    p.add_argument("--specular", choices=core.RenderOptions.specular_names, default=None)
    p.add_argument("--background", type=_triple, default=None, help="r,g,b in [0,1] (0,0,0)")
    p.add_argument("--threads", type=int, default=None, help="worker threads (default: all)")
    p.add_argument("--cull-backfaces", action="store_true", default=None)


def _render(
    scene: core.Scene,
    camera: core.Camera,
    args: argparse.Namespace,
    file_options: dict[str, Any] | None = None,
) -> None:
    """Renders with a scene file's options updated by the flags given."""
    flags = {k: getattr(args, k) for k in ("shading", "specular", "background", "threads")}
    flags["cull_backfaces"] = args.cull_backfaces
    if args.size is not None:
        flags["width"], flags["height"] = args.size
    given = {k: v for k, v in flags.items() if v is not None}
    opts = core.RenderOptions(**{**(file_options or {}), **given})
    t0 = time.perf_counter()
    img = core.render(scene, camera, options=opts)
    dt = (time.perf_counter() - t0) * 1e3
    save_image(img, args.output)
    w, h = opts.width, opts.height
    print(f"wrote {args.output} ({w}x{h}, {scene.n_triangles} triangles, {dt:.1f} ms)")


# Options of `render MODEL` that a scene file sets itself.
_MODEL_ONLY = ("material", "ambient", "fov", "view", "eye", "target", "up", "light")


def cmd_render_scene(args: argparse.Namespace) -> None:
    given = [k for k in _MODEL_ONLY if getattr(args, k) is not None]
    if given:
        flags = ", ".join("--" + k for k in given)
        raise ValueError(f"{flags} cannot be used with a scene file; set it in the file")
    sf = load_scene(args.model)
    camera = sf.camera if sf.camera is not None else frame_scene(sf.scene)
    _render(sf.scene, camera, args, sf.render_options)


def _add_model(scene: core.Scene, path: str, preset: str | None) -> np.ndarray:
    """Adds the model at ``path`` to ``scene``; returns all its vertices (for framing).

    An OBJ keeps its MTL materials, one per group and ``usemtl`` run, unless a preset is
    given; parts without one (and other formats) get the preset, gold by default."""
    fallback = core.Material.preset(preset or "gold")
    if os.fspath(path).lower().endswith(".obj"):
        parts = core.load_obj_parts(path)
        for _, mesh, mtl in parts:
            scene.add(mesh, material=fallback if preset or mtl is None else mtl)
        return np.concatenate([mesh.vertices for _, mesh, _ in parts])
    mesh = load_mesh(path)
    scene.add(mesh, material=fallback)
    return mesh.vertices


def cmd_render(args: argparse.Namespace) -> None:
    if Path(args.model).suffix.lower() == ".toml":
        cmd_render_scene(args)
        return
    scene = core.Scene(ambient=args.ambient if args.ambient is not None else (0.2, 0.2, 0.2))
    vertices = _add_model(scene, args.model, args.material)
    fov = args.fov if args.fov is not None else 35.0
    view = args.view if args.view is not None else (0.55, 0.35, 1.0)
    camera = frame_mesh(vertices, fov_y=fov, direction=view)
    if args.eye is not None:
        target = args.target if args.target is not None else camera.target
        camera = core.Camera.look_at(
            eye=args.eye,
            target=target,
            up=args.up if args.up is not None else (0.0, 1.0, 0.0),
            fov_y=fov,
            near=camera.near,
            far=camera.far,
        )
    for d in args.light or [(-0.5, -1.0, -0.8)]:
        scene.add_light(core.DirectionalLight(direction=d))
    _render(scene, camera, args)


def cmd_demo(args: argparse.Namespace) -> None:
    scene, camera = demo_scene()
    _render(scene, camera, args)


def cmd_materials(args: argparse.Namespace) -> None:
    for name in core.Material.preset_names():
        m = core.Material.preset(name)
        fmt = lambda v: " ".join(f"{x:.6g}" for x in v)  # noqa: E731
        print(
            f"{name:16s} ambient {fmt(m.ambient):28s} diffuse {fmt(m.diffuse):28s} "
            f"specular {fmt(m.specular):28s} shininess {m.shininess:g}"
        )
    if args.sheet is not None:
        sheet = material_sheet(cell=args.cell, columns=args.columns)
        save_image(sheet, args.sheet)
        h, w = sheet.shape[:2]
        print(f"wrote {args.sheet} ({w}x{h}, one sphere per preset)", file=sys.stderr)


def cmd_figures(args: argparse.Namespace) -> None:
    from .figures import lecture_figures

    for path in lecture_figures(args.output):
        print(f"wrote {path}")


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``shadelab`` command; returns the exit status."""
    parser = argparse.ArgumentParser(prog="shadelab", description=__doc__)
    parser.add_argument("--version", action="version", version=core.__version__)
    sub = parser.add_subparsers(dest="command", required=True)

    r = sub.add_parser(
        "render",
        help="render a mesh file (OBJ, or anything trimesh reads) or a scene file (.toml)",
    )
    r.add_argument("model", help="mesh file, or a scene file (.toml; see the user guide)")
    r.add_argument(
        "--material",
        default=None,
        help="preset for the whole model (see 'shadelab materials'); default: the OBJ's MTL "
        "materials, gold where it has none",
    )
    r.add_argument("--ambient", type=_triple, default=None, help="scene ambient r,g,b (0.2,...)")
    r.add_argument("--fov", type=float, default=None, help="vertical field of view, degrees (35)")
    r.add_argument(
        "--view",
        type=_triple,
        default=None,
        help="direction from the model's centre to the camera (x,y,z; 0.55,0.35,1)",
    )
    r.add_argument("--eye", type=_triple, default=None, help="explicit camera position x,y,z")
    r.add_argument("--target", type=_triple, default=None, help="point looked at (with --eye)")
    r.add_argument("--up", type=_triple, default=None, help="camera up x,y,z (0,1,0)")
    r.add_argument(
        "--light",
        type=_triple,
        action="append",
        help="directional light travel direction x,y,z (repeatable)",
    )
    _render_args(r)
    r.set_defaults(func=cmd_render)

    d = sub.add_parser("demo", help="render the built-in demo scene")
    _render_args(d)
    d.set_defaults(func=cmd_demo, output="demo.png")

    m = sub.add_parser("materials", help="list the material presets (and render a swatch sheet)")
    m.add_argument("--sheet", default=None, help="also write an image with a sphere per preset")
    m.add_argument("--cell", type=int, default=128, help="pixels per swatch (128)")
    m.add_argument("--columns", type=int, default=6, help="swatches per row (6)")
    m.set_defaults(func=cmd_materials)

    f = sub.add_parser("figures", help="render the lecture figures (PNGs and captions.md)")
    f.add_argument("-o", "--output", default="figures", help="directory to write (figures)")
    f.set_defaults(func=cmd_figures)

    args = parser.parse_args(argv)
    try:
        args.func(args)
    except (ValueError, TypeError, OSError, MemoryError, RuntimeError) as e:
        # One line whatever the message (docs/USER_GUIDE.md, "Command line": exit status).
        message = " ".join(str(e).split("\n")) or type(e).__name__
        print(f"shadelab: error: {message}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
