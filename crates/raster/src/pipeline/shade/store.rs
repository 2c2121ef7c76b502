//! Output samples: how a linear RGB colour is stored (`u8` quantised, `f32` as is), into
//! rows that are written exactly once and never read (`MaybeUninit`).

use std::mem::MaybeUninit;

use glam::Vec3;

use crate::lighting::{lane, Lanes, LANES};
use crate::pipeline::tiles::TILE;

mod sealed {
    /// Only the crate's own sample types are [`super::Pixel`]s.
    pub trait Sealed {}
    impl Sealed for u8 {}
    impl Sealed for f32 {}
}

/// An output sample type: how a linear RGB colour is stored. Implemented for `u8`
/// (`round(clamp(c, 0, 1) · 255)`) and `f32` (linear, unclamped) only (sealed).
pub trait Pixel: sealed::Sealed + Copy + Default + Send + Sync + 'static {
    /// Writes `c` into `dst[0..3]`.
    fn store(dst: &mut [Self], c: Vec3);

    /// A pixel's three stored samples as one value (`u8`: the low three bytes of a u32),
    /// for rows filled a run at a time ([`Pixel::stored`], [`Pixel::put_stored`]).
    #[doc(hidden)]
    type Stored: Copy + Default;

    /// The samples [`Pixel::store`] writes for `c`, as one [`Pixel::Stored`].
    #[doc(hidden)]
    fn stored(c: Vec3) -> Self::Stored;

    /// Writes the pixels `row` into the output `dst` (its first `3 · row.len()` samples).
    #[doc(hidden)]
    fn put_stored(dst: &mut [Out<Self>], row: &[Self::Stored]);

    /// Writes the first `dst.len() / 3` colours of the row `c` (`c[channel][pixel]`) into
    /// the output `dst`, as [`Pixel::store`] would one by one. `wide`: the render runs on
    /// AVX2 ([`Isa::Avx2`](crate::pipeline::isa::Isa)), whose instructions the stores may use.
    #[doc(hidden)]
    #[inline(always)]
    fn store_row(dst: &mut [MaybeUninit<Self>], c: &RowColors, _wide: bool) {
        for (k, px) in dst.chunks_exact_mut(3).enumerate() {
            store_out(px, lane(c, k));
        }
    }

    /// Writes the [`LANES`] colours `c` (`c[channel][lane]`) to the [`LANES`] consecutive
    /// pixels of `dst` (`3 · LANES` samples), as [`Pixel::store`] would one by one
    /// (`wide` as for [`Pixel::store_row`]).
    #[doc(hidden)]
    #[inline(always)]
    fn store_group(dst: &mut [Out<Self>], c: &[Lanes; 3], _wide: bool) {
        for (k, px) in dst.chunks_exact_mut(3).take(LANES).enumerate() {
            store_out(px, lane(c, k));
        }
    }

    /// Writes lane `k` of `c` (`c[channel][lane]`) to tile slot `at[k]` = (row, column) of
    /// the output rows `rows`, for every `k < at.len()`, as [`Pixel::store`] would one by one
    /// (`wide` as for [`Pixel::store_row`]).
    #[doc(hidden)]
    #[inline(always)]
    fn store_lanes(
        rows: &mut [&mut [Out<Self>]],
        at: &[(usize, usize)],
        c: &[Lanes; 3],
        _wide: bool,
    ) {
        let [r, g, b] = c;
        for (((&(j, i), r), g), b) in at.iter().zip(r).zip(g).zip(b) {
            store_out(&mut rows[j][i * 3..i * 3 + 3], Vec3::new(*r, *g, *b));
        }
    }
}

/// Output rows are written, never read, so the image needs no zeroing first: the
/// pipeline writes every sample of them (background or shaded) exactly once.
pub(crate) type Out<T> = MaybeUninit<T>;

/// Copies `src` into the output `dst` (same length).
#[inline(always)]
pub(crate) fn put<T: Copy>(dst: &mut [Out<T>], src: &[T]) {
    for (d, &s) in dst.iter_mut().zip(src) {
        d.write(s);
    }
}

