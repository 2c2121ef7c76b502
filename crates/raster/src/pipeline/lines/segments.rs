//! Which mesh edges a render draws, projected to screen segments with their depth, and
//! binned to the tiles their lines can touch.

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use super::coverage::Capsule;
use super::topology::{MeshEdge, Topology, NO_FACE};
use crate::camera::{Camera, Projection};
use crate::options::{EdgeMode, RenderOptions};
use crate::pipeline::bin::Bins;
use crate::pipeline::clip::ClipPlanes;
use crate::pipeline::setup::ONE;
use crate::pipeline::tiles::{tile_counts, TILE};
use crate::pipeline::vertex::Vertices;

/// A window depth plane over pixel coordinates: `z = a·x + b·y + c` (reversed-Z, larger is
/// nearer). Window depth is affine in screen space over a planar triangle, so this is exact
/// up to f64 rounding.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ZPlane {
    pub a: f64,
    pub b: f64,
    pub c: f64,
}

impl ZPlane {
    /// The plane through three (x, y, z) points; `None` when they are collinear on screen.
    pub fn through(p: [DVec3; 3]) -> Option<Self> {
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        if n.z == 0.0 || !n.is_finite() {
            return None;
        }
        let (a, b) = (-n.x / n.z, -n.y / n.z);
        Some(ZPlane {
            a,
            b,
            c: p[0].z - a * p[0].x - b * p[0].y,
        })
    }

    /// The plane of snapped screen vertices (16.8 fixed-point x, y and window z).
    pub fn of_snapped(x: [i32; 3], y: [i32; 3], z: [f32; 3]) -> Option<Self> {
        let inv = 1.0 / ONE as f64;
        Self::through(
            [0, 1, 2].map(|k| DVec3::new(x[k] as f64 * inv, y[k] as f64 * inv, z[k] as f64)),
        )
    }

    /// Depth at `p` (pixels).
    #[inline]
    pub fn at(&self, p: [f64; 2]) -> f64 {
        self.a * p[0] + self.b * p[1] + self.c
    }

    /// A depth tolerance for comparisons against this plane: a relative 1e-6 of `z` plus
    /// the depth change over 1/64 pixel (vertices are snapped to 1/256 pixel, so two planes
    /// through a shared edge that should coincide differ by less away from it).
    #[inline]
    pub fn tolerance(&self, z: f64) -> f64 {
        1e-6 * z.abs() + (self.a.abs() + self.b.abs()) * (1.0 / 64.0)
    }
}

/// One line to draw: a mesh edge projected to the screen.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Segment {
    pub capsule: Capsule,
    /// Window depth at each end (affine along the projected segment).
    pub z: [f64; 2],
    /// Welded ids of the endpoints: a triangle having both is one of the edge's faces.
    pub ends: [u32; 2],
    /// The depth planes of the edge's first two faces (the line's "ribbon"), where known,
    /// with the faces' welded vertex ids.
    pub ribbon: [Option<(ZPlane, [u32; 3])>; 2],
    /// Inclusive pixel bounds the line can touch: x0, y0, x1, y1.
    pub bbox: [i32; 4],
}

impl Segment {
    /// Window depth of the edge at parameter `t`.
    #[inline]
    pub fn z_at(&self, t: f64) -> f64 {
        self.z[0] + (self.z[1] - self.z[0]) * t
    }
}

/// How each face is oriented towards the eye: 1 front, −1 back, 0 degenerate.
fn facing(topo: &Topology, world: &[glam::Vec3], camera: &Camera) -> Vec<i8> {
    let eye = camera.eye();
    let ortho = match camera.projection() {
        Projection::Orthographic { .. } => Some(eye - camera.target()),
        _ => None,
    };
    (0..topo.faces.len() as u32)
        .into_par_iter()
        .map(|f| {
            let n = topo.normal(world, f);
            let p0 = world[topo.faces[f as usize][0] as usize].as_dvec3();
            let s = n.dot(ortho.unwrap_or(eye - p0));
            if n == DVec3::ZERO || s == 0.0 {
                0
            } else if s > 0.0 {
                1
            } else {
                -1
            }
        })
        .collect()
}

/// Whether `mode` draws `e` (before visibility): every edge for all and visible; for
/// features, boundaries, non-manifold edges, silhouettes and creases. With back-face
/// culling an edge no front face has is never drawn (its faces are not).
fn selected(
    e: &MeshEdge,
    topo: &Topology,
    world: &[glam::Vec3],
    facing: &[i8],
    options: &RenderOptions,
    cos_angle: f64,
) -> bool {
    let front = |f: u32| f != NO_FACE && facing[f as usize] > 0;
    if options.cull_backfaces && !(front(e.faces[0]) || front(e.faces[1]) || e.count > 2) {
        return false;
    }
    if options.edges != EdgeMode::Features || e.count != 2 {
        return true;
    }
    let (fa, fb) = (facing[e.faces[0] as usize], facing[e.faces[1] as usize]);
    if fa != 0 && fb != 0 && fa != fb {
        return true; // silhouette
    }
    let (na, nb) = (
        topo.normal(world, e.faces[0]),
        topo.normal(world, e.faces[1]),
    );
    let len = na.length() * nb.length();
    if len == 0.0 {
        return false;
    }
    // Neighbours wound the same way round the edge have one normal flipped.
    let cos = na.dot(nb) / len * if e.consistent { 1.0 } else { -1.0 };
    cos < cos_angle
}

