//! The runs of equal triangle ids along a row of a tile's visibility buffer: what every
//! shading loop walks. A row's run ends are found at once, eight ids per compare, into a
//! bit mask; each run is then a bit scan (a scan of the ids per run, one id at a time past
//! the first four, was a third of a flat tile's time on meshes of small triangles).

use crate::lighting::LANES;
use crate::pipeline::raster::{TileBuffers, ID_PAD};
use crate::pipeline::tiles::TILE;

/// One run: pixels `start..end` of the row are covered by triangle `id` (or by none,
/// [`NO_TRIANGLE`](crate::pipeline::raster::NO_TRIANGLE)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Run {
    pub id: u32,
    pub start: usize,
    pub end: usize,
}

impl Run {
    /// The run's pixels widened to whole groups of [`LANES`] from its start, for loops that
    /// write a row buffer a group at a time: the last group spills into the next run's
    /// pixels, which that run then overwrites. Ends before `TILE + LANES`.
    #[inline(always)]
    pub fn whole_lanes(&self) -> std::ops::Range<usize> {
        self.start..self.start + (self.end - self.start).div_ceil(LANES) * LANES
    }
}

/// The runs of row `j` of `buf` over its first `w` pixels, left to right.
#[inline(always)]
pub(super) fn row_runs(buf: &TileBuffers, j: usize, w: usize) -> Runs<'_> {
    // The row and the id after it: the padding makes that exist for the last row.
    const _: () = assert!(ID_PAD >= 1);
    let ids = &buf.id[j * TILE..j * TILE + TILE + 1];
    Runs {
        ids,
        ends: run_ends(ids, w),
        start: 0,
    }
}

/// Iterator of [`Run`]s (see [`row_runs`]).
pub(super) struct Runs<'a> {
    ids: &'a [u32],
    /// Bit `i` set: a run ends at pixel `i`; cleared as runs are taken.
    ends: u64,
    start: usize,
}

impl Iterator for Runs<'_> {
    type Item = Run;

    #[inline(always)]
    fn next(&mut self) -> Option<Run> {
        if self.ends == 0 {
            return None;
        }
        let end = self.ends.trailing_zeros() as usize + 1;
        self.ends &= self.ends - 1;
        let start = std::mem::replace(&mut self.start, end);
        Some(Run {
            id: self.ids[start],
            start,
            end,
        })
    }
}

/// Bit `i` (i < `w`) set where a run ends at pixel `i`: `ids[i] != ids[i + 1]`, or `i` is
/// the last pixel. `ids` holds the row and at least the id after its `TILE`-th (read, not
/// used, past `w`): whole groups of [`LANES`] compared with the group one id on.
#[inline(always)]
fn run_ends(ids: &[u32], w: usize) -> u64 {
    debug_assert!((1..=TILE).contains(&w) && ids.len() > TILE);
    let mut ends = 0u64;
    for g in 0..w.div_ceil(LANES) {
        let at = g * LANES;
        let a: &[u32; LANES] = ids[at..at + LANES].try_into().unwrap();
        let b: &[u32; LANES] = ids[at + 1..at + 1 + LANES].try_into().unwrap();
        ends |= u64::from(differ(a, b)) << at;
    }
    let last = 1u64 << (w - 1);
    (ends | last) & (last | (last - 1))
}

