//! The secondary stage's tile: reflections, refractions, order-independent transparency and
//! the environment background, for the scenes that have them (`ShadeContext::secondary`).
//!
//! 1. Visibility of the opaque layer: every triangle except those of
//!    [`Kind::Blended`] objects (transparent, no refraction technique).
//! 2. The local colour of that layer, shaded by the mode's own loops (`shade_tile`, or
//!    the textured ones) into a tile-local f32 buffer, without fog.
//! 3. Per pixel: the environment along the view ray where no triangle is (when asked);
//!    at an [`Kind::Optical`] surface, the point's position and normal (interpolated per
//!    pixel with the perspective weights; flat uses the face normal), and the mix
//!    `L·local + R·reflected + T·transmitted` of the reflect room; then the fog.
//! 4. Transparent fragments in front of the opaque layer, collected per tile, sorted per
//!    pixel by depth (nearest first; ties by triangle id, i.e. submission order, so the
//!    result never depends on threads), blended front to back over the pixel:
//!    `c = Σ_i (Π_{j<i} T_j)·a_i + (Π_i T_i)·opaque`, where `a_i` is the fragment's own
//!    mix (local and reflected light) and `T_i` what it lets through.
//! 5. The colour stored once into the user's rows, a row at a time.

use glam::Vec3;

use super::id_runs::row_runs;
use super::phong::face_normal;
use super::planes::{weight_planes, PlaneCache};
use super::store::{deinterleave, deinterleave8, rgb_at, Out, Pixel, RowColors, ROW_LANES};
use super::{shade_textured_tile, shade_tile, ShadeContext};
use crate::lighting::{lane, normalize_lanes, set_lane, LANES};
use crate::options::ShadingMode;
use crate::pipeline::raster::{self, Span, SpanSink, TileBuffers, NO_TRIANGLE};
use crate::pipeline::setup::SetupTri;
use crate::pipeline::tiles::{TileRect, TILE};
use crate::reflect::{FirstSurface, Kind, Lookup, Point, SecondaryEffect, World};

/// A transparent fragment in front of the opaque layer.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fragment {
    slot: u32,
    z: f32,
    id: u32,
}

/// A worker's buffers for secondary tiles (allocated on first use).
#[derive(Default)]
pub(crate) struct SecondaryWork {
    local: Vec<Out<f32>>,
    frags: Vec<Fragment>,
}

/// Collects the fragments of blended triangles nearer than an opaque depth buffer (the
/// opaque layer, or one sample position's), each made by `make(slot, z, id)`: one sink for
/// both secondary tiles, which differ only in what a fragment records.
pub(crate) struct Collect<'a, T, F: Fn(usize, f32, u32) -> T> {
    pub opaque: &'a [f32],
    pub frags: &'a mut Vec<T>,
    pub make: F,
}

impl<T, F: Fn(usize, f32, u32) -> T> SpanSink for Collect<'_, T, F> {
    fn span(&mut self, s: Span) {
        for k in 0..s.len {
            self.pixel(s.start + k, s.z_at(k), s.id);
        }
    }

    fn pixel(&mut self, slot: usize, z: f32, id: u32) {
        if z > self.opaque[slot] {
            self.frags.push((self.make)(slot, z, id));
        }
    }
}

