//! Objects with different shading modes in one frame (`shading="auto"`): each tile's pixels
//! are grouped by their triangle's object's mode, each mode's own loop ([`shade_tile`])
//! shades its pixels, and every pixel is stored once from its mode's result.
//!
//! A tile whose visible triangles all share one mode (most tiles) runs that mode's loop
//! straight into the user's rows, exactly as a render with that mode. A tile with several
//! shades each mode into a tile-local f32 buffer with the other modes' pixels masked out
//! (the loops then see background there), and stores each pixel from its own mode's buffer:
//! the stored values are the ones that mode alone would have stored (`Pixel::store` of the
//! same colour), so a mixed frame is, pixel by pixel, the frame of each pixel's own mode.

use super::id_runs::{row_runs, Run};
use super::store::{put, Out, Pixel, RowColors, ROW_LANES};
use super::{shade_tile, ShadeContext};
use crate::options::ShadingMode;
use crate::pipeline::raster::{TileBuffers, NO_TRIANGLE};
use crate::pipeline::tiles::{TileRect, TILE};

const MODES: [ShadingMode; 3] = [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong];

/// Owner value of a pixel no triangle covers.
const BACKGROUND: u8 = 3;

/// A worker's buffers for tiles that mix modes (allocated on the first such tile).
#[derive(Default)]
pub(crate) struct MixedWork {
    /// Each pixel's mode (index into `MODES`, or [`BACKGROUND`]).
    owner: Vec<u8>,
    /// The visibility buffer with the other modes' pixels masked out.
    masked: Option<TileBuffers>,
    /// One mode's shaded colours (row-major RGB) and depths.
    color: Vec<Out<f32>>,
    depth: Vec<Out<f32>>,
    /// The tile's colours and depths, each pixel from its own mode.
    merged: Vec<f32>,
    merged_depth: Vec<f32>,
}

/// Shades one rasterized tile whose objects may have different modes (`modes`, per object)
/// into its output rows. `AFFINE` as for [`shade_tile`].
#[allow(clippy::too_many_arguments)]
pub(crate) fn shade_mixed_tile<P: Pixel, const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    modes: &[ShadingMode],
    rect: TileRect,
    buf: &TileBuffers,
    work: &mut MixedWork,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    work.owner.resize(TILE * TILE, BACKGROUND);
    let mut present = [false; 3];
    for j in 0..rect.h {
        for Run { id, start: i, end } in row_runs(buf, j, rect.w) {
            let m = if id == NO_TRIANGLE {
                BACKGROUND
            } else {
                let object = ctx.tris.get(id).object as usize;
                MODES.iter().position(|&x| x == modes[object]).unwrap_or(2) as u8
            };
            work.owner[j * TILE + i..j * TILE + end].fill(m);
            if m != BACKGROUND {
                present[m as usize] = true;
            }
        }
    }
    let used: Vec<usize> = (0..3).filter(|&k| present[k]).collect();
    if used.len() <= 1 {
        // One mode (or none) in this tile: its loop, straight into the user's rows.
        let mode = used.first().map_or(ShadingMode::Flat, |&k| MODES[k]);
        shade_tile::<P, AFFINE>(ctx, mode, rect, buf, color, depth);
        return;
    }
    let want_depth = depth.is_some();
    let masked = work.masked.get_or_insert_with(TileBuffers::new);
    masked.depth.copy_from_slice(&buf.depth[..]);
    work.color.resize(TILE * TILE * 3, Out::new(0.0));
    work.depth.resize(TILE * TILE, Out::new(0.0));
    work.merged.resize(TILE * TILE * 3, 0.0);
    work.merged_depth.resize(TILE * TILE, 0.0);
    for (pass, &k) in used.iter().enumerate() {
        let pixels = masked.id.iter_mut().zip(&buf.id[..]).zip(&work.owner);
        for ((m, &id), &owner) in pixels {
            *m = if owner == k as u8 { id } else { NO_TRIANGLE };
        }
        let mut rows: Vec<&mut [Out<f32>]> = work
            .color
            .chunks_mut(TILE * 3)
            .take(rect.h)
            .map(|r| &mut r[..rect.w * 3])
            .collect();
        let mut depth_rows: Vec<&mut [Out<f32>]> = work
            .depth
            .chunks_mut(TILE)
            .take(if want_depth { rect.h } else { 0 })
            .map(|r| &mut r[..rect.w])
            .collect();
        let d = want_depth.then_some(&mut depth_rows[..]);
        shade_tile::<f32, AFFINE>(ctx, MODES[k], rect, masked, &mut rows, d);
        // This mode's pixels, and on the first pass the background (every pass wrote it).
        for j in 0..rect.h {
            for i in 0..rect.w {
                let slot = j * TILE + i;
                let o = work.owner[slot];
                if o != k as u8 && !(pass == 0 && o == BACKGROUND) {
                    continue;
                }
                for ch in 0..3 {
                    // SAFETY: the shading loop wrote every sample of the rows it was given
                    // (each tile writes every pixel of its rows: background or shaded).
                    work.merged[slot * 3 + ch] = unsafe { rows[j][i * 3 + ch].assume_init() };
                }
                if want_depth {
                    // SAFETY: as above, for the depth rows it was given.
                    work.merged_depth[slot] = unsafe { depth_rows[j][i].assume_init() };
                }
            }
        }
    }
    let mut row_colors: RowColors = [[0.0; ROW_LANES]; 3];
    for (j, out) in color.iter_mut().enumerate().take(rect.h) {
        for i in 0..rect.w {
            for (ch, c) in row_colors.iter_mut().enumerate() {
                c[i] = work.merged[(j * TILE + i) * 3 + ch];
            }
        }
        P::store_row(&mut out[..rect.w * 3], &row_colors, ctx.wide());
    }
    if let Some(rows) = depth {
        for (j, out) in rows.iter_mut().enumerate().take(rect.h) {
            put(
                &mut out[..rect.w],
                &work.merged_depth[j * TILE..j * TILE + rect.w],
            );
        }
    }
}
