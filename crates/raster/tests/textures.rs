//! Textured renders end to end: a white map changes nothing, a map's texel lands where its
//! UV says, vertex colours replace ambient and diffuse, specular stays untextured, and the
//! untextured scene is unaffected by the texture path existing.

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::*;

const W: u32 = 80;
const H: u32 = 60;

fn camera() -> Camera {
    Camera::look_at(
        DVec3::new(0.0, 2.2, 1.2),
        DVec3::ZERO,
        DVec3::Y,
        50.0,
        0.1,
        100.0,
    )
    .unwrap()
}

fn f32_frame(scene: &Scene, mode: ShadingMode) -> Vec<f32> {
    let mut o = RenderOptions::new(W, H);
    o.shading = mode;
    match render(scene, &camera(), &o, ColorFormat::F32, false)
        .unwrap()
        .color
    {
        ColorBuffer::F32(v) => v,
        ColorBuffer::U8(_) => unreachable!(),
    }
}

fn plane_scene(material: Material, maps: Option<Maps>, colors: Option<Vec<Vec3>>) -> Scene {
    let mut mesh = primitives::plane();
    if let Some(c) = colors {
        mesh = mesh.with_colors(c).unwrap();
    }
    let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
    let obj = Object::new(Arc::new(mesh), material, Mat4::IDENTITY)
        .unwrap()
        .with_maps(maps.map(Arc::new))
        .unwrap();
    scene.add_object(obj);
    scene.add_light(PointLight::new(Vec3::new(0.3, 1.0, 0.4), Vec3::ONE, 1.0).unwrap());
    scene
}

fn solid(c: Vec3) -> Arc<Texture> {
    let img = texture::Image::from_top_rows(1, 1, 3, &c.to_array(), false).unwrap();
    Arc::new(Texture::from_image(
        Arc::new(img),
        Filter::Trilinear,
        [Wrap::Repeat; 2],
    ))
}

const MODES: [ShadingMode; 3] = [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong];

fn max_diff(a: &[f32], b: &[f32]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

#[test]
fn a_white_map_renders_as_no_map() {
    let gold = Material::preset("gold").unwrap();
    let plain = plane_scene(gold, None, None);
    let maps = Maps {
        diffuse: Some(solid(Vec3::ONE)),
        ..Maps::default()
    };
    let textured = plane_scene(gold, Some(maps), None);
    for mode in MODES {
        let d = max_diff(&f32_frame(&plain, mode), &f32_frame(&textured, mode));
        assert!(d < 1e-5, "{mode:?}: {d}");
    }
}

#[test]
fn maps_weigh_their_terms_and_specular_is_added_after() {
    let m = Material::new(Vec3::splat(0.3), Vec3::splat(0.6), Vec3::splat(0.5), 10.0)
        .unwrap()
        .with_emission(Vec3::splat(0.1))
        .unwrap();
    let red = Vec3::new(1.0, 0.0, 0.0);
    // Diffuse map red: ambient (defaults to the diffuse map) and diffuse lose green and blue,
    // specular and emission do not.
    let maps = Maps {
        diffuse: Some(solid(red)),
        ..Maps::default()
    };
    let only_spec = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::splat(0.5), 10.0)
        .unwrap()
        .with_emission(Vec3::splat(0.1))
        .unwrap();
    for mode in MODES {
        let t = f32_frame(&plane_scene(m, Some(maps.clone()), None), mode);
        let spec = f32_frame(&plane_scene(only_spec, None, None), mode);
        let full = f32_frame(&plane_scene(m, None, None), mode);
        for ((t, s), f) in t.chunks(3).zip(spec.chunks(3)).zip(full.chunks(3)) {
            // Green: emission + specular only; red: the whole untextured colour.
            assert!((t[1] - s[1]).abs() < 1e-5, "{mode:?} {t:?} {s:?}");
            assert!((t[0] - f[0]).abs() < 1e-5, "{mode:?} {t:?} {f:?}");
        }
    }
}

#[test]
fn vertex_colors_replace_ambient_and_diffuse() {
    let m = Material::new(Vec3::splat(0.9), Vec3::splat(0.9), Vec3::ZERO, 1.0).unwrap();
    let c = Vec3::new(0.2, 0.4, 0.6);
    let want = Material::new(c, c, Vec3::ZERO, 1.0).unwrap();
    for mode in MODES {
        let a = f32_frame(&plane_scene(m, None, Some(vec![c; 4])), mode);
        let b = f32_frame(&plane_scene(want, None, None), mode);
        assert!(max_diff(&a, &b) < 1e-5, "{mode:?}");
    }
}

