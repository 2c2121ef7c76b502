//! End-to-end properties of the pipeline against analytic values: near-plane clipping,
//! perspective-correct interpolation, depth, lighting and determinism.

mod common;

use std::sync::Arc;

use common::*;
use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::*;

const W: u32 = 96;
const H: u32 = 64;

/// Perspective camera at the origin looking down −z.
fn origin_camera(near: f64, far: f64) -> Camera {
    Camera::look_at(DVec3::ZERO, -DVec3::Z, DVec3::Y, 60.0, near, far).unwrap()
}

/// The eye-space ray through screen point (sx, sy), with z = −1 (so t = eye depth).
fn screen_ray(sx: f64, sy: f64) -> DVec3 {
    let t = (30f64).to_radians().tan();
    let aspect = W as f64 / H as f64;
    let nx = 2.0 * sx / W as f64 - 1.0;
    let ny = 1.0 - 2.0 * sy / H as f64;
    DVec3::new(nx * t * aspect, ny * t, -1.0)
}

/// Vertices are snapped to 1/256 px, which moves a triangle's interpolated values as if the
/// sample point moved by up to about this much.
const SNAP_PX: f64 = 1.0 / 256.0;

/// Barycentrics of `p` in triangle (a, b, c) (all in the plane y = const).
fn bary_xz(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> [f64; 3] {
    let area = |p: DVec3, q: DVec3, r: DVec3| (q.x - p.x) * (r.z - p.z) - (q.z - p.z) * (r.x - p.x);
    let t = area(a, b, c);
    [area(p, b, c) / t, area(a, p, c) / t, area(a, b, p) / t]
}

/// A floor triangle at y = −1 that reaches behind the camera (crossing the near plane).
fn floor() -> [DVec3; 3] {
    [
        DVec3::new(-30.0, -1.0, 5.0),
        DVec3::new(30.0, -1.0, 5.0),
        DVec3::new(0.0, -1.0, -40.0),
    ]
}

fn floor_scene(normals: [Vec3; 3], specular: Vec3) -> Scene {
    let p = floor().map(|v| v.as_vec3()).to_vec();
    let mesh = Mesh::new(p, vec![[0, 1, 2]], Some(normals.to_vec()), None).unwrap();
    let mut scene = Scene::new(Vec3::splat(0.5)).unwrap();
    let m = Material::new(
        Vec3::new(0.2, 0.1, 0.0),
        Vec3::new(0.6, 0.8, 1.0),
        specular,
        8.0,
    )
    .unwrap();
    scene.add(Arc::new(mesh), m, Mat4::IDENTITY).unwrap();
    scene.add_light(DirectionalLight::new(-Vec3::Y, Vec3::ONE, 1.0).unwrap());
    scene
}

/// Eye depth and barycentrics of the floor hit seen through screen point (sx, sy).
fn floor_hit(sx: f64, sy: f64) -> Option<(f64, [f64; 3])> {
    let [a, b, c] = floor();
    let d = screen_ray(sx, sy);
    if d.y >= -1e-9 {
        return None;
    }
    let t = -1.0 / d.y;
    Some((t, bary_xz(d * t, a, b, c)))
}

/// Visits the pixels whose ray hits the floor triangle well inside its edges. `f` gets the
/// pixel index and a function giving (eye depth, barycentrics) at sub-pixel offsets from
/// the centre, so tests can bound the effect of vertex snapping.
fn for_floor_hits(mut f: impl FnMut(usize, &dyn Fn(f64, f64) -> (f64, [f64; 3]))) -> usize {
    let mut n = 0;
    for y in 0..H {
        for x in 0..W {
            let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
            let Some((t, l)) = floor_hit(cx, cy) else {
                continue;
            };
            // Stay clear of the triangle's edges (in barycentric terms) and the near plane.
            if l.iter().all(|&v| v > 0.01) && t > 0.2 {
                let at = |dx: f64, dy: f64| floor_hit(cx + dx, cy + dy).expect("near the centre");
                f((y * W + x) as usize, &at);
                n += 1;
            }
        }
    }
    n
}

/// The largest change of `g` when the sample point moves by [`SNAP_PX`] in x or y.
fn snap_tolerance(
    at: &dyn Fn(f64, f64) -> (f64, [f64; 3]),
    g: impl Fn((f64, [f64; 3])) -> f64,
) -> f64 {
    let c = g(at(0.0, 0.0));
    [
        (SNAP_PX, 0.0),
        (-SNAP_PX, 0.0),
        (0.0, SNAP_PX),
        (0.0, -SNAP_PX),
    ]
    .iter()
    .map(|&(dx, dy)| (g(at(dx, dy)) - c).abs())
    .fold(0.0, f64::max)
}

#[test]
fn near_plane_crossing_triangle_matches_ray_cast() {
    let normals = [Vec3::Y; 3];
    let scene = floor_scene(normals, Vec3::ZERO);
    let mut opts = RenderOptions::new(W, H);
    opts.shading = ShadingMode::Flat;
    let f = render(
        &scene,
        &origin_camera(0.1, 100.0),
        &opts,
        ColorFormat::F32,
        true,
    )
    .unwrap();
    assert_eq!(f.stats.triangles_clipped, 1);
    let depth = f.depth.unwrap();
    let n = for_floor_hits(|i, at| {
        let t = at(0.0, 0.0).0;
        let tol = 1e-5 * t + snap_tolerance(at, |(t, _)| t);
        assert!(
            (depth[i] as f64 - t).abs() <= tol,
            "pixel {i}: depth {} vs {t}",
            depth[i]
        );
    });
    assert!(n > 1000, "{n}");
    // Upper half of the image (rays going up) sees nothing.
    assert!(depth[..(W * H / 2 - W) as usize]
        .iter()
        .all(|d| d.is_infinite()));
}

#[test]
fn triangle_behind_camera_draws_nothing() {
    let p = vec![
        Vec3::new(-1.0, -1.0, 2.0),
        Vec3::new(1.0, -1.0, 2.0),
        Vec3::new(0.0, 1.0, 2.0),
    ];
    let scene = white_scene(Mesh::new(p, vec![[0, 1, 2]], None, None).unwrap());
    let (c, d) = render_f32(&scene, &origin_camera(0.1, 10.0), &RenderOptions::new(W, H));
    assert!(c.iter().all(|&v| v == 0.0) && d.iter().all(|v| v.is_infinite()));
}

#[test]
fn gouraud_interpolation_is_perspective_correct() {
    // Vertex normals tilt away from the overhead light, so the three vertex colours differ;
    // across the receding floor the colour must be the world-space barycentric blend.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let normals = [Vec3::Y, Vec3::new(s, s, 0.0), Vec3::X];
    let scene = floor_scene(normals, Vec3::ZERO);
    let mut opts = RenderOptions::new(W, H);
    opts.shading = ShadingMode::Gouraud;
    let (c, _) = render_f32(&scene, &origin_camera(0.1, 100.0), &opts);
    let ka_ia = [0.1, 0.05, 0.0];
    let kd = [0.6, 0.8, 1.0];
    let ndl = [1.0, s as f64, 0.0];
    let n = for_floor_hits(|i, at| {
        for ch in 0..3 {
            let colour = |(_, l): (f64, [f64; 3])| -> f64 {
                (0..3).map(|k| l[k] * (ka_ia[ch] + kd[ch] * ndl[k])).sum()
            };
            let want = colour(at(0.0, 0.0));
            let tol = 1e-5 + snap_tolerance(at, colour);
            let got = c[i * 3 + ch] as f64;
            assert!(
                (got - want).abs() <= tol,
                "pixel {i} ch {ch}: {got} vs {want}"
            );
        }
    });
    assert!(n > 1000);
}

#[test]
fn phong_interpolation_renormalises_per_pixel() {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let normals = [Vec3::Y, Vec3::new(s, s, 0.0), Vec3::X];
    let scene = floor_scene(normals, Vec3::ZERO);
    let (c, _) = render_f32(
        &scene,
        &origin_camera(0.1, 100.0),
        &RenderOptions::new(W, H),
    );
    let nv = normals.map(|v| v.as_dvec3());
    let n = for_floor_hits(|i, at| {
        for (ch, (ka_ia, kd)) in [(0.1, 0.6), (0.05, 0.8), (0.0, 1.0)]
            .into_iter()
            .enumerate()
        {
            let colour = |(_, l): (f64, [f64; 3])| -> f64 {
                let n = (nv[0] * l[0] + nv[1] * l[1] + nv[2] * l[2]).normalize();
                ka_ia + kd * n.y
            };
            let want = colour(at(0.0, 0.0));
            let tol = 1e-5 + snap_tolerance(at, colour);
            let got = c[i * 3 + ch] as f64;
            assert!((got - want).abs() <= tol, "pixel {i}: {got} vs {want}");
        }
    });
    assert!(n > 1000);
}

#[test]
fn nearer_surface_wins_in_any_order_and_ties_go_to_the_first() {
    let (w, h) = (16, 16);
    let cam = pixel_camera(w, h);
    let square = |z: f32| {
        let p = vec![
            Vec3::new(-1.0, -1.0, z),
            Vec3::new(20.0, -1.0, z),
            Vec3::new(20.0, 20.0, z),
            Vec3::new(-1.0, 20.0, z),
        ];
        Arc::new(Mesh::new(p, vec![[0, 1, 2], [0, 2, 3]], None, None).unwrap())
    };
    let flat = |r: f32| Material::new(Vec3::new(r, 0.0, 0.0), Vec3::ZERO, Vec3::ZERO, 1.0).unwrap();
    for (first, second, want) in [(0.0, 1.0, 0.5), (1.0, 0.0, 0.25), (0.5, 0.5, 0.25)] {
        let mut scene = Scene::new(Vec3::ONE).unwrap();
        scene
            .add(square(first), flat(0.25), Mat4::IDENTITY)
            .unwrap();
        scene
            .add(square(second), flat(0.5), Mat4::IDENTITY)
            .unwrap();
        let (c, d) = render_f32(&scene, &cam, &RenderOptions::new(w, h));
        let near_z = f32::max(first, second);
        assert!(c.chunks(3).all(|p| p[0] == want), "{first} {second}");
        // Eye at z = 10: depth is 10 − z.
        assert!(
            d.iter().all(|&v| (v - (10.0 - near_z)).abs() < 1e-5),
            "{:?}",
            d[0]
        );
    }
}

#[test]
fn lighting_matches_hand_computed_values() {
    let (w, h) = (16, 16);
    let cam = pixel_camera(w, h);
    let p = vec![
        Vec3::new(-8.0, -8.0, 0.0),
        Vec3::new(24.0, -8.0, 0.0),
        Vec3::new(24.0, 24.0, 0.0),
        Vec3::new(-8.0, 24.0, 0.0),
    ];
    let mesh = Arc::new(Mesh::new(p, vec![[0, 1, 2], [0, 2, 3]], None, None).unwrap());
    let m = Material::new(
        Vec3::new(0.1, 0.2, 0.3),
        Vec3::new(0.5, 0.6, 0.7),
        Vec3::splat(0.25),
        10.0,
    )
    .unwrap();
    let mut scene = Scene::new(Vec3::splat(0.5)).unwrap();
    scene.add(mesh, m, Mat4::IDENTITY).unwrap();
    scene.add_light(DirectionalLight::new(-Vec3::Z, Vec3::ONE, 1.0).unwrap());
    // Flat: each triangle is lit at its centroid, (40/3, 8/3) or (8/3, 40/3), seen from the
    // eye at (8, 8, 10): n·l = 1 and n·h = cos(θ/2), θ the angle between v and the normal.
    let mut opts = RenderOptions::new(w, h);
    opts.shading = ShadingMode::Flat;
    let (c, _) = render_f32(&scene, &cam, &opts);
    let v = (DVec3::new(8.0, 8.0, 10.0) - DVec3::new(40.0 / 3.0, 8.0 / 3.0, 0.0)).normalize();
    let spec = 0.25 * (v + DVec3::Z).normalize().z.powf(10.0);
    let want = [0.05 + 0.5 + spec, 0.1 + 0.6 + spec, 0.15 + 0.7 + spec];
    for px in c.chunks(3) {
        for ch in 0..3 {
            assert!(
                (px[ch] as f64 - want[ch]).abs() < 1e-6,
                "{px:?} vs {want:?}"
            );
        }
    }
    // Phong: the highlight is exactly 0.25 only below the eye; elsewhere
    // n·h = cos(θ/2) with θ the angle between v and the normal.
    let (c, _) = render_f32(&scene, &cam, &RenderOptions::new(w, h));
    for y in 0..h {
        for x in 0..w {
            let p = DVec3::new(x as f64 + 0.5, h as f64 - y as f64 - 0.5, 0.0);
            let v = (DVec3::new(8.0, 8.0, 10.0) - p).normalize();
            let nh = (v + DVec3::Z).normalize().z;
            let spec = 0.25 * nh.powf(10.0);
            let i = ((y * w + x) * 3) as usize;
            assert!((c[i] as f64 - (0.55 + spec)).abs() < 1e-5, "({x},{y})");
        }
    }
}

/// Three overlapping objects, a directional and a point light.
fn busy_scene() -> (Scene, Camera) {
    let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
    let sphere = Arc::new(primitives::uv_sphere(150, 300));
    scene
        .add(
            sphere.clone(),
            Material::preset("gold").unwrap(),
            Mat4::IDENTITY,
        )
        .unwrap();
    let t = Mat4::from_scale_rotation_translation(
        Vec3::new(0.6, 0.3, 0.9),
        glam::Quat::from_rotation_y(0.7),
        Vec3::new(0.5, 0.2, 0.4),
    );
    scene
        .add(
            Arc::new(primitives::cube()),
            Material::preset("chrome").unwrap(),
            t,
        )
        .unwrap();
    scene
        .add(
            sphere,
            Material::preset("copper").unwrap(),
            Mat4::from_translation(Vec3::new(-0.4, 0.0, 0.5)),
        )
        .unwrap();
    scene.add_light(DirectionalLight::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE, 1.0).unwrap());
    scene.add_light(PointLight::new(Vec3::new(2.0, 3.0, 4.0), Vec3::splat(0.5), 1.0).unwrap());
    let cam = Camera::look_at(
        DVec3::new(0.5, 0.7, 2.5),
        DVec3::ZERO,
        DVec3::Y,
        50.0,
        0.5,
        10.0,
    )
    .unwrap();
    (scene, cam)
}

