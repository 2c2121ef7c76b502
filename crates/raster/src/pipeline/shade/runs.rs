//! Flat and Gouraud: a run of equal triangle ids at a time, their few planes stepped along
//! the run, colours stored a whole row of lanes at a time when nothing else is asked.

use glam::Vec3;

use super::id_runs::{row_runs, Run};
use super::planes::{PlaneCache, RunColors, RunPlanes, RunStart};
use super::store::{fill_out, put, store_out, Out, Pixel, RowColors, ROW_LANES};
use super::{background_row, ShadeContext, FLAT, GOURAUD};
use crate::lighting::LANES;
use crate::pipeline::raster::{TileBuffers, NO_TRIANGLE};
use crate::pipeline::tiles::{TileRect, TILE};

/// Entries of the per-tile caches of [`RunPlanes`]: more than [`super::planes::PLANE_CACHE`],
/// as an entry is small (96 bytes) and a miss costs a plane set-up (about 200
/// instructions). With 64, a Gouraud frame of Spot (23,424 triangles at 512 × 512, 10,385
/// set up) made 16,677 set-ups, the triangles live in a tile's rows evicting each other;
/// with 256, 11,945 (a triangle that straddles tiles is set up once per tile).
const RUN_PLANES: usize = 256;

/// Entries of the per-tile flat colour cache.
const FLAT_CACHE: usize = 64;

/// Flat and Gouraud, a run of equal triangle ids at a time: the run's planes are evaluated
/// once and stepped along it (1/w for the depth in f64 from the run's first pixel, the
/// colour as [`RunColors`] from the row's first pixel, whatever the path).
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
    if MODE == GOURAUD && !want_depth {
        return gouraud_rows::<P, AFFINE>(ctx, rect, buf, color);
    }
    if MODE == FLAT && !want_depth {
        return flat_rows::<P>(ctx, rect, buf, color);
    }
    let mut planes = PlaneCache::<RunPlanes, RUN_PLANES>::new();
    let background = background_row::<P>(ctx);
    for j in 0..rect.h {
        let row = &mut color[j][..rect.w * 3];
        let zs = &buf.depth[j * TILE..j * TILE + rect.w];
        let mut depth_row = depth.as_deref_mut().map(|d| &mut d[j][..rect.w]);
        let y = (rect.y0 + j) as f64 + 0.5;
        for Run { id, start: i, end } in row_runs(buf, j, rect.w) {
            let out = &mut row[i * 3..end * 3];
            if id == NO_TRIANGLE {
                put(out, &background[..out.len()]);
                if let Some(d) = depth_row.as_deref_mut() {
                    fill_out(&mut d[i..end], f32::INFINITY);
                }
            } else {
                let t = ctx.tris.get(id);
                let pl = planes.get(id, || RunPlanes::new::<MODE, AFFINE>(ctx, t));
                let run = RunStart::new(&pl, (rect.x0 + i) as f64 + 0.5, y);
                // Flat needs only the 1/w plane (its colour is the triangle's).
                let colors =
                    (MODE == GOURAUD).then(|| RunColors::new(&pl, rect.x0 as f64 + 0.5, y));
                for (k, px) in out.chunks_exact_mut(3).enumerate() {
                    let kf = k as f64;
                    let inv_w = run.inv_w(kf);
                    let eye_depth = ctx.eye_depth::<AFFINE>(want_depth, zs[i + k], inv_w as f32);
                    if let Some(d) = depth_row.as_deref_mut() {
                        d[i + k].write(eye_depth);
                    }
                    let c = match &colors {
                        Some(colors) => Vec3::from_array(colors.at((i + k) as f32)),
                        None => t.flat,
                    };
                    let (px_x, px_y) = (rect.x0 + i + k, rect.y0 + j);
                    store_out(px, ctx.fogged::<FOG>(c, px_x, px_y, eye_depth));
                }
            }
        }
    }
}

/// Flat without depth output or fog, the common case: each tile row's stored pixels (one
/// value each, [`Pixel::Stored`]) filled a run at a time (whole [`LANES`], as Gouraud's
/// colours) into a row buffer and written out
/// once a row (four bytes a pixel for `u8`; a pixel at a time, three byte stores each, cost
/// a quarter of a flat frame at 1080p).
#[inline(always)]
fn flat_rows<P: Pixel>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
) {
    let background = P::stored(ctx.background);
    // Stored pixels of recently seen flat colours: the rows of a triangle alternate with
    // its neighbours', so a last-id cache would miss on every row.
    let mut flat = PlaneCache::<P::Stored, FLAT_CACHE>::new();
    let mut line = [P::Stored::default(); ROW_LANES];
    for (j, row) in color[..rect.h].iter_mut().enumerate() {
        for run in row_runs(buf, j, rect.w) {
            let id = run.id;
            let v = if id == NO_TRIANGLE {
                background
            } else {
                flat.get(id, || P::stored(ctx.tris.get(id).flat))
            };
            // Whole groups of LANES (one vector store each for u8), within ROW_LANES.
            for group in line[run.whole_lanes()].chunks_exact_mut(LANES) {
                group.fill(v);
            }
        }
        P::put_stored(&mut row[..rect.w * 3], &line[..rect.w]);
    }
}

/// Gouraud without depth output or fog, the common case: each tile row's linear colours
/// into a row buffer, every run (background ones too) over whole [`LANES`] (SIMD; a run's
/// last lanes spill into the next run's pixels, which that run then overwrites), and the
/// row stored once. Storing each run apart (and short runs a pixel at a time) cost more
/// than the colours on meshes of small triangles.
#[inline(always)]
fn gouraud_rows<P: Pixel, const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
) {
    let mut planes = PlaneCache::<RunPlanes, RUN_PLANES>::new();
    let bg = ctx.background.to_array();
    let mut lin: RowColors = [[0.0; ROW_LANES]; 3];
    for (j, row) in color[..rect.h].iter_mut().enumerate() {
        let y = (rect.y0 + j) as f64 + 0.5;
        for run in row_runs(buf, j, rect.w) {
            let (id, i, group) = (run.id, run.start, run.whole_lanes());
            let [lr, lg, lb] = &mut lin;
            let lanes = lr[group.clone()]
                .chunks_exact_mut(LANES)
                .zip(lg[group.clone()].chunks_exact_mut(LANES))
                .zip(lb[group].chunks_exact_mut(LANES));
            if id == NO_TRIANGLE {
                for ((cr, cg), cb) in lanes {
                    cr.fill(bg[0]);
                    cg.fill(bg[1]);
                    cb.fill(bg[2]);
                }
            } else {
                // The triangle is read only when its planes are not cached (a chain of
                // dependent loads, paid per run before).
                let pl = planes.get(id, || {
                    RunPlanes::new::<GOURAUD, AFFINE>(ctx, ctx.tris.get(id))
                });
                let colors = RunColors::new(&pl, rect.x0 as f64 + 0.5, y);
                for (c, ((cr, cg), cb)) in lanes.enumerate() {
                    for l in 0..LANES {
                        // Via i32: one SIMD conversion (k < TILE + LANES).
                        let k = (i + c * LANES + l) as i32 as f32;
                        [cr[l], cg[l], cb[l]] = colors.at(k);
                    }
                }
            }
        }
        P::store_row(&mut row[..rect.w * 3], &lin, ctx.wide());
    }
}
