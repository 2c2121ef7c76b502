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

use crate::mesh_edges::MeshEdges;

/// Whether `faces` over `positions` are closed, consistently wound, and each connected
/// piece encloses a positive volume. The mesh's own indices are tried first (a few tens of
/// nanoseconds per face); only a mesh open by its indices is welded by position (`welded`,
/// the mesh's [`MeshEdges`]: an OBJ's vertices split along UV seams close up there).
pub(crate) fn bounds_solids<'a>(
    positions: &[Vec3],
    faces: &[[u32; 3]],
    welded: impl FnOnce() -> &'a MeshEdges,
) -> bool {
    if closed_by_indices(positions.len(), faces) {
        return outward(positions, faces, |i| i);
    }
    let edges = welded();
    !edges.edges.is_empty()
        && edges.edges.iter().all(|e| e.count == 2 && e.consistent)
        && outward(positions, faces, |i| edges.weld[i as usize])
}

/// Whether every edge of the faces (those with three distinct indices) is walked exactly
/// once in each direction: each directed edge `a → b` once, and `b → a` once. The directed
/// edges are listed per start vertex (a counting sort), so each check scans one vertex's
/// few neighbours.
fn closed_by_indices(vertices: usize, faces: &[[u32; 3]]) -> bool {
    let proper = |f: &[u32; 3]| f[0] != f[1] && f[1] != f[2] && f[0] != f[2];
    let mut start = vec![0u32; vertices + 1];
    for f in faces.iter().filter(|f| proper(f)) {
        for &a in f {
            start[a as usize + 1] += 1;
        }
    }
    for k in 0..vertices {
        start[k + 1] += start[k];
    }
    if start[vertices] == 0 {
        return false;
    }
    let mut fill = start.clone();
    let mut to = vec![0u32; start[vertices] as usize];
    for f in faces.iter().filter(|f| proper(f)) {
        for k in 0..3 {
            let a = f[k] as usize;
            to[fill[a] as usize] = f[(k + 1) % 3];
            fill[a] += 1;
        }
    }
    let out = |a: u32| &to[start[a as usize] as usize..start[a as usize + 1] as usize];
    (0..vertices as u32).all(|a| {
        let mine = out(a);
        mine.iter()
            .enumerate()
            .all(|(k, &b)| !mine[..k].contains(&b) && out(b).contains(&a))
    })
}

/// Whether every connected piece of the faces (vertices identified by `weld`) encloses a
/// positive signed volume.
fn outward(positions: &[Vec3], faces: &[[u32; 3]], weld: impl Fn(u32) -> u32) -> bool {
    let n = positions.len();
    let faces = || {
        faces.iter().filter_map(|f| {
            let w = f.map(&weld);
            (w[0] != w[1] && w[1] != w[2] && w[0] != w[2]).then_some((f, w))
        })
    };
    // Connected pieces: union–find over the welded vertex ids.
    let mut parent: Vec<u32> = (0..n as u32).collect();
    for (_, w) in faces() {
        for b in [w[1], w[2]] {
            let (ra, rb) = (root(&mut parent, w[0]), root(&mut parent, b));
            if ra != rb {
                parent[ra.max(rb) as usize] = ra.min(rb);
            }
        }
    }
    // Signed volume (six times it) per piece, about the centre of the bounding box so that
    // a model far from the origin does not lose its volume to cancellation; `scale` sums
    // the terms' magnitudes, to tell a volume from rounding.
    let (lo, hi) = positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let centre = (lo.as_dvec3() + hi.as_dvec3()) * 0.5;
    let mut volume = vec![0.0f64; n];
    let mut scale = vec![0.0f64; n];
    let mut has_faces = vec![false; n];
    for (f, w) in faces() {
        let p: [DVec3; 3] = f.map(|i| positions[i as usize].as_dvec3() - centre);
        let det = p[0].dot(p[1].cross(p[2]));
        let r = root(&mut parent, w[0]) as usize;
        volume[r] += det;
        scale[r] += det.abs();
        has_faces[r] = true;
    }
    // Every piece with faces encloses a volume well above the terms' rounding (~1e-16 of
    // their sum; a flat, two-layered piece encloses none and is refused).
    (0..n).all(|r| !has_faces[r] || volume[r] > 1e-9 * scale[r].max(f64::MIN_POSITIVE))
}

/// The representative of `x`'s set, halving the path on the way.
fn root(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let up = parent[parent[x as usize] as usize];
        parent[x as usize] = up;
        x = up;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    fn solid(positions: &[Vec3], faces: &[[u32; 3]]) -> bool {
        let edges = MeshEdges::new(positions, faces);
        let by_weld = bounds_solids(positions, faces, || &edges);
        // The welded test alone agrees wherever the indices close the mesh.
        if closed_by_indices(positions.len(), faces) {
            let welded = edges.edges.iter().all(|e| e.count == 2 && e.consistent)
                && outward(positions, faces, |i| edges.weld[i as usize]);
            assert_eq!(welded, by_weld);
        }
        by_weld
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