/// Bit `l` set where `a[l] != b[l]`, in SSE2 (part of x86-64): two compares of four ids
/// and a move of their sign bits, about ten instructions a group. The lane loop
/// ([`differ_lanes`]) compiled to about 35 mixed vector and scalar ones, which callgrind
/// put at 8 % of a Gouraud frame of small triangles (this: 2 % faster there, 4 % for flat).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn differ(a: &[u32; LANES], b: &[u32; LANES]) -> u8 {
    use std::arch::x86_64::*;
    const _: () = assert!(LANES == 8);
    // SAFETY: SSE2 is part of x86-64; each unaligned load reads four of an array's eight
    // u32, at offset 0 or 4.
    unsafe {
        let (pa, pb) = (a.as_ptr().cast::<__m128i>(), b.as_ptr().cast::<__m128i>());
        let lo = _mm_cmpeq_epi32(_mm_loadu_si128(pa), _mm_loadu_si128(pb));
        let hi = _mm_cmpeq_epi32(_mm_loadu_si128(pa.add(1)), _mm_loadu_si128(pb.add(1)));
        let eq =
            _mm_movemask_ps(_mm_castsi128_ps(lo)) | (_mm_movemask_ps(_mm_castsi128_ps(hi)) << 4);
        !(eq as u8)
    }
}

/// [`differ`] elsewhere.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn differ(a: &[u32; LANES], b: &[u32; LANES]) -> u8 {
    differ_lanes(a, b)
}

/// [`differ`] as a lane loop: its definition.
#[cfg(any(test, not(target_arch = "x86_64")))]
#[inline(always)]
fn differ_lanes(a: &[u32; LANES], b: &[u32; LANES]) -> u8 {
    let mut m = 0u8;
    for l in 0..LANES {
        m |= u8::from(a[l] != b[l]) << l;
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The runs by the definition: a scan of the ids.
    fn scanned(ids: &[u32], w: usize) -> Vec<Run> {
        let mut out = Vec::new();
        let mut start = 0;
        while start < w {
            let id = ids[start];
            let end = start + ids[start..w].iter().take_while(|&&v| v == id).count();
            out.push(Run { id, start, end });
            start = end;
        }
        out
    }

    #[test]
    fn runs_match_a_scan_of_the_row() {
        // Every width, rows of runs of every length 1..=20 (and one run over the whole row),
        // with the ids past the width (the next row's, the padding) equal to the row's last
        // or not: a run must end at the width either way.
        let mut buf = TileBuffers::new();
        let mut seed = 7u32;
        for w in 1..=TILE {
            for len in (1..=20).chain([TILE]) {
                for tail_same in [false, true] {
                    for (j, k) in [(0, 0), (TILE - 1, 1)] {
                        let row = &mut buf.id[j * TILE..];
                        for (i, v) in row.iter_mut().take(TILE + 1).enumerate() {
                            *v = if i < w {
                                (i / len) as u32 % 3 + k
                            } else if tail_same {
                                ((w - 1) / len) as u32 % 3 + k
                            } else {
                                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                                seed
                            };
                        }
                        let got: Vec<Run> = row_runs(&buf, j, w).collect();
                        let want = scanned(&buf.id[j * TILE..], w);
                        // Ids cycle 0, 1, 2: neighbours always differ, so runs have `len`.
                        assert_eq!(got, want, "w {w} len {len} tail_same {tail_same} row {j}");
                        assert_eq!(got.len(), w.div_ceil(len));
                        for r in &got {
                            let g = r.whole_lanes();
                            assert!(g.start == r.start && g.end >= r.end);
                            assert!(g.len() % LANES == 0 && g.len() - (r.end - r.start) < LANES);
                            assert!(g.end < TILE + LANES);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn differ_is_its_lane_loop() {
        // Every pattern of equal and unequal lanes, with ids that differ in the bottom bit,
        // the top (sign) bit only, or in every bit (no signed compare may treat them as
        // equal).
        for pattern in 0..=255u8 {
            for flip in [1u32, 1 << 31, u32::MAX] {
                let a: [u32; LANES] = std::array::from_fn(|l| 0x5a5a_0000 + l as u32);
                let b: [u32; LANES] = std::array::from_fn(|l| {
                    if pattern >> l & 1 == 1 {
                        a[l] ^ flip
                    } else {
                        a[l]
                    }
                });
                assert_eq!(
                    differ(&a, &b),
                    pattern,
                    "pattern {pattern:08b} flip {flip:x}"
                );
                assert_eq!(differ_lanes(&a, &b), pattern);
            }
        }
    }
}
