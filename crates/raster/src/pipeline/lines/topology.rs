//! Mesh edges: every object's vertices welded by exact position, and each undirected edge
//! once, with the faces that share it. Built once per render that draws lines.

use std::collections::HashMap;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::scene::Scene;

/// No face (an edge's second slot when only one face has it).
pub(crate) const NO_FACE: u32 = u32::MAX;

/// One undirected edge of a mesh.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MeshEdge {
    /// Global vertex indices of its endpoints (those of the first face that has it).
    pub v: [u32; 2],
    /// Welded ids of the endpoints.
    pub ends: [u32; 2],
    /// The first two faces that have it (global face indices; [`NO_FACE`] when absent).
    pub faces: [u32; 2],
    /// How many faces have it: 1 on a boundary, 2 inside a manifold, more where non-manifold.
    pub count: u32,
    /// The two faces walk it in opposite directions (consistently wound neighbours).
    pub consistent: bool,
}

/// The scene's faces (global vertex indices), welded vertex ids and unique edges.
pub(crate) struct Topology {
    /// Every object's faces in submission order, as global vertex indices.
    pub faces: Vec<[u32; 3]>,
    /// Welded id of each (transformed) vertex: vertices of one object at the same position
    /// share an id; ids of different objects never meet.
    pub weld: Vec<u32>,
    pub edges: Vec<MeshEdge>,
}

/// Position bits with −0 made +0, so the two zeros weld.
fn key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

impl Topology {
    /// Welds and collects the edges of every object of `scene`.
    pub fn new(scene: &Scene) -> Self {
        let mut faces = Vec::new();
        let mut weld = Vec::new();
        let mut first_vertex = 0u32;
        for o in scene.objects() {
            let mesh = o.mesh();
            let mut ids: HashMap<[u32; 3], u32> = HashMap::with_capacity(mesh.positions().len());
            for p in mesh.positions() {
                let next = weld.len() as u32;
                weld.push(*ids.entry(key(*p)).or_insert(next));
            }
            faces.extend(mesh.indices().iter().map(|f| f.map(|i| i + first_vertex)));
            first_vertex += mesh.positions().len() as u32;
        }
        // (lower welded id, higher, face, slot): one entry per face side; sorted, the sides
        // of one edge are adjacent, faces in submission order.
        let mut sides: Vec<(u32, u32, u32, u8)> = faces
            .par_iter()
            .enumerate()
            .flat_map_iter(|(f, v)| {
                let w = v.map(|i| weld[i as usize]);
                let degenerate = w[0] == w[1] || w[1] == w[2] || w[0] == w[2];
                (0..3u8).filter(move |_| !degenerate).map(move |k| {
                    let (a, b) = (w[k as usize], w[(k as usize + 1) % 3]);
                    (a.min(b), a.max(b), f as u32, k)
                })
            })
            .collect();
        sides.par_sort_unstable();
        let mut edges = Vec::with_capacity(sides.len() / 2 + 1);
        let mut i = 0;
        while i < sides.len() {
            let (lo, hi, f, k) = sides[i];
            let mut j = i + 1;
            while j < sides.len() && sides[j].0 == lo && sides[j].1 == hi {
                j += 1;
            }
            let fv = faces[f as usize];
            let (v0, v1) = (fv[k as usize], fv[(k as usize + 1) % 3]);
            let dir = |(_, _, f, k): (u32, u32, u32, u8)| {
                weld[faces[f as usize][k as usize] as usize] == lo
            };
            let second = (j - i >= 2).then(|| sides[i + 1]);
            edges.push(MeshEdge {
                v: [v0, v1],
                ends: [weld[v0 as usize], weld[v1 as usize]],
                faces: [f, second.map_or(NO_FACE, |s| s.2)],
                count: (j - i) as u32,
                consistent: second.is_some_and(|s| dir(s) != dir(sides[i])),
            });
            i = j;
        }
        Topology { faces, weld, edges }
    }

    /// The unnormalised normal `(p1 − p0) × (p2 − p0)` of face `f` in world space.
    pub fn normal(&self, world: &[Vec3], f: u32) -> DVec3 {
        let [a, b, c] = self.faces[f as usize].map(|i| world[i as usize].as_dvec3());
        (b - a).cross(c - a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::mesh::Mesh;
    use glam::Mat4;
    use std::sync::Arc;

    fn scene_of(positions: Vec<Vec3>, indices: Vec<[u32; 3]>) -> Scene {
        let mesh = Mesh::new(positions, indices, None, None).unwrap();
        let mut s = Scene::new(Vec3::ZERO).unwrap();
        s.add(Arc::new(mesh), Material::default(), Mat4::IDENTITY)
            .unwrap();
        s
    }

    #[test]
    fn a_quad_has_five_edges_and_one_shared_diagonal() {
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let t = Topology::new(&scene_of(p, vec![[0, 1, 2], [0, 2, 3]]));
        assert_eq!(t.edges.len(), 5);
        let shared: Vec<_> = t.edges.iter().filter(|e| e.count == 2).collect();
        assert_eq!(shared.len(), 1);
        assert!(shared[0].consistent);
        assert_eq!(shared[0].faces, [0, 1]);
    }

    #[test]
    fn duplicated_vertices_weld_by_position() {
        // Two triangles sharing an edge through separate (equal) vertices, one with -0.0.
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let t = Topology::new(&scene_of(p, vec![[0, 1, 2], [3, 4, 5]]));
        assert_eq!(t.weld[3], t.weld[0]);
        assert_eq!(t.edges.len(), 5);
        assert_eq!(t.edges.iter().filter(|e| e.count == 2).count(), 1);
    }
}

#[cfg(test)]
mod cube_tests {
    use super::*;
    use crate::material::Material;
    use glam::Mat4;
    use std::sync::Arc;

    #[test]
    fn a_cube_has_eighteen_edges() {
        let mut s = Scene::new(Vec3::ZERO).unwrap();
        s.add(
            Arc::new(crate::primitives::cube()),
            Material::default(),
            Mat4::IDENTITY,
        )
        .unwrap();
        let t = Topology::new(&s);
        assert_eq!(t.edges.len(), 18);
        assert!(t.edges.iter().all(|e| e.count == 2 && e.consistent));
    }
}