/// Small scenes are split into finer work items on more threads (`chunk_len`): the
/// 89,400-triangle spheres in chunks of 8,192 triangles on 1 and 2 threads, of 7,450 on 3,
/// 5,588 on 4 and 2,794 on 8; the close camera's near plane cuts the spheres, so clip-made
/// vertices land in differently split chunks too.
#[test]
fn identical_bytes_for_any_thread_count() {
    let (scene, far) = busy_scene();
    let near = Camera::look_at(
        DVec3::new(0.3, 0.2, 1.05),
        DVec3::ZERO,
        DVec3::Y,
        60.0,
        0.5,
        10.0,
    )
    .unwrap();
    for (mode, cam) in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong]
        .into_iter()
        .flat_map(|m| [(m, &far), (m, &near)])
    {
        let mut reference = None;
        for threads in [1, 2, 3, 4, 8, 1] {
            let mut opts = RenderOptions::new(333, 207);
            opts.shading = mode;
            opts.threads = Some(threads);
            let f = render(&scene, cam, &opts, ColorFormat::F32, true).unwrap();
            if threads == 1 && std::ptr::eq(cam, &near) {
                assert!(
                    f.stats.triangles_clipped > 0,
                    "the near camera clips nothing"
                );
            }
            let bits: Vec<u32> = match &f.color {
                ColorBuffer::F32(c) => c
                    .iter()
                    .chain(f.depth.as_ref().unwrap())
                    .map(|v| v.to_bits())
                    .collect(),
                ColorBuffer::U8(_) => unreachable!(),
            };
            match &reference {
                None => reference = Some(bits),
                Some(r) => assert!(r == &bits, "{mode:?} with {threads} threads differs"),
            }
        }
    }
}

