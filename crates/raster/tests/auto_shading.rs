//! `shading="auto"` (`RenderOptions::tolerance`): the estimates' exact properties, and a
//! frame mixing modes being, pixel by pixel, the frame of each pixel's own mode.

mod common;

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::*;

const W: u32 = 160;
const H: u32 = 120;

fn gold() -> Material {
    Material::preset("gold").unwrap()
}

fn matte() -> Material {
    Material::new(Vec3::splat(0.1), Vec3::splat(0.7), Vec3::ZERO, 1.0).unwrap()
}

/// A shiny sphere at x = −0.6 and, behind and beside it, a matte floor square at x = +0.6
/// under one directional light: the floor needs only flat (its lighting is constant), the
/// coarse sphere needs Phong.
fn two_objects(rings: u32) -> Scene {
    let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
    let sphere = Arc::new(primitives::uv_sphere(rings, 2 * rings));
    scene
        .add(
            sphere,
            gold(),
            Mat4::from_translation(Vec3::new(-0.6, 0.0, 0.0)),
        )
        .unwrap();
    let floor = Arc::new(primitives::plane());
    let t = Mat4::from_translation(Vec3::new(0.6, -0.5, -0.5)) * Mat4::from_scale(Vec3::splat(1.2));
    scene.add(floor, matte(), t).unwrap();
    scene.add_light(DirectionalLight::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE, 1.0).unwrap());
    scene
}

fn camera() -> Camera {
    Camera::look_at(
        DVec3::new(0.0, 1.2, 4.0),
        DVec3::new(0.0, -0.2, 0.0),
        DVec3::Y,
        40.0,
        0.1,
        100.0,
    )
    .unwrap()
}

fn options(shading: ShadingMode) -> RenderOptions {
    let mut o = RenderOptions::new(W, H);
    o.shading = shading;
    o
}

#[test]
fn a_constant_lit_plane_needs_only_flat_and_a_coarse_shiny_sphere_more() {
    let est = explain_shading(
        &two_objects(6),
        &camera(),
        &options(ShadingMode::Phong),
        1.0,
    )
    .unwrap();
    assert_eq!(est.len(), 2);
    // The floor: a directional light, no specular, a plane: every mode is exact but for the
    // renderer's float rounding, which flips a level now and then (the same for all three).
    let e = est[1].estimates;
    assert!(e[0] == e[1] && e[1] == e[2] && e[0] < 0.05, "{e:?}");
    assert_eq!(est[1].mode, ShadingMode::Flat);
    assert!(est[1].meets && est[1].pixels > 100.0, "{:?}", est[1]);
    // The sphere: Phong no worse than the others (on a coarse mesh Gouraud can be worse than
    // flat: it smears a highlight over triangles that do not hold it), flat well above 1.
    let e = est[0].estimates;
    assert!(e[0] >= e[2] && e[1] >= e[2] && e[0] > 1.0, "{e:?}");
    assert_ne!(est[0].mode, ShadingMode::Flat);
}

#[test]
fn finer_meshes_and_looser_tolerances_never_ask_for_a_costlier_mode() {
    let rank = |m: ShadingMode| m as u8;
    let cam = camera();
    let o = options(ShadingMode::Phong);
    let mut last = [f32::INFINITY; 3];
    for rings in [4, 8, 16, 32, 64, 128] {
        let e = explain_shading(&two_objects(rings), &cam, &o, 1.0).unwrap()[0].estimates;
        for k in 0..3 {
            assert!(e[k] <= last[k], "rings {rings}: {e:?} after {last:?}");
        }
        last = e;
        let mut prev = rank(ShadingMode::Phong);
        for tol in [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 64.0] {
            let est = explain_shading(&two_objects(rings), &cam, &o, tol).unwrap();
            let m = rank(est[0].mode);
            assert!(m <= prev, "rings {rings} tolerance {tol}: {est:?}");
            prev = m;
            // The chosen mode meets the tolerance, or no mode does and Phong is used.
            let chosen = est[0].estimate(est[0].mode);
            assert!(
                (est[0].meets && chosen <= tol)
                    || (!est[0].meets && est[0].mode == ShadingMode::Phong && chosen > tol),
                "{est:?}"
            );
        }
    }
}

#[test]
fn tolerance_is_checked() {
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let mut o = options(ShadingMode::Phong);
        o.tolerance = Some(bad);
        let err = o.validate().unwrap_err();
        assert!(err.to_string().contains("tolerance"), "{err}");
        assert!(explain_shading(
            &two_objects(6),
            &camera(),
            &options(ShadingMode::Phong),
            bad
        )
        .is_err());
    }
}

/// Which object owns each pixel: the depth of the whole scene equals the depth of the scene
/// with object 0 alone there (and is finite).
fn owner_is_first(scene: &Scene, o: &RenderOptions) -> Vec<bool> {
    let mut alone = Scene::new(scene.ambient()).unwrap();
    alone.add_object(scene.objects()[0].clone());
    let (_, d_all) = common::render_f32(scene, &camera(), o);
    let (_, d_one) = common::render_f32(&alone, &camera(), o);
    d_all
        .iter()
        .zip(&d_one)
        .map(|(a, b)| a.is_finite() && a == b)
        .collect()
}

