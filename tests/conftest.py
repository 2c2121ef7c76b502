"""Shared fixtures of the pytest suite.

The float64 reference is the top-level package ``shadelab_ref`` (shared with bench/),
importable because pyproject.toml puts the repository root on pytest's ``pythonpath``.
"""

from __future__ import annotations

import numpy as np
import pytest
import shadelab_rs as sl

from shadelab_ref import reference as ref

#: A small UV sphere: 86 vertices (so every integer dtype can index it), 168 triangles.
SPHERE_LAT, SPHERE_LON = 8, 12


@pytest.fixture(scope="session")
def sphere_arrays() -> tuple[np.ndarray, np.ndarray]:
    """``(vertices float64 (86, 3), faces int64 (168, 3))`` of a unit UV sphere."""
    v, f = ref.uv_sphere(SPHERE_LAT, SPHERE_LON)
    v.setflags(write=False)
    f.setflags(write=False)
    return v, f


@pytest.fixture(scope="session")
def camera() -> sl.Camera:
    """A perspective camera looking at the origin from slightly above and to the right."""
    return sl.Camera.look_at(eye=(0.8, 0.6, 3.0), target=(0, 0, 0), up=(0, 1, 0), fov_y=45.0)


def _make_scene(mesh: sl.Mesh, material: str = "gold", transform=None) -> sl.Scene:
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2))
    scene.add(mesh, material=sl.Material.preset(material), transform=transform)
    scene.add_light(sl.DirectionalLight(direction=(-1.0, -1.0, -1.0)))
    scene.add_light(sl.PointLight(position=(2.0, 3.0, 4.0), color=(0.4, 0.4, 0.5)))
    return scene


@pytest.fixture(scope="session")
def make_scene():
    """``make_scene(mesh, material="gold", transform=None)``: ``mesh`` in a scene with a
    directional key light and a coloured point fill light."""
    return _make_scene


@pytest.fixture(scope="session")
def sphere_scene(sphere_arrays) -> sl.Scene:
    """The small sphere, gold, under two lights."""
    return _make_scene(sl.Mesh(*sphere_arrays))
