"""The bundled demo scene and camera helpers: framing any mesh or scene, named views for
any up axis, orbiting, and pinhole intrinsics."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ._core import Camera, DirectionalLight, Material, Mesh, PointLight, Scene, load_obj

_DATA = Path(__file__).parent / "data"


def data_path(name: str) -> Path:
    """Path of a bundled data file, e.g. ``data_path("spot/spot_triangulated.obj")``."""
    return _DATA / name


#: Named views of :func:`frame_mesh`, each a direction from the model to the camera in the
#: frame of the up axis (see :func:`view_direction`).
VIEWS = ("front", "back", "left", "right", "top", "bottom", "iso")

#: The default view: from the front, a little to the right and above (right, up, front).
DEFAULT_VIEW = (0.55, 0.35, 1.0)


def _unit(v: Any, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be three finite numbers, got {v!r}")
    n = float(np.linalg.norm(a))
    if n == 0.0:
        raise ValueError(f"{name} must be non-zero, got {tuple(a.tolist())}")
    return a / n


def view_frame(up: Any = (0.0, 1.0, 0.0)) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The (right, up, front) axes of named views for the up axis ``up``: front is +z for a
    Y-up world (OpenGL's convention) and -y for a Z-up one (Blender's, CAD's), right is
    ``up x front``."""
    u = _unit(up, "up")
    for c in ((0.0, 0.0, 1.0), (0.0, -1.0, 0.0), (1.0, 0.0, 0.0)):
        cand = np.asarray(c)
        if abs(float(cand @ u)) < 0.9:
            break
    front = cand - (cand @ u) * u
    front /= np.linalg.norm(front)
    return np.cross(u, front), u, front


