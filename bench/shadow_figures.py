#!/usr/bin/env python3
"""Shadow accuracy per technique against the float64 reference's exact ray casts, on the
scenes of tests/test_shadows.py (their figures and definitions), as the Markdown table of
docs/LIGHTING.md's shadows section, with each technique's render time at 800 x 600.

    python bench/shadow_figures.py            # PYTHONPATH=. (make does it)
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import shadelab_rs as sl
from harness import test_module

ROOT = Path(__file__).resolve().parent.parent
t = test_module("test_shadows")

TECHNIQUES = {
    '"exact"': "exact",
    "True (2048, PCF 3)": True,
    '2048, "none"': sl.ShadowSettings(2048, "none"),
    "2048, PCF 5": sl.ShadowSettings(2048, "pcf", 5),
    "512, PCF 3": sl.ShadowSettings(512, "pcf", 3),
    "4096, PCF 3": sl.ShadowSettings(4096, "pcf", 3),
    "2048, PCF 3, 3 cascades": sl.ShadowSettings(2048, "pcf", 3, cascades=3),
}


def ms(case, shadows) -> float:
    """Median wall time of three 800 x 600 renders, in milliseconds."""
    times = []
    for _ in range(3):
        t0 = time.perf_counter()
        t.render(case, shadows, (800, 600))
        times.append((time.perf_counter() - t0) * 1e3)
    return statistics.median(times)


def main() -> int:
    print("| scene | shadows= | mismatch | max dist (px) | acne | leak | ms at 800x600 |")
    print("|---|---|---|---|---|---|---|")
    for case in [*t.HARD, t.WIDE]:
        base = ms(case, False)
        for label, shadows in TECHNIQUES.items():
            f = t.shadow_figures(case, shadows)
            print(
                f"| {case.label} | {label} | {100 * f['mismatch']:.3f} % | {f['max_dist']:.1f} "
                f"| {f['acne']} | {f['leak']} | {ms(case, shadows):.1f} (none: {base:.1f}) |"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