/// One tile of a scene with the secondary stage. `AFFINE` as for [`shade_tile`]; `WIDE`
/// as for [`shade_textured_tile`] (inlined into each instruction set's body, `isa.rs`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn shade_secondary_tile<P: Pixel, const AFFINE: bool, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    index: usize,
    rect: TileRect,
    buf: &mut TileBuffers,
    work: &mut SecondaryWork,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    let sec = ctx
        .secondary
        .as_ref()
        .expect("a scene with the secondary stage");
    let kind = |t: &SetupTri| sec.kinds[t.object as usize];
    // 1. The opaque layer.
    if sec.any_blended {
        buf.clear();
        let opaque = ctx
            .tris
            .tile(index)
            .filter(|(_, t)| kind(t) != Kind::Blended);
        raster::for_each_span(opaque, rect, buf);
    } else {
        raster::rasterize_tile(ctx.tris, index, rect, buf);
    }
    // 2. Its local colour.
    work.local.resize(TILE * TILE * 3, Out::new(0.0));
    let mut rows: Vec<&mut [Out<f32>]> = work
        .local
        .chunks_mut(TILE * 3)
        .take(rect.h)
        .map(|r| &mut r[..rect.w * 3])
        .collect();
    if ctx.textured.is_some() {
        shade_textured_tile::<f32, AFFINE, WIDE>(ctx, mode, rect, buf, &mut rows, depth);
    } else {
        shade_tile::<f32, AFFINE>(ctx, mode, rect, buf, &mut rows, depth);
    }
    // 4 (first half). The transparent fragments, sorted per pixel.
    work.frags.clear();
    if sec.any_blended {
        let blended = ctx
            .tris
            .tile(index)
            .filter(|(_, t)| kind(t) == Kind::Blended);
        let mut sink = Collect {
            opaque: &buf.depth[..],
            frags: &mut work.frags,
            make: |slot, z, id| Fragment {
                slot: slot as u32,
                z,
                id,
            },
        };
        raster::for_each_span(blended, rect, &mut sink);
        work.frags.sort_unstable_by(|a, b| {
            a.slot
                .cmp(&b.slot)
                .then(b.z.total_cmp(&a.z))
                .then(a.id.cmp(&b.id))
        });
    }
    let world = world(ctx, mode);
    let mut cache = PointCache::new();
    let mut next = 0;
    // A row's final colours, channel-major, stored into the output at the row's end (a
    // vectorised store: a pixel at a time, quantising was a tenth of a mirror frame).
    let mut colors: RowColors = [[0.0; ROW_LANES]; 3];
    for (j, dst) in color.iter_mut().enumerate().take(rect.h) {
        let out = &mut colors;
        let row = Row {
            ctx,
            sec,
            mode,
            x0: rect.x0,
            y: rect.y0 + j,
        };
        let mut sky = SkyRun::default();
        let mut mirrors = Lookups::<false>::default();
        let mut glass = Lookups::<true>::default();
        // The row's runs of one triangle (or bare background), each cut where a pixel has
        // transparent fragments over it (that pixel on its own): a piece's pixels share a
        // route, asked once. A pixel at a time, the route, the run's end and a batch's
        // bookkeeping were about a seventh of a mirror frame's instructions.
        for run in row_runs(buf, j, rect.w) {
            let id = run.id;
            let mut i = run.start;
            while i < run.end {
                let slot = j * TILE + i;
                let first = next;
                while next < work.frags.len() && work.frags[next].slot as usize == slot {
                    next += 1;
                }
                // Up to the next pixel with a fragment over it, or the run's end.
                let end = match work.frags.get(next) {
                    Some(f) if (f.slot as usize) < j * TILE + run.end => f.slot as usize - j * TILE,
                    _ => run.end,
                };
                let route = Route::of(ctx, sec, id, next > first);
                i = match route {
                    // 3 (plain). A run of pixels of one triangle (or of bare background) whose
                    // colour is the local one the loops wrote: copied into the row's colours as
                    // they are. Through `opaque_color` a pixel at a time, the colour went
                    // through memory as a `Vec3` and its reload stalled: a tenth of a mirror
                    // frame.
                    Route::Plain => {
                        deinterleave(rows[j], i..end, out, WIDE);
                        end
                    }
                    // 3 (background). Runs of bare background pixels are looked up over lanes.
                    Route::Sky => {
                        sky.push(i..end, sec, rect, j, out);
                        end
                    }
                    // 3 (mirrors, glass). A mix that only looks the environment up waits for
                    // others.
                    Route::Mirror | Route::Glass => {
                        sky.flush(sec, rect, j, out);
                        let piece = RunOf {
                            id,
                            cols: i..end,
                            depth: &buf.depth[j * TILE..],
                            local: rows[j],
                        };
                        if route == Route::Mirror {
                            mirrors.push::<AFFINE, WIDE>(piece, &row, &mut cache, out);
                        } else {
                            glass.push::<AFFINE, WIDE>(piece, &row, &mut cache, out);
                        }
                        end
                    }
                    Route::General => {
                        sky.flush(sec, rect, j, out);
                        let (x, y, z) = (rect.x0 + i, rect.y0 + j, buf.depth[slot]);
                        let local = local_at(rows[j], i);
                        // 3. The opaque layer's colour.
                        let c = opaque_color::<AFFINE>(
                            ctx, sec, &world, mode, id, z, local, x, y, &mut cache,
                        );
                        // 4. The transparent fragments over it, front to back.
                        let frags = &work.frags[first..next];
                        let c = if frags.is_empty() {
                            c
                        } else {
                            let layers = frags.iter().map(|f| {
                                fragment_mix::<AFFINE>(
                                    ctx, sec, &world, mode, f.id, f.z, x, y, &mut cache,
                                )
                            });
                            composite(layers, c)
                        };
                        set_lane(out, i, c);
                        i + 1
                    }
                };
            }
        }
        sky.flush(sec, rect, j, out);
        mirrors.flush::<AFFINE, WIDE>(&row, &mut cache, out);
        glass.flush::<AFFINE, WIDE>(&row, &mut cache, out);
        P::store_row(&mut dst[..rect.w * 3], &colors, WIDE);
    }
}

