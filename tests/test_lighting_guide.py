"""The lighting guide: its image script runs and draws every figure, and the committed guide
and images match it (docs/LIGHTING.md, docs/lighting/*.png). Not a timing test."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

ROOT = Path(__file__).resolve().parent.parent
SCRIPT = ROOT / "docs" / "lighting" / "make_images.py"
GUIDE = ROOT / "docs" / "LIGHTING.md"


@pytest.fixture(scope="module")
def script():
    spec = importlib.util.spec_from_file_location("make_lighting_images", SCRIPT)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    # Registered first: dataclasses look their module up in sys.modules.
    sys.modules[spec.name] = mod
    try:
        spec.loader.exec_module(mod)
        yield mod
    finally:
        sys.modules.pop(spec.name, None)


def test_script_writes_every_image(script, tmp_path: Path) -> None:
    # A quarter of the panel size: every scene is built and rendered, in about a second.
    assert script.main(["--out", str(tmp_path), "--scale", "0.25"]) == 0
    written = sorted(p.stem for p in tmp_path.glob("*.png"))
    assert written == sorted(script.names())
    for p in tmp_path.glob("*.png"):
        img = np.asarray(Image.open(p).convert("RGB"))
        assert img.shape[0] >= 16 and img.shape[1] >= 16, p.name
        # Non-trivial: many distinct colours, and something brighter than the background.
        assert len(np.unique(img.reshape(-1, 3), axis=0)) > 50, p.name
        assert img.max() > 100, p.name


def test_unknown_figure_is_an_error(script, tmp_path: Path) -> None:
    with pytest.raises(SystemExit):
        script.main(["--out", str(tmp_path), "--only", "no-such-figure"])


def test_guide_shows_every_committed_image(script) -> None:
    text = GUIDE.read_text(encoding="utf-8")
    linked = set(re.findall(r"\]\(lighting/([\w-]+)\.png\)", text))
    assert linked == set(script.names())
    for name in linked:
        png = ROOT / "docs" / "lighting" / f"{name}.png"
        assert png.is_file(), png
        assert png.stat().st_size < 600_000, f"{png} is not kept small"
    total = sum(p.stat().st_size for p in (ROOT / "docs" / "lighting").glob("*.png"))
    assert total < 3_000_000