#[test]
fn a_checker_lands_where_its_uvs_say() {
    // Seen from straight above, the plane's u runs along x and v along -z (v = 1 at the
    // top of the image): a 2 x 2 checker's top-left quarter is texel (0, 0) of the image.
    let mut scene = Scene::new(Vec3::ONE).unwrap();
    let emit = Material::new(Vec3::ONE, Vec3::ZERO, Vec3::ZERO, 1.0).unwrap();
    let data = [
        1.0, 0.0, 0.0, 0.0, 1.0, 0.0, //
        0.0, 0.0, 1.0, 1.0, 1.0, 1.0,
    ];
    let img = Arc::new(texture::Image::from_top_rows(2, 2, 3, &data, false).unwrap());
    let tex = Arc::new(Texture::from_image(img, Filter::Nearest, [Wrap::Clamp; 2]));
    let maps = Maps {
        diffuse: Some(tex),
        ..Maps::default()
    };
    let obj = Object::new(Arc::new(primitives::plane()), emit, Mat4::IDENTITY)
        .unwrap()
        .with_maps(Some(Arc::new(maps)))
        .unwrap();
    scene.add_object(obj);
    let cam = Camera::look_at(
        DVec3::new(0.0, 3.0, 0.0),
        DVec3::ZERO,
        -DVec3::Z,
        60.0,
        0.1,
        10.0,
    )
    .unwrap();
    let o = RenderOptions::new(64, 64);
    let f = render(&scene, &cam, &o, ColorFormat::U8, false).unwrap();
    let ColorBuffer::U8(px) = f.color else {
        unreachable!()
    };
    let at = |x: usize, y: usize| &px[(y * 64 + x) * 3..(y * 64 + x) * 3 + 3];
    assert_eq!(at(26, 26), [255, 0, 0]);
    assert_eq!(at(38, 26), [0, 255, 0]);
    assert_eq!(at(26, 38), [0, 0, 255]);
    assert_eq!(at(38, 38), [255, 255, 255]);
}

#[test]
fn maps_without_uvs_are_refused() {
    let mesh = Mesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        vec![[0, 1, 2]],
        None,
        None,
    )
    .unwrap();
    let maps = Maps {
        diffuse: Some(solid(Vec3::ONE)),
        ..Maps::default()
    };
    let e = Object::new(Arc::new(mesh), Material::default(), Mat4::IDENTITY)
        .unwrap()
        .with_maps(Some(Arc::new(maps)))
        .unwrap_err();
    assert!(e.to_string().contains("no UVs"), "{e}");
}

#[test]
fn flat_normal_and_constant_bump_maps_change_nothing() {
    // (0.5, 0.5, 1) decodes to exactly (0, 0, 1); a constant height has no gradient: only
    // the renormalisation of an already unit normal moves it (by an ulp), which gold's
    // specular power (51.2) amplifies: 1.8e-6 measured; 1e-5 allowed.
    let gold = Material::preset("gold").unwrap();
    let plain = f32_frame(&plane_scene(gold, None, None), ShadingMode::Phong);
    for maps in [
        Maps {
            normal: Some(solid(Vec3::new(0.5, 0.5, 1.0))),
            ..Maps::default()
        },
        Maps {
            bump: Some(solid(Vec3::splat(0.3))),
            bump_scale: 5.0,
            ..Maps::default()
        },
    ] {
        let mapped = f32_frame(&plane_scene(gold, Some(maps), None), ShadingMode::Phong);
        let d = max_diff(&plain, &mapped);
        assert!(d < 1e-5, "{d}");
    }
}

#[test]
fn normal_maps_need_phong_and_tilt_the_lighting() {
    let m = Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ZERO, 1.0).unwrap();
    // The plane's tangent is +x (u along x): tilting toward +x changes the diffuse term.
    let tilted = Maps {
        normal: Some(solid(Vec3::new(0.8, 0.5, 0.9))),
        ..Maps::default()
    };
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud] {
        let mut o = RenderOptions::new(W, H);
        o.shading = mode;
        let scene = plane_scene(m, Some(tilted.clone()), None);
        let e = render(&scene, &camera(), &o, ColorFormat::F32, false).unwrap_err();
        assert!(e.to_string().contains("per-pixel lighting"), "{e}");
    }
    let a = f32_frame(&plane_scene(m, None, None), ShadingMode::Phong);
    let b = f32_frame(&plane_scene(m, Some(tilted), None), ShadingMode::Phong);
    assert!(max_diff(&a, &b) > 0.05);
}

