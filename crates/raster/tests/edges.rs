//! Lines (`RenderOptions::edges`): the modes draw nested sets, the image is identical for
//! any thread count and instruction set, and the rest of the image is the render without
//! lines. (Accuracy against the float64 reference: tests/test_edges.py.)

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::*;

fn cube_scene() -> Scene {
    let mut s = Scene::new(Vec3::splat(0.3)).unwrap();
    s.add(
        Arc::new(primitives::cube()),
        Material::default(),
        Mat4::IDENTITY,
    )
    .unwrap();
    s.add(
        Arc::new(primitives::uv_sphere(12, 24)),
        Material::default(),
        Mat4::from_translation(Vec3::new(0.8, 0.9, 0.6)) * Mat4::from_scale(Vec3::splat(0.7)),
    )
    .unwrap();
    s.add_light(DirectionalLight::new(Vec3::new(-1.0, -2.0, -1.5), Vec3::ONE, 1.0).unwrap());
    s
}

fn camera() -> Camera {
    Camera::look_at(
        DVec3::new(2.2, 1.7, 3.0),
        DVec3::ZERO,
        DVec3::Y,
        50.0,
        0.1,
        100.0,
    )
    .unwrap()
}

fn render_f32(mode: EdgeMode, samples: u32, tweak: impl Fn(&mut RenderOptions)) -> Vec<f32> {
    let mut o = RenderOptions::new(157, 121);
    o.edges = mode;
    o.edge_color = Vec3::new(1.0, 0.0, 0.0);
    o.samples = samples;
    tweak(&mut o);
    let f = render(&cube_scene(), &camera(), &o, ColorFormat::F32, false).unwrap();
    match f.color {
        ColorBuffer::F32(c) => c,
        ColorBuffer::U8(_) => unreachable!(),
    }
}

/// Pixels whose colour differs from the render without lines.
fn inked(mode: EdgeMode, samples: u32) -> Vec<bool> {
    let plain = render_f32(EdgeMode::None, samples, |_| {});
    let lined = render_f32(mode, samples, |_| {});
    plain
        .chunks_exact(3)
        .zip(lined.chunks_exact(3))
        .map(|(a, b)| a != b)
        .collect()
}

#[test]
fn features_within_visible_within_all() {
    for samples in [1, 4] {
        let all = inked(EdgeMode::All, samples);
        let visible = inked(EdgeMode::Visible, samples);
        let features = inked(EdgeMode::Features, samples);
        let count = |v: &[bool]| v.iter().filter(|&&b| b).count();
        assert!(count(&features) > 100, "{samples}");
        assert!(count(&features) < count(&visible), "{samples}");
        assert!(count(&visible) < count(&all), "{samples}");
        for k in 0..all.len() {
            assert!(!visible[k] || all[k], "pixel {k}");
            assert!(!features[k] || visible[k], "pixel {k}");
        }
    }
}

#[test]
fn lines_are_identical_for_any_thread_count_and_instruction_set() {
    for mode in [EdgeMode::All, EdgeMode::Visible, EdgeMode::Features] {
        for samples in [1, 8] {
            let base = render_f32(mode, samples, |o| o.threads = Some(1));
            for t in [2, 3] {
                assert_eq!(base, render_f32(mode, samples, |o| o.threads = Some(t)));
            }
            assert_eq!(base, render_f32(mode, samples, |o| o.baseline_isa = true));
        }
    }
}

#[test]
fn lines_alone_keep_the_background_elsewhere() {
    let c = render_f32(EdgeMode::Visible, 4, |o| {
        o.edges_only = true;
        o.background = Vec3::ONE;
    });
    let mut partial = 0;
    for px in c.chunks_exact(3) {
        // White, red, or a blend of the two (anti-aliased): never a shaded surface.
        assert_eq!(px[0], 1.0);
        assert_eq!(px[1], px[2]);
        if px[1] > 0.0 && px[1] < 1.0 {
            partial += 1;
        }
    }
    assert!(partial > 50);
}

#[test]
fn bad_line_options_name_the_field() {
    let mut o = RenderOptions::new(8, 8);
    o.edges = EdgeMode::All;
    for (set, field) in [
        (
            (|o: &mut RenderOptions| o.edge_width = f32::NAN) as fn(&mut RenderOptions),
            "edge_width",
        ),
        (|o| o.edge_width = -1.0, "edge_width"),
        (|o| o.edge_color = Vec3::new(0.0, -1.0, 0.0), "edge_color"),
        (
            |o| o.edge_color = Vec3::new(f32::NAN, 0.0, 0.0),
            "edge_color",
        ),
        (|o| o.edge_angle = 200.0, "edge_angle"),
        (
            |o| {
                o.edges = EdgeMode::None;
                o.edges_only = true
            },
            "edges_only",
        ),
    ] {
        let mut bad = o.clone();
        set(&mut bad);
        let e = bad.validate().unwrap_err();
        assert!(e.to_string().contains(field), "{e}");
    }
}
