#!/usr/bin/env python3
"""What each lighting feature costs per shaded pixel (``make bench`` → docs/FEATURE_COSTS.md).

One fixed scene: a ~100k-triangle UV sphere (gold, exact normals) filling 95 % of the height
of a 1920x1080 frame. The baseline is the global ambient plus one directional light; every
other variant adds exactly one feature to it (a light, a light option, fog, a light-model
switch, another specular lobe, or removes the specular term). All variants are rendered
round-robin, one frame each per round in a shuffled order, so slow drifts in machine load hit
every variant alike. Per variant the report gives the median frame time and its IQR, and the
added cost against the baseline as the median of the per-round differences (variant − baseline
in the same round), in ms and in ns per covered pixel (pixels with finite depth), with the IQR
of those differences so the noise is visible.

``--against-commit REV`` also answers "does the baseline render as fast as before the lighting
work?": it builds REV's extension (``git archive`` into ``target/bench-before/<sha>/``, a release
wheel with maturin, installed into its own venv there; reused on later runs) and times the
baseline scene with both builds in two worker processes, alternating frame by frame.

    python bench/bench_features.py                      # full run (~4 min), table on stdout
    python bench/bench_features.py --quick              # smoke run (a few rounds)
    python bench/bench_features.py --write docs/FEATURE_COSTS.md --against-commit 97b7ad9

Only NumPy and the standard library besides shadelab_rs; nothing is imported from tests/.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import gc
import json
import math
import os
import random
import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from harness import machine, write_csv
from sphere_mesh import uv_sphere  # the same mesh for every build compared

# shadelab_rs is imported lazily (see _sl) so that ``--worker`` runs under another venv's
# build, and the build step does not need the current one.

WIDTH, HEIGHT = 1920, 1080
FOV_Y = 45.0
SPHERE_FILL = 0.95  # silhouette / frame height
SPHERE_RINGS = 158  # uv_sphere(158, 316): 99,224 triangles, as sphere_100k in BENCHMARKS.md
ROOT = Path(__file__).resolve().parent.parent
DEFAULT_CSV = ROOT / "bench" / "results" / "bench_features.csv"
BEFORE_DIR = ROOT / "target" / "bench-before"
# The first commit of the lighting work (issue 3) is 9d219f3; its parent is "before".
DEFAULT_BEFORE = "97b7ad9"


def _sl() -> Any:
    import shadelab_rs

    return shadelab_rs


# --------------------------------------------------------------------------- the scene


def camera() -> Any:
    """Perspective camera on +z; the unit sphere's silhouette spans SPHERE_FILL of the height."""
    sl = _sl()
    alpha = math.atan(SPHERE_FILL * math.tan(math.radians(FOV_Y) / 2))
    dist = 1.0 / math.sin(alpha)
    return sl.Camera.look_at(
        eye=(0.0, 0.0, dist),
        target=(0.0, 0.0, 0.0),
        up=(0.0, 1.0, 0.0),
        fov_y=FOV_Y,
        near=0.1,
        far=dist + 10.0,
    )


_MESH: dict[str, Any] = {}


def sphere_mesh() -> Any:
    if "m" not in _MESH:
        v, f = uv_sphere(SPHERE_RINGS, 2 * SPHERE_RINGS)
        _MESH["m"] = _sl().Mesh(v, f, normals=v)
    return _MESH["m"]


def sphere_mesh_uv() -> Any:
    """The same sphere with UVs (u = longitude / 2π, v = 1 − colatitude / π; no seam split,
    so one column of triangles reads a squeezed copy): for the texture-map variants only,
    since builds before textures take no ``uvs``."""
    if "uv" not in _MESH:
        v, f = uv_sphere(SPHERE_RINGS, 2 * SPHERE_RINGS)
        vd = v.astype(np.float64)
        u = (np.arctan2(vd[:, 0], vd[:, 2]) / (2 * np.pi)) % 1.0
        t = 1.0 - np.arccos(np.clip(vd[:, 1], -1.0, 1.0)) / np.pi
        _MESH["uv"] = _sl().Mesh(v, f, normals=v, uvs=np.stack([u, t], axis=1))
    return _MESH["uv"]


