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

/// Smallest interior angle of a triangle, in degrees (f64, from the exact integer vertices).
fn min_angle_deg(v: [(i64, i64); 3]) -> f64 {
    (0..3)
        .map(|k| {
            let (a, b, c) = (v[k], v[(k + 1) % 3], v[(k + 2) % 3]);
            let (ux, uy) = ((b.0 - a.0) as f64, (b.1 - a.1) as f64);
            let (wx, wy) = ((c.0 - a.0) as f64, (c.1 - a.1) as f64);
            (ux * wy - uy * wx)
                .abs()
                .atan2(ux * wx + uy * wy)
                .to_degrees()
        })
        .fold(f64::INFINITY, f64::min)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// Triangles 1/64 px across (4 units of 1/256 px), placed within a few units of pixel
    /// centres so that they do or do not catch one: coverage equals the exact reference.
    #[test]
    fn triangles_of_one_64th_pixel_match_reference(
        centre in (0i64..S, 0i64..S),
        offset in (-6i64..=6, -6i64..=6),
        pts in prop::array::uniform3((0i64..=4, 0i64..=4)),
    ) {
        let base = (centre.0 * 256 + 128 + offset.0 - 2, centre.1 * 256 + 128 + offset.1 - 2);
        let v = pts.map(|(x, y)| (base.0 + x, base.1 + y));
        prop_assert_eq!(render_counts(v), reference(v));
    }

    /// Slivers with angles below 1e-4 degrees: a long edge (14 000 to 16 000 px, reaching
    /// far into the guard band) along a lattice direction through pixel centres, and the
    /// third vertex 1 or 2 units (1/256 px) off it near the middle. Which centres on the long edge are
    /// covered is decided by the fill rule alone; coverage equals the exact reference.
    #[test]
    fn slivers_below_1e_minus_4_degrees_match_reference(
        dir in prop::sample::select(vec![(1i64, 0i64), (0, 1), (1, 1), (1, -1), (2, 1), (-1, 3), (3, 2)]),
        centre in (0i64..S, 0i64..S),
        reach_px in (7000.0f64..8000.0, 7000.0f64..8000.0),
        off in prop::sample::select(vec![-2i64, -1, 1, 2]),
        along in -300i64..300,
    ) {
        let c = (centre.0 * 256 + 128, centre.1 * 256 + 128);
        let step = (dir.0 * 256, dir.1 * 256); // one lattice step along the edge
        let len = ((dir.0 * dir.0 + dir.1 * dir.1) as f64).sqrt();
        let reach = ((reach_px.0 / len) as i64, (reach_px.1 / len) as i64);
        let a = (c.0 - reach.0 * step.0, c.1 - reach.0 * step.1);
        let b = (c.0 + reach.1 * step.0, c.1 + reach.1 * step.1);
        // Third vertex: near the middle, pushed `off` units across the edge (perpendicular
        // to it for axis directions, along an axis otherwise; never on the edge).
        let m = (c.0 + along * step.0, c.1 + along * step.1);
        let p = if dir.1 == 0 { (m.0, m.1 + off) } else { (m.0 + off, m.1) };
        let v = [a, b, p];
        prop_assert!(min_angle_deg(v) < 1e-4, "angle {}", min_angle_deg(v));
        let got = render_counts(v);
        prop_assert_eq!(&got, &reference(v));
        // And the other winding covers the same centres.
        prop_assert_eq!(render_counts([a, p, b]), got);
    }
}

/// A 1-px square around a pixel centre tiled by 64 × 64 cells of 1/64 px (8192 triangles),
/// the centre on a cell corner, an edge or inside a cell: covered exactly once, and
/// nothing else.
#[test]
fn tiling_of_one_64th_pixel_cells_covers_the_centre_once() {
    for shift in [(0i64, 0i64), (2, 0), (0, 2), (1, 3)] {
        let (cx, cy) = (10 * 256 + 128, 20 * 256 + 128);
        let (x0, y0) = (cx - 128 + shift.0, cy - 128 + shift.1);
        let mut p = Vec::new();
        for j in 0..=64 {
            for i in 0..=64 {
                let (x, y) = (x0 + 4 * i, y0 + 4 * j);
                p.push(screen(S as u32, x as f32 / 256.0, y as f32 / 256.0));
            }
        }
        let mut idx = Vec::new();
        for j in 0..64u32 {
            for i in 0..64u32 {
                let k = j * 65 + i;
                // Alternate the diagonal so both diagonal directions meet the centre.
                if (i + j) % 2 == 0 {
                    idx.push([k, k + 1, k + 66]);
                    idx.push([k, k + 66, k + 65]);
                } else {
                    idx.push([k, k + 1, k + 65]);
                    idx.push([k + 1, k + 66, k + 65]);
                }
            }
        }
        let mesh = Mesh::new(p, idx, None, None).unwrap();
        let h = S as u32;
        let c = counts(mesh, &pixel_camera(h, h), h, h);
        for (i, &n) in c.iter().enumerate() {
            let want = u32::from(i == 20 * S as usize + 10);
            assert_eq!(n, want, "shift {shift:?}, pixel {i}");
        }
    }
}
