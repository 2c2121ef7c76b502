"""The exact visible-edge set of a mesh, in float64, for the hidden-line tests.

Independent of the renderer: edges come from the mesh (vertices welded by exact
position), points along each edge are ray-cast from the eye against every triangle
(:func:`shadelab_ref.shadows.occluded`, Moller-Trumbore in float64), and the result is a
pair of per-pixel distance maps: how far each pixel centre is from the nearest point of an
edge that is certainly visible, and from the nearest point that may be drawn (visible, or
within ``margin`` pixels along the edge of a change of visibility). A renderer drawing the
visible edges ``w`` pixels wide with one sample must then cover every pixel whose first
distance is below ``w/2`` and no pixel whose second distance is above it (each up to the
snapping slack the test states).

Perspective cameras only (:class:`shadelab_ref.reference.Camera` without ``ortho_height``
or ``intrinsics``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import reference as ref
from .shadows import occluded


@dataclass
class MeshEdges:
    """Undirected edges of a welded mesh."""

    #: (E, 2) vertex indices of each edge's ends.
    ends: np.ndarray
    #: (E, 2) the first two faces having each edge (-1 where absent).
    faces: np.ndarray
    #: (E,) number of faces having each edge.
    count: np.ndarray
    #: (E,) whether the two faces walk the edge in opposite directions.
    consistent: np.ndarray


def mesh_edges(vertices, faces) -> MeshEdges:
    """Every undirected edge once, vertices welded by exact position."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    _, weld = np.unique(v + 0.0, axis=0, return_inverse=True)
    weld = weld.reshape(-1)
    table: dict[tuple[int, int], list[tuple[int, bool, int, int]]] = {}
    for fi, tri in enumerate(f):
        w = weld[tri]
        if len(set(w.tolist())) < 3:
            continue
        for k in range(3):
            a, b = int(w[k]), int(w[(k + 1) % 3])
            key = (min(a, b), max(a, b))
            table.setdefault(key, []).append((fi, a < b, int(tri[k]), int(tri[(k + 1) % 3])))
    ends, fs, count, consistent = [], [], [], []
    for sides in table.values():
        ends.append((sides[0][2], sides[0][3]))
        fs.append((sides[0][0], sides[1][0] if len(sides) > 1 else -1))
        count.append(len(sides))
        consistent.append(len(sides) > 1 and sides[0][1] != sides[1][1])
    return MeshEdges(np.array(ends), np.array(fs), np.array(count), np.array(consistent))


