"""``render`` and ``render_frame``: the compiled renderer plus what a first call needs.

The compiled functions in ``_core`` draw a :class:`Scene` through a :class:`Camera`. These
wrappers also take a bare mesh (a :class:`Mesh`, trimesh, ``(V, F)`` pair, ...) and no
camera, add a transparent background (``alpha=True``) and display encoding
(``encoding="srgb"``), and warn when a render draws nothing because of the camera.
Near/far planes the camera leaves open and the default light rig are applied by the
compiled renderer itself (see :meth:`Camera.look_at` and :attr:`Scene.default_lights`).
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any, Literal, TypedDict, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._core import Camera, RenderOptions, Scene

if TYPE_CHECKING:
    from typing_extensions import Unpack

    from ._core import _RenderOptionsArgs

Encoding = Literal["linear", "srgb"]
_U8 = Literal["uint8"] | type[np.uint8] | np.dtype[np.uint8]
_F32 = Literal["float32"] | type[np.float32] | np.dtype[np.float32]


class EmptyRenderWarning(UserWarning):
    """A render drew no triangle although the scene has some that back-face culling kept:
    every one is behind the camera, beyond its near/far planes or outside the frame."""


class Frame(TypedDict):
    """What :func:`render_frame` returns."""

    image: NDArray[Any]
    depth: NDArray[np.float32] | None
    stats: dict[str, Any]


def _scene_of(scene: Any) -> Scene:
    if isinstance(scene, Scene):
        return scene
    s = Scene()
    try:
        s.add(scene)
    except TypeError as e:
        raise TypeError(f"scene must be a Scene or a mesh: {e}") from None
    return s


def srgb_encode(linear: ArrayLike) -> NDArray[np.float32]:
    """The sRGB transfer function (IEC 61966-2-1) of linear values, clamped to [0, 1]
    first: ``12.92 c`` below 0.0031308, ``1.055 c**(1/2.4) - 0.055`` above."""
    c = np.clip(np.nan_to_num(np.asarray(linear, dtype=np.float32), nan=0.0), 0.0, 1.0)
    return np.where(  # type: ignore[no-any-return]
        c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055
    ).astype(np.float32)


def _dtype_name(dtype: Any) -> str:
    if dtype is None:
        return "uint8"
    try:
        name = np.dtype(dtype).name
    except TypeError:
        raise TypeError(f"dtype must be 'uint8' or 'float32', got {dtype}") from None
    if name not in ("uint8", "float32"):
        raise ValueError(f"dtype must be 'uint8' or 'float32', got '{name}'")
    return name


def render_frame(
    scene: Any,
    camera: Camera | None = None,
    *args: Any,
    dtype: Any = None,
    return_depth: bool = False,
    options: RenderOptions | None = None,
    alpha: bool = False,
    encoding: Encoding = "linear",
    **kwargs: Unpack[_RenderOptionsArgs],
) -> Frame:
    """Like :func:`render`, returning a dict with "image", "depth" (or None) and "stats".

    Every argument is that of :func:`render`. "stats" holds the triangle counters
    (``triangles_in``, ``triangles_setup`` (handed to the rasterizer after clipping),
    ``triangles_clipped``, ``triangles_culled``, ``triangles_dropped``), ``light_sources``
    (point sources lit per shaded point, the default rig's three included) and per-stage
    wall times in milliseconds (``vertex_ms``, ``setup_ms``, ``raster_shade_ms``). With
    ``shading="auto"`` also ``shading`` (the mode used per object, in scene order) and
    ``shading_estimates`` (per object, as :func:`explain` returns them).
    """
    return _frame(
        scene,
        camera,
        args,
        kwargs,
        dtype=dtype,
        return_depth=return_depth,
        options=options,
        alpha=alpha,
        encoding=encoding,
        stacklevel=3,
    )


def explain(
    scene: Any,
    camera: Camera | None = None,
    *args: Any,
    tolerance: float | None = None,
    options: RenderOptions | None = None,
    **kwargs: Any,
) -> dict[str, Any]:
    """What ``shading="auto"`` would choose, without rendering.

    Returns ``{"shading": [mode per object, in scene order], "shading_estimates": [...],
    "tolerance": t}``, the same as ``render_frame(..., shading="auto")["stats"]``: each
    estimate is a dict with the ``mode`` used, the estimated RMSE in 8-bit levels of
    ``flat``, ``gouraud`` and ``phong``, ``meets`` (whether the mode's estimate is within
    the tolerance) and ``pixels`` (the object's estimated projected pixels). ``tolerance``
    defaults to the options' (``shading="auto", tolerance=...``) or
    :data:`DEFAULT_TOLERANCE`; the other arguments are :func:`render`'s (the image size
    and camera decide how large the triangles are on screen).
    """
    s = _scene_of(scene)
    if camera is None:
        from .scene_file import frame_scene

        camera = frame_scene(s)
    return _core.explain(s, camera, *args, tolerance=tolerance, options=options, **kwargs)


def _frame(
    scene: Any,
    camera: Camera | None,
    args: tuple[Any, ...],
    kwargs: _RenderOptionsArgs,
    *,
    dtype: Any,
    return_depth: bool,
    options: RenderOptions | None,
    alpha: bool,
    encoding: Encoding,
    stacklevel: int,
) -> Frame:
    """render_frame; ``stacklevel`` points the empty-render warning at the caller. The
    render options (``args``, ``options``, ``kwargs``) go to the binding untouched: it
    checks and merges them (:class:`RenderOptions`)."""
    s = _scene_of(scene)
    if camera is None:
        from .scene_file import frame_scene

        camera = frame_scene(s)
    if encoding not in ("linear", "srgb"):
        raise ValueError(f"encoding must be 'linear' or 'srgb', got {encoding!r}")
    out_dtype = _dtype_name(dtype)
    core_dtype = "float32" if encoding == "srgb" else dtype
    frame = _core.render_frame(
        s,
        camera,
        *args,
        dtype=core_dtype,
        return_depth=return_depth,
        options=options,
        alpha=alpha,
        **kwargs,
    )
    stats = frame["stats"]
    # No triangle reached the rasterizer though some survived culling: every one was
    # behind the eye, beyond the near/far planes, outside the frame, or so small that it
    # covers no pixel centre (set-up skips those too).
    if stats["triangles_setup"] == 0 and stats["triangles_culled"] < stats["triangles_in"]:
        cam = camera.fitted(s)
        lo, hi = s.bounds() or ((0.0,) * 3, (0.0,) * 3)
        warnings.warn(
            f"render drew no triangle: all {s.n_triangles} triangles of the scene are "
            f"outside the camera's view (behind the eye, beyond the near/far planes or "
            f"outside the frame; eye {_fmt(cam.eye)}, looking at {_fmt(cam.target)}, "
            f"near {cam.near:g}, far {cam.far:g}; the scene spans {_fmt(lo)} to {_fmt(hi)}), "
            f"or too small to cover any pixel centre at this image size",
            EmptyRenderWarning,
            stacklevel=stacklevel,
        )
    image = _finish(frame["image"], frame["alpha"], out_dtype=out_dtype, encoding=encoding)
    return {"image": image, "depth": frame["depth"], "stats": stats}


def _finish(
    image: NDArray[Any],
    alpha: NDArray[np.float32] | None,
    *,
    out_dtype: str,
    encoding: Encoding,
) -> NDArray[Any]:
    """The renderer's image (float32 when ``encoding="srgb"``) encoded and, given the
    coverage ``alpha`` of a render over a transparent background, with its alpha channel
    (premultiplied), as ``render`` returns it; the command line's many-view renders use it
    too."""
    if encoding == "srgb":
        if alpha is not None:
            # Encode the colour, not the colour times coverage: un-premultiply, encode,
            # premultiply again (in float, before any rounding).
            a = alpha[..., None]
            straight = np.divide(image, a, out=np.zeros_like(image), where=a > 0)
            enc = srgb_encode(straight) * a
        else:
            enc = srgb_encode(image)
        image = np.floor(enc * 255.0 + 0.5).astype(np.uint8) if out_dtype == "uint8" else enc
    if alpha is not None:
        if image.dtype == np.uint8:
            a8 = np.floor(alpha * 255.0 + 0.5).astype(np.uint8)
            image = np.concatenate([image, a8[:, :, None]], axis=2)
        else:
            image = np.concatenate([image, alpha[:, :, None].astype(image.dtype)], axis=2)
        image = np.ascontiguousarray(image)
    return image


def _fmt(v: Any) -> str:
    return "(" + ", ".join(f"{float(x):.4g}" for x in v) + ")"


@overload
def render(
    scene: Any,
    camera: Camera | None = None,
    *args: Any,
    dtype: _U8 | None = None,
    return_depth: Literal[False] = False,
    options: RenderOptions | None = None,
    alpha: bool = False,
    encoding: Encoding = "linear",
    **kwargs: Unpack[_RenderOptionsArgs],
) -> NDArray[np.uint8]: ...


@overload
def render(
    scene: Any,
    camera: Camera | None = None,
    *args: Any,
    dtype: _F32,
    return_depth: Literal[False] = False,
    options: RenderOptions | None = None,
    alpha: bool = False,
    encoding: Encoding = "linear",
    **kwargs: Unpack[_RenderOptionsArgs],
) -> NDArray[np.float32]: ...


@overload
def render(
    scene: Any,
    camera: Camera | None = None,
    *args: Any,
    dtype: _U8 | None = None,
    return_depth: Literal[True],
    options: RenderOptions | None = None,
    alpha: bool = False,
    encoding: Encoding = "linear",
    **kwargs: Unpack[_RenderOptionsArgs],
) -> tuple[NDArray[np.uint8], NDArray[np.float32]]: ...


@overload
def render(
    scene: Any,
    camera: Camera | None = None,
    *args: Any,
    dtype: _F32,
    return_depth: Literal[True],
    options: RenderOptions | None = None,
    alpha: bool = False,
    encoding: Encoding = "linear",
    **kwargs: Unpack[_RenderOptionsArgs],
) -> tuple[NDArray[np.float32], NDArray[np.float32]]: ...


@overload
def render(
    scene: Any,
    camera: Camera | None = None,
    *args: Any,
    dtype: Any = None,
    return_depth: bool = False,
    options: RenderOptions | None = None,
    alpha: bool = False,
    encoding: Encoding = "linear",
    **kwargs: Unpack[_RenderOptionsArgs],
) -> Any: ...


def render(
    scene: Any,
    camera: Camera | None = None,
    *args: Any,
    dtype: Any = None,
    return_depth: bool = False,
    options: RenderOptions | None = None,
    alpha: bool = False,
    encoding: Encoding = "linear",
    **kwargs: Unpack[_RenderOptionsArgs],
) -> Any:
    """Renders ``scene`` through ``camera`` into a C-contiguous (height, width, 3) array
    ((height, width, 4) with ``alpha=True``), or a tuple (image, depth) with
    ``return_depth=True``. The GIL is released while rendering.

    Parameters:

    - ``scene``: a :class:`Scene`, or anything :meth:`Scene.add` takes (a :class:`Mesh`,
      ``trimesh.Trimesh`` / ``trimesh.Scene``, ``(vertices, faces)``, PyVista PolyData),
      drawn in the default material.
    - ``camera``: a :class:`Camera`; None frames the scene (:func:`frame_scene`). Near/far
      planes the camera leaves as None are fitted to the scene's bounds for its eye.
    - The render options, :class:`RenderOptions`' arguments: positionally after the
      camera (``render(s, c, 640, 480, shading="flat")``) or by keyword, or ``options``
      (a :class:`RenderOptions`, updated by any keyword given with it). ``width``,
      ``height``: pixels, 1 to ``MAX_IMAGE_SIZE`` (800 x 600). ``shading``: "flat",
      "gouraud", "phong" (default; case-insensitive) or "auto" (per object the cheapest
      mode whose estimated error is within ``tolerance``, RMSE in 8-bit levels, default
      1.0; see :func:`explain`). ``specular``: "blinn"
      (Blinn-Phong, default), "phong" or "blinn-normalized". ``background``: linear RGB of
      empty pixels, each in [0, 1] for 8-bit output (default black). ``cull_backfaces``:
      skip triangles facing away from the camera. ``cull_hidden``: skip the back faces
      that cannot show (default True; the image is the same): those of opaque objects
      whose mesh bounds solids, seen from outside (see the user guide, "Hidden back
      faces"). ``threads``: worker threads, None for
      all cores; the image is bit-identical for any. ``gouraud``: "normals" (default:
      vertex normals averaged, lit per vertex) or "face-intensities" (the lectures' simple
      method: each vertex takes the mean of its faces' flat-lit colours).
      ``interpolation``: "perspective" (default) or "screen" (the lectures' scan-line
      formulas, affine in screen space). ``samples``: 1 (default) or 2, 4, 8, 16:
      multi-sample anti-aliasing (standard D3D/Vulkan sample positions; each pixel shaded
      once per visible triangle, weighted by the share of samples it covers).
      ``supersample``: k in 1..8, render k x k pixels per output pixel and average them
      (exact, k^2 times the work). ``edges``: draw triangle edges as lines over the
      image: None (default), "all" (every edge, hidden ones too: a wireframe), "visible"
      (hidden-line removal: every edge no nearer surface hides, diagonals of flat quads
      included) or "features" (visible silhouettes, boundary edges and creases sharper
      than ``edge_angle`` degrees, default 30). ``edge_color``: linear RGB (default
      black); ``edge_width``: pixels (default 1; a sample within width/2 of an edge is
      covered, so lines are anti-aliased with ``samples`` > 1); ``edges_only``: the lines
      alone over the ``background`` (surfaces still hide what is behind them; with
      ``alpha``, over transparency).
      ``background="environment"`` shows the scene's
      environment along each pixel's view ray. ``reflections``: "environment" (default,
      one lookup along the mirror direction) or "ray" (secondary rays through the scene);
      ``refractions``: None (default: transparent surfaces blend straight through, sorted
      per pixel), "environment" or "ray" (Snell's law, total internal reflection);
      ``max_depth``: secondary ray segments at most (5; then the environment). See the
      lighting guide, "Reflection, refraction and transparency".
    - ``dtype``: "uint8" (default, ``round(clamp(c, 0, 1) * 255)``) or "float32" (linear,
      unclamped unless ``encoding="srgb"``).
    - ``return_depth``: also return the float32 eye-space depth (distance along the viewing
      axis, world units), +inf where nothing was drawn. With ``samples`` > 1 it is the
      depth of the surface covering most of the pixel's samples (+inf where the
      background covers most); with ``supersample`` the nearest of the k x k.
    - ``alpha``: render over a transparent background and add an alpha channel: the share
      of each pixel's samples a triangle covers (0 or 1 with one sample, fractions at
      anti-aliased edges), 255 or 1.0 where fully covered. The colour is premultiplied
      (edge pixels hold colour x coverage; the ``background`` option is not drawn), so the
      image composites with ``out = rgb + (1 - alpha) * under``.
    - ``encoding``: "linear" (default): the shading's linear values, as OpenGL's classic
      pipeline writes them. "srgb": encoded for display with the sRGB transfer function
      (:func:`srgb_encode`), which brightens mid-tones the way viewers expect for an
      image file; use it for pictures to look at, linear for measurements.

    Lights: a scene without lights is lit by a rig that moves with the camera (see
    :attr:`Scene.default_lights`). A render that draws no triangle although the scene has
    some emits an :class:`EmptyRenderWarning` saying where the camera and the scene are.
    """
    f = _frame(
        scene,
        camera,
        args,
        kwargs,
        dtype=dtype,
        return_depth=return_depth,
        options=options,
        alpha=alpha,
        encoding=encoding,
        stacklevel=3,
    )
    if return_depth:
        return f["image"], f["depth"]
    return f["image"]
