//! The safety net of restructurings: hashes of renders over every output-affecting switch
//! (shading mode × fog × pixel type × depth output × thread count × instruction set × light
//! kinds, with clipping, culling, two-sided lighting, back materials, the infinite viewer,
//! the three specular lobes and both projections), committed as constants. A refactor that
//! claims "same pixels" must keep every hash; a change that means to change pixels updates
//! the table in the same commit and says why.
//!
//! `SHADELAB_PRINT_HASHES=1 cargo test --test output_hashes -- --nocapture` prints the table.

mod common;

use std::sync::Arc;

use glam::{DVec3, Mat4, Quat, Vec3};
use shadelab_raster::*;

/// FNV-1a, 64-bit: small, stable, no dependency.
fn fnv1a(hash: &mut u64, bytes: &[u8]) {
    for &b in bytes {
        *hash ^= b as u64;
        *hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
}

const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

/// The bytes of one frame: colour samples (u8 or f32 bits), then depth bits if any.
fn frame_bytes(f: &Frame) -> Vec<u8> {
    let mut out = match &f.color {
        ColorBuffer::U8(c) => c.clone(),
        ColorBuffer::F32(c) => c.iter().flat_map(|v| v.to_le_bytes()).collect(),
    };
    if let Some(d) = &f.depth {
        out.extend(d.iter().flat_map(|v| v.to_le_bytes()));
    }
    out
}

struct Case {
    name: &'static str,
    scene: Scene,
    camera: Camera,
    specular: SpecularModel,
    cull: bool,
}

fn base_scene(ambient: f32) -> Scene {
    let mut scene = Scene::new(Vec3::splat(ambient)).unwrap();
    let sphere = Arc::new(primitives::uv_sphere(24, 48));
    scene
        .add(
            sphere.clone(),
            Material::preset("gold").unwrap(),
            Mat4::IDENTITY,
        )
        .unwrap();
    let t = Mat4::from_scale_rotation_translation(
        Vec3::new(0.6, 0.3, 0.9),
        Quat::from_rotation_y(0.7),
        Vec3::new(0.5, 0.2, 0.4),
    );
    let chrome = Material::preset("chrome")
        .unwrap()
        .with_emission(Vec3::new(0.05, 0.0, 0.02))
        .unwrap();
    scene.add(Arc::new(primitives::cube()), chrome, t).unwrap();
    // An open surface seen from both sides, with a back material.
    let plane = Object::new(
        Arc::new(primitives::plane()),
        Material::preset("copper").unwrap(),
        Mat4::from_scale_rotation_translation(
            Vec3::splat(1.6),
            Quat::from_rotation_x(1.2),
            Vec3::new(-0.3, -0.6, -0.2),
        ),
    )
    .unwrap()
    .with_back_material(Some(Material::preset("emerald").unwrap()));
    scene.add_object(plane);
    scene.add_object(
        Object::new(
            sphere,
            Material::preset("ruby").unwrap(),
            Mat4::from_translation(Vec3::new(-0.5, 0.1, 0.5)) * Mat4::from_scale(Vec3::splat(0.4)),
        )
        .unwrap(),
    );
    scene
}

fn perspective(eye: DVec3, near: f64) -> Camera {
    Camera::look_at(eye, DVec3::new(0.0, -0.1, 0.0), DVec3::Y, 50.0, near, 10.0).unwrap()
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();

    // No light: ambient and emission only.
    out.push(Case {
        name: "ambient-only",
        scene: base_scene(0.6),
        camera: perspective(DVec3::new(0.5, 0.7, 2.5), 0.5),
        specular: SpecularModel::BlinnPhong,
        cull: false,
    });

    // Directional + plain point light, Blinn-Phong.
    let mut s = base_scene(0.2);
    s.add_light(DirectionalLight::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE, 1.0).unwrap());
    s.add_light(PointLight::new(Vec3::new(2.0, 3.0, 4.0), Vec3::splat(0.5), 1.0).unwrap());
    out.push(Case {
        name: "sun-point",
        scene: s,
        camera: perspective(DVec3::new(0.5, 0.7, 2.5), 0.5),
        specular: SpecularModel::BlinnPhong,
        cull: false,
    });

    // Attenuated point with light ambient, a soft-edged spot, split colours; Phong lobe; the
    // near plane cuts through the scene (clipped triangles and clip-made vertices).
    let mut s = base_scene(0.1);
    let p = PointLight::new(Vec3::new(-1.0, 1.5, 1.5), Vec3::new(0.9, 0.8, 0.7), 2.0)
        .unwrap()
        .with_attenuation(0.5, 0.2, 0.1)
        .unwrap()
        .with_ambient(Vec3::splat(0.15))
        .unwrap();
    s.add_light(p);
    let sp = PointLight::new(Vec3::new(0.5, 2.0, 0.5), Vec3::ONE, 2.0)
        .unwrap()
        .with_ambient(Vec3::splat(0.05))
        .unwrap();
    s.add_light(
        SpotLight::new(sp, Vec3::new(-0.2, -1.0, -0.1), 40.0, 3.0)
            .unwrap()
            .with_inner(25.0)
            .unwrap(),
    );
    s.add_light(
        DirectionalLight::new(Vec3::new(1.0, -0.3, -0.5), Vec3::ONE, 0.5)
            .unwrap()
            .with_split_colors(
                Some(Vec3::new(0.2, 0.4, 0.6)),
                Some(Vec3::new(1.0, 0.5, 0.0)),
            )
            .unwrap(),
    );
    out.push(Case {
        name: "attenuated-spot-clipped",
        scene: s,
        camera: perspective(DVec3::new(0.3, 0.4, 1.2), 0.9),
        specular: SpecularModel::Phong,
        cull: false,
    });

    // Area lights: one-sided rectangle and a two-sided disc; normalised Blinn; culling.
    let mut s = base_scene(0.1);
    s.add_light(
        AreaLight::new(
            Vec3::new(0.0, 2.0, 1.0),
            Vec3::new(0.8, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -0.8),
            AreaShape::Rectangle,
            3,
        )
        .unwrap()
        .with_color(Vec3::new(1.0, 0.9, 0.8), 3.0)
        .unwrap()
        .with_one_sided(true),
    );
    s.add_light(
        AreaLight::new(
            Vec3::new(-2.0, 0.5, 1.0),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::new(0.0, 0.0, 0.5),
            AreaShape::Disk,
            2,
        )
        .unwrap()
        .with_attenuation(1.0, 0.1, 0.05)
        .unwrap(),
    );
    out.push(Case {
        name: "area-lights",
        scene: s,
        camera: perspective(DVec3::new(-0.4, 0.9, 2.4), 0.5),
        specular: SpecularModel::NormalizedBlinnPhong,
        cull: true,
    });

    // Infinite viewer, orthographic camera.
    let mut s = base_scene(0.2);
    s.set_local_viewer(false);
    s.add_light(DirectionalLight::new(Vec3::new(-0.5, -1.0, -0.8), Vec3::ONE, 1.0).unwrap());
    s.add_light(
        PointLight::new(Vec3::new(1.0, 1.0, 2.0), Vec3::splat(0.6), 1.0)
            .unwrap()
            .with_attenuation(1.0, 0.0, 0.2)
            .unwrap(),
    );
    out.push(Case {
        name: "infinite-viewer-ortho",
        scene: s,
        camera: Camera::orthographic(
            DVec3::new(1.0, 1.5, 3.0),
            DVec3::ZERO,
            DVec3::Y,
            2.5,
            0.5,
            10.0,
        )
        .unwrap(),
        specular: SpecularModel::BlinnPhong,
        cull: false,
    });
    out
}

