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
    let (mut rendered, mut multi_optics) = (0, 0);
    for base in seeds().iter().filter(|s| s.len() < 400) {
        for pad in (0..48).step_by(3) {
            let mut data = base.clone();
            data.extend(std::iter::repeat(0).take(pad));
            data.push(0x23 | ((pad as u8 & 1) << 6));
            for _ in 0..64 {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                data.push((seed >> 24) as u8);
            }
            let ok = fuzzing::pipeline(&data);
            rendered += ok as usize;
            // The byte after the optics block picks the sample count: MSAA is reached too.
            let desc = fuzzing::describe_pipeline_input(&data).unwrap_or_default();
            let some =
                |key: &str, zero: &str| desc.matches(key).count() > desc.matches(zero).count();
            let optical = some("reflectivity: ", "reflectivity: Vec3(0.0, 0.0, 0.0)")
                || some("transparency: ", "transparency: 0.0,");
            multi_optics += (ok && optical && !desc.contains("samples: 1,")) as usize;
        }
    }
    assert!(rendered > 20, "only {rendered} inputs rendered");
    assert!(
        multi_optics > 5,
        "only {multi_optics} with samples > 1 and optics"
    );
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

/// A mirror floor, a reflective sphere and a transparent one (index 1.5; blended unless the
/// options refract) over the environment, with fog.
fn optics_scene() -> (Scene, Camera) {
    let mut scene = Scene::new(Vec3::splat(0.1)).unwrap();
    let sky: Vec<f32> = (0..8 * 16)
        .flat_map(|k| [k as f32 / 128.0, 0.5, 1.0 - k as f32 / 256.0])
        .collect();
    scene.set_environment(Some(Environment::new(&sky, 8, 16, 0.0, 1.0).unwrap()));
    let optic = |refl: f32, transp: f32, ior: f32| {
        Material::new(
            Vec3::splat(0.1),
            Vec3::new(0.6, 0.3, 0.2),
            Vec3::splat(0.4),
            20.0,
        )
        .unwrap()
        .with_optics(Vec3::splat(refl), transp, ior, true, Vec3::ZERO)
        .unwrap()
    };
    let sphere = Arc::new(primitives::uv_sphere(10, 20));
    let at = |s: f32, x: f32, y: f32, z: f32| {
        Mat4::from_translation(Vec3::new(x, y, z)) * Mat4::from_scale(Vec3::splat(s))
    };
    scene
        .add(
            Arc::new(quad(0.0, true)),
            optic(0.6, 0.0, 1.0),
            Mat4::IDENTITY,
        )
        .unwrap();
    scene
        .add(
            sphere.clone(),
            optic(0.5, 0.0, 1.0),
            at(0.5, -0.4, 0.5, 0.0),
        )
        .unwrap();
    scene
        .add(sphere, optic(0.1, 0.6, 1.5), at(0.4, 0.5, 0.4, 0.6))
        .unwrap();
    scene.add_light(DirectionalLight::new(Vec3::new(-1.0, -2.0, -1.0), Vec3::ONE, 1.0).unwrap());
    scene.set_fog(Some(
        Fog::new(
            FogMode::Linear {
                start: 2.0,
                end: 8.0,
            },
            Vec3::splat(0.5),
        )
        .unwrap(),
    ));
    let cam = Camera::look_at(
        DVec3::new(0.2, 1.2, 3.0),
        DVec3::new(0.0, 0.3, 0.0),
        DVec3::Y,
        50.0,
        0.05,
        100.0,
    )
    .unwrap();
    (scene, cam)
}

/// Renders `o` at 1 thread, checks that 2 and 3 threads and the baseline instruction set
/// give the same colour and depth bits, and returns the 1-thread frame.
fn same_for_any_thread_count_and_isa(scene: &Scene, cam: &Camera, o: &RenderOptions) -> Frame {
    let mut o = o.clone();
    o.threads = Some(1);
    let base = render(scene, cam, &o, ColorFormat::F32, true).unwrap();
    let ColorBuffer::F32(c) = &base.color else {
        unreachable!()
    };
    assert!(c.iter().all(|v| v.is_finite()));
    let bits = |d: &Option<Vec<f32>>| d.iter().flatten().map(|v| v.to_bits()).collect::<Vec<_>>();
    for (threads, baseline) in [(2, false), (1, true), (3, true)] {
        let mut p = o.clone();
        p.threads = Some(threads);
        p.baseline_isa = baseline;
        let f = render(scene, cam, &p, ColorFormat::F32, true).unwrap();
        let what = format!("{:?} n={} {threads} {baseline}", o.shading, o.samples);
        assert_eq!(f.color, base.color, "{what}");
        assert_eq!(bits(&f.depth), bits(&base.depth), "{what}");
    }
    base
}

