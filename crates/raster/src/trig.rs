//! `acos`, `atan2`, `cos` and `sin` by short polynomials, where libm's correctly rounded
//! versions were a measurable share of the work and nothing needs their precision.
//!
//! - The shading estimate (`auto_shading`) takes about a dozen angles per evaluated
//!   triangle and light; libm's functions were an eighth of its instructions.
//! - An equirectangular environment look-up (`Environment::uv`) takes an `atan2` and an
//!   `acos` per direction, a pixel's share of the secondary stage at every mirror, glass and
//!   background pixel; libm's were about a sixth of that stage.
//!
//! These are within 3·10⁻⁸ rad (acos), 3·10⁻¹⁰ rad (atan2) and 10⁻⁸ (cos, sin) of libm
//! (tested below): an estimate does not move, and a look-up moves by under 10⁻⁵ of a texel
//! in a 4096-texel-wide image. They are plain arithmetic the compiler inlines.

use std::f64::consts::{FRAC_PI_2, PI};

/// `acos x` for `x` in [-1, 1] (clamped), within 3·10⁻⁸ rad (Abramowitz & Stegun 4.4.46:
/// `√(1 − x)` times a degree-7 polynomial on [0, 1], `π − acos(−x)` below 0). Exact at 1.
/// Branch-free: it vectorises over lanes.
#[inline(always)]
pub(crate) fn acos(x: f64) -> f64 {
    let x = x.clamp(-1.0, 1.0);
    let a = x.abs();
    let p = 1.570_796_305_0
        + a * (-0.214_598_801_6
            + a * (0.088_978_987_4
                + a * (-0.050_174_304_6
                    + a * (0.030_891_881_0
                        + a * (-0.017_088_125_6 + a * (0.006_670_090_1 + a * -0.001_262_491_1))))));
    let r = (1.0 - a).sqrt() * p;
    if x < 0.0 {
        PI - r
    } else {
        r
    }
}

/// `atan2(y, x)` (the angle of (x, y) in (−π, π], as [`f64::atan2`]) within 3·10⁻¹⁰ rad:
/// `atan t` for `t = min/max(|x|, |y|)` in [0, 1] as `t·P(t²)` (P of degree 10, a
/// Chebyshev fit of `atan(t)/t`), placed in its octant. Exact on the axes (0, ±π/2, ±π);
/// where both are zero, NaN or infinite, libm's.
pub(crate) fn atan2(y: f64, x: f64) -> f64 {
    if atan2_in_range(y, x) {
        atan2_core(y, x)
    } else {
        y.atan2(x)
    }
}

/// Whether [`atan2_core`] is [`atan2`] at (x, y): the larger magnitude is positive and
/// finite.
#[inline(always)]
pub(crate) fn atan2_in_range(y: f64, x: f64) -> bool {
    let hi = x.abs().max(y.abs());
    hi > 0.0 && hi < f64::INFINITY
}

/// [`atan2`] without its guard, branch-free (it vectorises over lanes): meaningless where
/// [`atan2_in_range`] is false.
#[inline(always)]
pub(crate) fn atan2_core(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = if ay > ax { (ax, ay) } else { (ay, ax) };
    let t = lo / hi;
    let z = t * t;
    // Horner's nest in two parts, the inner first (the same operations in the same order;
    // rustfmt 1.9 spins without end on the ten-deep nest written whole).
    let inner = -0.087_961_175_518_993_21
        + z * (0.067_101_139_777_195_1
            + z * (-0.044_273_668_127_761_47
                + z * (0.022_203_454_804_966_587
                    + z * (-0.007_166_164_849_440_387 + z * 0.001_084_492_742_330_726_7))));
    let p = 0.999_999_999_614_525_5
        + z * (-0.333_333_236_656_257
            + z * (0.199_995_958_541_454_38
                + z * (-0.142_790_484_166_020_05 + z * (0.110_537_847_515_686_38 + z * inner))));
    let a = t * p;
    let a = if ay > ax { FRAC_PI_2 - a } else { a };
    let a = if x.is_sign_negative() { PI - a } else { a };
    a.copysign(y)
}

/// `cos x` for `x` in [-π, π] (beyond it, libm's), within 10⁻⁸: the Taylor series to
/// `x¹²` on [0, π/2], `−cos(π − x)` above.
pub(crate) fn cos(x: f64) -> f64 {
    let a = x.abs();
    if a > PI {
        return x.cos();
    }
    let (a, sign) = if a > FRAC_PI_2 {
        (PI - a, -1.0)
    } else {
        (a, 1.0)
    };
    let z = a * a;
    let c = 1.0
        + z * (-1.0 / 2.0
            + z * (1.0 / 24.0
                + z * (-1.0 / 720.0
                    + z * (1.0 / 40_320.0
                        + z * (-1.0 / 3_628_800.0 + z * (1.0 / 479_001_600.0))))));
    sign * c
}

/// `sin x` for `x` in [-π/2, 3π/2] (beyond it, libm's), as `cos(π/2 − x)`, within 10⁻⁸.
pub(crate) fn sin(x: f64) -> f64 {
    cos(FRAC_PI_2 - x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn acos_is_within_its_bound_and_exact_at_the_ends() {
        let mut worst = 0.0f64;
        for k in -100_000..=100_000 {
            let x = k as f64 / 100_000.0;
            worst = worst.max((acos(x) - x.acos()).abs());
        }
        assert!(worst < 3e-8, "{worst}");
        assert_eq!(acos(1.0), 0.0);
        assert!((acos(-1.0) - PI).abs() < 3e-8);
        // Clamped like the callers' dot products of unit vectors.
        assert_eq!(acos(1.0 + 1e-12), 0.0);
        // Small angles keep their relative precision (the turns between close normals).
        let t: f64 = 1e-3;
        assert!((acos(t.cos()) / t - 1.0).abs() < 1e-4);
    }

    #[test]
    fn atan2_is_within_its_bound_and_exact_on_the_axes() {
        let mut worst = 0.0f64;
        for k in 0..400_000 {
            let a = -PI + (k as f64 + 0.5) / 400_000.0 * 2.0 * PI;
            for r in [1e-3, 1.0, 7.5] {
                let (y, x) = (r * a.sin(), r * a.cos());
                worst = worst.max((atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst < 3e-10, "{worst}");
        for (y, x) in [
            (0.0, 1.0),
            (-0.0, 1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (0.0, -0.0),
            (-0.0, 0.0),
            (2.0, -0.0),
            (f64::NAN, 1.0),
            (1.0, f64::INFINITY),
            (f64::INFINITY, f64::INFINITY),
        ] {
            let (got, want) = (atan2(y, x), y.atan2(x));
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "atan2({y}, {x}) = {got}, libm {want}"
            );
        }
    }

    #[test]
    fn cos_and_sin_are_within_their_bound() {
        let mut worst = 0.0f64;
        for k in -200_000..=200_000 {
            let x = k as f64 / 200_000.0 * PI;
            worst = worst.max((cos(x) - x.cos()).abs());
            let y = -FRAC_PI_2 + (k + 200_000) as f64 / 400_000.0 * 2.0 * PI;
            worst = worst.max((sin(y) - y.sin()).abs());
        }
        assert!(worst < 1e-8, "{worst}");
        assert_eq!(cos(0.0), 1.0);
        assert_eq!(cos(4.0), 4.0f64.cos());
        assert!((sin(-2.0) - (-2.0f64).sin()).abs() < 1e-15);
    }
}
