//! Coverage: the top-left fill rule, known pixel sets, and watertightness of shared edges.

mod common;

use common::*;
use glam::Vec3;
use shadelab_raster::*;

fn quad(h: u32, x0: f32, y0: f32, x1: f32, y1: f32) -> Mesh {
    // Screen-space rectangle as two triangles sharing the diagonal.
    let p = vec![
        screen(h, x0, y0),
        screen(h, x1, y0),
        screen(h, x1, y1),
        screen(h, x0, y1),
    ];
    Mesh::new(p, vec![[0, 2, 1], [0, 3, 2]], None, None).unwrap()
}

#[test]
fn rectangle_on_pixel_centres_follows_top_left_rule() {
    let (w, h) = (8, 6);
    // Edges through pixel centres: left x=1.5 and top y=1.5 are in, right x=4.5 and bottom
    // y=3.5 are out → pixels x ∈ {1, 2, 3}, y ∈ {1, 2}.
    let c = counts(quad(h, 1.5, 1.5, 4.5, 3.5), &pixel_camera(w, h), w, h);
    for y in 0..h as usize {
        for x in 0..w as usize {
            let want = u32::from((1..=3).contains(&x) && (1..=2).contains(&y));
            assert_eq!(c[y * w as usize + x], want, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn diagonal_split_square_covers_each_pixel_once() {
    let (w, h) = (4, 4);
    for (x0, y0) in [(0.0, 0.0), (0.5, 0.5), (0.25, 0.75)] {
        let c = counts(
            quad(h, x0, y0, x0 + 2.0, y0 + 2.0),
            &pixel_camera(w, h),
            w,
            h,
        );
        let total: u32 = c.iter().sum();
        assert!(
            c.iter().all(|&v| v <= 1),
            "a pixel was covered twice: {c:?}"
        );
        assert_eq!(total, 4, "a 2x2 square covers 4 pixel centres: {c:?}");
    }
}

#[test]
fn single_triangles_cover_known_pixels() {
    let (w, h) = (8, 8);
    // Right triangle with legs on pixel centres: (0.5,0.5), (4.5,0.5), (0.5,4.5).
    // Centres (x+.5, y+.5) with x + y < 4 are strictly inside; the hypotenuse x + y = 4 is a
    // right/bottom edge (excluded); the legs are top and left edges (included).
    let p = vec![
        screen(h, 0.5, 0.5),
        screen(h, 4.5, 0.5),
        screen(h, 0.5, 4.5),
    ];
    let mesh = Mesh::new(p, vec![[0, 2, 1]], None, None).unwrap();
    let c = counts(mesh, &pixel_camera(w, h), w, h);
    for y in 0..8usize {
        for x in 0..8usize {
            assert_eq!(c[y * 8 + x], u32::from(x + y < 4), "pixel ({x}, {y})");
        }
    }
    // Winding does not change coverage.
    let p = vec![
        screen(h, 0.5, 0.5),
        screen(h, 4.5, 0.5),
        screen(h, 0.5, 4.5),
    ];
    let mesh = Mesh::new(p, vec![[0, 1, 2]], None, None).unwrap();
    assert_eq!(counts(mesh, &pixel_camera(w, h), w, h), c);
}

#[test]
fn tiny_triangle_between_centres_covers_nothing() {
    let (w, h) = (4, 4);
    let p = vec![
        screen(h, 1.6, 1.6),
        screen(h, 1.9, 1.6),
        screen(h, 1.6, 1.9),
    ];
    let c = counts(
        Mesh::new(p, vec![[0, 1, 2]], None, None).unwrap(),
        &pixel_camera(w, h),
        w,
        h,
    );
    assert!(c.iter().all(|&v| v == 0));
}

/// A jittered, rotated grid of `n × n` quads larger than the screen (jitter ≤ ±1/8 step, so
/// no triangle folds over): every pixel is covered
/// exactly once.
fn jittered_grid(n: usize, w: u32, h: u32, rng: &mut Rng) -> Mesh {
    let (cx, cy) = (w as f32 / 2.0, h as f32 / 2.0);
    let span = (w.max(h) as f32) * 1.6;
    let angle = rng.f32() * std::f32::consts::TAU;
    let (s, c) = angle.sin_cos();
    let step = span / n as f32;
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let interior = i > 0 && i < n && j > 0 && j < n;
            let jit = |r: &mut Rng| {
                if interior {
                    (r.f32() - 0.5) * step * 0.25
                } else {
                    0.0
                }
            };
            let u = -span / 2.0 + i as f32 * step + jit(rng);
            let v = -span / 2.0 + j as f32 * step + jit(rng);
            p.push(Vec3::new(cx + c * u - s * v, cy + s * u + c * v, 0.0));
        }
    }
    let idx = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            // Alternate the diagonal so both orientations of shared edges occur.
            if (i + j) % 2 == 0 {
                t.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
                t.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
            } else {
                t.push([idx(i, j), idx(i + 1, j), idx(i, j + 1)]);
                t.push([idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]);
            }
        }
    }
    Mesh::new(p, t, None, None).unwrap()
}

