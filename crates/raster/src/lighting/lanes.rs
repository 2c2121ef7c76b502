//! Lane arrays: [`LANES`] points in structure-of-arrays form, written as plain loops that the
//! compiler turns into SIMD (8 f32 lanes fill an AVX2 register, two SSE2 ones).

/// Points evaluated together.
pub(crate) const LANES: usize = 8;

/// One value per lane.
pub(crate) type Lanes = [f32; LANES];

/// Normalises the vectors `f(lane)` into `out` (zero stays zero).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
pub(crate) fn normalize_lanes(out: &mut [Lanes; 3], f: impl Fn(usize) -> (f32, f32, f32)) {
    for k in 0..LANES {
        let (x, y, z) = f(k);
        let len2 = x * x + y * y + z * z;
        let inv = if len2 > 0.0 { 1.0 / len2.sqrt() } else { 0.0 };
        out[0][k] = x * inv;
        out[1][k] = y * inv;
        out[2][k] = z * inv;
    }
}