/// Colour (as bits, u8 widened) and depth bits of one render.
fn frame_bits(scene: &Scene, cam: &Camera, opts: &RenderOptions, format: ColorFormat) -> Vec<u32> {
    let f = render(scene, cam, opts, format, true).unwrap();
    let color: Vec<u32> = match &f.color {
        ColorBuffer::F32(c) => c.iter().map(|v| v.to_bits()).collect(),
        ColorBuffer::U8(c) => c.iter().map(|&v| v as u32).collect(),
    };
    let depth = f.depth.unwrap();
    color
        .into_iter()
        .chain(depth.iter().map(|v| v.to_bits()))
        .collect()
}

#[test]
fn identical_bytes_for_any_instruction_set() {
    // The AVX2 build of the tile passes against the baseline one (the same on CPUs without
    // AVX2, where this checks nothing new), in every mode and with every per-pixel feature.
    let (mut scene, cam) = busy_scene();
    let spot = PointLight::new(Vec3::new(-1.0, 2.0, 1.5), Vec3::new(0.3, 0.6, 0.2), 1.0)
        .unwrap()
        .with_attenuation(1.0, 0.2, 0.05)
        .unwrap();
    scene.add_light(SpotLight::new(spot, Vec3::new(1.0, -2.0, -1.5), 30.0, 4.0).unwrap());
    for fog in [
        None,
        Some(Fog::new(FogMode::Exp2 { density: 0.3 }, Vec3::new(0.5, 0.6, 0.7)).unwrap()),
    ] {
        for two_sided in [false, true] {
            scene.set_fog(fog);
            scene.set_two_sided(two_sided);
            for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
                for format in [ColorFormat::U8, ColorFormat::F32] {
                    let mut opts = RenderOptions::new(333, 207);
                    opts.shading = mode;
                    opts.background = Vec3::new(0.1, 0.2, 0.3);
                    let auto = frame_bits(&scene, &cam, &opts, format);
                    opts.baseline_isa = true;
                    let baseline = frame_bits(&scene, &cam, &opts, format);
                    assert!(
                        auto == baseline,
                        "{mode:?} {format:?} fog {fog:?} two-sided {two_sided} differs"
                    );
                }
            }
        }
    }
}

