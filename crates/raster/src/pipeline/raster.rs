//! Visibility pass: rasterize a tile's bin into a tile-local depth + triangle-id buffer.
//!
//! Coverage uses exact i64 edge functions over 16.8 fixed-point vertices with the top-left
//! fill rule, so meshes are watertight. Depth is reversed-Z (larger is nearer) with a strict
//! `>` test: among equal depths the first-submitted triangle wins, independent of threads.

use super::bin::Binned;
use super::setup::{SetupTri, HALF, ONE};
use super::tiles::{TileRect, TILE};

/// Triangle id of an empty pixel.
pub(crate) const NO_TRIANGLE: u32 = u32::MAX;

/// Depth + id buffers for one tile, reused across tiles by a worker.
pub(crate) struct TileBuffers {
    pub depth: Box<[f32; TILE * TILE]>,
    pub id: Box<[u32; TILE * TILE]>,
}

impl TileBuffers {
    pub fn new() -> Self {
        TileBuffers {
            depth: Box::new([0.0; TILE * TILE]),
            id: Box::new([NO_TRIANGLE; TILE * TILE]),
        }
    }

    pub(crate) fn clear(&mut self) {
        // Below every valid reversed-Z depth, so even a surface exactly on the far plane
        // (z = 0) is drawn.
        self.depth.fill(-1.0);
        self.id.fill(NO_TRIANGLE);
    }
}

/// Rows at least this wide compute their covered span with one division per edge instead
/// of testing every pixel.
const SPAN_MIN_WIDTH: i64 = 12;

/// The pixels `i` in `0..width` with `e_k + i·step_k ≥ 0` for all three edges, if any.
#[inline]
fn row_span(e: [i64; 3], step: [i64; 3], width: i64) -> Option<(usize, usize)> {
    let (mut lo, mut hi) = (0i64, width - 1);
    for k in 0..3 {
        let (e, a) = (e[k], step[k]);
        if a > 0 {
            // e + a·i ≥ 0  ⇔  i ≥ ceil(−e / a)
            lo = lo.max(-(e.div_euclid(a)));
        } else if a < 0 {
            // e + a·i ≥ 0  ⇔  i ≤ floor(e / −a)
            hi = hi.min(e.div_euclid(-a));
        } else if e < 0 {
            return None;
        }
    }
    (lo <= hi).then_some((lo as usize, hi as usize))
}

/// Rasterizes the triangles binned to tile `index` (in submission order) into `buf`.
#[inline(always)]
pub(crate) fn rasterize_tile(tris: &Binned, index: usize, rect: TileRect, buf: &mut TileBuffers) {
    buf.clear();
    // A chunk at a time: through `Binned::tile`'s flattened iterator, each triangle cost an
    // out-of-line `FlatMap::next` call (about 20 M instructions a frame of the 998k-triangle
    // sphere).
    for (c, chunk) in tris.chunks.iter().enumerate() {
        for_each_span(chunk.tile(c, index), rect, buf);
    }
}

/// [`rasterize_tile`] compiled out of line, once per instruction set (`WIDE`: AVX2 + FMA,
/// which the caller checked): the visibility pass is the same for every pixel type and
/// shading body, so the code beside it in a tile body no longer changes how its loops are
/// compiled (and they are compiled once, not once per body).
#[inline(always)]
pub(crate) fn rasterize_tile_on<const WIDE: bool>(
    tris: &Binned,
    index: usize,
    rect: TileRect,
    buf: &mut TileBuffers,
) {
    #[cfg(target_arch = "x86_64")]
    if WIDE {
        // SAFETY: `WIDE` only in the bodies run after `Isa::detect` found AVX2 and FMA.
        unsafe { rasterize_tile_avx2(tris, index, rect, buf) };
        return;
    }
    rasterize_tile_baseline(tris, index, rect, buf);
}

#[inline(never)]
fn rasterize_tile_baseline(tris: &Binned, index: usize, rect: TileRect, buf: &mut TileBuffers) {
    rasterize_tile(tris, index, rect, buf);
}

/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
unsafe fn rasterize_tile_avx2(tris: &Binned, index: usize, rect: TileRect, buf: &mut TileBuffers) {
    rasterize_tile(tris, index, rect, buf);
}

