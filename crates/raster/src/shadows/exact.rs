//! Exact visibility: a shadow ray from the shaded point to the light through the BVH.

use glam::Vec3;

use super::Toward;
use crate::rays::Bvh;

/// 1 if nothing lies between the point `p` (shading normal `n`, geometric normal `g`) and
/// the light, else 0. A point facing away from the light (`n·l ≤ 0`) gets no diffuse or
/// specular whatever its visibility: no ray is cast and 1 is returned.
#[inline]
pub(super) fn visibility(bvh: &Bvh, toward: Toward, n: Vec3, p: Vec3, g: Vec3, offset: f32) -> f32 {
    let g = g.normalize_or_zero();
    let g = if g.dot(n) < 0.0 { -g } else { g };
    let origin = p + g * (offset + 1e-6 * p.abs().max_element());
    let (dir, t_max) = match toward {
        Toward::Direction(d) => (d, f32::INFINITY),
        // The segment's far end is the light itself (t = 1).
        Toward::Position(q) => (q - origin, 1.0),
    };
    if n.dot(dir) <= 0.0 {
        return 1.0;
    }
    if bvh.occluded(origin, dir, t_max) {
        0.0
    } else {
        1.0
    }
}
