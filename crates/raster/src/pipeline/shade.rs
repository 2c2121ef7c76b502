//! Shade pass: every visible pixel of a tile is shaded exactly once, from its triangle's
//! setup data, and written straight into the output rows.
//!
//! The shading mode is a const generic, so each mode's loop carries only its own work: flat
//! reads one colour per triangle, Gouraud interpolates colours, Phong normals and positions.

use std::mem::MaybeUninit;

use glam::Vec3;

use super::bin::Binned;
use super::raster::{TileBuffers, NO_TRIANGLE};
use super::setup::{SetupTri, ONE};
use super::tiles::{TileRect, TILE};
use super::vertex::Vertices;
use super::Sides;
use crate::camera::{Camera, EyeDistance};
use crate::fog::Fog;
use crate::lighting::{normalize_lanes, Lanes, Surface, LANES};
use crate::options::ShadingMode;

mod sealed {
    /// Only the crate's own sample types are [`super::Pixel`]s.
    pub trait Sealed {}
    impl Sealed for u8 {}
    impl Sealed for f32 {}
}

/// An output sample type: how a linear RGB colour is stored. Implemented for `u8`
/// (`round(clamp(c, 0, 1) · 255)`) and `f32` (linear, unclamped) only (sealed).
pub trait Pixel: sealed::Sealed + Copy + Default + Send + Sync + 'static {
    /// Writes `c` into `dst[0..3]`.
    fn store(dst: &mut [Self], c: Vec3);

    /// Writes the first `dst.len() / 3` colours of the row `c` (`c[channel][pixel]`) into
    /// the output `dst`, as [`Pixel::store`] would one by one.
    #[doc(hidden)]
    #[inline(always)]
    fn store_row(dst: &mut [MaybeUninit<Self>], c: &RowColors) {
        for (k, px) in dst.chunks_exact_mut(3).enumerate() {
            store_out(px, Vec3::new(c[0][k], c[1][k], c[2][k]));
        }
    }
}

/// Output rows are written, never read, so the image needs no zeroing first: the
/// pipeline writes every sample of them (background or shaded) exactly once.
pub(crate) type Out<T> = MaybeUninit<T>;

/// Copies `src` into the output `dst` (same length).
#[inline(always)]
pub(crate) fn put<T: Copy>(dst: &mut [Out<T>], src: &[T]) {
    for (d, &s) in dst.iter_mut().zip(src) {
        d.write(s);
    }
}

/// Fills the output `dst` with `v`.
#[inline(always)]
fn fill_out<T: Copy>(dst: &mut [Out<T>], v: T) {
    for d in dst {
        d.write(v);
    }
}

/// [`Pixel::store`] into the output.
#[inline(always)]
fn store_out<P: Pixel>(dst: &mut [Out<P>], c: Vec3) {
    let mut px = [P::default(); 3];
    P::store(&mut px, c);
    put(dst, &px);
}

/// Linear colours of up to a tile row's pixels (plus a lane loop's overrun), channel-major.
#[doc(hidden)]
pub type RowColors = [[f32; ROW_LANES]; 3];

/// Length of a [`RowColors`] channel: a tile row rounded up to whole [`LANES`].
#[doc(hidden)]
pub const ROW_LANES: usize = TILE + LANES;

/// `round(clamp(v, 0, 1) · 255)`, NaN to 0.
#[inline(always)]
fn quantize(v: f32) -> u8 {
    quantize_i32(v) as u8
}

/// [`quantize`] as an i32 (what a SIMD conversion makes; narrowed when stored).
#[inline(always)]
#[allow(clippy::manual_clamp)] // `clamp` keeps NaN; `max` sends it to 0, as wanted
fn quantize_i32(v: f32) -> i32 {
    // Clamped before the cast (`max` sends NaN to 0): v > 1 gives at least 255.5 → 255,
    // v < 0 less than 0.5 → 0. The cast of a value known to be in [0, 255] then needs no
    // saturation fix-ups, so lane loops of this vectorise.
    let x = (v * 255.0 + 0.5).max(0.0).min(255.0);
    // SAFETY: x is in [0, 255] and not NaN, so it is representable in i32.
    unsafe { x.to_int_unchecked::<i32>() }
}

