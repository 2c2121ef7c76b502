"""Pictures of the defaults for the user guide ("First pictures"): run from the repository
root after `make build` (`make docs-images` runs it). Writes docs/first_minutes/defaults.png:

row 1: a millimetre-scale box (Z-up) seen from (100, -150, 80) with the planes fitted;
       Spot from the front, back and top under the default light rig;
row 2: an STL icosphere as loaded (welded, smooth), the same unwelded (faceted), a box with
       shared corners (sharp edges kept), Spot in sRGB encoding.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import shadelab_rs as sl
import trimesh

CELL = 200
OUT = Path(__file__).with_name("defaults.png")


def cell(scene_or_mesh, camera=None, **kw) -> np.ndarray:
    return sl.render(scene_or_mesh, camera, CELL, CELL, background=(0.12, 0.12, 0.14), **kw)


def main() -> None:
    spot = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
    box = trimesh.creation.box(extents=(60, 30, 48))
    box.apply_translation((0, 0, 24))
    mm = sl.Scene()
    mm.add(box, material="gold")
    row1 = [cell(mm, sl.Camera.look_at((100, -150, 80), (0, 0, 24), up=(0, 0, 1)))]
    for view in ("front", "back", "top"):
        s = sl.Scene()
        s.add(spot, material="gold")
        row1.append(cell(s, sl.frame_mesh(spot, direction=view)))
    with tempfile.TemporaryDirectory() as tmp:
        stl = Path(tmp) / "sphere.stl"
        trimesh.creation.icosphere(subdivisions=2).export(stl)
        welded = sl.load_mesh(stl)
        raw = trimesh.load(stl, process=False)
        unwelded = sl.Mesh(raw.vertices, raw.faces)  # the old loader: three per triangle
        ply = Path(tmp) / "box.ply"
        trimesh.creation.box().export(ply)
        sharp = sl.load_mesh(ply)
    row2 = [
        cell(welded, sl.frame_mesh(welded)),
        cell(unwelded, sl.frame_mesh(welded)),
        cell(sharp, sl.frame_mesh(sharp, direction="iso")),
        cell(spot, sl.frame_mesh(spot), encoding="srgb"),
    ]
    sl.save_image(
        np.concatenate([np.concatenate(row1, 1), np.concatenate(row2, 1)], 0),
        OUT,
        compression="high",
    )
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
