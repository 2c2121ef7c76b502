"""Pictures of reflection, refraction and transparency for the lighting guide ("Reflection,
refraction and transparency"): run from the repository root after `make build` (`make
docs-images` runs it). Writes docs/reflect/*.png and docs/reflect/captions.md, each picture
made by the call its caption names:

- mirror.png: a mirror floor under three spheres, reflections="environment" (left: one
  lookup of the sky, the spheres are missing from the mirror) and "ray" (right: the
  lectures' second-order reflection, the spheres and their own reflections);
- glass.png: a glass sphere (ior 1.5) in front of a striped wall, refractions="ray": the
  stripes are bent and turned upside down behind it;
- water.png: a water surface (ior 1.33) seen from below: inside Snell's window (48.75
  degrees around the vertical) the sky shows, beyond it total internal reflection mirrors
  the pool floor;
- transparent.png: three overlapping transparent spheres and a pane, sorted per pixel
  (refractions=None): the same picture in any submission order.
- antialiased.png: the mirror scene (reflections="ray") and the transparent scene with
  samples=4: multi-sample anti-aliasing with the secondary stage (transparent surfaces
  blended per sample), and a crop of each at samples=1 and samples=4 enlarged 4x.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import shadelab_rs as sl

HERE = Path(__file__).parent
W, H = 480, 320
DEEP = (0.02, 0.12, 0.16)


def sky(h: int = 128) -> sl.Environment:
    """A procedural sky: blue above, a warm horizon band, a darker ground, a sun disc."""
    v = (np.arange(h) + 0.5) / h
    u = (np.arange(2 * h) + 0.5) / (2 * h)
    vv, uu = np.meshgrid(v, u, indexing="ij")
    up = np.clip(1 - 2 * vv, 0, 1)[..., None]
    ground = np.clip(2 * vv - 1, 0, 1)[..., None]
    horizon = np.exp(-(((vv - 0.5) / 0.06) ** 2))[..., None]
    img = (
        up * np.array([0.25, 0.45, 0.95])
        + (1 - up - ground) * np.array([0.8, 0.85, 0.9])
        + horizon * np.array([0.5, 0.35, 0.15])
        + ground * np.array([0.25, 0.22, 0.2])
    )
    # Checks on the ground so reflections show structure.
    checks = ((np.floor(uu * 48) + np.floor(vv * 24)) % 2)[..., None] * ground * 0.15
    img = img + checks
    sun = np.exp(-(((uu - 0.62) / 0.02) ** 2 + ((vv - 0.3) / 0.03) ** 2))[..., None]
    img = img + sun * np.array([6.0, 5.0, 3.5])
    return sl.Environment(img.astype(np.float32))


def floor(y: float, half: float) -> sl.Mesh:
    v = np.array([[-half, y, -half], [-half, y, half], [half, y, half], [half, y, -half]])
    return sl.Mesh(v, [[0, 1, 2], [0, 2, 3]])


def place(s: float, x: float, y: float, z: float) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3] *= s
    t[:3, 3] = (x, y, z)
    return t


def mirror_scene() -> sl.Scene:
    scene = sl.Scene(ambient=(0.1, 0.1, 0.1), environment=sky())
    scene.add_light(sl.DirectionalLight(direction=(-0.3, -1.0, -0.5), intensity=0.9))
    ball = sl.Mesh.uv_sphere(32, 64)
    for (x, z), preset in zip([(-1.1, -0.2), (0.0, 0.4), (1.1, -0.3)], ["ruby", "gold", "jade"]):
        scene.add(ball, material=preset, transform=place(0.5, x, 0.5, z))
    mirror = sl.Material((0.02, 0.02, 0.02), (0.1, 0.1, 0.12), (0, 0, 0), 1.0, reflectivity=0.85)
    scene.add(floor(0.0, 4.0), material=mirror)
    return scene


def stripes(z: float) -> list[tuple[sl.Mesh, sl.Material]]:
    out = []
    for k in range(12):
        x0 = -3.0 + k * 0.5
        v = np.array([[x0, -1.5, z], [x0 + 0.5, -1.5, z], [x0 + 0.5, 2.5, z], [x0, 2.5, z]])
        c = (0.9, 0.2, 0.15) if k % 2 else (0.95, 0.9, 0.8)
        m = sl.Material((0.3 * c[0], 0.3 * c[1], 0.3 * c[2]), c, (0, 0, 0), 1.0)
        out.append((sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), m))
    # A blue bar across, so the flip shows vertically too.
    v = np.array([[-3, 1.2, z + 0.01], [3, 1.2, z + 0.01], [3, 1.5, z + 0.01], [-3, 1.5, z + 0.01]])
    out.append(
        (
            sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]),
            sl.Material((0.05, 0.1, 0.3), (0.1, 0.3, 0.9), (0, 0, 0), 1.0),
        )
    )
    return out


def glass_scene() -> sl.Scene:
    scene = sl.Scene(ambient=(0.25, 0.25, 0.25), environment=sky())
    scene.add_light(sl.DirectionalLight(direction=(-0.2, -0.6, -1.0), intensity=0.8))
    for mesh, m in stripes(-2.0):
        scene.add(mesh, material=m)
    glass = sl.Material(
        (0, 0, 0),
        (0, 0, 0),
        (1, 1, 1),
        200.0,
        transparency=0.95,
        ior="glass",
        absorption=(0.05, 0.02, 0.05),
    )
    scene.add(sl.Mesh.uv_sphere(48, 96), material=glass, transform=place(0.8, 0.0, 0.5, 0.5))
    return scene


def water_scene() -> sl.Scene:
    scene = sl.Scene(ambient=(0.3, 0.3, 0.3), environment=sky())
    scene.add_light(sl.DirectionalLight(direction=(-0.2, -1.0, -0.3), intensity=0.7))
    # The pool floor: tiles of two colours, 3 m below the surface.
    for i in range(-14, 14):
        for j in range(-24, 6):
            v = np.array([[i, -3, j], [i, -3, j + 1], [i + 1, -3, j + 1], [i + 1, -3, j]], float)
            c = (0.1, 0.5, 0.6) if (i + j) % 2 else (0.85, 0.9, 0.9)
            scene.add(
                sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]),
                material=sl.Material((0.5 * c[0], 0.5 * c[1], 0.5 * c[2]), c, (0, 0, 0), 1.0),
            )
    scene.add(sl.Mesh.uv_sphere(24, 48), material="ruby", transform=place(0.6, 0.8, -1.6, -4.0))
    water = sl.Material((0, 0, 0), (0, 0, 0), (0, 0, 0), 1.0, transparency=0.95, ior="water")
    scene.add(floor(0.0, 40.0), material=water)
    return scene


def transparent_scene(order=(0, 1, 2, 3)) -> sl.Scene:
    scene = sl.Scene(ambient=(0.2, 0.2, 0.2), environment=sky())
    scene.add_light(sl.DirectionalLight(direction=(-0.3, -0.8, -0.6), intensity=0.8))
    scene.add(floor(-0.6, 4.0), material="white plastic")
    parts = []
    ball = sl.Mesh.uv_sphere(32, 64)
    for (x, z), c in zip(
        [(-0.5, 0.0), (0.5, 0.0), (0.0, -0.7)],
        [(0.9, 0.1, 0.1), (0.1, 0.8, 0.2), (0.15, 0.3, 0.95)],
    ):
        m = sl.Material(
            (0.3 * c[0], 0.3 * c[1], 0.3 * c[2]), c, (0.6, 0.6, 0.6), 60.0, transparency=0.55
        )
        parts.append((ball, m, place(0.6, x, 0.1, z)))
    v = np.array([[-1.5, -0.6, 0.8], [1.5, -0.6, 0.8], [1.5, 0.5, 0.8], [-1.5, 0.5, 0.8]])
    pane = sl.Material((0.1, 0.1, 0.05), (0.9, 0.85, 0.3), (0, 0, 0), 1.0, transparency=0.7)
    parts.append((sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), pane, np.eye(4)))
    for k in order:
        mesh, m, t = parts[k]
        scene.add(mesh, material=m, transform=t)
    return scene


def timed(scene, cam, **kw):
    t0 = time.perf_counter()
    img = sl.render(scene, cam, W, H, encoding="srgb", **kw)
    return img, time.perf_counter() - t0


def side_by_side(a, b):
    gap = np.full((a.shape[0], 6, 3), 255, np.uint8)
    return np.concatenate([a, gap, b], axis=1)


def main() -> None:
    lines = ["# Reflection and refraction pictures", ""]
    cam = sl.Camera.look_at((0.0, 1.5, 4.2), (0.0, 0.4, 0.0), (0, 1, 0), fov_y=40)
    env_img, t_env = timed(mirror_scene(), cam, reflections="environment", background="environment")
    ray_img, t_ray = timed(mirror_scene(), cam, reflections="ray", background="environment")
    sl.save_image(side_by_side(env_img, ray_img), HERE / "mirror.png")
    lines += [
        "![mirror](mirror.png)",
        "",
        f"`sl.render(mirror_scene(), cam, {W}, {H}, encoding='srgb', "
        f"reflections='environment', background='environment')` (left, {t_env * 1000:.0f} ms) and "
        f"`reflections='ray'` (right, {t_ray * 1000:.0f} ms; max_depth 5).",
        "",
    ]
    cam = sl.Camera.look_at((0.0, 0.5, 4.0), (0.0, 0.5, 0.0), (0, 1, 0), fov_y=40)
    img, t = timed(
        glass_scene(), cam, refractions="ray", reflections="ray", background="environment"
    )
    sl.save_image(img, HERE / "glass.png")
    lines += [
        "![glass](glass.png)",
        "",
        f"`sl.render(glass_scene(), cam, {W}, {H}, encoding='srgb', refractions='ray', "
        f"reflections='ray', background='environment')` ({t * 1000:.0f} ms).",
        "",
    ]
    cam = sl.Camera.look_at((0.0, -2.2, 2.0), (0.0, -0.2, -3.0), (0, 1, 0), fov_y=70)
    img, t = timed(water_scene(), cam, refractions="ray", reflections="ray", background=DEEP)
    sl.save_image(img, HERE / "water.png")
    lines += [
        "![water](water.png)",
        "",
        f"`sl.render(water_scene(), cam, {W}, {H}, encoding='srgb', refractions='ray', "
        f"reflections='ray', background={DEEP})` ({t * 1000:.0f} ms): the camera is 2.2 "
        "below the surface; the background is the colour of deep water.",
        "",
    ]
    cam = sl.Camera.look_at((0.0, 1.0, 3.5), (0.0, 0.0, 0.0), (0, 1, 0), fov_y=40)
    img, t = timed(transparent_scene(), cam, background="environment")
    other, _ = timed(transparent_scene((3, 2, 0, 1)), cam, background="environment")
    assert np.array_equal(img, other), "order-independent transparency changed with order"
    sl.save_image(img, HERE / "transparent.png")
    lines += [
        "![transparent](transparent.png)",
        "",
        f"`sl.render(transparent_scene(), cam, {W}, {H}, encoding='srgb', "
        f"background='environment')` ({t * 1000:.0f} ms; "
        "refractions=None: sorted per pixel, identical for the objects in any order).",
        "",
    ]
    # Anti-aliasing with the secondary stage: both scenes at samples=4, and crops.
    mirror_cam = sl.Camera.look_at((0.0, 1.5, 4.2), (0.0, 0.4, 0.0), (0, 1, 0), fov_y=40)
    ms_mirror, t_m = timed(
        mirror_scene(), mirror_cam, reflections="ray", background="environment", samples=4
    )
    ms_glass, t_g = timed(transparent_scene(), cam, background="environment", samples=4)
    one_glass, _ = timed(transparent_scene(), cam, background="environment")
    y0, x0, size = 150, 250, 60  # a crop across the pane's edge and the spheres' outlines

    def crop(img):
        return np.kron(img[y0 : y0 + size, x0 : x0 + size], np.ones((4, 4, 1), np.uint8))

    bottom = side_by_side(crop(one_glass), crop(ms_glass))
    pad = np.full((bottom.shape[0], ms_mirror.shape[1] * 2 + 6 - bottom.shape[1], 3), 255, np.uint8)
    sheet = np.concatenate(
        [
            side_by_side(ms_mirror, ms_glass),
            np.full((6, ms_mirror.shape[1] * 2 + 6, 3), 255, np.uint8),
            np.concatenate([bottom, pad], axis=1),
        ]
    )
    sl.save_image(sheet, HERE / "antialiased.png")
    lines += [
        "![antialiased](antialiased.png)",
        "",
        f"Top: `sl.render(mirror_scene(), cam, {W}, {H}, encoding='srgb', reflections='ray', "
        f"background='environment', samples=4)` ({t_m * 1000:.0f} ms) and "
        f"`sl.render(transparent_scene(), cam, {W}, {H}, encoding='srgb', "
        f"background='environment', samples=4)` ({t_g * 1000:.0f} ms). Bottom: a "
        f"{size}x{size} crop of the transparent scene at (x={x0}, y={y0}), samples=1 (left) "
        "and samples=4 (right), enlarged 4x: the pane's border and the spheres' outlines "
        "are blended per sample.",
        "",
    ]
    (HERE / "captions.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
