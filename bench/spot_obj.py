#!/usr/bin/env python3
"""Writes Spot Loop-subdivided to a level, with the averaged vertex normals the speed–error
report uses (`speed_error.spot_meshes`), as an OBJ: the mesh `frame_cost spot=PATH` (the
Rust example for instruction counts and profiles) renders.

    python bench/spot_obj.py 1 /tmp/spot1.obj    # 23,424 triangles
    cargo build --release --example frame_cost
    valgrind --tool=callgrind target/release/examples/frame_cost \\
        phong 0 512 lights=sun,point spot=/tmp/spot1.obj frames=4
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # shadelab_ref

import speed_error


def write_obj(path: Path, vertices, faces, normals) -> None:
    """Positions, normals and faces (1-based, each corner's normal its vertex's)."""
    with open(path, "w") as out:
        out.writelines(f"v {a:.9g} {b:.9g} {c:.9g}\n" for a, b, c in vertices)
        out.writelines(f"vn {a:.9g} {b:.9g} {c:.9g}\n" for a, b, c in normals)
        out.writelines(
            f"f {a + 1}//{a + 1} {b + 1}//{b + 1} {c + 1}//{c + 1}\n" for a, b, c in faces
        )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("level", type=int, help="Loop subdivision level (0: the OBJ as shipped)")
    ap.add_argument("path", type=Path, help="where to write the OBJ")
    args = ap.parse_args(argv)
    if args.level < 0:
        ap.error("level must be >= 0")
    v, f, n = speed_error.spot_meshes((args.level,))[args.level]
    write_obj(args.path, v, f, n)
    print(f"{args.path}: {len(f)} triangles")
    return 0


if __name__ == "__main__":
    sys.exit(main())
