"""Command line: ``shadelab render``, ``shadelab demo``, ``shadelab materials``."""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from . import _core as core
from .demo import VIEWS, demo_scene, view_direction
from .io import PNG_COMPRESSIONS, file_up_axis, load_environment, load_mesh, save_depth, save_image
from .rendering import EmptyRenderWarning, _finish, render, render_frame
from .scene_file import frame_scene, light_with_shadows, load_scene
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


def _background(text: str) -> str | tuple[float, float, float]:
    """r,g,b or "environment"."""
    return "environment" if text == "environment" else _triple(text)


def _view(text: str) -> str | tuple[float, float, float]:
    """A view name or an x,y,z direction."""
    if text.lower() in VIEWS:
        return text.lower()
    try:
        return _triple(text)
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(
            f"expected a view name ({', '.join(VIEWS)}) or a direction x,y,z, got '{text}'"
        ) from None


def _fmt3(v: Sequence[float]) -> str:
    return ",".join(f"{x:g}" for x in v)


def _check_values(args: argparse.Namespace) -> None:
    """Value checks the parser's types do not make (exit status 1 with one line, like the
    renderer's own errors): nothing is clamped or ignored silently."""
    bg = args.background
    if (
        bg is not None
        and bg != "environment"
        and not all(math.isfinite(c) and 0.0 <= c <= 1.0 for c in bg)
    ):
        hint = " (for 8-bit values divide by 255)" if max(bg) > 1.0 else ""
        raise ValueError(
            f"--background components must be in [0, 1] (linear r,g,b), got {_fmt3(bg)}{hint}"
        )
    vectors = [("--up", getattr(args, "up", None))]
    view = getattr(args, "view", None)
    if view is not None and not isinstance(view, str):
        vectors.append(("--view", view))
    vectors += [("--light", d) for d in getattr(args, "light", None) or []]
    for name, v in vectors:
        if v is not None and not (all(math.isfinite(c) for c in v) and any(v)):
            raise ValueError(f"{name} direction must be finite and non-zero, got {_fmt3(v)}")


def _render_args(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "-o",
        "--output",
        default="out.png",
        help="image file to write (PNG, JPEG, TIFF, .npy; '-' writes PNG to stdout)",
    )
    p.add_argument("--size", type=_size, default=None, help="WIDTHxHEIGHT (800x600)")
    p.add_argument(
        "--shading",
        choices=core.RenderOptions.shading_names,
        default=None,
        help="flat, gouraud, phong, or auto: per object the cheapest mode within --tolerance",
    )
    p.add_argument(
        "--tolerance",
        type=float,
        default=None,
        help="error budget of --shading auto: RMSE in 8-bit levels (1.0)",
    )
    p.add_argument("--specular", choices=core.RenderOptions.specular_names, default=None)
    p.add_argument(
        "--background",
        type=_background,
        default=None,
        help="r,g,b in [0,1] (0,0,0), or 'environment' (the scene's environment)",
    )
    p.add_argument(
        "--environment",
        default=None,
        nargs="+",
        metavar="FILE",
        help="environment lighting reflections and refractions: one equirectangular image "
        "(.npy float, PNG, JPEG), or six square cube faces in the order +X -X +Y -Y +Z -Z",
    )
    p.add_argument("--reflections", choices=["environment", "ray"], default=None)
    p.add_argument(
        "--refractions",
        choices=["none", "environment", "ray"],
        default=None,
        help="none: transparent surfaces blend straight through (sorted per pixel)",
    )
    p.add_argument("--max-depth", type=int, default=None, help="secondary ray segments at most (5)")
    p.add_argument("--threads", type=int, default=None, help="worker threads (default: all)")
    p.add_argument("--cull-backfaces", action="store_true", default=None)
    p.add_argument(
        "--draw-hidden",
        dest="cull_hidden",
        action="store_false",
        default=None,
        help="draw the back faces of closed solids too (skipped by default: they cannot show)",
    )
    p.add_argument(
        "--shadows",
        choices=["off", "map", "exact"],
        default=None,
        help="every light casts shadows: map (shadow maps, default settings), exact (shadow "
        "rays) or off; default: as the scene says",
    )
    p.add_argument(
        "--samples",
        type=int,
        default=None,
        help="anti-aliasing samples per pixel: 1 (off), 2, 4, 8 or 16",
    )
    p.add_argument(
        "--supersample",
        type=int,
        default=None,
        help="render KxK pixels per output pixel and average them (1..8)",
    )
    p.add_argument(
        "--edges",
        choices=core.RenderOptions.edges_names,
        default=None,
        help="draw triangle edges as lines: all (wireframe), visible (hidden lines removed) "
        "or features (silhouettes, boundaries, creases)",
    )
    p.add_argument(
        "--edge-color", type=_triple, default=None, help="r,g,b of the lines (linear, 0,0,0)"
    )
    p.add_argument("--edge-width", type=float, default=None, help="line width in pixels (1)")
    p.add_argument(
        "--edge-angle", type=float, default=None, help="crease angle in degrees (features, 30)"
    )
    p.add_argument(
        "--edges-only",
        action="store_true",
        default=None,
        help="draw the lines alone over the background (surfaces still hide what is behind)",
    )
    p.add_argument("--alpha", action="store_true", help="write RGBA with a transparent background")
    p.add_argument(
        "--encoding",
        choices=["linear", "srgb"],
        default="linear",
        help="linear (default, OpenGL's values) or srgb (encoded for display)",
    )
    p.add_argument(
        "--compression",
        choices=list(PNG_COMPRESSIONS),
        default="fast",
        help="PNG compression: fast (default) writes a 1080p image in ~10 ms; high makes the "
        "smallest file (~40x slower); all are lossless",
    )
    p.add_argument(
        "--depth",
        default=None,
        metavar="FILE",
        help="also write the depth map (.png: 16-bit millimetres at 1 unit = 1 m, "
        ".tif/.npy: float)",
    )
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
        "images (OUTPUT with a {:04d} field, or OUTPUT_0000.png ...; --depth FILE likewise)",
    )


