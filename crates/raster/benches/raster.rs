//! Criterion benchmarks of the core renderer, Rust only (no Python, no output allocation:
//! frames are rendered with `render_into` into a reused buffer).
//!
//! - `sphere`: UV spheres of 9,800 and 99,224 triangles filling 95 % of the height of a
//!   1920×1080 frame, flat and Phong shading, 1 and 2 threads. Throughput is in covered
//!   pixels, so `elem/s` reads as shaded pixels per second.
//! - `fill`: MOC-style fill rate. Randomly placed and rotated right triangles with legs of 4,
//!   16, 64 and 256 pixels, facing an orthographic camera at random depths, flat shading, 1 and
//!   2 threads. Throughput is in triangles, so `elem/s` reads as triangles per second.
//!
//! Kept short on purpose (10 samples, about 2 s of measurement each, about a minute in all):
//!
//! ```sh
//! cargo bench -p shadelab-raster --bench raster             # everything
//! cargo bench -p shadelab-raster --bench raster -- fill     # one group
//! cargo bench -p shadelab-raster --bench raster -- --quick  # faster, rougher
//! ```
//!
//! The frame-time report with per-stage times is `make bench` (bench/bench_render.py).

// `criterion_group!` defines an undocumented public function.
#![allow(missing_docs)]

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use criterion::{
    criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode, Throughput,
};
use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::{
    primitives, render, render_into, Camera, ColorFormat, DirectionalLight, Material, Mesh,
    PointLight, RenderOptions, Scene, ShadingMode,
};

const WIDTH: u32 = 1920;
const HEIGHT: u32 = 1080;
const FOV_Y: f64 = 45.0;
/// The sphere's silhouette spans this fraction of the frame height (as in bench_render.py).
const SPHERE_FILL: f64 = 0.95;
const THREADS: [usize; 2] = [1, 2];

fn lit_scene(mesh: Mesh) -> Scene {
    let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
    scene
        .add(
            Arc::new(mesh),
            Material::preset("gold").unwrap(),
            Mat4::IDENTITY,
        )
        .unwrap();
    scene.add_light(DirectionalLight::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE, 1.0).unwrap());
    scene.add_light(
        PointLight::new(Vec3::new(2.0, 3.0, 4.0), Vec3::new(0.4, 0.4, 0.5), 1.0).unwrap(),
    );
    scene
}

fn sphere_camera() -> Camera {
    let half = (FOV_Y / 2.0).to_radians();
    let alpha = (SPHERE_FILL * half.tan()).atan();
    let dist = 1.0 / alpha.sin();
    Camera::look_at(
        DVec3::new(0.0, 0.0, dist),
        DVec3::ZERO,
        DVec3::Y,
        FOV_Y,
        0.1,
        dist + 10.0,
    )
    .unwrap()
}

fn options(shading: ShadingMode, threads: usize) -> RenderOptions {
    let mut o = RenderOptions::new(WIDTH, HEIGHT);
    o.shading = shading;
    o.threads = Some(threads);
    o
}

/// Pixels some triangle is visible in (finite depth).
fn covered_pixels(scene: &Scene, camera: &Camera) -> u64 {
    let frame = render(
        scene,
        camera,
        &options(ShadingMode::Flat, 2),
        ColorFormat::U8,
        true,
    )
    .unwrap();
    let depth = frame.depth.unwrap();
    depth.iter().filter(|d| d.is_finite()).count() as u64
}

fn bench_frame(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: BenchmarkId,
    scene: &Scene,
    camera: &Camera,
    opts: &RenderOptions,
) {
    let mut color = vec![0u8; opts.pixel_count() * 3];
    group.bench_function(id, |b| {
        b.iter(|| {
            let stats = render_into(scene, camera, opts, &mut color, None).unwrap();
            black_box(stats)
        })
    });
}

fn sphere(c: &mut Criterion) {
    let camera = sphere_camera();
    let mut group = c.benchmark_group("sphere");
    group.sampling_mode(SamplingMode::Flat);
    // (rings, segments): 2·segments·(rings − 1) triangles.
    for (label, rings, segments) in [("10k", 50, 100), ("100k", 158, 316)] {
        let scene = lit_scene(primitives::uv_sphere(rings, segments));
        group.throughput(Throughput::Elements(covered_pixels(&scene, &camera)));
        for (mode_name, mode) in [("flat", ShadingMode::Flat), ("phong", ShadingMode::Phong)] {
            for threads in THREADS {
                let id = BenchmarkId::new(format!("{label}/{mode_name}"), format!("{threads}t"));
                bench_frame(&mut group, id, &scene, &camera, &options(mode, threads));
            }
        }
    }
    group.finish();
}

/// xorshift64*: a fixed, dependency-free stream of numbers in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// `count` right triangles with legs of `size` pixels, randomly placed inside the frame and
/// rotated, counter-clockwise towards +z, at depths in [−5, 5]. World units are pixels under
/// [`fill_camera`].
fn random_triangles(count: usize, size: f32, seed: u64) -> Mesh {
    let mut rng = Rng(seed);
    let (hw, hh) = (WIDTH as f32 / 2.0, HEIGHT as f32 / 2.0);
    let mut positions = Vec::with_capacity(count * 3);
    for _ in 0..count {
        let centre = Vec3::new(
            (rng.next() * 2.0 - 1.0) * (hw - size),
            (rng.next() * 2.0 - 1.0) * (hh - size),
            rng.next() * 10.0 - 5.0,
        );
        let a = rng.next() * std::f32::consts::TAU;
        let (u, v) = (
            Vec3::new(a.cos(), a.sin(), 0.0) * size,
            Vec3::new(-a.sin(), a.cos(), 0.0) * size,
        );
        let p0 = centre - (u + v) / 3.0;
        positions.extend([p0, p0 + u, p0 + v]);
    }
    let indices = (0..count as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let normals = vec![Vec3::Z; positions.len()];
    Mesh::new(positions, indices, Some(normals), None).unwrap()
}

/// Orthographic camera on +z with one world unit per pixel.
fn fill_camera() -> Camera {
    Camera::orthographic(
        DVec3::new(0.0, 0.0, 10.0),
        DVec3::ZERO,
        DVec3::Y,
        HEIGHT as f64,
        0.1,
        100.0,
    )
    .unwrap()
}

fn fill(c: &mut Criterion) {
    let camera = fill_camera();
    let frame_px = (WIDTH * HEIGHT) as f32;
    let mut group = c.benchmark_group("fill");
    group.sampling_mode(SamplingMode::Flat);
    for size in [4u32, 16, 64, 256] {
        let area = (size * size) as f32 / 2.0;
        // About 4 frames' worth of coverage, at most 200k triangles.
        let count = ((4.0 * frame_px / area) as usize).min(200_000);
        let scene = lit_scene(random_triangles(count, size as f32, 0x5EED ^ size as u64));
        group.throughput(Throughput::Elements(count as u64));
        for threads in THREADS {
            let id = BenchmarkId::new(format!("{size}px"), format!("{threads}t"));
            bench_frame(
                &mut group,
                id,
                &scene,
                &camera,
                &options(ShadingMode::Flat, threads),
            );
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = sphere, fill
}
criterion_main!(benches);
