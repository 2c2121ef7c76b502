//! Shared helpers for the integration tests.
#![allow(dead_code)]

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::*;

/// An orthographic camera that maps world (x, y) to screen (x, height − y): one world unit is
/// one pixel, so screen-space test cases can be written in world coordinates.
pub fn pixel_camera(width: u32, height: u32) -> Camera {
    let c = DVec3::new(width as f64 / 2.0, height as f64 / 2.0, 0.0);
    Camera::orthographic(c + DVec3::Z * 10.0, c, DVec3::Y, height as f64, 1.0, 100.0).unwrap()
}

/// Converts screen coordinates (y down) to the world coordinates of [`pixel_camera`].
pub fn screen(height: u32, x: f32, y: f32) -> Vec3 {
    Vec3::new(x, height as f32 - y, 0.0)
}

/// A scene of one unlit-white mesh (ambient 1, kd = ks = 0): every covered pixel is 1.0.
pub fn white_scene(mesh: Mesh) -> Scene {
    let mut scene = Scene::new(Vec3::ONE).unwrap();
    let m = Material::new(Vec3::ONE, Vec3::ZERO, Vec3::ZERO, 1.0).unwrap();
    scene.add(Arc::new(mesh), m, Mat4::IDENTITY).unwrap();
    scene
}

/// Coverage counts for a single mesh through `camera`.
pub fn counts(mesh: Mesh, camera: &Camera, width: u32, height: u32) -> Vec<u32> {
    let scene = white_scene(mesh);
    coverage_counts(&scene, camera, &RenderOptions::new(width, height)).unwrap()
}

/// Renders to float32, returning colour and depth.
pub fn render_f32(scene: &Scene, camera: &Camera, options: &RenderOptions) -> (Vec<f32>, Vec<f32>) {
    let f = render(scene, camera, options, ColorFormat::F32, true).unwrap();
    let ColorBuffer::F32(c) = f.color else {
        unreachable!()
    };
    (c, f.depth.unwrap())
}

/// A tiny deterministic PRNG (xorshift64*), so tests need no extra dependency.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545F4914F6CDD1D)
    }

    /// Uniform in [0, 1).
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
}