impl Pixel for u8 {
    /// `round(clamp(c, 0, 1) · 255)`.
    #[inline]
    fn store(dst: &mut [u8], c: Vec3) {
        dst[0] = quantize(c.x);
        dst[1] = quantize(c.y);
        dst[2] = quantize(c.z);
    }

    #[inline(always)]
    fn store_row(dst: &mut [Out<u8>], c: &RowColors) {
        // Quantised a channel at a time over whole lanes (SIMD), then interleaved.
        let n = (dst.len() / 3).div_ceil(LANES) * LANES;
        let mut q = [[0i32; ROW_LANES]; 3];
        for (qc, cc) in q.iter_mut().zip(c) {
            for (qv, &v) in qc[..n].iter_mut().zip(&cc[..n]) {
                *qv = quantize_i32(v);
            }
        }
        for (k, px) in dst.chunks_exact_mut(3).enumerate() {
            put(px, &[q[0][k] as u8, q[1][k] as u8, q[2][k] as u8]);
        }
    }
}

impl Pixel for f32 {
    /// Linear, unclamped.
    #[inline]
    fn store(dst: &mut [f32], c: Vec3) {
        dst[0] = c.x;
        dst[1] = c.y;
        dst[2] = c.z;
    }
}

/// Everything the shade pass reads, shared by all tiles.
pub(crate) struct ShadeContext<'a> {
    pub tris: &'a Binned,
    pub verts: &'a Vertices,
    pub materials: &'a [Sides],
    pub camera: &'a Camera,
    pub eye: Vec3,
    pub background: Vec3,
    /// Back faces (clockwise on screen) are lit with the flipped normal.
    pub two_sided: bool,
    /// Image width and height in pixels (the viewport of the clip coordinates).
    pub size: (f64, f64),
    /// The scene's fog and the per-render constants to find eye distances.
    pub fog: Option<(Fog, EyeDistance)>,
}

impl ShadeContext<'_> {
    /// Eye depth of a pixel from its stored z and interpolated 1/w, when `wanted` (depth
    /// output or fog); 0 otherwise, saving a division per pixel.
    #[inline(always)]
    fn eye_depth(&self, wanted: bool, z: f32, inv_w: f32) -> f32 {
        if wanted {
            self.camera.eye_depth(z, inv_w)
        } else {
            0.0
        }
    }

    /// `c` seen through the fog at pixel (x, y) with eye depth `depth`. `FOG` is whether the
    /// scene has fog, fixed per render so the foggless loops carry no fog code at all.
    #[inline(always)]
    fn fogged<const FOG: bool>(&self, c: Vec3, x: usize, y: usize, depth: f32) -> Vec3 {
        match &self.fog {
            Some((fog, dist)) if FOG => fog.apply(c, dist.at(x, y, depth)),
            _ => c,
        }
    }
}

/// The background colour stored once for a whole tile row.
fn background_row<P: Pixel>(ctx: &ShadeContext<'_>) -> [P; TILE * 3] {
    let mut px = [P::default(); 3];
    P::store(&mut px, ctx.background);
    let mut row = [P::default(); TILE * 3];
    for dst in row.chunks_exact_mut(3) {
        dst.copy_from_slice(&px);
    }
    row
}

/// Fills a tile that no triangle touches with the background (and infinite depth).
#[inline(always)]
pub(crate) fn fill_background<P: Pixel>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    let bg = background_row::<P>(ctx);
    for row in color.iter_mut() {
        put(row, &bg[..rect.w * 3]);
    }
    for row in depth.into_iter().flatten() {
        fill_out(row, f32::INFINITY);
    }
}

