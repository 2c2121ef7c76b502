"""The bundled demo scene and a helper that frames any mesh."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ._core import Camera, DirectionalLight, Material, Mesh, PointLight, Scene, load_obj

_DATA = Path(__file__).parent / "data"


def data_path(name: str) -> Path:
    """Path of a bundled data file, e.g. ``data_path("spot/spot_triangulated.obj")``."""
    return _DATA / name


def frame_mesh(
    vertices: np.ndarray,
    fov_y: float = 35.0,
    direction: tuple[float, float, float] = (0.55, 0.35, 1.0),
) -> Camera:
    """A perspective camera that looks at the bounding sphere of ``vertices`` from
    ``direction`` and fits it in the frame."""
    v = np.asarray(vertices, dtype=np.float64)
    lo, hi = v.min(axis=0), v.max(axis=0)
    centre = (lo + hi) / 2
    radius = max(float(np.linalg.norm(hi - lo)) / 2, 1e-6)
    d = np.asarray(direction, dtype=np.float64)
    d = d / np.linalg.norm(d)
    dist = radius / math.sin(math.radians(fov_y) / 2) * 1.05
    eye = centre + d * dist
    return Camera.look_at(
        eye=tuple(eye),
        target=tuple(centre),
        up=(0.0, 1.0, 0.0),
        fov_y=fov_y,
        near=max(dist - 2 * radius, dist * 1e-3),
        far=dist + 2 * radius,
    )


def _translate_rotate_y(x: float, z: float, degrees: float) -> np.ndarray:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return np.array(
        [[c, 0, s, x], [0, 1, 0, 0], [-s, 0, c, z], [0, 0, 0, 1]],
        dtype=np.float64,
    )


def demo_scene() -> tuple[Scene, Camera]:
    """Three Spot cows (Keenan Crane, public domain) in gold, polished silver and copper on a
    pewter cube, under a directional key light and a bluish point fill light."""
    cow: Mesh = load_obj(data_path("spot/spot_triangulated.obj"))
    cube: Mesh = load_obj(data_path("cube/cube.obj"))
    scene = Scene(ambient=(0.25, 0.25, 0.25))
    for x, name, angle in (
        (-1.15, "gold", 215.0),
        (0.0, "polished silver", 180.0),
        (1.15, "copper", 145.0),
    ):
        scene.add(cow, material=Material.preset(name), transform=_translate_rotate_y(x, 0, angle))
    base = np.diag([2.0, 0.08, 0.9, 1.0])
    base[1, 3] = -0.83
    scene.add(cube, material=Material.preset("pewter"), transform=base)
    scene.add_light(DirectionalLight(direction=(-0.5, -1.0, -0.8), color=(1.0, 0.97, 0.9)))
    scene.add_light(PointLight(position=(-3.0, 2.0, 4.0), color=(0.35, 0.4, 0.55)))
    camera = Camera.look_at(
        eye=(0.0, 1.1, 4.4), target=(0.0, -0.1, 0.0), up=(0, 1, 0), fov_y=42.0, near=0.1, far=50.0
    )
    return scene, camera