/// Hash of one (case, mode, fog) over pixel types × depth output; also checks that 1 and 2
/// threads and both instruction sets give the same bytes.
fn hash_of(case: &Case, mode: ShadingMode) -> u64 {
    let mut h = FNV_START;
    for format in [ColorFormat::U8, ColorFormat::F32] {
        for depth in [false, true] {
            let mut reference: Option<Vec<u8>> = None;
            for (threads, baseline_isa) in [(1, false), (2, false), (2, true)] {
                let mut opts = RenderOptions::new(97, 61);
                opts.shading = mode;
                opts.specular = case.specular;
                opts.cull_backfaces = case.cull;
                opts.background = Vec3::new(0.1, 0.2, 0.3);
                opts.threads = Some(threads);
                opts.baseline_isa = baseline_isa;
                let bytes =
                    frame_bytes(&render(&case.scene, &case.camera, &opts, format, depth).unwrap());
                match &reference {
                    None => reference = Some(bytes),
                    Some(r) => assert!(
                        r == &bytes,
                        "{} {mode:?} {format:?} depth {depth}: {threads} threads, baseline {baseline_isa} differs",
                        case.name
                    ),
                }
            }
            fnv1a(&mut h, &reference.unwrap());
        }
    }
    h
}

/// (case, mode, fog, two-sided) → hash, as rendered by the commit this table was made on.
const EXPECTED: &[(&str, &str, &str, bool, u64)] = &[
    ("ambient-only", "flat", "none", false, 0x14cf5a88518a7835),
    ("ambient-only", "gouraud", "none", false, 0x515971c1751b2745),
    ("ambient-only", "phong", "none", false, 0xdc4c325cc0749c4d),
    ("ambient-only", "flat", "none", true, 0x14cf5a88518a7835),
    ("ambient-only", "gouraud", "none", true, 0x515971c1751b2745),
    ("ambient-only", "phong", "none", true, 0xdc4c325cc0749c4d),
    ("ambient-only", "flat", "linear", false, 0x6a4dd6433203423d),
    (
        "ambient-only",
        "gouraud",
        "linear",
        false,
        0x0bdc705527dfa81d,
    ),
    ("ambient-only", "phong", "linear", false, 0x0694f927bc639a91),
    ("ambient-only", "flat", "linear", true, 0x6a4dd6433203423d),
    (
        "ambient-only",
        "gouraud",
        "linear",
        true,
        0x0bdc705527dfa81d,
    ),
    ("ambient-only", "phong", "linear", true, 0x0694f927bc639a91),
    ("ambient-only", "flat", "exp2", false, 0x2cff8e1650c4b203),
    ("ambient-only", "gouraud", "exp2", false, 0x7ce7d2d9112dc71b),
    ("ambient-only", "phong", "exp2", false, 0xf4fdee3b74ff00eb),
    ("ambient-only", "flat", "exp2", true, 0x2cff8e1650c4b203),
    ("ambient-only", "gouraud", "exp2", true, 0x7ce7d2d9112dc71b),
    ("ambient-only", "phong", "exp2", true, 0xf4fdee3b74ff00eb),
    ("sun-point", "flat", "none", false, 0x69c9afe988d25cc3),
    ("sun-point", "gouraud", "none", false, 0x6314927264499867),
    ("sun-point", "phong", "none", false, 0x2db8f91f325cdc1f),
    ("sun-point", "flat", "none", true, 0x69c9afe988d25cc3),
    ("sun-point", "gouraud", "none", true, 0x6314927264499867),
    ("sun-point", "phong", "none", true, 0x2db8f91f325cdc1f),
    ("sun-point", "flat", "linear", false, 0x4433a2274a6d4c15),
    ("sun-point", "gouraud", "linear", false, 0x37d8559e11af42b9),
    ("sun-point", "phong", "linear", false, 0x4739ceec87727a45),
    ("sun-point", "flat", "linear", true, 0x4433a2274a6d4c15),
    ("sun-point", "gouraud", "linear", true, 0x37d8559e11af42b9),
    ("sun-point", "phong", "linear", true, 0x4739ceec87727a45),
    ("sun-point", "flat", "exp2", false, 0x9b0adf26a0929afd),
    ("sun-point", "gouraud", "exp2", false, 0x64364c64c9c74877),
    ("sun-point", "phong", "exp2", false, 0x89509d1a5d1eadd5),
    ("sun-point", "flat", "exp2", true, 0x9b0adf26a0929afd),
    ("sun-point", "gouraud", "exp2", true, 0x64364c64c9c74877),
    ("sun-point", "phong", "exp2", true, 0x89509d1a5d1eadd5),
    (
        "attenuated-spot-clipped",
        "flat",
        "none",
        false,
        0x49864bb49a79a76d,
    ),
    (
        "attenuated-spot-clipped",
        "gouraud",
        "none",
        false,
        0xacd36e0387378ea1,
    ),
    (
        "attenuated-spot-clipped",
        "phong",
        "none",
        false,
        0x3d5cd4544787fccf,
    ),
    (
        "attenuated-spot-clipped",
        "flat",
        "none",
        true,
        0x5d6bdc087aaaca2d,
    ),
    (
        "attenuated-spot-clipped",
        "gouraud",
        "none",
        true,
        0x1f7b2ea8264692c7,
    ),
    (
        "attenuated-spot-clipped",
        "phong",
        "none",
        true,
        0x1985ec67a3175611,
    ),
    (
        "attenuated-spot-clipped",
        "flat",
        "linear",
        false,
        0xe9ae73e02ed32959,
    ),
    (
        "attenuated-spot-clipped",
        "gouraud",
        "linear",
        false,
        0x1200d81f517d1437,
    ),
    (
        "attenuated-spot-clipped",
        "phong",
        "linear",
        false,
        0xd67211195b565275,
    ),
    (
        "attenuated-spot-clipped",
        "flat",
        "linear",
        true,
        0xac1500c702621959,
    ),
    (
        "attenuated-spot-clipped",
        "gouraud",
        "linear",
        true,
        0xc28ea0ae3395e1e3,
    ),
    (
        "attenuated-spot-clipped",
        "phong",
        "linear",
        true,
        0xb3b7faf06931ae4d,
    ),
    (
        "attenuated-spot-clipped",
        "flat",
        "exp2",
        false,
        0xc2a7cdbdd9aa6b8f,
    ),
    (
        "attenuated-spot-clipped",
        "gouraud",
        "exp2",
        false,
        0x8d59f85ba5cdfef5,
    ),
    (
        "attenuated-spot-clipped",
        "phong",
        "exp2",
        false,
        0x21992871d51c3fd5,
    ),
    (
        "attenuated-spot-clipped",
        "flat",
        "exp2",
        true,
        0x08d1796fc884f2b5,
    ),
    (
        "attenuated-spot-clipped",
        "gouraud",
        "exp2",
        true,
        0xf67d8a9ea96c9979,
    ),
    (
        "attenuated-spot-clipped",
        "phong",
        "exp2",
        true,
        0xbd4691e6754aec39,
    ),
    ("area-lights", "flat", "none", false, 0x1612fcd5d1e5c9a9),
    ("area-lights", "gouraud", "none", false, 0xf3570c849b62686f),
    ("area-lights", "phong", "none", false, 0x11508361f0e36505),
    ("area-lights", "flat", "none", true, 0x1612fcd5d1e5c9a9),
    ("area-lights", "gouraud", "none", true, 0xf3570c849b62686f),
    ("area-lights", "phong", "none", true, 0x11508361f0e36505),
    ("area-lights", "flat", "linear", false, 0x7b96cf48d1540e63),
    (
        "area-lights",
        "gouraud",
        "linear",
        false,
        0x49a2d85bd1fb101b,
    ),
    ("area-lights", "phong", "linear", false, 0xdda3103c43910933),
    ("area-lights", "flat", "linear", true, 0x7b96cf48d1540e63),
    ("area-lights", "gouraud", "linear", true, 0x49a2d85bd1fb101b),
    ("area-lights", "phong", "linear", true, 0xdda3103c43910933),
    ("area-lights", "flat", "exp2", false, 0xe16e8fbbd6bdb82b),
    ("area-lights", "gouraud", "exp2", false, 0x64eae4d8afa38f5b),
    ("area-lights", "phong", "exp2", false, 0xbb33530b33a33af9),
    ("area-lights", "flat", "exp2", true, 0xe16e8fbbd6bdb82b),
    ("area-lights", "gouraud", "exp2", true, 0x64eae4d8afa38f5b),
    ("area-lights", "phong", "exp2", true, 0xbb33530b33a33af9),
    (
        "infinite-viewer-ortho",
        "flat",
        "none",
        false,
        0xb1a0d26c0999fe6d,
    ),
    (
        "infinite-viewer-ortho",
        "gouraud",
        "none",
        false,
        0x1033c722e27ad435,
    ),
    (
        "infinite-viewer-ortho",
        "phong",
        "none",
        false,
        0x57adaa94605d8b7d,
    ),
    (
        "infinite-viewer-ortho",
        "flat",
        "none",
        true,
        0xb1a0d26c0999fe6d,
    ),
    (
        "infinite-viewer-ortho",
        "gouraud",
        "none",
        true,
        0x1033c722e27ad435,
    ),
    (
        "infinite-viewer-ortho",
        "phong",
        "none",
        true,
        0x57adaa94605d8b7d,
    ),
    (
        "infinite-viewer-ortho",
        "flat",
        "linear",
        false,
        0xd90297da45401c7d,
    ),
    (
        "infinite-viewer-ortho",
        "gouraud",
        "linear",
        false,
        0xda5bd86751eeeb63,
    ),
    (
        "infinite-viewer-ortho",
        "phong",
        "linear",
        false,
        0x7e52cf1d6e315fd1,
    ),
    (
        "infinite-viewer-ortho",
        "flat",
        "linear",
        true,
        0xd90297da45401c7d,
    ),
    (
        "infinite-viewer-ortho",
        "gouraud",
        "linear",
        true,
        0xda5bd86751eeeb63,
    ),
    (
        "infinite-viewer-ortho",
        "phong",
        "linear",
        true,
        0x7e52cf1d6e315fd1,
    ),
    (
        "infinite-viewer-ortho",
        "flat",
        "exp2",
        false,
        0x104974d304bc6cd5,
    ),
    (
        "infinite-viewer-ortho",
        "gouraud",
        "exp2",
        false,
        0x846d1f851d5b113d,
    ),
    (
        "infinite-viewer-ortho",
        "phong",
        "exp2",
        false,
        0xf6d4c10bdc73469d,
    ),
    (
        "infinite-viewer-ortho",
        "flat",
        "exp2",
        true,
        0x104974d304bc6cd5,
    ),
    (
        "infinite-viewer-ortho",
        "gouraud",
        "exp2",
        true,
        0x846d1f851d5b113d,
    ),
    (
        "infinite-viewer-ortho",
        "phong",
        "exp2",
        true,
        0xf6d4c10bdc73469d,
    ),
];