def _map_image(kind: str, n: int = 512) -> np.ndarray:
    """A 512 x 512 float32 map: value noise for colour and heights, its bumps for normals."""
    rng = np.random.default_rng(7)
    coarse = rng.random((n // 16, n // 16))
    h = np.kron(coarse, np.ones((16, 16)))
    if kind == "normal":
        gy, gx = np.gradient(h)
        nrm = np.stack([-gx * 4, gy * 4, np.ones_like(h)], -1)
        nrm /= np.linalg.norm(nrm, axis=-1, keepdims=True)
        return ((nrm + 1) / 2).astype(np.float32)
    return np.repeat(h[..., None], 3, axis=2).astype(np.float32)


def _mapped(**maps: str) -> Callable[[], tuple[Any, dict[str, Any]]]:
    """The baseline on the UV sphere with image maps (512², trilinear): ``key=kind``."""

    def build() -> tuple[Any, dict[str, Any]]:
        sl = _sl()
        scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
        kw: dict[str, Any] = {}
        for key, kind in maps.items():
            if key.endswith("_scale"):
                kw[key] = float(kind)
            else:
                kw[key] = sl.Texture(_map_image(kind))
        gold = sl.Material.preset("gold")
        m = sl.Material(gold.ambient, gold.diffuse, gold.specular, gold.shininess, **kw)
        scene.add(sphere_mesh_uv(), material=m)
        scene.add_light(sl.DirectionalLight(direction=KEY_DIRECTION))
        return scene, {}

    return build


KEY_DIRECTION = (-1.0, -1.0, -1.0)
# Extra directional lights, dim so the image stays readable; all light the visible side.
EXTRA_DIRECTIONS = [
    (1, -1, -1),
    (0, -1, -1),
    (-1, 0, -1),
    (1, 0, -1),
    (0, 1, -1),
    (-1, 1, -1),
    (1, 1, -1),
]
POSITION = (2.0, 3.0, 4.0)


@dataclass(frozen=True)
class Variant:
    """One scene configuration: ``build`` returns (scene, extra render keyword arguments)."""

    name: str
    feature: str  # what it adds to the baseline, for the report
    build: Callable[[], tuple[Any, dict[str, Any]]]


def _scene(
    material: dict[str, Any] | None = None,
    scene_kw: dict[str, Any] | None = None,
    extra: Callable[[Any], list[Any]] | None = None,
    key_kw: dict[str, Any] | None = None,
) -> Callable[[], tuple[Any, dict[str, Any]]]:
    """A builder for the baseline scene with one change."""

    def build() -> tuple[Any, dict[str, Any]]:
        sl = _sl()
        scene = sl.Scene(ambient=(0.2, 0.2, 0.2), **(scene_kw or {}))
        gold = sl.Material.preset("gold")
        if material:
            kw = {
                "ambient": gold.ambient,
                "diffuse": gold.diffuse,
                "specular": gold.specular,
                "shininess": gold.shininess,
            }
            kw.update(material)
            gold = sl.Material(**kw)
        scene.add(sphere_mesh(), material=gold)
        scene.add_light(sl.DirectionalLight(direction=KEY_DIRECTION, **(key_kw or {})))
        for light in extra(sl) if extra else []:
            scene.add_light(light)
        return scene, {}

    return build


def _with_kw(build: Callable[[], tuple[Any, dict[str, Any]]], **kw: Any) -> Callable:
    def wrapped() -> tuple[Any, dict[str, Any]]:
        scene, extra = build()
        return scene, {**extra, **kw}

    return wrapped


def _dirs(n: int) -> Callable[[Any], list[Any]]:
    return lambda sl: [
        sl.DirectionalLight(direction=d, color=(0.3, 0.3, 0.3)) for d in EXTRA_DIRECTIONS[:n]
    ]


def _area(samples: int, shape: str = "rectangle", one_sided: bool = False) -> Callable:
    # A 2x2 panel above and in front of the sphere, facing down (u x v = -y).
    return lambda sl: [
        sl.AreaLight(
            position=(0.0, 3.0, 2.0),
            u=(2.0, 0.0, 0.0),
            v=(0.0, 0.0, 2.0),
            shape=shape,
            samples=samples,
            one_sided=one_sided,
            color=(0.6, 0.6, 0.6),
        )
    ]


def variants() -> list[Variant]:
    """Every variant, baseline first. Names are stable (they key the CSV)."""
    base = _scene()

    def point(**kw: Any) -> Callable[[Any], list[Any]]:
        return lambda sl: [sl.PointLight(position=POSITION, color=(0.4, 0.4, 0.5), **kw)]

    def spot(**kw: Any) -> Callable[[Any], list[Any]]:
        # On the camera axis, pointing at the sphere: the cone covers part of it.
        return lambda sl: [
            sl.SpotLight(position=(0.0, 0.0, 3.0), direction=(0.0, 0.0, -1.0), cutoff=20.0, **kw)
        ]

    att = {"attenuation": (1.0, 0.05, 0.02)}
    return [
        Variant("baseline", "ambient + 1 directional light, gold, Blinn-Phong", base),
        Variant(
            "no_specular",
            "ks = 0 (specular term skipped)",
            _scene(material={"specular": (0, 0, 0)}),
        ),
        Variant("emission", "material emission", _scene(material={"emission": (0.1, 0.05, 0.0)})),
        Variant(
            "dir_ambient",
            "the light's own ambient colour",
            _scene(key_kw={"ambient": (0.1, 0.1, 0.1)}),
        ),
        Variant("spec_phong", 'specular="phong" (r·v)', _with_kw(base, specular="phong")),
        Variant(
            "spec_blinn_norm",
            'specular="blinn-normalized"',
            _with_kw(base, specular="blinn-normalized"),
        ),
        Variant("infinite_viewer", "local_viewer=False", _scene(scene_kw={"local_viewer": False})),
        Variant("two_sided", "two_sided=True", _scene(scene_kw={"two_sided": True})),
        Variant("dir_2", "2nd directional light", _scene(extra=_dirs(1))),
        Variant("dir_4", "4 directional lights", _scene(extra=_dirs(3))),
        Variant("dir_8", "8 directional lights", _scene(extra=_dirs(7))),
        Variant("point", "+ point light", _scene(extra=point())),
        Variant("point_att", "+ point light with attenuation", _scene(extra=point(**att))),
        Variant(
            "point_att_amb",
            "+ point light with attenuation and ambient",
            _scene(extra=point(ambient=(0.1, 0.1, 0.1), **att)),
        ),
        Variant("spot", "+ spot light, hard edge", _scene(extra=spot())),
        Variant(
            "spot_smooth",
            "+ spot light, inner cone 10° and exponent 8",
            _scene(extra=spot(inner=10.0, exponent=8.0)),
        ),
        Variant(
            "area_rect_2", "+ area light, rectangle, samples=2 (4 points)", _scene(extra=_area(2))
        ),
        Variant(
            "area_rect_4", "+ area light, rectangle, samples=4 (16 points)", _scene(extra=_area(4))
        ),
        Variant(
            "area_rect_8", "+ area light, rectangle, samples=8 (64 points)", _scene(extra=_area(8))
        ),
        Variant(
            "area_disk_4",
            "+ area light, disk, samples=4 (16 points)",
            _scene(extra=_area(4, "disk")),
        ),
        Variant(
            "area_one_sided_4",
            "+ area light, rectangle, one_sided, samples=4",
            _scene(extra=_area(4, one_sided=True)),
        ),
        Variant("fog_linear", "linear fog", _fog("linear", start=2.0, end=4.0)),
        Variant("fog_exp", "exp fog", _fog("exp", density=0.3)),
        Variant("fog_exp2", "exp2 fog", _fog("exp2", density=0.3)),
        Variant("msaa_2", "samples=2 (multi-sample anti-aliasing)", _with_kw(base, samples=2)),
        Variant("msaa_4", "samples=4 (multi-sample anti-aliasing)", _with_kw(base, samples=4)),
        Variant("msaa_16", "samples=16 (multi-sample anti-aliasing)", _with_kw(base, samples=16)),
        Variant("diffuse_map", "diffuse_map (512² image, trilinear)", _mapped(diffuse_map="color")),
        Variant("normal_map", "normal_map (512² image, trilinear)", _mapped(normal_map="normal")),
        Variant(
            "bump_map",
            "bump_map (512² image, trilinear, 4 height reads)",
            _mapped(bump_map="height", bump_scale="0.002"),
        ),
        Variant(
            "diffuse_normal_map",
            "diffuse_map + normal_map",
            _mapped(diffuse_map="color", normal_map="normal"),
        ),
        *realism_variants(),
    ]


# --------------------------------------------------------------------------- realism rooms


def _realism(
    key_shadows: Any = False,
    extra: Callable[[Any], list[Any]] | None = None,
    material: Callable[[Any], dict[str, Any]] | None = None,
    mesh: Callable[[], Any] = sphere_mesh,
    environment: bool = False,
    **render_kw: Any,
) -> Callable[[], tuple[Any, dict[str, Any]]]:
    """The baseline scene with a realism feature: the key light's shadows, extra lights, a
    material change (built from the module), a scene environment, render options."""

    def build() -> tuple[Any, dict[str, Any]]:
        sl = _sl()
        scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
        if environment:
            sky = np.linspace(0.2, 1.0, 64, dtype=np.float32)[:, None, None]
            scene.environment = sl.Environment(np.broadcast_to(sky, (64, 128, 3)).copy())
        gold = sl.Material.preset("gold")
        kw = {
            "ambient": gold.ambient,
            "diffuse": gold.diffuse,
            "specular": gold.specular,
            "shininess": gold.shininess,
        }
        kw.update(material(sl) if material else {})
        scene.add(mesh(), material=sl.Material(**kw))
        shadows = key_shadows(sl) if callable(key_shadows) else key_shadows
        scene.add_light(sl.DirectionalLight(direction=KEY_DIRECTION, shadows=shadows))
        for light in extra(sl) if extra else []:
            scene.add_light(light)
        return scene, dict(render_kw)

    return build


def realism_variants() -> list[Variant]:
    """Textures, shadows, reflection and refraction on the baseline sphere (this build only:
    an older build may not have them)."""

    def point(shadows: Any) -> Callable[[Any], list[Any]]:
        return lambda sl: [sl.PointLight(position=POSITION, color=(0.4, 0.4, 0.5), shadows=shadows)]

    def spot(shadows: Any) -> Callable[[Any], list[Any]]:
        return lambda sl: [
            sl.SpotLight(
                position=(0.0, 0.0, 3.0),
                direction=(0.0, 0.0, -1.0),
                cutoff=20.0,
                shadows=shadows,
            )
        ]

    image = np.random.default_rng(1).random((1024, 1024, 3), dtype=np.float32)
    return [
        Variant(
            "tex_checker",
            "diffuse_map: procedural checker (uv sphere)",
            _realism(
                material=lambda sl: {"diffuse_map": sl.Texture.procedural("checker")},
                mesh=sphere_mesh_uv,
            ),
        ),
        Variant(
            "tex_image_aniso8",
            "diffuse_map: 1024² image, anisotropy 8",
            _realism(
                material=lambda sl: {"diffuse_map": sl.Texture(image, anisotropy=8)},
                mesh=sphere_mesh_uv,
            ),
        ),
        Variant("shadow_dir_map", "key light shadows=True (2048² map)", _realism(True)),
        Variant(
            "shadow_dir_cascades",
            "key light shadows, 3 cascades of 2048²",
            _realism(lambda sl: sl.ShadowSettings(cascades=3)),
        ),
        Variant("shadow_dir_exact", 'key light shadows="exact" (BVH rays)', _realism("exact")),
        Variant(
            "shadow_point_map",
            "+ point light, shadows=True (cube map)",
            _realism(extra=point(True)),
        ),
        Variant(
            "shadow_point_exact", '+ point light, shadows="exact"', _realism(extra=point("exact"))
        ),
        Variant(
            "shadow_spot_map", "+ spot light, shadows=True (one map)", _realism(extra=spot(True))
        ),
        Variant(
            "reflect_env",
            "reflectivity 0.5, environment lookup",
            _realism(material=lambda sl: {"reflectivity": 0.5}, environment=True),
        ),
        Variant(
            "reflect_ray",
            'reflectivity 0.5, reflections="ray"',
            _realism(
                material=lambda sl: {"reflectivity": 0.5}, environment=True, reflections="ray"
            ),
        ),
        Variant(
            "glass_env",
            'glass (transparency 0.9, ior "glass"), refractions="environment"',
            _realism(
                material=lambda sl: {"transparency": 0.9, "ior": "glass"},
                environment=True,
                refractions="environment",
            ),
        ),
        Variant(
            "glass_ray",
            'glass, refractions="ray", max_depth 4',
            _realism(
                material=lambda sl: {"transparency": 0.9, "ior": "glass"},
                environment=True,
                refractions="ray",
                max_depth=4,
            ),
        ),
    ]


def _fog(mode: str, **kw: Any) -> Callable:
    def build() -> tuple[Any, dict[str, Any]]:
        sl = _sl()
        return _scene(scene_kw={"fog": sl.Fog(mode, color=(0.5, 0.5, 0.6), **kw)})()

    return build


# Gouraud and flat light per vertex / per triangle, so most features cost nothing per pixel
# there; these show that, and fog and anti-aliasing (per pixel in every mode).
OTHER_MODE_VARIANTS = (
    "baseline",
    "no_specular",
    "dir_8",
    "point_att",
    "spot_smooth",
    "area_rect_8",
    "fog_exp2",
    "msaa_4",
    "msaa_16",
)


def configurations(modes: list[str]) -> list[tuple[str, Variant]]:
    """(mode, variant) pairs to measure: every variant in Phong, a subset in the others."""
    out = []
    for mode in modes:
        for v in variants():
            if mode == "phong" or v.name in OTHER_MODE_VARIANTS:
                out.append((mode, v))
    return out


# --------------------------------------------------------------------------- measuring


@dataclass
class Series:
    mode: str
    variant: Variant
    covered_px: int = 0
    light_sources: int = 0
    wall_ms: list[float] = field(default_factory=list)
    cpu_ms: list[float] = field(default_factory=list)
    # Variant minus the nearest baseline frame (same mode, same round), per frame.
    diff_wall: list[float] = field(default_factory=list)
    diff_cpu: list[float] = field(default_factory=list)


def _render(scene: Any, kw: dict[str, Any], mode: str, threads: int) -> tuple[float, float]:
    """Wall ms and process CPU ms of one render_frame call. CPU time leaves out the time the
    renderer's threads waited for a core that other work held, so on a loaded machine it is
    the steadier measure of the work itself."""
    sl = _sl()
    cam = _CAMERA.setdefault("c", camera())
    c0, t0 = time.process_time(), time.perf_counter()
    sl.render_frame(scene, cam, width=WIDTH, height=HEIGHT, shading=mode, threads=threads, **kw)
    return (time.perf_counter() - t0) * 1e3, (time.process_time() - c0) * 1e3


_CAMERA: dict[str, Any] = {}


def covered(scene: Any, kw: dict[str, Any], mode: str) -> tuple[int, int]:
    """Covered pixels (finite depth) and the light sources the renderer evaluated."""
    cam = _CAMERA.setdefault("c", camera())
    frame = _sl().render_frame(
        scene, cam, width=WIDTH, height=HEIGHT, shading=mode, return_depth=True, **kw
    )
    return int(np.isfinite(frame["depth"]).sum()), int(frame["stats"].get("light_sources", -1))


def round_order(series: list[Series], rng: random.Random) -> list[int]:
    """One round: every variant once in a shuffled order, with the baseline of each mode at
    the start, the middle and the end, so every variant frame has a baseline frame of its
    mode close to it in time."""
    base = [i for i, s in enumerate(series) if s.variant.name == "baseline"]
    rest = [i for i, s in enumerate(series) if s.variant.name != "baseline"]
    rng.shuffle(rest)
    half = len(rest) // 2
    return [*base, *rest[:half], *base[::-1], *rest[half:], *base]


def measure(
    configs: list[tuple[str, Variant]], threads: int, min_rounds: int, seconds: float, seed: int
) -> tuple[list[Series], int]:
    """Rounds of :func:`round_order` until ``min_rounds`` are done and ``seconds`` have
    passed. Returns the series and the number of rounds."""
    series, scenes = [], []
    for mode, v in configs:
        scene, kw = v.build()
        s = Series(mode, v)
        s.covered_px, s.light_sources = covered(scene, kw, mode)
        _render(scene, kw, mode, threads)  # warm-up
        series.append(s)
        scenes.append((scene, kw))
    rng = random.Random(seed)
    start = time.perf_counter()
    rounds = 0
    while rounds < min_rounds or time.perf_counter() - start < seconds:
        order = round_order(series, rng)
        frames = []  # (position, series index, wall, cpu)
        gc.collect()
        gc.disable()
        try:
            for pos, i in enumerate(order):
                wall, cpu = _render(*scenes[i], series[i].mode, threads)
                frames.append((pos, i, wall, cpu))
        finally:
            gc.enable()
        for pos, i, wall, cpu in frames:
            s = series[i]
            s.wall_ms.append(wall)
            s.cpu_ms.append(cpu)
            if s.variant.name == "baseline":
                continue
            near = min(
                (f for f in frames if series[f[1]].variant.name == "baseline"
                 and series[f[1]].mode == s.mode),
                key=lambda f: abs(f[0] - pos),
            )  # fmt: skip
            s.diff_wall.append(wall - near[2])
            s.diff_cpu.append(cpu - near[3])
        rounds += 1
        print(f"\rround {rounds} ({time.perf_counter() - start:.0f} s)", end="", file=sys.stderr)
    print(file=sys.stderr)
    return series, rounds


def _q(xs: list[float]) -> tuple[float, float, float]:
    q1, q2, q3 = np.percentile(xs, [25, 50, 75])
    return float(q1), float(q2), float(q3)


def rows(series: list[Series], threads: int) -> list[dict[str, Any]]:
    """One row per series: wall and CPU time quartiles, and the cost against the nearest
    baseline frames (CPU time; the wall-time figure is in the CSV too)."""
    out = []
    for s in series:
        w1, wmed, w3 = _q(s.wall_ms)
        c1, cmed, c3 = _q(s.cpu_ms)
        base = s.variant.name == "baseline"
        d1, dmed, d3 = (0.0, 0.0, 0.0) if base else _q(s.diff_cpu)
        dw = 0.0 if base else statistics.median(s.diff_wall)
        ns = 1e6 / s.covered_px  # ms per frame -> ns per covered pixel
        out.append(
            {
                "mode": s.mode,
                "variant": s.variant.name,
                "feature": s.variant.feature,
                "threads": threads,
                "frames": len(s.wall_ms),
                "covered_px": s.covered_px,
                "light_sources": s.light_sources,
                "wall_ms": round(wmed, 3),
                "wall_iqr_ms": round(w3 - w1, 3),
                "cpu_ms": round(cmed, 3),
                "cpu_iqr_ms": round(c3 - c1, 3),
                "added_ms": round(dmed, 3),
                "added_iqr_ms": round(d3 - d1, 3),
                "added_wall_ms": round(dw, 3),
                "added_ns_px": round(dmed * ns, 2),
                "added_ns_px_q1": round(d1 * ns, 2),
                "added_ns_px_q3": round(d3 * ns, 2),
            }
        )
    return out


# --------------------------------------------------------------------------- before/after


def _git(*args: str) -> str:
    return subprocess.run(
        ["git", *args], cwd=ROOT, check=True, capture_output=True, text=True
    ).stdout.strip()


def build_commit(rev: str) -> Path:
    """A venv with REV's extension (release wheel), built once into target/bench-before/<sha>;
    returns its python."""
    sha = _git("rev-parse", "--verify", f"{rev}^{{commit}}")
    home = BEFORE_DIR / sha
    py = home / "venv" / "bin" / "python"
    stamp = home / "built"
    if stamp.exists() and py.exists():
        return py
    if home.exists():
        shutil.rmtree(home)
    src = home / "src"
    src.mkdir(parents=True)
    # git archive, not a worktree: nothing is registered in the shared repository.
    archive = subprocess.run(["git", "archive", sha], cwd=ROOT, check=True, capture_output=True)
    subprocess.run(["tar", "-x", "-C", str(src)], input=archive.stdout, check=True)
    print(f"building {sha[:9]} in {src} (release; takes a few minutes)", file=sys.stderr)
    maturin = Path(sys.executable).parent / "maturin"
    # The earlier commit is built with one codegen unit, as the current release profile
    # builds ours: with several, the partition decided whether lane loops were vectorised,
    # which moved frame times by several percent unrelated to the code compared.
    env = {
        **os.environ,
        "CARGO_TARGET_DIR": str(home / "target"),
        "CARGO_PROFILE_RELEASE_CODEGEN_UNITS": "1",
    }
    env.pop("VIRTUAL_ENV", None)
    wheels = home / "wheels"
    subprocess.run(
        [str(maturin), "build", "--release", "-q", "-o", str(wheels), "-i", sys.executable],
        cwd=src,
        env=env,
        check=True,
    )
    subprocess.run([sys.executable, "-m", "venv", str(home / "venv")], check=True)
    wheel = next(wheels.glob("shadelab_rs-*.whl"))
    subprocess.run([str(py), "-m", "pip", "install", "-q", str(wheel)], check=True)
    stamp.write_text(sha + "\n")
    return py


class Worker:
    """A ``--worker`` subprocess under some venv's python: renders the baseline on request."""

    def __init__(self, python: Path | str, threads: int) -> None:
        self.proc = subprocess.Popen(
            [str(python), str(Path(__file__).resolve()), "--worker", "--threads", str(threads)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            cwd="/",
        )
        self.info = self._ask({"cmd": "info"})

    def _ask(self, msg: dict[str, Any]) -> dict[str, Any]:
        assert self.proc.stdin and self.proc.stdout
        self.proc.stdin.write(json.dumps(msg) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"worker {self.proc.args} died")
        return json.loads(line)

    def frame(self, mode: str) -> tuple[float, float]:
        """Wall and CPU ms of one baseline frame in ``mode``."""
        r = self._ask({"cmd": "frame", "mode": mode})
        return r["wall_ms"], r["cpu_ms"]

    def close(self) -> None:
        assert self.proc.stdin
        self.proc.stdin.close()
        self.proc.wait(timeout=30)


def worker_main(threads: int) -> int:
    """The ``--worker`` loop: one JSON request per stdin line, one JSON answer per line."""
    sl = _sl()
    base = variants()[0]
    scene, kw = base.build()
    warmed: set[str] = set()
    for line in sys.stdin:
        msg = json.loads(line)
        if msg["cmd"] == "info":
            px, _ = covered(scene, kw, "phong")
            path = Path(sl.__file__).resolve().parent
            ans: dict[str, Any] = {"version": sl.__version__, "path": str(path), "covered_px": px}
        else:
            if msg["mode"] not in warmed:
                _render(scene, kw, msg["mode"], threads)
                warmed.add(msg["mode"])
            gc.collect()
            wall, cpu = _render(scene, kw, msg["mode"], threads)
            ans = {"wall_ms": wall, "cpu_ms": cpu}
        print(json.dumps(ans), flush=True)
    return 0


def compare_builds(
    before_py: Path, modes: list[str], threads: int, rounds: int
) -> list[dict[str, Any]]:
    """The baseline with this build and with the ``before`` one, in two worker processes,
    alternating (which goes first alternates too), ``rounds`` frames each per mode."""
    now, before = Worker(sys.executable, threads), Worker(before_py, threads)
    try:
        out = []
        for mode in modes:
            t: dict[str, list[tuple[float, float]]] = {"now": [], "before": []}
            for r in range(rounds):
                pair = [("now", now), ("before", before)]
                for key, w in pair if r % 2 == 0 else pair[::-1]:
                    t[key].append(w.frame(mode))
            cpu_n, cpu_b = [c for _, c in t["now"]], [c for _, c in t["before"]]
            wall_n, wall_b = [w for w, _ in t["now"]], [w for w, _ in t["before"]]
            qn, qb = _q(cpu_n), _q(cpu_b)
            qr = _q([a / b for a, b in zip(cpu_n, cpu_b)])
            out.append(
                {
                    "mode": mode,
                    "frames": rounds,
                    "now_cpu_ms": round(qn[1], 3),
                    "now_cpu_iqr_ms": round(qn[2] - qn[0], 3),
                    "before_cpu_ms": round(qb[1], 3),
                    "before_cpu_iqr_ms": round(qb[2] - qb[0], 3),
                    "ratio": round(qr[1], 4),
                    "ratio_q1": round(qr[0], 4),
                    "ratio_q3": round(qr[2], 4),
                    "now_wall_ms": round(statistics.median(wall_n), 3),
                    "before_wall_ms": round(statistics.median(wall_b), 3),
                    "wall_ratio": round(
                        statistics.median(a / b for a, b in zip(wall_n, wall_b)), 4
                    ),
                    "covered_now": now.info["covered_px"],
                    "covered_before": before.info["covered_px"],
                }
            )
        return out
    finally:
        now.close()
        before.close()


# --------------------------------------------------------------------------- reporting


def _f(x: float, digits: int = 2) -> str:
    return f"{x:+.{digits}f}" if x else f"{0:.{digits}f}"


def table(rs: list[dict[str, Any]]) -> list[str]:
    lines = [
        "| mode | variant | what it adds | light sources | wall ms (IQR) | CPU ms (IQR) | added CPU ms (IQR) | added ns/px [q1, q3] |",  # noqa: E501
        "|---|---|---|---:|---:|---:|---:|---:|",
    ]
    for r in rs:
        added = (
            "–" if r["variant"] == "baseline" else f"{_f(r['added_ms'])} ({r['added_iqr_ms']:.2f})"
        )
        ns = (
            "–"
            if r["variant"] == "baseline"
            else f"{_f(r['added_ns_px'], 1)} [{r['added_ns_px_q1']:.1f}, {r['added_ns_px_q3']:.1f}]"
        )
        lines.append(
            f"| {r['mode']} | `{r['variant']}` | {r['feature']} | {r['light_sources']} | "
            f"{r['wall_ms']:.1f} ({r['wall_iqr_ms']:.1f}) | {r['cpu_ms']:.1f} "
            f"({r['cpu_iqr_ms']:.1f}) | {added} | {ns} |"
        )
    return lines


def markdown(
    meta: dict[str, Any], rs: list[dict[str, Any]], cmp: list[dict[str, Any]] | None
) -> str:
    info = meta["machine"]
    base = next(r for r in rs if r["variant"] == "baseline" and r["mode"] == "phong")
    out = [
        "# What each lighting feature costs",
        "",
        f"Generated by `bench/bench_features.py` on {meta['date']}; raw numbers in "
        f"`{meta['csv']}`. Every figure was measured in that run on the machine below.",
        "",
        "## Reproduce",
        "",
        "```sh",
        "make bench    # also runs: .venv/bin/python bench/bench_features.py --write docs/FEATURE_COSTS.md",  # noqa: E501
        "# with the before/after comparison (builds that commit once into target/bench-before/):",
        f"make bench AGAINST={DEFAULT_BEFORE}",
        "# or this benchmark alone:",
        f".venv/bin/python bench/bench_features.py --write docs/FEATURE_COSTS.md --against-commit {DEFAULT_BEFORE}",  # noqa: E501
        "```",
        "",
        "`--quick` is a smoke run of a few rounds; `--seconds S` sets how long to keep measuring; "
        "`--threads N` the worker threads per frame; `--csv PATH` where the raw numbers go.",
        "",
        "## Machine",
        "",
        "| | |",
        "|---|---|",
        *[f"| {k} | {v} |" for k, v in info.items()],
        f"| load average (1 min) at start / end | {meta['load'][0]:.2f} / {meta['load'][1]:.2f} |",
        f"| benchmark wall time | {meta['wall_s']:.0f} s |",
        "",
        "A shared 2-core virtual machine: other engineers' builds ran at the same time (see the "
        "load average: above 2 means the cores were oversubscribed). Wall times are therefore "
        "noisy; the costs are computed from the process's CPU time per frame, which leaves out "
        "the time the renderer waited for a core, and from frames close together in time. The "
        "IQRs show how much noise is left; costs whose brackets span zero are not resolved.",
        "",
        "## What is measured",
        "",
        f"One scene: a unit UV sphere of {meta['triangles']:,} triangles (exact vertex normals, "
        f"`gold`), seen by a 45° perspective camera so its silhouette spans 95 % of the height "
        f"of a {WIDTH}×{HEIGHT} frame: {base['covered_px']:,} covered pixels "
        f"({base['covered_px'] / (WIDTH * HEIGHT):.0%} of the frame; finite depth in "
        "`render_frame(..., return_depth=True)`). The **baseline** is the scene ambient (0.2) "
        "plus one directional light, Blinn-Phong specular, local viewer, one-sided lighting, no "
        "fog. Every other variant changes exactly one thing (the *what it adds* column). "
        f"Frames are u8 RGB rendered with {meta['threads']} worker thread(s); each is one "
        "`sl.render_frame` call, timed in wall time and in process CPU time.",
        "",
        "Method: build every (mode, variant) scene, count its covered pixels, render one "
        f"warm-up frame, then {meta['rounds']} rounds. A round renders every variant once in a "
        "freshly shuffled order, with the baseline of each mode at its start, middle and end. "
        "*Wall ms* and *CPU ms* are medians (IQR) over a variant's frames. *Added CPU ms* is the "
        "median over frames of (variant − the baseline frame of the same mode nearest to it in "
        "the same round), in CPU time, with the IQR of those differences; *added ns/px* is that "
        "divided by the covered pixels, with the first and third quartiles in brackets (the "
        "median added wall time is in the CSV). *Light sources* is `stats['light_sources']`, the "
        "point sources the renderer evaluates (an area light counts samples²). Negative costs are "
        "savings, or noise when the bracket spans zero.",
        "",
    ]
    if cmp:
        out += [
            f"## The baseline against an earlier build ({meta['before'][:7]})",
            "",
            f"Before = `{meta['before']}` (“{meta['before_subject']}”)"
            + (
                ", the parent of the first lighting commit of issue 3 (9d219f3)"
                if meta["before"].startswith(DEFAULT_BEFORE)
                else ""
            )
            + ". The earlier commit is built with one codegen unit, as the release profile "
            "builds ours (with several, the partition decided whether lane loops were "
            "vectorised). Both builds rendered the baseline scene in "
            "their own worker process (this script with `--worker`, under each build's venv), "
            "one frame each in alternation, the first of each pair alternating too. Ratio = "
            "median over pairs of now / before in CPU time (below 1: now is faster); the wall-time "
            "ratio, noisier, is given for comparison. Raw numbers: "
            f"`{meta['csv'].replace('.csv', '_before.csv')}`.",
            "",
            "| mode | frames each | now CPU ms (IQR) | before CPU ms (IQR) | now / before [q1, q3] "
            "| wall-time ratio |",
            "|---|---:|---:|---:|---:|---:|",
        ]
        for c in cmp:
            out.append(
                f"| {c['mode']} | {c['frames']} | {c['now_cpu_ms']:.1f} "
                f"({c['now_cpu_iqr_ms']:.1f}) | {c['before_cpu_ms']:.1f} "
                f"({c['before_cpu_iqr_ms']:.1f}) | {c['ratio']:.3f} [{c['ratio_q1']:.3f}, "
                f"{c['ratio_q3']:.3f}] | {c['wall_ratio']:.3f} |"
            )
        same = {c["covered_now"] == c["covered_before"] for c in cmp}
        out += [
            "",
            "Both builds covered the same pixels."
            if same == {True}
            else "The builds covered different pixel counts (see the CSV).",
            "",
        ]
    else:
        out += [
            "## The baseline against an earlier build",
            "",
            f"Not measured in this run (it needs a second build): add `--against-commit "
            f"{DEFAULT_BEFORE}`.",
            "",
        ]
    out += ["## Cost of each feature", "", *table(rs), ""]
    out += ["## Reading", "", *meta["reading"], ""]
    return "\n".join(out)


def reading(rs: list[dict[str, Any]], cmp: list[dict[str, Any]] | None) -> list[str]:
    """A few sentences computed from the numbers (so they stay true when regenerated): each
    cost with its bracket, and "within noise" when the bracket spans zero."""
    by = {(r["mode"], r["variant"]): r for r in rs}

    def ns(name: str, mode: str = "phong") -> str:
        r = by.get((mode, name))
        if r is None:
            return "n/a"
        lo, hi = r["added_ns_px_q1"], r["added_ns_px_q3"]
        noise = " (within noise)" if lo <= 0 <= hi else ""
        return f"{r['added_ns_px']:+.1f} ns/px{noise}"

    def have(*names: str) -> bool:
        return all(("phong", n) in by for n in names)

    lines = []
    if cmp:
        lines.append(
            "- The baseline against the earlier build, now / before in CPU time: "
            + ", ".join(
                f"{c['mode']} {c['ratio']:.3f} [{c['ratio_q1']:.3f}, {c['ratio_q3']:.3f}]"
                for c in cmp
            )
            + " (1 = as fast; see the table above for the frame times)."
        )
    if have("emission", "dir_ambient", "two_sided", "spec_blinn_norm"):
        lines.append(
            "- Folded once per render (constants, or a choice made once): emission "
            f"{ns('emission')}, a directional light's own ambient {ns('dir_ambient')}, "
            f"two_sided on this closed sphere {ns('two_sided')}, the normalised lobe "
            f"{ns('spec_blinn_norm')}."
        )
    if have("no_specular", "infinite_viewer", "spec_phong"):
        lines.append(
            f"- Less work per pixel: ks = 0 skips the specular lobe ({ns('no_specular')}); the "
            f"infinite viewer skips normalising v ({ns('infinite_viewer')}); Phong's r·v instead "
            f"of the half vector: {ns('spec_phong')}."
        )
    if have("dir_2", "dir_8", "point", "point_att", "spot", "spot_smooth"):
        per_dir = by[("phong", "dir_8")]["added_ns_px"] / 7
        lines.append(
            f"- Lights, per pixel in Phong: each extra directional light about {per_dir:.1f} "
            f"ns/px (2nd {ns('dir_2')}, 8 in all {ns('dir_8')}); a point light {ns('point')} (l "
            f"and its length per pixel); with attenuation {ns('point_att')}, and ambient as well "
            f"{ns('point_att_amb')}; a spot light {ns('spot')}, with an inner cone and exponent "
            f"{ns('spot_smooth')}."
        )
    if have("area_rect_2", "area_rect_4", "area_rect_8", "area_disk_4", "area_one_sided_4"):
        per_point = by[("phong", "area_rect_8")]["added_ns_px"] / 64
        lines.append(
            f"- An area light costs its samples² point lights: samples 2/4/8 add "
            f"{ns('area_rect_2')} / {ns('area_rect_4')} / {ns('area_rect_8')}, about "
            f"{per_point:.1f} ns/px per point at 8×8; a disk of 4×4 points "
            f"{ns('area_disk_4')} (the rectangle: {ns('area_rect_4')}). One-sided, each point "
            f"is a spot light (cutoff 90°, exponent 1) and the light costs "
            f"{ns('area_one_sided_4')} at 4×4."
        )
    if have("fog_linear", "fog_exp", "fog_exp2"):
        lines.append(
            f"- Fog, per pixel in every mode: in Phong linear {ns('fog_linear')}, exp "
            f"{ns('fog_exp')}, exp2 {ns('fog_exp2')}; in Gouraud (exp2) {ns('fog_exp2', 'gouraud')}"
            f" and flat (exp2) {ns('fog_exp2', 'flat')}, which otherwise need no per-pixel "
            "position."
        )
    others = [
        r for r in rs if r["mode"] != "phong" and r["variant"] not in ("baseline", "fog_exp2")
    ]
    if others:
        lines.append(
            "- Gouraud lights the vertices and flat the triangles (here ~50k vertices and ~100k "
            "triangles for ~830k pixels), so their light costs are per vertex or triangle, "
            "shown per pixel for comparison: "
            + "; ".join(
                f"{r['mode']} `{r['variant']}` {ns(r['variant'], r['mode'])}" for r in others
            )
            + "."
        )
    return lines


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="smoke run: a few rounds")
    p.add_argument("--write", type=Path, help="write the Markdown report here")
    p.add_argument("--csv", type=Path, default=DEFAULT_CSV, help="raw numbers (CSV)")
    p.add_argument("--threads", type=int, default=1, help="worker threads per frame (1)")
    p.add_argument("--seconds", type=float, help="keep measuring for this long (default 200)")
    p.add_argument("--modes", default="phong,gouraud,flat", help="comma-separated")
    p.add_argument(
        "--against-commit",
        metavar="REV",
        help=f"also time the baseline with REV's build (e.g. {DEFAULT_BEFORE})",
    )
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    if a.worker:
        return worker_main(a.threads)

    modes = [m.strip() for m in a.modes.split(",") if m.strip()]
    before_py = build_commit(a.against_commit) if a.against_commit else None
    t0, load0 = time.time(), os.getloadavg()[0]
    seconds = a.seconds if a.seconds is not None else (2.0 if a.quick else 200.0)
    series, rounds = measure(configurations(modes), a.threads, 2 if a.quick else 12, seconds, 3)
    rs = rows(series, a.threads)
    cmp = None
    if before_py:
        cmp = compare_builds(before_py, modes, a.threads, 4 if a.quick else 60)
    wall, load1 = time.time() - t0, os.getloadavg()[0]

    for line in table(rs):
        print(line)
    if cmp:
        for c in cmp:
            print(c)
    csv_path = a.csv if a.csv.is_absolute() else Path.cwd() / a.csv
    write_csv(csv_path, rs)
    if cmp:
        write_csv(csv_path.with_name(csv_path.stem + "_before.csv"), cmp)
    if a.write:
        meta = {
            "date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "csv": os.path.relpath(csv_path, ROOT),
            "machine": machine(_sl().__version__),
            "load": (load0, load1),
            "wall_s": wall,
            "threads": a.threads,
            "rounds": rounds,
            "triangles": 2 * (2 * SPHERE_RINGS) * (SPHERE_RINGS - 1),
            "reading": reading(rs, cmp),
        }
        if a.against_commit:
            meta["before"] = _git("rev-parse", "--short", a.against_commit)
            meta["before_subject"] = _git("log", "-1", "--format=%s", a.against_commit)
        a.write.write_text(markdown(meta, rs, cmp))
        print(f"wrote {a.write}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