/// Fills the output `dst` with `v`.
#[inline(always)]
pub(crate) fn fill_out<T: Copy>(dst: &mut [Out<T>], v: T) {
    for d in dst {
        d.write(v);
    }
}

/// [`Pixel::store`] into the output.
#[inline(always)]
pub(crate) fn store_out<P: Pixel>(dst: &mut [Out<P>], c: Vec3) {
    let mut px = [P::default(); 3];
    P::store(&mut px, c);
    put(dst, &px);
}

/// Linear colours of up to a tile row's pixels (plus a lane loop's overrun), channel-major.
#[doc(hidden)]
pub type RowColors = [[f32; ROW_LANES]; 3];

/// Length of a [`RowColors`] channel: a tile row rounded up to whole [`LANES`].
#[doc(hidden)]
pub const ROW_LANES: usize = TILE + LANES;

/// Column `i`'s three channels in a tile row the shading loops wrote, as values (a plain
/// run stores them straight into lanes: through a `Vec3` in memory, the reload stalled).
#[inline(always)]
pub(crate) fn rgb_at(row: &[Out<f32>], i: usize) -> [f32; 3] {
    // SAFETY: the shading loops wrote every sample of the rows they were given.
    unsafe {
        [
            row[i * 3].assume_init(),
            row[i * 3 + 1].assume_init(),
            row[i * 3 + 2].assume_init(),
        ]
    }
}

/// Columns `cols` of a tile row of interleaved colours (`row`: three samples a pixel, as the
/// shading loops write a secondary stage's local colours) into the channel-major `out`, the
/// same values. In AVX2 when `wide` (the caller is the AVX2 tile body), eight pixels at a
/// time by shuffles: a sample at a time, these copies were a few percent of a mirror
/// frame's instructions (callgrind).
///
/// # Panics
/// If a column is past `row` or `out` (a caller's bug: columns are a tile row's).
#[inline(always)]
pub(crate) fn deinterleave(
    row: &[Out<f32>],
    cols: std::ops::Range<usize>,
    out: &mut RowColors,
    wide: bool,
) {
    let (row, mut k) = (&row[..cols.end * 3], cols.start);
    if wide {
        while k + LANES <= cols.end {
            let src: &[Out<f32>; 3 * LANES] = row[k * 3..(k + LANES) * 3].try_into().unwrap();
            let [r, g, b] = deinterleave8(src, wide);
            out[0][k..k + LANES].copy_from_slice(&r);
            out[1][k..k + LANES].copy_from_slice(&g);
            out[2][k..k + LANES].copy_from_slice(&b);
            k += LANES;
        }
    }
    #[allow(clippy::needless_range_loop)] // one column of three channel rows
    for k in k..cols.end {
        [out[0][k], out[1][k], out[2][k]] = rgb_at(row, k);
    }
}

/// Eight interleaved pixels (three samples each, initialised) as three channels, the same
/// values: in AVX2 when `wide` (the caller is the AVX2 tile body), else a lane loop.
#[inline(always)]
pub(crate) fn deinterleave8(src: &[Out<f32>; 3 * LANES], wide: bool) -> [[f32; LANES]; 3] {
    #[cfg(target_arch = "x86_64")]
    if wide {
        // SAFETY: `wide` is set only in the AVX2 tile bodies (the CPU has AVX2).
        return unsafe { deinterleave8_avx2(src) };
    }
    let _ = wide;
    let px: [[f32; 3]; LANES] = std::array::from_fn(|k| rgb_at(src, k));
    std::array::from_fn(|c| px.map(|p| p[c]))
}