def feature_mask(vertices, faces, edges: MeshEdges, eye, angle_deg: float) -> np.ndarray:
    """Which edges are feature lines: boundaries and non-manifold edges, silhouettes (one
    face towards ``eye``, the other away) and creases (face normals more than
    ``angle_deg`` apart)."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    facing = np.sign(np.sum(n * (np.asarray(eye, dtype=np.float64) - v[f[:, 0]]), axis=1))
    out = edges.count != 2
    two = edges.count == 2
    fa, fb = edges.faces[:, 0], np.where(two, edges.faces[:, 1], edges.faces[:, 0])
    out |= two & (facing[fa] != 0) & (facing[fb] != 0) & (facing[fa] != facing[fb])
    na, nb = n[fa], n[fb]
    cos = np.sum(na * nb, axis=1) / (np.linalg.norm(na, axis=1) * np.linalg.norm(nb, axis=1))
    cos = np.where(edges.consistent, cos, -cos)
    out |= two & (cos < math.cos(math.radians(angle_deg)))
    return out


def _screen(camera: ref.Camera, p, width: int, height: int) -> np.ndarray:
    return ref.project_to_screen(ref._world_to_eye(camera, p), camera, width, height)


def distance_maps(
    vertices,
    faces,
    camera: ref.Camera,
    width: int,
    height: int,
    *,
    select: np.ndarray | None = None,
    margin: float = 1.5,
    coarse: float = 0.5,
    fine: float = 0.05,
) -> tuple[np.ndarray, np.ndarray]:
    """``(d_visible, d_possible)``, each (height, width): the distance from each pixel
    centre to the nearest point of a selected edge that is visible, and to the nearest
    that is visible or within ``margin`` pixels (along the edge on screen) of where its
    visibility changes. Visibility is ray-cast every ``coarse`` pixels or less; distances
    are to points ``fine`` pixels apart or less (over-estimating by under
    ``fine**2 / 4``). ``select``: a mask over :func:`mesh_edges`' edges (all by default).
    Distances beyond two pixels are reported as +inf."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    edges = mesh_edges(v, f)
    keep = np.ones(len(edges.ends), bool) if select is None else np.asarray(select, bool)
    eye = np.asarray(camera.eye, dtype=np.float64)
    d_vis = np.full((height, width), np.inf)
    d_pos = np.full((height, width), np.inf)
    pts_vis, pts_pos = [], []
    for (i, j), k in zip(edges.ends, keep):
        if not k:
            continue
        a, b = v[i], v[j]
        sa, sb = _screen(camera, np.stack([a, b]), width, height)
        length = float(np.linalg.norm(sb - sa))
        nc = max(2, math.ceil(2.0 * length / coarse) + 1)
        tc = np.linspace(0.0, 1.0, nc)
        pc = a[None] + tc[:, None] * (b - a)[None]
        vis = ~occluded(np.broadcast_to(eye, pc.shape), pc - eye, 1.0 - 1e-6, v, f)
        sc = _screen(camera, pc, width, height)
        arc_c = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(sc, axis=0), axis=1))])
        nf = max(2, math.ceil(2.0 * length / fine) + 1)
        tf = np.linspace(0.0, 1.0, nf)
        sf = _screen(camera, a[None] + tf[:, None] * (b - a)[None], width, height)
        arc_f = np.interp(tf, tc, arc_c)
        nearest = np.clip(np.searchsorted(tc, tf), 0, nc - 1)
        left = np.clip(nearest - 1, 0, nc - 1)
        pick = np.where(np.abs(tc[left] - tf) < np.abs(tc[nearest] - tf), left, nearest)
        cls_vis = vis[pick].copy()
        uncertain = np.zeros(nf, bool)
        for c in np.nonzero(vis[1:] != vis[:-1])[0]:
            lo, hi = arc_c[c] - margin, arc_c[c + 1] + margin
            uncertain |= (arc_f >= lo) & (arc_f <= hi)
        cls_vis &= ~uncertain
        pts_vis.append(sf[cls_vis])
        pts_pos.append(sf[cls_vis | uncertain])
    for pts, out in ((pts_vis, d_vis), (pts_pos, d_pos)):
        if not pts:
            continue
        p = np.concatenate(pts)
        bx, by = np.floor(p[:, 0] - 0.5).astype(np.int64), np.floor(p[:, 1] - 0.5).astype(np.int64)
        for dy in range(-2, 4):
            for dx in range(-2, 4):
                x, y = bx + dx, by + dy
                ok = (x >= 0) & (x < width) & (y >= 0) & (y < height)
                d = np.hypot(p[ok, 0] - (x[ok] + 0.5), p[ok, 1] - (y[ok] + 0.5))
                np.minimum.at(out, (y[ok], x[ok]), d)
    return d_vis, d_pos


def torus(major: float = 1.0, minor: float = 0.4, n_major: int = 24, n_minor: int = 12):
    """A closed torus around the y axis: (vertices, faces), counter-clockwise outside."""
    u = np.arange(n_major) * 2.0 * math.pi / n_major
    w = np.arange(n_minor) * 2.0 * math.pi / n_minor
    uu, ww = np.meshgrid(u, w, indexing="ij")
    r = major + minor * np.cos(ww)
    vertices = np.stack([r * np.cos(uu), minor * np.sin(ww), -r * np.sin(uu)], axis=-1)
    faces = []
    for i in range(n_major):
        for j in range(n_minor):
            a = i * n_minor + j
            b = ((i + 1) % n_major) * n_minor + j
            c = ((i + 1) % n_major) * n_minor + (j + 1) % n_minor
            d = i * n_minor + (j + 1) % n_minor
            faces += [(a, b, c), (a, c, d)]
    return vertices.reshape(-1, 3), np.array(faces, dtype=np.int64)
