//! Built-in meshes with exact normals: UV sphere, ico sphere, cube and plane.

use std::collections::HashMap;
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

/// Largest `subdivisions` of [`ico_sphere`]: 20·4¹⁰ ≈ 21 million triangles.
pub const MAX_ICO_SUBDIVISIONS: u32 = 10;

/// A unit sphere centred at the origin made by subdividing a regular icosahedron
/// `subdivisions` times (each triangle into four, new vertices pushed onto the sphere):
/// `20·4^s` triangles and `10·4^s + 2` vertices, all nearly the same size (unlike a UV
/// sphere's, which crowd at the poles). Normals are exact (equal to the positions);
/// `subdivisions` above [`MAX_ICO_SUBDIVISIONS`] is clamped to it.
pub fn ico_sphere(subdivisions: u32) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    // Positions in f64 until the end, so every vertex is on the sphere to f32 rounding.
    let mut p: Vec<glam::DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .map(|(x, y, z)| glam::DVec3::new(x, y, z).normalize())
    .to_vec();
    let mut idx: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions.min(MAX_ICO_SUBDIVISIONS) {
        // One new vertex per edge, shared by the two triangles on it (watertight).
        let mut mid: HashMap<(u32, u32), u32> = HashMap::with_capacity(idx.len() * 3 / 2);
        let mut midpoint = |a: u32, b: u32| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                p.push((p[a as usize] + p[b as usize]).normalize());
                p.len() as u32 - 1
            })
        };
        idx = idx
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (midpoint(a, b), midpoint(b, c), midpoint(c, a));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    let p: Vec<Vec3> = p.iter().map(|v| v.as_vec3()).collect();
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
        for s in 0..4 {
            let ico = ico_sphere(s);
            assert_eq!(ico.triangle_count(), 20 << (2 * s));
            assert_eq!(ico.positions().len(), 10 * (1 << (2 * s)) + 2);
            assert!(outward(&ico));
            for (p, n) in ico.positions().iter().zip(ico.vertex_normals()) {
                assert!((p.length() - 1.0).abs() < 1e-6 && (*n - *p).length() < 1e-6);
            }
            // Closed and watertight: every edge is shared by exactly two triangles, in
            // opposite directions.
            let mut edges = HashMap::new();
            for t in ico.indices() {
                for k in 0..3 {
                    *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
                }
            }
            assert!(edges
                .iter()
                .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1)));
        }
        let p = plane();
        let [a, b, c] = p.indices()[0].map(|i| p.positions()[i as usize]);
        assert_eq!(face_normal(a, b, c).as_vec3(), Vec3::Y);
    }
}
