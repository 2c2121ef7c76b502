"""Many views in one call: ``render_batch`` and ``iter_render``.

The loop over views runs in Rust (``_core.render_batch``) with the GIL released while each
frame renders; this module only adds the optional progress bar (tqdm, when installed) and
the iterator form.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any, Union

import numpy as np
from numpy.typing import NDArray

from . import _core
from ._core import Camera, RenderOptions, Scene

#: Batches with at least this many views show a progress bar by default (when tqdm is
#: installed and ``progress`` is None).
PROGRESS_MIN_VIEWS = 50

Progress = Union[bool, None, Callable[[int, int], object]]
Frame = Union[NDArray[Any], tuple[NDArray[Any], NDArray[np.float32]]]


def _count(scene: object, cameras: object) -> int:
    """The number of views (0 when unknown: the core then reports the bad argument)."""
    many = cameras if not isinstance(cameras, Camera) else scene
    if isinstance(many, Scene):
        return 1
    try:
        return len(many)  # type: ignore[arg-type]
    except TypeError:
        return 0


def _progress(progress: Progress, total: int) -> tuple[Callable[[int], object] | None, Any]:
    """``(progress_callable_or_None, bar_to_close_or_None)`` for ``total`` views."""
    if callable(progress):
        user = progress
        return (lambda done: user(done, total)), None
    if progress is False or (progress is None and total < PROGRESS_MIN_VIEWS):
        return None, None
    try:
        tqdm = importlib.import_module("tqdm.auto").tqdm
    except ImportError:  # tqdm is optional: no bar without it
        return None, None
    bar = tqdm(total=total, unit="view", desc="render_batch")
    return (lambda done: bar.update(done - bar.n)), bar


def render_batch(
    scene: Scene | Sequence[Scene],
    cameras: Camera | Sequence[Camera],
    *args: Any,
    options: RenderOptions | None = None,
    callback: Callable[..., object] | None = None,
    progress: Progress = None,
    **render_options: Any,
) -> Any:
    """Renders many views: one scene through many cameras, many scenes through one camera,
    or scenes and cameras in pairs (two sequences of the same length).

    Returns an ``(N, height, width, 3)`` array (uint8, or float32 with ``dtype="float32"``),
    or ``(images, depths)`` with ``return_depth=True`` (depths ``(N, height, width)``
    float32). Frame ``i`` is bit-identical to ``render(scene_i, camera_i, ...)``: the render
    options are :func:`shadelab_rs.render`'s (:class:`RenderOptions`' arguments positionally
    after ``cameras`` or by keyword, or ``options=``, plus ``dtype`` and ``return_depth``),
    and each view gets what ``render`` fills in (near/far planes the camera leaves as None
    fitted to its scene, the default light rig for a scene without lights). ``alpha`` and
    ``encoding`` are not taken (apply them to the frames if needed).

    With ``callback``, nothing is kept: ``callback(i, image)`` (or ``callback(i, image,
    depth)``) is called after each frame, in order, and the function returns None; use it
    to stream batches larger than memory to disk.

    ``progress``: None shows a tqdm bar when tqdm is installed and the batch has at least
    :data:`PROGRESS_MIN_VIEWS` views; True always (when tqdm is installed); False never; a
    callable is called as ``progress(done, total)`` after each frame.

    Errors: every scene and camera is checked before the first frame, so a wrong item is a
    ``TypeError`` naming its index (``cameras[7] must be a Camera``) and nothing renders. An
    error while rendering frame ``i`` (out of memory) or an exception from ``callback`` or
    ``progress`` stops the batch at once and propagates (the message of a render error
    starts with ``view i:``); the frames before ``i`` were already delivered to the
    callback. Ctrl-C (KeyboardInterrupt) is checked between frames and stops the batch the
    same way.
    """
    report, bar = _progress(progress, _count(scene, cameras))
    try:
        return _core.render_batch(
            scene,
            cameras,
            *args,
            options=options,
            callback=callback,
            progress=report,
            **render_options,
        )
    finally:
        if bar is not None:
            bar.close()


def iter_render(
    scene: Scene | Sequence[Scene],
    cameras: Camera | Iterable[Camera],
    *args: Any,
    options: RenderOptions | None = None,
    chunk: int = 16,
    **render_options: Any,
) -> Iterator[Frame]:
    """Yields the frames of :func:`render_batch` one by one (each an image, or ``(image,
    depth)`` with ``return_depth=True``), rendering ``chunk`` views at a time: memory stays
    bounded by one chunk however many views there are. ``cameras`` may be any iterable
    (e.g. a generator); errors name the view's index in the whole sequence."""
    if chunk < 1:
        raise ValueError(f"chunk must be >= 1, got {chunk}")
    many_scenes = not isinstance(scene, Scene)
    if isinstance(cameras, Camera):
        cameras = [cameras] * (len(scene) if many_scenes else 1)  # type: ignore[arg-type]
    it = iter(cameras)
    start = 0
    while True:
        cams: list[Camera] = []
        for cam in it:
            cams.append(cam)
            if len(cams) == chunk:
                break
        if not cams:
            return
        scenes = scene[start : start + len(cams)] if many_scenes else scene  # type: ignore[index]
        out = _core.render_batch(
            scenes,
            cams,
            *args,
            options=options,
            index_base=start,
            **render_options,
        )
        if isinstance(out, tuple):
            yield from zip(out[0], out[1])
        else:
            yield from out
        start += len(cams)
