//! What each shading mode costs one object, so that `shading="auto"` picks the *fastest* mode
//! within the tolerance, not the first in the order flat < Gouraud < Phong: on a dense mesh
//! seen small, Gouraud lights far more vertices than Phong lights pixels (a 99,224-triangle
//! sphere filling a quarter of 512×512: 49,614 vertices against 11,600 pixels, and Gouraud
//! the slowest of the three).
//!
//! Only the work that differs between the modes is counted: the points each lights (flat:
//! its set-up triangles; Gouraud: every vertex; Phong: every covered pixel), the normals
//! Gouraud and Phong transform per vertex, and the per-pixel interpolation. The constants
//! were measured on the project's 2-core test machine (docs/LIGHTING.md, "What the modes
//! cost"); only their ratios matter.

/// Lighting one point under one light (ns): the lane loops of flat, Gouraud and Phong cost
/// about the same per point; a specular term (normalising `h`, the power) adds to it.
const LIGHT_NS: f64 = 5.0;
const SPECULAR_NS: f64 = 3.0;
/// Transforming one vertex normal (Gouraud and Phong; flat needs none).
const NORMAL_NS: f64 = 3.0;
/// Interpolating a colour (Gouraud) or a normal and position (Phong, before its lighting)
/// per covered pixel, beyond flat's constant colour.
const INTERPOLATE_NS: f64 = 0.7;

/// The counts the costs scale with, for one object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Work {
    /// Pixels its front faces cover (projected area, occlusion ignored).
    pub pixels: f64,
    /// Front faces on screen (flat lights each set-up triangle once; no more than the
    /// pixels, since a triangle covering no pixel centre is culled before it is lit).
    pub front_triangles: f64,
    /// Vertices of its mesh (Gouraud lights every one).
    pub vertices: f64,
    /// Point sources lighting it (an area light counts its points).
    pub lights: usize,
    /// Whether its material has a specular term.
    pub specular: bool,
}

/// Each mode's cost (ns, flat, Gouraud, Phong), up to what they share.
pub(super) fn mode_costs(w: &Work) -> [f64; 3] {
    let per_point = (LIGHT_NS + if w.specular { SPECULAR_NS } else { 0.0 }) * w.lights as f64;
    let flat = per_point * w.front_triangles.min(w.pixels);
    let gouraud = (NORMAL_NS + per_point) * w.vertices + INTERPOLATE_NS * w.pixels;
    let phong = NORMAL_NS * w.vertices + (per_point + INTERPOLATE_NS) * w.pixels;
    [flat, gouraud, phong]
}

/// The modes (indices into flat, Gouraud, Phong) from the cheapest to the costliest; ties
/// keep the order flat < Gouraud < Phong.
pub(super) fn by_cost(costs: [f64; 3]) -> [usize; 3] {
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| costs[a].total_cmp(&costs[b]).then(a.cmp(&b)));
    order
}

/// The cheapest mode whose estimate is within `tolerance`, `None` when none is.
pub(super) fn pick(estimates: [f32; 3], costs: [f64; 3], tolerance: f32) -> Option<usize> {
    by_cost(costs)
        .into_iter()
        .find(|&m| estimates[m] <= tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn work(pixels: f64, triangles: f64, vertices: f64) -> Work {
        Work {
            pixels,
            front_triangles: triangles / 2.0,
            vertices,
            lights: 2,
            specular: true,
        }
    }

    #[test]
    fn a_coarse_mesh_filling_the_frame_costs_flat_then_gouraud_then_phong() {
        let c = mode_costs(&work(180_000.0, 9_800.0, 4_902.0));
        assert_eq!(by_cost(c), [0, 1, 2]);
    }

    #[test]
    fn a_dense_mesh_seen_small_is_cheaper_in_phong_than_in_gouraud() {
        let c = mode_costs(&work(11_600.0, 99_224.0, 49_614.0));
        assert_eq!(by_cost(c), [0, 2, 1]);
        // Flat over the tolerance: Phong, not Gouraud, when both meet it.
        assert_eq!(pick([3.0, 0.2, 0.1], c, 1.0), Some(2));
        assert_eq!(pick([3.0, 0.2, 1.5], c, 1.0), Some(1));
        assert_eq!(pick([3.0, 2.0, 1.5], c, 1.0), None);
    }
}
