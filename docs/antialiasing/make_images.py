"""Pictures of anti-aliasing for the user guide ("Anti-aliasing"): run from the repository
root after `make build` (`make docs-images` runs it). Writes docs/antialiasing/*.png, each
made by the call named in its caption (docs/antialiasing/captions.md):

- edges.png: a crop of the demo scene, enlarged 4x without smoothing, at samples 1, 4, 16
  and supersample 4;
- alpha.png: the demo scene rendered with alpha=True and samples=8, composited over a
  checkerboard (premultiplied: rgb + (1 - alpha) * checker).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shadelab_rs as sl

HERE = Path(__file__).parent
W, H = 480, 360
CROP = (slice(100, 190), slice(40, 160))  # rows, columns: a cow's back and the floor edge
ZOOM = 4

PANELS = [
    ("samples=1", {}),
    ("samples=4", {"samples": 4}),
    ("samples=16", {"samples": 16}),
    ("supersample=4", {"supersample": 4}),
]


def main() -> None:
    scene, cam = sl.demo_scene()
    crops = []
    for _, kw in PANELS:
        img = sl.render(scene, cam, W, H, encoding="srgb", **kw)
        crop = img[CROP]
        crops.append(np.repeat(np.repeat(crop, ZOOM, 0), ZOOM, 1))
    gap = np.full((crops[0].shape[0], 6, 3), 255, np.uint8)
    row = np.concatenate([x for c in crops for x in (c, gap)][:-1], 1)
    sl.save_image(row, HERE / "edges.png", compression="high")

    rgba = sl.render(scene, cam, W, H, dtype="float32", alpha=True, samples=8)
    yy, xx = np.mgrid[0:H, 0:W]
    checker = np.where(((yy // 16) + (xx // 16)) % 2 == 0, 0.85, 0.55).astype(np.float32)
    over = rgba[..., :3] + (1 - rgba[..., 3:]) * checker[..., None]
    sl.save_image(
        np.floor(sl.srgb_encode(over) * 255 + 0.5).astype(np.uint8),
        HERE / "alpha.png",
        compression="high",
    )

    lines = [
        "# Anti-aliasing pictures",
        "",
        "Made by `docs/antialiasing/make_images.py` (`make docs-images`).",
        "",
        f"- `edges.png`: rows {CROP[0].start}-{CROP[0].stop}, columns {CROP[1].start}-"
        f"{CROP[1].stop} of `sl.render(*sl.demo_scene(), {W}, {H}, encoding='srgb', ...)` "
        f"enlarged {ZOOM}x without smoothing, left to right: "
        + ", ".join(f"`{name}`" for name, _ in PANELS)
        + ".",
        f"- `alpha.png`: `sl.render(*sl.demo_scene(), {W}, {H}, dtype='float32', alpha=True, "
        "samples=8)` composited over a checkerboard as `rgb + (1 - alpha) * checker`, then "
        "sRGB-encoded.",
        "",
    ]
    (HERE / "captions.md").write_text("\n".join(lines))
    print(f"wrote {HERE}/edges.png, alpha.png, captions.md")


if __name__ == "__main__":
    main()
