//! Phong: normals and positions interpolated per pixel, lit [`LANES`] pixels at a time.

use glam::Vec3;

use super::id_runs::{row_runs, Run};
use super::planes::{weight_planes, PlaneCache};
use super::program::finish_batch;
use super::store::{fill_out, put, Out, Pixel};
use super::{background_row, ShadeContext};
use crate::lighting::{lane, normalize_lanes, set_lane, Folded, Lanes, Surface, LANES};
use crate::pipeline::raster::{TileBuffers, NO_TRIANGLE};
use crate::pipeline::setup::SetupTri;
use crate::pipeline::tiles::{TileRect, TILE};
use crate::shadows::ShadowEffect;

/// Phong: per-triangle data, made once per triangle and tile and kept in a cache of recent
/// triangles (a row alternates between neighbouring triangles, and copying this out each
/// time the triangle changed cost more than making it).
#[derive(Clone, Copy, Default)]
struct Current<'a> {
    /// What is interpolated, as planes over pixel coordinates (f64): the interpolated 1/w
    /// (Σ λ_k/w_k), then the three axes of the normal and of the position, each over w
    /// (Σ λ_k/w_k · a_k), so a pixel's value is plane / (1/w): seven planes stepped along a
    /// row ([`RowPlanes`]) instead of three weights and eighteen products per pixel.
    /// Coefficient-major (`planes[c][attribute]`, the eighth unused), so a row's start
    /// values are a few SIMD operations.
    planes: [[f64; ROW_PLANES]; 3],
    material: Option<&'a Surface>,
    /// The face normal (read with shadows only; zero otherwise).
    face: Vec3,
    /// Planes too steep in x to step in f32 across a tile row ([`STEEP`]): slivers, whose
    /// pixels are then evaluated one by one in f64.
    steep: bool,
}

/// A triangle is steep when a weight plane changes by more than this many times the
/// largest vertex 1/w across a tile row: stepped in f32 from the row's first pixel, the
/// start value's rounding (2⁻²⁴ of it) would then exceed about 2⁻¹⁶ of the values
/// interpolated. Only triangles narrower than a quarter of a pixel across x reach it (the
/// x-gradient of a barycentric is about 1 / the triangle's width); their rows are one or
/// two pixels long anyway.
const STEEP: f64 = 256.0;

/// Planes of [`Current`]: 1/w, the normal's three axes, the position's three, and one
/// unused, so a row's eight values fill whole SIMD registers.
const ROW_PLANES: usize = 8;

impl<'a> Current<'a> {
    #[allow(clippy::needless_range_loop)] // plane coefficient c of several arrays
    fn make<const AFFINE: bool, const SHADOWS: bool>(ctx: &ShadeContext<'a>, t: &SetupTri) -> Self {
        let v = t.v.map(|k| k as usize);
        let back = ctx.two_sided && !t.front;
        let w = weight_planes::<AFFINE>(ctx, t);
        let n = v.map(|k| ctx.verts.normal[k].as_dvec3().to_array());
        let p = v.map(|k| ctx.verts.world[k].as_dvec3().to_array());
        let mut planes = [[0.0; ROW_PLANES]; 3];
        // Written out, as in `RunPlanes::new` (per triangle and tile).
        for (c, pc) in planes.iter_mut().enumerate() {
            pc[0] = w[0][c] + w[1][c] + w[2][c];
            for axis in 0..3 {
                pc[1 + axis] = w[0][c] * n[0][axis] + w[1][c] * n[1][axis] + w[2][c] * n[2][axis];
                pc[4 + axis] = w[0][c] * p[0][axis] + w[1][c] * p[1][axis] + w[2][c] * p[2][axis];
            }
        }
        let scale = if AFFINE {
            1.0
        } else {
            t.inv_w.iter().fold(0.0f64, |m, &v| m.max(v.abs() as f64))
        };
        // A NaN gradient or a zero scale (never for a drawn triangle) fails the test too:
        // steep, the exact path.
        let limit = STEEP * scale / TILE as f64;
        let steep = !w.iter().all(|p| p[0].abs() <= limit);
        Current {
            planes,
            steep,
            material: Some(&ctx.materials[t.object as usize][back as usize]),
            face: if SHADOWS {
                face_normal(t, &ctx.verts.world)
            } else {
                Vec3::ZERO
            },
        }
    }
}

