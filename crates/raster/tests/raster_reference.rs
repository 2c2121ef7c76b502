//! The optimised rasterizer against a brute-force reference written from the definition:
//! a pixel is covered when its centre is strictly inside the triangle, or exactly on an edge
//! that is a top edge (horizontal, interior below) or a left edge (interior to the right).
//!
//! Vertices are multiples of 1/256 px on a 64×64 image seen through the pixel camera, so the
//! renderer's 16.8 snapping is exact and the reference can work in exact integers.

mod common;

use common::*;
use proptest::prelude::*;
use shadelab_raster::*;

const S: i64 = 64;

/// Exact coverage of one triangle given in 1/256-px screen units (y down).
fn reference(v: [(i64, i64); 3]) -> Vec<u32> {
    let cross = |a: (i64, i64), b: (i64, i64), p: (i64, i64)| {
        (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0)
    };
    let area = cross(v[0], v[1], v[2]);
    let mut out = vec![0u32; (S * S) as usize];
    if area == 0 {
        return out;
    }
    for y in 0..S {
        for x in 0..S {
            let p = (x * 256 + 128, y * 256 + 128);
            let mut inside = true;
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                // Distance sign relative to the triangle's own orientation.
                let d = cross(a, b, p) * area.signum();
                if d < 0 {
                    inside = false;
                } else if d == 0 {
                    // On the edge: the interior side decides whether it is top or left.
                    // Interior normal (pointing into the triangle), y down.
                    let (ex, ey) = (b.0 - a.0, b.1 - a.1);
                    let (nx, ny) = if area > 0 { (-ey, ex) } else { (ey, -ex) };
                    let top = ny > 0 && nx == 0; // horizontal edge, interior below
                    let left = nx > 0; // interior to the right
                    if !(top || left) {
                        inside = false;
                    }
                }
            }
            out[(y * S + x) as usize] = u32::from(inside);
        }
    }
    out
}

fn render_counts(v: [(i64, i64); 3]) -> Vec<u32> {
    let h = S as u32;
    let p = v
        .iter()
        .map(|&(x, y)| screen(h, x as f32 / 256.0, y as f32 / 256.0))
        .collect();
    let mesh = Mesh::new(p, vec![[0, 1, 2]], None, None).unwrap();
    counts(mesh, &pixel_camera(h, h), h, h)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn coverage_matches_reference(
        pts in prop::array::uniform3((-2560i64..(S * 256 + 2560), -2560i64..(S * 256 + 2560))),
    ) {
        prop_assert_eq!(render_counts(pts), reference(pts));
    }

    /// Vertices on the pixel-centre lattice (and half way between) make many centres fall
    /// exactly on edges, the cases the fill rule decides.
    #[test]
    fn coverage_on_lattice_points_matches_reference(
        pts in prop::array::uniform3((-8i64..(2 * S + 8), -8i64..(2 * S + 8))),
    ) {
        let pts = pts.map(|(x, y)| (x * 128, y * 128));
        prop_assert_eq!(render_counts(pts), reference(pts));
    }
}

#[test]
fn reference_agrees_on_hand_cases() {
    // Axis-aligned right triangle with legs on pixel centres (see fill_rule.rs).
    let t = [(128, 128), (128, 4 * 256 + 128), (4 * 256 + 128, 128)];
    let r = reference(t);
    assert_eq!(r.iter().sum::<u32>(), 10);
    assert_eq!(render_counts(t), r);
}