def view_direction(view: Any, up: Any = (0.0, 1.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """The unit direction from the model to the camera for ``view`` and the camera up
    vector to use with it. ``view``: a name of :data:`VIEWS` or a direction (x, y, z) in
    world space. The top and bottom views (and any direction parallel to ``up``) look
    along the up axis, so their camera up is the model's back (top) or front (bottom):
    the front of the model is at the bottom of a top view, as in CAD."""
    right, u, front = view_frame(up)
    if isinstance(view, str):
        name = view.lower()
        table = {
            "front": front,
            "back": -front,
            "right": right,
            "left": -right,
            "top": u,
            "bottom": -u,
            "iso": right + u + front,
            "default": DEFAULT_VIEW[0] * right + DEFAULT_VIEW[1] * u + DEFAULT_VIEW[2] * front,
        }
        if name not in table:
            raise ValueError(f"unknown view '{view}'; use one of {', '.join(VIEWS)} or x,y,z")
        d = table[name] / np.linalg.norm(table[name])
    else:
        d = _unit(view, "view direction")
    along = float(d @ u)
    cam_up = u if abs(along) < 0.999 else (-front if along > 0 else front)
    return d, cam_up


def _points_of(obj: Any) -> np.ndarray:
    if isinstance(obj, Mesh):
        return obj.vertices
    if isinstance(obj, Scene):
        b = obj.bounds()
        if b is None:
            raise ValueError("cannot frame a scene without objects; give a camera")
        return np.array(b)
    if hasattr(obj, "vertices") and not isinstance(obj, np.ndarray):
        return np.asarray(obj.vertices)
    if isinstance(obj, tuple) and len(obj) == 2:
        return np.asarray(obj[0])
    return np.asarray(obj)


def frame_mesh(
    vertices: Any,
    fov_y: float = 35.0,
    direction: Any = None,
    up: Any = (0.0, 1.0, 0.0),
) -> Camera:
    """A perspective camera that looks at the bounding sphere of a mesh from ``direction``
    and fits it in the frame.

    ``vertices``: an (N, 3) array, a :class:`Mesh`, a trimesh, a ``(V, F)`` pair or a
    :class:`Scene`. ``direction``: from the model to the camera, a view name (see
    :func:`view_direction`: "front", "top", "iso", ...) or (x, y, z); None is the default
    view, from the front, a little right and above, for the up axis ``up`` (default +y;
    ``(0, 0, 1)`` for Z-up models such as STL files). The near/far planes are left to
    ``render`` to fit to the scene (``near``/``far`` are None)."""
    v = np.asarray(_points_of(vertices), dtype=np.float64).reshape(-1, 3)
    if len(v) == 0 or not np.all(np.isfinite(v)):
        raise ValueError("cannot frame an empty or non-finite set of vertices")
    if not (0.0 < fov_y < 180.0):
        raise ValueError(f"fov_y must be in (0, 180) degrees, got {fov_y}")
    lo, hi = v.min(axis=0), v.max(axis=0)
    centre = (lo + hi) / 2
    radius = max(float(np.linalg.norm(hi - lo)) / 2, 1e-6)
    d, cam_up = view_direction("default" if direction is None else direction, up)
    dist = radius / math.sin(math.radians(fov_y) / 2) * 1.05
    eye = centre + d * dist
    return Camera.look_at(
        eye=tuple(eye.tolist()),
        target=tuple(centre.tolist()),
        up=tuple(cam_up.tolist()),
        fov_y=fov_y,
    )


def _rotate(v: np.ndarray, axis: np.ndarray, degrees: float) -> np.ndarray:
    """``v`` rotated about the unit ``axis`` by ``degrees`` (right-handed; Rodrigues)."""
    a = math.radians(degrees)
    return (
        v * math.cos(a)
        + np.cross(axis, v) * math.sin(a)
        + axis * float(axis @ v) * (1 - math.cos(a))
    )


def orbit(camera: Camera, azimuth: float = 0.0, elevation: float = 0.0, up: Any = None) -> Camera:
    """``camera`` moved around its target at the same distance: ``azimuth`` degrees about
    the up axis (positive: to the camera's right) and then ``elevation`` degrees up towards
    it (negative: down). ``up`` defaults to the camera's own; the projection, field of view
    or height and the near/far planes (None stays None: fitted) are kept. Passing over the
    pole is allowed: the camera up then follows :func:`view_direction`'s rule. A pinhole
    camera keeps its intrinsics."""
    u = _unit(camera.up if up is None else up, "up")
    target = np.asarray(camera.target, dtype=np.float64)
    d = np.asarray(camera.eye, dtype=np.float64) - target
    d = _rotate(d, u, azimuth)
    side = np.cross(d, u)
    if np.linalg.norm(side) > 1e-12 * np.linalg.norm(d):
        d = _rotate(d, side / np.linalg.norm(side), elevation)
    _, cam_up = view_direction(tuple(d.tolist()), u)
    eye = tuple((target + d).tolist())
    t, cu = tuple(target.tolist()), tuple(cam_up.tolist())
    if camera.fov_y is not None:
        return Camera.look_at(eye, t, cu, fov_y=camera.fov_y, near=camera.near, far=camera.far)
    if camera.intrinsics is not None:
        fx, fy, cx, cy, skew, w, h = camera.intrinsics
        return Camera.from_intrinsics(
            eye,
            t,
            cu,
            fx=fx,
            fy=fy,
            cx=cx,
            cy=cy,
            skew=skew,
            width=w,
            height=h,
            near=camera.near,
            far=camera.far,
        )
    assert camera.height is not None
    return Camera.orthographic(eye, t, cu, height=camera.height, near=camera.near, far=camera.far)


def intrinsics(camera: Camera, width: int, height: int) -> np.ndarray:
    """The 3x3 pinhole matrix K of a perspective or pinhole ``camera`` rendering ``width`` x
    ``height`` pixels, in the computer-vision convention (x right, y down, pixel (x, y)
    centred at (x + 0.5, y + 0.5)): ``[[fx, skew, cx], [0, fy, cy], [0, 0, 1]]``.

    A pinhole camera (:meth:`Camera.from_intrinsics`) gives its own K scaled by the size
    ratio to its reference image (exactly its K at that size); a ``look_at`` camera gives
    ``[[f, 0, width/2], [0, f, height/2], [0, 0, 1]]`` with
    ``f = height / (2 tan(fov_y / 2))``."""
    if camera.kind == "orthographic":
        raise ValueError("an orthographic camera has no pinhole intrinsics")
    if not (width >= 1 and height >= 1):
        raise ValueError(f"width and height must be >= 1, got {width}x{height}")
    if camera.intrinsics is not None:
        fx, fy, cx, cy, skew, w0, h0 = camera.intrinsics
        sx, sy = width / w0, height / h0
        return np.array([[fx * sx, skew * sx, cx * sx], [0.0, fy * sy, cy * sy], [0.0, 0.0, 1.0]])
    assert camera.fov_y is not None
    f = height / (2.0 * math.tan(math.radians(camera.fov_y) / 2.0))
    return np.array([[f, 0.0, width / 2.0], [0.0, f, height / 2.0], [0.0, 0.0, 1.0]])


def camera_from_intrinsics(
    K: Any,
    width: int,
    height: int,
    eye: Any,
    target: Any,
    up: Any = (0.0, 1.0, 0.0),
    near: float | None = None,
    far: float | None = None,
) -> Camera:
    """A pinhole camera (:meth:`Camera.from_intrinsics`) from a 3x3 matrix
    ``K = [[fx, skew, cx], [0, fy, cy], [0, 0, 1]]`` for a ``width`` x ``height`` image:
    any focal lengths, principal point and skew, kept exactly (``intrinsics(camera, width,
    height)`` gives ``K`` back). The optical axis passes through ``target``. ``K`` must be
    finite and upper triangular with ``K[2] == (0, 0, 1)``, ``fx, fy > 0``; anything else
    is a ``ValueError`` naming the value."""
    k = np.asarray(K, dtype=np.float64)
    if k.shape != (3, 3) or not np.all(np.isfinite(k)):
        raise ValueError(f"K must be a finite 3x3 matrix, got shape {k.shape}")
    if k[1, 0] != 0.0 or k[2, 0] != 0.0 or k[2, 1] != 0.0 or k[2, 2] != 1.0:
        raise ValueError(
            "K must be [[fx, skew, cx], [0, fy, cy], [0, 0, 1]]: got "
            f"K[1, 0]={k[1, 0]:g}, K[2]=({k[2, 0]:g}, {k[2, 1]:g}, {k[2, 2]:g})"
        )
    return Camera.from_intrinsics(
        eye,
        target,
        up,
        fx=float(k[0, 0]),
        fy=float(k[1, 1]),
        cx=float(k[0, 2]),
        cy=float(k[1, 2]),
        skew=float(k[0, 1]),
        width=width,
        height=height,
        near=near,
        far=far,
    )


def camera_from_matrix(
    view: Any, fov_y: float = 45.0, near: float | None = None, far: float | None = None
) -> Camera:
    """A perspective camera from a 4x4 world-to-eye matrix (OpenGL's: the camera looks
    down -z, y up; as :meth:`Camera.view_matrix` returns): the eye, a target one unit in
    front and the up vector are read from it. The matrix must be a rigid motion (rotation
    and translation, to 1e-6)."""
    m = np.asarray(view, dtype=np.float64)
    if m.shape != (4, 4) or not np.all(np.isfinite(m)):
        raise ValueError(f"view must be a finite 4x4 matrix, got shape {m.shape}")
    r, t = m[:3, :3], m[:3, 3]
    if not (
        np.allclose(r @ r.T, np.eye(3), atol=1e-6)
        and np.linalg.det(r) > 0
        and np.allclose(m[3], (0, 0, 0, 1))
    ):
        raise ValueError("view must be a rigid motion (a rotation and a translation)")
    eye = -r.T @ t
    forward = -r[2]
    return Camera.look_at(
        tuple(eye.tolist()),
        tuple((eye + forward).tolist()),
        tuple(r[1].tolist()),
        fov_y=fov_y,
        near=near,
        far=far,
    )


def _translate_rotate_y(x: float, z: float, degrees: float) -> np.ndarray:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return np.array(
        [[c, 0, s, x], [0, 1, 0, 0], [-s, 0, c, z], [0, 0, 0, 1]],
        dtype=np.float64,
    )


def demo_scene() -> tuple[Scene, Camera]:
    """Three Spot cows (Keenan Crane, public domain) in gold, polished silver and copper on a
    pewter cube, under a directional key light (casting shadow-mapped shadows onto the base)
    and a bluish point fill light."""
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
    scene.add_light(
        DirectionalLight(direction=(-0.5, -1.0, -0.8), color=(1.0, 0.97, 0.9), shadows=True)
    )
    scene.add_light(PointLight(position=(-3.0, 2.0, 4.0), color=(0.35, 0.4, 0.55)))
    camera = Camera.look_at(
        eye=(0.0, 1.1, 4.4), target=(0.0, -0.1, 0.0), up=(0, 1, 0), fov_y=42.0, near=0.1, far=50.0
    )
    return scene, camera
