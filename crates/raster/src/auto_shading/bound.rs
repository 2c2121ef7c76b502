//! The shading error of one triangle under one light, from what is known before shading.
//!
//! Everything is in angles: how far the lighting's arguments (the normal against the light
//! direction `l` and against the half vector `h`) move across the triangle, and how fast the
//! diffuse `cos θ` and the specular lobe `cos^f β` change with them. The derivation is in
//! docs/LIGHTING.md ("How `shading="auto"` estimates the error"); the names here follow it.

use std::f64::consts::FRAC_PI_2;

use crate::lighting::pow01;
use crate::trig;

/// How the lighting's arguments vary over one triangle (radians).
#[derive(Debug, Clone, Copy)]
pub(super) struct Spread {
    /// Angle between the light direction and the centroid's normal.
    pub theta: f64,
    /// How far `θ` moves over the triangle: the normal spread plus the angle the triangle
    /// subtends from a point light.
    pub span_d: f64,
    /// Σ over the three edges of the square of how far `θ` moves along each.
    pub edges_d: f64,
    /// The same for the part of each edge's motion along the diffuse term's gradient (the
    /// direction in which `θ` changes): what a linear field's deviation depends on.
    pub along_d: f64,
    /// Angle between the half vector and the centroid's normal.
    pub beta: f64,
    /// How far `β` moves: the normal spread plus half the angles the triangle subtends from
    /// the light and from the eye.
    pub span_s: f64,
    /// Σ over the three edges of the square of how far `β` moves along each, split into the
    /// parts along the lobe's gradient (radially from the highlight's centre) and across it:
    /// the lobe's curvature differs in the two directions.
    pub along_s: f64,
    pub across_s: f64,
    /// How far (rad) the face normal, which flat shades with, is from the centroid's normal,
    /// along the diffuse and the lobe's gradients: on a sphere the face normal is the
    /// circumcentre's, a sixth of the legs off the centroid on a right triangle.
    pub face_d: f64,
    pub face_s: f64,
    /// The geometric normal error every mode shares: the rms angle between the normal the
    /// mesh gives a pixel and the true surface's normal where that pixel's ray meets it.
    pub geometric: f64,
    /// The largest such angle anywhere on the triangle (for the colour's range).
    pub geometric_max: f64,
}

/// Per unit of the light's diffuse and specular amplitudes (`kd·Id·att`, `ks·Is·att`), the
/// rms error of each mode over the triangle, linear colour.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Sensitivity {
    pub flat: [f64; 2],
    pub gouraud: [f64; 2],
    pub phong: [f64; 2],
}

/// The range over one triangle of the diffuse factor `max(cos θ, 0)` and of the lobe
/// `cos^f β` (0 when there is no specular term), each `[low, high]`: what the colour can be
/// anywhere on the triangle, for the clamping and float-rounding terms.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Range {
    pub diffuse: [f64; 2],
    pub specular: [f64; 2],
    /// Whether the lighting is smooth on the triangle's scale: no terminator inside it (the
    /// kink of `max(cos θ, 0)` and the lobe's step there), and a lobe absent, negligible or
    /// at least as wide (half width at half maximum) as the triangle's turn in `β`. Only
    /// then does [`super::nodal`]'s seven-point interpolant stand for the error.
    pub smooth: bool,
    /// Whether the lobe alone is smooth (absent, negligible or wide enough, as above): where
    /// only the terminator is not, [`super::nodal`]'s fine grid stands for the error.
    pub lobe_smooth: bool,
}

/// The lobe's half width at half maximum, `acos(2^(−1/f))`: once per object (an `acos` and a
/// power per triangle and light otherwise).
pub(super) fn lobe_half_width(f: f64) -> f64 {
    (0.5f64.powf(1.0 / f)).acos()
}

/// The specular lobe `S(β) = cos^f β` (0 beyond 90°).
fn lobe(f: f64, beta: f64) -> f64 {
    if beta >= FRAC_PI_2 {
        0.0
    } else {
        power(trig::cos(beta), f)
    }
}

/// `c^e` for `c` in [0, 1]: the renderer's own `pow01` for `e ≥ 0` (relative error below
/// 2·10⁻⁵ for the exponents of real materials, absolute below 10⁻⁶ at any: far below what
/// moves an estimate, and no libm call), `powf` for a negative one.
#[inline]
fn power(c: f64, e: f64) -> f64 {
    if e >= 0.0 {
        pow01(c as f32, e as f32) as f64
    } else {
        c.powf(e)
    }
}