def _render(
    scene: core.Scene,
    camera: core.Camera,
    args: argparse.Namespace,
    file_options: dict[str, Any] | None = None,
) -> None:
    """Renders with a scene file's options updated by the flags given."""
    _check_values(args)
    if args.shadows is not None:
        choices: dict[str, bool | str] = {"off": False, "map": True, "exact": "exact"}
        shadows = choices[args.shadows]
        lights = [light_with_shadows(light, shadows) for light in scene.lights]
        scene.clear_lights()
        for light in lights:
            scene.add_light(light)
    if args.environment is not None:
        files = args.environment
        if len(files) not in (1, 6):
            raise ValueError(
                f"--environment takes one equirectangular image or six cube faces "
                f"(+X -X +Y -Y +Z -Z), got {len(files)} files"
            )
        scene.environment = load_environment(files[0] if len(files) == 1 else files)
    names = (
        "shading",
        "specular",
        "background",
        "threads",
        "samples",
        "supersample",
        "edges",
        "edge_color",
        "edge_width",
        "edge_angle",
        "edges_only",
        "reflections",
        "max_depth",
        "tolerance",
    )
    flags = {k: getattr(args, k) for k in names}
    flags["cull_backfaces"] = args.cull_backfaces
    flags["cull_hidden"] = args.cull_hidden
    if args.size is not None:
        flags["width"], flags["height"] = args.size
    given = {k: v for k, v in flags.items() if v is not None}
    if args.refractions is not None:
        given["refractions"] = None if args.refractions == "none" else args.refractions
    base = dict(file_options or {})
    if given.get("shading", "auto") != "auto" and "tolerance" not in given:
        # --shading with a fixed mode overrides a file's shading="auto" and its tolerance.
        base.pop("tolerance", None)
    opts = core.RenderOptions(**{**base, **given})
    if args.views is not None and args.cameras is not None:
        raise ValueError("--views and --cameras cannot be used together")
    if args.views is not None:
        if args.views < 1:
            raise ValueError(f"--views must be >= 1, got {args.views}")
        _render_many(scene, turntable(camera, args.views), args, opts)
        return
    if args.cameras is not None:
        _render_many(scene, load_cameras(args.cameras), args, opts)
        return
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", EmptyRenderWarning)
        img, depth = render(
            scene,
            camera,
            options=opts,
            return_depth=True,
            alpha=args.alpha,
            encoding=args.encoding,
        )
    for warning in caught:
        print(f"shadelab: warning: {warning.message}", file=sys.stderr)
    dt = (time.perf_counter() - t0) * 1e3
    save_image(img, args.output, compression=args.compression)
    if args.depth is not None:
        save_depth(depth, args.depth)
    w, h = opts.width, opts.height
    # With -o - the image is on stdout: the report goes to stderr.
    print(
        f"wrote {args.output} ({w}x{h}, {scene.n_triangles} triangles, {dt:.1f} ms)",
        file=sys.stderr if args.output == "-" else sys.stdout,
    )


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


