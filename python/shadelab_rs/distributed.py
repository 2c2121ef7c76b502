"""Many views over many processes or machines, on an existing engine.

``render_many(scene, cameras, executor, ...)`` splits the cameras into chunks and renders
each chunk with :func:`shadelab_rs.render_batch` on ``executor``: any
:class:`concurrent.futures.Executor` (``ProcessPoolExecutor``, ``ThreadPoolExecutor``, loky,
mpi4py's ``MPIPoolExecutor``, ...) or a ``dask.distributed.Client`` (``pip install
shadelab_rs[dask]``). Results come back in camera order, or are written to disk by the
workers.

Policy (see the user guide, "Many views"):

- Every view belongs to exactly one chunk and its result is stored under its index, so a
  retried chunk can never duplicate a frame; files are written to a temporary name and
  renamed into place, so a killed worker never leaves a truncated image under a final name.
- Dask: the scene is scattered once to every worker; a chunk whose worker dies is
  rescheduled by the scheduler on another worker, and a chunk that raises is retried
  ``retries`` times.
- ``concurrent.futures``: a chunk that raises is resubmitted up to ``retries`` times. A
  ``ProcessPoolExecutor`` whose worker process dies is broken for good (Python's rule), so
  :class:`WorkersLost` is raised naming the views that were not rendered; with
  ``output_dir`` the frames already written stay, and calling ``render_many`` again with a
  new executor renders only the missing ones (``resume=True``, the default).
"""

from __future__ import annotations

import math
import os
import pickle
import sys
import uuid
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, Future
from concurrent.futures import wait as wait_futures
from pathlib import Path
from typing import Any

import numpy as np

from ._core import Camera, RenderOptions, Scene
from .batch import Progress, _progress

__all__ = ["WorkersLost", "render_many"]


class WorkersLost(RuntimeError):
    """Workers died or the executor broke before every view was rendered.

    ``missing`` lists the indices of the views not rendered (with ``output_dir``, the
    others are on disk, and a new call with ``resume=True`` renders only these)."""

    def __init__(self, message: str, missing: list[int]):
        super().__init__(message)
        self.missing = missing


# Unpickled scenes, per worker process, by token: a worker that renders many chunks of the
# same batch unpickles the scene once.
_SCENES: dict[str, Scene] = {}


def _scene_of(token: str, scene: Scene | bytes) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if token not in _SCENES:
        _SCENES.clear()  # one batch at a time per process: keep memory bounded
        _SCENES[token] = pickle.loads(scene)
    return _SCENES[token]


def _write(path: Path, image: np.ndarray) -> None:
    """Writes ``image`` under a temporary name, then renames it into place (atomic)."""
    from .io import save_image

    tmp = path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:8]}.tmp{path.suffix}")
    if path.suffix == ".npy":
        np.save(tmp, image)
    else:
        save_image(image, tmp)
    os.replace(tmp, path)


def _render_chunk(
    token: str,
    scene: Scene | bytes,
    indices: list[int],
    cameras: list[Camera],
    options: dict[str, Any],
    output: tuple[str, str] | None,
) -> Any:
    """Runs on a worker: renders the views ``indices`` and returns them (or writes them)."""
    from .batch import render_batch

    s = _scene_of(token, scene)
    if output is None:
        return indices, render_batch(s, cameras, progress=False, **options)
    directory, pattern = output

    def save(i: int, image: np.ndarray) -> None:
        _write(Path(directory) / pattern.format(indices[i]), image)

    render_batch(s, cameras, callback=save, progress=False, **options)
    return indices, None


def _is_dask_client(executor: object) -> bool:
    if "distributed" not in sys.modules:
        return False
    from distributed import Client

    return isinstance(executor, Client)


def _n_workers(executor: object, dask: bool) -> int:
    if dask:
        return max(1, len(executor.scheduler_info()["workers"]))  # type: ignore[attr-defined]
    return int(getattr(executor, "_max_workers", 0) or os.cpu_count() or 1)