/// The drawn edges of a render as screen segments, and their per-tile lists.
pub(crate) struct Segments {
    pub segs: Vec<Segment>,
    pub bins: Bins,
}

impl Segments {
    /// Selects, projects (clipping where an end is outside the clip volume) and bins the
    /// edges `options.edges` draws.
    pub fn new(
        topo: &Topology,
        verts: &Vertices,
        camera: &Camera,
        options: &RenderOptions,
    ) -> Self {
        let (w, h) = (options.width, options.height);
        let world = &verts.world[..topo.weld.len()];
        let facing = facing(topo, world, camera);
        let cos_angle = (options.edge_angle as f64).to_radians().cos() - 1e-12;
        let planes = ClipPlanes::new(w, h);
        let inv = 1.0 / ONE as f64;
        let width = options.edge_width as f64;
        // A face's depth plane, from its snapped vertices when all three were snapped.
        let face_plane = |f: u32| -> Option<(ZPlane, [u32; 3])> {
            if f == NO_FACE {
                return None;
            }
            let v = topo.faces[f as usize];
            if v.iter().any(|&i| verts.outcode[i as usize] != 0) {
                return None;
            }
            let s = v.map(|i| verts.screen[i as usize]);
            let plane = ZPlane::of_snapped(s.map(|p| p.0), s.map(|p| p.1), s.map(|p| p.2))?;
            Some((plane, v.map(|i| topo.weld[i as usize])))
        };
        let project = |c: DVec4| -> Option<([f64; 2], f64)> {
            let iw = 1.0 / c.w;
            let p = [
                (c.x * iw + 1.0) * 0.5 * w as f64,
                (1.0 - c.y * iw) * 0.5 * h as f64,
            ];
            let z = c.z * iw;
            (p[0].is_finite() && p[1].is_finite() && z.is_finite()).then_some((p, z))
        };
        let segs: Vec<Segment> = topo
            .edges
            .par_iter()
            .filter(|e| selected(e, topo, world, &facing, options, cos_angle))
            .filter_map(|e| {
                let [v0, v1] = e.v.map(|i| i as usize);
                let (c0, c1) = (verts.outcode[v0], verts.outcode[v1]);
                let ((a, za), (b, zb)) = if c0 == 0 && c1 == 0 {
                    let at = |s: crate::pipeline::setup::Snapped| {
                        ([s.0 as f64 * inv, s.1 as f64 * inv], s.2 as f64)
                    };
                    (at(verts.screen[v0]), at(verts.screen[v1]))
                } else {
                    let invalid = crate::pipeline::clip::INVALID;
                    if (c0 | c1) & invalid != 0 || c0 & c1 != 0 {
                        return None;
                    }
                    let (p, q) = planes
                        .clip_segment(verts.clip[v0].as_dvec4(), verts.clip[v1].as_dvec4())?;
                    (project(p)?, project(q)?)
                };
                let r = 0.5 * width + 1.0;
                let bbox = [
                    (a[0].min(b[0]) - r).floor().max(-1.0),
                    (a[1].min(b[1]) - r).floor().max(-1.0),
                    (a[0].max(b[0]) + r).floor().min(w as f64),
                    (a[1].max(b[1]) + r).floor().min(h as f64),
                ]
                .map(|v| v as i32);
                if bbox[0] > bbox[2].min(w as i32 - 1)
                    || bbox[1] > bbox[3].min(h as i32 - 1)
                    || bbox[2] < 0
                    || bbox[3] < 0
                {
                    return None;
                }
                Some(Segment {
                    capsule: Capsule::new(a, b, width),
                    z: [za, zb],
                    ends: e.ends,
                    ribbon: e.faces.map(face_plane),
                    bbox: [
                        bbox[0].max(0),
                        bbox[1].max(0),
                        bbox[2].min(w as i32 - 1),
                        bbox[3].min(h as i32 - 1),
                    ],
                })
            })
            .collect();
        let bins = bin_segments(&segs, tile_counts(w as usize, h as usize));
        Segments { segs, bins }
    }
}

/// Counting sort of segments into the tiles their bounds touch, in segment order.
fn bin_segments(segs: &[Segment], (tx, ty): (usize, usize)) -> Bins {
    let range = |s: &Segment| {
        let [x0, y0, x1, y1] = s.bbox.map(|v| v as usize / TILE);
        (x0, y0, x1, y1)
    };
    let mut offsets = vec![0usize; tx * ty + 1];
    for s in segs {
        let (x0, y0, x1, y1) = range(s);
        for y in y0..=y1 {
            for x in x0..=x1 {
                offsets[y * tx + x + 1] += 1;
            }
        }
    }
    for i in 0..tx * ty {
        offsets[i + 1] += offsets[i];
    }
    let mut cursor = offsets.clone();
    let mut items = vec![0u32; offsets[tx * ty]];
    for (i, s) in segs.iter().enumerate() {
        let (x0, y0, x1, y1) = range(s);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c = &mut cursor[y * tx + x];
                items[*c] = i as u32;
                *c += 1;
            }
        }
    }
    Bins { offsets, items }
}