#[test]
fn renders_hash_to_the_committed_table() {
    let fogs = [
        ("none", None),
        (
            "linear",
            Some(
                Fog::new(
                    FogMode::Linear {
                        start: 1.5,
                        end: 4.0,
                    },
                    Vec3::new(0.5, 0.6, 0.7),
                )
                .unwrap(),
            ),
        ),
        (
            "exp2",
            Some(Fog::new(FogMode::Exp2 { density: 0.4 }, Vec3::new(0.7, 0.6, 0.5)).unwrap()),
        ),
    ];
    let print = std::env::var_os("SHADELAB_PRINT_HASHES").is_some();
    let mut got = Vec::new();
    for mut case in cases() {
        for (fog_name, fog) in &fogs {
            for two_sided in [false, true] {
                case.scene.set_fog(*fog);
                case.scene.set_two_sided(two_sided);
                for (mode_name, mode) in [
                    ("flat", ShadingMode::Flat),
                    ("gouraud", ShadingMode::Gouraud),
                    ("phong", ShadingMode::Phong),
                ] {
                    got.push((
                        case.name,
                        mode_name,
                        *fog_name,
                        two_sided,
                        hash_of(&case, mode),
                    ));
                }
            }
        }
    }
    if print {
        for (c, m, f, t, h) in &got {
            println!("    (\"{c}\", \"{m}\", \"{f}\", {t}, 0x{h:016x}),");
        }
    }
    let mismatches: Vec<String> = got
        .iter()
        .zip(EXPECTED)
        .filter(|(g, e)| g != e)
        .map(|(g, e)| format!("got {g:?}, expected {e:?}"))
        .collect();
    assert_eq!(
        got.len(),
        EXPECTED.len(),
        "the table has {} rows, the matrix {}",
        EXPECTED.len(),
        got.len()
    );
    assert!(
        mismatches.is_empty(),
        "{} of {} renders changed:\n{}",
        mismatches.len(),
        got.len(),
        mismatches.join("\n")
    );
}
