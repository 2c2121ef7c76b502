"""The small harness the benchmark scripts share: commands, the machine description, CSV
rows and Markdown report sections. Standard library only (every build's ``--worker`` of
bench_features.py imports it under its own venv)."""

from __future__ import annotations

import csv
import os
import platform
import subprocess
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent


def run(cmd: list[str]) -> str:
    """Standard output of `cmd` run in the repository root, or "unknown" if it fails or
    prints nothing."""
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=30, cwd=ROOT)
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return out.stdout.strip() if out.returncode == 0 and out.stdout.strip() else "unknown"


def _numpy_version() -> str:
    try:
        import numpy as np
    except ImportError:  # pragma: no cover - every bench venv has NumPy
        return "unknown"
    return np.__version__


def _cpuinfo() -> tuple[str, str, bool]:
    """CPU model, its SIMD extensions (the build targets baseline x86-64 unless RUSTFLAGS say
    otherwise, so not all of them are used), and whether it runs under a hypervisor."""
    model, flags = platform.processor() or "unknown", set()
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return model, "unknown", False
    for line in text.splitlines():
        key, _, value = line.partition(":")
        if key.strip() == "model name":
            model = value.strip()
        elif key.strip() == "flags":
            flags = set(value.split())
    simd = [f for f in ("sse4_2", "avx", "avx2", "fma", "avx512f") if f in flags]
    return model, " ".join(simd) or "unknown", "hypervisor" in flags


def _memory() -> str:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                return f"{int(line.split()[1]) / 1024**2:.1f} GiB"
    except (OSError, ValueError):
        pass
    return "unknown"


def _os() -> str:
    name = platform.system()
    try:
        for line in Path("/etc/os-release").read_text().splitlines():
            if line.startswith("PRETTY_NAME="):
                name = line.split("=", 1)[1].strip('"')
    except OSError:
        pass
    return f"{name}, kernel {platform.release()} ({platform.machine()})"


def machine(version: str) -> dict[str, str]:
    """The machine and build a report was measured on (``version``: shadelab_rs's)."""
    model, simd, virtual = _cpuinfo()
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    commit = run(["git", "rev-parse", "--short", "HEAD"])
    changed = run(["git", "diff", "--name-only", "HEAD"])
    if commit != "unknown" and changed != "unknown":
        # Top-level entries with uncommitted changes, so a reader sees whether the renderer
        # itself (crates/, python/) differed from the commit.
        dirty = sorted({name.split("/")[0] for name in changed.splitlines()})
        commit += f" (uncommitted changes in: {', '.join(dirty)})"
    return {
        "CPU": model + (" (virtual machine)" if virtual else ""),
        "CPU SIMD flags": simd,
        "logical cores": f"{os.cpu_count()} ({usable} usable by this process)",
        "memory": _memory(),
        "OS": _os(),
        "rustc": run(["rustc", "-V"]),
        "Python": platform.python_version(),
        "NumPy": _numpy_version(),
        "shadelab_rs": version,
        "source tree (git)": commit,
    }


def write_csv(path: Path, rows: list[dict[str, Any]]) -> None:
    """``rows`` (dicts with the same keys) as a CSV file with a header."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def write_section(path: Path, text: str, marker: str | None = None) -> None:
    """Writes ``text`` to ``path``; with ``marker`` (the first line of ``text``), only
    replaces what follows ``marker`` in the file, keeping the report of another script
    above it."""
    old = path.read_text() if marker is not None and path.exists() else ""
    old = old.split(marker)[0].rstrip() + "\n\n" if old and marker else ""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(old + text)
