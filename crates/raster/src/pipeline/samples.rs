//! Multi-sample visibility and its resolve: the tile target with room for N samples.
//!
//! With `samples = N > 1` a tile is rasterized once per sample position (coverage and depth
//! at each sample, the same exact edge functions and fill rule as the pixel centre, so a
//! closed mesh stays watertight per sample). The samples of a pixel are then grouped by the
//! triangle that owns them into *layers*: layer 0 holds, for every pixel, the triangle (or
//! the background) covering most of its samples, layer 1 the next, and so on. Each layer is
//! an ordinary single-sample visibility buffer, so the shading loops of every mode shade it
//! unchanged, once per pixel per visible triangle, at the pixel centre. The resolve weighs
//! each layer's colour with the share of samples it covers and is the only code that writes
//! the user's colour rows; the depth output is layer 0's (the majority surface's eye depth,
//! +inf where the background covers most samples).
//!
//! With one sample the shading loops write the user's rows directly (their store is the
//! resolve): that path is exactly the single-sample renderer and pays nothing for this room.

use super::bin::Binned;
use super::raster::{self, TileBuffers, ID_LEN, NO_TRIANGLE};
use super::setup::{SetupTri, HALF, ONE};
use super::shade::{self, Out, Pixel, RowColors, ShadeContext, ROW_LANES};
use super::tiles::{TileRect, TILE};
use crate::options::ShadingMode;

/// Standard sample positions (Direct3D 11 / Vulkan `standardSampleLocations`), in 1/16 pixel
/// from the pixel centre, y down, for 1, 2, 4, 8 and 16 samples.
const PATTERN_1: [(i8, i8); 1] = [(0, 0)];
const PATTERN_2: [(i8, i8); 2] = [(4, 4), (-4, -4)];
const PATTERN_4: [(i8, i8); 4] = [(-2, -6), (6, -2), (-6, 2), (2, 6)];
const PATTERN_8: [(i8, i8); 8] = [
    (1, -3),
    (-1, 3),
    (5, 1),
    (-3, -5),
    (-5, 5),
    (-7, -1),
    (3, 7),
    (7, -7),
];
const PATTERN_16: [(i8, i8); 16] = [
    (1, 1),
    (-1, -3),
    (-3, 2),
    (4, -1),
    (-5, -2),
    (2, 5),
    (5, 3),
    (3, -5),
    (-2, 6),
    (0, -7),
    (-4, -6),
    (-6, 4),
    (-8, 0),
    (7, -4),
    (6, 7),
    (-7, -8),
];

/// The sample positions of `n` samples per pixel (one of
/// [`SAMPLE_COUNTS`](crate::options::SAMPLE_COUNTS)), in 1/16 pixel from the centre.
pub(crate) fn pattern(n: u32) -> &'static [(i8, i8)] {
    match n {
        2 => &PATTERN_2,
        4 => &PATTERN_4,
        8 => &PATTERN_8,
        16 => &PATTERN_16,
        _ => &PATTERN_1,
    }
}

/// Fixed-point units per 1/16 pixel.
const SIXTEENTH: i64 = ONE / 16;

/// The sample positions of `n` samples per pixel as fixed-point offsets from the centre.
#[inline]
pub(crate) fn offsets(n: usize) -> impl Iterator<Item = (i64, i64)> {
    pattern(n as u32)
        .iter()
        .map(|&(sx, sy)| (sx as i64 * SIXTEENTH, sy as i64 * SIXTEENTH))
}

/// How far (fixed-point units) the samples of `n` reach from the pixel centre: triangle
/// setup widens its pixel bounds by this, so a triangle that covers a sample but no pixel
/// centre is still drawn.
pub(crate) fn margin(n: u32) -> i64 {
    pattern(n)
        .iter()
        .map(|&(x, y)| (x as i64).abs().max((y as i64).abs()))
        .max()
        .unwrap_or(0)
        * SIXTEENTH
}

