#!/usr/bin/env python3
"""Many views of one scene, four ways (the user guide's "Many views" section as a script;
the test suite runs it, so it stays correct). Cells are separated by ``# %%`` so that
Jupyter (jupytext) and VS Code open it as a notebook.

    python examples/many_views.py OUTDIR [--views N] [--size S]
"""

# %% Set-up: a scene and a turntable of cameras.
from __future__ import annotations

import argparse
import multiprocessing
import pickle
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import shadelab_rs as sl

ap = argparse.ArgumentParser()
ap.add_argument("outdir", type=Path)
ap.add_argument("--views", type=int, default=24)
ap.add_argument("--size", type=int, default=128)
args = ap.parse_args()
args.outdir.mkdir(parents=True, exist_ok=True)
size = dict(width=args.size, height=args.size)

scene, camera = sl.demo_scene()
cameras = [
    sl.Camera.look_at((4.4 * np.sin(a), 1.1, 4.4 * np.cos(a)), (0, -0.1, 0), fov_y=42)
    for a in np.linspace(0, 2 * np.pi, args.views, endpoint=False)
]

# %% 1. One call, one array: (N, H, W, 3) uint8, plus depth.
images, depths = sl.render_batch(scene, cameras, return_depth=True, **size)
print("render_batch:", images.shape, images.dtype, depths.shape)

# %% 2. Streaming to disk: nothing is kept in memory.
sl.render_batch(
    scene,
    cameras,
    callback=lambda i, im: sl.save_image(im, args.outdir / f"frame_{i:04d}.png"),
    **size,
)

# %% 3. Scenes pickle (protocol 5 passes mesh buffers out of band), so process pools work.
buffers: list[pickle.PickleBuffer] = []
data = pickle.dumps(scene, protocol=5, buffer_callback=buffers.append)
print(f"pickled scene: {len(data)} bytes in band, {len(buffers)} buffers out of band")
# fork: this notebook-style script has no `if __name__ == "__main__":` guard, which the
# spawn start method (macOS, Windows) needs; put the pool code under one there.
with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("fork")) as pool:
    again = sl.distributed.render_many(scene, cameras, pool, threads=1, **size)
assert np.array_equal(again, images)

# %% 4. Notebook display: the last expression of a cell shows inline.
preview = sl.preview(scene, camera, width=160, height=120)
(args.outdir / "preview.png").write_bytes(preview._repr_png_())
preview  # noqa: B018 (a notebook cell's last expression is displayed)