#[test]
fn a_mixed_frame_is_each_pixels_own_mode() {
    let scene = two_objects(6);
    let mut auto = options(ShadingMode::Phong);
    auto.tolerance = Some(1.0);
    let f = render(&scene, &camera(), &auto, ColorFormat::F32, true).unwrap();
    let modes: Vec<ShadingMode> = f.stats.shading.iter().map(|e| e.mode).collect();
    assert_eq!(modes[1], ShadingMode::Flat);
    assert_ne!(modes[0], ShadingMode::Flat, "the test needs two modes");
    let first = owner_is_first(&scene, &options(ShadingMode::Phong));
    assert!(first.iter().any(|&b| b) && first.iter().any(|&b| !b));
    let (sphere_img, sphere_d) = common::render_f32(&scene, &camera(), &options(modes[0]));
    let (flat_img, flat_d) = common::render_f32(&scene, &camera(), &options(ShadingMode::Flat));
    let (ColorBuffer::F32(mixed), Some(depth)) = (&f.color, &f.depth) else {
        unreachable!()
    };
    let mut both = [0usize; 2];
    for (p, &is_first) in first.iter().enumerate() {
        let (want, want_d) = if is_first {
            (&sphere_img, &sphere_d)
        } else {
            (&flat_img, &flat_d)
        };
        assert_eq!(
            &mixed[p * 3..p * 3 + 3],
            &want[p * 3..p * 3 + 3],
            "pixel {p}"
        );
        assert_eq!(depth[p].to_bits(), want_d[p].to_bits(), "depth {p}");
        both[is_first as usize] += 1;
    }
    // The images differ where the modes do: the check above compared something.
    assert_ne!(sphere_img, flat_img);
    assert!(both[0] > 0 && both[1] > 0);
}

#[test]
fn a_mixed_frame_is_the_same_for_threads_instruction_sets_and_pixel_types() {
    let scene = two_objects(6);
    let mut o = options(ShadingMode::Phong);
    o.tolerance = Some(1.0);
    let reference = render(&scene, &camera(), &o, ColorFormat::U8, true).unwrap();
    assert!(reference.stats.shading.len() == 2);
    for (threads, baseline) in [(1, false), (2, false), (2, true)] {
        let mut p = o.clone();
        p.threads = Some(threads);
        p.baseline_isa = baseline;
        let f = render(&scene, &camera(), &p, ColorFormat::U8, true).unwrap();
        assert_eq!(
            f.color, reference.color,
            "threads {threads} baseline {baseline}"
        );
        assert_eq!(f.depth, reference.depth);
    }
    // u8 is the f32 image stored as u8.
    let f = render(&scene, &camera(), &o, ColorFormat::F32, false).unwrap();
    let (ColorBuffer::F32(c), ColorBuffer::U8(u)) = (&f.color, &reference.color) else {
        unreachable!()
    };
    for (a, b) in c.iter().zip(u) {
        assert_eq!((a.clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u8, *b);
    }
}

#[test]
fn scenes_that_cannot_mix_use_the_most_accurate_mode_for_all() {
    let scene = two_objects(6);
    let mut o = options(ShadingMode::Phong);
    o.tolerance = Some(1.0);
    o.samples = 4;
    let f = render(&scene, &camera(), &o, ColorFormat::U8, false).unwrap();
    let modes: Vec<ShadingMode> = f.stats.shading.iter().map(|e| e.mode).collect();
    assert_eq!(modes[0], modes[1]);
    assert_ne!(modes[0], ShadingMode::Flat);
    let mut fixed = o.clone();
    fixed.tolerance = None;
    fixed.shading = modes[0];
    let g = render(&scene, &camera(), &fixed, ColorFormat::U8, false).unwrap();
    assert_eq!(f.color, g.color);
}

#[test]
fn the_estimate_is_the_same_for_any_thread_count_and_instruction_set() {
    // A mesh large enough to be split into many parallel chunks, and a point light besides
    // the sun (its lane loop has an AVX2 copy of its own).
    let mut scene = two_objects(200);
    scene.add_light(PointLight::new(Vec3::new(2.0, 3.0, 4.0), Vec3::splat(0.5), 1.0).unwrap());
    let mut want = None;
    for threads in [1, 2, 3] {
        for baseline in [false, true] {
            let mut o = options(ShadingMode::Phong);
            o.threads = Some(threads);
            o.baseline_isa = baseline;
            let e = explain_shading(&scene, &camera(), &o, 1.0).unwrap();
            match &want {
                None => want = Some(e),
                Some(w) => assert_eq!(&e, w, "threads {threads}, baseline {baseline}"),
            }
        }
    }
}