/// The lobe `S = (n·h)^f` as a function of the normal on the unit sphere: its slope
/// `|dS/dβ| = f cos^(f−1) β sin β` (radial: toward or away from `h`), and its Hessian's
/// magnitudes radially, `|f(f−1) cos^(f−2) β sin² β − f cos^f β|`, and across, `f cos^f β`
/// (the Hessian of `c = n·h` on the sphere is `−c·I`, so that of `c^f` is
/// `f(f−1)c^(f−2)∇c∇cᵀ − f c^f I`, `|∇c| = sin β`), from one power.
fn lobe_derivatives(f: f64, beta: f64) -> [f64; 3] {
    if beta >= FRAC_PI_2 || f == 0.0 {
        return [0.0; 3];
    }
    let (s, c) = (trig::sin(beta), trig::cos(beta));
    let p = power(c, f - 2.0);
    [
        f * p * c * s,
        (f * (f - 1.0) * p * s * s - f * p * c * c).abs(),
        f * p * c * c,
    ]
}

/// Mean of `g` over `[lo, hi]` by Simpson's rule on four intervals (one point when the
/// interval is a small share of the lobe's half width `w`, where `g` is nearly constant).
fn mean_over(lo: f64, hi: f64, w: f64, g: impl Fn(f64) -> [f64; 3]) -> [f64; 3] {
    if hi - lo <= 0.05 * w {
        return g(0.5 * (lo + hi));
    }
    let mut acc = [0.0; 3];
    for (k, wt) in [1.0, 4.0, 2.0, 4.0, 1.0].into_iter().enumerate() {
        let v = g(lo + (hi - lo) * k as f64 / 4.0);
        for i in 0..3 {
            acc[i] += wt * v[i];
        }
    }
    acc.map(|a| a / 12.0)
}

/// The mean of the lobe's slope `|dS/dβ|` over `[lo, hi]`: `(S(lo) − S(hi))/(hi − lo)`
/// exactly (the lobe falls monotonically on `[0, π/2]`), the slope at the middle where the
/// interval is a small share of the half width `w` (the difference would cancel).
fn mean_slope(f: f64, lo: f64, hi: f64, w: f64) -> f64 {
    if hi - lo <= 0.05 * w {
        lobe_derivatives(f, 0.5 * (lo + hi))[0]
    } else {
        (lobe(f, lo) - lobe(f, hi)) / (hi - lo)
    }
}

/// How many lobe half widths (at half maximum) a triangle's turn in `β` may span for the
/// lobe to count as smooth on it ([`Range::smooth`]). Checked numerically over random
/// triangles and highlight positions (docs/LIGHTING.md): within 1.5 half widths the
/// seven-point interpolant's rms error summed over triangles is 1.0 to 1.05 times the true
/// one; a single triangle can be as low as 0.5, which the sampling margin covers.
const SMOOTH_SPAN: f64 = 1.5;

/// The centroid lies within 2/3 of the longest edge of every point of a triangle (its
/// medians are at most as long as... the longest edge times √3/2, and it sits at 2/3 of
/// each), so an argument that moves by `span` across the triangle stays within this of its
/// centroid value.
const REACH: f64 = 2.0 / 3.0;

/// The rms of the linear-interpolation error of a quadratic over a triangle over its mean
/// (the error is `½L''(ρ² − |x − o|²)`, of mean `L''(a² + b² + c²)/24`): 1.03 for an
/// equilateral triangle, 1.05 for a right isosceles one, rising to `√1.2 ≈ 1.0954` for a
/// sliver (where it is a parabola's); the same for an anisotropic quadratic, which an affine
/// map takes to an isotropic one without changing the ratio.
pub(super) const RMS_OVER_MEAN: f64 = 1.0955;