#[test]
fn non_finite_scales_are_refused() {
    let maps = Maps {
        normal: Some(solid(Vec3::ONE)),
        normal_scale: f32::NAN,
        ..Maps::default()
    };
    let e = Object::new(
        Arc::new(primitives::plane()),
        Material::default(),
        Mat4::IDENTITY,
    )
    .unwrap()
    .with_maps(Some(Arc::new(maps)))
    .unwrap_err();
    assert!(e.to_string().contains("normal_scale"), "{e}");
}

/// Filters, wraps and anisotropy the identity tests below cover.
const CASES: [(Filter, Wrap, u32); 5] = [
    (Filter::Nearest, Wrap::Repeat, 1),
    (Filter::Bilinear, Wrap::Mirror, 1),
    (Filter::Bilinear, Wrap::Clamp, 1),
    (Filter::Trilinear, Wrap::Repeat, 1),
    (Filter::Trilinear, Wrap::Mirror, 8),
];

/// A gold sphere with a 12 × 12 diffuse and specular map of `filter`, `wrap` and `aniso`
/// (with vertex colours for bilinear, a normal map for trilinear in Phong), a shadow-casting
/// sun and a point light, fog if asked; and a camera on it.
fn mapped_sphere(case: (Filter, Wrap, u32), mode: ShadingMode, fog: bool) -> (Scene, Camera) {
    let (filter, wrap, aniso) = case;
    let texels: Vec<f32> = (0..12 * 12)
        .flat_map(|k| {
            let (i, j) = (k % 12, k / 12);
            [i as f32 / 11.0, j as f32 / 11.0, ((i + j) % 3) as f32 / 2.0]
        })
        .collect();
    let img = Arc::new(texture::Image::from_top_rows(12, 12, 3, &texels, false).unwrap());
    let s = primitives::uv_sphere(12, 24);
    let uvs: Vec<glam::Vec2> = s
        .positions()
        .iter()
        .map(|p| glam::Vec2::new(3.0 * p.x - 0.2, 2.5 * p.z + 0.7))
        .collect();
    let mut mesh = Mesh::new(
        s.positions().to_vec(),
        s.indices().to_vec(),
        s.given_normals().map(<[Vec3]>::to_vec),
        Some(uvs),
    )
    .unwrap();
    if filter == Filter::Bilinear {
        let colors = mesh.positions().iter().map(|p| p.abs()).collect();
        mesh = mesh.with_colors(colors).unwrap();
    }
    let tex = Arc::new(
        Texture::from_image(img, filter, [wrap; 2])
            .with_anisotropy(aniso)
            .unwrap(),
    );
    let maps = Maps {
        diffuse: Some(tex.clone()),
        specular: Some(tex.clone()),
        // Normal maps need per-pixel lighting.
        normal: (filter == Filter::Trilinear && mode == ShadingMode::Phong).then(|| tex.clone()),
        ..Maps::default()
    };
    let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
    let obj = Object::new(
        Arc::new(mesh),
        Material::preset("gold").unwrap(),
        Mat4::IDENTITY,
    )
    .unwrap()
    .with_maps(Some(Arc::new(maps)))
    .unwrap();
    scene.add_object(obj);
    let sun = DirectionalLight::new(Vec3::new(-1.0, -1.0, -0.5), Vec3::ONE, 0.8)
        .unwrap()
        .with_shadows(Shadows::Map(ShadowSettings::default()));
    scene.add_light(sun);
    scene.add_light(PointLight::new(Vec3::new(1.0, 2.0, 2.0), Vec3::splat(0.5), 1.0).unwrap());
    if fog {
        scene.set_fog(Some(
            Fog::new(FogMode::Exp2 { density: 0.2 }, Vec3::new(0.5, 0.6, 0.7)).unwrap(),
        ));
    }
    let cam = Camera::look_at(
        DVec3::new(0.4, 1.1, 2.4),
        DVec3::ZERO,
        DVec3::Y,
        50.0,
        0.1,
        100.0,
    )
    .unwrap();
    (scene, cam)
}

