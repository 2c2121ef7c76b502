//! Built-in meshes with exact normals: UV sphere, cube and plane.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::mesh::Mesh;

/// A unit sphere centred at the origin with `rings` latitude bands and `segments` longitude
/// segments (clamped to at least 2 and 3). Poles are single vertices; normals are exact
/// (equal to the positions). Triangle count is `2·segments·(rings − 1)`.
pub fn uv_sphere(rings: u32, segments: u32) -> Mesh {
    let (rings, segments) = (rings.max(2), segments.max(3));
    let mut p = vec![Vec3::Y];
    for i in 1..rings {
        let theta = PI * i as f32 / rings as f32;
        for j in 0..segments {
            let phi = 2.0 * PI * j as f32 / segments as f32;
            p.push(Vec3::new(
                theta.sin() * phi.sin(),
                theta.cos(),
                theta.sin() * phi.cos(),
            ));
        }
    }
    p.push(-Vec3::Y);
    let south = p.len() as u32 - 1;
    let ring = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
    let mut idx = Vec::new();
    for j in 0..segments {
        idx.push([0, ring(1, j), ring(1, j + 1)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b) = (ring(i, j), ring(i, j + 1));
            let (c, d) = (ring(i + 1, j), ring(i + 1, j + 1));
            idx.push([a, c, d]);
            idx.push([a, d, b]);
        }
    }
    for j in 0..segments {
        idx.push([ring(rings - 1, j), south, ring(rings - 1, j + 1)]);
    }
    let normals = p.iter().map(|v| v.normalize()).collect();
    Mesh::new(p, idx, Some(normals), None).expect("a valid sphere")
}

/// The cube [−1, 1]³ with 24 vertices (4 per face), exact face normals and per-face UVs.
pub fn cube() -> Mesh {
    let mut p = Vec::new();
    let mut n = Vec::new();
    let mut uv = Vec::new();
    let mut idx = Vec::new();
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        for sign in [1.0f32, -1.0] {
            let normal = axis * sign;
            // Two tangents with u × v = normal, so the quad is counter-clockwise from outside.
            let u = Vec3::new(axis.y, axis.z, axis.x) * sign;
            let v = normal.cross(u);
            let base = p.len() as u32;
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                p.push(normal + u * su + v * sv);
                n.push(normal);
                uv.push(Vec2::new((su + 1.0) / 2.0, (sv + 1.0) / 2.0));
            }
            idx.push([base, base + 1, base + 2]);
            idx.push([base, base + 2, base + 3]);
        }
    }
    Mesh::new(p, idx, Some(n), Some(uv)).expect("a valid cube")
}

/// The square [−1, 1]² in the xz plane at y = 0, facing +y, as two triangles.
pub fn plane() -> Mesh {
    let p = vec![
        Vec3::new(-1.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, -1.0),
        Vec3::new(-1.0, 0.0, -1.0),
    ];
    let uv = vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    Mesh::new(
        p,
        vec![[0, 1, 2], [0, 2, 3]],
        Some(vec![Vec3::Y; 4]),
        Some(uv),
    )
    .expect("a valid plane")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::face_normal;

    fn outward(m: &Mesh) -> bool {
        m.indices().iter().all(|t| {
            let [a, b, c] = t.map(|i| m.positions()[i as usize]);
            let n = face_normal(a, b, c);
            n.dot(((a + b + c) / 3.0).as_dvec3()) > 0.0
        })
    }

    #[test]
    fn primitives_are_outward_and_counted() {
        let s = uv_sphere(8, 16);
        assert_eq!(s.triangle_count(), 2 * 16 * 7);
        assert!(outward(&s));
        let c = cube();
        assert_eq!(c.triangle_count(), 12);
        assert!(outward(&c));
        for t in c.indices() {
            let [a, b, cc] = t.map(|i| c.positions()[i as usize]);
            let n = face_normal(a, b, cc).as_vec3();
            assert_eq!(n, c.vertex_normals()[t[0] as usize]);
        }
        let p = plane();
        let [a, b, c] = p.indices()[0].map(|i| p.positions()[i as usize]);
        assert_eq!(face_normal(a, b, c).as_vec3(), Vec3::Y);
    }
}
