//! Lines (`RenderOptions::edges`): which edges are drawn, line coverage, determinism.

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

fn red_pixels(scene: &Scene, mode: EdgeMode, samples: u32) -> usize {
    let mut o = RenderOptions::new(160, 120);
    o.edges = mode;
    o.edge_color = Vec3::new(1.0, 0.0, 0.0);
    o.samples = samples;
    let f = render(scene, &camera(), &o, ColorFormat::F32, false).unwrap();
    let ColorBuffer::F32(c) = f.color else {
        panic!()
    };
    for x in 85..95 {
        let i = (80 * 160 + x) * 3;
        eprint!("{:?} ", &c[i..i + 3]);
    }
    eprintln!();
    let mut ppm = format!("P3 160 120 255\n");
    for v in &c {
        ppm += &format!("{} ", (v.clamp(0.0, 1.0) * 255.0) as u8);
    }
    std::fs::write(format!("/tmp/edges/{mode:?}.ppm"), ppm).unwrap();
    c.chunks_exact(3)
        .filter(|p| p[0] > 0.0 && p[1] == 0.0 && p[2] == 0.0)
        .count()
}

#[test]
fn debug_counts() {
    let s = cube_scene();
    for m in [EdgeMode::All, EdgeMode::Visible, EdgeMode::Features] {
        eprintln!("{m:?} {}", red_pixels(&s, m, 1));
    }
}
