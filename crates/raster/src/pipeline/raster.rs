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

    fn clear(&mut self) {
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
pub(crate) fn rasterize_tile(tris: &Binned, index: usize, rect: TileRect, buf: &mut TileBuffers) {
    buf.clear();
    let (depth, ids) = (&mut *buf.depth, &mut *buf.id);
    for_each_covered(tris.tile(index), rect, |slot, z, id| {
        if z > depth[slot] {
            depth[slot] = z;
            ids[slot] = id;
        }
    });
}

/// Calls `f(slot, z, id)` for every pixel centre of the tile covered by one of `tris`
/// (in the given order); `slot` is `row · TILE + column` within the tile.
#[inline(always)]
pub(crate) fn for_each_covered<'a>(
    tris: impl Iterator<Item = (u32, &'a SetupTri)>,
    rect: TileRect,
    mut f: impl FnMut(usize, f32, u32),
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
        let (px, py) = (x0 * ONE + HALF, y0 * ONE + HALF);
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
            let zrow = z0 + dzdy * j as f32;
            if width >= SPAN_MIN_WIDTH {
                // Wide rows: solve each edge for the covered span exactly, then fill it.
                if let Some((lo, hi)) = row_span(row, step_x, width) {
                    for i in lo..=hi {
                        f(base + i, zrow + dzdx * i as f32, id);
                    }
                }
            } else {
                let [mut e0, mut e1, mut e2] = row;
                for i in 0..width as usize {
                    if (e0 | e1 | e2) >= 0 {
                        f(base + i, zrow + dzdx * i as f32, id);
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
