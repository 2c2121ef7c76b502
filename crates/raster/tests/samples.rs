//! Multi-sample anti-aliasing (`RenderOptions::samples`) and supersampling
//! (`RenderOptions::supersample`) against exact values: the share of sample positions inside
//! an edge, watertightness per sample, interior pixels equal to one sample, determinism, and
//! the edge error against the exact area coverage falling as samples grow.

mod common;

use std::sync::Arc;

use common::*;
use glam::{DVec2, DVec3, Mat4, Vec3};
use shadelab_raster::*;

const W: u32 = 80;
const H: u32 = 64;

/// The standard sample positions (D3D11 / Vulkan), 1/16 px from the centre, y down: an
/// independent copy of the table the renderer uses.
fn positions(n: u32) -> Vec<(f64, f64)> {
    let p: &[(i32, i32)] = match n {
        1 => &[(0, 0)],
        2 => &[(4, 4), (-4, -4)],
        4 => &[(-2, -6), (6, -2), (-6, 2), (2, 6)],
        8 => &[
            (1, -3),
            (-1, 3),
            (5, 1),
            (-3, -5),
            (-5, 5),
            (-7, -1),
            (3, 7),
            (7, -7),
        ],
        16 => &[
            (1, 1),
            (-1, -3),
            (-3, 2),
            (4, -1),
            (-5, -2),
            (2, 5),
            (5, 3),
            (3, -5),
            (-2, 6),
            (0, -7),
            (-4, -6),
            (-6, 4),
            (-8, 0),
            (7, -4),
            (6, 7),
            (-7, -8),
        ],
        _ => unreachable!(),
    };
    p.iter()
        .map(|&(x, y)| (x as f64 / 16.0, y as f64 / 16.0))
        .collect()
}

fn options(samples: u32) -> RenderOptions {
    let mut o = RenderOptions::new(W, H);
    o.samples = samples;
    o
}

/// A white (unlit, ambient 1) mesh of screen-space triangles (y down, pixel units).
fn white(tris: &[[(f64, f64); 3]]) -> Scene {
    let mut v = Vec::new();
    let mut f = Vec::new();
    for t in tris {
        let k = v.len() as u32;
        v.extend(t.iter().map(|&(x, y)| screen(H, x as f32, y as f32)));
        f.push([k, k + 1, k + 2]);
    }
    white_scene(Mesh::new(v, f, None, None).unwrap())
}

fn red(c: &[f32]) -> Vec<f32> {
    c.chunks_exact(3).map(|p| p[0]).collect()
}

