//! Lines: triangle edges drawn over the image (`RenderOptions::edges`), a stage of its own.
//!
//! Once per render that asks for lines: the scene's edges are found ([`topology`]: vertices
//! welded by position, each undirected edge once with its faces), selected for the mode,
//! projected and binned to tiles ([`segments`]). Per tile, after the tile body has
//! rasterized and shaded into a tile-local f32 buffer, every visibility sample is tested
//! against the tile's segments ([`coverage`]: within half the width of the segment) and, for
//! hidden-line modes, against the visibility buffer ([`visibility`]); the share of a pixel's
//! samples some visible line covers is its line coverage α, and the pixel becomes
//! `(1 − α)·colour + α·edge_color` before the one store into the user's rows. A render
//! without lines never reaches this module: `passes::color_pass` picks its tile closure
//! once, and the tile bodies are those of every other render.

mod coverage;
mod segments;
mod topology;
mod visibility;

use glam::Vec3;

use super::bin::Binned;
use super::isa::{self, Isa, TileJob, Workspace};
use super::raster::{self, ID_LEN, NO_TRIANGLE};
use super::samples;
use super::setup::SetupTri;
use super::setup::ONE;
use super::shade::{Out, Pixel, RowColors, ShadeContext, ROW_LANES};
use super::tiles::{TileRect, TILE};
use super::vertex::Vertices;
use crate::camera::Camera;
use crate::options::{EdgeMode, RenderOptions, ShadingMode};
use crate::reflect::Kind;
use crate::scene::Scene;
use segments::Segments;
use topology::Topology;
use visibility::OwnerCache;

/// Rasterizes tile `index` into the worker's visibility buffers as the tile bodies do (the
/// single-sample buffer, or every sample position's), without shading: the triangles the
/// secondary stage blends are not in it, as in its opaque layer.
fn visibility_only(
    ctx: &ShadeContext<'_>,
    multi: bool,
    work: &mut Workspace,
    index: usize,
    rect: TileRect,
) {
    let blended = |t: &SetupTri| {
        ctx.secondary
            .as_ref()
            .is_some_and(|s| s.kinds[t.object as usize] == Kind::Blended)
    };
    if multi {
        work.target
            .rasterize_where(ctx.tris, index, rect, |t| !blended(t));
    } else {
        work.buf.clear();
        let kept = ctx.tris.tile(index).filter(|(_, t)| !blended(t));
        raster::for_each_span(kept, rect, &mut work.buf);
    }
}

/// Everything a render's line stage reads, shared by all tiles.
pub(crate) struct LinePass<'a> {
    tris: &'a Binned,
    weld: Vec<u32>,
    segments: Segments,
    /// Hidden-line test on (visible, features); `all` draws every covered sample.
    hidden_line: bool,
    /// The ribbon comparison only for neighbours of the edge's faces (visible: every other
    /// owner's own edges cover its samples; see `visibility.rs`).
    neighbours_only: bool,
    color: Vec3,
    /// Sample offsets from the pixel centre, in pixels (the multi-sample pattern).
    offsets: Vec<[f64; 2]>,
    /// How far the offsets reach from the centre on each axis.
    reach: f64,
    edges_only: bool,
    background: Vec3,
}

/// A worker's tile-local buffers for the line stage.
pub(crate) struct LineScratch {
    color: Vec<Out<f32>>,
    coverage: Vec<Out<f32>>,
    mask: Box<[u16; TILE * TILE]>,
}

impl LineScratch {
    pub fn new() -> Self {
        LineScratch {
            color: vec![Out::new(0.0); TILE * TILE * 3],
            coverage: vec![Out::new(0.0); TILE * TILE],
            mask: Box::new([0; TILE * TILE]),
        }
    }
}

/// The output rows of one tile.
pub(crate) struct TileRows<'a, 'b, P> {
    pub color: &'a mut [&'b mut [Out<P>]],
    pub depth: Option<&'a mut [&'b mut [Out<f32>]]>,
    pub coverage: Option<&'a mut [&'b mut [Out<f32>]]>,
}

impl<'a> LinePass<'a> {
    /// The render's lines: edges found, selected for `options.edges`, projected and binned.
    pub fn new(
        scene: &Scene,
        camera: &Camera,
        options: &RenderOptions,
        tris: &'a Binned,
        verts: &Vertices,
    ) -> Self {
        let topo = Topology::new(scene);
        let segments = Segments::new(&topo, verts, camera, options);
        let pattern = samples::pattern(options.samples);
        let px = 1.0 / 16.0;
        LinePass {
            tris,
            weld: topo.weld,
            segments,
            hidden_line: options.edges != EdgeMode::All,
            // Features too: a grazing occluder next to a hidden feature line would pass the
            // comparison against an unrelated face's extended plane (measured on a torus).
            neighbours_only: true,
            color: options.edge_color,
            offsets: pattern
                .iter()
                .map(|&(x, y)| [x as f64 * px, y as f64 * px])
                .collect(),
            reach: samples::margin(options.samples) as f64 / ONE as f64,
            edges_only: options.edges_only,
            background: options.background,
        }
    }