#[test]
fn every_output_sample_is_written() {
    // `render` does not zero its buffers, relying on the pipeline writing every sample:
    // render_into over buffers pre-filled with two different sentinels must give the same
    // bytes as render, in every mode, with and without depth, fog and visible background.
    let (mut scene, cam) = busy_scene();
    for fog in [
        None,
        Some(
            Fog::new(
                FogMode::Linear {
                    start: 1.0,
                    end: 4.0,
                },
                Vec3::splat(0.5),
            )
            .unwrap(),
        ),
    ] {
        scene.set_fog(fog);
        for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
            // 333 x 207: partial tiles on the right and bottom edges.
            let mut opts = RenderOptions::new(333, 207);
            opts.shading = mode;
            let n = 333 * 207;
            for with_depth in [false, true] {
                let f = render(&scene, &cam, &opts, ColorFormat::F32, with_depth).unwrap();
                let ColorBuffer::F32(want) = &f.color else {
                    unreachable!()
                };
                for sentinel in [f32::NAN, -7.0] {
                    let mut c = vec![sentinel; n * 3];
                    let mut d = vec![sentinel; n];
                    let depth = with_depth.then_some(&mut d[..]);
                    render_into(&scene, &cam, &opts, &mut c, depth).unwrap();
                    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&c), bits(want), "{mode:?} fog {fog:?}");
                    if with_depth {
                        assert_eq!(bits(&d), bits(f.depth.as_ref().unwrap()), "{mode:?}");
                    }
                }
                let f8 = render(&scene, &cam, &opts, ColorFormat::U8, with_depth).unwrap();
                let ColorBuffer::U8(want8) = &f8.color else {
                    unreachable!()
                };
                for sentinel in [0u8, 0xAB] {
                    let mut c = vec![sentinel; n * 3];
                    render_into(&scene, &cam, &opts, &mut c, None).unwrap();
                    assert!(&c == want8, "{mode:?} fog {fog:?} uint8");
                }
            }
        }
    }
}

