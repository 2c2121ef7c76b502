"""Analytic ground truth: spheres and planes shaded exactly, in float64.

A ray from the eye through each pixel centre (the project's camera conventions, from
``shadelab_ref.reference``'s :func:`pixel_rays`) is intersected with the true surface, and the
exact normal at the hit point goes through the same lighting equation as the float64
reference rasterizer (:func:`reference.lighting`, reused rather than rewritten). Every
tessellation and shading mode approximates this image; the difference is its error.

Only NumPy; every pixel is independent, so each step is one vectorised expression.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import reference as ref

__all__ = ["Truth", "plane_truth", "sphere_truth", "world_rays"]


@dataclass
class Truth:
    """An exact image: ``color`` (H, W, 3) linear float64 (unclamped, ``background`` where
    nothing is hit), ``mask`` (H, W) bool coverage, ``depth`` (H, W) eye depth (``inf``
    where nothing is hit)."""

    color: np.ndarray
    mask: np.ndarray
    depth: np.ndarray

    @property
    def u8(self) -> np.ndarray:
        """The uint8 image, rounded as the renderers store it."""
        return ref.to_uint8(self.color)


def world_rays(camera: ref.Camera, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """World-space rays through every pixel centre as ``(origin, direction)``, each
    ``(H, W, 3)``; directions are scaled so the ray parameter is the eye depth."""
    origin, direction = ref.pixel_rays(camera, width, height)
    rot = ref.look_at(camera.eye, camera.target, camera.up)[:3, :3]  # world -> eye
    # Eye -> world is the transpose of the rotation; eye-space points are R @ (p - eye).
    return origin @ rot + np.asarray(camera.eye, np.float64), direction @ rot


def _shade(camera, hit, t, p, n, material, lights, ambient, specular, background):
    h, w = hit.shape
    color = np.broadcast_to(np.asarray(background, np.float64), (h, w, 3)).copy()
    color[hit] = ref.lighting(
        p[hit], n[hit], np.asarray(camera.eye, np.float64), material, lights, ambient, specular
    )
    depth = np.where(hit, t, np.inf)
    return Truth(color=color, mask=hit, depth=depth)


def sphere_truth(
    *,
    camera: ref.Camera,
    width: int,
    height: int,
    material: ref.Material,
    lights,
    center=(0.0, 0.0, 0.0),
    radius: float = 1.0,
    ambient=(0.2, 0.2, 0.2),
    specular: str = "blinn",
    background=(0.0, 0.0, 0.0),
) -> Truth:
    """The exact image of a sphere: nearest ray/sphere hit with eye depth in [near, far],
    normal ``(p - center) / radius``."""
    o, d = world_rays(camera, width, height)
    c = np.asarray(center, np.float64)
    oc = o - c
    # |oc + t d|^2 = r^2: a t^2 + 2 b t + k = 0, solved in the cancellation-free form.
    a = np.einsum("...i,...i", d, d)
    b = np.einsum("...i,...i", oc, d)
    k = np.einsum("...i,...i", oc, oc) - radius * radius
    disc = b * b - a * k
    hit = disc >= 0
    root = np.sqrt(np.where(hit, disc, 0.0))
    q = -(b + np.copysign(root, b))
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = q / a, np.where(q != 0, k / q, 0.0)
    near_t, far_t = np.minimum(t0, t1), np.maximum(t0, t1)
    ok0 = hit & (near_t >= camera.near) & (near_t <= camera.far)
    ok1 = hit & ~ok0 & (far_t >= camera.near) & (far_t <= camera.far)
    t = np.where(ok0, near_t, far_t)
    hit = ok0 | ok1
    p = o + np.where(hit, t, 0.0)[..., None] * d
    # The outward normal also where the near plane cuts the sphere open and the far hit is
    # seen from inside: back faces are lit with the normal as given (one-sided lighting).
    n = (p - c) / radius
    return _shade(camera, hit, t, p, n, material, lights, ambient, specular, background)


def plane_truth(
    *,
    camera: ref.Camera,
    width: int,
    height: int,
    material: ref.Material,
    lights,
    point=(0.0, 0.0, 0.0),
    normal=(0.0, 1.0, 0.0),
    ambient=(0.2, 0.2, 0.2),
    specular: str = "blinn",
    background=(0.0, 0.0, 0.0),
) -> Truth:
    """The exact image of an infinite plane through ``point`` lit with its unit ``normal``
    on both sides (OpenGL's default one-sided lighting), visible for eye depth in
    [near, far]."""
    o, d = world_rays(camera, width, height)
    nrm = np.asarray(normal, np.float64)
    nrm = nrm / np.linalg.norm(nrm)
    denom = d @ nrm
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((np.asarray(point, np.float64) - o) @ nrm) / denom
    hit = (denom != 0) & (t >= camera.near) & (t <= camera.far)
    p = o + np.where(hit, t, 0.0)[..., None] * d
    n = np.broadcast_to(nrm, p.shape)
    return _shade(camera, hit, t, p, n, material, lights, ambient, specular, background)