/// Signed area test: > 0 on the inside of a counter-clockwise (y-down: clockwise on
/// screen, whichever; we test both signs) triangle.
fn inside(t: &[(f64, f64); 3], p: (f64, f64)) -> Option<bool> {
    let mut signs = [0.0; 3];
    for k in 0..3 {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        signs[k] = (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
    }
    // A sample within a hair of an edge would depend on the fill rule and the 1/256 px
    // snapping: not a question for this test.
    if signs.iter().any(|s| s.abs() < 0.05) {
        return None;
    }
    Some(signs.iter().all(|&s| s > 0.0) || signs.iter().all(|&s| s < 0.0))
}

#[test]
fn each_pixel_is_the_share_of_its_samples_inside() {
    // Vertices on the 1/256 px grid, so snapping moves nothing.
    let t = [(3.25, 2.5), (71.75, 20.125), (20.5, 60.875)];
    let scene = white(&[t]);
    let camera = pixel_camera(W, H);
    for n in [1, 2, 4, 8, 16] {
        let (c, _) = render_f32(&scene, &camera, &options(n));
        let r = red(&c);
        let mut checked = 0;
        for y in 0..H as usize {
            for x in 0..W as usize {
                let centre = (x as f64 + 0.5, y as f64 + 0.5);
                let hits: Option<Vec<bool>> = positions(n)
                    .iter()
                    .map(|&(dx, dy)| inside(&t, (centre.0 + dx, centre.1 + dy)))
                    .collect();
                let Some(hits) = hits else { continue };
                let want = hits.iter().filter(|&&h| h).count() as f32 / n as f32;
                assert_eq!(r[y * W as usize + x], want, "n={n} pixel ({x}, {y})");
                checked += 1;
            }
        }
        assert!(checked > 4000, "{checked}");
    }
}

#[test]
fn shared_edges_leak_no_background_at_any_sample_count() {
    // A quad split along an irregular diagonal, and a fan of 7 triangles around an interior
    // point: every pixel whose samples are all inside the outline is exactly 1.
    let (a, b, c, d) = ((4.0, 4.0), (76.0, 6.5), (70.25, 60.0), (6.75, 58.0));
    let m = (37.3, 29.9);
    let fan: Vec<_> = [a, (40.0, 3.0), b, c, (38.0, 61.0), d, (3.0, 30.0), a]
        .windows(2)
        .map(|w| [m, w[0], w[1]])
        .collect();
    for tris in [vec![[a, b, c], [a, c, d]], fan] {
        let scene = white(&tris);
        let outline = [a, b, c, d];
        let camera = pixel_camera(W, H);
        for n in [2, 4, 8, 16] {
            let (col, _) = render_f32(&scene, &camera, &options(n));
            let r = red(&col);
            let mut interior = 0;
            for y in 0..H as usize {
                for x in 0..W as usize {
                    // Inside the convex outline with a margin of one pixel.
                    let p = (x as f64 + 0.5, y as f64 + 0.5);
                    let deep = (0..4).all(|k| {
                        let (u, v) = (outline[k], outline[(k + 1) % 4]);
                        let e = DVec2::new(v.0 - u.0, v.1 - u.1);
                        let cross = e.x * (p.1 - u.1) - e.y * (p.0 - u.0);
                        cross / e.length() > 1.0
                    });
                    if deep {
                        assert_eq!(r[y * W as usize + x], 1.0, "n={n} ({x}, {y})");
                        interior += 1;
                    }
                }
            }
            assert!(interior > 3000);
        }
    }
}

/// One large lit triangle seen in perspective, with a point light (colour varies per pixel).
fn lit_triangle() -> (Scene, Camera) {
    let p = vec![
        Vec3::new(-3.0, -2.0, -4.0),
        Vec3::new(3.0, -1.5, -5.0),
        Vec3::new(0.2, 2.5, -4.5),
    ];
    let mesh = Mesh::new(p, vec![[0, 1, 2]], None, None).unwrap();
    let mut scene = Scene::new(Vec3::splat(0.1)).unwrap();
    scene
        .add(
            Arc::new(mesh),
            Material::preset("gold").unwrap(),
            Mat4::IDENTITY,
        )
        .unwrap();
    scene.add_light(PointLight::new(Vec3::new(0.5, 0.3, -2.0), Vec3::ONE, 1.0).unwrap());
    let camera = Camera::look_at(DVec3::ZERO, -DVec3::Z, DVec3::Y, 60.0, 0.1, 50.0).unwrap();
    (scene, camera)
}

#[test]
fn pixels_inside_one_triangle_equal_the_single_sample_render() {
    let (scene, camera) = lit_triangle();
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        let mut one = options(1);
        one.shading = mode;
        let (c1, d1) = render_f32(&scene, &camera, &one);
        for n in [2, 4, 8, 16] {
            let mut o = one.clone();
            o.samples = n;
            let (cn, dn) = render_f32(&scene, &camera, &o);
            let mut same = 0;
            for y in 1..H as usize - 1 {
                for x in 1..W as usize - 1 {
                    // Interior: the pixel and its 8 neighbours covered with one sample.
                    let all = (0..9)
                        .all(|k| d1[(y + k / 3 - 1) * W as usize + x + k % 3 - 1].is_finite());
                    let i = y * W as usize + x;
                    if all {
                        assert_eq!(cn[i * 3..i * 3 + 3], c1[i * 3..i * 3 + 3], "{mode:?} n={n}");
                        let rel = ((dn[i] - d1[i]) / d1[i]).abs();
                        assert!(rel < 1e-6, "{mode:?} n={n} depth {} vs {}", dn[i], d1[i]);
                        same += 1;
                    }
                    // The depth output is the majority surface's: finite exactly where more
                    // than half the samples are covered (a tie keeps the earlier sample's).
                }
            }
            assert!(same > 1000, "{same}");
        }
    }
}

