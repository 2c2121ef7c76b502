"""The benchmark's ground truth (shadelab_ref.truth) and its error figures (shadelab_ref.errors).

The analytic sphere and plane are checked against independent geometry and against the
float64 reference rasterizer (shadelab_ref.reference): a plane is exactly a two-triangle mesh, so
the two must agree to float64 rounding; a sphere is the limit of ever finer tessellations, so
the reference's error against it must shrink towards zero as the mesh is refined.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from shadelab_ref import errors, truth
from shadelab_ref import reference as ref

GOLD = ref.Material(
    (0.24725, 0.1995, 0.0745), (0.75164, 0.60648, 0.22648), (0.628281, 0.555802, 0.366065), 51.2
)
LIGHTS = [
    ref.DirectionalLight((-1.0, -1.0, -1.0)),
    ref.PointLight((2.0, 3.0, 4.0), (0.4, 0.4, 0.5)),
]
CAM = ref.Camera(eye=(0.8, 0.6, 3.0), target=(0, 0, 0), up=(0, 1, 0), fov_y=45.0)


# ------------------------------------------------------------------------------ error figures


def _blank(h=4, w=5):
    return np.zeros((h, w, 3), np.uint8), np.zeros((h, w), bool)


def test_identical_images_have_zero_error():
    img = np.random.default_rng(1).integers(0, 256, (6, 7, 3), dtype=np.uint8)
    mask = np.ones((6, 7), bool)
    lin = img / 255.0
    e = errors.error_figures(img, mask, img, mask, test_linear=lin, ref_linear=lin)
    assert (e.n_both, e.rmse_levels, e.max_levels, e.share_gt0) == (42, 0.0, 0, 0.0)
    assert (e.rmse_linear, e.max_linear, e.only_test, e.only_ref) == (0.0, 0.0, 0, 0)
    assert e.silhouette_share == 0.0


def test_error_figures_by_hand():
    t, tm = _blank()
    r, rm = _blank()
    tm[:2] = rm[:2] = True  # 10 pixels in both
    tm[2, 0] = True  # one only in the test image
    rm[3, :2] = True  # two only in the reference
    t[0, 0] = (3, 0, 0)  # > 1 level
    t[0, 1] = (0, 9, 1)  # > 8 levels
    t[1, 4] = (1, 1, 1)  # 1 level: not > 1
    t[2, 0] = (255, 255, 255)  # outside the common coverage: ignored by the colour figures
    e = errors.error_figures(t, tm, r, rm)
    assert e.n_both == 10
    assert e.max_levels == 9
    assert e.rmse_levels == pytest.approx(math.sqrt((9 + 81 + 1 + 3) / 30))
    assert (e.share_gt0, e.share_gt1, e.share_gt8) == (0.3, 0.2, 0.1)
    assert (e.only_test, e.only_ref) == (1, 2)
    assert e.silhouette_share == pytest.approx(3 / 13)
    assert math.isnan(e.rmse_linear) and math.isnan(e.max_linear)


def test_error_figures_linear_and_region():
    t, m = _blank(2, 2)
    m[:] = True
    tl = np.zeros((2, 2, 3))
    rl = np.zeros((2, 2, 3))
    tl[0, 0, 0] = 0.3
    tl[1, 1, 2] = -2.0  # unclamped values count as they are
    region = np.array([[True, True], [True, False]])
    e = errors.error_figures(t, m, t, m, test_linear=tl, ref_linear=rl, region=region)
    assert e.n_both == 3
    assert e.max_linear == pytest.approx(0.3)
    assert e.rmse_linear == pytest.approx(math.sqrt(0.09 / 9))


def test_error_figures_reject_bad_input():
    t, m = _blank()
    with pytest.raises(ValueError, match="both be"):
        errors.error_figures(t, m, t[:, :3], m)
    with pytest.raises(ValueError, match="uint8"):
        errors.error_figures(t.astype(np.float32), m, t, m)
    with pytest.raises(ValueError, match="test_mask"):
        errors.error_figures(t, m[:2], t, m)
    with pytest.raises(ValueError, match="both linear"):
        errors.error_figures(t, m, t, m, test_linear=t / 255.0)


def test_empty_overlap_gives_nan_colour_figures():
    t, m = _blank()
    r, rm = _blank()
    m[0, 0] = True
    e = errors.error_figures(t, m, r, rm)
    assert e.n_both == 0 and math.isnan(e.rmse_levels) and e.silhouette_share == 1.0


# ------------------------------------------------------------------------------ analytic truth


def test_sphere_truth_geometry_on_axis():
    """Camera on the z axis: the centre pixel (odd size) hits the sphere at depth D - 1, and
    a pixel is covered exactly when its ray is within asin(1/D) of the axis."""
    d, size = 4.0, 65
    cam = ref.Camera(eye=(0, 0, d), target=(0, 0, 0), up=(0, 1, 0), fov_y=40.0)
    tr = truth.sphere_truth(camera=cam, width=size, height=size, material=GOLD, lights=LIGHTS)
    assert tr.depth[size // 2, size // 2] == pytest.approx(d - 1.0, abs=1e-12)
    _, direction = ref.pixel_rays(cam, size, size)
    cos_axis = 1.0 / np.linalg.norm(direction, axis=-1)  # directions have z = -1
    inside = cos_axis >= math.cos(math.asin(1.0 / d))
    np.testing.assert_array_equal(tr.mask, inside)
    assert np.all(np.isinf(tr.depth[~tr.mask]))
    assert np.all(tr.color[~tr.mask] == 0.0)


def test_plane_truth_matches_reference_of_a_quad():
    """A plane is exactly two triangles: the analytic plane and the float64 rasterizer of a
    big quad with the plane's normal agree to rounding wherever the quad is seen."""
    cam = ref.Camera(eye=(0.3, 1.5, 2.0), target=(0.0, -1.0, -3.0), up=(0, 1, 0), near=0.5, far=30)
    v = np.array([[-20, -1, -20], [20, -1, -20], [20, -1, 20], [-20, -1, 20]], np.float64)
    f = np.array([[0, 3, 2], [0, 2, 1]])  # counter-clockwise seen from +y
    n = np.tile([0.0, 1.0, 0.0], (4, 1))
    kw = dict(camera=cam, width=80, height=60, material=GOLD, lights=LIGHTS)
    r = ref.render_reference(v, f, normals=n, shading="phong", **kw)
    tr = truth.plane_truth(point=(0, -1, 0), normal=(0, 2, 0), **kw)
    assert r.mask.sum() > 1000
    assert np.all(tr.mask[r.mask])
    np.testing.assert_allclose(tr.color[r.mask], r.color[r.mask], rtol=0, atol=1e-9)
    np.testing.assert_allclose(tr.depth[r.mask], r.depth[r.mask], rtol=1e-12)


