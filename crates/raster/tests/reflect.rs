//! Reflection, refraction and transparency from Rust: the fuzz body reaches the secondary
//! stage (every committed pipeline seed with an optics block appended at each possible
//! offset, so one of them lands on the block), and a mirror corridor stops at `max_depth`.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::*;

fn seeds() -> Vec<Vec<u8>> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/pipeline");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

/// Seeds with zero padding (which decodes as "no extension") then an optics block of
/// pseudo-random bytes: whatever lands where, no panic, and the renders' invariants hold
/// (`fuzzing::check_render`: finite colours, thread and instruction-set invariance, u8 =
/// rounded f32).
#[test]
fn fuzz_body_reaches_the_secondary_stage() {
    let mut seed = 0x2545_f491u32;
    let mut rendered = 0;
    for base in seeds().iter().filter(|s| s.len() < 400) {
        for pad in (0..48).step_by(3) {
            let mut data = base.clone();
            data.extend(std::iter::repeat(0).take(pad));
            data.push(0x23 | ((pad as u8 & 1) << 6));
            for _ in 0..64 {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                data.push((seed >> 24) as u8);
            }
            rendered += fuzzing::pipeline(&data) as usize;
        }
    }
    assert!(rendered > 20, "only {rendered} inputs rendered");
}

fn quad(y: f32, up: bool) -> Mesh {
    let p = vec![
        Vec3::new(-50.0, y, -50.0),
        Vec3::new(-50.0, y, 50.0),
        Vec3::new(50.0, y, 50.0),
        Vec3::new(50.0, y, -50.0),
    ];
    let idx = if up {
        vec![[0, 1, 2], [0, 2, 3]]
    } else {
        vec![[0, 2, 1], [0, 3, 2]]
    };
    Mesh::new(p, idx, None, None).unwrap()
}

#[test]
fn parallel_mirrors_stop_at_max_depth_and_depth_zero_is_the_environment() {
    let mut scene = Scene::new(Vec3::splat(0.1)).unwrap();
    let sky: Vec<f32> = (0..8 * 16)
        .flat_map(|k| [k as f32 / 128.0, 0.5, 1.0])
        .collect();
    scene.set_environment(Some(Environment::new(&sky, 8, 16, 0.0, 1.0).unwrap()));
    let mirror = Material::new(Vec3::ZERO, Vec3::splat(0.2), Vec3::ZERO, 1.0)
        .unwrap()
        .with_optics(Vec3::splat(0.9), 0.0, 1.0, true, Vec3::ZERO)
        .unwrap();
    scene
        .add(Arc::new(quad(0.0, true)), mirror, Mat4::IDENTITY)
        .unwrap();
    scene
        .add(Arc::new(quad(1.0, false)), mirror, Mat4::IDENTITY)
        .unwrap();
    let cam = Camera::look_at(
        DVec3::new(0.0, 0.5, 0.0),
        DVec3::new(1.0, 0.4, 0.0),
        DVec3::Y,
        60.0,
        0.01,
        1000.0,
    )
    .unwrap();
    let render_with = |tech: Technique, depth: u32| {
        let mut o = RenderOptions::new(24, 24);
        o.reflections = tech;
        o.max_depth = depth;
        match render(&scene, &cam, &o, ColorFormat::F32, false)
            .unwrap()
            .color
        {
            ColorBuffer::F32(c) => c,
            _ => unreachable!(),
        }
    };
    let env = render_with(Technique::Environment, 5);
    assert_eq!(render_with(Technique::Ray, 0), env);
    let deep = render_with(Technique::Ray, MAX_TRACE_DEPTH);
    assert!(deep.iter().all(|v| v.is_finite()));
    assert_ne!(
        render_with(Technique::Ray, 1),
        render_with(Technique::Ray, 2)
    );
    let mut bad = RenderOptions::new(8, 8);
    bad.max_depth = MAX_TRACE_DEPTH + 1;
    assert!(matches!(
        render(&scene, &cam, &bad, ColorFormat::U8, false),
        Err(RasterError::InvalidField {
            field: "max_depth",
            ..
        })
    ));
}