/// A worker's buffers for multi-sample tiles, reused across tiles (nothing is allocated for
/// one sample).
pub(crate) struct SampleTarget {
    /// One visibility buffer per sample position.
    samples: Vec<TileBuffers>,
    /// Layer k: the pixel's k-th triangle by coverage, with its depth at the pixel centre.
    layers: Vec<TileBuffers>,
    /// Samples each layer covers, per pixel.
    counts: Vec<[u8; TILE * TILE]>,
    /// Σ count · colour per pixel, channel-major.
    acc: Vec<[f32; TILE * TILE]>,
    /// One layer's shaded colours, as the shading loops write them (row-major RGB).
    layer_color: Vec<Out<f32>>,
    /// Layers the last tile wrote (those above 0 are cleared before the next).
    dirty: usize,
}

impl SampleTarget {
    /// Buffers for `n` samples per pixel (none for one).
    pub fn new(n: u32) -> Self {
        let n = if n > 1 { n as usize } else { 0 };
        SampleTarget {
            samples: (0..n).map(|_| TileBuffers::new()).collect(),
            layers: (0..n).map(|_| TileBuffers::new()).collect(),
            counts: vec![[0; TILE * TILE]; n],
            acc: if n > 0 {
                vec![[0.0; TILE * TILE]; 3]
            } else {
                Vec::new()
            },
            layer_color: if n > 0 {
                vec![Out::new(0.0); TILE * TILE * 3]
            } else {
                Vec::new()
            },
            dirty: 0,
        }
    }
}

impl SampleTarget {
    /// Whether this target has room for several samples (it is empty for one).
    pub fn is_multi(&self) -> bool {
        !self.samples.is_empty()
    }

    /// The owner of every pixel at each sample position of the tile last rasterized, in
    /// pattern order.
    pub fn sample_ids(&self) -> impl Iterator<Item = &[u32; ID_LEN]> {
        self.samples.iter().map(|s| &*s.id)
    }

    /// Rasterizes the triangles of tile `index` that `keep` accepts (in submission order)
    /// at every sample position, each into its own visibility buffer.
    #[inline(always)]
    pub fn rasterize_where(
        &mut self,
        tris: &Binned,
        index: usize,
        rect: TileRect,
        keep: impl Fn(&SetupTri) -> bool,
    ) {
        let n = self.samples.len();
        for (buf, offset) in self.samples.iter_mut().zip(offsets(n)) {
            buf.clear();
            let kept = tris.tile(index).filter(|(_, t)| keep(t));
            raster::for_each_span_at(kept, rect, offset, buf);
        }
    }

    /// Groups each pixel's samples by owner into the layers (see [`build_layers`]); returns
    /// how many layers the tile uses.
    pub fn layer(&mut self, ctx: &ShadeContext<'_>, rect: TileRect) -> usize {
        build_layers(ctx, rect, self)
    }

    /// Layer `k` of the tile last grouped (a single-sample visibility buffer: per pixel its
    /// k-th owner by coverage and that owner's depth at the pixel centre).
    pub fn layer_buffer(&self, k: usize) -> &TileBuffers {
        &self.layers[k]
    }

    /// How many samples of pixel `slot` layer `k` covers (0: the layer has no owner there).
    #[inline]
    pub fn layer_count(&self, k: usize, slot: usize) -> u8 {
        self.counts[k][slot]
    }

    /// The visibility buffer of sample position `s` of the tile last rasterized.
    pub fn sample_buffer(&self, s: usize) -> &TileBuffers {
        &self.samples[s]
    }

    /// Samples per pixel.
    pub fn per_pixel(&self) -> usize {
        self.samples.len()
    }

    /// The share of each pixel's samples owned by a triangle in the tile last rendered,
    /// into `rows`.
    pub fn write_coverage(&self, rect: TileRect, rows: &mut [&mut [Out<f32>]]) {
        let inv_n = 1.0 / self.samples.len() as f32;
        for (j, row) in rows.iter_mut().enumerate().take(rect.h) {
            for (i, o) in row[..rect.w].iter_mut().enumerate() {
                let slot = j * TILE + i;
                let covered: u32 = self
                    .layers
                    .iter()
                    .zip(&self.counts)
                    .filter(|(l, _)| l.id[slot] != NO_TRIANGLE)
                    .map(|(_, c)| c[slot] as u32)
                    .sum();
                o.write(covered as f32 * inv_n);
            }
        }
    }
}

