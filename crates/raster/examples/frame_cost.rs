//! Renders one scene a few times on one thread, for instruction counts under callgrind
//! (stable on a noisy machine, unlike timings):
//!
//! ```text
//! cargo build --release --example frame_cost
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null \
//!     target/release/examples/frame_cost phong 99 1080 lights=sun,point fog frames=2
//! ```
//!
//! Arguments: shading mode, sphere rings (segments = 2·rings), image height (16:9), then any
//! of `lights=none|sun|point|spot|area` (comma-separated), `fog`, `two-sided`, `depth`,
//! `f32`, `frames=N`, `stats` (print each stage's median time over the frames), `samples=N`
//! (multi-sample anti-aliasing), `plane` (a ground plane under the sphere, for shadows to fall on),
//! `shadows=map|plain|exact` (every light casts shadows: a default map, a map with
//! `filter="none"`, or rays), `texture=nearest|bilinear|trilinear` (every object gets planar
//! UVs, u = 4x, v = 4z, and a 64 × 64 checkerboard diffuse map with that filter) and
//! `aniso=N` (its anisotropy); `spot=PATH` replaces the sphere by that OBJ's mesh (its normals
//! if it has them), seen from `bench/speed_error.py`'s Spot camera at 1:1 (`bench/spot_obj.py`
//! writes Spot's subdivided levels); `floor` replaces the sphere scene by `bench/bench_textures.py`'s
//! (an unlit textured floor to the horizon at 4:3, with `texture=`'s filter, nearest by
//! default; the sphere's rings are then unused); `mirror` replaces it by
//! `bench/bench_reflect.py`'s mirror floor under a red sphere (4:3, its environment looked
//! up along the mirror directions; the rings are unused), and `glass` adds that report's glass
//! ball in front (reflected and refracted look-ups; `fog` fogs both scenes after the
//! look-ups), `opaque` makes both scenes' materials plain (the report's "none" rows: what
//! the optics cost); `dump=PATH` writes the last frame's
//! colour samples there (raw u8, or f32 little-endian with `f32`, row-major RGB), for
//! comparing builds; `explain=TOL` runs only `shading="auto"`'s estimate (at that
//! tolerance) `frames` times. Prints a checksum of the last frame so the work cannot be
//! optimised away.

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec2, Vec3};
use shadelab_raster::*;

