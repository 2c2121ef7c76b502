//! Per-vertex tangent frames from positions, UVs and vertex normals, for normal and bump
//! maps (tangent space).
//!
//! MikkTSpace-style: each face's tangent ∂P/∂u and bitangent ∂P/∂v (solved from its edges
//! and UV differences) are projected onto the plane of each corner's vertex normal
//! (Gram–Schmidt), normalised, and accumulated weighted by the corner's angle; each vertex's
//! sum is projected and normalised again. The handedness `w` is +1 when the accumulated
//! bitangent lies on the side of N × T, −1 when the UV map is mirrored there, so the
//! bitangent a shader rebuilds is `w · N × T`.

use glam::{DVec3, Vec2, Vec3, Vec4};

/// A unit vector perpendicular to `n` (any: the fallback tangent where UVs give none).
fn perpendicular(n: DVec3) -> DVec3 {
    let a = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    (a - n * n.dot(a)).normalize_or_zero()
}

/// The component of `v` perpendicular to the unit vector `n`, normalised (zero if none).
fn orthonormal(v: DVec3, n: DVec3) -> DVec3 {
    (v - n * n.dot(v)).normalize_or_zero()
}

/// Tangents (xyz, unit, perpendicular to the vertex normal) and handedness (w = ±1) per
/// vertex. `normals` are the mesh's vertex normals (unit or zero).
///
/// Never NaN: faces whose UVs have no area, or no area themselves, add nothing; a vertex
/// without any tangent gets a perpendicular of its normal (w = +1), and a vertex with a
/// zero normal gets (1, 0, 0, 1).
pub fn generate_tangents(
    positions: &[Vec3],
    uvs: &[Vec2],
    normals: &[Vec3],
    indices: &[[u32; 3]],
) -> Vec<Vec4> {
    let mut tan = vec![DVec3::ZERO; positions.len()];
    let mut bit = vec![DVec3::ZERO; positions.len()];
    let vn: Vec<DVec3> = normals.iter().map(|n| n.as_dvec3()).collect();
    for tri in indices {
        let v = tri.map(|i| i as usize);
        let p = v.map(|k| positions[k].as_dvec3());
        let t = v.map(|k| uvs[k].as_dvec2());
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let (d1, d2) = (t[1] - t[0], t[2] - t[0]);
        let r = d1.x * d2.y - d2.x * d1.y;
        if r.is_nan() || r.abs() <= 1e-20 {
            continue; // UVs without area: no direction for u or v
        }
        // P − P0 = ∂P/∂u·(u − u0) + ∂P/∂v·(v − v0), solved on the two edges.
        let dpdu = (e1 * d2.y - e2 * d1.y) / r;
        let dpdv = (e2 * d1.x - e1 * d2.x) / r;
        if !(dpdu.is_finite() && dpdv.is_finite()) {
            continue;
        }
        for c in 0..3 {
            let a = p[(c + 1) % 3] - p[c];
            let b = p[(c + 2) % 3] - p[c];
            let angle = a.angle_between(b);
            if angle.is_nan() || angle <= 0.0 {
                continue; // a degenerate corner
            }
            let n = vn[v[c]];
            tan[v[c]] += orthonormal(dpdu, n) * angle;
            bit[v[c]] += orthonormal(dpdv, n) * angle;
        }
    }
    tan.iter()
        .zip(&bit)
        .zip(&vn)
        .map(|((t, b), n)| {
            if *n == DVec3::ZERO {
                return Vec4::new(1.0, 0.0, 0.0, 1.0);
            }
            let mut t = orthonormal(*t, *n);
            if t == DVec3::ZERO {
                t = perpendicular(*n);
            }
            let w = if n.cross(t).dot(*b) < 0.0 { -1.0 } else { 1.0 };
            t.as_vec3().extend(w)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit quad in the z = 0 plane, normal +z, with UVs `uv`.
    fn quad(uv: [Vec2; 4]) -> Vec<Vec4> {
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        generate_tangents(&p, &uv, &[Vec3::Z; 4], &[[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn tangent_follows_u_and_handedness_follows_the_map() {
        let uv = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        assert!(quad(uv).iter().all(|t| *t == Vec4::new(1.0, 0.0, 0.0, 1.0)));
        // u runs along +y, v along +x: N × T = z × y = −x, the bitangent +x: mirrored.
        let swapped = uv.map(|t| Vec2::new(t.y, t.x));
        assert!(quad(swapped)
            .iter()
            .all(|t| *t == Vec4::new(0.0, 1.0, 0.0, -1.0)));
        // u mirrored: the tangent is −x, N × T = −y but v runs along +y.
        let mirrored = uv.map(|t| Vec2::new(1.0 - t.x, t.y));
        assert!(quad(mirrored)
            .iter()
            .all(|t| *t == Vec4::new(-1.0, 0.0, 0.0, -1.0)));
    }

    #[test]
    fn tangents_are_perpendicular_to_tilted_normals_and_never_nan() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(3.0, 3.0, 3.0)];
        let n = [
            Vec3::new(0.0, 0.6, 0.8),
            Vec3::Z,
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
        ];
        let uv = [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ZERO];
        // A face with degenerate UVs (all three equal) and one unused vertex.
        let t = generate_tangents(&p, &uv, &n, &[[0, 1, 2], [0, 0, 1]]);
        assert!(t.iter().all(|t| t.is_finite()));
        assert!(t[0].truncate().dot(n[0]).abs() < 1e-6);
        assert!((t[0].truncate().length() - 1.0).abs() < 1e-6);
        assert_eq!(t[2], Vec4::new(1.0, 0.0, 0.0, 1.0)); // zero normal
        assert!(t[3].truncate().dot(n[3]).abs() < 1e-6); // no face: a perpendicular
    }

    use proptest::prelude::*;

    proptest! {
        /// For any finite positions, UVs and normals (degenerate ones included): every
        /// tangent is finite, unit and perpendicular to its (non-zero) normal, w = ±1.
        #[test]
        fn tangents_are_unit_perpendicular_and_finite(
            p in prop::collection::vec(prop::array::uniform3(-1e3f32..1e3), 4),
            uv in prop::collection::vec(prop::array::uniform2(-10f32..10.0), 4),
            n in prop::collection::vec(prop::array::uniform3(-1f32..1.0), 4),
        ) {
            let p: Vec<Vec3> = p.into_iter().map(Vec3::from_array).collect();
            let uv: Vec<Vec2> = uv.into_iter().map(Vec2::from_array).collect();
            let n: Vec<Vec3> = n.into_iter().map(|x| Vec3::from_array(x).normalize_or_zero()).collect();
            let t = generate_tangents(&p, &uv, &n, &[[0, 1, 2], [0, 2, 3], [1, 3, 2]]);
            for (t, n) in t.iter().zip(&n) {
                prop_assert!(t.is_finite());
                prop_assert!(t.w == 1.0 || t.w == -1.0);
                prop_assert!((t.truncate().length() - 1.0).abs() < 1e-5, "{t}");
                if *n != Vec3::ZERO {
                    prop_assert!(t.truncate().dot(*n).abs() < 1e-5, "{t} {n}");
                }
            }
        }
    }
}
