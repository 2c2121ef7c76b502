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

/// Normalises the vectors `f(lane)` into `out` (zero stays zero).
///
/// Written as three plain lane loops with the square root and division on every lane (of 1
/// where the length is zero or NaN; only the result is selected): as one loop with them
/// inside `if len2 > 0`, the fully unrolled code stayed mostly scalar where Phong lights a
/// run's whole group (`sqrtss` and `divss` with a branch per lane, seen in perf).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
pub(crate) fn normalize_lanes(out: &mut [Lanes; 3], f: impl Fn(usize) -> (f32, f32, f32)) {
    let mut v = [[0.0; LANES]; 3];
    for k in 0..LANES {
        (v[0][k], v[1][k], v[2][k]) = f(k);
    }
    let mut inv = [0.0; LANES];
    for k in 0..LANES {
        let len2 = v[0][k] * v[0][k] + v[1][k] * v[1][k] + v[2][k] * v[2][k];
        let ok = len2 > 0.0;
        let i = 1.0 / (if ok { len2 } else { 1.0 }).sqrt();
        inv[k] = if ok { i } else { 0.0 };
    }
    for (o, v) in out.iter_mut().zip(&v) {
        for k in 0..LANES {
            o[k] = v[k] * inv[k];
        }
    }
}
