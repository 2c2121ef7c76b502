//! `acos`, `atan2`, `cos` and `sin` by short polynomials, where libm's correctly rounded
//! versions were a measurable share of the work and nothing needs their precision.
//!
//! - The shading estimate (`auto_shading`) takes about a dozen angles per evaluated
//!   triangle and light; libm's functions were an eighth of its instructions.
//! - An equirectangular environment look-up (`Environment::uv`) takes two `atan2` per
//!   direction, a pixel's share of the secondary stage at every mirror, glass and
//!   background pixel; libm's were about a sixth of that stage. It takes them in f32, eight
//!   lanes to an AVX register ([`atan2_f32`]).
//!
//! These are within 3·10⁻⁸ rad (acos), 10⁻⁸ (cos, sin) of libm and 3.5·10⁻⁷ rad (the f32
//! atan2) of the exact angle (tested below): an estimate does not move, and a look-up moves
//! by under 10⁻³ of a texel in a 4096-texel-wide image. They are plain arithmetic the
//! compiler inlines.

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

/// `atan2(y, x)` in f32 (the angle of (x, y) in [−π, π], as [`f32::atan2`]) for finite
/// `x`, `y`, within 3.5·10⁻⁷ rad of the exact angle (3·10⁻⁷ measured below against f64's):
/// `atan t` for `t = min/max(|x|, |y|)` in [0, 1] as `t·P(t²)` (P of degree 7, a
/// near-minimax fit of `atan(t)/t`, 4·10⁻⁸ in exact arithmetic; the rest is f32 rounding),
/// placed in its octant (which rounds to f32's π). Exact on the axes (0, ±π/2, ±π in
/// f32); where both are zero, libm's signed zero or ±π. Branch-free: it vectorises over
/// lanes, eight to an AVX register.
#[inline(always)]
pub(crate) fn atan2_f32(y: f32, x: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = if ay > ax { (ax, ay) } else { (ay, ax) };
    // Both zero: t = 0, and the octant placement gives libm's answers.
    let t = lo / if hi > 0.0 { hi } else { 1.0 };
    let z = t * t;
    let p = 0.999_999_34
        + z * (-0.333_298_6
            + z * (0.199_465_66
                + z * (-0.139_086_29
                    + z * (0.096_421_96
                        + z * (-0.055_912_3 + z * (0.021_862_935 + z * -0.004_054_56))))));
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
    fn atan2_f32_is_within_its_bound_and_exact_on_the_axes() {
        let mut worst = 0.0f64;
        for k in 0..400_000 {
            let a = -PI + (k as f64 + 0.5) / 400_000.0 * 2.0 * PI;
            for r in [1e-3, 1.0, 7.5, 3e30] {
                let (y, x) = ((r * a.sin()) as f32, (r * a.cos()) as f32);
                let exact = (y as f64).atan2(x as f64);
                worst = worst.max((atan2_f32(y, x) as f64 - exact).abs());
            }
        }
        assert!(worst < 3.5e-7, "{worst}");
        for (y, x) in [
            (0.0f32, 1.0f32),
            (-0.0, 1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (0.0, 0.0),
            (0.0, -0.0),
            (-0.0, 0.0),
            (-0.0, -0.0),
            (2.0, -0.0),
        ] {
            let (got, want) = (atan2_f32(y, x), y.atan2(x));
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
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
