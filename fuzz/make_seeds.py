"""Writes the committed seed corpora of the fuzz targets (fuzz/seeds/<target>/).

The pipeline target decodes bytes as described in crates/raster/src/fuzzing.rs; this script
is the matching encoder, so every seed is a readable scene. Run it from anywhere:
``python3 fuzz/make_seeds.py``. Seeds whose name starts with ``error-`` must be refused
with an error (the smoke test checks that every other seed renders). Crash inputs found by
fuzzing are copied into the seed directories by hand (named ``crash-*``) and are not touched
by this script.
"""

from __future__ import annotations

import struct
from pathlib import Path

HERE = Path(__file__).resolve().parent
SPECIAL = {"nan": 13, "inf": 14, "-inf": 15}


def f(x) -> bytes:
    """One number: a small multiple of 1/8 in [-7, 7] as one tag byte, else raw f32 bits."""
    if isinstance(x, str):
        return bytes([SPECIAL[x]])
    t = x * 8 + 72
    if t == int(t) and 16 <= t <= 127:
        return bytes([int(t)])
    return bytes([128]) + struct.pack("<f", x)


def v3(v) -> bytes:
    return b"".join(f(c) for c in v)


def scene(
    *,
    size=(24, 16),
    shading=2,
    specular=0,
    cull=False,
    two_sided=False,
    infinite_viewer=False,
    ortho=False,
    eye=(0, 0, 3),
    target=(0, 0, 0),
    up=(0, 1, 0),
    fov_or_height=45,
    near=0.125,
    far=50,
    ambient=(0.25, 0.25, 0.25),
    objects=(),
    lights=(),
    fog=None,
    threads=2,
    back_materials=None,
    split_colors=None,
) -> bytes:
    flags = shading + 3 * specular + 0x10 * cull + 0x20 * two_sided + 0x40 * infinite_viewer
    out = bytes([size[0] - 1, size[1] - 1, flags, int(ortho)])
    out += v3(eye) + v3(target) + v3(up) + f(fov_or_height) + f(near) + f(far)
    out += v3(ambient)
    out += bytes([len(objects) - 1])
    for o in objects:
        verts, faces = o["v"], o["f"]
        out += bytes([len(verts) - 1]) + b"".join(v3(p) for p in verts)
        normals = o.get("n")
        out += bytes([normals is not None])
        if normals is not None:
            out += b"".join(v3(n) for n in normals)
        out += bytes([len(faces) - 1]) + bytes(i for tri in faces for i in tri)
        m = o.get("material", ((0.25, 0.25, 0.25), (0.75, 0.5, 0.25), (0.5, 0.5, 0.5), 32))
        out += v3(m[0]) + v3(m[1]) + v3(m[2]) + f(m[3]) + v3(o.get("emission", (0, 0, 0)))
        t = o.get("transform")
        out += bytes([t is not None])
        if t is not None:
            out += b"".join(f(x) for row in t[:3] for x in row)
            out += bytes([len(t) == 4])
            if len(t) == 4:
                out += b"".join(f(x) for x in t[3])
    out += bytes([len(lights)])
    for kind, *args in lights:
        if kind == "dir":
            d, c, i = args
            out += bytes([0]) + v3(d) + v3(c) + f(i)
        elif kind == "point":
            p, c, i, att = args
            out += bytes([1]) + v3(p) + v3(c) + f(i) + b"".join(f(a) for a in att)
        elif kind == "spot":
            p, c, i, d, cutoff, exponent = args
            out += bytes([2]) + v3(p) + v3(c) + f(i) + v3(d) + f(cutoff) + f(exponent)
        else:
            p, u, v, disk, samples, c, i, one_sided = args
            out += bytes([3]) + v3(p) + v3(u) + v3(v) + bytes([disk, samples - 1])
            out += v3(c) + f(i) + bytes([one_sided])
    if fog is None:
        out += bytes([0])
    else:
        mode, *args = fog
        out += bytes([1, mode]) + b"".join(f(a) for a in args[:-1]) + v3(args[-1])
    out += bytes([threads - 1])
    # Extension block: a back material per object, split colours per light (None: absent).
    for m in back_materials or []:
        out += bytes([m is not None])
        if m is not None:
            out += v3(m[0]) + v3(m[1]) + v3(m[2]) + f(m[3])
    for split in split_colors or []:
        out += bytes([split is not None])
        if split is not None:
            for c in split:
                out += bytes([c is not None]) + (v3(c) if c is not None else b"")
    return out


TRI = {"v": [(-1, -1, 0), (1, -1, 0), (0, 1, 0)], "f": [(0, 1, 2)]}
SUN = ("dir", (-1, -1, -1), (1, 1, 1), 1)
QUAD = {
    "v": [(-2, -2, -1), (2, -2, -1), (2, 2, -1), (-2, 2, -1)],
    "f": [(0, 1, 2), (0, 2, 3)],
}

