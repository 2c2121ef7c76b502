//! Renders a gold sphere in each shading mode to `sphere_<mode>.png` (Rust-only usage).
//!
//! `cargo run --release --example sphere`

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::*;

fn main() -> std::result::Result<(), Box<dyn std::error::Error>> {
    let mut scene = Scene::new(Vec3::splat(0.2))?;
    scene.add(
        Arc::new(primitives::uv_sphere(12, 24)),
        Material::preset("gold")?,
        Mat4::IDENTITY,
    )?;
    scene.add_light(DirectionalLight::new(
        Vec3::new(-1.0, -1.0, -1.0),
        Vec3::ONE,
        1.0,
    )?);
    scene.add_light(PointLight::new(
        Vec3::new(2.0, 3.0, 4.0),
        Vec3::new(0.4, 0.4, 0.5),
        1.0,
    )?);
    let camera = Camera::look_at(
        DVec3::new(0.0, 0.0, 3.0),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        0.1,
        100.0,
    )?;
    for (name, mode) in [
        ("flat", ShadingMode::Flat),
        ("gouraud", ShadingMode::Gouraud),
        ("phong", ShadingMode::Phong),
    ] {
        let mut options = RenderOptions::new(320, 240);
        options.shading = mode;
        let frame = render(&scene, &camera, &options, ColorFormat::U8, false)?;
        let ColorBuffer::U8(pixels) = frame.color else {
            unreachable!()
        };
        let path = format!("sphere_{name}.png");
        image::save_buffer(
            &path,
            &pixels,
            frame.width,
            frame.height,
            image::ColorType::Rgb8,
        )?;
        println!("{path}: {:?}", frame.stats.timings);
    }
    Ok(())
}