/// The local colour the shading loops wrote for column `i` of a tile row.
#[inline(always)]
fn local_at(row: &[Out<f32>], i: usize) -> Vec3 {
    Vec3::from_array(rgb_at(row, i))
}

/// How a pixel of the opaque layer is shaded: its object's [`FirstSurface`], and for the
/// background whether it shows the environment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Route {
    /// The local colour the loops wrote, unchanged (a run at a time).
    Plain,
    /// Bare background showing the environment (a run looked up over lanes).
    Sky,
    /// [`FirstSurface::Mirror`] ([`Lookups`]).
    Mirror,
    /// [`FirstSurface::Glass`] ([`Lookups`]).
    Glass,
    /// [`opaque_color`] and the transparent fragments over it, a pixel at a time.
    General,
}

impl Route {
    /// The route of a pixel of triangle `id` (or [`NO_TRIANGLE`]), with transparent
    /// fragments over it or not: one look-up of its object.
    #[inline(always)]
    fn of(ctx: &ShadeContext<'_>, sec: &SecondaryEffect, id: u32, fragments: bool) -> Route {
        if fragments {
            return Route::General;
        }
        if id == NO_TRIANGLE {
            return if sec.env_background {
                Route::Sky
            } else {
                Route::Plain
            };
        }
        match sec.first_surface(ctx.tris.get(id).object) {
            FirstSurface::Plain => Route::Plain,
            FirstSurface::Mirror => Route::Mirror,
            FirstSurface::Glass => Route::Glass,
            FirstSurface::Mix => Route::General,
        }
    }
}

/// What a tile row's batches read: the render, its mode, and the row (`y`, and the
/// tile's first column `x0`, in image pixels).
struct Row<'a, 'c> {
    ctx: &'a ShadeContext<'c>,
    sec: &'a SecondaryEffect,
    mode: ShadingMode,
    x0: usize,
    y: usize,
}

/// Pixels of one triangle in a tile row whose colour is their [`Lookup`]'s (mirrors, or
/// with `GLASS` glass, reading the environment: [`Lookup::of`]), waiting
/// to be shaded [`LANES`] at a time: the surface point's normal and view direction
/// ([`point_at`]'s), the split of the light and the look-ups, over all lanes at once; then
/// fogged as [`opaque_color`] does. Each lane is [`point_at`]'s and [`Lookup::of`]'s
/// operations in their order (no fused multiply-add), so the same bits (the integration
/// test `environment_mirrors_match_escaping_rays_bit_for_bit`: against the pixel path).
///
/// A batch holds one triangle (a new one flushes it): its weight planes, face normal,
/// vertices, side and material are the batch's, read once. One pixel at a time, the
/// surface point and the mix (returned by value through memory, then stored a field at a
/// time into lanes) were two thirds of a mirror floor's secondary stage.
#[derive(Default)]
struct Lookups<const GLASS: bool> {
    id: u32,
    col: [usize; LANES],
    z: [f32; LANES],
    /// The local colours, channel-major.
    local: [[f32; LANES]; 3],
    len: usize,
}

/// A run of pixels of one triangle in a tile row: its id, its columns, and the row's
/// window depths and local colours (indexed by column).
struct RunOf<'r> {
    id: u32,
    cols: std::ops::Range<usize>,
    depth: &'r [f32],
    local: &'r [Out<f32>],
}