/// The rms error of flat, Gouraud and Phong over a triangle with spread `s` under a light
/// whose specular lobe has exponent `f` and half width `w` (`None`: no specular term), per
/// unit amplitude; and the range of the lighting factors over the triangle.
/// `interp`: also the flat and Gouraud interpolation terms (otherwise zero: the caller has
/// them from [`super::nodal`]).
pub(super) fn sensitivity(
    s: &Spread,
    lobe_fw: Option<(f64, f64)>,
    interp: bool,
) -> (Sensitivity, Range) {
    // Unlit over the whole triangle: no diffuse or specular anywhere, no error.
    if s.theta - REACH * s.span_d - s.geometric_max >= FRAC_PI_2 {
        let range = Range {
            smooth: true,
            lobe_smooth: true,
            ..Range::default()
        };
        return (Sensitivity::default(), range);
    }
    // Diffuse `max(cos θ, 0)`: slope `sin θ ≤ 1`, curvature `cos θ ≤ 1`.
    let (lo_d, hi_d) = (
        (s.theta - REACH * s.span_d).max(0.0),
        s.theta + REACH * s.span_d,
    );
    let slope_d = trig::sin(hi_d.min(FRAC_PI_2));
    // Linear interpolation of a quadratic with curvature L'' over a triangle with edges
    // a, b, c errs by ½L''(ρ² − |x − o|²) (o, ρ: circumcentre and radius), whose mean is
    // L''(a² + b² + c²)/24; its rms is at most RMS_OVER_MEAN times that. Across the terminator
    // the kink of `max(cos θ, 0)` (unit slope) leaves a tent of height ≤ span/4 along the
    // gradient, of rms ≤ (span/4)/√3 < span/7.
    let interp_d = if hi_d > FRAC_PI_2 {
        s.span_d / 7.0
    } else {
        trig::cos(lo_d) * s.edges_d * RMS_OVER_MEAN / 24.0
    };
    // Flat: the rms deviation of a field linear over the triangle (gradient g) from its
    // value at the centroid is √(gᵀMg), M = Σ_k e_k e_kᵀ/36 the triangle's second moment
    // about its centroid (e_k its edges): |g|·√(Σ_k (ĝ·e_k)²)/6, the edges' components
    // along the gradient only.
    // The face normal's offset adds a constant, which a zero-mean linear deviation adds to
    // in quadrature; the curvature adds at most L''·Σ/72 (the mean of ½|x − c|²L'').
    let flat_d = slope_d * (s.along_d / 36.0 + s.face_d * s.face_d).sqrt() + s.edges_d / 72.0;
    let geo_d = slope_d * s.geometric;
    let mut out = Sensitivity {
        flat: [flat_d + geo_d, 0.0],
        gouraud: [interp_d + geo_d, 0.0],
        phong: [geo_d, 0.0],
    };
    // Where the true surface's normal can be: the mesh's range widened by the largest
    // geometric normal error.
    let mut range = Range {
        diffuse: [
            trig::cos((hi_d + s.geometric_max).min(FRAC_PI_2)),
            trig::cos((lo_d - s.geometric_max).max(0.0)),
        ],
        specular: [0.0, 0.0],
        smooth: hi_d + s.geometric_max < FRAC_PI_2,
        lobe_smooth: true,
    };
    let Some((f, w)) = lobe_fw.filter(|(f, _)| f.is_finite() && *f > 0.0) else {
        return (out, range);
    };
    let (lo, hi) = (
        (s.beta - REACH * s.span_s).max(0.0),
        (s.beta + REACH * s.span_s).min(FRAC_PI_2),
    );
    if lo >= FRAC_PI_2 {
        return (out, range);
    }
    let top = lobe(f, (lo - s.geometric_max).max(0.0));
    // The specular step at n·l = 0 is not modelled (LIGHTING.md), so the lobe's low end is
    // 0 wherever the triangle may be unlit.
    let bottom = if hi_d + s.geometric_max < FRAC_PI_2 {
        lobe(f, (hi + s.geometric_max).min(FRAC_PI_2))
    } else {
        0.0
    };
    range.specular = [bottom, top];
    range.lobe_smooth = top < 1e-6 || s.span_s <= SMOOTH_SPAN * w;
    range.smooth &= range.lobe_smooth;
    // Every mode's colour and the truth's lie in [bottom, top]: a lobe that small over the
    // whole triangle errs by at most its height, and its derivatives need not be evaluated.
    if top < 1e-6 {
        out.flat[1] = top;
        out.gouraud[1] = top;
        out.phong[1] = top;
        return (out, range);
    }
    // The lobe's slope and curvature vary across a triangle near the highlight by far more
    // than the diffuse term's: the interpolation error at a point is a kernel-weighted
    // average of the curvature over the triangle, so its mean over the triangle's range of
    // β stands for L'' (exact for a constant curvature), and likewise the slope for flat.
    if !interp {
        // The slope's mean over [lo, hi] is exact from the lobe's ends (it is monotonic).
        let slope = mean_slope(f, lo, hi, w);
        let geo_s = slope * s.geometric;
        out.flat[1] = geo_s;
        out.gouraud[1] = geo_s;
        out.phong[1] = geo_s;
        return (out, range);
    }
    let [_, radial, across] = mean_over(lo, hi, w, |b| lobe_derivatives(f, b));
    let slope = mean_slope(f, lo, hi, w);
    // A highlight narrower than the triangle's spread: the lobe covers a share of about
    // (2w/span)² of it (w its half width at half maximum), so the rms of an error as large
    // as the lobe's whole range over it is that range times min(1, 2w/span).
    let span_range = lobe(f, lo) - lobe(f, hi);
    let missed = span_range * (2.0 * w / s.span_s.max(1e-12)).min(1.0);
    let geo_s = slope * s.geometric;
    // Gouraud: the interpolation error's mean is Σ_k e_kᵀHe_k/24, at most with |H|, whose
    // radial and across parts weigh the edges' components in those directions.
    let interp_s = (radial * s.along_s + across * s.across_s) * RMS_OVER_MEAN / 24.0;
    let flat_s = slope * (s.along_s / 36.0 + s.face_s * s.face_s).sqrt()
        + (radial * s.along_s + across * s.across_s) / 72.0;
    out.flat[1] = flat_s.min(missed) + geo_s;
    out.gouraud[1] = interp_s.min(missed) + geo_s;
    out.phong[1] = geo_s;
    (out, range)
}