/// [`rasterize_tile`] with every pixel's sample point moved from the centre by `offset`
/// (fixed-point units): one sample position of a multi-sample tile.
#[inline(always)]
pub(crate) fn rasterize_tile_at(
    tris: &Binned,
    index: usize,
    rect: TileRect,
    offset: (i64, i64),
    buf: &mut TileBuffers,
) {
    buf.clear();
    for (c, chunk) in tris.chunks.iter().enumerate() {
        for_each_span_at(chunk.tile(c, index), rect, offset, buf);
    }
}

/// What [`for_each_span`] hands its spans to. A trait with an `#[inline(always)]` method
/// rather than a closure, so the depth test is inlined into its caller's instruction set.
pub(crate) trait SpanSink {
    /// A covered span of a wide row.
    fn span(&mut self, s: Span);
    /// One covered pixel of a narrow row: tile slot, depth, triangle id (the depth is
    /// [`Span::z_at`]'s value for the same pixel).
    fn pixel(&mut self, slot: usize, z: f32, id: u32);
}

impl SpanSink for TileBuffers {
    #[inline(always)]
    fn span(&mut self, s: Span) {
        depth_test_span(&s, &mut self.depth[..], &mut self.id[..]);
    }

    #[inline(always)]
    fn pixel(&mut self, slot: usize, z: f32, id: u32) {
        depth_test(&mut self.depth[slot], &mut self.id[slot], z, id);
    }
}

/// The depth test of one pixel: strictly nearer (reversed Z) replaces depth and id, so among
/// equal depths the first-submitted triangle stays.
#[inline(always)]
fn depth_test(depth: &mut f32, slot_id: &mut u32, z: f32, id: u32) {
    if z > *depth {
        *depth = z;
        *slot_id = id;
    }
}

/// Depth test and write of one span: `s.len` slots of the tile from `s.start`. Spans of at
/// least [`LANES`](crate::lighting::LANES) go a window of [`LANES`](crate::lighting::LANES)
/// slots at a time ([`depth_window`]); the last window ends at the span's end, overlapping
/// the one before, which is harmless as testing a pixel against its own depth changes
/// nothing.
#[inline(always)]
fn depth_test_span(s: &Span, depth: &mut [f32], ids: &mut [u32]) {
    const LANES: usize = 8;
    let depth = &mut depth[s.start..s.start + s.len];
    let ids = &mut ids[s.start..s.start + s.len];
    if s.len < LANES {
        for (k, (d, i)) in depth.iter_mut().zip(ids).enumerate() {
            depth_test(d, i, s.z_at(k), s.id);
        }
        return;
    }
    let mut k0 = 0;
    loop {
        let k0_window = k0.min(s.len - LANES);
        let window = k0_window..k0_window + LANES;
        let dw: &mut [f32; LANES] = (&mut depth[window.clone()]).try_into().unwrap();
        let iw: &mut [u32; LANES] = (&mut ids[window]).try_into().unwrap();
        depth_window(&s.z_window(k0_window), s.id, dw, iw);
        k0 += LANES;
        if k0 >= s.len {
            return;
        }
    }
}

