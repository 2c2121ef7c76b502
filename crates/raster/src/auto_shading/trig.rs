//! `acos`, `cos` and `sin` by short polynomials, for the estimate's angles.
//!
//! The estimate takes about a dozen of them per evaluated triangle and light (the angles
//! to the light and the half vector, the normals' turns, the lobe and the diffuse term
//! at the ends of their ranges); libm's correctly rounded versions were an eighth of its
//! instructions. An estimate needs nothing like their precision: these are within
//! 3·10⁻⁸ (acos, radians) and 10⁻⁸ (cos, sin) of them (tested below), far below what moves
//! an error estimate, and are plain arithmetic the compiler inlines.

use std::f64::consts::{FRAC_PI_2, PI};

/// `acos x` for `x` in [-1, 1] (clamped), within 3·10⁻⁸ rad (Abramowitz & Stegun 4.4.46:
/// `√(1 − x)` times a degree-7 polynomial on [0, 1], `π − acos(−x)` below 0). Exact at 1.
pub(super) fn acos(x: f64) -> f64 {
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

/// `cos x` for `x` in [-π, π] (beyond it, libm's), within 10⁻⁸: the Taylor series to
/// `x¹²` on [0, π/2], `−cos(π − x)` above.
pub(super) fn cos(x: f64) -> f64 {
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
pub(super) fn sin(x: f64) -> f64 {
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