/// The expected squared difference in 8-bit levels of two images whose exact colours differ
/// by `e` levels (rms): `e²` plus the rounding of both to whole levels, which differs at a
/// pixel with probability about `|e|` for `|e| < 1` and adds at most 1/4 beyond.
pub(super) fn quantized_square(e: f64) -> f64 {
    e * e + e.min(0.25)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spread(span: f64, beta: f64) -> Spread {
        Spread {
            theta: 0.3,
            span_d: span,
            edges_d: 2.0 * span * span,
            along_d: 2.0 * span * span,
            beta,
            span_s: span,
            along_s: 2.0 * span * span,
            across_s: 2.0 * span * span,
            face_d: 0.0,
            face_s: 0.0,
            geometric: 0.0,
            geometric_max: 0.0,
        }
    }

    #[test]
    fn a_flat_triangle_under_a_directional_light_has_no_error() {
        let (s, _) = sensitivity(&spread(0.0, 0.2), Some((50.0, lobe_half_width(50.0))), true);
        assert_eq!(s, Sensitivity::default());
    }

    #[test]
    fn modes_are_ordered_and_shrink_with_the_spread() {
        let mut last = f64::INFINITY;
        for span in [0.4, 0.2, 0.1, 0.05, 0.01] {
            let (s, _) = sensitivity(
                &spread(span, 0.3),
                Some((30.0, lobe_half_width(30.0))),
                true,
            );
            for k in 0..2 {
                assert!(
                    s.phong[k] <= s.gouraud[k] && s.phong[k] <= s.flat[k],
                    "{s:?}"
                );
            }
            let total = s.gouraud[0] + s.gouraud[1];
            assert!(total < last, "{span}: {total} >= {last}");
            last = total;
        }
    }

    #[test]
    fn a_narrow_highlight_inside_a_wide_triangle_is_bounded_by_its_share() {
        // f = 10^4: the lobe is ~0.012 rad wide; a 0.5 rad triangle holding the peak can miss
        // it, and the bound is the lobe's range times its share, not the curvature's f·span².
        let w = lobe_half_width(1e4);
        let (s, _) = sensitivity(&spread(0.5, 0.0), Some((1e4, w)), true);
        assert!((s.gouraud[1] - 2.0 * w / 0.5).abs() < 1e-9, "{s:?}");
    }

    #[test]
    fn rounding_adds_at_most_a_quarter() {
        assert_eq!(quantized_square(0.0), 0.0);
        assert!((quantized_square(0.1) - 0.11).abs() < 1e-12);
        assert!((quantized_square(3.0) - 9.25).abs() < 1e-12);
    }
}
