//! Whether a mesh bounds solids wound outward: the condition under which its back faces can
//! never show from a viewpoint outside it, so the rasterizer may skip them (hidden back
//! faces, [`crate::RenderOptions::cull_hidden`]).
//!
//! A surface that is closed (every edge of its welded vertices shared by exactly two faces)
//! and consistently wound (the two walk the edge in opposite directions) separates space
//! into an inside and an outside. Seen from outside, a ray meets the surface first where it
//! enters a solid: through a face whose front (counter-clockwise side) looks out, if the
//! winding is outward. Each connected piece must then enclose a positive signed volume
//! (an inward-wound piece, such as a room modelled to be seen from within, shows its back
//! faces from outside). Computed once per mesh, from its positions and faces alone.
//!
//! Not detected: a piece that passes through itself so that part of it is turned inside out
//! (a region of negative winding number). Such a mesh can show back faces from outside; the
//! option exists to turn the skipping off for it.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::mesh_edges::weld;

/// Whether `faces` over `positions` are closed, consistently wound, and each connected
/// piece encloses a positive volume. The mesh's own indices are tried first (tens of
/// nanoseconds per face); only a mesh open by its indices is welded by position first (an
/// OBJ's vertices split along UV seams or crease normals close up there).
pub(crate) fn bounds_solids(positions: &[Vec3], faces: &[[u32; 3]]) -> bool {
    closed_outward(positions, faces).unwrap_or_else(|| welded_solids(positions, faces))
}

/// [`bounds_solids`] by the faces' own indices: `None` when they do not close the mesh.
fn closed_outward(positions: &[Vec3], faces: &[[u32; 3]]) -> Option<bool> {
    let outgoing = Outgoing::new(positions.len(), faces);
    if !outgoing.closed() {
        return None;
    }
    let (piece, pieces) = outgoing.pieces();
    let proper = faces.iter().filter(|f| distinct(f));
    Some(positive_volumes(
        positions,
        proper.map(|f| (f, piece[f[0] as usize] as usize)),
        pieces,
    ))
}

/// [`bounds_solids`] of the mesh welded by position: each vertex replaced by the first one
/// at the same position (bit for bit, ±0 alike), which has the same coordinates, so the
/// welded faces enclose the same volumes.
fn welded_solids(positions: &[Vec3], faces: &[[u32; 3]]) -> bool {
    let weld = weld(positions);
    let welded: Vec<[u32; 3]> = faces
        .par_iter()
        .map(|f| f.map(|i| weld[i as usize]))
        .collect();
    closed_outward(positions, &welded).unwrap_or(false)
}

/// A face's three vertex ids differ (otherwise it has no area and no edge of the surface).
fn distinct(f: &[u32; 3]) -> bool {
    f[0] != f[1] && f[1] != f[2] && f[0] != f[2]
}

/// The directed edges `a → b` of the faces (those with three distinct indices), listed by
/// start vertex (a counting sort): the ends of the edges leaving `a` are
/// `to[start[a]..start[a + 1]]`.
struct Outgoing {
    start: Vec<u32>,
    to: Vec<u32>,
}

impl Outgoing {
    fn new(vertices: usize, faces: &[[u32; 3]]) -> Self {
        let mut start = vec![0u32; vertices + 1];
        for f in faces.iter().filter(|f| distinct(f)) {
            for &a in f {
                start[a as usize + 1] += 1;
            }
        }
        for k in 0..vertices {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut to = vec![0u32; start[vertices] as usize];
        for f in faces.iter().filter(|f| distinct(f)) {
            for (a, b) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
                to[fill[a as usize] as usize] = b;
                fill[a as usize] += 1;
            }
        }
        Outgoing { start, to }
    }

    fn of(&self, a: u32) -> &[u32] {
        &self.to[self.start[a as usize] as usize..self.start[a as usize + 1] as usize]
    }

    /// Every edge walked exactly once in each direction: no directed edge twice, and each
    /// one's reverse present (once, since none is there twice). Each check scans one
    /// vertex's few neighbours.
    fn closed(&self) -> bool {
        !self.to.is_empty()
            && (0..self.start.len() as u32 - 1)
                .into_par_iter()
                .with_min_len(1 << 14)
                .all(|a| {
                    let mine = self.of(a);
                    (0..mine.len()).all(|k| {
                        let b = mine[k];
                        !mine[..k].contains(&b) && self.of(b).contains(&a)
                    })
                })
    }

    /// A piece number per vertex (connected through the edges; a closed mesh lists each
    /// edge from both ends, so the outgoing ones reach every neighbour) and their count.
    /// Vertices on no face get no meaningful number (no face asks for theirs).
    fn pieces(&self) -> (Vec<u32>, usize) {
        let n = self.start.len() - 1;
        let mut piece = vec![u32::MAX; n];
        let mut count = 0u32;
        let mut stack = Vec::new();
        for seed in 0..n as u32 {
            if piece[seed as usize] != u32::MAX || self.of(seed).is_empty() {
                continue;
            }
            piece[seed as usize] = count;
            stack.push(seed);
            while let Some(a) = stack.pop() {
                for &b in self.of(a) {
                    if piece[b as usize] == u32::MAX {
                        piece[b as usize] = count;
                        stack.push(b);
                    }
                }
            }
            count += 1;
        }
        (piece, count as usize)
    }
}

