"""Repeated renders with lines: what finding the edges costs per render (issue 14).

A 262k-triangle UV sphere (256 x 512) at 960 x 540, 2 threads, best of N renders of one
scene: no lines, edges="visible", and edges="visible" with edges_only=True. Run it against
two builds (e.g. PYTHONPATH=<other build> python bench/lines_repeat.py) on the same
machine, alternating, to compare.
"""

from __future__ import annotations

import sys
import time

import shadelab_rs as sl


def main(repeats: int = 5) -> None:
    scene = sl.Scene()
    scene.add(sl.Mesh.uv_sphere(256, 512), material="gold")
    cam = sl.Camera.look_at((0.3, 0.5, 3.0), (0, 0, 0), (0, 1, 0), fov_y=45)
    cases = {
        "none": {},
        "visible": {"edges": "visible"},
        "edges_only": {"edges": "visible", "edges_only": True},
    }
    out = []
    for name, kw in cases.items():
        best = float("inf")
        for _ in range(repeats):
            t = time.perf_counter()
            sl.render(scene, cam, 960, 540, threads=2, **kw)
            best = min(best, time.perf_counter() - t)
        out.append(f"{name} {best * 1000:.1f} ms")
    print(", ".join(out))


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