    /// Sets bit k of `mask[slot]` for every sample k of the tile that a visible line covers.
    /// `ids[k]`: the owners at sample position k (`None`: no triangle touches the tile).
    fn cover(
        &self,
        index: usize,
        rect: TileRect,
        ids: Option<&[&[u32; ID_LEN]]>,
        mask: &mut [u16; TILE * TILE],
    ) {
        mask.fill(0);
        let mut cache = OwnerCache::new();
        let (tx0, ty0) = (rect.x0 as i32, rect.y0 as i32);
        let (tx1, ty1) = (tx0 + rect.w as i32 - 1, ty0 + rect.h as i32 - 1);
        for &s in self.segments.bins.tile(index) {
            let seg = &self.segments.segs[s as usize];
            let cap = &seg.capsule;
            for y in seg.bbox[1].max(ty0)..=seg.bbox[3].min(ty1) {
                let cy = y as f64 + 0.5;
                let Some((lo, hi)) = cap.row_span(cy, self.reach) else {
                    continue;
                };
                // Columns whose centre x + 0.5 lies in [lo, hi].
                let x0 = ((lo - 0.5).ceil() as i32).max(seg.bbox[0]).max(tx0);
                let x1 = ((hi - 0.5).floor() as i32).min(seg.bbox[2]).min(tx1);
                for x in x0..=x1 {
                    let slot = (y - ty0) as usize * TILE + (x - tx0) as usize;
                    let cx = x as f64 + 0.5;
                    for (k, off) in self.offsets.iter().enumerate() {
                        if mask[slot] & (1 << k) != 0 {
                            continue;
                        }
                        let p = [cx + off[0], cy + off[1]];
                        let Some(t) = cap.covers(p) else {
                            continue;
                        };
                        let owner = ids.map_or(NO_TRIANGLE, |ids| ids[k][slot]);
                        if !self.hidden_line
                            || visibility::visible(
                                seg,
                                p,
                                t,
                                owner,
                                self.tris,
                                &self.weld,
                                self.neighbours_only,
                                &mut cache,
                            )
                        {
                            mask[slot] |= 1 << k;
                        }
                    }
                }
            }
        }
    }

    /// One tile of a render with lines: the tile body (the same as without lines) into the
    /// scratch f32 colour, the lines' coverage from its visibility, the composite, the store.
    #[allow(clippy::too_many_arguments)]
    pub fn run_tile<P: Pixel>(
        &self,
        isa: Isa,
        ctx: &ShadeContext<'_>,
        (mode, screen, samples): (ShadingMode, bool, u32),
        work: &mut Workspace,
        scratch: &mut LineScratch,
        index: usize,
        rect: TileRect,
        out: TileRows<'_, '_, P>,
    ) {
        let LineScratch {
            color,
            coverage,
            mask,
        } = scratch;
        if self.edges_only && out.depth.is_none() {
            // Lines alone: only the visibility the hidden-line rule reads, no shading.
            if !self.tris.tile_is_empty(index) {
                visibility_only(ctx, samples > 1, work, index, rect);
            }
        } else {
            let mut rows: Vec<&mut [Out<f32>]> = color
                .chunks_mut(TILE * 3)
                .take(rect.h)
                .map(|r| &mut r[..rect.w * 3])
                .collect();
            // Re-borrowed to the local rows' lifetime (a tile job's rows share one).
            let mut depth: Option<Vec<&mut [Out<f32>]>> =
                out.depth.map(|d| d.iter_mut().map(|r| &mut **r).collect());
            let job = TileJob {
                index,
                rect,
                color: &mut rows,
                depth: depth.as_deref_mut(),
            };
            isa::run_tile(isa, ctx, mode, screen, samples, work, job);
        }
        let empty = self.tris.tile_is_empty(index);
        let wants_coverage = out.coverage.is_some();
        if wants_coverage && !self.edges_only {
            let mut rows: Vec<&mut [Out<f32>]> = coverage
                .chunks_mut(TILE)
                .take(rect.h)
                .map(|r| &mut r[..rect.w])
                .collect();
            work.write_coverage(rect, empty, &mut rows);
        }
        let ids: Option<Vec<&[u32; ID_LEN]>> = match (empty, samples > 1) {
            (true, _) => None,
            (false, false) => Some(vec![&*work.buf.id]),
            (false, true) => Some(work.target.sample_ids().collect()),
        };
        self.cover(index, rect, ids.as_deref(), mask);
        let inv_n = 1.0 / self.offsets.len() as f32;
        let full = ((1u32 << self.offsets.len()) - 1) as u16;
        let e = self.color;
        let mut row_colors: RowColors = [[0.0; ROW_LANES]; 3];
        let mut coverage_out = out.coverage;
        for (j, dst) in out.color.iter_mut().enumerate().take(rect.h) {
            for i in 0..rect.w {
                let slot = j * TILE + i;
                let c = if self.edges_only {
                    self.background
                } else {
                    let px = &color[j * TILE * 3 + i * 3..][..3];
                    // SAFETY: the tile body wrote every sample of the rows it was given
                    // (each tile writes every pixel of its rows: background or shaded).
                    unsafe {
                        Vec3::new(
                            px[0].assume_init(),
                            px[1].assume_init(),
                            px[2].assume_init(),
                        )
                    }
                };
                let m = mask[slot];
                let c = if m == 0 {
                    c
                } else if m == full {
                    e
                } else {
                    let a = m.count_ones() as f32 * inv_n;
                    c * (1.0 - a) + e * a
                };
                row_colors[0][i] = c.x;
                row_colors[1][i] = c.y;
                row_colors[2][i] = c.z;
            }
            P::store_row(&mut dst[..rect.w * 3], &row_colors, ctx.wide());
            if let Some(rows) = coverage_out.as_deref_mut() {
                for (i, o) in rows[j][..rect.w].iter_mut().enumerate() {
                    let slot = j * TILE + i;
                    let v = if self.edges_only {
                        0.0
                    } else {
                        // SAFETY: written above by `write_coverage` for every pixel of the
                        // tile's rows.
                        unsafe { coverage[slot].assume_init() }
                    };
                    let m = mask[slot];
                    let a = m.count_ones() as f32 * inv_n;
                    o.write(if m == 0 {
                        v
                    } else if m == full {
                        1.0
                    } else {
                        v + (1.0 - v) * a
                    });
                }
            }
        }
    }
}