impl<const GLASS: bool> Lookups<GLASS> {
    /// Adds a run's pixels in order, flushing the batch first when it holds another
    /// triangle, and whenever it is full: the same batches as adding them one at a time.
    #[inline(always)]
    fn push<const AFFINE: bool, const WIDE: bool>(
        &mut self,
        run: RunOf<'_>,
        row: &Row<'_, '_>,
        cache: &mut PointCache,
        out: &mut RowColors,
    ) {
        if self.len > 0 && self.id != run.id {
            self.flush::<AFFINE, WIDE>(row, cache, out);
        }
        self.id = run.id;
        let mut i = run.cols.start;
        while i < run.cols.end {
            let k0 = self.len;
            let m = (LANES - k0).min(run.cols.end - i);
            if WIDE && m == LANES {
                // A whole batch of the run (so the batch was empty): its colours by
                // shuffles, its columns and depths as slices (a pixel at a time, these
                // copies were a twentieth of a mirror frame's instructions).
                let src = run.local[i * 3..(i + LANES) * 3].try_into().unwrap();
                self.local = deinterleave8(src, WIDE);
                self.col = std::array::from_fn(|q| i + q);
                self.z.copy_from_slice(&run.depth[i..i + LANES]);
            } else {
                for q in 0..m {
                    let (k, c) = (k0 + q, i + q);
                    (self.col[k], self.z[k]) = (c, run.depth[c]);
                    let [r, g, b] = rgb_at(run.local, c);
                    (self.local[0][k], self.local[1][k], self.local[2][k]) = (r, g, b);
                }
            }
            self.len += m;
            i += m;
            if self.len == LANES {
                self.flush::<AFFINE, WIDE>(row, cache, out);
            }
        }
    }

