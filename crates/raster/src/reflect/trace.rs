//! The scene as secondary rays see it: the rays room's BVH over every object's
//! world-space triangles, and for each triangle its vertices and object, so a hit can be
//! turned into a lit surface point.

use glam::Vec3;

use super::Point;
use crate::lighting::Surface;
use crate::rays::Bvh;
use crate::scene::Scene;

/// What the secondary rays read of the prepared scene.
pub(crate) struct World<'a> {
    /// World positions of every vertex (the vertex stage's).
    pub world: &'a [Vec3],
    /// World normals (empty in flat mode: hits then use the face normal).
    pub normal: &'a [Vec3],
    /// Per object, its lit surfaces (front, back as lit).
    pub surfaces: &'a [[Surface; 2]],
    /// Two-sided lighting: back faces lit with the flipped normal and the back material.
    pub two_sided: bool,
}

impl World<'_> {
    /// The local colour of a hit point: the lighting equation at the point, seen from the
    /// ray's origin (`p + v`), with the normal the raster loops would light it with.
    pub fn light(&self, q: &Point) -> Vec3 {
        let surface = &self.surfaces[q.object as usize][q.side];
        // The loops light the outward normal, flipped on a two-sided back face; `q.n`
        // faces the ray, which is the outward side exactly on a front face.
        let n = if q.entering || self.two_sided {
            q.n
        } else {
            -q.n
        };
        surface.shade(n, q.p, q.p + q.v)
    }
}

/// The BVH and, per triangle, its vertex indices and object.
pub(crate) struct RayScene {
    bvh: Bvh,
    tris: Vec<([u32; 3], u32)>,
    /// Scene-size part of the ray offset (as for shadow rays: 1e-4 of the bounding box's
    /// diagonal).
    offset: f32,
}

impl RayScene {
    /// The scene's triangles in world space (`world`: the vertex stage's positions).
    pub fn new(scene: &Scene, world: &[Vec3]) -> Self {
        let mut tris = Vec::with_capacity(scene.triangle_count());
        let mut corners = Vec::with_capacity(scene.triangle_count());
        let mut first = 0u32;
        for (oi, o) in scene.objects().iter().enumerate() {
            let mesh = o.mesh();
            for t in mesh.indices() {
                let v = t.map(|i| first + i);
                tris.push((v, oi as u32));
                corners.push(v.map(|i| world[i as usize]));
            }
            first += mesh.positions().len() as u32;
        }
        let mut bounds = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in world.iter().filter(|p| p.is_finite()) {
            bounds = (bounds.0.min(*p), bounds.1.max(*p));
        }
        let diagonal = (bounds.1 - bounds.0).length();
        RayScene {
            bvh: Bvh::new(corners),
            tris,
            offset: if diagonal.is_finite() {
                1e-4 * diagonal
            } else {
                0.0
            },
        }
    }

    /// The first surface the ray from `p` (geometric normal `g`) along `dir` meets, as a
    /// [`Point`] seen from the ray, and its distance. The ray starts off the surface on the
    /// side `dir` leaves to, so it never hits its own triangle by rounding.
    pub fn hit(&self, w: &World<'_>, p: Vec3, g: Vec3, dir: Vec3) -> Option<(Point, f32)> {
        let dir = dir.normalize_or_zero();
        if dir == Vec3::ZERO {
            return None;
        }
        let side = if g.dot(dir) < 0.0 { -g } else { g };
        let origin = p + side * (self.offset + 1e-6 * p.abs().max_element());
        let h = self.bvh.closest(origin, dir, f32::INFINITY)?;
        let (v, object) = self.tris[h.index as usize];
        let [a, b, c] = v.map(|i| w.world[i as usize]);
        let (u, s) = h.uv;
        let q = origin + dir * h.t;
        // Outward (counter-clockwise) face normal.
        let face = (b - a).cross(c - a).normalize_or_zero();
        let entering = face.dot(dir) < 0.0;
        let toward = -dir;
        let g = if entering { face } else { -face };
        let n = if w.normal.is_empty() {
            g
        } else {
            let [na, nb, nc] = v.map(|i| w.normal[i as usize]);
            let n = na * (1.0 - u - s) + nb * u + nc * s;
            let n = n.normalize_or_zero();
            let n = if entering { n } else { -n };
            if n.dot(toward) > 0.0 {
                n
            } else {
                g
            }
        };
        let back = !entering && w.two_sided;
        Some((
            Point {
                p: q,
                n,
                g,
                v: toward,
                entering,
                object,
                side: back as usize,
            },
            (q - p).length(),
        ))
    }
}