fn sphere_scene() -> (Scene, Camera) {
    let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
    scene
        .add(
            Arc::new(primitives::uv_sphere(12, 24)),
            Material::preset("gold").unwrap(),
            Mat4::IDENTITY,
        )
        .unwrap();
    scene.add_light(DirectionalLight::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE, 1.0).unwrap());
    scene.set_fog(Some(
        Fog::new(
            FogMode::Linear {
                start: 2.0,
                end: 5.0,
            },
            Vec3::splat(0.5),
        )
        .unwrap(),
    ));
    let camera = Camera::look_at(
        DVec3::new(0.3, 0.4, 3.0),
        DVec3::ZERO,
        DVec3::Y,
        50.0,
        0.1,
        20.0,
    )
    .unwrap();
    (scene, camera)
}

#[test]
fn identical_for_any_thread_count_and_instruction_set() {
    let (scene, camera) = sphere_scene();
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        for n in [2, 4, 16] {
            let mut o = RenderOptions::new(150, 130);
            o.shading = mode;
            o.samples = n;
            o.threads = Some(1);
            let base = render(&scene, &camera, &o, ColorFormat::U8, true).unwrap();
            for (threads, baseline) in [(2, false), (1, true), (2, true)] {
                let mut p = o.clone();
                p.threads = Some(threads);
                p.baseline_isa = baseline;
                let f = render(&scene, &camera, &p, ColorFormat::U8, true).unwrap();
                assert_eq!(f.color, base.color, "{mode:?} n={n} {threads} {baseline}");
                let same_depth = f
                    .depth
                    .iter()
                    .flatten()
                    .zip(base.depth.iter().flatten())
                    .all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same_depth);
            }
        }
    }
}

/// Exact area of the unit pixel square at (x, y) inside triangle `t` (Sutherland–Hodgman
/// clipping in f64).
fn exact_coverage(t: &[(f64, f64); 3], x: f64, y: f64) -> f64 {
    let mut poly = vec![(x, y), (x + 1.0, y), (x + 1.0, y + 1.0), (x, y + 1.0)];
    // Orient the triangle so the inside is on the left of each edge (positive cross).
    let area = (t[1].0 - t[0].0) * (t[2].1 - t[0].1) - (t[1].1 - t[0].1) * (t[2].0 - t[0].0);
    let t = if area > 0.0 { *t } else { [t[0], t[2], t[1]] };
    for k in 0..3 {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let side = |p: (f64, f64)| (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
        let mut out = Vec::new();
        for i in 0..poly.len() {
            let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let s = sp / (sp - sq);
                out.push((p.0 + s * (q.0 - p.0), p.1 + s * (q.1 - p.1)));
            }
        }
        poly = out;
        if poly.is_empty() {
            return 0.0;
        }
    }
    let mut a = 0.0;
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        a += p.0 * q.1 - q.0 * p.1;
    }
    a.abs() / 2.0
}

#[test]
fn edge_error_against_exact_coverage_falls_as_samples_grow() {
    // A fan of thin and wide triangles with edges at many angles (disjoint, so each pixel's
    // exact coverage is the sum over triangles).
    let c = (40.0, 32.0);
    let rim: Vec<(f64, f64)> = (0..13)
        .map(|k| {
            let a = k as f64 * 0.4537 + 0.1;
            let r = if k % 2 == 0 { 29.0 } else { 23.5 };
            (c.0 + r * a.cos(), c.1 + r * a.sin())
        })
        .collect();
    let tris: Vec<[(f64, f64); 3]> = rim.windows(2).map(|w| [c, w[0], w[1]]).collect();
    let scene = white(&tris);
    let camera = pixel_camera(W, H);
    let mut exact = vec![0.0; (W * H) as usize];
    for (i, e) in exact.iter_mut().enumerate() {
        let (x, y) = ((i % W as usize) as f64, (i / W as usize) as f64);
        *e = tris.iter().map(|t| exact_coverage(t, x, y)).sum::<f64>();
    }
    let edge: Vec<usize> = (0..exact.len())
        .filter(|&i| exact[i] > 1e-9 && exact[i] < 1.0 - 1e-9)
        .collect();
    assert!(edge.len() > 200, "{}", edge.len());
    let rmse = |o: &RenderOptions| {
        let (col, _) = render_f32(&scene, &camera, o);
        let r = red(&col);
        let s: f64 = edge.iter().map(|&i| (r[i] as f64 - exact[i]).powi(2)).sum();
        (s / edge.len() as f64).sqrt()
    };
    let errors: Vec<f64> = [1, 2, 4, 8, 16].map(|n| rmse(&options(n))).to_vec();
    eprintln!(
        "edge pixels {}, RMSE for 1..16 samples {errors:?}",
        edge.len()
    );
    for w in errors.windows(2) {
        assert!(w[1] < w[0], "{errors:?}");
    }
    // With 16 well-spread samples the coverage error is a few percent of the contrast.
    assert!(errors[4] < 0.06, "{errors:?}");
    let mut ss = options(1);
    ss.supersample = 4;
    let e_ss = rmse(&ss);
    assert!(e_ss < errors[1], "supersample 4x4: {e_ss} vs {errors:?}");
}

