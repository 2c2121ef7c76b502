"""Depth precision of the reversed-Z f32 scheme: the smallest separation (relative to the
distance) at which the nearer of two parallel planes wins every pixel, in both submission
orders, with near = 0.001 and far = 10 000. Prints the Markdown table of docs/HARD_CASES.md.

Run: .venv/bin/python bench/depth_precision.py
"""

from __future__ import annotations

import numpy as np
import shadelab_rs as sl

SEPARATIONS = [1e-6, 1e-7, 5e-8, 2e-8]
DISTANCES = [0.01, 1, 100, 1000, 9000]


def nearer_wins_share(d: float, rel: float, near: float = 0.001, far: float = 1e4) -> float:
    """Share of pixels (worst of both submission orders) where the nearer plane wins."""
    h = d * 0.8
    quad = np.array([[-h, -h, -d], [h, -h, -d], [h, h, -d], [-h, h, -d]], float)
    faces = [[0, 1, 2], [0, 2, 3]]

    def flat(rgb):
        return sl.Material(ambient=rgb, diffuse=(0, 0, 0), specular=(0, 0, 0))

    pair = [(quad, (0, 1, 0)), (quad - [0, 0, d * rel], (1, 0, 0))]
    shares = []
    for order in (pair, pair[::-1]):
        s = sl.Scene(ambient=(1, 1, 1))
        for q, c in order:
            s.add(sl.Mesh(q, faces), material=flat(c))
        cam = sl.Camera.look_at((0, 0, 0), (0, 0, -1), near=near, far=far)
        img = sl.render(s, cam, 128, 96)
        shares.append(float((img[..., 1] == 255).mean()))
    return min(shares)


def main() -> None:
    print("| distance | " + " | ".join(f"{r:g}" for r in SEPARATIONS) + " |")
    print("|---|" + "---|" * len(SEPARATIONS))
    for d in DISTANCES:
        cells = " | ".join(f"{100 * nearer_wins_share(d, r):.0f} %" for r in SEPARATIONS)
        print(f"| {d:g} | {cells} |")


if __name__ == "__main__":
    main()
