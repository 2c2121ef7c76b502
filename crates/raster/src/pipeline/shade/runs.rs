//! Flat and Gouraud: a run of equal triangle ids at a time, their few planes stepped along
//! the run, colours stored a whole row of lanes at a time when nothing else is asked.

use glam::Vec3;

use super::planes::{PlaneCache, RunPlanes, RunStart};
use super::store::{fill_out, put, store_out, Out, Pixel, RowColors, ROW_LANES};
use super::{background_row, ShadeContext, FLAT, GOURAUD};
use crate::lighting::LANES;
use crate::pipeline::raster::{TileBuffers, NO_TRIANGLE};
use crate::pipeline::tiles::{TileRect, TILE};

/// Length of the run of `id` at the start of `ids` (at least 1 when `ids[0] == id`).
#[inline(always)]
pub(super) fn run_length(ids: &[u32], id: u32) -> usize {
    let mut n = 0;
    // Four ids per compare while the run lasts (one SIMD compare), then one at a time.
    while let Some(chunk) = ids.get(n..n + 4) {
        if chunk != [id; 4] {
            break;
        }
        n += 4;
    }
    n + ids[n..].iter().take_while(|&&v| v == id).count()
}

/// Gouraud runs up to this long are shaded a pixel at a time: a whole lane loop and row
/// store would cost more than they save (small triangles).
const SHORT_RUN: usize = 4;

/// Entries of the per-tile flat colour cache.
const FLAT_CACHE: usize = 64;

/// Flat and Gouraud, a run of equal triangle ids at a time: the run's planes are evaluated
/// once at its first pixel and stepped along it (f64 throughout, so stepping adds nothing
/// measurable: 64 steps at most).
#[inline(always)]
pub(super) fn shade_runs<P: Pixel, const MODE: u8, const FOG: bool, const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    mut depth: Option<&mut [&mut [Out<f32>]]>,
) {
    // Fog needs every pixel's eye depth, like the depth output.
    let want_depth = depth.is_some() || FOG;
    let mut planes = PlaneCache::<RunPlanes>::new();
    let background = background_row::<P>(ctx);
    let mut lin: RowColors = [[0.0; ROW_LANES]; 3];
    // Stored samples of recently seen flat colours, direct-mapped by id: the rows of a
    // triangle alternate with its neighbours', so a last-id cache would miss on every row.
    let mut flat_cache = [(NO_TRIANGLE, [P::default(); 3]); FLAT_CACHE];
    for j in 0..rect.h {
        let row = &mut color[j][..rect.w * 3];
        let ids = &buf.id[j * TILE..j * TILE + rect.w];
        let zs = &buf.depth[j * TILE..j * TILE + rect.w];
        let mut depth_row = depth.as_deref_mut().map(|d| &mut d[j][..rect.w]);
        let y = (rect.y0 + j) as f64 + 0.5;
        let mut i = 0;
        while i < rect.w {
            let id = ids[i];
            let end = i + run_length(&ids[i..], id);
            let out = &mut row[i * 3..end * 3];
            if id == NO_TRIANGLE {
                put(out, &background[..out.len()]);
                if let Some(d) = depth_row.as_deref_mut() {
                    fill_out(&mut d[i..end], f32::INFINITY);
                }
            } else if MODE == FLAT && !want_depth {
                let entry = &mut flat_cache[id as usize % FLAT_CACHE];
                if entry.0 != id {
                    entry.0 = id;
                    P::store(&mut entry.1, ctx.tris.get(id).flat);
                }
                for px in out.chunks_exact_mut(3) {
                    put(px, &entry.1);
                }
            } else {
                let t = ctx.tris.get(id);
                let pl = planes.get(id, || RunPlanes::new::<MODE, AFFINE>(ctx, t));
                let run = RunStart::new::<MODE>(&pl, (rect.x0 + i) as f64 + 0.5, y);
                if MODE == GOURAUD && !want_depth && end - i > SHORT_RUN {
                    // The common case, kept free of depth and fog: the run's colours into
                    // a row buffer over whole [`LANES`] (SIMD), then stored.
                    let n = (end - i).div_ceil(LANES) * LANES;
                    let [lr, lg, lb] = &mut lin;
                    let rows = lr[..n].iter_mut().zip(&mut lg[..n]).zip(&mut lb[..n]);
                    for (k, ((cr, cg), cb)) in rows.enumerate() {
                        // Via i32: one SIMD conversion (runs are at most 64 pixels).
                        let kf = k as i32 as f64;
                        [*cr, *cg, *cb] = run.color(kf, 1.0 / run.inv_w(kf));
                    }
                    P::store_row(out, &lin);
                } else {
                    for (k, px) in out.chunks_exact_mut(3).enumerate() {
                        let kf = k as f64;
                        let inv_w = run.inv_w(kf);
                        let eye_depth =
                            ctx.eye_depth::<AFFINE>(want_depth, zs[i + k], inv_w as f32);
                        if let Some(d) = depth_row.as_deref_mut() {
                            d[i + k].write(eye_depth);
                        }
                        let c = if MODE == FLAT {
                            t.flat
                        } else {
                            Vec3::from_array(run.color(kf, 1.0 / inv_w))
                        };
                        let (px_x, px_y) = (rect.x0 + i + k, rect.y0 + j);
                        store_out(px, ctx.fogged::<FOG>(c, px_x, px_y, eye_depth));
                    }
                }
            }
            i = end;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_length_counts_the_leading_run() {
        // Every run length 0..=20 after and before other ids, around the 4-wide chunks.
        for n in 0..=20usize {
            for tail in [vec![], vec![7], vec![7, 5, 5, 5, 5]] {
                let mut ids = vec![5u32; n];
                ids.extend(&tail);
                if ids.is_empty() {
                    continue;
                }
                let want = ids.iter().take_while(|&&v| v == ids[0]).count();
                assert_eq!(run_length(&ids, ids[0]), want, "{ids:?}");
            }
        }
    }
}
