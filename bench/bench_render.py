#!/usr/bin/env python3
"""Frame-time benchmark of shadelab_rs at 1920x1080 (``make bench``).

Renders UV spheres of about 1k, 10k, 100k and 1M triangles that fill most of the frame
height, and the bundled demo scene, in each shading mode (flat, Gouraud, Phong) with 1 and 2
worker threads. Each (scene, mode) pair is warmed up, then frames at 1 and 2 threads are
timed alternately, so slow drifts in machine load hit both thread counts alike. Reported per
configuration: median and interquartile range of the wall time of ``sl.render_frame`` (the
whole Python call: argument conversion, render, NumPy hand-off), Mtri/s (triangles submitted
per second), Mpix/s (covered pixels per second) and the medians of the per-stage times the
renderer reports in ``stats``.

    python bench/bench_render.py                 # full run, table on stdout
    python bench/bench_render.py --quick         # smoke run, a few frames each
    python bench/bench_render.py --write docs/BENCHMARKS.md   # also the Markdown report

Only NumPy and the standard library besides shadelab_rs; nothing is imported from tests/.
"""

from __future__ import annotations

import argparse
import csv
import datetime as _dt
import gc
import math
import os
import platform
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import shadelab_rs as sl

WIDTH, HEIGHT = 1920, 1080
FOV_Y = 45.0
# The sphere's silhouette spans this fraction of the frame height.
SPHERE_FILL = 0.95
MODES = ("flat", "gouraud", "phong")
THREADS = (1, 2)
STAGES = ("vertex_ms", "setup_ms", "binning_ms", "raster_shade_ms")
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


FULL = Budget(warmup_frames=2, min_frames=7, max_frames=60, seconds=2.5)
QUICK = Budget(warmup_frames=1, min_frames=3, max_frames=5, seconds=0.3)


# --------------------------------------------------------------------------- geometry


def uv_sphere(n_lat: int, n_lon: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit UV sphere at the origin: single-vertex poles, ``n_lat - 1`` rings of ``n_lon``
    vertices, counter-clockwise faces seen from outside. Returns float32 vertices
    ``(2 + (n_lat-1)*n_lon, 3)`` and int32 faces ``(2*n_lon*(n_lat-1), 3)``."""
    if n_lat < 2 or n_lon < 3:
        raise ValueError("uv_sphere needs n_lat >= 2 and n_lon >= 3")
    theta = np.pi * np.arange(1, n_lat) / n_lat
    phi = 2.0 * np.pi * np.arange(n_lon) / n_lon
    st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
    ring = np.stack(
        [st * np.sin(phi), np.broadcast_to(ct, (n_lat - 1, n_lon)), st * np.cos(phi)], axis=-1
    ).reshape(-1, 3)
    verts = np.concatenate([[[0.0, 1.0, 0.0]], ring, [[0.0, -1.0, 0.0]]])
    south = len(verts) - 1

    j = np.arange(n_lon)
    j1 = (j + 1) % n_lon
    north_cap = np.stack([np.zeros(n_lon, dtype=np.int64), 1 + j, 1 + j1], axis=-1)
    i = np.arange(n_lat - 2)[:, None]
    a, b = 1 + i * n_lon + j, 1 + i * n_lon + j1
    c, d = a + n_lon, b + n_lon
    bands = np.stack([np.stack([a, c, d], -1), np.stack([a, d, b], -1)], axis=2).reshape(-1, 3)
    last = 1 + (n_lat - 2) * n_lon
    south_cap = np.stack([last + j, np.full(n_lon, south), last + j1], axis=-1)
    faces = np.concatenate([north_cap, bands, south_cap])
    return verts.astype(np.float32), faces.astype(np.int32)


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
    return sl.Camera.look_at(
        eye=(0.0, 0.0, dist), target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov_y=FOV_Y,
        near=0.1, far=dist + 10.0,
    )  # fmt: skip


def sphere_scene(n: int) -> tuple[sl.Scene, sl.Camera]:
    verts, faces = uv_sphere(n, 2 * n)
    _check_outward(verts, faces)
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    scene.add(sl.Mesh(verts, faces, normals=verts), material=sl.Material.preset("gold"))
    scene.add_light(sl.DirectionalLight(direction=(-1.0, -1.0, -1.0)))
    scene.add_light(sl.PointLight(position=(2.0, 3.0, 4.0), color=(0.4, 0.4, 0.5)))
    return scene, sphere_camera()


def scenes() -> list[tuple[str, sl.Scene, sl.Camera]]:
    out = [(name, *sphere_scene(n)) for name, n in SPHERES]
    out.append(("demo", *sl.demo_scene()))
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
    stages: dict[str, list[float]] = field(default_factory=lambda: {s: [] for s in STAGES})
    triangles_setup: int = 0
    triangles_clipped: int = 0

    def quartiles(self) -> tuple[float, float, float]:
        q1, q2, q3 = np.percentile(self.times_ms, [25, 50, 75])
        return float(q1), float(q2), float(q3)

    @property
    def median_ms(self) -> float:
        return statistics.median(self.times_ms)

    def stage_ms(self, stage: str) -> float:
        return statistics.median(self.stages[stage])

    @property
    def other_ms(self) -> float:
        """Median over frames of the wall time not inside a reported stage."""
        rest = [t - sum(self.stages[s][k] for s in STAGES) for k, t in enumerate(self.times_ms)]
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
            "mtri_per_s": round(self.triangles / med / 1e3, 3),
            "mpix_per_s": round(self.covered_px / med / 1e3, 3),
            **{s: round(self.stage_ms(s), 3) for s in STAGES},
            "other_ms": round(self.other_ms, 3),
            "triangles_setup": self.triangles_setup,
            "triangles_clipped": self.triangles_clipped,
        }


def _frame(scene: sl.Scene, camera: sl.Camera, mode: str, threads: int) -> tuple[float, dict]:
    t0 = time.perf_counter()
    out = sl.render_frame(scene, camera, width=WIDTH, height=HEIGHT, shading=mode,
                          threads=threads)  # fmt: skip
    return (time.perf_counter() - t0) * 1e3, out["stats"]


def covered_pixels(scene: sl.Scene, camera: sl.Camera) -> int:
    """Pixels some triangle is visible in: finite depth (counted once per scene)."""
    _, depth = sl.render(scene, camera, width=WIDTH, height=HEIGHT, return_depth=True)
    return int(np.isfinite(depth).sum())


def measure_pair(
    name: str, scene: sl.Scene, camera: sl.Camera, mode: str, covered: int, budget: Budget
) -> list[Result]:
    """Times one (scene, mode) at every thread count, alternating thread counts frame by
    frame after a warm-up."""
    tris = scene.triangle_count if isinstance(scene.triangle_count, int) else None
    results = [Result(name, 0, covered, mode, t) for t in THREADS]
    for _ in range(budget.warmup_frames):
        for r in results:
            _frame(scene, camera, mode, r.threads)
    gc.collect()
    gc.disable()
    try:
        start = time.perf_counter()
        while True:
            for r in results:
                ms, stats = _frame(scene, camera, mode, r.threads)
                r.times_ms.append(ms)
                for s in STAGES:
                    r.stages[s].append(float(stats[s]))
                r.triangles = int(stats["triangles_in"])
                r.triangles_setup = int(stats["triangles_setup"])
                r.triangles_clipped = int(stats["triangles_clipped"])
            n = len(results[0].times_ms)
            elapsed = time.perf_counter() - start
            if n >= budget.max_frames or (n >= budget.min_frames and elapsed >= budget.seconds):
                break
    finally:
        gc.enable()
    del tris
    return results
