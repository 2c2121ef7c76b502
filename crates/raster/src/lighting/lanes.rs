//! Lane arrays: [`LANES`] points in structure-of-arrays form, written as plain loops that the
//! compiler turns into SIMD (8 f32 lanes fill an AVX2 register, two SSE2 ones).

use glam::Vec3;

/// Points evaluated together.
pub(crate) const LANES: usize = 8;

/// One value per lane.
pub(crate) type Lanes = [f32; LANES];

/// Lane `k` of the channel-major vectors `v`.
#[inline(always)]
pub(crate) fn lane<const N: usize>(v: &[[f32; N]; 3], k: usize) -> Vec3 {
    Vec3::new(v[0][k], v[1][k], v[2][k])
}

/// Sets lane `k` of the channel-major vectors `v` to `x`.
#[inline(always)]
pub(crate) fn set_lane<const N: usize>(v: &mut [[f32; N]; 3], k: usize, x: Vec3) {
    (v[0][k], v[1][k], v[2][k]) = (x.x, x.y, x.z);
}

/// Normalises the vectors `v` into `out`: `v · (1 / √|v|²)` per lane, and zero where
/// `|v|²` is zero or NaN.
///
/// On x86-64 in intrinsics: eight lanes in AVX when `wide` (the render's ISA is AVX2:
/// inlined into the AVX2 tile bodies, which have the feature), else two SSE halves. As
/// lane loops, LLVM's SLP vectoriser split the eight lanes into scalar and 2- and 4-lane
/// pieces with shuffles and, where Phong lights a run's whole group, branched per lane
/// around `sqrtss` and `divss` (perf put 12 % of a Phong tile on them and on the stalled
/// reloads between the pieces); SSE halves stored where AVX loads read stalled store
/// forwarding in turn. Each lane is the same IEEE operations in the same order in every
/// form (no fused multiply-add), so the bits are those of the lane loop kept for other
/// architectures (`normalize_lanes_matches_the_scalar_form`).
#[inline(always)]
pub(crate) fn normalize_lanes(out: &mut [Lanes; 3], v: &[Lanes; 3], wide: bool) {
    #[cfg(target_arch = "x86_64")]
    {
        if wide {
            // SAFETY: `wide` only where the render's ISA is AVX2 (or a surface's
            // `with_wide_lanes`), both detected on this CPU.
            unsafe { normalize_lanes_avx(out, v) };
        } else {
            normalize_lanes_sse(out, v);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = wide;
        normalize_lanes_scalar(out, v);
    }
}

/// [`normalize_lanes`] in AVX, all eight lanes at once.
///
/// # Safety
/// The CPU must support AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn normalize_lanes_avx(out: &mut [Lanes; 3], v: &[Lanes; 3]) {
    use std::arch::x86_64::*;
    let (zero, one) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
    // SAFETY: each load reads one lane array's eight f32.
    let (x, y, z) = unsafe {
        (
            _mm256_loadu_ps(v[0].as_ptr()),
            _mm256_loadu_ps(v[1].as_ptr()),
            _mm256_loadu_ps(v[2].as_ptr()),
        )
    };
    let len2 = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(x, x), _mm256_mul_ps(y, y)),
        _mm256_mul_ps(z, z),
    );
    // Ordered, non-signalling len2 > 0: false for NaN, as `>`.
    let ok = _mm256_cmp_ps::<_CMP_GT_OQ>(len2, zero);
    let s = _mm256_sqrt_ps(_mm256_blendv_ps(one, len2, ok));
    let inv = _mm256_and_ps(ok, _mm256_div_ps(one, s));
    // SAFETY: each store writes one lane array's eight f32.
    unsafe {
        _mm256_storeu_ps(out[0].as_mut_ptr(), _mm256_mul_ps(x, inv));
        _mm256_storeu_ps(out[1].as_mut_ptr(), _mm256_mul_ps(y, inv));
        _mm256_storeu_ps(out[2].as_mut_ptr(), _mm256_mul_ps(z, inv));
    }
}

