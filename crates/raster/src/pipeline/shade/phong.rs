//! Phong: normals and positions interpolated per pixel, lit [`LANES`] pixels at a time.

use glam::Vec3;

use super::planes::{weight_planes, Plane, PlaneCache};
use super::program::finish_batch;
use super::runs::run_length;
use super::store::{fill_out, put, Out, Pixel};
use super::{background_row, ShadeContext};
use crate::lighting::{normalize_lanes, Folded, Lanes, Surface, LANES};
use crate::pipeline::raster::{TileBuffers, NO_TRIANGLE};
use crate::pipeline::setup::SetupTri;
use crate::pipeline::tiles::{TileRect, TILE};

/// Phong: per-triangle data, made once per triangle and tile and kept in a cache of recent
/// triangles (a row alternates between neighbouring triangles, and copying this out each
/// time the triangle changed cost more than making it).
#[derive(Clone, Copy, Default)]
struct Current<'a> {
    /// Perspective weight planes ([`weight_planes`]).
    plane: [Plane; 3],
    normal: [Vec3; 3],
    pos: [Vec3; 3],
    material: Option<&'a Surface>,
    /// The face normal (read with shadows only; zero otherwise).
    face: Vec3,
}

impl<'a> Current<'a> {
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

    /// The inputs of one pixel at (x, y) (pixel centre) with stored depth `z`: the normal
    /// (not yet normalised; the face normal for a zero or unusable blend, flipped for the
    /// back of a two-sided surface), the position and the eye depth (0 unless wanted). The
    /// same operations in the same order as [`Current::lanes`] per lane.
    #[inline(always)]
    fn pixel<const AFFINE: bool>(
        &self,
        ctx: &ShadeContext<'_>,
        t: &SetupTri,
        (x, y): (f64, f64),
        z: f32,
        want_depth: bool,
    ) -> (Vec3, Vec3, f32) {
        let [q0, q1, q2] = self.weights(x, y);
        let inv_w = q0 + q1 + q2;
        let eye_depth = ctx.eye_depth::<AFFINE>(want_depth, z, inv_w);
        let r = 1.0 / inv_w;
        let (b0, b1, b2) = (q0 * r, q1 * r, q2 * r);
        let a = &self.normal;
        let n = a[0] * b0 + a[1] * b1 + a[2] * b2;
        let len2 = n.length_squared();
        let n = if len2 > 1e-30 && len2.is_finite() {
            n
        } else {
            face_normal(t, &ctx.verts.world)
        };
        let n = if ctx.two_sided && !t.front { -n } else { n };
        let p = self.pos[0] * b0 + self.pos[1] * b1 + self.pos[2] * b2;
        (n, p, eye_depth)
    }

    fn make<const AFFINE: bool, const SHADOWS: bool>(ctx: &ShadeContext<'a>, t: &SetupTri) -> Self {
        let v = t.v.map(|k| k as usize);
        let back = ctx.two_sided && !t.front;
        Current {
            plane: weight_planes::<AFFINE>(ctx, t),
            normal: v.map(|k| ctx.verts.normal[k]),
            pos: v.map(|k| ctx.verts.world[k]),
            material: Some(&ctx.materials[t.object as usize][back as usize]),
            face: if SHADOWS {
                face_normal(t, &ctx.verts.world)
            } else {
                Vec3::ZERO
            },
        }
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
            let raw = &self.n;
            let raw = |k: usize| (raw[0][k], raw[1][k], raw[2][k]);
            let p = head(&self.p);
            let lit = match &ctx.shadows {
                Some(shadows) if SHADOWS => {
                    let mut n = [[0.0; LANES]; 3];
                    normalize_lanes(&mut n, raw);
                    let g = head(&self.g);
                    shadows.visibility(&n, &p, &g, len, &mut self.vis);
                    m.terms_lanes_visible::<Folded>(&n, &p, eye, &self.vis).0
                }
                _ => light_lanes(m, raw, &p, eye),
            };
            let depth: Lanes = self.depth[..LANES].try_into().expect("ROOM > LANES");
            finish_batch(ctx, lit, &self.at[..len], &depth, rect, color);
        }
        self.len -= len;
    }
}