/// The planes of [`Current`] along one tile row, in f32: each value at the row's pixel k is
/// `start + step·k` (eight pixels a SIMD operation). They start at the row's first pixel,
/// not a run's, so a pixel's inputs do not depend on where its run starts (the layers of a
/// multi-sample tile split rows into other runs), as Gouraud's colours ([`RunColors`]).
/// Against the f64 weights per pixel and the blend of the vertex values by them that this
/// replaced, on spheres of 288 to 998,000 triangles at 910 × 512 and 1920 × 1080 with a sun
/// and a point light: at most 1.1·10⁻⁵ in f32 output (3·10⁻³ of an 8-bit level; with a
/// shadow map 3.2·10⁻⁴, where a position moved across a depth comparison's edge), and at
/// most 34 of 6.2 M u8 samples one level apart.
///
/// [`RunColors`]: super::planes::RunColors
#[derive(Clone, Copy)]
struct RowPlanes {
    start: [f32; ROW_PLANES],
    step: [f32; ROW_PLANES],
}

impl RowPlanes {
    /// `cur`'s planes from the row's first pixel centre (x, y).
    #[inline(always)]
    fn new(cur: &Current<'_>, x: f64, y: f64) -> Self {
        let [a, b, c] = &cur.planes;
        let mut r = RowPlanes {
            start: [0.0; ROW_PLANES],
            step: [0.0; ROW_PLANES],
        };
        for k in 0..ROW_PLANES {
            r.start[k] = (a[k] * x + b[k] * y + c[k]) as f32;
            r.step[k] = a[k] as f32;
        }
        r
    }

    /// Interpolated 1/w, normal (not normalised) and position at the row's pixel `k`. Every
    /// path computes them with this function (lanes and single pixels alike; Rust fuses no
    /// multiply-add unasked), so a pixel's inputs do not depend on the path.
    #[inline(always)]
    fn at(&self, k: f32) -> (f32, [f32; 3], [f32; 3]) {
        let (s, d) = (&self.start, &self.step);
        let inv_w = s[0] + d[0] * k;
        let r = 1.0 / inv_w;
        let v = |a: usize| (s[a] + d[a] * k) * r;
        (inv_w, [v(1), v(2), v(3)], [v(4), v(5), v(6)])
    }
}

/// The normal of one pixel from its interpolated `n`: the face normal for a zero or unusable
/// blend, flipped for the back of a two-sided surface (as [`RowPlanes::lanes`] per lane).
#[inline(always)]
fn usable_normal(ctx: &ShadeContext<'_>, t: &SetupTri, n: [f32; 3]) -> Vec3 {
    let n = or_face_normal(ctx, t, Vec3::from_array(n));
    if ctx.two_sided && !t.front {
        -n
    } else {
        n
    }
}

/// `n`, or the face normal where `n` is zero or not finite (a blend of opposed or unusable
/// vertex normals): one test for the one-pixel path and the lanes' fix-up.
#[inline(always)]
fn or_face_normal(ctx: &ShadeContext<'_>, t: &SetupTri, n: Vec3) -> Vec3 {
    let len2 = n.length_squared();
    if len2 > 1e-30 && len2.is_finite() {
        n
    } else {
        face_normal(t, &ctx.verts.world)
    }
}

/// Twice [`LANES`]: a batch holds up to `LANES - 1` waiting pixels plus a whole run chunk
/// appended behind them in one fixed-size copy.
const ROOM: usize = 2 * LANES;

/// Pixels waiting to be lit together, all with the same material. The first [`LANES`]
/// are lit when full; lanes at `len` and beyond hold stale values that nothing reads.
struct PhongBatch<'a> {
    /// Interpolated normals, not yet normalised (never zero).
    n: [[f32; ROOM]; 3],
    p: [[f32; ROOM]; 3],
    /// (row in tile, column in tile) of each lane.
    at: [(usize, usize); ROOM],
    /// Eye depth of each lane (for fog).
    depth: [f32; ROOM],
    len: usize,
    material: Option<&'a Surface>,
    /// Geometric (face) normals per lane, and each source's visibility: read only by the
    /// loop with shadows.
    g: [[f32; ROOM]; 3],
    vis: Vec<Option<Lanes>>,
}

/// The first [`LANES`] of each row of `a`.
#[inline(always)]
fn head(a: &[[f32; ROOM]; 3]) -> [Lanes; 3] {
    a.map(|r| r[..LANES].try_into().expect("ROOM > LANES"))
}