/// The colour bits of a 97 × 71 f32 render with `samples` per pixel (with a depth output if
/// asked).
fn color_bits(
    scene: &Scene,
    cam: &Camera,
    mode: ShadingMode,
    baseline: bool,
    threads: usize,
    depth: bool,
    samples: u32,
) -> Vec<u32> {
    let mut o = RenderOptions::new(97, 71);
    o.shading = mode;
    o.baseline_isa = baseline;
    o.threads = Some(threads);
    o.samples = samples;
    let f = render(scene, cam, &o, ColorFormat::F32, depth).unwrap();
    let ColorBuffer::F32(c) = f.color else {
        unreachable!()
    };
    c.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn textured_frames_are_identical_on_every_instruction_set_and_thread_count() {
    // The textured tile body has an AVX2 copy (its batches lit with wide lane loops): it
    // must give the baseline's bits, with every filter and wrap mode, vertex colours and a
    // normal map, shadows and fog, in every mode.
    for (mode, case) in MODES.into_iter().flat_map(|m| CASES.map(|c| (m, c))) {
        let (scene, cam) = mapped_sphere(case, mode, true);
        let frames: Vec<Vec<u32>> = [(false, 1), (true, 1), (false, 2), (true, 3)]
            .iter()
            .map(|&(baseline, threads)| color_bits(&scene, &cam, mode, baseline, threads, false, 1))
            .collect();
        for f in &frames[1..] {
            assert!(*f == frames[0], "{case:?} {mode:?} differs");
        }
    }
}

#[test]
fn multi_sampled_textured_frames_are_identical_on_every_instruction_set() {
    // Multi-sample tiles shade their textured layers with the AVX2 copy too (before, the
    // AVX2 body passed the baseline's to them): the same bits, every mode, filter and wrap,
    // with and without a depth output.
    for (mode, case) in MODES.into_iter().flat_map(|m| CASES.map(|c| (m, c))) {
        let (scene, cam) = mapped_sphere(case, mode, true);
        for depth in [false, true] {
            let wide = color_bits(&scene, &cam, mode, false, 2, depth, 4);
            let base = color_bits(&scene, &cam, mode, true, 1, depth, 4);
            assert!(wide == base, "{case:?} {mode:?} depth {depth} differs");
            let one = color_bits(&scene, &cam, mode, false, 2, depth, 1);
            assert!(wide != one, "{case:?} {mode:?}: 4 samples changed nothing");
        }
    }
}

#[test]
fn flat_and_gouraud_rows_give_the_batch_paths_bits() {
    // Without fog or a depth output, flat and Gouraud texture a tile row at a time; with a
    // depth output they go through the batches that Phong uses. Same operations per pixel,
    // so the same bits: every filter and wrap, vertex colours, shadows, both instruction
    // sets, and Phong with no light reaching the surface (shaded flat, so by rows too).
    for (mode, case) in [ShadingMode::Flat, ShadingMode::Gouraud]
        .into_iter()
        .flat_map(|m| CASES.map(|c| (m, c)))
    {
        let (scene, cam) = mapped_sphere(case, mode, false);
        for baseline in [false, true] {
            let rows = color_bits(&scene, &cam, mode, baseline, 2, false, 1);
            let batches = color_bits(&scene, &cam, mode, baseline, 2, true, 1);
            assert!(
                rows == batches,
                "{case:?} {mode:?} baseline {baseline} differs"
            );
        }
    }
}

/// With no light (or only black ones, which add nothing and are dropped) a textured
/// surface's lighting is its ambient term alone, so Phong shades it as flat does (once per
/// triangle, no per-pixel normals): the three modes' pictures are bit for bit the same, and
/// a black light changes no bit of any mode's picture.
#[test]
fn unlit_textured_surfaces_are_the_same_in_every_mode() {
    let mut checks = Vec::new();
    for j in 0..8 {
        for i in 0..8 {
            let c = if (i + j) % 2 == 0 { 0.9 } else { 0.1 };
            checks.extend([c, c * 0.5, 1.0 - c]);
        }
    }
    let img = texture::Image::from_top_rows(8, 8, 3, &checks, false).unwrap();
    let maps = Maps {
        diffuse: Some(Arc::new(Texture::from_image(
            Arc::new(img),
            Filter::Bilinear,
            [Wrap::Repeat; 2],
        ))),
        ..Maps::default()
    };
    let gold = Material::preset("gold").unwrap();
    let unlit = |black: bool| {
        let mut s = Scene::new(Vec3::splat(0.4)).unwrap();
        let obj = Object::new(Arc::new(primitives::plane()), gold, Mat4::IDENTITY)
            .unwrap()
            .with_maps(Some(Arc::new(maps.clone())))
            .unwrap();
        s.add_object(obj);
        if black {
            s.add_light(PointLight::new(Vec3::new(0.3, 1.0, 0.4), Vec3::ZERO, 1.0).unwrap());
        }
        s
    };
    let flat = f32_frame(&unlit(false), ShadingMode::Flat);
    assert!(flat.iter().any(|&c| c > 0.0), "the plane is drawn");
    for mode in MODES {
        for black in [false, true] {
            let got = f32_frame(&unlit(black), mode);
            assert!(
                got.iter()
                    .zip(&flat)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "{mode:?} black light {black}"
            );
        }
    }
}

/// A 16 × 8 map (powers of two, so `Repeat` wraps by a mask) as the only map of a sphere,
/// with `filter`, a (u, v) transform of scale `scale`, the material's emission `ke` and an
/// emission map when `emission_map`; `lit`: a sun with a shadow map and a point light, else
/// none.
fn diffuse_only_sphere(
    filter: Filter,
    scale: f64,
    ke: Vec3,
    emission_map: bool,
    lit: bool,
) -> (Scene, Camera) {
    let texels: Vec<f32> = (0..16 * 8)
        .flat_map(|k| {
            let (i, j) = (k % 16, k / 16);
            [
                i as f32 / 15.0,
                j as f32 / 7.0,
                ((i * 3 + j) % 5) as f32 / 4.0,
            ]
        })
        .collect();
    let img = Arc::new(texture::Image::from_top_rows(16, 8, 3, &texels, false).unwrap());
    // `mapped_sphere`'s mesh (without vertex colours when nearest), lights and camera.
    let (base, cam) = mapped_sphere((Filter::Nearest, Wrap::Repeat, 1), ShadingMode::Flat, false);
    let tex = Arc::new(
        Texture::from_image(img, filter, [Wrap::Repeat; 2]).with_uv_transform(
            glam::DVec2::new(scale, -0.75 * scale),
            glam::DVec2::new(0.3, -0.1),
        ),
    );
    let maps = Maps {
        diffuse: Some(tex.clone()),
        emission: emission_map.then(|| tex.clone()),
        ..Maps::default()
    };
    let mut material = Material::preset("jade").unwrap();
    material.emission = ke;
    let obj = Object::new(base.objects()[0].mesh().clone(), material, Mat4::IDENTITY)
        .unwrap()
        .with_maps(Some(Arc::new(maps)))
        .unwrap();
    let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
    scene.add_object(obj);
    if lit {
        scene.lights_mut().extend(base.lights().iter().cloned());
    }
    (scene, cam)
}

#[test]
fn diffuse_only_rows_give_the_batch_paths_bits() {
    // A diffuse image map alone, in any filter under `Repeat` on powers of two, goes
    // through the rows' register path with AVX2 (`textured::lean`): the same bits as the
    // batches (with a depth output) and as the baseline's rows. Coordinates beyond 2³¹
    // texels (scale 10¹⁰) take the sampler's general path mid-run; emission without a map
    // is added, an emission map with no emission is not read.
    let cases = [
        (1.0, Vec3::ZERO, false, true),
        (3.0, Vec3::new(0.05, 0.1, 0.0), false, true),
        (1.0, Vec3::ZERO, true, true),
        (1e10, Vec3::ZERO, false, true),
        (2.0, Vec3::ZERO, false, false),
    ];
    for filter in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
        for (scale, ke, emission_map, lit) in cases {
            let (scene, cam) = diffuse_only_sphere(filter, scale, ke, emission_map, lit);
            for mode in [ShadingMode::Flat, ShadingMode::Gouraud] {
                let what = format!(
                    "{filter:?} scale {scale} ke {ke} map {emission_map} lit {lit} {mode:?}"
                );
                let rows = color_bits(&scene, &cam, mode, false, 2, false, 1);
                assert!(rows.iter().any(|&b| b != 0), "{what}: drawn");
                for (baseline, depth) in [(false, true), (true, false), (true, true)] {
                    let other = color_bits(&scene, &cam, mode, baseline, 2, depth, 1);
                    assert!(
                        rows == other,
                        "{what}: baseline {baseline} depth {depth} differs"
                    );
                }
            }
        }
    }
}