/// The single-sample body looks bare background pixels up a run of lanes at a time, and
/// the mirrors and (refracting) glass reading the environment eight pixels at a time; the
/// others (behind a transparent fragment, or without the environment background) a pixel
/// at a time: all of them, on both instruction sets and any thread count, give the same
/// bits.
#[test]
fn single_sample_secondary_is_identical_for_any_thread_count_and_instruction_set() {
    let (scene, cam) = optics_scene();
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        for env_background in [true, false] {
            for refractions in [None, Some(Technique::Environment)] {
                let mut o = RenderOptions::new(97, 61);
                o.shading = mode;
                o.environment_background = env_background;
                o.refractions = refractions;
                same_for_any_thread_count_and_isa(&scene, &cam, &o);
            }
        }
    }
}

#[test]
fn multi_sample_secondary_is_identical_for_any_thread_count_and_instruction_set() {
    let (scene, cam) = optics_scene();
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        for n in [2, 4, 16] {
            let mut o = RenderOptions::new(90, 70);
            o.shading = mode;
            o.samples = n;
            o.reflections = Technique::Ray;
            o.environment_background = true;
            let base = same_for_any_thread_count_and_isa(&scene, &cam, &o);
            let ColorBuffer::F32(c) = &base.color else {
                unreachable!()
            };
            // The u8 output is the rounded f32 one.
            let f8 = render(&scene, &cam, &o, ColorFormat::U8, false).unwrap();
            let ColorBuffer::U8(q) = f8.color else {
                unreachable!()
            };
            for (&q, &c) in q.iter().zip(c) {
                assert_eq!(q, (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8);
            }
        }
    }
}

/// The 16 × 32 sky of the bumpy-mirror tests, turned 30° about +y: its colours vary in
/// both directions, so a look-up at the wrong texel shows.
fn test_sky() -> Environment {
    let sky: Vec<f32> = (0..16 * 32)
        .flat_map(|k| {
            let (r, c) = ((k / 32) as f32, (k % 32) as f32);
            [r / 16.0, 0.3 + 0.02 * c, 1.0 - r * c / 512.0]
        })
        .collect();
    Environment::new(&sky, 16, 32, 30.0, 1.0).unwrap()
}

/// The bumpy grid's material: lit, and a tinted mirror.
fn bumpy_mirror() -> Material {
    Material::new(Vec3::splat(0.1), Vec3::splat(0.3), Vec3::splat(0.5), 20.0)
        .unwrap()
        .with_optics(Vec3::new(0.8, 0.6, 0.7), 0.0, 1.0, true, Vec3::ZERO)
        .unwrap()
}

/// The bumpy-mirror scenes' one light.
fn test_sun() -> DirectionalLight {
    DirectionalLight::new(Vec3::new(-0.3, -1.0, -0.2), Vec3::ONE, 1.0).unwrap()
}

/// The bumpy-mirror scenes' fog, when they have one.
fn test_fog() -> Fog {
    Fog::new(FogMode::Exp2 { density: 0.2 }, Vec3::new(0.5, 0.6, 0.7)).unwrap()
}

