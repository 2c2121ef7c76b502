"""The one function that measures an image's error against a reference image.

Every error figure in the speed–error report, the peer comparison and the tests comes from
:func:`error_figures`, so they are all defined the same way:

* Colour is compared only where **both** images cover the pixel. 8-bit figures use the uint8
  images (``round(clamp(c, 0, 1) * 255)``); linear figures use the unclamped float colours.
* RMSE is over every channel of those pixels; max is the largest channel difference; the
  ``share_gt0`` / ``share_gt1`` / ``share_gt8`` figures are the shares of those pixels whose
  largest channel difference exceeds 0 / 1 / 8 levels.
* Silhouette mismatch (covered by one image only) is counted separately and never enters
  the colour figures.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

__all__ = ["ErrorFigures", "error_figures", "to_uint8"]


def to_uint8(img: np.ndarray) -> np.ndarray:
    """Linear colour to uint8 as the renderer stores it: ``floor(clip(c, 0, 1) * 255 + 0.5)``."""
    a = np.clip(np.asarray(img, dtype=np.float64), 0.0, 1.0)
    return np.floor(a * 255.0 + 0.5).astype(np.uint8)


@dataclass(frozen=True)
class ErrorFigures:
    """Error of a test image against a reference image (see the module docstring)."""

    n_both: int  # pixels covered by both images: the colour figures are over these
    rmse_levels: float
    max_levels: int
    share_gt0: float  # of n_both: any channel differs
    share_gt1: float  # of n_both: largest channel difference > 1 level
    share_gt8: float  # of n_both: largest channel difference > 8 levels
    rmse_linear: float  # NaN when no linear colours were given
    max_linear: float
    only_test: int  # covered by the test image only
    only_ref: int  # covered by the reference only
    silhouette_share: float  # (only_test + only_ref) / pixels covered by either

    def as_dict(self) -> dict[str, float]:
        """The figures as a flat dict (for CSV rows)."""
        return asdict(self)


def error_figures(
    test_u8: np.ndarray,
    test_mask: np.ndarray,
    ref_u8: np.ndarray,
    ref_mask: np.ndarray,
    *,
    test_linear: np.ndarray | None = None,
    ref_linear: np.ndarray | None = None,
    region: np.ndarray | None = None,
) -> ErrorFigures:
    """Error figures of ``test`` against ``ref``.

    Args:
        test_u8, ref_u8: ``(H, W, 3)`` uint8 images.
        test_mask, ref_mask: ``(H, W)`` bool coverage.
        test_linear, ref_linear: optional ``(H, W, 3)`` unclamped linear colours (both or
            neither) for the linear figures.
        region: optional ``(H, W)`` bool restricting the colour comparison (e.g. pixels away
            from triangle edges); the silhouette counts ignore it.

    Raises:
        ValueError: on mismatched shapes or dtypes, or only one linear image.
    """
    shape = np.shape(ref_u8)
    if len(shape) != 3 or shape[2] != 3 or np.shape(test_u8) != shape:
        raise ValueError(f"images must both be (H, W, 3), got {np.shape(test_u8)} and {shape}")
    if np.asarray(test_u8).dtype != np.uint8 or np.asarray(ref_u8).dtype != np.uint8:
        raise ValueError("test_u8 and ref_u8 must be uint8 images")
    for name, m in (("test_mask", test_mask), ("ref_mask", ref_mask), ("region", region)):
        if m is not None and np.shape(m) != shape[:2]:
            raise ValueError(f"{name} must have shape {shape[:2]}, got {np.shape(m)}")
    if (test_linear is None) != (ref_linear is None):
        raise ValueError("give both linear images or neither")
    tm, rm = np.asarray(test_mask, dtype=bool), np.asarray(ref_mask, dtype=bool)
    both = tm & rm
    if region is not None:
        both &= np.asarray(region, dtype=bool)
    n = int(both.sum())
    d8 = np.abs(np.asarray(test_u8, np.int16)[both] - np.asarray(ref_u8, np.int16)[both])
    worst = d8.max(axis=1) if n else np.zeros(0, np.int16)
    nan = float("nan")
    rmse_lin = max_lin = nan
    if test_linear is not None and n:
        dl = np.asarray(test_linear, np.float64)[both] - np.asarray(ref_linear, np.float64)[both]
        rmse_lin = float(np.sqrt(np.mean(dl * dl)))
        max_lin = float(np.abs(dl).max())
    only_t, only_r = int((tm & ~rm).sum()), int((rm & ~tm).sum())
    union = int((tm | rm).sum())
    return ErrorFigures(
        n_both=n,
        rmse_levels=float(np.sqrt(np.mean(d8.astype(np.float64) ** 2))) if n else nan,
        max_levels=int(worst.max()) if n else 0,
        share_gt0=float(np.mean(worst > 0)) if n else nan,
        share_gt1=float(np.mean(worst > 1)) if n else nan,
        share_gt8=float(np.mean(worst > 8)) if n else nan,
        rmse_linear=rmse_lin,
        max_linear=max_lin,
        only_test=only_t,
        only_ref=only_r,
        silhouette_share=(only_t + only_r) / union if union else 0.0,
    )