/// Moves lanes `LANES..ROOM` of `a` to its front.
#[inline(always)]
fn shift<T: Copy>(a: &mut [T; ROOM]) {
    a.copy_within(LANES..ROOM, 0);
}

impl<'a> PhongBatch<'a> {
    #[inline(always)]
    fn flush<P: Pixel, const SHADOWS: bool>(
        &mut self,
        ctx: &ShadeContext<'_>,
        rect: TileRect,
        color: &mut [&mut [Out<P>]],
    ) {
        let eye = ctx.eye;
        let len = self.len.min(LANES);
        if let Some(m) = self.material.filter(|_| len > 0) {
            let raw = head(&self.n);
            let p = head(&self.p);
            let lit = match &ctx.shadows {
                Some(shadows) if SHADOWS => {
                    let g = head(&self.g);
                    shadowed_lanes(ctx, shadows, m, (&raw, &p, &g), len, &mut self.vis)
                }
                _ => light_lanes(m, &raw, &p, eye, ctx.wide()),
            };
            let depth: Lanes = self.depth[..LANES].try_into().expect("ROOM > LANES");
            finish_batch(ctx, lit, &self.at[..len], &depth, rect, color);
        }
        self.len -= len;
    }
}

/// Lights [`LANES`] pixels of material `m` without shadows: the raw normals `raw` (not yet
/// normalised) normalised, then the lighting equation at positions `p`. One function for
/// the batch and a run's whole groups, so both give the same pixels.
#[inline(always)]
fn light_lanes(m: &Surface, raw: &[Lanes; 3], p: &[Lanes; 3], eye: Vec3, wide: bool) -> [Lanes; 3] {
    let mut n = [[0.0; LANES]; 3];
    normalize_lanes(&mut n, raw, wide);
    m.shade_lanes(&n, p, eye)
}

/// Lights [`LANES`] pixels of material `m` with shadows: the raw normals (not yet
/// normalised), positions and geometric normals `(raw, p, g)` of the first `live` lanes;
/// `vis` receives each source's visibility. One function for the batch and a run's whole
/// groups, so both give the same pixels.
#[inline(always)]
fn shadowed_lanes(
    ctx: &ShadeContext<'_>,
    shadows: &ShadowEffect,
    m: &Surface,
    (raw, p, g): (&[Lanes; 3], &[Lanes; 3], &[Lanes; 3]),
    live: usize,
    vis: &mut [Option<Lanes>],
) -> [Lanes; 3] {
    let mut n = [[0.0; LANES]; 3];
    normalize_lanes(&mut n, raw, ctx.wide());
    shadows.visibility(&n, p, g, live, vis);
    m.terms_lanes_visible::<Folded>(&n, p, ctx.eye, vis).0
}

/// The interpolated inputs of up to [`LANES`] consecutive pixels of one triangle's run.
struct RunLanes {
    /// Interpolated normals, not yet normalised (a zero or unusable blend replaced by the
    /// face normal, flipped for the back of a two-sided surface).
    n: [Lanes; 3],
    p: [Lanes; 3],
    /// Eye depth of each lane (0 unless wanted).
    depth: Lanes,
}

impl RowPlanes {
    /// 1/w, the normal (not normalised) and the position of the row's pixels `k0 + k`
    /// (k < [`LANES`]), as [`RowPlanes::at`] per lane, and whether a lane's normal is unusable
    /// (|n|² at most 1e-30, infinite or NaN, as [`or_face_normal`] tests it): every lane is
    /// tested (those past a run's end extrapolate the same planes and are rarely unusable;
    /// if one is, only the fix-up runs for nothing).
    ///
    /// In AVX when `wide` (the render's ISA is AVX2; inlined into its tile bodies): as lane
    /// loops, LLVM kept the planes' start and step values in stack copies and reloaded them
    /// (a store-forwarding stall perf put at 12 % of a Phong tile), and read the normals
    /// back from memory for the test (9 %). The same operations per lane either way, so the
    /// same bits.
    #[inline(always)]
    fn interpolate(
        &self,
        k0: usize,
        inv_w: &mut Lanes,
        n: &mut [Lanes; 3],
        p: &mut [Lanes; 3],
        wide: bool,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if wide {
            // SAFETY: `wide` only where the render's ISA is AVX2, detected on this CPU.
            return unsafe { self.interpolate_avx(k0, inv_w, n, p) };
        }
        let _ = wide;
        self.interpolate_lanes(k0, inv_w, n, p)
    }