/// Rasterizes tile `index` at every sample position, shades each layer and resolves into
/// the user's rows. `AFFINE` as for [`shade::shade_tile`]; `WIDE`: textured layers shaded
/// with AVX2 + FMA, which the caller must have checked the CPU has (the same bits).
#[inline(always)]
pub(crate) fn sample_tile<P: Pixel, const AFFINE: bool, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    index: usize,
    rect: TileRect,
    target: &mut SampleTarget,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    let n = target.samples.len();
    for (buf, offset) in target.samples.iter_mut().zip(offsets(n)) {
        raster::rasterize_tile_at(ctx.tris, index, rect, offset, buf);
    }
    let used = build_layers(ctx, rect, target);
    let SampleTarget {
        layers,
        counts,
        acc,
        layer_color,
        ..
    } = target;
    let mut depth = depth;
    for (k, (layer, count)) in layers[..used].iter().zip(counts.iter()).enumerate() {
        let mut rows: Vec<&mut [Out<f32>]> = layer_color
            .chunks_mut(TILE * 3)
            .take(rect.h)
            .map(|r| &mut r[..rect.w * 3])
            .collect();
        // Layer 0 covers every pixel (a triangle or the background), so it alone writes the
        // depth output: each depth sample once.
        let layer_depth = if k == 0 { depth.take() } else { None };
        if ctx.textured.is_some() {
            shade::shade_textured_tile::<f32, AFFINE, WIDE>(
                ctx,
                mode,
                rect,
                layer,
                &mut rows,
                layer_depth,
            );
        } else {
            shade::shade_tile::<f32, AFFINE>(ctx, mode, rect, layer, &mut rows, layer_depth);
        }
        accumulate(rect, &rows, count, acc, k == 0);
    }
    resolve(rect, acc, n, color, ctx.wide());
}

/// Groups each pixel's samples by owner into the layers (most samples first, ties in
/// sample order); returns how many layers the tile uses.
fn build_layers(ctx: &ShadeContext<'_>, rect: TileRect, target: &mut SampleTarget) -> usize {
    let n = target.samples.len();
    // Layers above 0 start empty: clear the ones the previous tile wrote (layer 0 is
    // written at every pixel below).
    for k in 1..target.dirty {
        target.layers[k].id.fill(NO_TRIANGLE);
        target.counts[k].fill(0);
    }
    let mut cached: Option<(u32, DepthPlane)> = None;
    let mut centre_depth = |id: u32, x: usize, y: usize| -> f32 {
        if id == NO_TRIANGLE {
            return -1.0;
        }
        let plane = match cached {
            Some((c, p)) if c == id => p,
            _ => {
                let p = DepthPlane::new(ctx.tris.get(id));
                cached = Some((id, p));
                p
            }
        };
        plane.at(x, y)
    };
    let mut used = 1;
    for j in 0..rect.h {
        for i in 0..rect.w {
            let slot = j * TILE + i;
            let (x, y) = (rect.x0 + i, rect.y0 + j);
            let first = target.samples[0].id[slot];
            if target.samples[1..].iter().all(|s| s.id[slot] == first) {
                // Inside a triangle (or the background): one layer, every sample.
                target.layers[0].id[slot] = first;
                target.layers[0].depth[slot] = centre_depth(first, x, y);
                target.counts[0][slot] = n as u8;
                continue;
            }
            // Distinct owners and their counts, in sample order (at most 16).
            let mut ids = [NO_TRIANGLE; 16];
            let mut cnt = [0u8; 16];
            let mut m = 0;
            for s in &target.samples {
                let id = s.id[slot];
                match ids[..m].iter().position(|&v| v == id) {
                    Some(p) => cnt[p] += 1,
                    None => {
                        ids[m] = id;
                        cnt[m] = 1;
                        m += 1;
                    }
                }
            }
            // Stable by count, descending: ties keep sample order.
            let mut order = [0usize; 16];
            for (k, o) in order[..m].iter_mut().enumerate() {
                *o = k;
            }
            order[..m].sort_by(|&a, &b| cnt[b].cmp(&cnt[a]));
            for (k, &o) in order[..m].iter().enumerate() {
                let layer = &mut target.layers[k];
                layer.id[slot] = ids[o];
                layer.depth[slot] = centre_depth(ids[o], x, y);
                target.counts[k][slot] = cnt[o];
            }
            used = used.max(m);
        }
    }
    target.dirty = used;
    used
}