/// Length of the run of `id` at the start of `ids` (at least 1 when `ids[0] == id`).
#[inline(always)]
fn run_length(ids: &[u32], id: u32) -> usize {
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

const FLAT: u8 = 0;
/// Entries of the per-tile flat colour cache.
const FLAT_CACHE: usize = 64;
const GOURAUD: u8 = 1;

/// Shades one tile into its output rows (and depth rows when requested).
#[inline(always)]
pub(crate) fn shade_tile<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    // One monomorphised loop per (mode, fog): a scene without fog pays nothing for it.
    match (mode, ctx.fog.is_some()) {
        (ShadingMode::Flat, false) => shade_impl::<P, FLAT, false>(ctx, rect, buf, color, depth),
        (ShadingMode::Flat, true) => shade_impl::<P, FLAT, true>(ctx, rect, buf, color, depth),
        (ShadingMode::Gouraud, false) => {
            shade_impl::<P, GOURAUD, false>(ctx, rect, buf, color, depth)
        }
        (ShadingMode::Gouraud, true) => {
            shade_impl::<P, GOURAUD, true>(ctx, rect, buf, color, depth)
        }
        (ShadingMode::Phong, false) => shade_phong::<P, false>(ctx, rect, buf, color, depth),
        (ShadingMode::Phong, true) => shade_phong::<P, true>(ctx, rect, buf, color, depth),
    }
}

/// The perspective weight planes of `t` in pixel units: λ_k / w_k at the pixel-space point
/// (x, y) is `plane[k][0]·x + plane[k][1]·y + plane[k][2]` (f64, so no cancellation matters).
///
/// Coverage uses the snapped vertices, but attributes are interpolated over the unsnapped
/// screen triangle (from the f32 clip coordinates, to ~1e-4 px instead of the snap's 1/512
/// px), as GPUs do: snapping then moves no colour or normal. Where snapping changed the
/// triangle's area by more than 2× (slivers), the unsnapped planes would extrapolate far
/// outside the triangle at covered pixels, so the exact planes of the snapped triangle are
/// used instead.
fn weight_planes(ctx: &ShadeContext<'_>, t: &SetupTri) -> [[f64; 3]; 3] {
    let (w, h) = ctx.size;
    let screen = |k: u32| {
        let c = ctx.verts.clip[k as usize].as_dvec4();
        let iw = 1.0 / c.w;
        ((c.x * iw + 1.0) * 0.5 * w, (1.0 - c.y * iw) * 0.5 * h)
    };
    let s = [screen(t.v[0]), screen(t.v[1]), screen(t.v[2])];
    let area = (s[1].0 - s[0].0) * (s[2].1 - s[0].1) - (s[1].1 - s[0].1) * (s[2].0 - s[0].0);
    let snapped_area = t.area2 as f64 / (ONE * ONE) as f64;
    let mut plane = [[0.0; 3]; 3];
    if area.is_finite() && area > 0.5 * snapped_area && area < 2.0 * snapped_area {
        let inv_area = 1.0 / area;
        for (k, pk) in plane.iter_mut().enumerate() {
            let ((ax, ay), (bx, by)) = (s[(k + 1) % 3], s[(k + 2) % 3]);
            let q = t.inv_w[k] as f64 * inv_area;
            *pk = [
                -(by - ay) * q,
                (bx - ax) * q,
                ((by - ay) * ax - (bx - ax) * ay) * q,
            ];
        }
    } else {
        // E_k(P) over fixed-point P = ONE·(x, y), divided by the snapped area.
        let e = t.edges();
        let one = ONE as f64;
        for (k, pk) in plane.iter_mut().enumerate() {
            let q = t.inv_w[k] as f64 / t.area2 as f64;
            *pk = [
                e.a[k] as f64 * one * q,
                e.b[k] as f64 * one * q,
                e.c[k] as f64 * q,
            ];
        }
    }
    plane
}

/// A plane `p[0]·x + p[1]·y + p[2]` over pixel coordinates.
type Plane = [f64; 3];

/// Phong: per-triangle data gathered once while consecutive pixels share a triangle.
struct Current<'a> {
    id: u32,
    /// Perspective weight planes ([`weight_planes`]).
    plane: [Plane; 3],
    normal: [Vec3; 3],
    pos: [Vec3; 3],
    material: Option<&'a Surface>,
}