fn main() -> std::result::Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode: ShadingMode = args.first().map_or("phong", |s| s.as_str()).parse()?;
    let height: u32 = args.get(2).map_or(Ok(1080), |s| s.parse())?;
    let flag = |name: &str| args.iter().any(|a| a == name);
    let value = |key: &str| {
        args.iter()
            .find_map(|a| a.strip_prefix(key).map(str::to_owned))
    };
    let frames: usize = value("frames=").map_or(Ok(2), |s| s.parse())?;
    let texture = value("texture=").or_else(|| flag("floor").then(|| "nearest".to_owned()));
    let maps = match texture {
        None => None,
        Some(name) => {
            let filter = Filter::from_name(&name).ok_or(format!("unknown filter {name}"))?;
            let aniso: u32 = value("aniso=").map_or(Ok(1), |s| s.parse())?;
            let texels: Vec<f32> = (0..64 * 64)
                .flat_map(|k| {
                    let c = if (k % 64 / 8 + k / 64 / 8) % 2 == 0 {
                        0.9
                    } else {
                        0.1
                    };
                    [c; 3]
                })
                .collect();
            let image = texture::Image::from_top_rows(64, 64, 3, &texels, false)?;
            let tex = Texture::from_image(Arc::new(image), filter, [Wrap::Repeat; 2])
                .with_anisotropy(aniso)?;
            Some(Arc::new(Maps {
                diffuse: Some(Arc::new(tex)),
                ..Maps::default()
            }))
        }
    };
    // With a texture: the same mesh with planar UVs (u = 4x, v = 4z).
    let place = |mesh: Mesh, material: &str, transform: Mat4| -> Result<Object> {
        let mesh = match &maps {
            None => mesh,
            Some(_) => {
                let uvs = mesh
                    .positions()
                    .iter()
                    .map(|p| Vec2::new(4.0 * p.x, 4.0 * p.z));
                Mesh::new(
                    mesh.positions().to_vec(),
                    mesh.indices().to_vec(),
                    mesh.given_normals().map(<[Vec3]>::to_vec),
                    Some(uvs.collect()),
                )?
            }
        };
        Object::new(Arc::new(mesh), Material::preset(material)?, transform)?.with_maps(maps.clone())
    };
    let (scene, camera, width) = if flag("floor") {
        floor_scene(maps.clone(), height)?
    } else if flag("mirror") || flag("glass") {
        mirror_scene(flag("glass"), flag("opaque"), flag("fog"), height)?
    } else {
        sphere_scene(&args, place)?
    };
    let mut options = RenderOptions::new(width, height);
    options.shading = mode;
    options.threads = Some(1);
    if let Some(n) = value("samples=") {
        options.samples = n.parse()?;
    }
    if flag("mirror") || flag("glass") {
        options.reflections = Technique::Environment;
        options.refractions = flag("glass").then_some(Technique::Environment);
    }
    let format = if flag("f32") {
        ColorFormat::F32
    } else {
        ColorFormat::U8
    };
    let mut sum = 0.0f64;
    if let Some(tol) = value("explain=") {
        // `shading="auto"`'s estimate alone, `frames` times.
        for _ in 0..frames {
            let e = explain_shading(&scene, &camera, &options, tol.parse()?)?;
            sum += e
                .iter()
                .map(|e| e.estimates.iter().sum::<f32>() as f64)
                .sum::<f64>();
        }
        println!("checksum {sum}");
        return Ok(());
    }
    let mut stages: Vec<[f64; 3]> = Vec::with_capacity(frames);
    for f in 0..frames {
        let frame = render(&scene, &camera, &options, format, flag("depth"))?;
        let t = &frame.stats.timings;
        stages.push([t.vertex, t.setup, t.raster_shade].map(|d| d.as_secs_f64() * 1e3));
        // The last frame's only: summing every frame was a quarter of a profile's samples.
        if f + 1 < frames {
            continue;
        }
        if let Some(path) = value("dump=") {
            let bytes: Vec<u8> = match &frame.color {
                ColorBuffer::U8(c) => c.clone(),
                ColorBuffer::F32(c) => c.iter().flat_map(|v| v.to_le_bytes()).collect(),
            };
            std::fs::write(path, bytes)?;
        }
        sum = match &frame.color {
            ColorBuffer::U8(c) => c.iter().map(|&v| v as f64).sum(),
            ColorBuffer::F32(c) => c.iter().map(|&v| v as f64).sum(),
        };
    }
    if flag("stats") {
        // Median per stage over the frames (timings on a noisy machine: compare runs
        // alternated in one sitting).
        let median = |k: usize| {
            let mut v: Vec<f64> = stages.iter().map(|s| s[k]).collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        println!(
            "median ms: vertex {:.3} setup {:.3} raster_shade {:.3}",
            median(0),
            median(1),
            median(2)
        );
    }
    println!("checksum {sum}");
    Ok(())
}

/// The fog of every scene here that asks for one (`fog`): exp2, density 0.3, blue-grey.
fn bench_fog() -> Result<Fog> {
    Fog::new(FogMode::Exp2 { density: 0.3 }, Vec3::new(0.5, 0.6, 0.7))
}