/// [`depth_test`] of 8 slots at once: a window where every pixel is nearer (the first
/// surface drawn there, or one in front of all) is stored whole, one where none is is left
/// alone, only a mixed one blends. With SSE2 (every x86-64) this is written with its
/// instructions: as lane loops, LLVM vectorised the window as 1 + 4 + 2 + 1 lanes with a
/// branch per scalar lane inside the tile bodies (about 50 instructions a window), however
/// the select was phrased.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn depth_window(z: &[f32; 8], id: u32, dw: &mut [f32; 8], iw: &mut [u32; 8]) {
    use std::arch::x86_64::*;
    // SAFETY: SSE2 is part of x86-64; every pointer is to 8 lanes of 4 bytes, read and
    // written as two unaligned halves of 4 lanes. `cmpgt` is `z > d` (false with a NaN),
    // and the and/andnot/or blend takes z's or d's bits whole, as `depth_test` does.
    unsafe {
        let (dp, ip) = (dw.as_mut_ptr(), iw.as_mut_ptr().cast::<__m128i>());
        let (z0, z1) = (_mm_loadu_ps(z.as_ptr()), _mm_loadu_ps(z.as_ptr().add(4)));
        let (d0, d1) = (_mm_loadu_ps(dp), _mm_loadu_ps(dp.add(4)));
        let (n0, n1) = (_mm_cmpgt_ps(z0, d0), _mm_cmpgt_ps(z1, d1));
        let mask = _mm_movemask_ps(n0) | _mm_movemask_ps(n1) << 4;
        let v = _mm_set1_epi32(id as i32);
        if mask == 0xff {
            _mm_storeu_ps(dp, z0);
            _mm_storeu_ps(dp.add(4), z1);
            _mm_storeu_si128(ip, v);
            _mm_storeu_si128(ip.add(1), v);
        } else if mask != 0 {
            let pick =
                |n: __m128, a: __m128, b: __m128| _mm_or_ps(_mm_and_ps(n, a), _mm_andnot_ps(n, b));
            _mm_storeu_ps(dp, pick(n0, z0, d0));
            _mm_storeu_ps(dp.add(4), pick(n1, z1, d1));
            let vf = _mm_castsi128_ps(v);
            let i0 = _mm_castsi128_ps(_mm_loadu_si128(ip));
            let i1 = _mm_castsi128_ps(_mm_loadu_si128(ip.add(1)));
            _mm_storeu_si128(ip, _mm_castps_si128(pick(n0, vf, i0)));
            _mm_storeu_si128(ip.add(1), _mm_castps_si128(pick(n1, vf, i1)));
        }
    }
}

/// [`depth_test`] of 8 slots at once, as lane loops (other architectures).
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn depth_window(z: &[f32; 8], id: u32, dw: &mut [f32; 8], iw: &mut [u32; 8]) {
    for k in 0..8 {
        let nearer = z[k] > dw[k];
        dw[k] = if nearer { z[k] } else { dw[k] };
        iw[k] = if nearer { id } else { iw[k] };
    }
}

/// The covered pixel centres of one triangle on one row of a tile: a triangle is convex, so
/// they are contiguous.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Span {
    /// Tile slot (`row · TILE + column`) of the first covered pixel.
    pub start: usize,
    pub len: usize,
    pub id: u32,
    /// Depth at the row's first pixel inside the bounding box, and its step per pixel.
    z_row: f32,
    dzdx: f32,
    /// Column of the span's first pixel counted from that first pixel.
    offset: usize,
}

impl Span {
    /// Depth at the span's `k`-th pixel (stepped in f32 from the row's start, so every
    /// caller sees the same value).
    #[inline(always)]
    pub fn z_at(&self, k: usize) -> f32 {
        // Via i32: converts in one SIMD instruction; columns are < 2^16.
        self.z_row + self.dzdx * (self.offset + k) as i32 as f32
    }

    /// [`Span::z_at`] of the 8 pixels from `k0`, bit-identical to it: the column of pixel
    /// `k0 + k` is the exact f32 sum of `k0`'s and `k` (integers below 2^24), written with
    /// a constant lane vector so the compiler vectorises it however the code around it is
    /// partitioned (an unrolled per-lane conversion stayed scalar in some builds).
    #[inline(always)]
    fn z_window(&self, k0: usize) -> [f32; 8] {
        const LANE: [f32; 8] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        let base = (self.offset + k0) as i32 as f32;
        LANE.map(|k| self.z_row + self.dzdx * (base + k))
    }
}

/// Hands `sink` every covered pixel of the tile for each of `tris` (in the given order),
/// row by row: a span at a time on wide rows, a pixel at a time on narrow ones.
#[inline(always)]
pub(crate) fn for_each_span<'a>(
    tris: impl Iterator<Item = (u32, &'a SetupTri)>,
    rect: TileRect,
    sink: &mut impl SpanSink,
) {
    for_each_span_at(tris, rect, (0, 0), sink);
}

