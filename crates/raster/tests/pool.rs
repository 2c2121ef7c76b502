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

#[cfg(target_os = "linux")]
#[test]
fn a_pool_of_every_cpu_binds_each_worker_to_its_own() {
    // The CPUs this process may use (the test harness does not bind its threads).
    let allowed = worker_cpus(Some(1)).unwrap().remove(0);
    assert!(!allowed.is_empty());
    // A single worker is left to the OS.
    assert_eq!(worker_cpus(Some(1)).unwrap(), vec![allowed.clone()]);
    // Fewer or more workers than CPUs: left to the OS (processes sharing the machine
    // would otherwise bind theirs to the same first CPUs).
    for n in [allowed.len() - 1, allowed.len() + 1] {
        if n >= 2 {
            let cpus = worker_cpus(Some(n)).unwrap();
            assert!(cpus.iter().all(|c| *c == allowed), "{n}: {cpus:?}");
        }
    }
    if allowed.len() < 2 || std::env::var(PIN_THREADS_ENV).is_ok_and(|v| v.trim() == "0") {
        return;
    }
    // Every CPU, as `threads=None` asks: worker i on the i-th CPU.
    let cpus = worker_cpus(None).unwrap();
    let expected: Vec<Vec<usize>> = allowed.iter().map(|&c| vec![c]).collect();
    assert_eq!(cpus, expected);
    assert_eq!(worker_cpus(Some(allowed.len())).unwrap(), expected);
}
