#!/usr/bin/env python3
"""Cold start: from a fresh ``python`` to a saved PNG (``make bench-cold`` → docs/COLD_START.md).

Three measurements, each the median of alternating runs so machine load hits every variant
alike:

1. **Import.** Wall time of a fresh interpreter running ``import numpy`` against
   ``import numpy, shadelab_rs`` (and ``-X importtime``'s own figure for shadelab_rs alone):
   what the package adds to NumPy's import.
2. **First picture.** A fresh interpreter that imports shadelab_rs, renders the demo scene
   at 1920x1080 and saves it as PNG, with each step's time measured inside it.
3. **save_image.** The same 1080p demo render written with every PNG compression setting,
   against the writer used before (zlib level 6 over unfiltered rows, in Python) and
   Pillow's default, with file sizes; every file is read back and compared.

    python bench/bench_cold_start.py                 # table on stdout
    python bench/bench_cold_start.py --write docs/COLD_START.md
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import statistics
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path
from typing import Any

import numpy as np
from harness import machine

ROOT = Path(__file__).resolve().parent.parent

FIRST_PICTURE = r"""
import json, sys, time
t0 = time.perf_counter()
import shadelab_rs as sl
t1 = time.perf_counter()
scene, cam = sl.demo_scene()
img = sl.render(scene, cam, width=1920, height=1080)
t2 = time.perf_counter()
sl.save_image(img, sys.argv[1])
t3 = time.perf_counter()
print(json.dumps({"import": t1 - t0, "render": t2 - t1, "save": t3 - t2}))
"""


def _wall(code: list[str]) -> float:
    t = time.perf_counter()
    subprocess.run([sys.executable, *code], check=True, capture_output=True)
    return time.perf_counter() - t


def import_times(rounds: int) -> dict[str, float]:
    numpy_only, both = [], []
    for r in range(rounds):
        pair = [
            (numpy_only, ["-c", "import numpy"]),
            (both, ["-c", "import numpy, shadelab_rs"]),
        ]
        for out, code in pair if r % 2 == 0 else pair[::-1]:
            out.append(_wall(code))
    self_ms = []
    for _ in range(rounds):
        err = subprocess.run(
            [sys.executable, "-X", "importtime", "-c", "import numpy; import shadelab_rs"],
            check=True,
            capture_output=True,
            text=True,
        ).stderr
        # The cumulative column of the top-level shadelab_rs line (numpy already imported).
        line = [ln for ln in err.splitlines() if ln.rstrip().endswith("| shadelab_rs")][-1]
        self_ms.append(int(line.split("|")[1]) / 1e3)
    return {
        "numpy_s": statistics.median(numpy_only),
        "numpy_and_shadelab_s": statistics.median(both),
        "added_s": statistics.median(b - a for a, b in zip(numpy_only, both)),
        "importtime_ms": statistics.median(self_ms),
    }


def first_picture(rounds: int, tmp: Path) -> dict[str, float]:
    runs = []
    for _ in range(rounds):
        t = time.perf_counter()
        out = subprocess.run(
            [sys.executable, "-c", FIRST_PICTURE, str(tmp / "first.png")],
            check=True,
            capture_output=True,
            text=True,
        ).stdout
        d = json.loads(out)
        d["total"] = time.perf_counter() - t
        runs.append(d)
    return {k: statistics.median(r[k] for r in runs) for k in runs[0]}


def _zlib6_png(a: np.ndarray) -> bytes:
    """The PNG writer save_image used before (Python, zlib level 6, no row filter)."""
    h, w, _ = a.shape
    rows = np.concatenate([np.zeros((h, 1), np.uint8), a.reshape(h, -1)], axis=1)

    def chunk(tag: bytes, data: bytes) -> bytes:
        body = tag + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    head = chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    idat = chunk(b"IDAT", zlib.compress(rows.tobytes(), 6))
    return b"\x89PNG\r\n\x1a\n" + head + idat + chunk(b"IEND", b"")


def save_times(rounds: int, tmp: Path) -> tuple[list[dict[str, Any]], float]:
    import shadelab_rs as sl
    from PIL import Image

    scene, cam = sl.demo_scene()
    t = time.perf_counter()
    img = sl.render(scene, cam, width=1920, height=1080)
    render_s = time.perf_counter() - t

    def ours(c: str) -> Any:
        return lambda p: sl.save_image(img, p, compression=c)

    def pillow(p: Path) -> None:
        Image.fromarray(img).save(p)

    def before(p: Path) -> None:
        p.write_bytes(_zlib6_png(img))

    methods: list[tuple[str, Any]] = [(f"save_image, {c}", ours(c)) for c in sl.io.PNG_COMPRESSIONS]
    methods += [("before: Python zlib level 6, no filter", before), ("Pillow default", pillow)]
    times: dict[str, list[float]] = {name: [] for name, _ in methods}
    for r in range(rounds):
        order = methods if r % 2 == 0 else methods[::-1]
        for name, f in order:
            path = tmp / "s.png"
            t = time.perf_counter()
            f(path)
            times[name].append(time.perf_counter() - t)
            if r == 0:
                with Image.open(path) as im:
                    assert np.array_equal(np.asarray(im), img), name
                times[name + " size"] = [path.stat().st_size]
    rows = [
        {
            "method": name,
            "ms": round(1e3 * statistics.median(times[name]), 1),
            "kB": round(times[name + " size"][0] / 1e3),
        }
        for name, _ in methods
    ]
    return rows, render_s


def markdown(
    meta: dict[str, Any],
    imp: dict[str, float],
    first: dict[str, float],
    rows: list[dict[str, Any]],
    render_s: float,
) -> str:
    m = meta["machine"]
    out = [
        "# Cold start",
        "",
        "From a fresh `python` to a saved PNG: what importing shadelab_rs adds to NumPy's",
        "import, the first picture step by step, and what `save_image` costs per PNG",
        "compression setting. Generated by `bench/bench_cold_start.py` (`make bench-cold`,",
        "also the last step of `make bench`); every figure is the median of alternating runs.",
        "",
        f"Measured {meta['date']} on {m.get('CPU', 'unknown')}, "
        f"source tree {m.get('source tree (git)', 'unknown')}; "
        f"load average {meta['load'][0]:.1f} before and {meta['load'][1]:.1f} after "
        f"({meta['rounds']} rounds).",
        "",
        "## Import",
        "",
        "| | wall time |",
        "|---|---:|",
        f"| `python -c 'import numpy'` | {1e3 * imp['numpy_s']:.0f} ms |",
        f"| `python -c 'import numpy, shadelab_rs'` | {1e3 * imp['numpy_and_shadelab_s']:.0f} ms |",
        f"| added by shadelab_rs (median of per-round differences) "
        f"| {1e3 * imp['added_s']:.0f} ms |",
        f"| `-X importtime`, shadelab_rs after NumPy (cumulative) "
        f"| {imp['importtime_ms']:.0f} ms |",
        "",
        "The wall-time difference includes loading the extension module (its shared library);",
        "`-X importtime` counts only Python-level imports.",
        "",
        "## First picture: the demo scene at 1920x1080, all cores",
        "",
        "| step | time |",
        "|---|---:|",
        f"| `import shadelab_rs` (NumPy included) | {1e3 * first['import']:.0f} ms |",
        f"| `demo_scene()` + `render` | {1e3 * first['render']:.0f} ms |",
        f"| `save_image(img, 'x.png')` | {1e3 * first['save']:.0f} ms |",
        f"| whole process, start to exit | {1e3 * first['total']:.0f} ms |",
        "",
        "## save_image: PNG compression settings",
        "",
        f"The same 1080p demo render (the render itself took {1e3 * render_s:.0f} ms here);",
        "every file is read back with Pillow and equals the image.",
        "",
        "| writer | time | size |",
        "|---|---:|---:|",
    ]
    for r in rows:
        out.append(f"| {r['method']} | {r['ms']:.1f} ms | {r['kB']} kB |")
    out += [
        "",
        '`save_image` encodes PNG in Rust (the `png` crate: adaptive row filters; "fastest"',
        'and "fast" use its fdeflate path, "balanced" and "high" zlib-style deflate) with the',
        'GIL released. The default is "fast"; `compression="high"` is for files that are kept.',
        "",
        "## Reproduce",
        "",
        "```sh",
        "make bench-cold   # or: python bench/bench_cold_start.py --write docs/COLD_START.md",
        "```",
        "",
    ]
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rounds", type=int, default=9)
    p.add_argument("--write", type=Path, help="write the Markdown report here")
    a = p.parse_args(argv)
    import shadelab_rs as sl

    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        imp = import_times(a.rounds)
        first = first_picture(a.rounds, tmp)
        rows, render_s = save_times(a.rounds, tmp)
    meta = {
        "date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "machine": machine(sl.__version__),
        "load": (load0, os.getloadavg()[0]),
        "rounds": a.rounds,
    }
    text = markdown(meta, imp, first, rows, render_s)
    print(text)
    if a.write:
        a.write.write_text(text)
        print(f"wrote {a.write}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
