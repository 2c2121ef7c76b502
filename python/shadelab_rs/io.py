"""File helpers: meshes through the Rust OBJ loader or trimesh (welded, with crease-angle
normals), images and depth maps through Pillow, NumPy or a small PNG writer."""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal, get_args

import numpy as np

from . import _core
from ._core import Environment, Material, Mesh, Texture, load_obj

#: Default crease angle of the mesh loaders, degrees: an edge between faces whose normals
#: differ by more stays sharp (a box's 90-degree edges), smaller ones are smoothed (the
#: facets of a tessellated sphere or Spot). Blender's auto-smooth default is 30; the larger
#: value keeps coarse curved models (an 8-sided cylinder has 45-degree facets) smooth.
CREASE_ANGLE = 60.0

#: Up axis by file format: STL and 3MF are Z-up by convention (3D printing, CAD), glTF is
#: Y-up by its specification; everything else is taken as Y-up, this library's convention.
_Z_UP_SUFFIXES = (".stl", ".3mf")


def file_up_axis(path: str | os.PathLike[str]) -> tuple[float, float, float]:
    """The up axis a mesh file's format implies: ``(0, 0, 1)`` for STL and 3MF (Z-up by
    convention), ``(0, 1, 0)`` for every other format (glTF/GLB are Y-up by specification;
    OBJ, PLY and OFF declare nothing and are taken as Y-up). The CLI frames files with it."""
    return (0.0, 0.0, 1.0) if Path(path).suffix.lower() in _Z_UP_SUFFIXES else (0.0, 1.0, 0.0)