/// [`normalize_lanes`] in SSE, two halves of four lanes (what every x86-64 has).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn normalize_lanes_sse(out: &mut [Lanes; 3], v: &[Lanes; 3]) {
    use std::arch::x86_64::*;
    // SAFETY: SSE and SSE2 are part of x86-64; every load and store reads or writes four
    // of a lane array's eight f32 at offset 0 or 4.
    unsafe {
        let (zero, one) = (_mm_setzero_ps(), _mm_set1_ps(1.0));
        for h in [0, 4] {
            let x = _mm_loadu_ps(v[0].as_ptr().add(h));
            let y = _mm_loadu_ps(v[1].as_ptr().add(h));
            let z = _mm_loadu_ps(v[2].as_ptr().add(h));
            let len2 = _mm_add_ps(
                _mm_add_ps(_mm_mul_ps(x, x), _mm_mul_ps(y, y)),
                _mm_mul_ps(z, z),
            );
            // len2 > 0, false for NaN; the root of 1 where not (only the result is kept).
            let ok = _mm_cmpgt_ps(len2, zero);
            let s = _mm_sqrt_ps(_mm_or_ps(_mm_and_ps(ok, len2), _mm_andnot_ps(ok, one)));
            let inv = _mm_and_ps(ok, _mm_div_ps(one, s));
            _mm_storeu_ps(out[0].as_mut_ptr().add(h), _mm_mul_ps(x, inv));
            _mm_storeu_ps(out[1].as_mut_ptr().add(h), _mm_mul_ps(y, inv));
            _mm_storeu_ps(out[2].as_mut_ptr().add(h), _mm_mul_ps(z, inv));
        }
    }
}

/// [`normalize_lanes`] as plain lane loops: the definition its SIMD form keeps to.
#[cfg(any(test, not(target_arch = "x86_64")))]
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays
pub(crate) fn normalize_lanes_scalar(out: &mut [Lanes; 3], v: &[Lanes; 3]) {
    let mut inv = [0.0; LANES];
    for k in 0..LANES {
        let len2 = v[0][k] * v[0][k] + v[1][k] * v[1][k] + v[2][k] * v[2][k];
        let ok = len2 > 0.0;
        let i = 1.0 / (if ok { len2 } else { 1.0 }).sqrt();
        inv[k] = if ok { i } else { 0.0 };
    }
    for (o, v) in out.iter_mut().zip(v) {
        for k in 0..LANES {
            o[k] = v[k] * inv[k];
        }
    }
}

/// `a − b` per lane and axis, with `a` one point.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays
pub(crate) fn from_lanes(a: Vec3, b: &[Lanes; 3]) -> [Lanes; 3] {
    let mut d = [[0.0; LANES]; 3];
    for axis in 0..3 {
        for k in 0..LANES {
            d[axis][k] = a[axis] - b[axis][k];
        }
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Awkward values for a lane: zeros of both signs, tiny and huge magnitudes (whose
    /// squares underflow or overflow), subnormals, infinities and NaN, and ordinary ones.
    fn awkward(k: usize) -> f32 {
        const V: [f32; 16] = [
            0.0,
            -0.0,
            1.0,
            -0.3,
            1e-20,
            -1e-25,
            1e20,
            -3e19,
            f32::MIN_POSITIVE,
            1e-40,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            0.577_350_3,
            123.456,
            -7.5e-3,
        ];
        V[k % V.len()]
    }

    /// The SIMD form gives the lane loops' bits on every lane, whatever its neighbours.
    #[test]
    fn normalize_lanes_matches_the_scalar_form() {
        for seed in 0..16 * 16 * 16 {
            let v: [Lanes; 3] = std::array::from_fn(|axis| {
                std::array::from_fn(|k| awkward(seed / 16usize.pow(axis as u32) + 5 * k))
            });
            let (mut got, mut want) = ([[0.0; LANES]; 3], [[0.0; LANES]; 3]);
            normalize_lanes(&mut got, &v, false);
            normalize_lanes_scalar(&mut want, &v);
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx") {
                let mut wide = [[0.0; LANES]; 3];
                normalize_lanes(&mut wide, &v, true);
                let bits = |a: [Lanes; 3]| a.map(|a| a.map(f32::to_bits));
                assert_eq!(bits(wide), bits(got), "{v:?}");
            }
            for axis in 0..3 {
                for k in 0..LANES {
                    let (g, w) = (got[axis][k], want[axis][k]);
                    assert!(g.to_bits() == w.to_bits(), "{v:?} lane {k}: {g} vs {w}");
                }
            }
        }
        // A unit vector stays unit, zero stays zero.
        let v = [[3.0; LANES], [4.0; LANES], [0.0; LANES]];
        let mut n = [[9.0; LANES]; 3];
        normalize_lanes(&mut n, &v, false);
        assert_eq!(n, [[0.6; LANES], [0.8; LANES], [0.0; LANES]]);
        normalize_lanes(&mut n, &[[0.0; LANES]; 3], false);
        assert_eq!(n, [[0.0; LANES]; 3]);
    }
}