/// `bench/bench_textures.py`'s scene: a 80 × 82 floor (u = x/2, v = −z/2) under a white
/// ambient light and a black sun, so each pixel is its texture; seen from (0, 1, 2) towards
/// (0, 0, −8), 60° vertically, at 4:3.
fn floor_scene(maps: Option<Arc<Maps>>, height: u32) -> Result<(Scene, Camera, u32)> {
    let e = 40.0;
    let p = vec![
        Vec3::new(-e, 0.0, 2.0),
        Vec3::new(e, 0.0, 2.0),
        Vec3::new(e, 0.0, -2.0 * e),
        Vec3::new(-e, 0.0, -2.0 * e),
    ];
    let uv = p.iter().map(|p| Vec2::new(0.5 * p.x, -0.5 * p.z)).collect();
    let mesh = Mesh::new(
        p,
        vec![[0, 1, 2], [0, 2, 3]],
        Some(vec![Vec3::Y; 4]),
        Some(uv),
    )?;
    let material = Material::new(Vec3::ONE, Vec3::ZERO, Vec3::ZERO, 1.0)?;
    let mut scene = Scene::new(Vec3::ONE)?;
    scene.add_object(Object::new(Arc::new(mesh), material, Mat4::IDENTITY)?.with_maps(maps)?);
    scene.add_light(DirectionalLight::new(Vec3::NEG_Y, Vec3::ZERO, 1.0)?);
    let camera = Camera::look_at(
        DVec3::new(0.0, 1.0, 2.0),
        DVec3::new(0.0, 0.0, -8.0),
        DVec3::Y,
        60.0,
        0.05,
        200.0,
    )?;
    Ok((scene, camera, height * 4 / 3))
}

/// `bench/bench_reflect.py`'s scenes (`tests/test_reflect.py`'s): a 5 × 5 mirror floor
/// (reflectivity 0.8) under a red sphere, a smooth 64 × 32 sky, one sun; with `glass`, a
/// glass ball (transparency 0.9, ior 1.5, Fresnel) in front. Seen from (0, 1.6, 3.4) towards
/// (0, 0.3, 0), 45° vertically, at 4:3.
fn mirror_scene(glass: bool, opaque: bool, fog: bool, height: u32) -> Result<(Scene, Camera, u32)> {
    let optics = |m: Material, r: f32, t: f32| {
        if opaque {
            Ok(m)
        } else {
            m.with_optics(Vec3::splat(r), t, 1.5, true, Vec3::ZERO)
        }
    };
    let h = 32;
    let sky: Vec<f32> = (0..h * 2 * h)
        .flat_map(|k| {
            let v = ((k / (2 * h)) as f32 + 0.5) / h as f32;
            let u = ((k % (2 * h)) as f32 + 0.5) / (2 * h) as f32;
            let s = (std::f32::consts::TAU * u).sin();
            [0.2 + 0.8 * (1.0 - v), 0.3 + 0.5 * s * s, 0.2 + 0.6 * v * u]
        })
        .collect();
    let mut scene = Scene::new(Vec3::splat(0.15))?;
    scene.set_environment(Some(Environment::new(&sky, h, 2 * h, 0.0, 1.0)?));
    let red = Material::new(
        Vec3::new(0.2, 0.05, 0.05),
        Vec3::new(0.8, 0.15, 0.1),
        Vec3::splat(0.4),
        30.0,
    )?;
    let sphere = Arc::new(primitives::uv_sphere(24, 48));
    let at = |s: f32, c: Vec3| Mat4::from_translation(c) * Mat4::from_scale(Vec3::splat(s));
    scene.add_object(Object::new(sphere, red, at(0.6, Vec3::new(0.0, 0.7, 0.0)))?);
    let mirror = optics(
        Material::new(Vec3::splat(0.05), Vec3::splat(0.2), Vec3::ZERO, 1.0)?,
        0.8,
        0.0,
    )?;
    scene.add_object(Object::new(
        Arc::new(primitives::plane()),
        mirror,
        Mat4::from_scale(Vec3::new(2.5, 1.0, 2.5)),
    )?);
    if glass {
        let glass = optics(
            Material::new(Vec3::ZERO, Vec3::splat(0.05), Vec3::splat(0.8), 120.0)?,
            0.0,
            0.9,
        )?;
        scene.add_object(Object::new(
            Arc::new(primitives::uv_sphere(32, 64)),
            glass,
            at(0.45, Vec3::new(0.55, 0.55, 0.9)),
        )?);
    }
    if fog {
        // Mixed in the secondary stage, after the look-ups.
        scene.set_fog(Some(bench_fog()?));
    }
    scene.add_light(DirectionalLight::new(
        Vec3::new(-0.4, -1.0, -0.6),
        Vec3::ONE,
        0.9,
    )?);
    let camera = Camera::look_at(
        DVec3::new(0.0, 1.6, 3.4),
        DVec3::new(0.0, 0.3, 0.0),
        DVec3::Y,
        45.0,
        0.1,
        100.0,
    )?;
    Ok((scene, camera, height * 4 / 3))
}