    /// [`RowPlanes::interpolate`] as lane loops.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays
    fn interpolate_lanes(
        &self,
        k0: usize,
        inv_w: &mut Lanes,
        n: &mut [Lanes; 3],
        p: &mut [Lanes; 3],
    ) -> bool {
        let (s, d) = (&self.start, &self.step);
        let mut kf: Lanes = [0.0; LANES];
        let mut r: Lanes = [0.0; LANES];
        for k in 0..LANES {
            // Via i32: one SIMD conversion (k0 + k < TILE + LANES).
            kf[k] = (k0 + k) as i32 as f32;
            inv_w[k] = s[0] + d[0] * kf[k];
            r[k] = 1.0 / inv_w[k];
        }
        for axis in 0..3 {
            let (sn, dn, sp, dp) = (s[1 + axis], d[1 + axis], s[4 + axis], d[4 + axis]);
            for k in 0..LANES {
                n[axis][k] = (sn + dn * kf[k]) * r[k];
                p[axis][k] = (sp + dp * kf[k]) * r[k];
            }
        }
        // A mask OR-ed over the lanes, which vectorises where a `bool` reduction did not.
        let mut unusable = 0u32;
        for k in 0..LANES {
            let len2 = n[0][k] * n[0][k] + n[1][k] * n[1][k] + n[2][k] * n[2][k];
            // `&`, not `&&`: no branch per lane. len2 ≥ 0 or NaN.
            unusable |= u32::from(!((len2 > 1e-30) & (len2 < f32::INFINITY)));
        }
        unusable != 0
    }

    /// [`RowPlanes::interpolate`] in AVX.
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    #[inline]
    unsafe fn interpolate_avx(
        &self,
        k0: usize,
        inv_w: &mut Lanes,
        n: &mut [Lanes; 3],
        p: &mut [Lanes; 3],
    ) -> bool {
        use std::arch::x86_64::*;
        let (s, d) = (&self.start, &self.step);
        // k0 + k as f32, exact (k0 + k < TILE + LANES), as the lane loop's i32 conversion.
        let base = k0 as i32;
        let kf = _mm256_cvtepi32_ps(_mm256_setr_epi32(
            base,
            base + 1,
            base + 2,
            base + 3,
            base + 4,
            base + 5,
            base + 6,
            base + 7,
        ));
        let at = |c: usize| {
            _mm256_add_ps(
                _mm256_set1_ps(s[c]),
                _mm256_mul_ps(_mm256_set1_ps(d[c]), kf),
            )
        };
        let w = at(0);
        let r = _mm256_div_ps(_mm256_set1_ps(1.0), w);
        let nv = [1, 2, 3].map(|c| _mm256_mul_ps(at(c), r));
        // SAFETY: each store writes one lane array's eight f32.
        unsafe {
            _mm256_storeu_ps(inv_w.as_mut_ptr(), w);
            for axis in 0..3 {
                _mm256_storeu_ps(n[axis].as_mut_ptr(), nv[axis]);
                _mm256_storeu_ps(p[axis].as_mut_ptr(), _mm256_mul_ps(at(4 + axis), r));
            }
        }
        // The lane loop's test on the values in registers (reading the stores back stalled).
        let sq = |v: __m256| _mm256_mul_ps(v, v);
        let len2 = _mm256_add_ps(_mm256_add_ps(sq(nv[0]), sq(nv[1])), sq(nv[2]));
        let ok = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(len2, _mm256_set1_ps(1e-30)),
            _mm256_cmp_ps::<_CMP_LT_OQ>(len2, _mm256_set1_ps(f32::INFINITY)),
        );
        _mm256_movemask_ps(ok) != 0xff
    }
}