    /// Shades the batch, looks it up, mixes, fogs and writes it into the row's colours.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays
    fn flush<const AFFINE: bool, const WIDE: bool>(
        &mut self,
        row: &Row<'_, '_>,
        cache: &mut PointCache,
        out: &mut RowColors,
    ) {
        let n = self.len;
        if n == 0 {
            return;
        }
        self.len = 0;
        let (ctx, sec) = (row.ctx, row.sec);
        let t = ctx.tris.get(self.id);
        let (pl, face) = cache.0.get(self.id, || {
            (
                weight_planes::<AFFINE>(ctx, t),
                face_normal(t, &ctx.verts.world),
            )
        });
        // The pixel centres (dead lanes repeat the last pixel: every lane stays finite).
        let mut px = [0.0f64; LANES];
        for k in 0..LANES {
            px[k] = (row.x0 + self.col[k.min(n - 1)]) as f64 + 0.5;
        }
        let py = row.y as f64 + 0.5;
        // The perspective weights, as `point_at`.
        let mut b = [[0.0f32; LANES]; 3];
        for k in 0..LANES {
            let q = pl.map(|p| p[0] * px[k] + p[1] * py + p[2]);
            let inv = 1.0 / (q[0] + q[1] + q[2]);
            for m in 0..3 {
                b[m][k] = (q[m] * inv) as f32;
            }
        }
        // The shading normal: the interpolated vertex normals, normalised (the face
        // normal where there are none or they cancel); turned toward the viewer.
        let mut nrm = [[0.0f32; LANES]; 3];
        let smooth = row.mode != ShadingMode::Flat && !ctx.verts.normal.is_empty();
        if smooth {
            let nv = t.v.map(|k| ctx.verts.normal[k as usize].to_array());
            let mut sum = [[0.0f32; LANES]; 3];
            for c in 0..3 {
                for k in 0..LANES {
                    sum[c][k] = nv[0][c] * b[0][k] + nv[1][c] * b[1][k] + nv[2][c] * b[2][k];
                }
            }
            normalize_lanes(&mut nrm, &sum, WIDE);
        }
        // Toward the viewer: the view rays negated.
        let mut v = [[0.0f32; LANES]; 3];
        sec.view_rays_at(&px, py, &mut v);
        for c in 0..3 {
            for k in 0..LANES {
                v[c][k] = -v[c][k];
            }
        }
        // The normal on the viewer's side (the interpolated one, or the face normal where
        // there is none, it cancels or it turns away from the viewer at a silhouette).
        let g = if t.front { face } else { -face }.to_array();
        let face = face.to_array();
        let mut nk = [[0.0f32; LANES]; 3];
        for k in 0..LANES {
            let zero = !smooth || (nrm[0][k] == 0.0 && nrm[1][k] == 0.0 && nrm[2][k] == 0.0);
            for c in 0..3 {
                // `-x` as `point_at`'s `-n_out`: a sign flip, not a product.
                let n_out = if zero { face[c] } else { nrm[c][k] };
                nk[c][k] = if t.front { n_out } else { -n_out };
            }
            let d = nk[0][k] * v[0][k] + nk[1][k] * v[1][k] + nk[2][k] * v[2][k];
            let facing = d > 0.0;
            for c in 0..3 {
                nk[c][k] = if facing { nk[c][k] } else { g[c] };
            }
        }
        let mut reflected = [[0.0f32; LANES]; 3];
        let mut refracted = [[0.0f32; LANES]; 3];
        let mut base = [[0.0f32; LANES]; 3];
        let mut reflect = [[0.0f32; LANES]; 3];
        let mut transmit = [0.0f32; LANES];
        let side = (ctx.two_sided && !t.front) as usize;
        let m = sec.material(t.object, side);
        // An opaque material's reflected weight is its reflectivity in every lane: read
        // from the material where it is mixed, not filled into `reflect`'s lanes.
        let opaque = m.transparency == 0.0;
        Lookup::base_and_mirror_lanes(m, &nk, &v, &self.local, &mut base, &mut reflected);
        if !opaque {
            // The weights `Lookup::of` takes from the split at every lane (those past `n`
            // are dropped); an opaque material's are its reflectivity and nothing.
            Lookup::transparent_weights_lanes(
                m,
                &nk,
                &v,
                sec.indices(m, t.front),
                &mut reflect,
                &mut transmit,
                &mut refracted,
            );
        }
        let mut r = [[0.0; LANES]; 3];
        sec.sky_dirs(&reflected, n, &mut r);
        // The refracted directions only where a pixel of the batch transmits.
        let mut tr = [[0.0; LANES]; 3];
        if GLASS && transmit[..n].iter().any(|&t| t > 0.0) {
            sec.sky_dirs(&refracted, n, &mut tr);
        }
        if !GLASS && sec.fog.is_none() {
            // `Lookup::color` of a mirror over the lanes, `base + reflect·sky(reflected)`
            // where the weight is not zero, in its operations. A lane at a time, the mix
            // and the colour went through memory as `Vec3`s.
            // A mirror's material is opaque on both sides: every lane's weight is its
            // reflectivity, so whether it reflects at all is the batch's.
            debug_assert!(opaque);
            let w = m.reflectivity.to_array();
            let reflects = m.reflectivity != Vec3::ZERO;
            let mix = |c: usize, k: usize| {
                if reflects {
                    base[c][k] + w[c] * r[c][k]
                } else {
                    base[c][k]
                }
            };
            // Columns rise within a batch: the last n − 1 past the first means consecutive,
            // stored as slices (they vectorise), else a column at a time.
            let c0 = self.col[0];
            if self.col[n - 1] == c0 + n - 1 {
                for c in 0..3 {
                    for (k, o) in out[c][c0..c0 + n].iter_mut().enumerate() {
                        *o = mix(c, k);
                    }
                }
            } else {
                for c in 0..3 {
                    for k in 0..n {
                        out[c][self.col[k]] = mix(c, k);
                    }
                }
            }
            return;
        }
        for k in 0..n {
            let i = self.col[k];
            let mix = Lookup {
                base: lane(&base, k),
                reflect: if opaque {
                    m.reflectivity
                } else {
                    lane(&reflect, k)
                },
                // A mirror's is zero: known here, its term is compiled out.
                transmit: if GLASS { transmit[k] } else { 0.0 },
                ..Lookup::default()
            };
            let c = mix.color(lane(&r, k), lane(&tr, k));
            let c = fogged(ctx, sec, c, row.x0 + i, row.y, self.z[k]);
            set_lane(out, i, c);
        }
    }
}

/// Consecutive background pixels of a tile row waiting for the environment: up to
/// [`LANES`] of them are looked up at once ([`SecondaryEffect::sky_lanes`]), the same
/// colours as one at a time.
#[derive(Default)]
struct SkyRun {
    /// Column (in the tile) of the first pixel.
    start: usize,
    len: usize,
}