/// A triangle's window depth as an exact plane over fixed-point pixel positions, as the
/// visibility pass computes it (barycentrics from the edge functions, in f64).
#[derive(Clone, Copy)]
struct DepthPlane {
    a: f64,
    b: f64,
    c: f64,
}

impl DepthPlane {
    fn new(t: &SetupTri) -> Self {
        let e = t.edges();
        let inv_area = 1.0 / t.area2 as f64;
        let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
        for k in 0..3 {
            let z = t.z[k] as f64 * inv_area;
            a += e.a[k] as f64 * z;
            b += e.b[k] as f64 * z;
            c += e.c[k] as f64 * z;
        }
        DepthPlane { a, b, c }
    }

    /// Depth at the centre of pixel (x, y).
    fn at(&self, x: usize, y: usize) -> f32 {
        let px = (x as i64 * ONE + HALF) as f64;
        let py = (y as i64 * ONE + HALF) as f64;
        (self.a * px + self.b * py + self.c) as f32
    }
}

/// Triangle `t`'s window depth at the centre of pixel (x, y), as the layers hold it.
pub(crate) fn centre_depth(t: &SetupTri, x: usize, y: usize) -> f32 {
    DepthPlane::new(t).at(x, y)
}

/// `acc (=|+=) count · colour` over the tile's pixels.
#[inline(always)]
fn accumulate(
    rect: TileRect,
    rows: &[&mut [Out<f32>]],
    count: &[u8; TILE * TILE],
    acc: &mut [[f32; TILE * TILE]],
    first: bool,
) {
    for (j, row) in rows.iter().enumerate() {
        for i in 0..rect.w {
            let slot = j * TILE + i;
            let w = count[slot] as f32;
            for (ch, a) in acc.iter_mut().enumerate() {
                // SAFETY: the shading loops wrote every sample of the rows they were given
                // (each tile writes every pixel of its rows: background or shaded).
                let c = unsafe { row[i * 3 + ch].assume_init() };
                // A layer that does not cover the pixel (weight 0) holds the background,
                // which is finite, so it adds exactly 0.
                let v = w * c;
                a[slot] = if first { v } else { a[slot] + v };
            }
        }
    }
}

/// Writes `acc / n` into the user's rows: the only write of a multi-sample tile's colour
/// (`wide`: the render runs on AVX2, see [`Pixel::store_row`]).
#[inline(always)]
fn resolve<P: Pixel>(
    rect: TileRect,
    acc: &[[f32; TILE * TILE]],
    n: usize,
    color: &mut [&mut [Out<P>]],
    wide: bool,
) {
    // n is a power of two: multiplying by 1/n is exact, so a pixel whose samples all belong
    // to one surface gets exactly that surface's colour, as with one sample.
    let inv_n = 1.0 / n as f32;
    let mut row_colors: RowColors = [[0.0; ROW_LANES]; 3];
    for (j, out) in color.iter_mut().enumerate().take(rect.h) {
        for (ch, a) in acc.iter().enumerate() {
            for i in 0..rect.w {
                row_colors[ch][i] = a[j * TILE + i] * inv_n;
            }
        }
        P::store_row(&mut out[..rect.w * 3], &row_colors, wide);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_have_n_distinct_positions_inside_the_pixel() {
        for n in crate::options::SAMPLE_COUNTS {
            let p = pattern(n);
            assert_eq!(p.len(), n as usize);
            for (k, a) in p.iter().enumerate() {
                assert!(
                    (-8..8).contains(&a.0) && (-8..8).contains(&a.1),
                    "{n}: {a:?}"
                );
                assert!(!p[..k].contains(a), "{n}: {a:?} twice");
            }
        }
        assert_eq!(margin(1), 0);
        assert_eq!(margin(4), 6 * SIXTEENTH);
        assert_eq!(margin(16), 8 * SIXTEENTH);
    }

    #[test]
    fn patterns_have_their_centroid_near_the_pixel_centre() {
        // The standard patterns are balanced: the mean offset is within 1/16 px.
        for n in crate::options::SAMPLE_COUNTS {
            let p = pattern(n);
            let (sx, sy) = p
                .iter()
                .fold((0i32, 0i32), |(a, b), &(x, y)| (a + x as i32, b + y as i32));
            assert!(
                sx.abs() <= n as i32 && sy.abs() <= n as i32,
                "{n}: {sx} {sy}"
            );
        }
    }
}