impl RowPlanes {
    /// The inputs of the row's pixels `k0 + k` (k < [`LANES`]), with stored depths `z`: the
    /// same operations, in the same order, as [`RowPlanes::at`] per lane, over whole lanes
    /// (SIMD), and the normal as [`usable_normal`].
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    #[allow(clippy::too_many_arguments)]
    fn lanes<const AFFINE: bool>(
        &self,
        ctx: &ShadeContext<'_>,
        t: &SetupTri,
        k0: usize,
        z: &Lanes,
        live: usize,
        want_depth: bool,
        out: &mut RunLanes,
    ) {
        let mut inv_w: Lanes = [0.0; LANES];
        let unusable = self.interpolate(k0, &mut inv_w, &mut out.n, &mut out.p, ctx.wide());
        for k in 0..LANES {
            out.depth[k] = ctx.eye_depth::<AFFINE>(want_depth, z[k], inv_w[k]);
        }
        // A zero or unusable blend takes the face normal instead: found over whole lanes
        // (`interpolate`), fixed up one lane at a time (rare).
        if unusable {
            for k in 0..live {
                let f = or_face_normal(ctx, t, lane(&out.n, k));
                set_lane(&mut out.n, k, f);
            }
        }
        if ctx.two_sided && !t.front {
            for axis in &mut out.n {
                for v in axis {
                    *v = -*v;
                }
            }
        }
    }
}

impl<'a> PhongBatch<'a> {
    /// Appends one pixel at tile slot (row, column) `at`, flushing when the batch fills.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn push<P: Pixel, const SHADOWS: bool>(
        &mut self,
        ctx: &ShadeContext<'_>,
        rect: TileRect,
        (m, g): (&'a Surface, Vec3),
        (n, p, depth): (Vec3, Vec3, f32),
        at: (usize, usize),
        color: &mut [&mut [Out<P>]],
    ) {
        if self.len > 0 && !std::ptr::eq(m, self.material.unwrap_or(m)) {
            self.flush::<P, SHADOWS>(ctx, rect, color);
        }
        self.material = Some(m);
        let k = self.len;
        set_lane(&mut self.n, k, n);
        set_lane(&mut self.p, k, p);
        if SHADOWS {
            set_lane(&mut self.g, k, g);
        }
        self.at[k] = at;
        self.depth[k] = depth;
        self.len += 1;
        if self.len == LANES {
            self.flush::<P, SHADOWS>(ctx, rect, color);
        }
    }

    /// Appends the first `live` lanes of a run chunk starting at tile column `i` of row `j`,
    /// all of material `m`, flushing whenever the batch fills.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn extend<P: Pixel, const SHADOWS: bool>(
        &mut self,
        ctx: &ShadeContext<'_>,
        rect: TileRect,
        m: &'a Surface,
        g: Vec3,
        lanes: &RunLanes,
        live: usize,
        want_depth: bool,
        (j, i): (usize, usize),
        color: &mut [&mut [Out<P>]],
    ) {
        if self.len > 0 && !std::ptr::eq(m, self.material.unwrap_or(m)) {
            self.flush::<P, SHADOWS>(ctx, rect, color);
        }
        self.material = Some(m);
        // The whole chunk behind the waiting pixels (fixed-size copies; the lanes past
        // `live` are stale and never read), then the first LANES lit and the rest moved
        // to the front.
        let at = self.len;
        for axis in 0..3 {
            self.n[axis][at..at + LANES].copy_from_slice(&lanes.n[axis]);
            self.p[axis][at..at + LANES].copy_from_slice(&lanes.p[axis]);
            if SHADOWS {
                self.g[axis][at..at + LANES].fill(g[axis]);
            }
        }
        for (k, slot) in self.at[at..at + LANES].iter_mut().enumerate() {
            *slot = (j, i + k);
        }
        if want_depth {
            // Read by the program's stages only (fog); unread, the copy stalled on the
            // lanes' scalar stores (7 % of a Phong tile in perf).
            self.depth[at..at + LANES].copy_from_slice(&lanes.depth);
        }
        self.len += live;
        if self.len >= LANES {
            self.flush::<P, SHADOWS>(ctx, rect, color);
            for axis in 0..3 {
                shift(&mut self.n[axis]);
                shift(&mut self.p[axis]);
                if SHADOWS {
                    shift(&mut self.g[axis]);
                }
            }
            shift(&mut self.at);
            shift(&mut self.depth);
        }
    }
}

/// Entries of the per-tile cache of [`Current`]. A Phong frame of Spot (23,424 triangles
/// at 512 × 512) made 16,677 of them with 64 entries (as the flat/Gouraud run caches did,
/// `runs.rs`), 13,610 with 128, 11,945 with 256. 256 entries of 224 bytes are 57 KB, more
/// than L1d: callgrind's cache model counted 16 % more L1 misses on Spot against 6 %
/// fewer instructions, and the frame measured no slower (a 99,224-triangle sphere, whose
/// triangles are smaller, about the same).
const PHONG_CACHE: usize = 256;

