//! Shade pass: every visible pixel of a tile is shaded exactly once, from its triangle's
//! setup data, and written straight into the output rows.
//!
//! The shading mode is a const generic, so each mode's loop carries only its own work: flat
//! reads one colour per triangle, Gouraud interpolates colours, Phong normals and positions.

use glam::Vec3;

use super::bin::Binned;
use super::raster::{TileBuffers, NO_TRIANGLE};
use super::setup::{Edges, SetupTri, HALF, ONE};
use super::tiles::{TileRect, TILE};
use super::vertex::Vertices;
use crate::camera::Camera;
use crate::shading::{PreparedMaterial, ShadingMode};

/// An output sample type: how a linear RGB colour is stored.
pub trait Pixel: Copy + Default + Send + Sync + 'static {
    /// Writes `c` into `dst[0..3]`.
    fn store(dst: &mut [Self], c: Vec3);
}

impl Pixel for u8 {
    /// `round(clamp(c, 0, 1) · 255)`.
    #[inline]
    fn store(dst: &mut [u8], c: Vec3) {
        let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        dst[0] = q(c.x);
        dst[1] = q(c.y);
        dst[2] = q(c.z);
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
    pub materials: &'a [PreparedMaterial],
    pub camera: &'a Camera,
    pub eye: Vec3,
    pub background: Vec3,
}

const FLAT: u8 = 0;
const GOURAUD: u8 = 1;
const PHONG: u8 = 2;

/// Shades one tile into its output rows (and depth rows when requested).
pub(crate) fn shade_tile<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [P]],
    depth: Option<&mut [&mut [f32]]>,
) {
    match mode {
        ShadingMode::Flat => shade_impl::<P, FLAT>(ctx, rect, buf, color, depth),
        ShadingMode::Gouraud => shade_impl::<P, GOURAUD>(ctx, rect, buf, color, depth),
        ShadingMode::Phong => shade_impl::<P, PHONG>(ctx, rect, buf, color, depth),
    }
}

/// Cached per-triangle data while consecutive pixels share a triangle.
struct Current {
    id: u32,
    edges: Edges,
    inv_area: f64,
}

fn shade_impl<P: Pixel, const MODE: u8>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [P]],
    mut depth: Option<&mut [&mut [f32]]>,
) {
    let want_depth = depth.is_some();
    let mut cur = Current {
        id: NO_TRIANGLE,
        edges: Edges {
            a: [0; 3],
            b: [0; 3],
            c: [0; 3],
            bias: [0; 3],
        },
        inv_area: 0.0,
    };
    for j in 0..rect.h {
        let row = &mut *color[j];
        let py = (rect.y0 + j) as i64 * ONE + HALF;
        for i in 0..rect.w {
            let slot = j * TILE + i;
            let id = buf.id[slot];
            if id == NO_TRIANGLE {
                P::store(&mut row[i * 3..i * 3 + 3], ctx.background);
                if let Some(d) = depth.as_deref_mut() {
                    d[j][i] = f32::INFINITY;
                }
                continue;
            }
            let t = ctx.tris.get(id);
            if MODE == FLAT && !want_depth {
                P::store(&mut row[i * 3..i * 3 + 3], t.flat);
                continue;
            }
            if id != cur.id {
                cur = Current {
                    id,
                    edges: t.edges(),
                    inv_area: 1.0 / t.area2 as f64,
                };
            }
            let px = (rect.x0 + i) as i64 * ONE + HALF;
            let e = &cur.edges;
            // Exact integer barycentrics, one rounding each, then the 1/w correction.
            let lambda = [0, 1, 2]
                .map(|k| ((e.a[k] * px + e.b[k] * py + e.c[k]) as f64 * cur.inv_area) as f32);
            let q = [0, 1, 2].map(|k| lambda[k] * t.inv_w[k]);
            let inv_w = q[0] + q[1] + q[2];
            if let Some(d) = depth.as_deref_mut() {
                d[j][i] = ctx.camera.eye_depth(buf.depth[slot], inv_w);
            }
            let c = match MODE {
                FLAT => t.flat,
                GOURAUD => {
                    let b = q.map(|v| v / inv_w);
                    let col = &ctx.verts.color;
                    col[t.v[0] as usize] * b[0]
                        + col[t.v[1] as usize] * b[1]
                        + col[t.v[2] as usize] * b[2]
                }
                _ => {
                    let b = q.map(|v| v / inv_w);
                    let (nrm, wld) = (&ctx.verts.normal, &ctx.verts.world);
                    let v = t.v.map(|k| k as usize);
                    let n = nrm[v[0]] * b[0] + nrm[v[1]] * b[1] + nrm[v[2]] * b[2];
                    let p = wld[v[0]] * b[0] + wld[v[1]] * b[1] + wld[v[2]] * b[2];
                    let n = n.try_normalize().unwrap_or_else(|| face_normal(t, wld));
                    ctx.materials[t.object as usize].shade(n, p, ctx.eye)
                }
            };
            P::store(&mut row[i * 3..i * 3 + 3], c);
        }
    }
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