PIPELINE = {
    "triangle-phong": scene(objects=[TRI], lights=[SUN]),
    "triangle-flat-cull-two-sided": scene(
        shading=0, cull=True, two_sided=True, objects=[TRI, {**TRI, "f": [(2, 1, 0)]}], lights=[SUN]
    ),
    # A floor reaching behind the camera: crosses the near plane, vertices with w < 0.
    "near-plane-crossing": scene(
        eye=(0, 0, 0),
        target=(0, 0, -1),
        objects=[{"v": [(-6, -1, 5), (6, -1, 5), (0, -1, -7)], "f": [(0, 1, 2)]}],
        lights=[SUN],
    ),
    # A vertex exactly in the eye plane (w = 0) and one a hair in front (w = 1e-7).
    "w-zero": scene(
        eye=(0, 0, 0),
        target=(0, 0, -1),
        near=1e-7,
        objects=[
            {
                "v": [(-1, 0, 0), (1, -1, -2), (1, 1, -2), (0, 0.5, -1e-7)],
                "f": [(0, 1, 2), (3, 1, 2)],
            }
        ],
        lights=[SUN],
    ),
    "huge-and-tiny": scene(
        eye=(0, 0, 0),
        target=(0, 0, -1),
        near=1e-7,
        far=1e30,
        objects=[
            {"v": [(-1e7, -1e7, -5), (1e7, -1e7, -5), (0, 1e7, -5)], "f": [(0, 1, 2)]},
            {"v": [(0, 0, -1), (1e-7, 0, -1), (0, 1e-7, -1)], "f": [(0, 1, 2)]},
        ],
        lights=[SUN],
    ),
    "ortho-degenerate": scene(
        ortho=True,
        fov_or_height=4,
        near=-5,
        far=5,
        shading=1,
        objects=[
            {
                "v": [(0, 0, 0), (1, 0, 0), (0, 1, 0), (2, 0, 0), (1, 0, 0)],
                "f": [(0, 1, 2), (0, 1, 3), (0, 0, 1), (1, 4, 2), (2, 1, 0)],
            }
        ],
        lights=[SUN],
    ),
    "lights-and-fog": scene(
        specular=2,
        objects=[QUAD],
        lights=[
            ("point", (0, 0, 0), (1, 0.5, 0.25), 2, (0, 0, 1)),
            ("spot", (0, 0, 2), (1, 1, 1), 3, (0, 0, -1), 20, 4),
            ("area", (0, 2, 1), (1, 0, 0), (0, 0, 1), 1, 3, (0.5, 0.5, 1), 1, 1),
        ],
        fog=(1, 0.25, (0.5, 0.5, 0.5)),
    ),
    "given-normals-zero-and-cancelling": scene(
        shading=2,
        objects=[{**TRI, "n": [(0, 0, 0), (0, 0, 1), (0, 0, -1)]}],
        lights=[SUN, ("point", (0, 0, 0), (1, 1, 1), 1, (1, 0, 0))],
    ),
    "light-on-surface-eye-on-surface": scene(
        eye=(0, 0, 1e-7),
        target=(0, 0, -1),
        near=1e-7,
        objects=[QUAD],
        lights=[("point", (0, 0, -1), (1, 1, 1), 4, (0, 0, 1))],
    ),
    "transform-scaled": scene(
        objects=[{**TRI, "transform": [(2, 0, 0, 0.5), (0, 0.5, 0, 0), (0, 0, 1, -1)]}],
        lights=[SUN],
        infinite_viewer=True,
    ),
    "back-material-and-split-colors": scene(
        two_sided=True,
        objects=[{**TRI, "f": [(0, 1, 2), (2, 1, 0)]}],
        lights=[SUN, ("point", (0, 0, 2), (1, 1, 1), 1, (1, 0, 0))],
        back_materials=[((0.5, 0, 0), (0, 0.75, 0), (0, 0, 1), 8)],
        split_colors=[((1, 0.5, 0), None), (None, (0, 0, 2))],
    ),
    "error-nan-vertex": scene(objects=[{**TRI, "v": [(-1, -1, 0), (1, "nan", 0), (0, 1, 0)]}]),
    "error-non-affine": scene(
        objects=[{**TRI, "transform": [(1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 1, 1)]}]
    ),
    "error-camera-up-parallel": scene(up=(0, 0, 1), objects=[TRI]),
}

T = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
OBJ = {
    "triangle.obj": T + "f 1 2 3\n",
    "quad-normals-uvs.obj": "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n",
    "pentagon-relative.obj": "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf -5 -4 -3 -2 -1\n",
    "groups-mtl.obj": "mtllib m.mtl\n" + T + "v 1 1 0\no a\nusemtl red\nf 1 2 3\ng b\nf 2 4 3\n"
    "\n#mtl\nnewmtl red\nKa 0.1 0 0\nKd 0.8 0.1 0.1\nKs 1 1 1\nNs 20\nKe 0 0 0.5\nmap_Kd x.png\n",
    "degenerate.obj": T + "v 2 0 0\nf 1 2 3\nf 3 2 1\nf 1 2 4\nf 1 1 2\n",
    "mixed-normals.obj": T + "vn 0 0 1\nf 1//1 2//1 3//1\nf 3 2 1\n",
    "error-nan-normal.obj": T + "vn nan 0 1\nf 1//1 2//1 3//1\n",
    "error-short-face.obj": T + "f 1 2\n",
    "error-truncated.obj": T + "f 1 2 3\nv 1 2",
    "error-index-zero.obj": T + "f 0 1 2\n",
    "vertex-w.obj": "v 0 0 0 2\nv 1 0 0 0.5\nv 0 1 0 1e-30\nf 1 2 3\n",
    "vertex-colors.obj": "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n",
    "lines-points.obj": T + "l 1 2\np 3\nf 1 2 3\n",
    "crlf.obj": T.replace("\n", "\r\n") + "f 1 2 3\r\n",
}


def main() -> None:
    for target, seeds in (("pipeline", PIPELINE), ("obj_loader", OBJ)):
        d = HERE / "seeds" / target
        d.mkdir(parents=True, exist_ok=True)
        for name, data in seeds.items():
            (d / name).write_bytes(data if isinstance(data, bytes) else data.encode())
    (HERE / "seeds" / "obj_loader" / "error-garbage.obj").write_bytes(bytes(range(256)))


if __name__ == "__main__":
    main()