#[test]
fn a_white_map_renders_as_no_map_on_back_faces() {
    // Seen from inside a two-sided sphere, every visible face is a back face, lit with the
    // flipped normal and the back material (textured Gouraud lights them before the tile
    // stage, `VertexTerms::back`).
    let back = Material::preset("ruby").unwrap();
    let cam = Camera::look_at(
        DVec3::new(0.1, 0.05, 0.0),
        DVec3::new(1.0, 0.3, 0.2),
        DVec3::Y,
        70.0,
        0.01,
        10.0,
    )
    .unwrap();
    let s = primitives::uv_sphere(16, 32);
    let uvs = s.positions().iter().map(|p| p.truncate()).collect();
    let mesh = Arc::new(
        Mesh::new(
            s.positions().to_vec(),
            s.indices().to_vec(),
            s.given_normals().map(<[Vec3]>::to_vec),
            Some(uvs),
        )
        .unwrap(),
    );
    let scene = |maps: Option<Maps>| {
        let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
        let obj = Object::new(
            mesh.clone(),
            Material::preset("gold").unwrap(),
            Mat4::IDENTITY,
        )
        .unwrap()
        .with_back_material(Some(back))
        .with_maps(maps.map(Arc::new))
        .unwrap();
        scene.add_object(obj);
        scene.add_light(PointLight::new(Vec3::new(0.2, 0.3, 0.1), Vec3::ONE, 1.0).unwrap());
        scene.set_two_sided(true);
        scene
    };
    let maps = Maps {
        diffuse: Some(solid(Vec3::ONE)),
        ..Maps::default()
    };
    let (plain, textured) = (scene(None), scene(Some(maps)));
    let frame = |s: &Scene, mode| {
        let mut o = RenderOptions::new(W, H);
        o.shading = mode;
        match render(s, &cam, &o, ColorFormat::F32, false).unwrap().color {
            ColorBuffer::F32(v) => v,
            ColorBuffer::U8(_) => unreachable!(),
        }
    };
    for mode in MODES {
        let (a, b) = (frame(&plain, mode), frame(&textured, mode));
        assert!(a.iter().all(|&c| c > 0.0), "{mode:?}: every pixel lit");
        // The split terms are summed in another order than the folded colour: a few ulps.
        let d = max_diff(&a, &b);
        assert!(d < 4e-5, "{mode:?}: {d}");
    }
}