/// The sphere scene (see the module's doc), its lights, fog and two-sidedness from `args`.
fn sphere_scene(
    args: &[String],
    place: impl Fn(Mesh, &str, Mat4) -> Result<Object>,
) -> std::result::Result<(Scene, Camera, u32), Box<dyn std::error::Error>> {
    let flag = |name: &str| args.iter().any(|a| a == name);
    let value = |key: &str| {
        args.iter()
            .find_map(|a| a.strip_prefix(key).map(str::to_owned))
    };
    let rings: u32 = args.get(1).map_or(Ok(99), |s| s.parse())?;
    let height: u32 = args.get(2).map_or(Ok(1080), |s| s.parse())?;
    let lights = value("lights=").unwrap_or_else(|| "sun".to_owned());
    let shadows = match value("shadows=").as_deref() {
        None => Shadows::Off,
        Some("map") => Shadows::Map(ShadowSettings::default()),
        Some("plain") => Shadows::Map(ShadowSettings::new(2048, ShadowFilter::None, 1.0)?),
        Some("exact") => Shadows::Exact,
        Some(other) => return Err(format!("unknown shadows {other}").into()),
    };
    let spot = value("spot=");
    let mesh = match &spot {
        Some(path) => load_obj(path)?,
        None => primitives::uv_sphere(rings, 2 * rings),
    };
    let mut scene = Scene::new(Vec3::splat(0.2))?;
    scene.add_object(place(mesh, "gold", Mat4::IDENTITY)?);
    if flag("plane") {
        scene.add_object(place(
            primitives::plane(),
            "white plastic",
            Mat4::from_translation(Vec3::new(0.0, -1.2, 0.0)) * Mat4::from_scale(Vec3::splat(6.0)),
        )?);
    }
    for kind in lights.split(',') {
        match kind {
            "none" => {}
            "sun" => scene.add_light(
                DirectionalLight::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE, 1.0)?
                    .with_shadows(shadows),
            ),
            "point" => scene.add_light(
                PointLight::new(Vec3::new(2.0, 3.0, 4.0), Vec3::splat(0.5), 1.0)?
                    .with_attenuation(1.0, 0.05, 0.01)?
                    .with_shadows(shadows),
            ),
            "spot" => scene.add_light(
                SpotLight::new(
                    PointLight::new(Vec3::new(0.0, 3.0, 1.0), Vec3::ONE, 1.0)?,
                    Vec3::new(0.0, -3.0, -1.0),
                    30.0,
                    2.0,
                )?
                .with_inner(20.0)?,
            ),
            "area" => scene.add_light(
                AreaLight::new(
                    Vec3::new(0.0, 2.0, 2.0),
                    Vec3::X,
                    Vec3::new(0.0, 0.5, -0.5),
                    AreaShape::Rectangle,
                    4,
                )?
                .with_one_sided(true),
            ),
            other => return Err(format!("unknown light kind {other}").into()),
        }
    }
    if flag("fog") {
        scene.set_fog(Some(bench_fog()?));
    }
    scene.set_two_sided(flag("two-sided"));
    if spot.is_some() {
        // `bench/speed_error.py`'s SPOT_CAMERA, square.
        let camera = Camera::look_at(
            DVec3::new(1.6, 0.9, 2.6),
            DVec3::new(0.0, 0.05, 0.0),
            DVec3::Y,
            40.0,
            0.5,
            10.0,
        )?;
        return Ok((scene, camera, height));
    }
    let camera = Camera::look_at(
        DVec3::new(0.0, 0.0, 2.6),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        0.1,
        100.0,
    )?;
    Ok((scene, camera, height * 16 / 9))
}