def render_many(
    scene: Scene,
    cameras: Sequence[Camera],
    executor: Any,
    *args: Any,
    options: RenderOptions | None = None,
    chunk_size: int | None = None,
    retries: int = 2,
    output_dir: str | os.PathLike[str] | None = None,
    pattern: str = "{:05d}.png",
    resume: bool = True,
    progress: Progress = None,
    **render_options: Any,
) -> Any:
    """Renders ``scene`` through every camera on ``executor`` (a
    ``concurrent.futures.Executor`` or a ``dask.distributed.Client``).

    Returns the images in camera order as one ``(N, height, width, 3)`` array (a tuple with
    depths for ``return_depth=True``), identical to ``render_batch(scene, cameras, ...)``.
    With ``output_dir``, the workers write view ``i`` to ``output_dir / pattern.format(i)``
    (PNG, JPEG, ... by extension, or ``.npy``) and the list of paths is returned; with
    ``resume`` (default) views whose file already exists are skipped.

    ``chunk_size``: views per task (default: about four tasks per worker, at most 64 views).
    ``retries``: how many times a chunk that raised is tried again. ``progress`` as for
    :func:`shadelab_rs.render_batch` (a tqdm bar in this process for long batches when tqdm
    is installed, False for none, or a callable ``progress(done, total)``), updated as
    chunks finish. Give each worker process a share
    of the cores with ``threads=`` (e.g. ``threads=cores // processes``). The render options
    are those of :func:`shadelab_rs.render_batch` (``RenderOptions``' arguments, ``options=``,
    ``dtype``, ``return_depth``); they are checked here, before any task is sent.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    cameras = list(cameras)
    for i, c in enumerate(cameras):
        if not isinstance(c, Camera):
            raise TypeError(f"cameras[{i}] must be a Camera, got {type(c).__name__}")
    if retries < 0:
        raise ValueError(f"retries must be >= 0, got {retries}")
    dtype = render_options.pop("dtype", None)
    return_depth = render_options.pop("return_depth", False)
    if output_dir is not None and return_depth:
        raise ValueError("return_depth is not supported with output_dir (images only)")
    # One checked RenderOptions for every worker (it pickles).
    if options is None:
        opts = RenderOptions(*args, **render_options)
    elif args:
        raise TypeError("give the render options either as options= or as arguments, not both")
    else:
        opts = options.replace(**render_options)
    options_kw: dict[str, Any] = {"options": opts, "dtype": dtype, "return_depth": return_depth}
    n = len(cameras)
    dask = _is_dask_client(executor)
    if not dask and not isinstance(executor, Executor):
        raise TypeError(
            "executor must be a concurrent.futures.Executor or a dask.distributed.Client, "
            f"got {type(executor).__name__}"
        )

    output: tuple[str, str] | None = None
    todo = list(range(n))
    paths: list[Path] = []
    if output_dir is not None:
        out = Path(output_dir)
        output = (str(out), pattern)
        paths = [out / pattern.format(i) for i in range(n)]
        if len(set(paths)) != n:
            raise ValueError(f"pattern {pattern!r} gives the same file name to several views")
        out.mkdir(parents=True, exist_ok=True)
        if resume:
            todo = [i for i in todo if not paths[i].exists()]

    workers = _n_workers(executor, dask)
    size = chunk_size or max(1, min(64, math.ceil(len(todo) / (4 * workers))))
    if size < 1:
        raise ValueError(f"chunk_size must be >= 1, got {chunk_size}")
    chunks = [todo[k : k + size] for k in range(0, len(todo), size)]
    token = uuid.uuid4().hex
    results: dict[int, Any] = {}
    done_views = n - len(todo)

    def finished(indices: list[int], value: Any) -> None:
        nonlocal done_views
        for j, i in enumerate(indices):
            if i not in results:  # a chunk is stored once, whatever happened
                results[i] = None if value is None else _pick(value, j)
        done_views = n - len(todo) + len(results)
        if report is not None:
            report(done_views)

    report, bar = _progress(progress, n)
    try:
        if dask:
            _run_dask(
                executor, scene, token, chunks, cameras, options_kw, output, retries, finished
            )
        else:
            _run_futures(
                executor,
                scene,
                token,
                chunks,
                cameras,
                options_kw,
                output,
                retries,
                finished,
                results,
            )
    except WorkersLost as e:
        if output_dir is not None:
            # A chunk cut short may have written some of its views (each file complete:
            # written under a temporary name, then renamed): only the others are missing.
            _remove_stray_temporaries(Path(output_dir))
            e.missing = [i for i in e.missing if not paths[i].exists()]
            e.args = (f"{e.args[0]}; {len(e.missing)} views have no file",)
        raise
    finally:
        if bar is not None:
            bar.close()
    if output_dir is not None:
        _remove_stray_temporaries(Path(output_dir))
        return paths
    return _assemble(results, n, opts.height, opts.width, options_kw)


def _pick(value: Any, j: int) -> Any:
    if isinstance(value, tuple):
        return value[0][j], value[1][j]
    return value[j]


def _assemble(results: dict[int, Any], n: int, h: int, w: int, options: dict[str, Any]) -> Any:
    dtype = np.dtype(options.get("dtype") or "uint8")
    images = np.empty((n, h, w, 3), dtype)
    depths = np.empty((n, h, w), np.float32) if options.get("return_depth") else None
    for i in range(n):
        r = results[i]
        if depths is not None:
            images[i], depths[i] = r
        else:
            images[i] = r
    return (images, depths) if depths is not None else images


def _remove_stray_temporaries(directory: Path) -> None:
    """Deletes half-written files a killed worker left behind (``.name.pid.xxxx.tmp.ext``)."""
    for p in directory.glob(".*.tmp*"):
        p.unlink(missing_ok=True)


def _run_futures(
    executor: Executor,
    scene: Scene,
    token: str,
    chunks: list[list[int]],
    cameras: list[Camera],
    options: dict[str, Any],
    output: tuple[str, str] | None,
    retries: int,
    finished: Callable[[list[int], Any], None],
    results: dict[int, Any],
) -> None:
    # Pickled once here (protocol 5); each worker process unpickles it once per batch.
    blob = pickle.dumps(scene, protocol=pickle.HIGHEST_PROTOCOL)
    tries: dict[int, int] = {}

    def submit(c: int) -> Future[Any]:
        ids = chunks[c]
        return executor.submit(
            _render_chunk, token, blob, ids, [cameras[i] for i in ids], options, output
        )

    pending: dict[Future[Any], int] = {}
    lost: BaseException | None = None
    for c in range(len(chunks)):
        try:
            pending[submit(c)] = c
        except Exception as e:  # broken or shut down: collect what was submitted
            lost = e
            break
    while pending:
        done, _ = wait_futures(list(pending), return_when="FIRST_COMPLETED")
        for f in done:
            c = pending.pop(f)
            try:
                indices, value = f.result()
            except Exception as e:
                if _is_broken(e):
                    lost = e
                    continue
                tries[c] = tries.get(c, 0) + 1
                if tries[c] > retries:
                    for g in pending:
                        g.cancel()
                    raise
                try:
                    pending[submit(c)] = c
                except Exception as e2:
                    lost = e2
                continue
            finished(indices, value)
    if lost is not None:
        missing = sorted(i for ch in chunks for i in ch if i not in results)
        raise WorkersLost(
            f"the executor broke ({type(lost).__name__}: {lost}); "
            f"{len(missing)} views were not rendered: {missing[:20]}"
            + (" ..." if len(missing) > 20 else ""),
            missing,
        ) from lost


def _is_broken(e: BaseException) -> bool:
    from concurrent.futures import BrokenExecutor

    return isinstance(e, BrokenExecutor)


def _run_dask(
    client: Any,
    scene: Scene,
    token: str,
    chunks: list[list[int]],
    cameras: list[Camera],
    options: dict[str, Any],
    output: tuple[str, str] | None,
    retries: int,
    finished: Callable[[list[int], Any], None],
) -> None:
    from distributed import as_completed

    # Sent once to every worker; tasks refer to it by key.
    scene_future = client.scatter(scene, broadcast=True, hash=False)
    futures = [
        client.submit(
            _render_chunk,
            token,
            scene_future,
            ids,
            [cameras[i] for i in ids],
            options,
            output,
            retries=retries,
            pure=False,
            key=f"shadelab-render-{token}-{c}",
        )
        for c, ids in enumerate(chunks)
    ]
    try:
        for f in as_completed(futures):
            indices, value = f.result()
            finished(indices, value)
    finally:
        client.cancel([*futures, scene_future])