#[test]
fn sizes_are_validated_before_allocation() {
    let scene = Scene::new(Vec3::ZERO).unwrap();
    let cam = origin_camera(0.1, 1.0);
    for (w, h) in [
        (0, 10),
        (10, 0),
        (200_000, 200_000),
        (MAX_IMAGE_SIZE + 1, 1),
    ] {
        let e = render(
            &scene,
            &cam,
            &RenderOptions::new(w, h),
            ColorFormat::U8,
            false,
        )
        .unwrap_err();
        assert!(matches!(e, RasterError::InvalidInput(_)), "{e}");
    }
    let mut opts = RenderOptions::new(4, 4);
    opts.threads = Some(0);
    assert!(render(&scene, &cam, &opts, ColorFormat::U8, false).is_err());
    let mut buf = vec![0u8; 10];
    assert!(render_into(&scene, &cam, &RenderOptions::new(4, 4), &mut buf, None).is_err());
}

/// Lighting that could overflow f32 is refused before rendering: an overflowed term is inf,
/// and inf meeting a zero (fog factor, barycentric, spot factor) was NaN. Below the limit,
/// huge HDR values come through finite.
#[test]
fn lighting_beyond_float32_range_is_refused_not_nan() {
    let tri = Mesh::new(
        vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        vec![[0, 1, 2]],
        None,
        None,
    )
    .unwrap();
    let tri = Arc::new(tri);
    let camera = Camera::look_at(
        DVec3::new(0.0, 0.0, 3.0),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        0.1,
        10.0,
    )
    .unwrap();
    let mut options = RenderOptions::new(8, 8);
    options.shading = ShadingMode::Gouraud;
    let m = Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ZERO, 1.0).unwrap();
    let scene_with = |intensity: f32, n: usize| {
        let mut s = Scene::new(Vec3::ZERO).unwrap();
        s.add(tri.clone(), m, Mat4::IDENTITY).unwrap();
        for _ in 0..n {
            s.add_light(DirectionalLight::new(-Vec3::Z, Vec3::ONE, intensity).unwrap());
        }
        s.set_fog(Some(
            Fog::new(FogMode::Exp { density: 100.0 }, Vec3::ONE).unwrap(),
        ));
        s
    };
    let e = render(
        &scene_with(3e38, 2),
        &camera,
        &options,
        ColorFormat::F32,
        false,
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("object 0: its lighting can reach 6.000e38"),
        "{msg}"
    );
    // An attenuated point light with kc = 0 can reach 1e6 times its colour.
    let mut s = Scene::new(Vec3::ZERO).unwrap();
    s.add(tri.clone(), m, Mat4::IDENTITY).unwrap();
    s.add_light(
        PointLight::new(Vec3::Z, Vec3::ONE, 1e32)
            .unwrap()
            .with_attenuation(0.0, 0.0, 1.0)
            .unwrap(),
    );
    assert!(render(&s, &camera, &options, ColorFormat::F32, false).is_err());
    // Fuzzing found a light whose colour·intensity overflows with kd = 0: the folded diffuse
    // term was 0·inf = NaN, which the bound skipped (`fuzz/seeds/pipeline/crash-nan-folded-light`).
    let mut s = Scene::new(Vec3::ZERO).unwrap();
    let dark = Material::new(Vec3::ONE, Vec3::ZERO, Vec3::ZERO, 1.0).unwrap();
    s.add(tri.clone(), dark, Mat4::IDENTITY).unwrap();
    s.add_light(DirectionalLight::new(-Vec3::Z, Vec3::splat(f32::MAX), 2.875).unwrap());
    let e = render(&s, &camera, &options, ColorFormat::F32, false).unwrap_err();
    assert!(e.to_string().contains("its lighting can reach inf"), "{e}");
    // 1e30 is fine: finite in float32 (fog factor ~0 leaves the fog colour), 255 in uint8.
    let f = render(
        &scene_with(1e30, 2),
        &camera,
        &options,
        ColorFormat::F32,
        false,
    )
    .unwrap();
    let ColorBuffer::F32(c) = f.color else {
        unreachable!()
    };
    assert!(c.iter().all(|v| v.is_finite()));
    options.shading = ShadingMode::Phong;
    let mut s = scene_with(1e30, 1);
    s.set_fog(None);
    let f = render(&s, &camera, &options, ColorFormat::F32, false).unwrap();
    let ColorBuffer::F32(c) = f.color else {
        unreachable!()
    };
    let centre = (4 * 8 + 4) * 3;
    assert_eq!(c[centre], 1e30);
}