/// Lights [`LANES`] pixels of material `m` without shadows: the raw normals (`raw(k)` for
/// lane k, not yet normalised) normalised, then the lighting equation at positions `p`.
/// One function for the batch and a run's whole groups, so both give the same pixels.
#[inline(always)]
fn light_lanes(
    m: &Surface,
    raw: impl Fn(usize) -> (f32, f32, f32),
    p: &[Lanes; 3],
    eye: Vec3,
) -> [Lanes; 3] {
    let mut n = [[0.0; LANES]; 3];
    normalize_lanes(&mut n, raw);
    m.shade_lanes(&n, p, eye)
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

impl Current<'_> {
    /// The inputs of the pixels at x = `x0 + k` (pixel centres, k < `LANES`) of the row at
    /// `y`, with stored depths `z`: the same operations, in the same order, as one pixel at a
    /// time, over whole lanes (SIMD).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    #[allow(clippy::too_many_arguments)]
    fn lanes<const AFFINE: bool>(
        &self,
        ctx: &ShadeContext<'_>,
        t: &SetupTri,
        x0: f64,
        y: f64,
        z: &Lanes,
        live: usize,
        want_depth: bool,
        out: &mut RunLanes,
    ) {
        let pl = &self.plane;
        // `p[1]·y` is constant along the row; it is the same product per lane.
        let row = [pl[0][1] * y, pl[1][1] * y, pl[2][1] * y];
        let mut b = [[0.0f32; LANES]; 3];
        let mut inv_w: Lanes = [0.0; LANES];
        for k in 0..LANES {
            let x = x0 + k as i32 as f64;
            let q0 = (pl[0][0] * x + row[0] + pl[0][2]) as f32;
            let q1 = (pl[1][0] * x + row[1] + pl[1][2]) as f32;
            let q2 = (pl[2][0] * x + row[2] + pl[2][2]) as f32;
            let iw = q0 + q1 + q2;
            let r = 1.0 / iw;
            inv_w[k] = iw;
            (b[0][k], b[1][k], b[2][k]) = (q0 * r, q1 * r, q2 * r);
        }
        for k in 0..LANES {
            out.depth[k] = ctx.eye_depth::<AFFINE>(want_depth, z[k], inv_w[k]);
        }
        blend_lanes(&self.normal, &b, &mut out.n);
        blend_lanes(&self.pos, &b, &mut out.p);
        // A zero or unusable blend takes the face normal instead: found over whole lanes
        // (SIMD), fixed up one lane at a time (rare).
        let mut unusable = false;
        for k in 0..LANES {
            let (x, y, z) = (out.n[0][k], out.n[1][k], out.n[2][k]);
            let len2 = x * x + y * y + z * z;
            // `&`, not `&&`: no branch per lane.
            unusable |= (k < live) & !((len2 > 1e-30) & (len2.abs() < f32::INFINITY));
        }
        if unusable {
            for k in 0..live {
                let (x, y, z) = (out.n[0][k], out.n[1][k], out.n[2][k]);
                let len2 = x * x + y * y + z * z;
                if !(len2 > 1e-30 && len2.is_finite()) {
                    let f = face_normal(t, &ctx.verts.world);
                    (out.n[0][k], out.n[1][k], out.n[2][k]) = (f.x, f.y, f.z);
                }
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

/// `a[0]·b0 + a[1]·b1 + a[2]·b2` per lane and axis (the order of the scalar form).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
fn blend_lanes(a: &[Vec3; 3], b: &[Lanes; 3], out: &mut [Lanes; 3]) {
    for (axis, o) in out.iter_mut().enumerate() {
        let (a0, a1, a2) = (a[0][axis], a[1][axis], a[2][axis]);
        for k in 0..LANES {
            o[k] = a0 * b[0][k] + a1 * b[1][k] + a2 * b[2][k];
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
        (self.n[0][k], self.n[1][k], self.n[2][k]) = (n.x, n.y, n.z);
        (self.p[0][k], self.p[1][k], self.p[2][k]) = (p.x, p.y, p.z);
        if SHADOWS {
            (self.g[0][k], self.g[1][k], self.g[2][k]) = (g.x, g.y, g.z);
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
        self.depth[at..at + LANES].copy_from_slice(&lanes.depth);
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
    let mut cache = PlaneCache::<Current>::new();
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
        let ids = &buf.id[j * TILE..j * TILE + rect.w];
        let zs = &buf.depth[j * TILE..j * TILE + rect.w];
        let mut i = 0;
        while i < rect.w {
            let id = ids[i];
            let end = i + run_length(&ids[i..], id);
            if id == NO_TRIANGLE {
                put(&mut color[j][i * 3..end * 3], &background[..(end - i) * 3]);
                if let Some(d) = depth.as_deref_mut() {
                    fill_out(&mut d[j][i..end], f32::INFINITY);
                }
                i = end;
                continue;
            }
            let t = ctx.tris.get(id);
            if id != cur_id {
                cur = cache.get_ref(id, || Current::make::<AFFINE, SHADOWS>(ctx, t));
                cur_id = id;
            }
            let (m, face) = (cur.material.expect("made for phong"), cur.face);
            if end - i < LANE_RUN {
                // Short runs (small triangles) a pixel at a time: a whole lane loop for a
                // few live lanes measured slower.
                for k in i..end {
                    let x = (rect.x0 + k) as f64 + 0.5;
                    let px = cur.pixel::<AFFINE>(ctx, t, (x, y), zs[k], want_depth);
                    if let Some(d) = depth.as_deref_mut() {
                        d[j][k].write(px.2);
                    }
                    batch.push::<P, SHADOWS>(ctx, rect, (m, face), px, (j, k), color);
                }
                i = end;
                continue;
            }
            for s in (i..end).step_by(LANES) {
                let live = (end - s).min(LANES);
                let mut z = [0.0; LANES];
                if want_depth {
                    z[..live].copy_from_slice(&zs[s..s + live]);
                }
                let x0 = (rect.x0 + s) as f64 + 0.5;
                cur.lanes::<AFFINE>(ctx, t, x0, y, &z, live, want_depth, &mut lanes);
                if let Some(d) = depth.as_deref_mut() {
                    for (o, &v) in d[j][s..s + live].iter_mut().zip(&lanes.depth) {
                        o.write(v);
                    }
                }
                if !SHADOWS && live == LANES {
                    // A whole group of the run is lit where it was interpolated: no copy
                    // into the batch and out again (same inputs, same pixels).
                    let raw = &lanes.n;
                    let raw = |k: usize| (raw[0][k], raw[1][k], raw[2][k]);
                    let lit = light_lanes(m, raw, &lanes.p, ctx.eye);
                    if ctx.program.is_empty() {
                        // Consecutive pixels: stored as a row, not through per-pixel slots.
                        P::store_group(&mut color[j][s * 3..(s + LANES) * 3], &lit);
                    } else {
                        let at: [(usize, usize); LANES] = std::array::from_fn(|k| (j, s + k));
                        finish_batch(ctx, lit, &at, &lanes.depth, rect, color);
                    }
                    continue;
                }
                batch.extend::<P, SHADOWS>(ctx, rect, m, face, &lanes, live, (j, s), color);
            }
            i = end;
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