/// Runs of a triangle at least this long are interpolated a lane loop at a time.
const LANE_RUN: usize = 4;

/// Phong: interpolation over whole runs of a triangle's pixels in a row ([`LANES`] at a
/// time), lighting [`LANES`] pixels at a time.
#[inline(always)]
pub(super) fn shade_phong<
    P: Pixel,
    const STAGES_READ_DEPTH: bool,
    const AFFINE: bool,
    const SHADOWS: bool,
>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    mut depth: Option<&mut [&mut [Out<f32>]]>,
) {
    // Whether the program's stages read the eye depth (fog does) is a constant of the loop:
    // a per-pixel test of it cost 3 % more instructions per Phong frame.
    let want_depth = depth.is_some() || STAGES_READ_DEPTH;
    let mut cache = PlaneCache::<Current, PHONG_CACHE>::new();
    let mut cur_id = NO_TRIANGLE;
    let mut cur = &Current::default();
    let background = background_row::<P>(ctx);
    let mut batch = PhongBatch {
        n: [[0.0; ROOM]; 3],
        p: [[0.0; ROOM]; 3],
        at: [(0, 0); ROOM],
        depth: [0.0; ROOM],
        len: 0,
        material: None,
        g: [[0.0; ROOM]; 3],
        vis: match &ctx.shadows {
            Some(s) if SHADOWS => vec![None; s.sources()],
            _ => Vec::new(),
        },
    };
    let mut lanes = RunLanes {
        n: [[0.0; LANES]; 3],
        p: [[0.0; LANES]; 3],
        depth: [0.0; LANES],
    };
    for j in 0..rect.h {
        let y = (rect.y0 + j) as f64 + 0.5;
        let zs = &buf.depth[j * TILE..j * TILE + rect.w];
        for Run { id, start: i, end } in row_runs(buf, j, rect.w) {
            if id == NO_TRIANGLE {
                put(&mut color[j][i * 3..end * 3], &background[..(end - i) * 3]);
                if let Some(d) = depth.as_deref_mut() {
                    fill_out(&mut d[j][i..end], f32::INFINITY);
                }
                continue;
            }
            let t = ctx.tris.get(id);
            if id != cur_id {
                cur = cache.get_ref(id, || Current::make::<AFFINE, SHADOWS>(ctx, t));
                cur_id = id;
            }
            let (m, face) = (cur.material.expect("made for phong"), cur.face);
            let row = RowPlanes::new(cur, rect.x0 as f64 + 0.5, y);
            if end - i < LANE_RUN || cur.steep {
                // Short runs (small triangles) a pixel at a time: a whole lane loop for a
                // few live lanes measured slower. A steep triangle's planes are evaluated
                // at each pixel itself (in f64, as a row's start), not stepped.
                for k in i..end {
                    let (inv_w, n, p) = if cur.steep {
                        RowPlanes::new(cur, (rect.x0 + k) as f64 + 0.5, y).at(0.0)
                    } else {
                        row.at(k as i32 as f32)
                    };
                    let eye_depth = ctx.eye_depth::<AFFINE>(want_depth, zs[k], inv_w);
                    if let Some(d) = depth.as_deref_mut() {
                        d[j][k].write(eye_depth);
                    }
                    let px = (usable_normal(ctx, t, n), Vec3::from_array(p), eye_depth);
                    batch.push::<P, SHADOWS>(ctx, rect, (m, face), px, (j, k), color);
                }
                continue;
            }
            for s in (i..end).step_by(LANES) {
                let live = (end - s).min(LANES);
                let mut z = [0.0; LANES];
                if want_depth {
                    z[..live].copy_from_slice(&zs[s..s + live]);
                }
                row.lanes::<AFFINE>(ctx, t, s, &z, live, want_depth, &mut lanes);
                if let Some(d) = depth.as_deref_mut() {
                    for (o, &v) in d[j][s..s + live].iter_mut().zip(&lanes.depth) {
                        o.write(v);
                    }
                }
                if live == LANES {
                    // A whole group of the run is lit where it was interpolated: no copy
                    // into the batch and out again (same inputs, same pixels; with shadows
                    // the copy's loads stalled on its stores, perf: 12 % of the tile).
                    let lit = match &ctx.shadows {
                        Some(shadows) if SHADOWS => {
                            let g = face.to_array().map(|c| [c; LANES]);
                            let inputs = (&lanes.n, &lanes.p, &g);
                            shadowed_lanes(ctx, shadows, m, inputs, LANES, &mut batch.vis)
                        }
                        _ => light_lanes(m, &lanes.n, &lanes.p, ctx.eye, ctx.wide()),
                    };
                    if ctx.program.is_empty() {
                        // Consecutive pixels: stored as a row, not through per-pixel slots.
                        P::store_group(&mut color[j][s * 3..(s + LANES) * 3], &lit, ctx.wide());
                    } else {
                        let at: [(usize, usize); LANES] = std::array::from_fn(|k| (j, s + k));
                        finish_batch(ctx, lit, &at, &lanes.depth, rect, color);
                    }
                    continue;
                }
                batch.extend::<P, SHADOWS>(
                    ctx,
                    rect,
                    m,
                    face,
                    &lanes,
                    live,
                    want_depth,
                    (j, s),
                    color,
                );
            }
        }
    }
    batch.flush::<P, SHADOWS>(ctx, rect, color);
}