#[test]
fn jittered_grids_are_watertight() {
    let mut rng = Rng(0x9E3779B97F4A7C15);
    for (n, w, h) in [
        (40, 97, 61),
        (120, 200, 150),
        (230, 256, 256),
        (240, 300, 200),
    ] {
        let mesh = jittered_grid(n, w, h, &mut rng);
        let tris = mesh.triangle_count();
        let c = counts(mesh, &pixel_camera(w, h), w, h);
        let bad: Vec<_> = c
            .iter()
            .enumerate()
            .filter(|(_, &v)| v != 1)
            .take(5)
            .collect();
        assert!(
            bad.is_empty(),
            "{tris} triangles: pixels not covered once: {bad:?}"
        );
    }
}

#[test]
fn fan_of_slivers_is_watertight() {
    // 100 000 thin triangles (apex angle 0.0036°) around one vertex inside the image,
    // reaching past the border.
    let (w, h) = (128, 128);
    let centre = screen(h, 61.3, 70.7);
    let n = 100_000;
    let mut p = vec![centre];
    for k in 0..n {
        let a = k as f32 / n as f32 * std::f32::consts::TAU;
        p.push(centre + Vec3::new(a.cos(), a.sin(), 0.0) * 400.0);
    }
    let t: Vec<[u32; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
    let c = counts(
        Mesh::new(p, t, None, None).unwrap(),
        &pixel_camera(w, h),
        w,
        h,
    );
    assert!(c.iter().all(|&v| v == 1), "max {:?}", c.iter().max());
}

#[test]
fn closed_sphere_is_covered_zero_or_twice() {
    // Seen through a perspective camera, front and back of a closed mesh meet along the
    // silhouette: every pixel is covered by exactly 0 or 2 triangles, and with back-face
    // culling by 0 or 1 (as by default, where the hidden back faces of a solid are skipped).
    let cam = Camera::look_at(
        glam::DVec3::new(0.3, 0.2, 3.0),
        glam::DVec3::ZERO,
        glam::DVec3::Y,
        45.0,
        0.1,
        100.0,
    )
    .unwrap();
    let scene = white_scene(primitives::uv_sphere(160, 320)); // 101 760 triangles
    let mut opts = RenderOptions::new(200, 160);
    opts.cull_hidden = false;
    let c = coverage_counts(&scene, &cam, &opts).unwrap();
    assert!(c.iter().all(|&v| v == 0 || v == 2));
    let inside = c.iter().filter(|&&v| v == 2).count();
    assert!(inside > 5000);
    let hidden_skipped = coverage_counts(&scene, &cam, &RenderOptions::new(200, 160)).unwrap();
    opts.cull_backfaces = true;
    let c1 = coverage_counts(&scene, &cam, &opts).unwrap();
    assert!(c1.iter().zip(&c).all(|(&a, &b)| a * 2 == b));
    assert_eq!(hidden_skipped, c1);
}
