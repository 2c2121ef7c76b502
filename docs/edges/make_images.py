"""Pictures of line drawing for the user guide ("Lines: wireframes and hidden lines"): run
from the repository root after `make build` (`make docs-images` runs it). Writes
docs/edges/*.png, each made by the call in its caption (docs/edges/captions.md):

- all.png, visible.png, features.png: the scene below shaded with each `edges` mode;
- hidden_line.png: `edges="visible", edges_only=True`: the classic hidden-line drawing;
- features_only.png: `edges="features", edges_only=True`;
- antialiased.png: a crop enlarged 4x without smoothing at samples 1, 4 and 16.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import shadelab_rs as sl

HERE = Path(__file__).parent
W, H = 480, 360
CROP = (slice(130, 200), slice(150, 250))
ZOOM = 4


def torus(major: float = 1.0, minor: float = 0.38, n_major: int = 32, n_minor: int = 14):
    u = np.arange(n_major) * 2 * math.pi / n_major
    w = np.arange(n_minor) * 2 * math.pi / n_minor
    uu, ww = np.meshgrid(u, w, indexing="ij")
    r = major + minor * np.cos(ww)
    v = np.stack([r * np.cos(uu), minor * np.sin(ww), -r * np.sin(uu)], -1).reshape(-1, 3)
    f = []
    for i in range(n_major):
        for j in range(n_minor):
            a, b = i * n_minor + j, ((i + 1) % n_major) * n_minor + j
            c, d = (
                ((i + 1) % n_major) * n_minor + (j + 1) % n_minor,
                i * n_minor + (j + 1) % n_minor,
            )
            f += [(a, b, c), (a, c, d)]
    return v, np.array(f)


def scene_and_camera() -> tuple[sl.Scene, sl.Camera]:
    """A torus around a cube, and an icosphere: creases, silhouettes and a flat quad's
    diagonals in one view."""
    s = sl.Scene()
    a, b = math.radians(20), math.radians(10)
    tilt = np.array(
        [
            [1, 0, 0, 0],
            [0, math.cos(a), -math.sin(a), 0],
            [0, math.sin(a), math.cos(a), 0],
            [0, 0, 0, 1],
        ]
    ) @ np.array(
        [
            [math.cos(b), -math.sin(b), 0, 0],
            [math.sin(b), math.cos(b), 0, 0],
            [0, 0, 1, 0],
            [0, 0, 0, 1],
        ]
    )
    s.add(torus(), "gold", tilt)
    s.add(sl.Mesh.cube(), "pearl", np.diag([0.45, 0.45, 0.45, 1.0]))
    place = np.diag([0.45, 0.45, 0.45, 1.0])
    place[:3, 3] = (1.6, 0.2, 0.6)
    s.add(sl.Mesh.ico_sphere(2), "ruby", place)
    cam = sl.Camera.look_at((0.9, 2.2, 3.6), (0.3, 0.0, 0.0), (0, 1, 0), 42.0)
    return s, cam


CALLS = {
    "all.png": {"edges": "all", "samples": 4, "background": (0.5, 0.55, 0.6)},
    "visible.png": {"edges": "visible", "samples": 4, "background": (0.5, 0.55, 0.6)},
    "features.png": {
        "edges": "features",
        "samples": 4,
        "edge_width": 1.5,
        "background": (0.5, 0.55, 0.6),
    },
    "hidden_line.png": {
        "edges": "visible",
        "edges_only": True,
        "background": (1, 1, 1),
        "samples": 4,
    },
    "features_only.png": {
        "edges": "features",
        "edges_only": True,
        "background": (1, 1, 1),
        "samples": 4,
        "edge_width": 1.5,
    },
}
AA = [("samples=1", 1), ("samples=4", 4), ("samples=16", 16)]


def _kw(kw: dict) -> str:
    return ", ".join(f"{k}={v!r}" for k, v in kw.items())


def main() -> None:
    scene, cam = scene_and_camera()
    for name, kw in CALLS.items():
        img = sl.render(scene, cam, W, H, encoding="srgb", **kw)
        sl.save_image(img, HERE / name, compression="high")
    crops = []
    for _, n in AA:
        img = sl.render(scene, cam, W, H, encoding="srgb", edges="visible", samples=n)
        crops.append(np.repeat(np.repeat(img[CROP], ZOOM, 0), ZOOM, 1))
    gap = np.full((crops[0].shape[0], 6, 3), 255, np.uint8)
    sl.save_image(
        np.concatenate([x for c in crops for x in (c, gap)][:-1], 1),
        HERE / "antialiased.png",
        compression="high",
    )
    lines = [
        "# Line drawing pictures",
        "",
        "Made by `docs/edges/make_images.py` (`make docs-images`); `scene, cam` is its "
        "`scene_and_camera()` (a gold torus of 896 triangles, a pearl cube, a ruby "
        "icosphere).",
        "",
    ]
    for name, kw in CALLS.items():
        lines.append(f"- `{name}`: `sl.render(scene, cam, {W}, {H}, encoding='srgb', {_kw(kw)})`")
    lines.append(
        f"- `antialiased.png`: rows {CROP[0].start}-{CROP[0].stop}, columns "
        f"{CROP[1].start}-{CROP[1].stop} of `sl.render(scene, cam, {W}, {H}, "
        f"encoding='srgb', edges='visible', samples=n)` enlarged {ZOOM}x without smoothing, "
        "left to right: " + ", ".join(f"`{a}`" for a, _ in AA) + "."
    )
    (HERE / "captions.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
