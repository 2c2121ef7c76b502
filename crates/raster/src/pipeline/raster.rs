//! Visibility pass: rasterize a tile's bin into a tile-local depth + triangle-id buffer.
//!
//! Coverage uses exact i64 edge functions over 16.8 fixed-point vertices with the top-left
//! fill rule, so meshes are watertight. Depth is reversed-Z (larger is nearer) with a strict
//! `>` test: among equal depths the first-submitted triangle wins, independent of threads.

use super::bin::Binned;
use super::setup::{SetupTri, HALF, ONE, SUBPIXEL_BITS};
use super::tiles::{TileRect, TILE};

/// Triangle id of an empty pixel.
pub(crate) const NO_TRIANGLE: u32 = u32::MAX;

/// Ids after a tile's last row, so that every row can be read with the id after it (run
/// ends are found by comparing each id with the next, whole rows at a time).
pub(crate) const ID_PAD: usize = 1;

/// Length of a tile's id buffer: the tile's pixels and [`ID_PAD`].
pub(crate) const ID_LEN: usize = TILE * TILE + ID_PAD;

/// Depth + id buffers for one tile, reused across tiles by a worker.
pub(crate) struct TileBuffers {
    pub depth: Box<[f32; TILE * TILE]>,
    pub id: Box<[u32; ID_LEN]>,
}

impl TileBuffers {
    pub fn new() -> Self {
        TileBuffers {
            depth: Box::new([0.0; TILE * TILE]),
            id: Box::new([NO_TRIANGLE; ID_LEN]),
        }
    }

    pub(crate) fn clear(&mut self) {
        self.depth.fill(EMPTY_DEPTH);
        self.id.fill(NO_TRIANGLE);
    }
}

/// The depth of a slot no triangle covers: below every valid reversed-Z depth, so even a
/// surface exactly on the far plane (z = 0) is drawn.
pub(crate) const EMPTY_DEPTH: f32 = -1.0;

/// Rows at least this wide compute their covered span with one division per edge instead
/// of testing every pixel.
const SPAN_MIN_WIDTH: i64 = 12;

/// Triangles whose box in a tile is at most `WINDOW_MAX_WIDTH` pixels wide and at least
/// `WINDOW_MIN_HEIGHT` rows tall are tested 8 pixels of a row at a time ([`windows`]) by the
/// visibility buffer. Wider ones cost less by spans; shorter ones (a million-triangle mesh's,
/// about 3 × 3 pixels at 1080p) a pixel at a time: from 3 rows up, the (then inlined) windows
/// made the 998k-triangle sphere's frame 4.4 % costlier.
const WINDOW_MIN_HEIGHT: i64 = 6;
const WINDOW_MAX_WIDTH: i64 = 16;

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
    rasterize_into(tris, index, rect, buf);
}

/// The triangles binned to tile `index` (in submission order) into `sink`.
#[inline(always)]
fn rasterize_into(tris: &Binned, index: usize, rect: TileRect, sink: &mut impl SpanSink) {
    // A chunk at a time: through `Binned::tile`'s flattened iterator, each triangle cost an
    // out-of-line `FlatMap::next` call (about 20 M instructions a frame of the 998k-triangle
    // sphere).
    for (c, chunk) in tris.chunks.iter().enumerate() {
        for_each_span(chunk.tile(c, index), rect, sink);
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
    buf.clear();
    rasterize_into(tris, index, rect, &mut WideBuffers(buf));
}

/// The depths alone of the triangles binned to tile `index` into `depth` (a depth pass,
/// which reads no ids): the same depths as [`rasterize_tile`]'s, without clearing or
/// writing a triangle id per slot.
#[inline(always)]
pub(crate) fn rasterize_depth_tile(
    tris: &Binned,
    index: usize,
    rect: TileRect,
    depth: &mut [f32; TILE * TILE],
) {
    depth.fill(EMPTY_DEPTH);
    rasterize_into(tris, index, rect, &mut DepthOnly(depth));
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

    /// Whether [`SpanSink::small`] may take a triangle.
    const SMALL: bool = false;

    /// Takes a small triangle of the tile whole (its box clipped to the tile: `bbox`, a
    /// whole tile), returning false when the caller must walk it by spans and pixels.
    #[inline(always)]
    fn small(&mut self, _t: &SetupTri, _id: u32, _at: TriangleAt) -> bool {
        false
    }
}

/// Where a small triangle is drawn: its box clipped to the tile (pixels, inclusive), the
/// tile's origin and the sample offset (fixed point).
#[derive(Clone, Copy)]
pub(crate) struct TriangleAt {
    pub bbox: [i64; 4],
    pub tile: (i64, i64),
    pub offset: (i64, i64),
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

    const SMALL: bool = true;

    #[inline(always)]
    fn small(&mut self, t: &SetupTri, id: u32, at: TriangleAt) -> bool {
        small_baseline(self, t, id, at)
    }
}

/// A tile's depth buffer alone, for [`rasterize_depth_tile`]: each covered slot keeps the
/// larger of its depth and the triangle's, as [`depth_test`] does, with no id. Small
/// triangles go by spans and pixels (the windows path writes ids; both give the same
/// depths, which the tests below hold them to).
struct DepthOnly<'a>(&'a mut [f32; TILE * TILE]);