def _frame_names(output: str, views: int) -> list[str]:
    """One file name per view from ``output`` (see :func:`_numbered`)."""
    if output == "-":
        raise ValueError("several views cannot be written to stdout: give -o a file pattern")
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
    return names


def _render_many(
    scene: core.Scene,
    cameras: list[core.Camera],
    args: argparse.Namespace,
    opts: core.RenderOptions,
) -> None:
    """Every camera in one :func:`render_batch` call, each image (and depth map with
    --depth) written as soon as it is rendered, as a single render would write it (--alpha
    and --encoding applied the same way)."""
    from .batch import render_batch

    views = len(cameras)
    names = _frame_names(args.output, views)
    depth_names = _frame_names(args.depth, views) if args.depth is not None else None

    def save(
        i: int, img: np.ndarray, depth: np.ndarray | None = None, alpha: np.ndarray | None = None
    ) -> None:
        img = _finish(img, alpha, out_dtype="uint8", encoding=args.encoding)
        save_image(img, names[i], compression=args.compression)
        if depth_names is not None:
            assert depth is not None
            save_depth(depth, depth_names[i])

    # As `render`: sRGB is encoded from the float image.
    dtype = "float32" if args.encoding == "srgb" else None
    t0 = time.perf_counter()
    if args.alpha and (opts.samples > 1 or opts.supersample > 1):
        # Fractional coverage comes with render_frame only: one view at a time.
        for i, cam in enumerate(cameras):
            f = render_frame(
                scene,
                cam,
                options=opts,
                alpha=True,
                encoding=args.encoding,
                return_depth=depth_names is not None,
            )
            save_image(f["image"], names[i], compression=args.compression)
            if depth_names is not None:
                assert f["depth"] is not None
                save_depth(f["depth"], depth_names[i])
    else:
        # With one sample the coverage is where the depth is finite; the background is
        # transparent as in `render`.
        batch_opts = opts.replace(background=(0.0, 0.0, 0.0)) if args.alpha else opts

        def save_batch(i: int, img: np.ndarray, depth: np.ndarray | None = None) -> None:
            alpha = None
            if args.alpha:
                assert depth is not None
                alpha = np.isfinite(depth).astype(np.float32)
            save(i, img, depth if depth_names is not None else None, alpha)

        render_batch(
            scene,
            cameras,
            options=batch_opts,
            dtype=dtype,
            return_depth=args.alpha or depth_names is not None,
            callback=save_batch,
        )
    dt = time.perf_counter() - t0
    w, h = opts.width, opts.height
    print(
        f"wrote {views} views {names[0]} ... {names[-1]} ({w}x{h}, {scene.n_triangles} "
        f"triangles, {dt * 1e3 / views:.1f} ms per view)"
    )


# Options of `render MODEL` that a scene file sets itself.
_MODEL_ONLY = ("material", "ambient")