impl<'a> Current<'a> {
    fn empty() -> Self {
        Current {
            id: NO_TRIANGLE,
            plane: [[0.0; 3]; 3],
            normal: [Vec3::ZERO; 3],
            pos: [Vec3::ZERO; 3],
            material: None,
        }
    }

    /// Perspective weights λ_k / w_k at the pixel centre (x, y) (pixel units). Their sum is
    /// the interpolated 1/w.
    #[inline(always)]
    fn weights(&self, x: f64, y: f64) -> [f32; 3] {
        let p = &self.plane;
        // Written out: `array::map` here is not always inlined, and this runs per pixel.
        [
            (p[0][0] * x + p[0][1] * y + p[0][2]) as f32,
            (p[1][0] * x + p[1][1] * y + p[1][2]) as f32,
            (p[2][0] * x + p[2][1] * y + p[2][2]) as f32,
        ]
    }

    fn load(
        ctx: &ShadeContext<'a>,
        id: u32,
        t: &SetupTri,
        planes: &mut PlaneCache<[Plane; 3]>,
    ) -> Self {
        let v = t.v.map(|k| k as usize);
        let back = ctx.two_sided && !t.front;
        Current {
            id,
            plane: planes.get(id, || weight_planes(ctx, t)),
            normal: v.map(|k| ctx.verts.normal[k]),
            pos: v.map(|k| ctx.verts.world[k]),
            material: Some(&ctx.materials[t.object as usize][back as usize]),
        }
    }
}

/// Entries of the per-tile plane caches.
const PLANE_CACHE: usize = 64;

/// Planes of recently seen triangles, direct-mapped by id: a triangle's rows alternate with
/// its neighbours' within a tile and each row segment needs them again, so without this they
/// (a dozen f64 products and four divisions) were recomputed per segment.
struct PlaneCache<T> {
    entries: [(u32, T); PLANE_CACHE],
}

impl<T: Copy + Default> PlaneCache<T> {
    fn new() -> Self {
        PlaneCache {
            entries: [(NO_TRIANGLE, T::default()); PLANE_CACHE],
        }
    }

    #[inline]
    fn get(&mut self, id: u32, make: impl FnOnce() -> T) -> T {
        let e = &mut self.entries[id as usize % PLANE_CACHE];
        if e.0 != id {
            *e = (id, make());
        }
        e.1
    }
}

/// What flat and Gouraud interpolate, as planes over pixel coordinates: `inv_w` is the
/// interpolated 1/w (Σ λ_k/w_k), and Gouraud's `color[c]` is Σ λ_k/w_k · colour_k[c], so a
/// pixel's colour is `color / inv_w`: four planes instead of three weights and nine products.
#[derive(Clone, Copy, Default)]
struct RunPlanes {
    inv_w: Plane,
    color: [Plane; 3],
}

impl RunPlanes {
    #[allow(clippy::needless_range_loop)] // plane coefficient c of three arrays
    fn new<const MODE: u8>(ctx: &ShadeContext<'_>, t: &SetupTri) -> Self {
        let w = weight_planes(ctx, t);
        let mut out = RunPlanes::default();
        for c in 0..3 {
            out.inv_w[c] = w[0][c] + w[1][c] + w[2][c];
        }
        if MODE == GOURAUD {
            let colors = if ctx.two_sided && !t.front {
                &ctx.verts.color_back
            } else {
                &ctx.verts.color
            };
            let a0 = colors[t.v[0] as usize].as_dvec3().to_array();
            let a1 = colors[t.v[1] as usize].as_dvec3().to_array();
            let a2 = colors[t.v[2] as usize].as_dvec3().to_array();
            // Written out: closures and array maps here were not inlined (per triangle and
            // tile, it showed in profiles of small-triangle meshes).
            for ch in 0..3 {
                for c in 0..3 {
                    out.color[ch][c] = w[0][c] * a0[ch] + w[1][c] * a1[ch] + w[2][c] * a2[ch];
                }
            }
        }
        out
    }
}

/// Value at (x, y) and step per pixel in x of a plane.
#[inline(always)]
fn start_step(p: &Plane, x: f64, y: f64) -> (f64, f64) {
    (p[0] * x + p[1] * y + p[2], p[0])
}

