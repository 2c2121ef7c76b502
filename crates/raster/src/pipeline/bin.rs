//! Binning: which triangles touch which screen tile, in submission order.

use super::setup::SetupTri;
use super::tiles::TILE;

/// Per-tile triangle lists stored flat: tile `t` owns `items[offsets[t]..offsets[t + 1]]`.
#[derive(Debug, Default)]
pub(crate) struct Bins {
    pub offsets: Vec<usize>,
    pub items: Vec<u32>,
}

impl Bins {
    pub fn tile(&self, t: usize) -> &[u32] {
        &self.items[self.offsets[t]..self.offsets[t + 1]]
    }
}

#[inline]
fn tile_range(t: &SetupTri) -> (usize, usize, usize, usize) {
    let [x0, y0, x1, y1] = t.bbox.map(|v| v as usize);
    (x0 / TILE, y0 / TILE, x1 / TILE, y1 / TILE)
}

/// Counting sort of triangles into tiles by bounding box (two passes, no per-tile vectors).
/// Triangle ids stay in increasing order inside every bin, which keeps the result identical
/// for any thread count.
pub(crate) fn bin(tris: &[SetupTri], tiles_x: usize, tiles_y: usize) -> Bins {
    let n = tiles_x * tiles_y;
    let mut offsets = vec![0usize; n + 1];
    for t in tris {
        let (tx0, ty0, tx1, ty1) = tile_range(t);
        for ty in ty0..=ty1 {
            for tx in tx0..=tx1 {
                offsets[ty * tiles_x + tx + 1] += 1;
            }
        }
    }
    for i in 0..n {
        offsets[i + 1] += offsets[i];
    }
    let mut cursor = offsets.clone();
    let mut items = vec![0u32; offsets[n]];
    for (id, t) in tris.iter().enumerate() {
        let (tx0, ty0, tx1, ty1) = tile_range(t);
        for ty in ty0..=ty1 {
            for tx in tx0..=tx1 {
                let c = &mut cursor[ty * tiles_x + tx];
                items[*c] = id as u32;
                *c += 1;
            }
        }
    }
    Bins { offsets, items }
}
