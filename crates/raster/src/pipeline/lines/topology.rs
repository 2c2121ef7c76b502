//! The scene's edges for the line stage: every object's cached [`MeshEdges`] (its
//! vertices welded by exact position, each undirected edge once with its faces) placed at
//! the object's global vertex and face indices. Assembled per render that draws lines; the
//! per-mesh work is done once per mesh ([`crate::mesh::Mesh::edges`]).

use glam::{DVec3, Vec3};

pub(crate) use crate::mesh_edges::{MeshEdge, NO_FACE};
use crate::scene::Scene;

/// The scene's faces (global vertex indices), welded vertex ids and unique edges.
pub(crate) struct Topology {
    /// Every object's faces in submission order, as global vertex indices.
    pub faces: Vec<[u32; 3]>,
    /// Welded id of each (transformed) vertex: vertices of one object at the same position
    /// share an id; ids of different objects never meet.
    pub weld: Vec<u32>,
    /// Every object's edges in submission order (each sorted by its welded ends), in
    /// global vertex and face indices.
    pub edges: Vec<MeshEdge>,
}

impl Topology {
    /// The edges of every object of `scene` (each mesh's computed on first use).
    pub fn new(scene: &Scene) -> Self {
        let (mut faces, mut weld, mut edges) = (Vec::new(), Vec::new(), Vec::new());
        let (mut first_vertex, mut first_face) = (0u32, 0u32);
        for o in scene.objects() {
            let mesh = o.mesh();
            let own = mesh.edges();
            weld.extend(own.weld.iter().map(|&w| w + first_vertex));
            faces.extend(mesh.indices().iter().map(|f| f.map(|i| i + first_vertex)));
            let face = |f: u32| {
                if f == NO_FACE {
                    NO_FACE
                } else {
                    f + first_face
                }
            };
            edges.extend(own.edges.iter().map(|e| MeshEdge {
                v: e.v.map(|i| i + first_vertex),
                ends: e.ends.map(|i| i + first_vertex),
                faces: e.faces.map(face),
                ..*e
            }));
            first_vertex += mesh.positions().len() as u32;
            first_face += mesh.indices().len() as u32;
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

#[cfg(test)]
mod cache_tests {
    use super::*;
    use crate::material::Material;
    use glam::Mat4;
    use std::sync::Arc;

    #[test]
    fn each_mesh_is_welded_once_and_placed_at_its_objects_indices() {
        let cube = Arc::new(crate::primitives::cube());
        let mut s = Scene::new(Vec3::ZERO).unwrap();
        for _ in 0..2 {
            s.add(cube.clone(), Material::default(), Mat4::IDENTITY)
                .unwrap();
        }
        let first = cube.edges() as *const _;
        let t = Topology::new(&s);
        // The cache is the mesh's: the same object, not rebuilt.
        assert_eq!(cube.edges() as *const _, first);
        let (nv, nf) = (cube.positions().len() as u32, cube.indices().len() as u32);
        assert_eq!(t.edges.len(), 36);
        for (a, b) in t.edges[..18].iter().zip(&t.edges[18..]) {
            assert_eq!(b.v, a.v.map(|i| i + nv));
            assert_eq!(b.ends, a.ends.map(|i| i + nv));
            assert_eq!(b.faces, a.faces.map(|f| f + nf));
            assert_eq!((b.count, b.consistent), (a.count, a.consistent));
        }
        assert_eq!(
            t.weld[nv as usize..],
            t.weld[..nv as usize]
                .iter()
                .map(|w| w + nv)
                .collect::<Vec<_>>()[..]
        );
    }
}