impl SpanSink for DepthOnly<'_> {
    #[inline(always)]
    fn span(&mut self, s: Span) {
        depth_only_span(&s, &mut self.0[..]);
    }

    #[inline(always)]
    fn pixel(&mut self, slot: usize, z: f32, _id: u32) {
        let d = &mut self.0[slot];
        if z > *d {
            *d = z;
        }
    }
}

/// [`depth_test_span`] without ids: windows of 8 slots as one `max` of their depths and the
/// span's (`maxps` is `z > d ? z : d`, NaN and ±0 included, which is `depth_test`'s rule).
#[inline(always)]
fn depth_only_span(s: &Span, depth: &mut [f32]) {
    const LANES: usize = 8;
    let depth = &mut depth[s.start..s.start + s.len];
    if s.len < LANES {
        for (k, d) in depth.iter_mut().enumerate() {
            let z = s.z_at(k);
            if z > *d {
                *d = z;
            }
        }
        return;
    }
    let mut k0 = 0;
    loop {
        let k0_window = k0.min(s.len - LANES);
        let dw: &mut [f32; LANES] = (&mut depth[k0_window..k0_window + LANES])
            .try_into()
            .unwrap();
        depth_only_window(&s.z_window(k0_window), dw);
        k0 += LANES;
        if k0 >= s.len {
            return;
        }
    }
}

/// `dw[k] = z[k] > dw[k] ? z[k] : dw[k]` for 8 slots, in SSE2 (every x86-64).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn depth_only_window(z: &[f32; 8], dw: &mut [f32; 8]) {
    use std::arch::x86_64::*;
    // SAFETY: SSE2 is part of x86-64; both pointers are to 8 lanes of 4 bytes, read and
    // written as two unaligned halves. `maxps(z, d)` returns d unless z > d.
    unsafe {
        let dp = dw.as_mut_ptr();
        let (z0, z1) = (_mm_loadu_ps(z.as_ptr()), _mm_loadu_ps(z.as_ptr().add(4)));
        let (d0, d1) = (_mm_loadu_ps(dp), _mm_loadu_ps(dp.add(4)));
        _mm_storeu_ps(dp, _mm_max_ps(z0, d0));
        _mm_storeu_ps(dp.add(4), _mm_max_ps(z1, d1));
    }
}

/// [`depth_only_window`] elsewhere: the lane loop.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn depth_only_window(z: &[f32; 8], dw: &mut [f32; 8]) {
    for k in 0..8 {
        dw[k] = if z[k] > dw[k] { z[k] } else { dw[k] };
    }
}

/// The visibility buffer of a tile on AVX2 + FMA: as [`TileBuffers`], with small triangles
/// taken by the AVX2 copy of [`small_triangle`].
#[cfg(target_arch = "x86_64")]
struct WideBuffers<'a>(&'a mut TileBuffers);

