//! Binning: which triangles touch which screen tile, in submission order.
//!
//! Each primitive-stage chunk bins its own triangles (in parallel with the other chunks);
//! a tile then walks the chunks in order, so it sees triangles in submission order without
//! any global merge or copy.

use super::setup::SetupTri;
use super::tiles::TILE;

/// Bits of a triangle id that index within its chunk; the rest is the chunk index.
pub(crate) const LOCAL_BITS: u32 = 16;

/// Set-up triangles of one chunk and their per-tile lists.
#[derive(Debug, Default)]
pub(crate) struct Chunk {
    pub tris: Vec<SetupTri>,
    pub bins: Bins,
    /// The object all of the chunk's triangles belong to.
    pub object: u32,
    /// Pieces of clipped triangles: (index in `tris`, the original triangle's vertices), in
    /// order; flat shading lights the original triangle, not the piece.
    pub clipped_from: Vec<(u32, [u32; 3])>,
}

impl Chunk {
    /// The triangles of this chunk (the `c`-th) touching tile `t`, as (id, triangle), in
    /// submission order.
    #[inline(always)]
    pub fn tile(&self, c: usize, t: usize) -> impl Iterator<Item = (u32, &SetupTri)> + '_ {
        let tris = &self.tris;
        self.bins
            .tile(t)
            .iter()
            .map(move |&l| (((c as u32) << LOCAL_BITS) | l, &tris[l as usize]))
    }
}

/// All set-up triangles, addressed by id `chunk << LOCAL_BITS | local`.
#[derive(Debug, Default)]
pub(crate) struct Binned {
    pub chunks: Vec<Chunk>,
}

impl Binned {
    #[inline]
    pub fn get(&self, id: u32) -> &SetupTri {
        &self.chunks[(id >> LOCAL_BITS) as usize].tris[(id & ((1 << LOCAL_BITS) - 1)) as usize]
    }

    /// The triangles touching tile `t`, as (id, triangle), in submission order.
    pub fn tile(&self, t: usize) -> impl Iterator<Item = (u32, &SetupTri)> + '_ {
        self.chunks
            .iter()
            .enumerate()
            .flat_map(move |(c, chunk)| chunk.tile(c, t))
    }

    /// Whether no triangle touches tile `t`.
    pub fn tile_is_empty(&self, t: usize) -> bool {
        self.chunks.iter().all(|c| c.bins.tile(t).is_empty())
    }

    /// Number of set-up triangles.
    pub fn len(&self) -> usize {
        self.chunks.iter().map(|c| c.tris.len()).sum()
    }
}

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
