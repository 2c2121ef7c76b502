//! Binning: which triangles touch which screen tile, in submission order.
//!
//! Each primitive-stage chunk bins its own triangles (in parallel with the other chunks);
//! a tile then walks the chunks in order, so it sees triangles in submission order without
//! any global merge or copy.

use super::setup::SetupTri;
use super::shade::prelight::Terms3;
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
    /// Textured flat only (else empty): each triangle's split terms
    /// ([`light_face_terms`](super::shade::prelight::light_face_terms)), indexed like `tris`.
    pub face_terms: Vec<Terms3>,
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

    /// Triangle `id`'s split terms, where they were lit before the tile stage (textured
    /// flat, [`Chunk::face_terms`]).
    #[inline]
    pub fn face_terms(&self, id: u32) -> Option<&Terms3> {
        self.chunks[(id >> LOCAL_BITS) as usize]
            .face_terms
            .get((id & ((1 << LOCAL_BITS) - 1)) as usize)
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

impl Drop for Binned {
    /// The chunks' triangle vectors go to the next frame ([`super::recycle`]).
    fn drop(&mut self) {
        super::recycle::give_back(self.chunks.iter_mut().map(|c| std::mem::take(&mut c.tris)));
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

/// Bins a chunk's triangles as setup makes them: each triangle's tile range is counted and
/// kept in an 8-byte record when it is pushed, so the 96-byte [`SetupTri`]s are not read
/// again (a separate binning pass read them twice, once to count and once to place).
#[derive(Debug)]
pub(crate) struct BinBuilder {
    tiles_x: usize,
    /// Triangles per tile, at `t + 1` (the prefix sum turns them into offsets in place).
    offsets: Vec<usize>,
    /// Tile range `(tx0, ty0, tx1, ty1)` of each triangle, in push order.
    ranges: Vec<[u16; 4]>,
}

impl BinBuilder {
    /// A builder for `tiles_x × tiles_y` tiles, with room for `capacity` triangles.
    pub fn new(tiles_x: usize, tiles_y: usize, capacity: usize) -> Self {
        BinBuilder {
            tiles_x,
            offsets: vec![0; tiles_x * tiles_y + 1],
            ranges: Vec::with_capacity(capacity),
        }
    }

    /// Records the next triangle (its index is the number pushed before it).
    #[inline(always)]
    pub fn push(&mut self, t: &SetupTri) {
        let r = tile_range(t);
        let (tx0, ty0, tx1, ty1) = (r[0] as usize, r[1] as usize, r[2] as usize, r[3] as usize);
        for ty in ty0..=ty1 {
            for tx in tx0..=tx1 {
                self.offsets[ty * self.tiles_x + tx + 1] += 1;
            }
        }
        self.ranges.push(r);
    }

    /// The per-tile lists: a counting sort, so ids stay in increasing order inside every bin
    /// (the same for any thread count).
    pub fn finish(self) -> Bins {
        let BinBuilder {
            tiles_x,
            mut offsets,
            ranges,
        } = self;
        let n = offsets.len() - 1;
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut cursor = offsets.clone();
        let mut items = vec![0u32; offsets[n]];
        for (id, r) in ranges.iter().enumerate() {
            let (tx0, ty0, tx1, ty1) = (r[0] as usize, r[1] as usize, r[2] as usize, r[3] as usize);
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
}

/// The tiles a triangle's pixel bounds touch: `(tx0, ty0, tx1, ty1)`, inclusive.
#[inline(always)]
fn tile_range(t: &SetupTri) -> [u16; 4] {
    // Pixel bounds are u16 and a tile is 64 pixels, so tile indices fit in u16.
    t.bbox.map(|v| (v as usize / TILE) as u16)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::setup::{setup, Setup, ONE};

    /// The builder's bins are the counting sort of the triangles' tile ranges: each tile
    /// lists, in increasing order, exactly the triangles whose pixel bounds touch it.
    #[test]
    fn builder_lists_each_triangle_in_the_tiles_it_touches() {
        let (w, h) = (300u32, 200u32);
        let (tx, ty) = (
            w.div_ceil(TILE as u32) as usize,
            h.div_ceil(TILE as u32) as usize,
        );
        let mut tris = Vec::new();
        let mut b = BinBuilder::new(tx, ty, 0);
        let mut seed = 12345u64;
        let mut next = |m: u64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 33) % m) as i32
        };
        while tris.len() < 200 {
            let s = [(); 3].map(|_| {
                let x = next(w as u64 + 40) - 20;
                let y = next(h as u64 + 40) - 20;
                (x * ONE as i32, y * ONE as i32, 0.5, 1.0)
            });
            if let Setup::Draw(t) = setup(s, [0, 1, 2], 0, (w, h), false, 0) {
                b.push(&t);
                tris.push(t);
            }
        }
        let bins = b.finish();
        for t in 0..tx * ty {
            let (x, y) = ((t % tx) * TILE, (t / tx) * TILE);
            let want: Vec<u32> = (0..tris.len() as u32)
                .filter(|&i| {
                    let bb = tris[i as usize].bbox.map(|v| v as usize);
                    bb[0] < x + TILE && bb[2] >= x && bb[1] < y + TILE && bb[3] >= y
                })
                .collect();
            assert_eq!(bins.tile(t), &want[..], "tile {t}");
        }
    }
}