/// Eight interleaved pixels as three channels: each channel's samples picked from the three
/// vectors by two blends, then put in order by one permute.
///
/// # Safety
/// The CPU must support AVX2; `src`'s samples must be initialised.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn deinterleave8_avx2(src: &[Out<f32>; 3 * LANES]) -> [[f32; LANES]; 3] {
    use std::arch::x86_64::*;
    let p = src.as_ptr().cast::<f32>();
    let mut out = [[0.0f32; LANES]; 3];
    // SAFETY: three loads of 8 samples within `src` (24 samples, initialised by the
    // caller's contract); three stores of 8 lanes into `out`.
    unsafe {
        let (a0, a1, a2) = (
            _mm256_loadu_ps(p),
            _mm256_loadu_ps(p.add(8)),
            _mm256_loadu_ps(p.add(16)),
        );
        // Sample s of pixel k is element 3k + s, in vector (3k + s) / 8: red takes a1 at
        // lanes 1, 4, 7 and a2 at 2, 5; green a1 at 2, 5 and a2 at 0, 3, 6; blue a1 at 0,
        // 3, 6 and a2 at 1, 4, 7; a0 elsewhere.
        let r = _mm256_blend_ps::<0x24>(_mm256_blend_ps::<0x92>(a0, a1), a2);
        let g = _mm256_blend_ps::<0x49>(_mm256_blend_ps::<0x24>(a0, a1), a2);
        let b = _mm256_blend_ps::<0x92>(_mm256_blend_ps::<0x49>(a0, a1), a2);
        let order = |v, i: [i32; 8]| {
            _mm256_permutevar8x32_ps(v, _mm256_loadu_si256(i.as_ptr().cast::<__m256i>()))
        };
        let r = order(r, [0, 3, 6, 1, 4, 7, 2, 5]);
        let g = order(g, [1, 4, 7, 2, 5, 0, 3, 6]);
        let b = order(b, [2, 5, 0, 3, 6, 1, 4, 7]);
        _mm256_storeu_ps(out[0].as_mut_ptr(), r);
        _mm256_storeu_ps(out[1].as_mut_ptr(), g);
        _mm256_storeu_ps(out[2].as_mut_ptr(), b);
    }
    out
}

/// `round(clamp(v, 0, 1) · 255)`, NaN to 0.
#[inline(always)]
fn quantize(v: f32) -> u8 {
    quantize_i32(v) as u8
}

/// [`quantize`] as an i32 (what a SIMD conversion makes; narrowed when stored).
#[inline(always)]
#[allow(clippy::manual_clamp)] // `clamp` keeps NaN; `max` sends it to 0, as wanted
fn quantize_i32(v: f32) -> i32 {
    // Clamped before the cast (`max` sends NaN to 0): v > 1 gives at least 255.5 → 255,
    // v < 0 less than 0.5 → 0. The cast of a value known to be in [0, 255] then needs no
    // saturation fix-ups, so lane loops of this vectorise.
    let x = (v * 255.0 + 0.5).max(0.0).min(255.0);
    // SAFETY: x is in [0, 255] and not NaN, so it is representable in i32.
    unsafe { x.to_int_unchecked::<i32>() }
}

/// `LANES` colours quantised ([`quantize_i32`]), each pixel's three samples in the low
/// bytes of a u32. On x86-64 in intrinsics, eight lanes in AVX2 when `wide` (the render's
/// ISA is AVX2: inlined into the AVX2 tile bodies), else four at a time in SSE2: as a lane loop,
/// LLVM compiled it to scalar conversions where Phong stores a run's whole group (perf:
/// `cvttss2si` per sample). The same operations per sample: `maxps` returns its second
/// operand (0) for a NaN, as `f32::max` does, and the value converted is in [0, 255].
#[inline(always)]
fn pack_window(r: &[f32], g: &[f32], b: &[f32], wide: bool) -> [u32; LANES] {
    let (r, g, b) = (&r[..LANES], &g[..LANES], &b[..LANES]);
    #[cfg(target_arch = "x86_64")]
    {
        if wide {
            // SAFETY: `wide` only on renders whose ISA is AVX2, detected on this CPU.
            unsafe { pack_window_avx2(r, g, b) }
        } else {
            pack_window_sse(r, g, b)
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = wide;
        pack_window_scalar(r, g, b)
    }
}

/// [`pack_window`] in SSE2, two halves of four lanes (what every x86-64 has).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn pack_window_sse(r: &[f32], g: &[f32], b: &[f32]) -> [u32; LANES] {
    let (r, g, b) = (&r[..LANES], &g[..LANES], &b[..LANES]);
    use std::arch::x86_64::*;
    let mut packed = [0u32; LANES];
    // SAFETY: SSE2 is part of x86-64; each load reads four of a slice's LANES f32 and
    // each store writes four of `packed`'s LANES u32, at offset 0 or 4.
    unsafe {
        let (scale, half) = (_mm_set1_ps(255.0), _mm_set1_ps(0.5));
        let (zero, top) = (_mm_setzero_ps(), _mm_set1_ps(255.0));
        let q = |v: __m128| {
            let x = _mm_add_ps(_mm_mul_ps(v, scale), half);
            _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(x, zero), top))
        };
        for h in [0, 4] {
            let qr = q(_mm_loadu_ps(r.as_ptr().add(h)));
            let qg = q(_mm_loadu_ps(g.as_ptr().add(h)));
            let qb = q(_mm_loadu_ps(b.as_ptr().add(h)));
            let p = _mm_or_si128(
                qr,
                _mm_or_si128(_mm_slli_epi32::<8>(qg), _mm_slli_epi32::<16>(qb)),
            );
            _mm_storeu_si128(packed.as_mut_ptr().add(h).cast::<__m128i>(), p);
        }
    }
    packed
}

