//! Validated triangle meshes and vertex-normal generation.

use std::sync::OnceLock;

use glam::{DVec3, Vec2, Vec3};

use crate::error::{RasterError, Result};

/// An indexed triangle mesh, validated on construction.
///
/// Invariants (checked by [`Mesh::new`]): at least one triangle, every index below the vertex
/// count, every coordinate finite, and normals/UVs (when present) one per vertex.
/// Degenerate (zero-area) triangles are allowed: the rasterizer skips them.
#[derive(Debug)]
pub struct Mesh {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    indices: Vec<[u32; 3]>,
    generated_normals: OnceLock<Vec<Vec3>>,
}

impl Mesh {
    /// Builds a mesh, checking every invariant and naming the first offending element.
    pub fn new(
        positions: Vec<Vec3>,
        indices: Vec<[u32; 3]>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
    ) -> Result<Self> {
        if positions.is_empty() {
            return Err(RasterError::invalid("mesh has no vertices"));
        }
        if indices.is_empty() {
            return Err(RasterError::invalid("mesh has no triangles"));
        }
        if positions.len() > u32::MAX as usize {
            return Err(RasterError::invalid(format!(
                "mesh has {} vertices, more than the 2^32 - 1 a u32 index can address",
                positions.len()
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(RasterError::invalid(format!(
                "vertex {i} has a non-finite coordinate {:?}",
                positions[i].to_array()
            )));
        }
        let n = positions.len() as u32;
        if let Some((f, tri)) = indices
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&i| i >= n))
        {
            return Err(RasterError::invalid(format!(
                "face {f} has index {:?} out of range for {n} vertices",
                tri.iter().copied().find(|&i| i >= n).unwrap_or(0)
            )));
        }
        if let Some(normals) = &normals {
            if normals.len() != positions.len() {
                return Err(RasterError::invalid(format!(
                    "normals has {} rows but the mesh has {} vertices",
                    normals.len(),
                    positions.len()
                )));
            }
            if let Some(i) = normals.iter().position(|v| !v.is_finite()) {
                return Err(RasterError::invalid(format!(
                    "normal {i} has a non-finite component {:?}",
                    normals[i].to_array()
                )));
            }
        }
        if let Some(uvs) = &uvs {
            if uvs.len() != positions.len() {
                return Err(RasterError::invalid(format!(
                    "uvs has {} rows but the mesh has {} vertices",
                    uvs.len(),
                    positions.len()
                )));
            }
            if let Some(i) = uvs.iter().position(|v| !v.is_finite()) {
                return Err(RasterError::invalid(format!(
                    "uv {i} has a non-finite component {:?}",
                    uvs[i].to_array()
                )));
            }
        }
        Ok(Mesh {
            positions,
            normals,
            uvs,
            indices,
            generated_normals: OnceLock::new(),
        })
    }

    /// Vertex positions (object space).
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Triangles as vertex-index triples; counter-clockwise is the front.
    pub fn indices(&self) -> &[[u32; 3]] {
        &self.indices
    }

    /// The vertex normals given at construction, if any.
    pub fn given_normals(&self) -> Option<&[Vec3]> {
        self.normals.as_deref()
    }

    /// Texture coordinates, if any.
    pub fn uvs(&self) -> Option<&[Vec2]> {
        self.uvs.as_deref()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Vertex normals: the given ones, or generated once (on first use) by
    /// [`generate_vertex_normals`] and cached.
    pub fn vertex_normals(&self) -> &[Vec3] {
        match &self.normals {
            Some(n) => n,
            None => self
                .generated_normals
                .get_or_init(|| generate_vertex_normals(&self.positions, &self.indices)),
        }
    }
}

/// Unit normal of the triangle (p0, p1, p2) in f64, or zero when it has no area.
pub fn face_normal(p0: Vec3, p1: Vec3, p2: Vec3) -> DVec3 {
    let (a, b, c) = (p0.as_dvec3(), p1.as_dvec3(), p2.as_dvec3());
    (b - a).cross(c - a).normalize_or_zero()
}

/// Vertex normals by the seed lectures' rule: the average of the unit normals of the faces
/// around each vertex, renormalised.
///
/// Fallbacks, never NaN: where the unit normals cancel (a sheet with both sides, say), the
/// vertex takes the unit normal of the first non-degenerate face that uses it; a vertex used
/// only by degenerate faces, or by none, gets the zero vector (the shader then falls back to
/// the face normal, and a zero normal receives no diffuse or specular light).
pub fn generate_vertex_normals(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<Vec3> {
    let mut sum = vec![DVec3::ZERO; positions.len()];
    let mut first = vec![DVec3::ZERO; positions.len()];
    for tri in indices {
        let [a, b, c] = tri.map(|i| i as usize);
        let n = face_normal(positions[a], positions[b], positions[c]);
        if n == DVec3::ZERO {
            continue;
        }
        for &v in &[a, b, c] {
            sum[v] += n;
            if first[v] == DVec3::ZERO {
                first[v] = n;
            }
        }
    }
    sum.iter()
        .zip(&first)
        .map(|(s, f)| {
            // A sum shorter than 1e-9 is cancellation noise, not a direction.
            if s.length_squared() > 1e-18 {
                s.normalize().as_vec3()
            } else {
                f.as_vec3()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_meshes() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        assert!(Mesh::new(p.clone(), vec![], None, None).is_err());
        let e = Mesh::new(p.clone(), vec![[0, 1, 3]], None, None).unwrap_err();
        assert!(e.to_string().contains("face 0"), "{e}");
        let mut bad = p.clone();
        bad[1].x = f32::NAN;
        let e = Mesh::new(bad, vec![[0, 1, 2]], None, None).unwrap_err();
        assert!(e.to_string().contains("vertex 1"), "{e}");
        let e = Mesh::new(p, vec![[0, 1, 2]], Some(vec![Vec3::Z]), None).unwrap_err();
        assert!(e.to_string().contains("normals"), "{e}");
    }

    #[test]
    fn normals_average_unit_face_normals() {
        // Two faces of a folded quad: the shared vertices get the normalised average.
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let idx = vec![[0, 1, 2], [0, 2, 3]]; // normals +z and +x
        let n = generate_vertex_normals(&p, &idx);
        let s = std::f32::consts::FRAC_1_SQRT_2;
        assert!((n[0] - Vec3::new(s, 0.0, s)).length() < 1e-6);
        assert_eq!(n[1], Vec3::Z);
        assert_eq!(n[3], Vec3::X);
    }

    #[test]
    fn cancelling_normals_fall_back_to_first_face() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(5.0, 5.0, 5.0)];
        let idx = vec![[0, 1, 2], [0, 2, 1], [0, 0, 1]];
        let n = generate_vertex_normals(&p, &idx);
        assert_eq!(n[0], Vec3::Z);
        assert_eq!(n[3], Vec3::ZERO); // unreferenced
        assert!(n.iter().all(|v| v.is_finite()));
    }
}