/// [`RunPlanes`] evaluated at a run's first pixel, with their steps along the run.
#[derive(Clone, Copy)]
struct RunStart {
    inv_w: (f64, f64),
    /// Gouraud only (zero otherwise).
    color: [(f64, f64); 3],
}

impl RunStart {
    #[inline(always)]
    fn new<const MODE: u8>(pl: &RunPlanes, x: f64, y: f64) -> Self {
        let mut color = [(0.0, 0.0); 3];
        if MODE == GOURAUD {
            color = pl.color.map(|p| start_step(&p, x, y));
        }
        RunStart {
            inv_w: start_step(&pl.inv_w, x, y),
            color,
        }
    }

    /// Interpolated 1/w at the run's pixel `k`.
    #[inline(always)]
    fn inv_w(&self, k: f64) -> f64 {
        self.inv_w.0 + self.inv_w.1 * k
    }

    /// Gouraud colour at the run's pixel `k`, given `r` = 1 / [`RunStart::inv_w`] there.
    #[inline(always)]
    fn color(&self, k: f64, r: f64) -> [f32; 3] {
        let [(r0, dr), (g0, dg), (b0, db)] = self.color;
        [
            ((r0 + dr * k) * r) as f32,
            ((g0 + dg * k) * r) as f32,
            ((b0 + db * k) * r) as f32,
        ]
    }
}

/// Flat and Gouraud, a run of equal triangle ids at a time: the run's planes are evaluated
/// once at its first pixel and stepped along it (f64 throughout, so stepping adds nothing
/// measurable: 64 steps at most).
#[inline(always)]
fn shade_impl<P: Pixel, const MODE: u8, const FOG: bool>(
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
                let pl = planes.get(id, || RunPlanes::new::<MODE>(ctx, t));
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
                        let eye_depth = ctx.eye_depth(want_depth, zs[i + k], inv_w as f32);
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

/// Pixels waiting to be lit together, all with the same material.
struct PhongBatch<'a> {
    /// Interpolated normals, not yet normalised (never zero).
    n: [Lanes; 3],
    p: [Lanes; 3],
    /// (row in tile, column in tile) of each lane.
    at: [(usize, usize); LANES],
    /// Eye depth of each lane (for fog).
    depth: Lanes,
    len: usize,
    material: Option<&'a Surface>,
}

impl<'a> PhongBatch<'a> {
    #[inline(always)]
    fn flush<P: Pixel, const FOG: bool>(
        &mut self,
        ctx: &ShadeContext<'_>,
        rect: TileRect,
        color: &mut [&mut [Out<P>]],
    ) {
        let eye = ctx.eye;
        if let Some(m) = self.material.filter(|_| self.len > 0) {
            let mut n = [[0.0; LANES]; 3];
            let raw = &self.n;
            normalize_lanes(&mut n, |k| (raw[0][k], raw[1][k], raw[2][k]));
            let c = m.shade_lanes(&n, &self.p, eye);
            for (k, &(j, i)) in self.at[..self.len].iter().enumerate() {
                let lit = Vec3::new(c[0][k], c[1][k], c[2][k]);
                let lit = ctx.fogged::<FOG>(lit, rect.x0 + i, rect.y0 + j, self.depth[k]);
                store_out(&mut color[j][i * 3..i * 3 + 3], lit);
            }
        }
        self.len = 0;
    }

    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn push<P: Pixel, const FOG: bool>(
        &mut self,
        ctx: &ShadeContext<'_>,
        rect: TileRect,
        m: &'a Surface,
        n: Vec3,
        p: Vec3,
        at: (usize, usize),
        depth: f32,
        color: &mut [&mut [Out<P>]],
    ) {
        if self.len > 0 && !std::ptr::eq(m, self.material.unwrap_or(m)) {
            self.flush::<P, FOG>(ctx, rect, color);
        }
        self.material = Some(m);
        let k = self.len;
        (self.n[0][k], self.n[1][k], self.n[2][k]) = (n.x, n.y, n.z);
        (self.p[0][k], self.p[1][k], self.p[2][k]) = (p.x, p.y, p.z);
        self.at[k] = at;
        self.depth[k] = depth;
        self.len += 1;
        if self.len == LANES {
            self.flush::<P, FOG>(ctx, rect, color);
        }
    }
}