/// [`pack_window`] in AVX2, all eight lanes at once.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn pack_window_avx2(r: &[f32], g: &[f32], b: &[f32]) -> [u32; LANES] {
    use std::arch::x86_64::*;
    let (scale, half) = (_mm256_set1_ps(255.0), _mm256_set1_ps(0.5));
    let (zero, top) = (_mm256_setzero_ps(), _mm256_set1_ps(255.0));
    let q = |v: __m256| {
        let x = _mm256_add_ps(_mm256_mul_ps(v, scale), half);
        _mm256_cvttps_epi32(_mm256_min_ps(_mm256_max_ps(x, zero), top))
    };
    let (r, g, b) = (&r[..LANES], &g[..LANES], &b[..LANES]);
    let mut packed = [0u32; LANES];
    // SAFETY: each load reads a slice's LANES f32; the store writes `packed`'s LANES u32.
    unsafe {
        let qr = q(_mm256_loadu_ps(r.as_ptr()));
        let qg = q(_mm256_loadu_ps(g.as_ptr()));
        let qb = q(_mm256_loadu_ps(b.as_ptr()));
        let p = _mm256_or_si256(
            qr,
            _mm256_or_si256(_mm256_slli_epi32::<8>(qg), _mm256_slli_epi32::<16>(qb)),
        );
        _mm256_storeu_si256(packed.as_mut_ptr().cast::<__m256i>(), p);
    }
    packed
}

/// [`pack_window`] as a lane loop: the definition its SIMD form keeps to.
#[cfg(any(test, not(target_arch = "x86_64")))]
#[inline(always)]
fn pack_window_scalar(r: &[f32], g: &[f32], b: &[f32]) -> [u32; LANES] {
    let mut packed = [0u32; LANES];
    for k in 0..LANES {
        packed[k] = quantize_i32(r[k]) as u32
            | (quantize_i32(g[k]) as u32) << 8
            | (quantize_i32(b[k]) as u32) << 16;
    }
    packed
}

/// Writes the packed pixels `packed` ([`pack_window`]) to the output `dst`, three samples
/// each: four bytes a pixel (the fourth is the next pixel's first, rewritten by it) and the
/// last pixel's three alone, so nothing past `3 · packed.len()` is touched.
#[inline(always)]
fn write_packed(dst: &mut [Out<u8>], packed: &[u32]) {
    let Some((last, rest)) = packed.split_last() else {
        return;
    };
    let dst = &mut dst[..3 * packed.len()];
    let out = dst.as_mut_ptr();
    for (k, p) in rest.iter().enumerate() {
        // SAFETY: k < packed.len() − 1, so bytes 3k..3k + 4 lie within
        // 0..3·packed.len() − 2 ⊆ 0..dst.len(); `Out<u8>` has u8's layout.
        unsafe {
            out.add(3 * k)
                .cast::<[u8; 4]>()
                .write_unaligned(p.to_le_bytes())
        };
    }
    let tail = 3 * rest.len();
    put(&mut dst[tail..tail + 3], &last.to_le_bytes()[..3]);
}