#[cfg(target_arch = "x86_64")]
impl SpanSink for WideBuffers<'_> {
    #[inline(always)]
    fn span(&mut self, s: Span) {
        self.0.span(s);
    }

    #[inline(always)]
    fn pixel(&mut self, slot: usize, z: f32, id: u32) {
        self.0.pixel(slot, z, id);
    }

    const SMALL: bool = true;

    #[inline(always)]
    fn small(&mut self, t: &SetupTri, id: u32, at: TriangleAt) -> bool {
        // SAFETY: a `WideBuffers` is only made by `rasterize_tile_avx2`, which runs after
        // `Isa::detect` found AVX2 and FMA.
        unsafe { small_avx2(self.0, t, id, at) }
    }
}

/// [`small_triangle`] out of line (so the main loop compiles as without it) for the baseline.
#[inline(never)]
fn small_baseline(buf: &mut TileBuffers, t: &SetupTri, id: u32, at: TriangleAt) -> bool {
    small_triangle(buf, t, id, at)
}

/// The same on AVX2 + FMA.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
unsafe fn small_avx2(buf: &mut TileBuffers, t: &SetupTri, id: u32, at: TriangleAt) -> bool {
    small_triangle(buf, t, id, at)
}

/// A small triangle 8 pixels of a row at a time ([`windows`]); false when its edge values
/// could leave i32 (nothing drawn then).
#[inline(always)]
fn small_triangle(buf: &mut TileBuffers, t: &SetupTri, id: u32, at: TriangleAt) -> bool {
    let [x0, y0, x1, y1] = at.bbox;
    let start = RowStart::new(t, x0, y0, at.offset);
    let pos = ((x0 - at.tile.0) as usize, (y0 - at.tile.1) as usize);
    let size = (x1 - x0 + 1, y1 - y0 + 1);
    windows(&start, pos, size, id, buf)
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
            // The same loads and compares, inlined next to these (nothing is stored in
            // between, so they are the values above).
            depth_window_blend(z, id, dw, iw);
        }
    }
}

/// [`depth_window`] without its branches: every window blended and stored whole (what
/// `depth_window` does to a mixed window). A small triangle's windows are mostly mixed
/// (its edges cross them), and which of the three cases a window is depends on the data,
/// so the branches there were mispredicted.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn depth_window_blend(z: &[f32; 8], id: u32, dw: &mut [f32; 8], iw: &mut [u32; 8]) {
    use std::arch::x86_64::*;
    // SAFETY: as `depth_window`'s.
    unsafe {
        let (dp, ip) = (dw.as_mut_ptr(), iw.as_mut_ptr().cast::<__m128i>());
        let (z0, z1) = (_mm_loadu_ps(z.as_ptr()), _mm_loadu_ps(z.as_ptr().add(4)));
        let (d0, d1) = (_mm_loadu_ps(dp), _mm_loadu_ps(dp.add(4)));
        let (n0, n1) = (_mm_cmpgt_ps(z0, d0), _mm_cmpgt_ps(z1, d1));
        let pick =
            |n: __m128, a: __m128, b: __m128| _mm_or_ps(_mm_and_ps(n, a), _mm_andnot_ps(n, b));
        _mm_storeu_ps(dp, pick(n0, z0, d0));
        _mm_storeu_ps(dp.add(4), pick(n1, z1, d1));
        let vf = _mm_castsi128_ps(_mm_set1_epi32(id as i32));
        let i0 = _mm_castsi128_ps(_mm_loadu_si128(ip));
        let i1 = _mm_castsi128_ps(_mm_loadu_si128(ip.add(1)));
        _mm_storeu_si128(ip, _mm_castps_si128(pick(n0, vf, i0)));
        _mm_storeu_si128(ip.add(1), _mm_castps_si128(pick(n1, vf, i1)));
    }
}

