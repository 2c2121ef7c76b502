//! Vertex normals with a crease angle ([`Mesh::with_normals`]): smooth across gentle
//! edges, sharp across edges whose faces turn by more than the angle, vertices split where
//! the corners that share them disagree.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use crate::error::{RasterError, Result};
use crate::mesh::{face_normal, Mesh};

/// A position's key for welding: its bits, with −0 read as +0.
fn weld_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

impl Mesh {
    /// The same mesh with vertex normals recomputed with a crease angle (degrees, 0 to
    /// 180; `None`: every edge smooth), vertices split where needed.
    ///
    /// Vertices at the same position are welded for the computation (so a mesh split at UV
    /// seams, or storing three vertices per triangle, shades smooth across them). Each
    /// triangle corner gets the normalised sum of the unit normals of the faces around its
    /// position whose normal is within `crease_angle` of its own face's normal (its own face
    /// included; a corner of a degenerate face takes the sum of all of them). A vertex whose
    /// corners get different normals is split into one vertex per normal (copies of its
    /// position, UV and colour), in the order of its corners; vertices are never merged, and
    /// a vertex no face uses keeps its place with a zero normal. Faces keep their order.
    /// Faces all within the angle of each other share bit-identical sums (the same faces
    /// added in the same order), so a smooth vertex is never split by rounding.
    pub fn with_normals(&self, crease_angle: Option<f64>) -> Result<Mesh> {
        let cos_t = match crease_angle {
            None => f64::NEG_INFINITY,
            Some(a) if a.is_finite() && (0.0..=180.0).contains(&a) => a.to_radians().cos(),
            Some(a) => {
                return Err(RasterError::invalid_field(
                    "crease_angle",
                    format!("crease_angle must be None or 0 to 180 degrees, got {a}"),
                ))
            }
        };
        let pos = self.positions();
        let idx = self.indices();
        let mut welded: HashMap<[u32; 3], u32> = HashMap::new();
        let weld: Vec<u32> = pos
            .iter()
            .map(|p| {
                let next = welded.len() as u32;
                *welded.entry(weld_key(*p)).or_insert(next)
            })
            .collect();
        let fnorm: Vec<DVec3> = idx
            .iter()
            .map(|t| face_normal(pos[t[0] as usize], pos[t[1] as usize], pos[t[2] as usize]))
            .collect();
        // The faces around each welded position (CSR, in face order).
        let mut start = vec![0usize; welded.len() + 1];
        for t in idx {
            for &v in t {
                start[weld[v as usize] as usize + 1] += 1;
            }
        }
        for i in 0..welded.len() {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut around = vec![0u32; start[welded.len()]];
        for (f, t) in idx.iter().enumerate() {
            for &v in t {
                let w = weld[v as usize] as usize;
                around[fill[w]] = f as u32;
                fill[w] += 1;
            }
        }
        // Each corner's normal, and one output vertex per (vertex, distinct normal).
        let mut split: Vec<Vec<Vec3>> = vec![Vec::new(); pos.len()];
        let mut corner = vec![[0usize; 3]; idx.len()];
        for (f, t) in idx.iter().enumerate() {
            let own = fnorm[f];
            for (c, &v) in t.iter().enumerate() {
                let w = weld[v as usize] as usize;
                let faces = &around[start[w]..start[w + 1]];
                let sum_where = |keep: &dyn Fn(DVec3) -> bool| {
                    faces
                        .iter()
                        .map(|&g| fnorm[g as usize])
                        .filter(|n| keep(*n))
                        .fold(DVec3::ZERO, |s, n| s + n)
                };
                let mut s = sum_where(&|n| own.dot(n) >= cos_t);
                if s.length_squared() <= 1e-18 {
                    s = sum_where(&|_| true);
                }
                let n = s.normalize_or_zero().as_vec3();
                let list = &mut split[v as usize];
                let k = match list
                    .iter()
                    .position(|m| m.to_array().map(f32::to_bits) == n.to_array().map(f32::to_bits))
                {
                    Some(k) => k,
                    None => {
                        list.push(n);
                        list.len() - 1
                    }
                };
                corner[f][c] = k;
            }
        }
        let mut first = Vec::with_capacity(pos.len());
        let mut positions = Vec::with_capacity(pos.len());
        let mut normals = Vec::with_capacity(pos.len());
        let mut source = Vec::with_capacity(pos.len());
        for (v, list) in split.iter().enumerate() {
            first.push(positions.len() as u32);
            let ns: &[Vec3] = if list.is_empty() { &[Vec3::ZERO] } else { list };
            for n in ns {
                positions.push(pos[v]);
                normals.push(*n);
                source.push(v);
            }
        }
        let indices: Vec<[u32; 3]> = idx
            .iter()
            .zip(&corner)
            .map(|(t, c)| [0, 1, 2].map(|k| first[t[k] as usize] + c[k] as u32))
            .collect();
        let uvs = self.uvs().map(|uv| source.iter().map(|&v| uv[v]).collect());
        let mesh = Mesh::new(positions, indices, Some(normals), uvs)?;
        match self.colors() {
            Some(c) => mesh.with_colors(source.iter().map(|&v| c[v]).collect()),
            None => Ok(mesh),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::primitives;

    /// A cube with 8 shared corners (no UVs).
    fn shared_cube() -> crate::Mesh {
        let c = primitives::cube();
        let mut pos: Vec<glam::Vec3> = Vec::new();
        let mut map = Vec::new();
        for p in c.positions() {
            let i = pos.iter().position(|q| q == p).unwrap_or_else(|| {
                pos.push(*p);
                pos.len() - 1
            });
            map.push(i as u32);
        }
        let idx = c
            .indices()
            .iter()
            .map(|t| t.map(|v| map[v as usize]))
            .collect();
        crate::Mesh::new(pos, idx, None, None).unwrap()
    }

    #[test]
    fn a_cube_at_30_degrees_has_flat_faces() {
        let cube = shared_cube();
        assert_eq!(cube.positions().len(), 8);
        let m = cube.with_normals(Some(30.0)).unwrap();
        assert_eq!(m.positions().len(), 24); // each corner split three ways
        let n = m.vertex_normals();
        for t in m.indices() {
            let p = t.map(|v| m.positions()[v as usize]);
            let f = crate::face_normal(p[0], p[1], p[2]).as_vec3();
            for v in t {
                assert_eq!(n[*v as usize], f);
            }
        }
        // No crease: 8 vertices, each along its corner's diagonal.
        let s = cube.with_normals(None).unwrap();
        assert_eq!(s.positions().len(), 8);
        for (p, n) in s.positions().iter().zip(s.vertex_normals()) {
            assert!((p.normalize() - *n).length() < 1e-6);
        }
    }

    #[test]
    fn a_sphere_stays_smooth() {
        let s = primitives::ico_sphere(3);
        let m = s.with_normals(Some(30.0)).unwrap();
        assert_eq!(m.positions().len(), s.positions().len());
        assert_eq!(m.indices(), s.indices());
        for (p, n) in m.positions().iter().zip(m.vertex_normals()) {
            assert!((p.normalize() - *n).length() < 0.02, "{p} {n}");
        }
    }

    #[test]
    fn bad_angles_name_the_field() {
        let c = primitives::cube();
        for a in [f64::NAN, -1.0, 181.0, f64::INFINITY] {
            let e = c.with_normals(Some(a)).unwrap_err();
            assert!(e.to_string().contains("crease_angle"), "{e}");
        }
    }
}