/// The world-space face normal in the triangle's original winding (zero if degenerate).
pub(super) fn face_normal(t: &SetupTri, world: &[Vec3]) -> Vec3 {
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

    /// The AVX interpolation gives the lane loops' bits (and `at`'s, per lane) for every
    /// start column of a tile row, rows far from the origin, and planes of every sign and
    /// scale; and the same verdict on unusable normals.
    #[test]
    fn interpolate_forms_agree() {
        let value = |k: usize| {
            let m = [1.0f64, -3.5e-3, 7.25, -0.0, 1e-7, -2.5e4, 0.3333, 12.0][k % 8];
            m * (1.0 + (k / 8) as f64 * 0.37)
        };
        let with = |planes: [[f64; ROW_PLANES]; 3]| Current {
            planes,
            ..Current::default()
        };
        // Besides the spread of values: a zero normal, a NaN one and one whose square
        // overflows, all unusable (the face normal's cases).
        let special = [0.0, f64::NAN, 1e20].map(|v| {
            with([
                [0.0; ROW_PLANES],
                [0.0; ROW_PLANES],
                [1.0, v, v, v, 0.5, 0.5, 0.5, 0.0],
            ])
        });
        let spread = (0..16).map(|seed| {
            with(std::array::from_fn(|c| {
                std::array::from_fn(|k| value(k * (c + 1) + seed) * [1e-2, 1e-3, 1.0][c])
            }))
        });
        #[cfg(target_arch = "x86_64")]
        let wide = std::arch::is_x86_feature_detected!("avx");
        #[cfg(not(target_arch = "x86_64"))]
        let wide = false;
        let mut unusable = 0;
        for cur in special.into_iter().chain(spread) {
            for xy in [(0.5, 0.5), (64.5, 37.5), (1856.5, 1079.5)] {
                let row = RowPlanes::new(&cur, xy.0, xy.1);
                for k0 in 0..TILE {
                    let zero = || ([0.0; LANES], [[0.0; LANES]; 3], [[0.0; LANES]; 3]);
                    let ((mut w, mut n, mut p), (mut w2, mut n2, mut p2)) = (zero(), zero());
                    let bad = row.interpolate(k0, &mut w, &mut n, &mut p, wide);
                    let bad2 = row.interpolate_lanes(k0, &mut w2, &mut n2, &mut p2);
                    assert_eq!(bad, bad2);
                    unusable += usize::from(bad);
                    let bits = |a: &Lanes| a.map(f32::to_bits);
                    assert_eq!(bits(&w), bits(&w2));
                    for axis in 0..3 {
                        assert_eq!(bits(&n[axis]), bits(&n2[axis]));
                        assert_eq!(bits(&p[axis]), bits(&p2[axis]));
                    }
                    for (k, wk) in w.iter().enumerate() {
                        let (aw, an, ap) = row.at((k0 + k) as f32);
                        assert_eq!(aw.to_bits(), wk.to_bits());
                        assert_eq!(
                            an.map(f32::to_bits),
                            lane(&n, k).to_array().map(f32::to_bits)
                        );
                        assert_eq!(
                            ap.map(f32::to_bits),
                            lane(&p, k).to_array().map(f32::to_bits)
                        );
                    }
                }
            }
        }
        assert!(
            unusable >= 9 * TILE,
            "the special rows are unusable at every column"
        );
    }
}