#[test]
fn depth_map_is_the_visibility_of_the_colour_pass() {
    // The depth-only pass (a shadow map's) against the colour pass's depth output: the same
    // pixels covered; with an orthographic camera the eye depth is the window depth mapped
    // linearly, so the two agree bit for bit.
    let (scene, _) = busy_scene();
    let ortho = Camera::orthographic(
        DVec3::new(0.5, 0.7, 2.5),
        DVec3::ZERO,
        DVec3::Y,
        2.5,
        0.5,
        10.0,
    )
    .unwrap();
    let (_, persp) = busy_scene();
    for (cam, is_ortho) in [(ortho, true), (persp, false)] {
        for mode in [ShadingMode::Flat, ShadingMode::Phong] {
            let mut opts = RenderOptions::new(173, 111);
            opts.shading = mode;
            let (map, stats) = render_depth_map(&scene, &cam, &opts).unwrap();
            let frame = render(&scene, &cam, &opts, ColorFormat::U8, true).unwrap();
            assert_eq!(stats.triangles_setup, frame.stats.triangles_setup);
            let depth = frame.depth.unwrap();
            let mut covered = 0;
            for (z, d) in map.iter().zip(&depth) {
                assert_eq!(*z == -1.0, d.is_infinite(), "coverage differs");
                assert!(*z == -1.0 || (0.0..=1.0).contains(z), "{z}");
                if *z != -1.0 {
                    covered += 1;
                    if is_ortho {
                        let eye = (10.0 - *z as f64 * (10.0 - 0.5)) as f32;
                        assert_eq!(eye.to_bits(), d.to_bits(), "{z} {d}");
                    }
                }
            }
            assert!(covered > 1000, "{covered}");
            // Any thread count gives the same map.
            opts.threads = Some(1);
            assert_eq!(render_depth_map(&scene, &cam, &opts).unwrap().0, map);
        }
    }
    // It reads no material: a scene whose lighting the colour pass refuses still has depth.
    let mut scene = Scene::new(Vec3::ZERO).unwrap();
    scene
        .add(
            Arc::new(primitives::cube()),
            Material::preset("gold").unwrap(),
            Mat4::IDENTITY,
        )
        .unwrap();
    scene.add_light(DirectionalLight::new(-Vec3::Z, Vec3::ONE, 3e38).unwrap());
    let cam = Camera::look_at(
        DVec3::new(2.0, 2.0, 3.0),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        0.5,
        10.0,
    )
    .unwrap();
    let opts = RenderOptions::new(64, 48);
    assert!(render(&scene, &cam, &opts, ColorFormat::U8, false).is_err());
    let (map, _) = render_depth_map(&scene, &cam, &opts).unwrap();
    assert!(map.iter().any(|&z| z > 0.0));
}