impl Pixel for u8 {
    /// `round(clamp(c, 0, 1) · 255)`.
    #[inline]
    fn store(dst: &mut [u8], c: Vec3) {
        dst[0] = quantize(c.x);
        dst[1] = quantize(c.y);
        dst[2] = quantize(c.z);
    }

    type Stored = u32;

    #[inline(always)]
    fn stored(c: Vec3) -> u32 {
        let mut px = [0u8; 3];
        Self::store(&mut px, c);
        u32::from_le_bytes([px[0], px[1], px[2], 0])
    }

    #[inline(always)]
    fn put_stored(dst: &mut [Out<u8>], row: &[u32]) {
        write_packed(dst, row);
    }

    #[inline(always)]
    fn store_row(dst: &mut [Out<u8>], c: &RowColors, wide: bool) {
        // Quantised over whole lanes (SIMD, in fixed windows so no scalar tail loop is
        // made), then written four bytes a pixel.
        let px = dst.len() / 3;
        let n = px.div_ceil(LANES) * LANES;
        let mut packed = [0u32; ROW_LANES];
        let [cr, cg, cb] = c;
        for (w, p) in packed[..n].chunks_exact_mut(LANES).enumerate() {
            let s = w * LANES..(w + 1) * LANES;
            p.copy_from_slice(&pack_window(&cr[s.clone()], &cg[s.clone()], &cb[s], wide));
        }
        write_packed(dst, &packed[..px]);
    }

    #[inline(always)]
    fn store_group(dst: &mut [Out<u8>], c: &[Lanes; 3], wide: bool) {
        write_packed(dst, &pack_window(&c[0], &c[1], &c[2], wide));
    }

    #[inline(always)]
    fn store_lanes(rows: &mut [&mut [Out<u8>]], at: &[(usize, usize)], c: &[Lanes; 3], wide: bool) {
        // Quantised over all lanes at once (SIMD), then written: four bytes a pixel when
        // the lanes are consecutive pixels of one row (a run's chunk, the usual case),
        // else three bytes per live lane (per lane, each channel was converted and
        // bounds-checked apart).
        let packed = pack_window(&c[0], &c[1], &c[2], wide);
        let Some(&(j0, i0)) = at.first() else {
            return;
        };
        let run = at
            .iter()
            .enumerate()
            .fold(true, |ok, (k, &(j, i))| ok & (j == j0) & (i == i0 + k));
        if run {
            write_packed(
                &mut rows[j0][i0 * 3..(i0 + at.len()) * 3],
                &packed[..at.len()],
            );
            return;
        }
        for (&(j, i), p) in at.iter().zip(&packed) {
            put(&mut rows[j][i * 3..i * 3 + 3], &p.to_le_bytes()[..3]);
        }
    }
}

impl Pixel for f32 {
    /// Linear, unclamped.
    #[inline]
    fn store(dst: &mut [f32], c: Vec3) {
        dst[0] = c.x;
        dst[1] = c.y;
        dst[2] = c.z;
    }

    type Stored = [f32; 3];

    #[inline(always)]
    fn stored(c: Vec3) -> [f32; 3] {
        c.to_array()
    }