impl SkyRun {
    /// Adds the pixels in columns `cols` in order (each right after the run's last, or
    /// starting a run): the same runs of at most [`LANES`] as adding them one at a time.
    #[inline(always)]
    fn push(
        &mut self,
        cols: std::ops::Range<usize>,
        sec: &SecondaryEffect,
        rect: TileRect,
        j: usize,
        out: &mut RowColors,
    ) {
        let mut i = cols.start;
        while i < cols.end {
            if self.len == LANES || (self.len > 0 && self.start + self.len != i) {
                self.flush(sec, rect, j, out);
            }
            if self.len == 0 {
                self.start = i;
            }
            let m = (LANES - self.len).min(cols.end - i);
            self.len += m;
            i += m;
        }
    }

    /// Looks the run up and writes it into row `j`'s colours.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays
    fn flush(&mut self, sec: &SecondaryEffect, rect: TileRect, j: usize, out: &mut RowColors) {
        if self.len == 0 {
            return;
        }
        let mut c = [[0.0; LANES]; 3];
        sec.sky_lanes(rect.x0 + self.start, rect.y0 + j, self.len, &mut c);
        for k in 0..self.len {
            let i = self.start + k;
            set_lane(out, i, lane(&c, k));
        }
        self.len = 0;
    }
}

/// A tile's perspective weight planes and face normals of recently seen triangles: a
/// pixel's surface point ([`point_at`]) needs both, and they are the triangle's, so they
/// are made once per triangle and tile instead of once per pixel (the same values).
pub(crate) struct PointCache(PlaneCache<([[f64; 3]; 3], Vec3)>);

impl PointCache {
    pub(crate) fn new() -> Self {
        PointCache(PlaneCache::new())
    }
}

/// What secondary rays and the mix see of the render's vertices and materials.
pub(crate) fn world<'a>(ctx: &ShadeContext<'a>, mode: ShadingMode) -> World<'a> {
    World {
        world: &ctx.verts.world,
        normal: if mode == ShadingMode::Flat {
            &[]
        } else {
            &ctx.verts.normal
        },
        surfaces: ctx.materials,
        two_sided: ctx.two_sided,
    }
}

/// The opaque colour of pixel (x, y) owned by triangle `id` (window depth `z` at the pixel
/// centre, colour `local` as the mode's loops shaded it): the environment along the view
/// ray where no triangle is (when asked), the mix at an [`Kind::Optical`] surface, then the
/// fog on surfaces. Inlined: most pixels of a scene with the secondary stage are plain
/// surfaces whose colour is their local one, and a call per pixel was 7 % of a mirror frame.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn opaque_color<const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    sec: &SecondaryEffect,
    world: &World<'_>,
    mode: ShadingMode,
    id: u32,
    z: f32,
    local: Vec3,
    x: usize,
    y: usize,
    cache: &mut PointCache,
) -> Vec3 {
    if id == NO_TRIANGLE {
        return if sec.env_background {
            sec.sky(sec.view_ray(x, y))
        } else {
            local
        };
    }
    let t = ctx.tris.get(id);
    let c = match sec.kinds[t.object as usize] {
        Kind::Optical => {
            let pt = point_at::<AFFINE>(ctx, sec, mode, id, x, y, cache);
            sec.mix(world, &pt.0, local, 0, Vec3::ZERO, false).color
        }
        _ => local,
    };
    fogged(ctx, sec, c, x, y, z)
}

/// Colour `c` of a surface at pixel (x, y), window depth `z`, through the fog (if any).
#[inline(always)]
fn fogged(
    ctx: &ShadeContext<'_>,
    sec: &SecondaryEffect,
    c: Vec3,
    x: usize,
    y: usize,
    z: f32,
) -> Vec3 {
    match &sec.fog {
        Some(fog) => fog.apply(c, x, y, ctx.camera.eye_depth_from_z(z)),
        None => c,
    }
}

/// A transparent fragment of triangle `id` at pixel (x, y) (window depth `z`, for the fog):
/// what it adds over what lies behind it (its own mix of local and reflected light, fogged)
/// and the share of what lies behind that still shows through.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn fragment_mix<const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    sec: &SecondaryEffect,
    world: &World<'_>,
    mode: ShadingMode,
    id: u32,
    z: f32,
    x: usize,
    y: usize,
    cache: &mut PointCache,
) -> (Vec3, f32) {
    let t = ctx.tris.get(id);
    let (pt, b) = point_at::<AFFINE>(ctx, sec, mode, id, x, y, cache);
    let own = fragment_color(ctx, mode, t, &pt, b);
    let m = sec.mix(world, &pt, own, 0, Vec3::ZERO, true);
    let a = match &sec.fog {
        // A layer letting `behind` through fogs as the opaque share of it.
        Some(fog) => {
            let d = ctx.camera.eye_depth_from_z(z);
            fog.apply(m.color, x, y, d) - m.behind * fog.apply(Vec3::ZERO, x, y, d)
        }
        None => m.color,
    };
    (a, m.behind)
}