/// Phong: interpolation per pixel, lighting [`LANES`] pixels at a time.
#[inline(always)]
fn shade_phong<P: Pixel, const FOG: bool>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    mut depth: Option<&mut [&mut [Out<f32>]]>,
) {
    let want_depth = depth.is_some() || FOG;
    let mut cur = Current::empty();
    let mut planes = PlaneCache::new();
    let background = background_row::<P>(ctx);
    let mut batch = PhongBatch {
        n: [[0.0; LANES]; 3],
        p: [[0.0; LANES]; 3],
        at: [(0, 0); LANES],
        depth: [0.0; LANES],
        len: 0,
        material: None,
    };
    for j in 0..rect.h {
        let y = (rect.y0 + j) as f64 + 0.5;
        for i in 0..rect.w {
            let slot = j * TILE + i;
            let id = buf.id[slot];
            if id == NO_TRIANGLE {
                put(&mut color[j][i * 3..i * 3 + 3], &background[..3]);
                if let Some(d) = depth.as_deref_mut() {
                    d[j][i].write(f32::INFINITY);
                }
                continue;
            }
            let t = ctx.tris.get(id);
            if id != cur.id {
                cur = Current::load(ctx, id, t, &mut planes);
            }
            let [q0, q1, q2] = cur.weights((rect.x0 + i) as f64 + 0.5, y);
            let inv_w = q0 + q1 + q2;
            let eye_depth = ctx.eye_depth(want_depth, buf.depth[slot], inv_w);
            if let Some(d) = depth.as_deref_mut() {
                d[j][i].write(eye_depth);
            }
            let r = 1.0 / inv_w;
            let (b0, b1, b2) = (q0 * r, q1 * r, q2 * r);
            let a = &cur.normal;
            // Normalised with the batch (in SIMD); a zero or unusable blend takes the face
            // normal instead.
            let n = a[0] * b0 + a[1] * b1 + a[2] * b2;
            let len2 = n.length_squared();
            let n = if len2 > 1e-30 && len2.is_finite() {
                n
            } else {
                face_normal(t, &ctx.verts.world)
            };
            let n = if ctx.two_sided && !t.front { -n } else { n };
            let p = cur.pos[0] * b0 + cur.pos[1] * b1 + cur.pos[2] * b2;
            let m = cur.material.expect("loaded for phong");
            batch.push::<P, FOG>(ctx, rect, m, n, p, (j, i), eye_depth, color);
        }
    }
    batch.flush::<P, FOG>(ctx, rect, color);
}

/// The world-space face normal in the triangle's original winding (zero if degenerate).
fn face_normal(t: &SetupTri, world: &[Vec3]) -> Vec3 {
    let [a, b, c] = t.v.map(|k| world[k as usize]);
    let n = (b - a).cross(c - a).normalize_or_zero();
    // Setup swapped two vertices of front faces to make the screen area positive.
    if t.front {
        -n
    } else {
        n
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

    #[test]
    fn u8_store_is_round_of_clamp_times_255() {
        let reference = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        let mut values = vec![
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -1e30,
            -1.0,
            -0.5 / 255.0,
            -1e-9,
            0.0,
            -0.0,
            1.0,
            1.0 + f32::EPSILON,
            1.5,
            1e30,
        ];
        // Every rounding boundary (k + 0.5)/255 and its neighbours.
        for k in 0..256 {
            let b = (k as f32 + 0.5) / 255.0;
            values.extend([
                b,
                f32::from_bits(b.to_bits() - 1),
                f32::from_bits(b.to_bits() + 1),
            ]);
        }
        for v in values {
            let mut out = [0u8; 3];
            u8::store(&mut out, Vec3::splat(v));
            assert_eq!(out, [reference(v); 3], "{v}");
        }
    }
}