#[test]
fn clip_made_vertices_are_lit_in_textured_gouraud() {
    // A floor reaching behind the camera: the near plane clips its two triangles, whose
    // pieces use clip-made vertices. Under a sun and without specular the lighting is the
    // same everywhere, so every vertex, clip-made or not, must carry it: the white-mapped
    // floor renders as the plain one (a vertex left unlit would darken its pieces).
    let m = Material::new(Vec3::splat(0.3), Vec3::splat(0.6), Vec3::ZERO, 1.0).unwrap();
    let cam = Camera::look_at(
        DVec3::new(0.0, 0.3, 0.0),
        DVec3::new(0.0, 0.0, -3.0),
        DVec3::Y,
        60.0,
        0.1,
        100.0,
    )
    .unwrap();
    let scene = |maps: Option<Maps>| {
        let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
        let obj = Object::new(
            Arc::new(primitives::plane()),
            m,
            Mat4::from_scale(Vec3::splat(20.0)),
        )
        .unwrap()
        .with_maps(maps.map(Arc::new))
        .unwrap();
        scene.add_object(obj);
        scene.add_light(DirectionalLight::new(Vec3::new(0.3, -1.0, -0.2), Vec3::ONE, 1.0).unwrap());
        scene
    };
    let maps = Maps {
        diffuse: Some(solid(Vec3::ONE)),
        ..Maps::default()
    };
    let mut o = RenderOptions::new(W, H);
    let frame = |s: &Scene, o: &RenderOptions| {
        let f = render(s, &cam, o, ColorFormat::F32, false).unwrap();
        let c = match f.color {
            ColorBuffer::F32(v) => v,
            ColorBuffer::U8(_) => unreachable!(),
        };
        (c, f.stats.triangles_clipped)
    };
    for mode in MODES {
        o.shading = mode;
        let (a, clipped) = frame(&scene(None), &o);
        let (b, _) = frame(&scene(Some(maps.clone())), &o);
        assert!(clipped > 0, "{mode:?}: the near plane clips the floor");
        let lit = a.chunks(3).filter(|c| c[0] > 0.25).count();
        assert!(
            lit > (W * H / 3) as usize,
            "{mode:?}: the floor covers the lower half"
        );
        let d = max_diff(&a, &b);
        assert!(d < 1e-5, "{mode:?}: {d}");
    }
}
