//! Renders started together from several threads run in parallel, each on its own pool.

use std::sync::Arc;
use std::time::Duration;

use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::*;

#[test]
fn two_single_thread_renders_are_in_flight_together() {
    let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
    scene
        .add(
            Arc::new(primitives::uv_sphere(8, 16)),
            Material::default(),
            Mat4::IDENTITY,
        )
        .unwrap();
    let camera = Camera::look_at(
        DVec3::new(0.0, 0.0, 3.0),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        0.1,
        10.0,
    )
    .unwrap();
    let mut options = RenderOptions::new(32, 24);
    options.threads = Some(1);
    // Each render waits on its worker until the other one is there too; with one shared
    // single-worker pool the second could not start until the first ended (the wait then
    // times out and the high-water mark stays at 1).
    set_rendezvous(2, Duration::from_secs(30));
    let barrier = std::sync::Barrier::new(2);
    let frames: Vec<Frame> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..2)
            .map(|_| {
                s.spawn(|| {
                    barrier.wait();
                    render(&scene, &camera, &options, ColorFormat::U8, false).unwrap()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let seen = max_in_flight();
    set_rendezvous(0, Duration::ZERO);
    assert_eq!(seen, 2);
    assert_eq!(frames[0].color, frames[1].color);
}