def _camera(
    scene: core.Scene,
    base: core.Camera | None,
    args: argparse.Namespace,
    default_up: tuple[float, float, float],
) -> core.Camera:
    """The camera of the flags: framed from --view (a name or direction) with --up, looking
    at --target when given, or placed at --eye; planes fitted to the scene at render time."""
    up = args.up if args.up is not None else (base.up if base is not None else default_up)
    fov = args.fov if args.fov is not None else (base.fov_y if base and base.fov_y else 35.0)
    if base is not None and args.view is None and args.eye is None:
        if args.target is None and args.up is None and args.fov is None:
            return base
        # Keep the file's eye; aim and roll from the flags.
        target = args.target if args.target is not None else base.target
        return core.Camera.look_at(eye=base.eye, target=target, up=up, fov_y=fov)
    framed = frame_scene(scene, fov_y=fov, direction=args.view, up=up)
    target = args.target if args.target is not None else framed.target
    if args.eye is not None:
        d = np.subtract(args.eye, target)
        if not np.any(d):
            raise ValueError("eye and target must be distinct points (--eye, --target)")
        _, cam_up = view_direction(tuple(d), up)
        return core.Camera.look_at(eye=args.eye, target=target, up=tuple(cam_up), fov_y=fov)
    if args.target is None:
        return framed
    # --target without --eye: the framed eye, moved with the target.
    offset = np.subtract(framed.eye, framed.target)
    return core.Camera.look_at(
        eye=tuple(np.add(target, offset)), target=target, up=framed.up, fov_y=fov
    )


def _lights(scene: core.Scene, args: argparse.Namespace) -> None:
    """--light replaces the scene's lights with directional lights."""
    if args.light:
        scene.clear_lights()
        for d in args.light:
            scene.add_light(core.DirectionalLight(direction=d))


def _check_cameras_flags(args: argparse.Namespace) -> None:
    """--cameras sets every camera: the camera flags next to it are errors, not ignored."""
    if getattr(args, "cameras", None) is None:
        return
    given = [
        k for k in ("fov", "view", "eye", "target", "up") if getattr(args, k, None) is not None
    ]
    if given:
        flags = ", ".join("--" + k for k in given)
        raise ValueError(f"{flags} cannot be used with --cameras: the file sets the cameras")


def cmd_render_scene(args: argparse.Namespace) -> None:
    _check_values(args)
    _check_cameras_flags(args)
    if args.texture is not None:
        raise ValueError(
            "--texture cannot be used with a scene file; give its material a diffuse_map"
        )
    for flag, key in (("normal_map", "normal_map"), ("bump_map", "bump_map")):
        if getattr(args, flag, None) is not None:
            raise ValueError(
                f"--{flag.replace('_', '-')} cannot be used with a scene file; give its "
                f"material a {key}"
            )
    given = [k for k in _MODEL_ONLY if getattr(args, k) is not None]
    if given:
        flags = ", ".join("--" + k for k in given)
        raise ValueError(f"{flags} cannot be used with a scene file; set it in the file")
    sf = load_scene(args.model)
    _lights(sf.scene, args)
    if args.two_sided:
        sf.scene.two_sided = True
    camera = _camera(sf.scene, sf.camera, args, (0.0, 1.0, 0.0))
    _render(sf.scene, camera, args, sf.render_options)


def _surface_maps(
    normal_map: str | None, normal_scale: float, bump_map: str | None, bump_scale: float
) -> Callable[[core.Material], core.Material]:
    """A function that adds the normal and bump maps named (image files, read as stored)
    to a material, keeping its other maps; the identity when neither is given."""
    nm = None if normal_map is None else core.Texture.load(normal_map)
    bm = None if bump_map is None else core.Texture.load(bump_map)

    def add(m: core.Material) -> core.Material:
        if nm is None and bm is None:
            return m
        return m.with_maps(
            diffuse_map=m.diffuse_map,
            ambient_map=m.ambient_map,
            specular_map=m.specular_map,
            emission_map=m.emission_map,
            shininess_map=m.shininess_map,
            normal_map=nm if nm is not None else m.normal_map,
            normal_scale=normal_scale if nm is not None else m.normal_scale,
            bump_map=bm if bm is not None else m.bump_map,
            bump_scale=bump_scale if bm is not None else m.bump_scale,
        )

    return add