/// Transparent layers (nearest first: what each adds, what it lets through) blended front
/// to back over `behind`: `Σ_i (Π_{j<i} T_j)·a_i + (Π_i T_i)·behind`. Layers after one
/// that lets nothing through are not read.
#[inline]
pub(crate) fn composite(layers: impl Iterator<Item = (Vec3, f32)>, behind: Vec3) -> Vec3 {
    let mut acc = Vec3::ZERO;
    let mut through = 1.0f32;
    for (a, t) in layers {
        acc += through * a;
        through *= t;
        if through == 0.0 {
            break;
        }
    }
    acc + through * behind
}

/// The surface point of triangle `id` at the centre of pixel (x, y) and its barycentrics:
/// position and normal interpolated with the perspective weights (flat, or a mesh without
/// usable normals: the face normal), both turned toward the viewer.
fn point_at<const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    sec: &SecondaryEffect,
    mode: ShadingMode,
    id: u32,
    x: usize,
    y: usize,
    cache: &mut PointCache,
) -> (Point, [f32; 3]) {
    let t = ctx.tris.get(id);
    let w = &ctx.verts.world;
    let (pl, face) = cache
        .0
        .get(id, || (weight_planes::<AFFINE>(ctx, t), face_normal(t, w)));
    let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
    let q = pl.map(|p| p[0] * px + p[1] * py + p[2]);
    // One division and three products instead of three divisions, the slowest operation
    // here (in f64 then rounded to f32: an f32 weight moves only where the f64 quotient
    // and product differ across an f32 rounding boundary).
    let inv = 1.0 / (q[0] + q[1] + q[2]);
    let b = q.map(|v| (v * inv) as f32);
    let v = t.v.map(|k| k as usize);
    let p = w[v[0]] * b[0] + w[v[1]] * b[1] + w[v[2]] * b[2];
    let n_out = if mode == ShadingMode::Flat || ctx.verts.normal.is_empty() {
        face
    } else {
        let nn = &ctx.verts.normal;
        let n = (nn[v[0]] * b[0] + nn[v[1]] * b[1] + nn[v[2]] * b[2]).normalize_or_zero();
        if n == Vec3::ZERO {
            face
        } else {
            n
        }
    };
    let view = -sec.view_ray(x, y);
    let (n, g) = if t.front {
        (n_out, face)
    } else {
        (-n_out, -face)
    };
    // Where the interpolated normal turns away from the viewer (silhouettes), the face
    // normal stands in.
    let n = if n.dot(view) > 0.0 { n } else { g };
    let back = ctx.two_sided && !t.front;
    (
        Point {
            p,
            n,
            g,
            v: view,
            entering: t.front,
            object: t.object,
            side: back as usize,
        },
        b,
    )
}

/// A transparent fragment's own (local) colour as its mode lights it: flat, the face's
/// colour; Gouraud (untextured), the interpolated vertex colours; otherwise the lighting
/// equation at the point with the interpolated normal (textures are not read here).
fn fragment_color(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    t: &SetupTri,
    pt: &Point,
    b: [f32; 3],
) -> Vec3 {
    let v = t.v.map(|k| k as usize);
    match mode {
        ShadingMode::Flat => t.flat,
        ShadingMode::Gouraud if ctx.textured.is_none() => {
            let colors = if ctx.two_sided && !t.front {
                &ctx.verts.color_back
            } else {
                &ctx.verts.color
            };
            colors[v[0]] * b[0] + colors[v[1]] * b[1] + colors[v[2]] * b[2]
        }
        _ => {
            // The loops light the outward normal, flipped on a two-sided back face.
            let n = if t.front || ctx.two_sided {
                pt.n
            } else {
                -pt.n
            };
            ctx.materials[t.object as usize][pt.side].shade(n, pt.p, ctx.eye)
        }
    }
}