#[test]
fn supersample_is_the_box_filter_of_the_larger_render() {
    let (scene, camera) = sphere_scene();
    for k in [2u32, 3] {
        let mut o = RenderOptions::new(50, 40);
        o.supersample = k;
        let (c, d) = render_f32(&scene, &camera, &o);
        let big = RenderOptions::new(50 * k, 40 * k);
        let (cb, db) = render_f32(&scene, &camera, &big);
        let bw = 50 * k as usize;
        for y in 0..40usize {
            for x in 0..50usize {
                let mut sum = [0.0f32; 3];
                let mut near = f32::INFINITY;
                for sy in 0..k as usize {
                    for sx in 0..k as usize {
                        let i = (y * k as usize + sy) * bw + x * k as usize + sx;
                        for ch in 0..3 {
                            sum[ch] += cb[i * 3 + ch];
                        }
                        near = near.min(db[i]);
                    }
                }
                let i = y * 50 + x;
                for ch in 0..3 {
                    assert_eq!(c[i * 3 + ch], sum[ch] / (k * k) as f32, "k={k} ({x}, {y})");
                }
                assert_eq!(d[i].to_bits(), near.to_bits());
            }
        }
        // u8 output is the quantised mean.
        let f = render(&scene, &camera, &o, ColorFormat::U8, false).unwrap();
        let ColorBuffer::U8(u) = f.color else {
            panic!()
        };
        for (q, v) in u.iter().zip(&c) {
            assert_eq!(*q, (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8);
        }
    }
}

#[test]
fn bad_sample_settings_are_errors_naming_the_field() {
    let (scene, camera) = sphere_scene();
    type Set = Box<dyn Fn(&mut RenderOptions)>;
    let cases: [(&str, Set); 5] = [
        ("samples", Box::new(|o| o.samples = 3)),
        ("samples", Box::new(|o| o.samples = 0)),
        ("supersample", Box::new(|o| o.supersample = 0)),
        ("supersample", Box::new(|o| o.supersample = 9)),
        (
            "supersample",
            Box::new(|o| {
                o.width = 4000;
                o.supersample = 5;
            }),
        ),
    ];
    for (field, set) in cases {
        let mut o = RenderOptions::new(20, 20);
        set(&mut o);
        let e = render(&scene, &camera, &o, ColorFormat::U8, false).unwrap_err();
        assert_eq!(e.field(), Some(field), "{e}");
    }
}

#[test]
fn coverage_output_is_the_share_of_covered_samples() {
    // White over black: the colour is the coverage, so the two outputs must agree exactly;
    // with one sample the coverage is where the depth is finite.
    let t = [(3.25, 2.5), (71.75, 20.125), (20.5, 60.875)];
    let scene = white(&[t]);
    let camera = pixel_camera(W, H);
    let outputs = Outputs {
        depth: true,
        coverage: true,
    };
    for (n, k) in [(1, 1), (2, 1), (4, 1), (16, 1), (1, 2), (4, 3)] {
        let mut o = options(n);
        o.supersample = k;
        let f = render_with(&scene, &camera, &o, ColorFormat::F32, outputs).unwrap();
        let ColorBuffer::F32(c) = &f.color else {
            unreachable!()
        };
        let cov = f.coverage.as_ref().unwrap();
        assert_eq!(&red(c), cov, "n={n} k={k}");
        let partial = cov.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
        assert_eq!(
            partial > 0,
            n * k > 1,
            "n={n} k={k}: {partial} partial pixels"
        );
        if n * k == 1 {
            for (v, d) in cov.iter().zip(f.depth.as_ref().unwrap()) {
                assert_eq!(*v == 1.0, d.is_finite());
            }
        }
    }
}