def _add_model(
    scene: core.Scene,
    path: str,
    preset: str | None,
    texture: str | None = None,
    surface: Callable[[core.Material], core.Material] | None = None,
) -> np.ndarray:
    """Adds the model at ``path`` to ``scene``; returns all its vertices (for framing).

    An OBJ keeps its MTL materials (and their texture maps), one per group and ``usemtl``
    run, unless a preset is given; parts without one (and other formats) get the preset,
    gold by default. ``texture``: an image file made every part's diffuse map (which also
    weighs ambient), in place of the MTL's maps; the model needs UVs. ``surface``: adds
    normal and bump maps (:func:`_surface_maps`) after that."""
    fallback = core.Material.preset(preset or "gold")
    tex = None if texture is None else core.Texture.load(texture)

    def with_texture(m: core.Material) -> core.Material:
        m = m if tex is None else m.with_maps(diffuse_map=tex)
        return m if surface is None else surface(m)

    if os.fspath(path).lower().endswith(".obj"):
        parts = core.load_obj_parts(path)
        for _, mesh, mtl in parts:
            scene.add(mesh, material=with_texture(fallback if preset or mtl is None else mtl))
        return np.concatenate([mesh.vertices for _, mesh, _ in parts])
    mesh = load_mesh(path)
    scene.add(mesh, material=with_texture(fallback))
    return mesh.vertices


def cmd_render(args: argparse.Namespace) -> None:
    if Path(args.model).suffix.lower() == ".toml":
        cmd_render_scene(args)
        return
    _check_values(args)
    _check_cameras_flags(args)
    scene = core.Scene(
        ambient=args.ambient if args.ambient is not None else (0.2, 0.2, 0.2),
        two_sided=bool(args.two_sided),
    )
    surface = _surface_maps(args.normal_map, args.normal_scale, args.bump_map, args.bump_scale)
    _add_model(scene, args.model, args.material, args.texture, surface)
    # No --light: the default rig, which moves with the camera.
    _lights(scene, args)
    camera = _camera(scene, None, args, file_up_axis(args.model))
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
        sheet = material_sheet(cell=args.cell, columns=args.columns, textures=args.textures)
        save_image(sheet, args.sheet)
        h, w = sheet.shape[:2]
        what = "preset, and textured swatches" if args.textures else "preset"
        print(f"wrote {args.sheet} ({w}x{h}, one sphere per {what})", file=sys.stderr)


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
    r.add_argument(
        "--texture",
        default=None,
        metavar="IMAGE",
        help="image file (PNG, JPEG) as the model's diffuse map, in place of its MTL maps "
        "(the model needs UVs; it multiplies the material's ambient and diffuse colour)",
    )
    r.add_argument(
        "--normal-map",
        default=None,
        metavar="IMAGE",
        help="image file as every part's tangent-space normal map (the model needs UVs; "
        "Phong shading only)",
    )
    r.add_argument(
        "--normal-scale",
        type=float,
        default=1.0,
        help="scale of the normal map's x and y (1.0)",
    )
    r.add_argument(
        "--bump-map",
        default=None,
        metavar="IMAGE",
        help="image file as every part's bump (height) map (the model needs UVs; Phong only)",
    )
    r.add_argument(
        "--bump-scale",
        type=float,
        default=1.0,
        help="height of a bump-map value 1, in UV units (1.0)",
    )
    r.add_argument("--ambient", type=_triple, default=None, help="scene ambient r,g,b (0.2,...)")
    r.add_argument("--fov", type=float, default=None, help="vertical field of view, degrees (35)")
    r.add_argument(
        "--view",
        type=_view,
        default=None,
        help=f"{'|'.join(VIEWS)}, or the direction x,y,z from the model's centre to the "
        "camera (default: front, a little right and above)",
    )
    r.add_argument("--eye", type=_triple, default=None, help="explicit camera position x,y,z")
    r.add_argument(
        "--target", type=_triple, default=None, help="point looked at (default: the centre)"
    )
    r.add_argument(
        "--up",
        type=_triple,
        default=None,
        help="up axis x,y,z (default: 0,0,1 for STL and 3MF, which are Z-up, else 0,1,0)",
    )
    r.add_argument(
        "--light",
        type=_triple,
        action="append",
        help="directional light travel direction x,y,z (repeatable; replaces a scene "
        "file's lights; default: a light rig that moves with the camera)",
    )
    r.add_argument(
        "--two-sided",
        action="store_true",
        default=None,
        help="light back faces too (open surfaces, single-sided planes)",
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
    m.add_argument(
        "--textures",
        action="store_true",
        help="add rows of textured swatches to the sheet (procedural checker, grid, stripes "
        "and noise diffuse maps, a bump map, a normal map)",
    )
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
