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


# Render options and their defaults. The command-line flags default to None so that a
# scene file's [render] table applies unless a flag is given.
_RENDER_DEFAULTS: dict[str, Any] = {
    "width": 800,
    "height": 600,
    "shading": "phong",
    "specular": "blinn",
    "background": (0.0, 0.0, 0.0),
    "cull_backfaces": False,
    "threads": None,
}


def _render_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("-o", "--output", default="out.png", help="image file to write (PNG, JPEG)")
    p.add_argument("--size", type=_size, default=None, help="WIDTHxHEIGHT (800x600)")
    p.add_argument("--shading", choices=["flat", "gouraud", "phong"], default=None)
    p.add_argument("--specular", choices=["blinn", "phong", "blinn-normalized"], default=None)
    p.add_argument("--background", type=_triple, default=None, help="r,g,b in [0,1] (0,0,0)")
    p.add_argument("--threads", type=int, default=None, help="worker threads (default: all)")
    p.add_argument("--cull-backfaces", action="store_true", default=None)
    p.add_argument(
        "--cameras",
        default=None,
        metavar="FILE",
        help="render every camera of FILE (TOML [[cameras]] or JSON list, scene-file camera "
        "schema) into numbered images, as --views",
    )
    p.add_argument(
        "--views",
        type=int,
        default=None,
        help="turntable: N views around the up axis through the target, written as numbered "
        "images (OUTPUT with a {:04d} field, or OUTPUT_0000.png ...)",
    )


def _render(
    scene: core.Scene,
    camera: core.Camera,
    args: argparse.Namespace,
    file_options: dict[str, Any] | None = None,
) -> None:
    """Renders with the defaults, updated by a scene file's options, updated by the flags."""
    opts = {**_RENDER_DEFAULTS, **(file_options or {})}
    if args.size is not None:
        opts["width"], opts["height"] = args.size
    for k in ("shading", "specular", "background", "cull_backfaces", "threads"):
        if getattr(args, k) is not None:
            opts[k] = getattr(args, k)
    w, h = opts["width"], opts["height"]
    if args.views is not None and args.cameras is not None:
        raise ValueError("--views and --cameras cannot be used together")
    if args.views is not None:
        if args.views < 1:
            raise ValueError(f"--views must be >= 1, got {args.views}")
        _render_many(scene, turntable(camera, args.views), args.output, opts)
        return
    if args.cameras is not None:
        _render_many(scene, load_cameras(args.cameras), args.output, opts)
        return
    t0 = time.perf_counter()
    img = core.render(scene, camera, **opts)
    dt = (time.perf_counter() - t0) * 1e3
    save_image(img, args.output)
    print(f"wrote {args.output} ({w}x{h}, {scene.n_triangles} triangles, {dt:.1f} ms)")


def turntable(camera: core.Camera, views: int) -> list[core.Camera]:
    """``views`` cameras evenly spaced on the circle the eye of ``camera`` describes about
    the axis through its target along its up vector (view 0 is ``camera`` itself)."""
    target = np.asarray(camera.target, np.float64)
    axis = np.asarray(camera.up, np.float64)
    axis = axis / np.linalg.norm(axis)
    r = np.asarray(camera.eye, np.float64) - target
    cams = []
    for k in range(views):
        a = 2.0 * np.pi * k / views
        # Rodrigues' rotation of r about the axis by a.
        rk = r * np.cos(a) + np.cross(axis, r) * np.sin(a) + axis * (axis @ r) * (1 - np.cos(a))
        eye = tuple(target + rk)
        if camera.kind == "perspective":
            cam = core.Camera.look_at(
                eye, camera.target, camera.up, camera.fov_y or 45.0, camera.near, camera.far
            )
        else:
            cam = core.Camera.orthographic(
                eye, camera.target, camera.up, camera.height or 2.0, camera.near, camera.far
            )
        cams.append(cam)
    return cams


def _numbered(output: str) -> str:
    """``output`` as a format pattern for a frame number: kept when it holds a ``{}``
    field, else ``name_{:04d}.ext``."""
    if "{" in output:
        return output
    p = Path(output)
    return str(p.with_name(f"{p.stem}_{{:04d}}{p.suffix}"))


def load_cameras(path: str | os.PathLike[str]) -> list[core.Camera]:
    """The cameras of a file: TOML with an array of tables ``[[cameras]]``, or JSON (a list,
    or an object with a ``"cameras"`` list), each camera in the scene-file schema (``type``,
    ``eye``, ``target``, ``up``, ``fov_y`` or ``height``, ``near``, ``far``). Errors name the
    file and the key path (``cameras[3].fov_y``)."""
    import json

    from .scene_file import SceneFileError, _camera, tomllib

    p = Path(path)
    where = str(p)
    try:
        if p.suffix.lower() == ".json":
            doc: Any = json.loads(p.read_text())
        else:
            with p.open("rb") as f:
                doc = tomllib.load(f)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as e:
        raise SceneFileError(f"cannot parse: {e}", "", where) from None
    cams = doc.get("cameras") if isinstance(doc, dict) else doc
    if not isinstance(cams, list) or not cams:
        raise SceneFileError("expected a non-empty list of cameras", "cameras", where)
    try:
        return [_camera(c, f"cameras[{i}]") for i, c in enumerate(cams)]
    except SceneFileError as e:
        raise SceneFileError(e.detail, e.key, where) from None


def _render_many(
    scene: core.Scene, cameras: list[core.Camera], output: str, opts: dict[str, Any]
) -> None:
    from .batch import render_batch

    views = len(cameras)
    pattern = _numbered(output)
    try:
        names = [pattern.format(i) for i in range(views)]
    except (IndexError, KeyError, ValueError) as e:
        raise ValueError(
            f"output pattern {output!r} is not a valid frame-number pattern: {e}"
        ) from None
    if len(set(names)) != views:
        raise ValueError(f"output pattern {output!r} gives several frames the same name")
    Path(names[0]).parent.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    render_batch(
        scene,
        cameras,
        callback=lambda i, img: save_image(img, names[i]),
        **opts,
    )
    dt = time.perf_counter() - t0
    w, h = opts["width"], opts["height"]
    print(
        f"wrote {views} views {names[0]} ... {names[-1]} ({w}x{h}, {scene.n_triangles} "
        f"triangles, {dt * 1e3 / views:.1f} ms per view)"
    )


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
    if args.cameras is not None:
        given = [k for k in ("fov", "view", "eye", "target", "up") if getattr(args, k) is not None]
        if given:
            flags = ", ".join("--" + k for k in given)
            raise ValueError(f"{flags} cannot be used with --cameras: the file sets the cameras")
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

    args = parser.parse_args(argv)
    try:
        args.func(args)
    except (ValueError, TypeError, OSError) as e:
        print(f"shadelab: error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