/// [`depth_window_blend`] elsewhere: the lane loops.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn depth_window_blend(z: &[f32; 8], id: u32, dw: &mut [f32; 8], iw: &mut [u32; 8]) {
    depth_window(z, id, dw, iw);
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
pub(crate) fn for_each_span_at<'a, S: SpanSink>(
    tris: impl Iterator<Item = (u32, &'a SetupTri)>,
    rect: TileRect,
    offset: (i64, i64),
    sink: &mut S,
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
        let width = x1 - x0 + 1;
        // Small triangles leave before the setup below, for an out-of-line path of their
        // own. Whole tiles only: in a tile cut by the image's right edge, a lane past the
        // box could be past the image but inside the triangle.
        if S::SMALL
            && width <= WINDOW_MAX_WIDTH
            && y1 - y0 + 1 >= WINDOW_MIN_HEIGHT
            && rect.w == TILE
        {
            let at = TriangleAt {
                bbox: [x0, y0, x1, y1],
                tile: (tx0, ty0),
                offset,
            };
            if sink.small(t, id, at) {
                continue;
            }
        }
        let RowStart {
            mut row,
            step_x,
            step_y,
            z: (z0, dzdx, dzdy),
        } = RowStart::new(t, x0, y0, offset);
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

/// A triangle's edge values and depth at the first pixel of its box in a tile, and their
/// steps per pixel.
struct RowStart {
    /// Edge values with the fill rule's bias (covered where all are ≥ 0).
    row: [i64; 3],
    /// Steps per pixel in x and in y (multiples of `ONE`).
    step_x: [i64; 3],
    step_y: [i64; 3],
    /// Depth at the first pixel, per pixel in x, per row.
    z: (f32, f32, f32),
}

impl RowStart {
    /// At pixel `(x0, y0)`, its sample point moved from the centre by `offset`.
    #[inline(always)]
    fn new(t: &SetupTri, x0: i64, y0: i64, offset: (i64, i64)) -> Self {
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
        RowStart {
            row,
            step_x,
            step_y,
            z: (z0 as f32, dzdx as f32, dzdy as f32),
        }
    }
}

/// The covered pixels of a triangle's box (`size` pixels from tile column and row `at`) into
/// `sink` 8 pixels of a row at a time, with no per-pixel branch: coverage as i32 lanes, each
/// uncovered lane's depth NaN (never nearer). `row` are the edge values (fill bias included)
/// at the box's first pixel, stepping `a` per pixel in x and `b` in y (times `ONE`); then
/// the depth at that pixel and its steps, stepped exactly as a span steps them. Returns
/// false, doing nothing, when an edge value of a lane could leave i32.
///
/// The edge values are taken in whole pixels, `floor(e / ONE)`: as every step is a multiple
/// of `ONE`, `e + n·ONE·a ≥ 0` exactly when `floor(e / ONE) + n·a ≥ 0` (llvmpipe's trick),
/// which leaves room for triangles far bigger than a tile.
#[inline(always)]
fn windows(
    start: &RowStart,
    (cx0, cy0): (usize, usize),
    (width, height): (i64, i64),
    id: u32,
    buf: &mut TileBuffers,
) -> bool {
    let (z0, dzdx, dzdy) = start.z;
    // The steps in whole pixels (exact: multiples of `ONE`).
    let a = start.step_x.map(|v| v >> SUBPIXEL_BITS);
    let b = start.step_y.map(|v| v >> SUBPIXEL_BITS);
    let row = start.row;
    let e = row.map(|v| v >> SUBPIXEL_BITS);
    // Affine, so the largest |value| over the lanes' columns (up to 7 before the box and
    // 15 past its first column, with the last window moved back) is at a corner.
    let fits = (0..3)
        .all(|k| e[k].abs() + (width + 15) * a[k].abs() + (height - 1) * b[k].abs() < 1 << 30);
    if !fits {
        return false;
    }
    // Windows from a start column that keeps all of them in the tile row: a lane before
    // the box is then beside a box not cut by the tile's left edge, one past it beside a box
    // not cut by the right edge, so either lies outside the triangle (setup's box holds
    // every pixel with a covered sample point).
    let nwin = (width as usize).div_ceil(8);
    let first = cx0.min(TILE - 8 * nwin);
    let m0 = first as i32 - cx0 as i32;
    let a32 = a.map(|v| v as i32);
    const LANES: [i32; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    // Opaque to the optimiser: with lane 0's offset folded to a constant 0, its lane no
    // longer looked like the others and LLVM left half the lanes scalar.
    let lanes = std::hint::black_box(LANES);
    let [o0, o1, o2] = a32.map(|a| lanes.map(|l| l.wrapping_mul(a)));
    let rows = WindowRows {
        edges: e.map(|v| v as i32),
        a: a32,
        step: b.map(|v| v as i32),
        lanes: [o0, o1, o2],
        m0,
        slot: cy0 * TILE + first,
        height: height as usize,
        z: (z0, dzdx, dzdy),
        id,
    };
    // The window count as a constant, so the loop over windows unrolls (with a run-time
    // count, LLVM kept it a loop and the path cost more than the pixel loop it replaces).
    if nwin == 1 {
        rows.draw::<1>(buf);
    } else {
        rows.draw::<2>(buf);
    }
    true
}

/// A small triangle's window walk: [`windows`]' values, per row of its box.
struct WindowRows {
    /// Edge values in whole pixels at the box's first pixel.
    edges: [i32; 3],
    /// Steps per pixel in x and per row, whole pixels.
    a: [i32; 3],
    step: [i32; 3],
    /// Each edge's step times the lane index.
    lanes: [[i32; 8]; 3],
    /// Column of the first window's lane 0 relative to the box's first pixel (≤ 0).
    m0: i32,
    /// Tile slot of the first window's lane 0 in the box's first row.
    slot: usize,
    height: usize,
    /// Depth at the box's first pixel, per pixel in x, per row.
    z: (f32, f32, f32),
    id: u32,
}

impl WindowRows {
    /// `N` windows of 8 pixels per row (the box is at most `8 N` pixels wide).
    #[inline(always)]
    fn draw<const N: usize>(&self, buf: &mut TileBuffers) {
        const LANE: [f32; 8] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        let (z0, dzdx, dzdy) = self.z;
        let [o0, o1, o2] = self.lanes;
        let mut er = self.edges;
        for j in 0..self.height {
            let z_row = z0 + dzdy * j as f32;
            let slot = self.slot + j * TILE;
            for w in 0..N {
                // Lane l is pixel m + l of the box's row.
                let m = self.m0 + 8 * w as i32;
                let [s0, s1, s2] = [0, 1, 2].map(|k| er[k].wrapping_add(m.wrapping_mul(self.a[k])));
                // As `Span::z_window`: the f32 column is exact, so these are its values.
                let base = m as f32;
                let z = LANE.map(|k| z_row + dzdx * (base + k));
                let v: [i32; 8] = std::array::from_fn(|l| {
                    s0.wrapping_add(o0[l]) | s1.wrapping_add(o1[l]) | s2.wrapping_add(o2[l])
                });
                // An uncovered lane (an edge value's sign set) gets the exponent and quiet
                // bit of a NaN, with bit operations only so the lanes stay SIMD (branches or
                // selects here made LLVM split them into scalars).
                let z: [f32; 8] = std::array::from_fn(|l| {
                    f32::from_bits(z[l].to_bits() | ((v[l] >> 31) as u32 & 0x7fc0_0000))
                });
                let at = slot + 8 * w;
                let dw: &mut [f32; 8] = (&mut buf.depth[at..at + 8]).try_into().unwrap();
                let iw: &mut [u32; 8] = (&mut buf.id[at..at + 8]).try_into().unwrap();
                // A NaN depth is never nearer, so uncovered lanes keep their slots.
                depth_window_blend(&z, self.id, dw, iw);
            }
            // Indexed: the zipped form cost 1.3 M more instructions a 99-ring frame.
            #[allow(clippy::needless_range_loop)]
            for k in 0..3 {
                er[k] = er[k].wrapping_add(self.step[k]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The depth pass's window keeps `depth_test`'s rule bit for bit on every pair of
    /// awkward depths: NaN on either side, zeros of both signs, infinities.
    #[test]
    fn depth_only_window_is_the_depth_test() {
        let vals = [
            f32::NAN,
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for (a, &za) in vals.iter().enumerate() {
            for (b, &da) in vals.iter().enumerate() {
                // Every pair in lane 0 and lane 5 (both halves), others mixed around them.
                let z: [f32; 8] =
                    std::array::from_fn(|k| if k % 5 == 0 { za } else { vals[(a + k) % 8] });
                let d: [f32; 8] = std::array::from_fn(|k| {
                    if k % 5 == 0 {
                        da
                    } else {
                        vals[(b + 3 * k) % 8]
                    }
                });
                let mut got = d;
                depth_only_window(&z, &mut got);
                for k in 0..8 {
                    let (mut want, mut id) = (d[k], 0);
                    depth_test(&mut want, &mut id, z[k], 1);
                    assert_eq!(got[k].to_bits(), want.to_bits(), "z {} d {}", z[k], d[k]);
                }
            }
        }
    }

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

        /// The 8-pixel windows of small triangles leave exactly the visibility the span and
        /// pixel paths leave (a sink without the small-triangle path), on the baseline and on
        /// AVX2, at the pixel centre and at sample
        /// offsets, for triangles of every size and at every tile position, in tiles cut by
        /// the image's edge too.
        #[test]
        fn windows_match_spans_and_pixels(
            tris in proptest::collection::vec(
                (0i32..210 * 256, 0i32..150 * 256, -4000i32..4000, -4000i32..4000,
                 -4000i32..4000, -4000i32..4000, 0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0),
                1..40,
            ),
            offset in (-100i64..100, -100i64..100),
            scale in 0u32..3,
        ) {
            use super::super::setup::{setup, Setup};
            use super::super::tiles::tile_rects;
            /// The span and pixel paths alone, into the same buffers.
            struct NoWindows(TileBuffers);
            impl SpanSink for NoWindows {
                fn span(&mut self, s: Span) {
                    self.0.span(s);
                }
                fn pixel(&mut self, slot: usize, z: f32, id: u32) {
                    self.0.pixel(slot, z, id);
                }
            }
            let (w, h) = (200usize, 140usize);
            let set_up: Vec<SetupTri> = tris
                .iter()
                .filter_map(|&(x, y, dx1, dy1, dx2, dy2, z0, z1, z2)| {
                    // Small, medium and large triangles.
                    let k = [1, 8, 64][scale as usize];
                    let s = [
                        (x, y, z0, 1.0),
                        (x + dx1 * k / 8, y + dy1 * k / 8, z1, 1.0),
                        (x + dx2 * k / 8, y + dy2 * k / 8, z2, 1.0),
                    ];
                    // Boxes widened by the samples' reach, as the multi-sample target's.
                    match setup(s, [0, 1, 2], 0, (w as u32, h as u32), false, 100) {
                        Setup::Draw(t) => Some(t),
                        _ => None,
                    }
                })
                .collect();
            for rect in tile_rects(w, h) {
                let mut with = TileBuffers::new();
                let mut without = NoWindows(TileBuffers::new());
                with.clear();
                without.0.clear();
                let each = || set_up.iter().enumerate().map(|(i, t)| (i as u32, t));
                for_each_span_at(each(), rect, offset, &mut with);
                for_each_span_at(each(), rect, offset, &mut without);
                // The depth pass's sink: the same depths with no ids.
                let mut alone = Box::new([EMPTY_DEPTH; TILE * TILE]);
                for_each_span_at(each(), rect, offset, &mut DepthOnly(&mut alone));
                prop_assert_eq!(&with.id[..], &without.0.id[..]);
                let bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                prop_assert_eq!(bits(&with.depth[..]), bits(&without.0.depth[..]));
                prop_assert_eq!(bits(&alone[..]), bits(&with.depth[..]));
                // The AVX2 copy of the small-triangle path, where the CPU has it.
                #[cfg(target_arch = "x86_64")]
                if super::super::isa::Isa::detect(false) != super::super::isa::Isa::Baseline {
                    let mut wide = TileBuffers::new();
                    wide.clear();
                    for_each_span_at(each(), rect, offset, &mut WideBuffers(&mut wide));
                    prop_assert_eq!(&wide.id[..], &without.0.id[..]);
                    prop_assert_eq!(bits(&wide.depth[..]), bits(&without.0.depth[..]));
                }
            }
        }
    }
}