@pytest.fixture(scope="module")
def sphere_truth_96():
    return truth.sphere_truth(camera=CAM, width=96, height=96, material=GOLD, lights=LIGHTS)


def _tessellation_error(n, shading, tr):
    v, f = ref.uv_sphere(n, 2 * n)
    r = ref.render_reference(
        v, f, camera=CAM, width=96, height=96, material=GOLD, lights=LIGHTS, normals=v,
        shading=shading,
    )  # fmt: skip
    return errors.error_figures(
        ref.to_uint8(r.color), r.mask, tr.u8, tr.mask, test_linear=r.color, ref_linear=tr.color
    )


def test_fine_tessellation_converges_to_the_analytic_sphere(sphere_truth_96):
    """Phong on ever finer exact-normal tessellations (float64 reference) approaches the
    analytic image: the error falls with every refinement, and at 65 k triangles (a triangle
    spans about a third of a pixel here) it is down to rounding."""
    figs = [_tessellation_error(n, "phong", sphere_truth_96) for n in (8, 32, 128)]
    rmse = [e.rmse_levels for e in figs]
    assert rmse[0] > rmse[1] > rmse[2]
    fine = figs[-1]
    assert fine.rmse_levels < 0.25 and fine.max_levels <= 1
    assert fine.rmse_linear < 2e-4
    # The inscribed mesh is a hair smaller than the sphere: it never covers more.
    assert fine.only_test == 0 and fine.silhouette_share < 0.01


def test_shading_modes_rank_by_error(sphere_truth_96):
    """At a coarse tessellation, flat > Gouraud > Phong in error against the truth."""
    rmse = [_tessellation_error(12, s, sphere_truth_96).rmse_levels for s in ("flat", "gouraud")]
    rmse.append(_tessellation_error(12, "phong", sphere_truth_96).rmse_levels)
    assert rmse[0] > rmse[1] > rmse[2]