/// [`for_each_span`] with the sample point of every pixel at its centre plus `offset`
/// (fixed-point units, each component within half a pixel).
#[inline(always)]
pub(crate) fn for_each_span_at<'a>(
    tris: impl Iterator<Item = (u32, &'a SetupTri)>,
    rect: TileRect,
    offset: (i64, i64),
    sink: &mut impl SpanSink,
) {
    let (tx0, ty0) = (rect.x0 as i64, rect.y0 as i64);
    let (tx1, ty1) = (tx0 + rect.w as i64 - 1, ty0 + rect.h as i64 - 1);
    for (id, t) in tris {
        let x0 = (t.bbox[0] as i64).max(tx0);
        let y0 = (t.bbox[1] as i64).max(ty0);
        let x1 = (t.bbox[2] as i64).min(tx1);
        let y1 = (t.bbox[3] as i64).min(ty1);
        if x0 > x1 || y0 > y1 {
            continue;
        }
        let e = t.edges();
        let (px, py) = (x0 * ONE + HALF + offset.0, y0 * ONE + HALF + offset.1);
        let mut row = [0i64; 3];
        let mut step_x = [0i64; 3];
        let mut step_y = [0i64; 3];
        // Depth plane from exact barycentrics at the first pixel, stepped in f32 from there.
        let inv_area = 1.0 / t.area2 as f64;
        let (mut z0, mut dzdx, mut dzdy) = (0.0f64, 0.0f64, 0.0f64);
        for k in 0..3 {
            let v = e.a[k] * px + e.b[k] * py + e.c[k];
            row[k] = v + e.bias[k];
            step_x[k] = e.a[k] * ONE;
            step_y[k] = e.b[k] * ONE;
            z0 += v as f64 * inv_area * t.z[k] as f64;
            dzdx += step_x[k] as f64 * inv_area * t.z[k] as f64;
            dzdy += step_y[k] as f64 * inv_area * t.z[k] as f64;
        }
        let (z0, dzdx, dzdy) = (z0 as f32, dzdx as f32, dzdy as f32);
        let width = x1 - x0 + 1;
        for (j, y) in (y0..=y1).enumerate() {
            let base = (y - ty0) as usize * TILE + (x0 - tx0) as usize;
            let z_row = z0 + dzdy * j as f32;
            if width >= SPAN_MIN_WIDTH {
                // Wide rows: solve each edge for the covered span exactly.
                if let Some((lo, hi)) = row_span(row, step_x, width) {
                    sink.span(Span {
                        start: base + lo,
                        len: hi - lo + 1,
                        id,
                        z_row,
                        dzdx,
                        offset: lo,
                    });
                }
            } else {
                // Narrow rows (small triangles): test and hand over pixel by pixel, which
                // measured faster than finding the span first.
                let [mut e0, mut e1, mut e2] = row;
                for i in 0..width as usize {
                    if (e0 | e1 | e2) >= 0 {
                        sink.pixel(base + i, z_row + dzdx * i as i32 as f32, id);
                    }
                    e0 += step_x[0];
                    e1 += step_x[1];
                    e2 += step_x[2];
                }
            }
            for k in 0..3 {
                row[k] += step_y[k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The windowed, branch-free depth test keeps exactly what a plain `z > depth` loop
        /// keeps, ties (the earlier triangle wins) included, and leaves every slot outside
        /// the span alone.
        #[test]
        fn span_depth_test_matches_the_scalar_loop(
            old in proptest::collection::vec((-2i32..3, 0u32..4), 64),
            start in 0usize..64,
            len in 1usize..40,
            z_row in -2i32..3,
            dz in -1i32..2,
            offset in 0usize..5,
        ) {
            let start = start.min(64 - len);
            // Quarter steps keep every depth exact, so ties really occur.
            let s = Span { start, len, id: 99, z_row: z_row as f32 * 0.25,
                           dzdx: dz as f32 * 0.25, offset };
            let mut depth: Vec<f32> = old.iter().map(|&(d, _)| d as f32 * 0.25).collect();
            let mut ids: Vec<u32> = old.iter().map(|&(_, i)| i).collect();
            let (mut want_d, mut want_i) = (depth.clone(), ids.clone());
            for k in 0..len {
                let z = s.z_at(k);
                if z > want_d[start + k] {
                    want_d[start + k] = z;
                    want_i[start + k] = s.id;
                }
            }
            depth_test_span(&s, &mut depth, &mut ids);
            prop_assert_eq!(depth, want_d);
            prop_assert_eq!(ids, want_i);
        }
    }
}
