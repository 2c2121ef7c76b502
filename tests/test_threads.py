"""Threads: bit-identical images for any thread count, concurrent Python threads, the GIL
released while rendering."""

from __future__ import annotations

import concurrent.futures
import threading
import time

import numpy as np
import pytest
import shadelab_rs as sl

# --------------------------------------------------------------------------------------------
# Threads: determinism, concurrency, GIL
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
def test_thread_count_is_bit_identical(make_scene, shading):
    spot = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
    scene = make_scene(spot)
    cam = sl.frame_mesh(spot.vertices)
    kw = dict(width=200, height=150, shading=shading, dtype="float32", return_depth=True)
    ref_img, ref_depth = sl.render(scene, cam, threads=1, **kw)
    for threads in (2, 3, 7, None):
        img, depth = sl.render(scene, cam, threads=threads, **kw)
        assert img.tobytes() == ref_img.tobytes(), threads
        assert depth.tobytes() == ref_depth.tobytes(), threads
    assert np.isfinite(ref_depth).sum() > 0.1 * ref_depth.size


def test_concurrent_python_threads_match_sequential():
    scene, cam = sl.demo_scene()
    jobs = [
        dict(width=160, height=120, shading=sh, dtype=dt, threads=th)
        for sh in ("flat", "gouraud", "phong")
        for dt in ("uint8", "float32")
        for th in (1, None)
    ]
    alone = [sl.render(scene, cam, **j).tobytes() for j in jobs]
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        together = list(pool.map(lambda j: sl.render(scene, cam, **j).tobytes(), jobs * 2))
    assert together == alone * 2


def test_render_releases_the_gil(make_scene):
    """While one thread renders, another keeps running Python code: a busy loop stamps the
    time while the render runs. Were the GIL held, the loop could run only before the render
    began (one 5 ms switch interval at most) and after it returned, so no stamp could fall
    in the second half of the ~0.1 s render. No speed threshold, so load cannot flake it."""
    spot = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
    scene = make_scene(spot)
    cam = sl.frame_mesh(spot.vertices)
    kw = dict(width=2400, height=1800, shading="phong", threads=1)  # ~0.1 s
    started, done = threading.Event(), threading.Event()
    span = []

    def work():
        started.set()
        t0 = time.perf_counter()
        sl.render(scene, cam, **kw)
        span.extend([t0, time.perf_counter()])
        done.set()

    thread = threading.Thread(target=work)
    thread.start()
    started.wait()
    stamps = []
    while not done.is_set():
        stamps.append(time.perf_counter())
    thread.join()
    t0, t1 = span
    second_half = sum((t0 + t1) / 2 < t < t1 for t in stamps)
    assert second_half > 10, (second_half, len(stamps), t1 - t0)