    #[inline(always)]
    fn put_stored(dst: &mut [Out<f32>], row: &[[f32; 3]]) {
        for (px, c) in dst.chunks_exact_mut(3).zip(row) {
            put(px, c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values a quantisation must get right: NaN, infinities, out-of-range values, signed
    /// zeros, the smallest normal value, and every rounding boundary (k + 0.5)/255 with its
    /// neighbours.
    fn awkward_values() -> Vec<f32> {
        let mut values = vec![
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -1e30,
            -1.0,
            -0.5 / 255.0,
            -1e-9,
            0.0,
            -0.0,
            f32::MIN_POSITIVE,
            1.0,
            1.0 + f32::EPSILON,
            1.5,
            1e30,
        ];
        for k in 0..256 {
            let b = (k as f32 + 0.5) / 255.0;
            values.extend([
                b,
                f32::from_bits(b.to_bits() - 1),
                f32::from_bits(b.to_bits() + 1),
            ]);
        }
        values
    }

    #[test]
    fn u8_store_is_round_of_clamp_times_255() {
        let reference = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        let values = awkward_values();
        for v in values {
            let mut out = [0u8; 3];
            u8::store(&mut out, Vec3::splat(v));
            assert_eq!(out, [reference(v); 3], "{v}");
        }
    }

    /// The `wide` arguments this CPU can run: false, and true where it has AVX2.
    fn wides() -> Vec<bool> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            return vec![false, true];
        }
        vec![false]
    }

    /// The SIMD quantisation (SSE2, and AVX2 where the CPU has it) gives the lane loop's
    /// bytes for every lane: the rounding boundaries, out-of-range values, infinities, NaN.
    #[test]
    fn deinterleave_copies_every_column_exactly() {
        // Distinct samples (bits included: a NaN payload and a negative zero), every range
        // of a tile row, both widths: each column's three samples land in their channels.
        let n = TILE;
        let mut samples: Vec<f32> = (0..3 * n).map(|i| i as f32 * 0.25 - 7.0).collect();
        samples[5] = f32::from_bits(0x7fc0_1234);
        samples[9] = -0.0;
        let row: Vec<Out<f32>> = samples.iter().map(|&v| Out::new(v)).collect();
        for wide in wides() {
            for k in 0..=n - LANES {
                let got = deinterleave8(row[k * 3..(k + LANES) * 3].try_into().unwrap(), wide);
                for (c, ch) in got.iter().enumerate() {
                    for (q, v) in ch.iter().enumerate() {
                        let want = samples[(k + q) * 3 + c];
                        assert_eq!(v.to_bits(), want.to_bits(), "{wide} {k} {q} {c}");
                    }
                }
            }
            for start in 0..n {
                for end in start..=n {
                    let mut out: RowColors = [[1e9; ROW_LANES]; 3];
                    deinterleave(&row, start..end, &mut out, wide);
                    for (c, ch) in out.iter().enumerate() {
                        for (k, v) in ch.iter().enumerate() {
                            let want = if (start..end).contains(&k) {
                                samples[k * 3 + c]
                            } else {
                                1e9
                            };
                            assert_eq!(
                                v.to_bits(),
                                want.to_bits(),
                                "{wide} {start}..{end} {k} {c}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn pack_window_matches_the_scalar_form() {
        let values = awkward_values();
        for w in 0..values.len() {
            let lanes = |ch: usize| -> Lanes {
                std::array::from_fn(|k| values[(w + 7 * k + 31 * ch) % values.len()])
            };
            let (r, g, b) = (lanes(0), lanes(1), lanes(2));
            let want = pack_window_scalar(&r, &g, &b);
            for wide in wides() {
                assert_eq!(pack_window(&r, &g, &b, wide), want, "{r:?}, wide {wide}");
            }
        }
    }

    /// The row, group and lane stores write what [`Pixel::store`] writes pixel by pixel,
    /// for every row length, and nothing past the pixels they are given.
    #[test]
    fn packed_stores_match_store() {
        let read = |v: &[Out<u8>]| -> Vec<u8> {
            v.iter()
                // SAFETY: every sample was initialised (7) before the stores wrote some.
                .map(|v| unsafe { v.assume_init() })
                .collect()
        };
        let value = |k: usize| ((k * 37 % 101) as f32 / 90.0) - 0.05; // −0.05..1.06
        let mut c: RowColors = [[0.0; ROW_LANES]; 3];
        for (ch, plane) in c.iter_mut().enumerate() {
            for (k, v) in plane.iter_mut().enumerate() {
                *v = value(3 * k + ch);
            }
        }
        let want = |k: usize| {
            let mut px = [0u8; 3];
            u8::store(&mut px, lane(&c, k));
            px
        };
        for (px, wide) in (0..=TILE).flat_map(|px| wides().into_iter().map(move |w| (px, w))) {
            let mut dst = vec![Out::new(7u8); 3 * px + 4];
            u8::store_row(&mut dst[..3 * px], &c, wide);
            let got = read(&dst);
            for k in 0..px {
                assert_eq!(got[3 * k..3 * k + 3], want(k), "row of {px}, pixel {k}");
            }
            assert_eq!(got[3 * px..], [7; 4], "row of {px} wrote past its end");
        }
        let lanes: [Lanes; 3] = std::array::from_fn(|ch| c[ch][..LANES].try_into().unwrap());
        let mut dst = [Out::new(7u8); 3 * LANES + 1];
        u8::store_group(&mut dst[..3 * LANES], &lanes, false);
        let got = read(&dst);
        for k in 0..LANES {
            assert_eq!(got[3 * k..3 * k + 3], want(k), "group pixel {k}");
        }
        assert_eq!(got[3 * LANES], 7, "group wrote past its end");
        // Scattered lanes, consecutive runs of every length (one ending at the row's end,
        // where four-byte writes must not run past it), and runs broken by a row or a gap.
        let mut cases: Vec<Vec<(usize, usize)>> =
            vec![(0..LANES - 1).map(|k| (0, 5 * k + 1)).collect()];
        for n in 1..=LANES {
            cases.push((0..n).map(|k| (0, 3 + k)).collect());
            cases.push((0..n).map(|k| (1, TILE - n + k)).collect());
        }
        cases.push(
            (0..LANES)
                .map(|k| (usize::from(k == LANES - 1), 2 + k))
                .collect(),
        );
        cases.push(
            (0..LANES)
                .map(|k| (1, 2 + k + usize::from(k > 3)))
                .collect(),
        );
        for at in cases {
            let mut rows = [[Out::new(7u8); 3 * TILE]; 2];
            let [r0, r1] = &mut rows;
            u8::store_lanes(&mut [&mut r0[..], &mut r1[..]], &at, &lanes, false);
            for (j, row) in rows.iter().enumerate() {
                let got = read(row);
                for i in 0..TILE {
                    let lane = at.iter().position(|&a| a == (j, i));
                    let expect = lane.map_or([7; 3], want);
                    assert_eq!(got[3 * i..3 * i + 3], expect, "{at:?}: row {j} pixel {i}");
                }
            }
        }
        // Rows of stored pixels (flat's runs), every length, for both sample types.
        let colors: Vec<Vec3> = (0..TILE).map(|k| lane(&c, k)).collect();
        for px in 0..=TILE {
            let stored: Vec<u32> = colors[..px].iter().map(|&v| u8::stored(v)).collect();
            let mut dst = vec![Out::new(7u8); 3 * px + 4];
            u8::put_stored(&mut dst[..3 * px], &stored);
            let got = read(&dst);
            for k in 0..px {
                assert_eq!(
                    got[3 * k..3 * k + 3],
                    want(k),
                    "stored row of {px}, pixel {k}"
                );
            }
            assert_eq!(
                got[3 * px..],
                [7; 4],
                "stored row of {px} wrote past its end"
            );
            let stored: Vec<[f32; 3]> = colors[..px].iter().map(|&v| f32::stored(v)).collect();
            let mut dst = vec![Out::new(7.0f32); 3 * px + 1];
            f32::put_stored(&mut dst[..3 * px], &stored);
            // SAFETY: every sample was initialised (7) before the stores wrote some.
            let got: Vec<f32> = dst.iter().map(|v| unsafe { v.assume_init() }).collect();
            for (k, v) in colors[..px].iter().enumerate() {
                let mut want = [0.0f32; 3];
                f32::store(&mut want, *v);
                assert_eq!(
                    got[3 * k..3 * k + 3],
                    want,
                    "f32 stored row of {px}, pixel {k}"
                );
            }
            assert_eq!(
                got[3 * px],
                7.0,
                "f32 stored row of {px} wrote past its end"
            );
        }
    }
}
