//! A mesh's edges: its vertices welded by exact position, and each undirected edge once,
//! with the faces that share it. Computed once per mesh, on the first render that draws its
//! lines, and kept with the mesh ([`crate::mesh::Mesh::edges`]): it depends only on the
//! mesh's positions and faces, which never change.

use glam::Vec3;
use rayon::prelude::*;

/// No face (an edge's second slot when only one face has it).
pub(crate) const NO_FACE: u32 = u32::MAX;

/// One undirected edge of a mesh, in the mesh's own vertex and face indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct MeshEdge {
    /// Vertex indices of its endpoints (those of the first face that has it).
    pub v: [u32; 2],
    /// Welded ids of the endpoints.
    pub ends: [u32; 2],
    /// The first two faces that have it ([`NO_FACE`] when absent).
    pub faces: [u32; 2],
    /// How many faces have it: 1 on a boundary, 2 inside a manifold, more where non-manifold.
    pub count: u32,
    /// The two faces walk it in opposite directions (consistently wound neighbours).
    pub consistent: bool,
}

/// A mesh's welded vertex ids and unique edges (sorted by their welded ends).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct MeshEdges {
    /// Welded id of each vertex: the index of the first vertex at the same position.
    pub weld: Vec<u32>,
    pub edges: Vec<MeshEdge>,
}

/// Position bits with −0 made +0, so the two zeros weld.
fn position_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// Each vertex's welded id: the index of the first vertex at the same position (bit for bit,
/// ±0 alike). Sorted by position rather than hashed: the same ids, without a hash per vertex.
pub(crate) fn weld(positions: &[Vec3]) -> Vec<u32> {
    let key = |i: u32| position_key(positions[i as usize]);
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.par_sort_unstable_by_key(|&i| (key(i), i));
    let mut weld = vec![0u32; positions.len()];
    for group in order.chunk_by(|&a, &b| key(a) == key(b)) {
        for &i in group {
            weld[i as usize] = group[0];
        }
    }
    weld
}

impl MeshEdges {
    /// Welds `positions` and collects the edges of `faces`.
    pub fn new(positions: &[Vec3], faces: &[[u32; 3]]) -> Self {
        let weld = weld(positions);
        // (lower welded id, higher, face, slot): one entry per face side; sorted, the sides
        // of one edge are adjacent, faces in order.
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
        MeshEdges { weld, edges }
    }
}
