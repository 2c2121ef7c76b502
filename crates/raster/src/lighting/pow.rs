//! `x^f` without libm, branch-free so lane loops over it vectorise.

/// `x^f` for `x` in [0, 1] and `f ≥ 0`, as `2^(f·log2 x)` with polynomial log2/exp2.
///
/// Faster than `powf` and branch-free, so lane loops over it vectorise. Relative error below
/// 2e-5 (0.005 of an 8-bit level) for the `f ≤ 128` of real materials (see the tests); the
/// absolute error stays below 1e-6 even at `f = 10 000`. Results below 2^-126 flush to 0;
/// `0^0 = 1` as with `powf`.
#[inline(always)]
#[allow(clippy::manual_clamp)] // `clamp` keeps NaN; `max`/`min` send it to a bound, as wanted
pub(crate) fn pow01(x: f32, f: f32) -> f32 {
    let bits = x.max(1e-30).to_bits();
    let mant = bits & 0x007f_ffff;
    // Mantissa folded into [sqrt(1/2), sqrt(2)) so the series argument stays small.
    let big = mant > 0x0035_04f3;
    let e = (((bits >> 23) & 0xff) as i32 - 127 + big as i32) as f32;
    let m = f32::from_bits(mant | if big { 0x3f00_0000 } else { 0x3f80_0000 });
    let t = (m - 1.0) / (m + 1.0);
    let t2 = t * t;
    // log2(m) = 2/ln 2 · atanh(t), |t| ≤ 0.1716: five odd terms reach f32 precision.
    let log2m =
        t * (2.885_39 + t2 * (0.961_796_7 + t2 * (0.577_078 + t2 * (0.412_198 + t2 * 0.320_6))));
    // Clamped to ≤ 0 too: a dot product of unit vectors can exceed 1 by rounding, and with a
    // huge exponent y then overflowed `i + 127` below (a NaN colour in release builds; found
    // by fuzzing). x ≥ 1 gives 1.
    // `max`/`min`, not `clamp`: they send NaN to a bound (no NaN reaches them from finite
    // inputs, but the cast below then needs no saturation code: a plain SIMD conversion).
    let y = (f * (e + log2m)).max(-126.0).min(0.0);
    // Round to nearest by truncating y − 0.5 (y ≤ ~0): no libm call on baseline x86-64.
    // SAFETY: y − 0.5 is in [−126.5, −0.5], representable in i32.
    let i = unsafe { (y - 0.5).to_int_unchecked::<i32>() };
    let z = (y - i as f32) * std::f32::consts::LN_2; // |z| ≤ ln2 / 2
                                                     // e^z by its Taylor series to degree 7 (relative error < 2e-8).
    let p = 1.0
        + z * (1.0
            + z * (0.5
                + z * (1.0 / 6.0
                    + z * (1.0 / 24.0
                        + z * (1.0 / 120.0 + z * (1.0 / 720.0 + z * (1.0 / 5040.0)))))));
    let r = p * f32::from_bits(((i + 127) as u32) << 23);
    let r = if y <= -126.0 { 0.0 } else { r };
    if x > 0.0 {
        r
    } else if f == 0.0 {
        1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fuzzing found `n·h` a rounding step above 1 with a huge exponent overflowing the
    /// exponent arithmetic (`fuzz/seeds/pipeline/crash-pow-above-one`).
    #[test]
    fn pow01_of_a_base_just_above_one_is_one() {
        let above = 1.0 + f32::EPSILON;
        for f in [0.0, 1.0, 1e4, 1e30, f32::MAX] {
            assert_eq!(pow01(above, f), 1.0, "f = {f}");
            assert_eq!(pow01(1.0, f), 1.0, "f = {f}");
        }
    }

    /// The exponent an infinite shininess is folded to: `pow01(x, f32::MAX)` is the step
    /// `[x ≥ 1]` for every f32 in [0, 1], the largest below 1 included.
    #[test]
    fn pow01_with_the_largest_exponent_is_the_mirror_step() {
        let below_one = f32::from_bits(1.0f32.to_bits() - 1);
        for x in [0.0, 1e-30, 0.5, 0.999, 0.999_999, below_one] {
            assert_eq!(pow01(x, f32::MAX), 0.0, "x = {x}");
        }
        assert_eq!(pow01(1.0, f32::MAX), 1.0);
        assert_eq!(pow01(1.0 + f32::EPSILON, f32::MAX), 1.0);
        // The finite exponents approach the step: x^1e8 is below 1e-6 once x < 1 - 1.4e-7.
        assert!(pow01(1.0 - 2e-7, 1e8) < 1e-6);
    }

    #[test]
    fn pow01_is_accurate() {
        let mut worst_rel = 0.0f64;
        let mut worst_abs = 0.0f64;
        for i in 0..=20_000 {
            let x = i as f32 / 20_000.0;
            for &f in &[
                0.0f32, 0.5, 1.0, 2.0, 9.84615, 27.8974, 51.2, 89.6, 128.0, 1000.0, 10_000.0,
            ] {
                let want = (x as f64).powf(f as f64);
                let got = pow01(x, f) as f64;
                worst_abs = worst_abs.max((got - want).abs());
                if f <= 128.0 && want > 1e-30 {
                    worst_rel = worst_rel.max(((got - want) / want).abs());
                }
            }
        }
        assert!(worst_rel < 2e-5, "relative {worst_rel}");
        assert!(worst_abs < 1e-6, "absolute {worst_abs}");
        assert_eq!(pow01(0.0, 0.0), 1.0);
        assert_eq!(pow01(0.0, 3.0), 0.0);
        assert_eq!(pow01(1.0, 10_000.0), 1.0);
    }
}