/// A 2 × 2 mirror grid at y = 0 (facing +y) whose vertex normals lean up to about 14°
/// from +y, pseudo-randomly: interpolated normals vary over every triangle.
fn bumpy_mirror_grid() -> Mesh {
    let n = 12;
    let mut p = Vec::new();
    let mut normals = Vec::new();
    let mut seed = 0x9e37_79b9u32;
    let mut rand = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5
    };
    for j in 0..=n {
        for i in 0..=n {
            p.push(Vec3::new(
                2.0 * i as f32 / n as f32 - 1.0,
                0.0,
                2.0 * j as f32 / n as f32 - 1.0,
            ));
            normals.push(Vec3::new(0.5 * rand(), 1.0, 0.5 * rand()).normalize());
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            idx.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
            idx.push([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
        }
    }
    Mesh::new(p, idx, Some(normals), None).unwrap()
}

/// Mirrors whose reflected rays escape to the sky (a bumpy mirror seen steeply from above,
/// and its back face from below, nothing else in the scene) look the same traced as looked
/// up, bit for bit: the environment technique shades their pixels eight at a time (the
/// point, the split and the look-ups over lanes), the traced one a pixel at a time through
/// `mix`, whose escaping rays read the same sky unattenuated. In every mode, with screen-
/// and perspective-correct interpolation, fog, and two-sided lighting.
#[test]
fn environment_mirrors_match_escaping_rays_bit_for_bit() {
    let mirror = bumpy_mirror();
    let grid = Arc::new(bumpy_mirror_grid());
    let mut checked = 0;
    for (eye, two_sided) in [
        (DVec3::new(0.2, 3.0, 1.2), false),
        (DVec3::new(-0.3, -3.0, 1.0), true),
        (DVec3::new(-0.3, -3.0, 1.0), false),
    ] {
        for fog in [false, true] {
            let mut scene = Scene::new(Vec3::splat(0.1)).unwrap();
            scene.set_environment(Some(test_sky()));
            scene.add(grid.clone(), mirror, Mat4::IDENTITY).unwrap();
            scene.add_light(test_sun());
            scene.set_two_sided(two_sided);
            if fog {
                scene.set_fog(Some(test_fog()));
            }
            let cam = Camera::look_at(eye, DVec3::ZERO, DVec3::Y, 40.0, 0.1, 100.0).unwrap();
            for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
                for interpolation in [Interpolation::Perspective, Interpolation::Screen] {
                    let frame = |tech: Technique| {
                        let mut o = RenderOptions::new(61, 47);
                        o.shading = mode;
                        o.interpolation = interpolation;
                        o.reflections = tech;
                        o.max_depth = 1;
                        match render(&scene, &cam, &o, ColorFormat::F32, false)
                            .unwrap()
                            .color
                        {
                            ColorBuffer::F32(c) => c,
                            _ => unreachable!(),
                        }
                    };
                    let (looked, traced) = (frame(Technique::Environment), frame(Technique::Ray));
                    let what = format!(
                        "eye {eye}, two-sided {two_sided}, fog {fog}, {mode:?}, {interpolation:?}"
                    );
                    // The mirror covers most of the frame, and its colours vary.
                    let background = RenderOptions::new(1, 1).background;
                    let covered = looked
                        .chunks(3)
                        .filter(|c| *c != background.to_array())
                        .count();
                    assert!(covered > 61 * 47 / 2, "{what}: {covered}");
                    let bits = |c: &[f32]| c.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&looked), bits(&traced), "{what}");
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, 36);
}

/// A transparent (blended) ball in front of a mirror changes only the pixels it covers, bit
/// for bit: the secondary stage takes a row's mirror and sky pixels a run of one triangle at
/// a time, cut at each pixel with a fragment over it, and every other pixel must keep the
/// colour it has without the ball (each lane of a batch is computed on its own, so how the
/// runs are cut must not matter). The covered pixels must show the ball. In every mode,
/// with fog and two-sided lighting, the environment as background or not.
#[test]
fn blended_fragments_over_a_mirror_change_only_the_pixels_they_cover() {
    let mirror = bumpy_mirror();
    let ball = Arc::new(primitives::uv_sphere(12, 24));
    let ball_at =
        Mat4::from_translation(Vec3::new(0.1, 1.2, 0.4)) * Mat4::from_scale(Vec3::splat(0.35));
    let tinted = Material::new(
        Vec3::splat(0.1),
        Vec3::new(0.2, 0.5, 0.1),
        Vec3::splat(0.4),
        30.0,
    )
    .unwrap()
    .with_optics(Vec3::ZERO, 0.6, 1.0, false, Vec3::ZERO)
    .unwrap();
    let opaque = Material::new(Vec3::splat(0.1), Vec3::splat(0.5), Vec3::ZERO, 1.0).unwrap();
    let grid = Arc::new(bumpy_mirror_grid());
    let cam = Camera::look_at(
        DVec3::new(0.2, 3.0, 1.2),
        DVec3::ZERO,
        DVec3::Y,
        40.0,
        0.1,
        100.0,
    )
    .unwrap();
    let (w, h) = (67u32, 49u32);
    // Where the ball is: its own depth, drawn opaque and alone.
    let mut alone = Scene::new(Vec3::ZERO).unwrap();
    alone.add(ball.clone(), opaque, ball_at).unwrap();
    let covered: Vec<bool> = render(
        &alone,
        &cam,
        &RenderOptions::new(w, h),
        ColorFormat::F32,
        true,
    )
    .unwrap()
    .depth
    .unwrap()
    .iter()
    .map(|d| d.is_finite())
    .collect();
    let n_covered = covered.iter().filter(|&&c| c).count();
    assert!(
        n_covered > 40 && n_covered < (w * h / 3) as usize,
        "{n_covered}"
    );
    let mut checked = 0;
    for (fog, two_sided) in [(false, false), (true, false), (false, true)] {
        let scene = |with_ball: bool| {
            let mut s = Scene::new(Vec3::splat(0.1)).unwrap();
            s.set_environment(Some(test_sky()));
            s.add(grid.clone(), mirror, Mat4::IDENTITY).unwrap();
            if with_ball {
                s.add(ball.clone(), tinted, ball_at).unwrap();
            }
            s.add_light(test_sun());
            s.set_two_sided(two_sided);
            if fog {
                s.set_fog(Some(test_fog()));
            }
            s
        };
        let (without, with) = (scene(false), scene(true));
        for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
            for sky_background in [false, true] {
                let frame = |s: &Scene| {
                    let mut o = RenderOptions::new(w, h);
                    o.shading = mode;
                    o.reflections = Technique::Environment;
                    o.environment_background = sky_background;
                    match render(s, &cam, &o, ColorFormat::F32, false).unwrap().color {
                        ColorBuffer::F32(c) => c,
                        _ => unreachable!(),
                    }
                };
                let (a, b) = (frame(&without), frame(&with));
                let what =
                    format!("fog {fog}, two-sided {two_sided}, {mode:?}, sky {sky_background}");
                let mut changed = 0;
                for (k, (pa, pb)) in a.chunks(3).zip(b.chunks(3)).enumerate() {
                    let same = pa.iter().zip(pb).all(|(x, y)| x.to_bits() == y.to_bits());
                    if covered[k] {
                        changed += !same as usize;
                    } else {
                        assert!(same, "{what}: pixel {k} not under the ball changed");
                    }
                }
                assert!(
                    changed * 10 >= n_covered * 9,
                    "{what}: {changed} of {n_covered}"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 18);
}
