//! Phong: normals and positions interpolated per pixel, lit [`LANES`] pixels at a time.

use glam::Vec3;

use super::planes::{weight_planes, Plane, PlaneCache};
use super::program::Fragments;
use super::store::{put, store_out, Out, Pixel};
use super::{background_row, ShadeContext};
use crate::lighting::{normalize_lanes, Lanes, Surface, LANES};
use crate::pipeline::raster::{TileBuffers, NO_TRIANGLE};
use crate::pipeline::setup::SetupTri;
use crate::pipeline::tiles::{TileRect, TILE};

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

    fn load<const AFFINE: bool>(
        ctx: &ShadeContext<'a>,
        id: u32,
        t: &SetupTri,
        planes: &mut PlaneCache<[Plane; 3]>,
    ) -> Self {
        let v = t.v.map(|k| k as usize);
        let back = ctx.two_sided && !t.front;
        Current {
            id,
            plane: planes.get(id, || weight_planes::<AFFINE>(ctx, t)),
            normal: v.map(|k| ctx.verts.normal[k]),
            pos: v.map(|k| ctx.verts.world[k]),
            material: Some(&ctx.materials[t.object as usize][back as usize]),
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
    fn flush<P: Pixel>(
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
            let mut frags = Fragments {
                color: m.shade_lanes(&n, &self.p, eye),
                at: &self.at[..self.len],
                depth: &self.depth,
                origin: (rect.x0, rect.y0),
            };
            // The render's program after lighting: one branch per stage per batch.
            for stage in &ctx.program {
                stage.run(ctx, &mut frags);
            }
            let c = &frags.color;
            for (k, &(j, i)) in self.at[..self.len].iter().enumerate() {
                store_out(
                    &mut color[j][i * 3..i * 3 + 3],
                    Vec3::new(c[0][k], c[1][k], c[2][k]),
                );
            }
        }
        self.len = 0;
    }

    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn push<P: Pixel>(
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
            self.flush::<P>(ctx, rect, color);
        }
        self.material = Some(m);
        let k = self.len;
        (self.n[0][k], self.n[1][k], self.n[2][k]) = (n.x, n.y, n.z);
        (self.p[0][k], self.p[1][k], self.p[2][k]) = (p.x, p.y, p.z);
        self.at[k] = at;
        self.depth[k] = depth;
        self.len += 1;
        if self.len == LANES {
            self.flush::<P>(ctx, rect, color);
        }
    }
}

/// Phong: interpolation per pixel, lighting [`LANES`] pixels at a time.
#[inline(always)]
pub(super) fn shade_phong<P: Pixel, const STAGES_READ_DEPTH: bool, const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    mut depth: Option<&mut [&mut [Out<f32>]]>,
) {
    // Whether the program's stages read the eye depth (fog does) is a constant of the loop:
    // a per-pixel test of it cost 3 % more instructions per Phong frame.
    let want_depth = depth.is_some() || STAGES_READ_DEPTH;
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
                cur = Current::load::<AFFINE>(ctx, id, t, &mut planes);
            }
            let [q0, q1, q2] = cur.weights((rect.x0 + i) as f64 + 0.5, y);
            let inv_w = q0 + q1 + q2;
            let eye_depth = ctx.eye_depth::<AFFINE>(want_depth, buf.depth[slot], inv_w);
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
            batch.push::<P>(ctx, rect, m, n, p, (j, i), eye_depth, color);
        }
    }
    batch.flush::<P>(ctx, rect, color);
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