def _unit_rows(a: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(a, axis=1, keepdims=True)
    return np.divide(a, n, out=np.zeros_like(a), where=n > 0)


def smooth_normals(
    vertices: Any,
    faces: Any,
    crease_angle: float | None = CREASE_ANGLE,
    uvs: Any = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
    """Vertex normals that ignore how a file split its vertices, and keep creases sharp.

    Vertices at the same position are welded for the computation (so an STL, which stores
    three vertices per triangle, or a mesh split at UV seams, shades smooth across them);
    each triangle corner gets the normalised sum of the unit normals of the faces around its
    position whose normal is within ``crease_angle`` degrees of its own face's (None: all of
    them, no creases). Vertices are then split only where a corner's normal differs (sharp
    edges), welded where a file duplicated them without need (when ``uvs`` is None), and
    keep their UVs. Returns ``(vertices, faces, normals, uvs)``."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    uv = None if uvs is None else np.asarray(uvs, dtype=np.float64).reshape(-1, 2)
    if len(f) == 0 or len(v) == 0 or f.min() < 0 or f.max() >= len(v):
        # Let the Mesh constructor report bad input with its own message.
        return v, f, np.zeros_like(v), uv
    _, weld = np.unique(v, axis=0, return_inverse=True)
    weld = weld.reshape(-1)
    fn = _unit_rows(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]))
    corner_v = weld[f].reshape(-1)  # welded vertex of each corner
    corner_f = np.repeat(np.arange(len(f)), 3)
    if crease_angle is None:
        acc = np.zeros((weld.max() + 1, 3))
        np.add.at(acc, corner_v, fn[corner_f])
        normals = acc[corner_v]
    else:
        cos_t = np.cos(np.radians(float(crease_angle)))
        order = np.argsort(corner_v, kind="stable")
        counts = np.bincount(corner_v)
        starts = np.concatenate(([0], np.cumsum(counts)[:-1]))
        deg = counts[corner_v]
        # Corners sorted by their vertex's degree, largest first, so that the corners with
        # a d-th neighbour are a prefix: the work is the sum of squared degrees.
        by_deg = np.argsort(-deg, kind="stable")
        normals = np.zeros((len(corner_v), 3))
        own = fn[corner_f[by_deg]]
        base = starts[corner_v[by_deg]]
        deg_sorted = deg[by_deg]
        for d in range(int(deg.max())):
            k = int(np.searchsorted(-deg_sorted, -d, side="left"))  # corners with deg > d
            if k == 0:
                break
            other = fn[corner_f[order[base[:k] + d]]]
            keep = np.einsum("ij,ij->i", own[:k], other) >= cos_t
            normals[by_deg[:k][keep]] += other[keep]
    normals = _unit_rows(normals)
    # A corner of a degenerate face has no normal of its own: take its vertex's average.
    bad = ~normals.any(axis=1)
    if bad.any():
        acc = np.zeros((weld.max() + 1, 3))
        np.add.at(acc, corner_v, fn[corner_f])
        normals[bad] = _unit_rows(acc[corner_v[bad]])
    # One output vertex per distinct (position, UV, normal); the key rounds the normal to
    # 1e-6 so that corners of one smooth vertex agree exactly.
    # With UVs the file's vertices are kept (a UV seam is a real split) and only split
    # further at creases; without, duplicates are welded.
    src = f.reshape(-1)
    ident = weld[src] if uv is None else src
    key = np.concatenate([ident[:, None].astype(np.float64), np.round(normals, 6)], axis=1)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    # Number the output vertices in the order of the file's vertices (so a mesh that needs
    # no split or weld keeps its vertex order).
    lowest = np.full(len(first), np.iinfo(np.int64).max)
    np.minimum.at(lowest, inverse, src)
    rank = np.lexsort((np.arange(len(first)), lowest))
    first = first[rank]
    inverse = np.argsort(rank)[inverse]
    out_v = v[src[first]]
    out_n = normals[first]
    out_uv = None if uv is None else uv[src[first]]
    return out_v, inverse.reshape(-1, 3), out_n, out_uv


def _trimesh_uvs(tm: Any) -> np.ndarray | None:
    uv = getattr(getattr(tm, "visual", None), "uv", None)
    return None if uv is None else np.asarray(uv)


def _trimesh_colors(tm: Any) -> np.ndarray | None:
    """Per-vertex colours of a trimesh (``ColorVisuals`` of kind ``"vertex"``), or None."""
    visual = getattr(tm, "visual", None)
    if visual is None or getattr(visual, "kind", None) != "vertex":
        return None
    c = np.asarray(visual.vertex_colors)
    return c if len(c) == len(tm.vertices) else None


def mesh_from_trimesh(
    tm: Any, use_normals: bool = False, crease_angle: float | None = CREASE_ANGLE
) -> Mesh:
    """A :class:`Mesh` from a ``trimesh.Trimesh`` (see :meth:`Mesh.from_trimesh`)."""
    if not (hasattr(tm, "vertices") and hasattr(tm, "faces")):
        raise TypeError(
            "from_trimesh expects a trimesh.Trimesh (with .vertices and .faces), got "
            f"{type(tm).__name__}"
        )
    uvs = _trimesh_uvs(tm)
    colors = _trimesh_colors(tm)
    if use_normals:
        return Mesh(tm.vertices, tm.faces, np.asarray(tm.vertex_normals), uvs, colors)
    if uvs is not None and len(uvs) != len(tm.vertices):
        uvs = None  # a per-face or broken UV array is not a vertex attribute
    if colors is None:
        v, f, n, uv = smooth_normals(tm.vertices, tm.faces, crease_angle, uvs)
        return Mesh(v, f, n, uv)
    # Vertex colours ride through the split as the source vertex index in the UV slot
    # (which also keeps the file's vertices, as real UVs do), exact below 2^53.
    index = np.stack([np.arange(len(tm.vertices), dtype=np.float64)] * 2, axis=1)
    v, f, n, src = smooth_normals(tm.vertices, tm.faces, crease_angle, index)
    assert src is not None
    k = src[:, 0].astype(np.int64)
    return Mesh(v, f, n, None if uvs is None else np.asarray(uvs)[k], colors[k])


def _texture_of(visual: Any) -> Texture | None:
    """The image of a trimesh ``TextureVisuals``' material (``SimpleMaterial.image`` or
    ``PBRMaterial.baseColorTexture``) as a Texture, when the mesh has UVs."""
    if getattr(visual, "kind", None) != "texture" or getattr(visual, "uv", None) is None:
        return None
    mat = getattr(visual, "material", None)
    img = getattr(mat, "image", None)
    if img is None:
        img = getattr(mat, "baseColorTexture", None)
    if img is None:
        return None
    return Texture(np.asarray(img.convert("RGB")))


def _material_of(tm: Any) -> Material | None:
    """The diffuse colour of a trimesh's material or face colours, as a Material, with its
    texture image as the diffuse map."""
    visual = getattr(tm, "visual", None)
    tex = _texture_of(visual)
    if tex is not None:
        return Material(ambient=(1.0, 1.0, 1.0), diffuse=(1.0, 1.0, 1.0), diffuse_map=tex)
    mat = getattr(visual, "material", None)
    rgba = None
    for attr in ("baseColorFactor", "main_color", "diffuse"):
        c = getattr(mat, attr, None)
        if c is not None:
            rgba = np.asarray(c, dtype=np.float64).reshape(-1)[:3]
            break
    if rgba is None and visual is not None and getattr(visual, "kind", None) == "face":
        fc = np.asarray(visual.face_colors, dtype=np.float64)
        if len(fc) and np.all(fc == fc[0]):
            rgba = fc[0, :3]
    if rgba is None:
        return None
    if rgba.max() > 1.0:
        rgba = rgba / 255.0
    d = tuple(float(x) for x in rgba)
    return Material(
        ambient=tuple(0.2 * x for x in d), diffuse=d, specular=(0.3, 0.3, 0.3), shininess=32.0
    )


def mesh_parts(obj: Any) -> list[tuple[Mesh, np.ndarray | None, Material | None]]:
    """The ``(mesh, transform, material)`` parts of whatever a user passes as a mesh: a
    :class:`Mesh`, a ``trimesh.Trimesh``, a ``trimesh.Scene`` (every geometry instance
    with its world transform and colour), a ``(vertices, faces)`` pair or a PyVista
    ``PolyData`` (triangulated). Used by :meth:`Scene.add` and :func:`render`."""
    if isinstance(obj, Mesh):
        return [(obj, None, None)]
    kind = type(obj).__module__.split(".")[0], type(obj).__name__
    if kind == ("trimesh", "Scene"):
        parts: list[tuple[Mesh, np.ndarray | None, Material | None]] = []
        for node in obj.graph.nodes_geometry:
            transform, name = obj.graph[node]
            geom = obj.geometry[name]
            if not hasattr(geom, "faces") or len(geom.faces) == 0:
                continue  # points and paths have nothing to rasterize
            parts.append((mesh_from_trimesh(geom), np.asarray(transform), _material_of(geom)))
        if not parts:
            raise ValueError("the trimesh.Scene holds no triangle meshes")
        return parts
    if kind[0] == "trimesh" and hasattr(obj, "faces"):
        return [(mesh_from_trimesh(obj), None, _material_of(obj))]
    if kind[0] == "pyvista" and hasattr(obj, "triangulate"):
        tri = obj.triangulate()
        cells = np.asarray(tri.faces).reshape(-1, 4)[:, 1:]
        v, f, n, _ = smooth_normals(np.asarray(tri.points), cells)
        return [(Mesh(v, f, n), None, None)]
    if isinstance(obj, (tuple, list)) and len(obj) == 2:
        return [(Mesh(obj[0], obj[1]), None, None)]
    raise TypeError(
        "expected a Mesh, trimesh.Trimesh, trimesh.Scene, (vertices, faces) pair or "
        f"pyvista PolyData, got {type(obj).__name__}"
    )


def as_mesh(obj: Any) -> Mesh:
    """One :class:`Mesh` from anything :func:`mesh_parts` accepts (a multi-part
    ``trimesh.Scene`` is flattened with its transforms)."""
    parts = mesh_parts(obj)
    if len(parts) == 1 and parts[0][1] is None:
        return parts[0][0]
    vs, fs, ns, off = [], [], [], 0
    for mesh, t, _ in parts:
        m = np.eye(4) if t is None else t
        v = mesh.vertices.astype(np.float64) @ m[:3, :3].T + m[:3, 3]
        n = mesh.normals.astype(np.float64) @ np.linalg.inv(m[:3, :3])
        vs.append(v)
        ns.append(n)
        fs.append(mesh.faces.astype(np.int64) + off)
        off += len(v)
    return Mesh(np.concatenate(vs), np.concatenate(fs), np.concatenate(ns))


def load_mesh(path: str | os.PathLike[str], crease_angle: float | None = CREASE_ANGLE) -> Mesh:
    """Loads a mesh file: OBJ through the Rust loader, any other format trimesh reads (STL,
    PLY, GLB, OFF, ...) through trimesh, with scenes flattened into one mesh.

    Files read through trimesh are welded and get crease-angle normals (see
    :func:`smooth_normals`): an STL sphere shades smooth, a box keeps its sharp edges.
    ``crease_angle=None`` smooths every edge. The coordinates are the file's own; see
    :func:`file_up_axis` for the up axis its format implies."""
    p = Path(path)
    if p.is_dir():
        raise IsADirectoryError(f"'{p}' is a directory, not a mesh file")
    if p.suffix.lower() == ".obj":
        return load_obj(p)
    if not p.exists():
        raise FileNotFoundError(f"no such file: '{p}'")
    import trimesh

    try:
        tm = trimesh.load(p, force="mesh", process=False)
    except Exception as e:  # trimesh raises many types for bad files
        raise ValueError(f"{p}: cannot read mesh: {e}") from e
    if not hasattr(tm, "faces") or len(tm.faces) == 0:
        raise ValueError(f"{p}: the file contains no triangles")
    return mesh_from_trimesh(tm, crease_angle=crease_angle)


def to_uint8(image: np.ndarray) -> np.ndarray:
    """A float image as uint8: round(clamp(c, 0, 1) * 255); uint8 input is returned as is."""
    a = np.asarray(image)
    if a.dtype == np.uint8:
        return a
    if a.dtype.kind != "f":
        raise TypeError(f"image must be uint8 or floating point, got dtype {a.dtype}")
    return np.floor(np.clip(np.nan_to_num(a, nan=0.0), 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)


#: PNG compression settings of :func:`save_image`, fastest first. "fast" (the default)
#: writes a 1080p render in a few milliseconds, smaller than zlib level 6 over unfiltered
#: rows; "high" is for files that are kept (see docs/BENCHMARKS.md, "Cold start").
PngCompression = Literal["none", "fastest", "fast", "balanced", "high"]
PNG_COMPRESSIONS: tuple[str, ...] = get_args(PngCompression)


def _png_bytes(
    a: np.ndarray, text: dict[str, str] | None = None, compression: PngCompression = "fast"
) -> bytes:
    """A PNG of an (H, W) or (H, W, C) uint8/uint16 array, C in 1..4 (grey, grey+alpha, RGB,
    RGBA), with ``text`` as tEXt chunks; encoded in Rust (the ``png`` crate, adaptive
    filters) with the GIL released."""
    return _core.encode_png(np.ascontiguousarray(a), compression, list((text or {}).items()))


def _channels(a: np.ndarray) -> np.ndarray:
    if a.ndim == 3 and a.shape[2] == 1:
        a = a[:, :, 0]
    if not (a.ndim == 2 or (a.ndim == 3 and a.shape[2] in (2, 3, 4))):
        raise ValueError(
            f"image must have shape (H, W) (grey), (H, W, 3) (RGB) or (H, W, 4) (RGBA), "
            f"got {a.shape}"
        )
    if a.shape[0] == 0 or a.shape[1] == 0:
        raise ValueError(f"image is empty: shape {a.shape}")
    return a


def _write(path: str | os.PathLike[str], data: bytes) -> None:
    """Writes bytes to a file, or to standard output for the path ``-``."""
    if os.fspath(path) == "-":
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
    else:
        Path(path).write_bytes(data)


def save_image(
    image: np.ndarray, path: str | os.PathLike[str], *, compression: PngCompression = "fast"
) -> None:
    """Writes an image; the format follows the extension (``-`` writes PNG to stdout).

    Shapes: (H, W) or (H, W, 1) grey, (H, W, 3) RGB, (H, W, 4) RGBA. Dtypes and formats:

    - ``.npy``: the array exactly as given.
    - ``.png``: uint8 as 8-bit, uint16 as 16-bit; float as 8-bit by :func:`to_uint8`
      (``round(clamp(c, 0, 1) * 255)``).
    - ``.tif``/``.tiff``: uint8 (any shape), float32 grey (32-bit float TIFF, values kept);
      float colour is refused (Pillow cannot write it: use ``.npy`` or ``.exr``).
    - ``.exr``: float32, through the optional ``OpenEXR`` package.
    - anything else Pillow writes (JPEG, BMP, ...): 8-bit, float through :func:`to_uint8`.

    Values are never silently cut to fewer bits than the format holds: uint16 into an 8-bit
    format and float colour into TIFF are errors that say what to use instead.

    ``compression`` (PNG only): "none", "fastest", "fast" (default), "balanced" or "high";
    every setting is lossless, the slower ones write smaller files."""
    if compression not in PNG_COMPRESSIONS:
        raise ValueError(
            f"compression must be one of {', '.join(PNG_COMPRESSIONS)}, got {compression!r}"
        )
    a = np.asarray(image)
    ext = "png" if os.fspath(path) == "-" else Path(path).suffix.lower().lstrip(".")
    if ext == "npy":
        np.save(os.fspath(path), a)
        return
    if a.dtype.kind not in "fu" or (a.dtype.kind == "u" and a.dtype not in (np.uint8, np.uint16)):
        raise TypeError(f"image must be uint8, uint16 or floating point, got dtype {a.dtype}")
    a = _channels(a)
    if ext == "exr":
        _save_exr(a.astype(np.float32), path)
        return
    if ext == "png":
        if a.dtype.kind == "f":
            a = to_uint8(a)
        _write(path, _png_bytes(a, compression=compression))
        return
    if a.dtype == np.uint16:
        raise ValueError(f"uint16 images can be written as .png or .npy, not .{ext}")
    if ext in ("jpg", "jpeg") and a.ndim == 3 and a.shape[2] in (2, 4):
        raise ValueError("JPEG has no alpha channel: write .png (or .tif, .npy) for RGBA")
    from PIL import Image

    if ext in ("tif", "tiff") and a.dtype.kind == "f":
        if a.ndim != 2:
            raise ValueError(
                "float colour images cannot be written as TIFF (Pillow writes float TIFF for "
                "one channel only): use .npy or .exr, or convert with to_uint8"
            )
        Image.fromarray(np.ascontiguousarray(a, dtype=np.float32), "F").save(os.fspath(path))
        return
    a = to_uint8(a)
    mode = {2: "L", 3: {2: "LA", 3: "RGB", 4: "RGBA"}}
    m = mode[2] if a.ndim == 2 else mode[3][a.shape[2]]  # type: ignore[index]
    Image.fromarray(np.ascontiguousarray(a), m).save(os.fspath(path))  # type: ignore[arg-type]


def _save_exr(a: np.ndarray, path: str | os.PathLike[str]) -> None:
    try:
        import OpenEXR  # type: ignore[import-not-found, unused-ignore]
    except ImportError:
        raise ImportError(
            "writing .exr needs the optional OpenEXR package (pip install OpenEXR); "
            ".npy or a float TIFF (grey) need nothing extra"
        ) from None
    names = {2: ["Y"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}
    if a.ndim == 2:
        a = a[:, :, None]
    chans = names[a.shape[2] if a.shape[2] > 1 else 2] if a.shape[2] != 2 else ["Y", "A"]
    channels = {n: np.ascontiguousarray(a[:, :, i]) for i, n in enumerate(chans)}
    with OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION}, channels) as f:
        f.write(os.fspath(path))


#: Default scale of 16-bit PNG depth maps: units per world unit (1000: millimetres when the
#: scene is in metres, the Kinect / RealSense convention).
DEPTH_PNG_SCALE = 1000.0


def save_depth(
    depth: np.ndarray, path: str | os.PathLike[str], scale: float = DEPTH_PNG_SCALE
) -> None:
    """Writes a depth map from ``render(..., return_depth=True)`` (float, +inf where nothing
    was drawn).

    - ``.png``: 16-bit grey, ``round(depth * scale)``, 0 where nothing was drawn; the scale
      is stated in the file (tEXt chunk ``depth_scale``). A depth that does not fit in
      1..65535 at this scale is an error naming the scale that would fit (never clipped).
    - ``.tif``/``.tiff``: 32-bit float, the values as they are (inf kept).
    - ``.npy``: the float32 array exactly; ``.exr``: float, through the optional OpenEXR."""
    d = np.asarray(depth)
    if d.ndim != 2 or d.dtype.kind != "f":
        raise ValueError(f"depth must be a float (H, W) array, got {d.dtype} {d.shape}")
    ext = "png" if os.fspath(path) == "-" else Path(path).suffix.lower().lstrip(".")
    if ext != "png":
        save_image(d.astype(np.float32), path)
        return
    if not (np.isfinite(scale) and scale > 0):
        raise ValueError(f"scale must be finite and > 0, got {scale}")
    drawn = np.isfinite(d)
    q = np.zeros(d.shape, np.uint16)
    if drawn.any():
        top = float(d[drawn].max())
        if top * scale > 65535.0:
            raise ValueError(
                f"depth up to {top:g} does not fit a 16-bit PNG at scale {scale:g} "
                f"(max 65535): use scale <= {65535.0 / top:.6g}, or .tif/.npy for float depth"
            )
        q[drawn] = np.maximum(np.round(d[drawn] * scale), 1).astype(np.uint16)
    _write(path, _png_bytes(q, {"depth_scale": repr(float(scale))}))


def _environment_image(p: Path) -> tuple[np.ndarray, bool]:
    """An environment image file's array and whether it is sRGB-encoded (8-bit)."""
    if not p.is_file():
        raise FileNotFoundError(f"environment image not found: {p}")
    if p.suffix.lower() == ".npy":
        array = np.load(p, allow_pickle=False)
        return array, array.dtype == np.uint8
    from PIL import Image

    with Image.open(p) as im:
        return np.asarray(im.convert("RGB")), True


def load_environment(
    path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]] | Mapping[str, Any],
    rotation: float = 0.0,
    intensity: float = 1.0,
) -> Environment:
    """An :class:`Environment` read from image files: ``.npy`` (float values linear and
    HDR allowed) or 8-bit images Pillow reads (PNG, JPEG: sRGB-decoded). ``path``: one
    equirectangular (H, 2H, 3) image, or six square cube faces of one size as a sequence
    in the order +X, -X, +Y, -Y, +Z, -Z or a dict with the keys "+x", "-x", "+y", "-y",
    "+z", "-z" (see :meth:`Environment.from_cube` for the orientation). The paths are
    recorded for scene files."""
    if isinstance(path, (str, os.PathLike)):
        p = Path(path)
        array, srgb = _environment_image(p)
        return Environment(array, rotation, intensity, srgb, path=p)
    names = ("+x", "-x", "+y", "-y", "+z", "-z")
    if isinstance(path, Mapping):
        if sorted(path) != sorted(names):
            raise ValueError(
                f"cube faces need exactly the keys {', '.join(names)}, got {sorted(path)}"
            )
        files = [Path(path[k]) for k in names]
    else:
        files = [Path(f) for f in path]
    if len(files) != 6:
        raise ValueError(
            f"a cube environment needs 6 face files (+x, -x, +y, -y, +z, -z), got {len(files)}"
        )
    images = [_environment_image(f) for f in files]
    encodings = {srgb for _, srgb in images}
    if len(encodings) > 1:
        raise ValueError("cube faces must all be 8-bit images or all float .npy arrays")
    return Environment.from_cube(
        [a for a, _ in images], rotation, intensity, encodings.pop(), paths=files
    )
