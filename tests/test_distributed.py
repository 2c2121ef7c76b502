"""render_many over concurrent.futures executors and a Dask LocalCluster: identical to
render_batch, in camera order; worker death loses nothing and duplicates nothing."""

from __future__ import annotations

import multiprocessing
import os
import signal
from concurrent.futures import Executor, Future, ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
import shadelab_rs as sl
from PIL import Image
from shadelab_rs.distributed import WorkersLost, render_many

KW = dict(width=48, height=36, threads=1)

# Python 3.12+ warns when a process with threads (our idle worker pools) forks; the pools
# are fork-safe (a child starts its own), which is what these tests check.
pytestmark = pytest.mark.filterwarnings(
    "ignore:This process .* is multi-threaded, use of fork:DeprecationWarning"
)


@pytest.fixture(scope="module")
def scene_cams() -> tuple[sl.Scene, list[sl.Camera]]:
    scene, _ = sl.demo_scene()
    cams = [
        sl.Camera.look_at((4 * np.sin(a), 1.2, 4 * np.cos(a)), (0, -0.1, 0), fov_y=40)
        for a in np.linspace(0, 2 * np.pi, 13, endpoint=False)
    ]
    return scene, cams


@pytest.fixture(scope="module")
def pool():
    # fork: workers start in milliseconds and inherit the imported extension.
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("fork")) as ex:
        yield ex


def _png(path: Path) -> bytes:
    return np.asarray(Image.open(path)).tobytes()


def test_process_pool_matches_render_batch(scene_cams, pool):
    scene, cams = scene_cams
    want, want_depth = sl.render_batch(scene, cams, return_depth=True, **KW)
    for chunk in (None, 1, 5):
        got, depth = render_many(scene, cams, pool, chunk_size=chunk, return_depth=True, **KW)
        assert got.tobytes() == want.tobytes(), chunk
        assert depth.tobytes() == want_depth.tobytes(), chunk
    f32 = render_many(scene, cams[:3], pool, dtype="float32", **KW)
    assert f32.dtype == np.float32
    assert f32.tobytes() == sl.render_batch(scene, cams[:3], dtype="float32", **KW).tobytes()


def test_thread_pool_and_progress(scene_cams):
    scene, cams = scene_cams
    seen: list[tuple[int, int]] = []
    with ThreadPoolExecutor(2) as ex:
        got = render_many(
            scene, cams, ex, chunk_size=4, progress=lambda d, t: seen.append((d, t)), **KW
        )
    assert got.tobytes() == sl.render_batch(scene, cams, **KW).tobytes()
    assert [d for d, _ in seen] == sorted(d for d, _ in seen) and seen[-1] == (13, 13)


def test_workers_write_files(scene_cams, pool, tmp_path):
    scene, cams = scene_cams
    paths = render_many(scene, cams, pool, output_dir=tmp_path, chunk_size=3, **KW)
    assert paths == [tmp_path / f"{i:05d}.png" for i in range(len(cams))]
    want = sl.render_batch(scene, cams, **KW)
    for i, p in enumerate(paths):
        assert _png(p) == want[i].tobytes()
    assert sorted(os.listdir(tmp_path)) == [p.name for p in paths]


class _FlakyExecutor(Executor):
    """Delegates to ``inner``; the submissions numbered in ``fail`` raise in the worker, and
    the one numbered ``kill`` kills its worker process (a ProcessPoolExecutor then breaks)."""

    def __init__(self, inner: Executor, fail=(), kill=None):
        self.inner, self.fail, self.kill, self.n = inner, set(fail), kill, 0

    def submit(self, fn, /, *args, **kwargs) -> Future:
        self.n += 1
        if self.n in self.fail:
            return self.inner.submit(_raise, self.n)
        if self.n == self.kill:
            return self.inner.submit(_die)
        return self.inner.submit(fn, *args, **kwargs)


def _raise(n: int) -> None:
    raise OSError(f"transient failure of submission {n}")


def _die() -> None:
    os.kill(os.getpid(), signal.SIGKILL)


def test_failed_chunks_are_retried_once_each(scene_cams, pool):
    scene, cams = scene_cams
    flaky = _FlakyExecutor(pool, fail={1, 3})
    got = render_many(scene, cams, flaky, chunk_size=4, retries=1, **KW)
    assert got.tobytes() == sl.render_batch(scene, cams, **KW).tobytes()
    assert flaky.n == 4 + 2  # four chunks, two resubmissions
    always = _FlakyExecutor(pool, fail=set(range(1, 100)))
    with pytest.raises(OSError, match="transient failure"):
        render_many(scene, cams, always, chunk_size=4, retries=2, **KW)


def test_killed_worker_loses_nothing_and_resumes_without_duplicates(scene_cams, tmp_path):
    """A worker process dies while rendering chunk 3: the process pool breaks, render_many
    names the views not rendered, the frames written stay, and a second call with a new
    executor renders exactly the missing views."""
    scene, cams = scene_cams
    fork = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(2, mp_context=fork) as ex, pytest.raises(WorkersLost) as info:
        render_many(
            scene, cams, _FlakyExecutor(ex, kill=3), output_dir=tmp_path, chunk_size=2, **KW
        )
    missing = info.value.missing
    # Chunks 0 and 1 (views 0 to 3) may have finished before the pool broke; chunk 2
    # (views 4, 5) never did.
    assert {4, 5} <= set(missing)
    on_disk = {int(p.stem) for p in tmp_path.glob("*.png")}
    assert on_disk.isdisjoint(missing) and on_disk | set(missing) == set(range(len(cams)))
    assert not list(tmp_path.glob(".*"))  # no half-written temporaries
    counted = _FlakyExecutor(ThreadPoolExecutor(2))
    render_many(scene, cams, counted, output_dir=tmp_path, chunk_size=1, **KW)
    assert counted.n == len(missing)  # only the missing views were rendered again
    want = sl.render_batch(scene, cams, **KW)
    names = sorted(os.listdir(tmp_path))
    assert names == [f"{i:05d}.png" for i in range(len(cams))]  # no duplicates, no temporaries
    for i in range(len(cams)):
        assert _png(tmp_path / f"{i:05d}.png") == want[i].tobytes()


def test_bad_arguments(scene_cams, pool):
    scene, cams = scene_cams
    with pytest.raises(TypeError, match=r"cameras\[1\] must be a Camera"):
        render_many(scene, [cams[0], "x"], pool)
    with pytest.raises(TypeError, match="executor must be"):
        render_many(scene, cams, object())
    with pytest.raises(TypeError, match="scene must be a Scene"):
        render_many([scene], cams, pool)
    with pytest.raises(ValueError, match="same file name"):
        render_many(scene, cams, pool, output_dir="unused", pattern="frame.png")


def test_progress_bar_when_tqdm_is_installed(scene_cams, monkeypatch):
    import sys
    import types

    scene, cams = scene_cams
    updates: list[int] = []

    class FakeBar:
        def __init__(self, total, **kw):
            self.total, self.n = total, 0

        def update(self, k):
            self.n += k
            updates.append(self.n)

        def close(self):
            updates.append(-1)

    fake = types.ModuleType("tqdm.auto")
    fake.tqdm = FakeBar  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "tqdm.auto", fake)
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    with ThreadPoolExecutor(2) as ex:
        render_many(scene, cams, ex, chunk_size=5, progress=True, **KW)
        assert updates[-2:] == [13, -1] and updates == [*sorted(updates[:-1]), -1]
        updates.clear()
        render_many(scene, cams, ex, chunk_size=5, **KW)  # 13 views: short, no bar
    assert updates == []