/// Whether every piece (numbered below `pieces`) with faces encloses a positive signed volume
/// (`faces`: each proper face with its piece).
fn positive_volumes<'a>(
    positions: &[Vec3],
    faces: impl Iterator<Item = (&'a [u32; 3], usize)>,
    pieces: usize,
) -> bool {
    // Signed volume (six times it) per piece, about the centre of the bounding box so that
    // a model far from the origin does not lose its volume to cancellation; `scale` sums
    // the terms' magnitudes, to tell a volume from rounding.
    let (lo, hi) = positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let centre = (lo.as_dvec3() + hi.as_dvec3()) * 0.5;
    let mut volume = vec![0.0f64; pieces];
    let mut scale = vec![0.0f64; pieces];
    let mut has_faces = vec![false; pieces];
    for (f, r) in faces {
        let p: [DVec3; 3] = f.map(|i| positions[i as usize].as_dvec3() - centre);
        let det = p[0].dot(p[1].cross(p[2]));
        volume[r] += det;
        scale[r] += det.abs();
        has_faces[r] = true;
    }
    // Every piece with faces encloses a volume well above the terms' rounding (~1e-16 of
    // their sum; a flat, two-layered piece encloses none and is refused).
    (0..pieces).all(|r| !has_faces[r] || volume[r] > 1e-9 * scale[r].max(f64::MIN_POSITIVE))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    fn solid(positions: &[Vec3], faces: &[[u32; 3]]) -> bool {
        let by_indices = bounds_solids(positions, faces);
        // The welded test alone agrees wherever the indices close the mesh.
        if Outgoing::new(positions.len(), faces).closed() {
            assert_eq!(welded_solids(positions, faces), by_indices);
        }
        by_indices
    }

    fn cube() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let p = (0..8)
            .map(|k| Vec3::new((k & 1) as f32, (k >> 1 & 1) as f32, (k >> 2 & 1) as f32))
            .collect();
        // Counter-clockwise seen from outside.
        let f = vec![
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ];
        (p, f)
    }

    #[test]
    fn closed_outward_meshes_are_solid() {
        let (p, f) = cube();
        assert!(solid(&p, &f));
        for m in [
            primitives::uv_sphere(12, 24),
            primitives::ico_sphere(2),
            primitives::cube(),
        ] {
            assert!(solid(m.positions(), m.indices()));
        }
        // Far from the origin: the volume is taken about the box's centre.
        let far: Vec<Vec3> = p.iter().map(|v| *v * 1e-3 + Vec3::splat(1e4)).collect();
        assert!(solid(&far, &f));
    }

    #[test]
    fn inward_open_or_inconsistent_meshes_are_not() {
        let (p, f) = cube();
        let inward: Vec<[u32; 3]> = f.iter().map(|t| [t[0], t[2], t[1]]).collect();
        assert!(!solid(&p, &inward));
        assert!(!solid(&p, &f[1..])); // a hole
        let mut flipped = f.clone();
        flipped[3] = [5, 6, 7]; // one face wound against its neighbours
        assert!(!solid(&p, &flipped));
        let plane = primitives::plane();
        assert!(!solid(plane.positions(), plane.indices()));
        // Two layers back to back: closed and consistent, but no volume.
        let sheet = [Vec3::ZERO, Vec3::X, Vec3::Y];
        assert!(!solid(&sheet, &[[0, 1, 2], [0, 2, 1]]));
    }

    #[test]
    fn every_piece_must_be_outward() {
        let (p, f) = cube();
        let mut p2 = p.clone();
        p2.extend(p.iter().map(|v| *v + Vec3::new(3.0, 0.0, 0.0)));
        let second = |t: &[u32; 3]| t.map(|i| i + 8);
        let mut both: Vec<[u32; 3]> = f.clone();
        both.extend(f.iter().map(second));
        assert!(solid(&p2, &both));
        // The second cube inward: its total with the first is still positive, but it is not.
        let mut mixed: Vec<[u32; 3]> = f.clone();
        mixed.extend(f.iter().map(|t| second(&[t[0], t[2], t[1]])));
        assert!(!solid(&p2, &mixed));
    }

    #[test]
    fn seams_weld_by_position() {
        // The cube with each face's vertices its own (as an OBJ with per-face UVs has them).
        let (p, f) = cube();
        let split: Vec<Vec3> = f.iter().flat_map(|t| t.map(|i| p[i as usize])).collect();
        let faces: Vec<[u32; 3]> = (0..f.len() as u32)
            .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
            .collect();
        assert!(solid(&split, &faces));
    }
}
