//! Fuzz target bodies, shared by the cargo-fuzz targets in `fuzz/` and by the seed-corpus
//! smoke test `tests/fuzz_seeds.rs` (which runs them on the stable toolchain, without
//! libFuzzer). Each body panics, with a message naming the broken invariant, when the
//! renderer misbehaves on its input; invalid input answered with an error is fine.
//!
//! Not part of the supported API.

use std::path::Path;
use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3, Vec4};

use crate::camera::{Camera, Projection};
use crate::effects::{Fog, FogMode};
use crate::environment::Environment;
use crate::error::RasterError;
use crate::frame::{ColorBuffer, ColorFormat};
use crate::lights::{AreaLight, AreaShape};
use crate::lights::{DirectionalLight, Light, PointLight, SplitColors, SpotLight};
use crate::lights::{ShadowFilter, ShadowSettings, Shadows};
use crate::material::Material;
use crate::mesh::Mesh;
use crate::obj::{merge_parts, parse_obj_parts};
use crate::options::{
    GouraudMethod, Interpolation, RenderOptions, ShadingMode, SpecularModel, Technique,
};
use crate::render::{coverage_counts, render};
use crate::scene::{Object, Scene};

/// Separates the OBJ text from the MTL text in an `obj_loader` input.
pub const MTL_SEPARATOR: &[u8] = b"\n#mtl\n";

/// Fuzz body for the OBJ loader. The input is OBJ text, optionally followed by
/// [`MTL_SEPARATOR`] and the text every `mtllib` line then reads.
///
/// Invariants: no panic; an error is a parse error naming `fuzz.obj` (and a line inside the
/// file, when it names one); a success satisfies every [`Mesh`] invariant, its materials
/// are finite and ≥ 0, the parts merge into one mesh, and rendering that mesh satisfies the
/// pipeline invariants of [`check_render`]. Returns whether the input loaded.
pub fn obj_loader(data: &[u8]) -> bool {
    let (obj, mtl) = match find(data, MTL_SEPARATOR) {
        Some(i) => (&data[..i], Some(&data[i + MTL_SEPARATOR.len()..])),
        None => (data, None),
    };
    let name = Path::new("fuzz.obj");
    let parts = match parse_obj_parts(obj, name, |_| mtl.map(<[u8]>::to_vec)) {
        Ok(parts) => parts,
        Err(e) => {
            let msg = e.to_string();
            let RasterError::Parse { line, path, .. } = e else {
                panic!("parsing from memory gave a non-parse error: {msg}");
            };
            // The OBJ file, or (a texture map's error) the MTL file and its line.
            let text = if path == name {
                obj
            } else {
                mtl.unwrap_or_else(|| panic!("error names {path:?} without an MTL: {msg}"))
            };
            assert!(
                msg.starts_with(&*path.to_string_lossy()),
                "error does not name the file: {msg}"
            );
            if let Some(line) = line {
                let lines = text.split(|&b| b == b'\n').count();
                assert!(
                    (1..=lines).contains(&line),
                    "line {line} outside the file's {lines} lines"
                );
            }
            return false;
        }
    };
    assert!(!parts.is_empty(), "Ok with no parts");
    let mut triangles = 0;
    for part in &parts {
        check_mesh(&part.mesh);
        triangles += part.mesh.triangle_count();
        if let Some(m) = part.material {
            for v in [m.ambient, m.diffuse, m.specular, m.emission] {
                assert!(
                    v.is_finite() && v.min_element() >= 0.0,
                    "bad MTL colour {v}"
                );
            }
            assert!(m.shininess >= 0.0, "bad MTL shininess {}", m.shininess);
        }
    }
    let mesh = merge_parts(parts).expect("parts that loaded must merge");
    check_mesh(&mesh);
    assert_eq!(mesh.triangle_count(), triangles, "merging lost triangles");
    // Frame the mesh's bounding box and render it (default material, one light).
    let (lo, hi) = mesh.positions().iter().fold(
        (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
        |(lo, hi), p| (lo.min(p.as_dvec3()), hi.max(p.as_dvec3())),
    );
    let (centre, radius) = ((lo + hi) / 2.0, (hi - lo).length() / 2.0);
    let Ok(camera) = Camera::look_at(
        centre + DVec3::new(0.3, 0.4, 2.5) * radius.max(1e-3),
        centre,
        DVec3::Y,
        45.0,
        radius.max(1e-3) * 0.1,
        radius.max(1e-3) * 10.0,
    ) else {
        return true;
    };
    let mut scene = Scene::new(Vec3::splat(0.2)).expect("valid ambient");
    scene
        .add(Arc::new(mesh), Material::default(), Mat4::IDENTITY)
        .expect("identity transform");
    scene.add_light(DirectionalLight::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE, 1.0).unwrap());
    for shading in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        let mut options = RenderOptions::new(12, 9);
        options.shading = shading;
        options.threads = Some(1);
        assert!(
            check_render(&scene, &camera, &options),
            "default lighting refused"
        );
    }
    true
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Asserts the invariants [`Mesh::new`] promises.
fn check_mesh(m: &Mesh) {
    let n = m.positions().len();
    assert!(n > 0 && m.triangle_count() > 0, "empty mesh");
    assert!(
        m.positions().iter().all(|p| p.is_finite()),
        "non-finite position"
    );
    assert!(
        m.indices().iter().flatten().all(|&i| (i as usize) < n),
        "index out of range"
    );
    let normals = m.vertex_normals();
    assert_eq!(normals.len(), n, "one normal per vertex");
    assert!(normals.iter().all(|v| v.is_finite()), "non-finite normal");
    if let Some(uv) = m.uvs() {
        assert_eq!(uv.len(), n, "one uv per vertex");
        assert!(uv.iter().all(|v| v.is_finite()), "non-finite uv");
    }
}

/// Reads fuzz bytes as a stream of small decisions and numbers; past the end, zeros.
struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

/// Numbers the decoder picks by tag: signed zeros, units, extreme scales, limits of f32,
/// a subnormal, and the non-finite values every constructor must refuse.
const SPECIAL: [f32; 16] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    1e-7,
    -1e-7,
    1e7,
    -1e7,
    1e-30,
    1e30,
    f32::MAX,
    f32::MIN_POSITIVE,
    1e-45,
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
];

impl<'a> Bytes<'a> {
    fn new(data: &'a [u8]) -> Self {
        Bytes { data, pos: 0 }
    }

    fn u8(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }

    fn flag(&mut self) -> bool {
        self.u8() & 1 == 1
    }

    /// Tag 0..16: a [`SPECIAL`] value; 16..128: a small multiple of 1/8 in [−7, 7];
    /// 128..256: the next four bytes as raw f32 bits.
    fn f32(&mut self) -> f32 {
        match self.u8() {
            t @ 0..=15 => SPECIAL[t as usize],
            t @ 16..=127 => (t as f32 - 72.0) / 8.0,
            _ => f32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()]),
        }
    }

    fn vec3(&mut self) -> Vec3 {
        Vec3::new(self.f32(), self.f32(), self.f32())
    }

    fn dvec3(&mut self) -> DVec3 {
        self.vec3().as_dvec3()
    }

    /// A light or material value (any f32: the renderer must refuse negative, non-finite
    /// and overflowing ones with an error).
    fn level(&mut self) -> f32 {
        self.f32()
    }

    fn color(&mut self) -> Vec3 {
        Vec3::new(self.level(), self.level(), self.level())
    }
}

/// A decoded pipeline case.
struct Case {
    scene: Scene,
    camera: Camera,
    options: RenderOptions,
}

/// Decodes a scene, a camera and options; `None` when a required part is refused by its
/// constructor (the refusal itself is the checked behaviour).
fn decode(b: &mut Bytes) -> Option<Case> {
    let mut options = RenderOptions::new(1 + (b.u8() % 40) as u32, 1 + (b.u8() % 40) as u32);
    let flags = b.u8();
    options.shading =
        [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong][flags as usize % 3];
    options.specular = [
        SpecularModel::BlinnPhong,
        SpecularModel::Phong,
        SpecularModel::NormalizedBlinnPhong,
    ][(flags as usize / 3) % 3];
    options.cull_backfaces = flags & 0x10 != 0;
    // The lectures' variants together (no new byte read, so seeds decode as before).
    if flags & 0x80 != 0 {
        options.gouraud = GouraudMethod::FaceIntensities;
        options.interpolation = Interpolation::Screen;
    }
    options.background = Vec3::new(0.125, 0.25, 0.375);
    // Both kinds read the same fields in the same order (tuple fields evaluate left to
    // right), so the seeds decode as before.
    let ortho = b.flag();
    let (eye, target, up) = (b.dvec3(), b.dvec3(), b.dvec3());
    let (size, near, far) = (b.f32() as f64, b.f32() as f64, b.f32() as f64);
    let camera = if ortho {
        Camera::orthographic(eye, target, up, size, near, far)
    } else {
        Camera::look_at(eye, target, up, size, near, far)
    };
    let camera = ok_or_message(camera)?;
    let mut scene = ok_or_message(Scene::new(b.color()))?;
    let mut objects = Vec::new();
    let mut lights: Vec<Light> = Vec::new();
    scene.set_two_sided(flags & 0x20 != 0);
    scene.set_local_viewer(flags & 0x40 == 0);
    for _ in 0..1 + b.u8() % 3 {
        let nv = 1 + (b.u8() % 12) as usize;
        let positions: Vec<Vec3> = (0..nv).map(|_| b.vec3()).collect();
        let normals = b.flag().then(|| (0..nv).map(|_| b.vec3()).collect());
        let nt = 1 + (b.u8() % 12) as usize;
        // Indices reach one past the last vertex, to exercise the range check.
        let indices: Vec<[u32; 3]> = (0..nt)
            .map(|_| [0; 3].map(|_: u32| (b.u8() as usize % (nv + 1)) as u32))
            .collect();
        let mesh = ok_or_message(Mesh::new(positions, indices, normals, None))?;
        let material = ok_or_message(
            Material::new(b.color(), b.color(), b.color(), b.level())
                .and_then(|m| m.with_emission(b.color())),
        )?;
        let transform = if b.flag() {
            let row = |b: &mut Bytes| Vec4::new(b.f32(), b.f32(), b.f32(), b.f32());
            let (r0, r1, r2) = (row(b), row(b), row(b));
            let r3 = if b.flag() { row(b) } else { Vec4::W };
            Mat4::from_cols(r0, r1, r2, r3).transpose()
        } else {
            Mat4::IDENTITY
        };
        objects.push(ok_or_message(Object::new(
            Arc::new(mesh),
            material,
            transform,
        ))?);
    }
    for _ in 0..b.u8() % 4 {
        let light: crate::Result<crate::lights::Light> = match b.u8() % 4 {
            0 => DirectionalLight::new(b.vec3(), b.color(), b.level()).map(Into::into),
            1 => PointLight::new(b.vec3(), b.color(), b.level())
                .and_then(|p| p.with_attenuation(b.level(), b.level(), b.level()))
                .map(Into::into),
            2 => PointLight::new(b.vec3(), b.color(), b.level())
                .and_then(|p| SpotLight::new(p, b.vec3(), b.f32(), b.level()))
                .map(Into::into),
            _ => AreaLight::new(
                b.vec3(),
                b.vec3(),
                b.vec3(),
                if b.flag() {
                    AreaShape::Disk
                } else {
                    AreaShape::Rectangle
                },
                1 + (b.u8() % 3) as u32,
            )
            .and_then(|a| a.with_color(b.color(), b.level()))
            .map(|a| a.with_one_sided(b.flag()))
            .map(Into::into),
        };
        lights.extend(ok_or_message(light));
    }
    if b.flag() {
        let mode = match b.u8() % 3 {
            0 => FogMode::Linear {
                start: b.f32(),
                end: b.f32(),
            },
            1 => FogMode::Exp { density: b.level() },
            _ => FogMode::Exp2 { density: b.level() },
        };
        scene.set_fog(ok_or_message(Fog::new(mode, b.color())));
    }
    options.threads = Some(1 + (b.u8() % 3) as usize);
    // Extension block, read after everything above so that older inputs (which end
    // earlier, and read zeros here) keep their meaning: back materials and per-light
    // diffuse/specular colours.
    for object in objects {
        let back = if b.flag() {
            ok_or_message(Material::new(b.color(), b.color(), b.color(), b.level()))
        } else {
            None
        };
        scene.add_object(object.with_back_material(back));
    }
    let mut split_lights = Vec::with_capacity(lights.len());
    for mut light in lights {
        if b.flag() {
            let diffuse = b.flag().then(|| b.color());
            let specular = b.flag().then(|| b.color());
            if let Some(split) = ok_or_message(SplitColors::new(diffuse, specular)) {
                match &mut light {
                    Light::Directional(d) => d.split = split,
                    Light::Point(p) => p.split = split,
                    Light::Spot(s) => s.point.split = split,
                    Light::Area(a) => a.split = split,
                }
            }
        }
        split_lights.push(light);
    }
    // Second extension block: each light's shadows (zeros: off). Map settings come from
    // any bytes (bad kernels and biases must be refused), at small resolutions.
    for light in split_lights {
        let shadows = match b.u8() % 3 {
            0 => Some(Shadows::Off),
            1 => Some(Shadows::Exact),
            _ => {
                let resolution = 16 + b.u8() as u32;
                let filter = match b.u8() % 4 {
                    0 => ShadowFilter::None,
                    k => ShadowFilter::Pcf(2 * k as u32 - 1 + (b.u8() % 2) as u32),
                };
                // Cascades from the resolution byte, so the corpora's bytes keep their meaning.
                let cascades = 1 + resolution % 4;
                ok_or_message(
                    ShadowSettings::new(resolution, filter, b.f32())
                        .and_then(|s| s.with_cascades(cascades)),
                )
                .map(Shadows::Map)
            }
        };
        let light: Light = match (light, shadows.unwrap_or_default()) {
            (Light::Directional(d), s) => d.with_shadows(s).into(),
            (Light::Point(p), s) => p.with_shadows(s).into(),
            (Light::Spot(l), s) => l.with_shadows(s).into(),
            (Light::Area(a), s) => a.with_shadows(s).into(),
        };
        scene.add_light(light);
    }
    // Third extension block (zeros: no optics): the techniques, an environment and each
    // object's reflectivity, transparency, ior, Fresnel and absorption.
    let optics = b.u8();
    if optics != 0 {
        options.reflections = if optics & 1 != 0 {
            Technique::Ray
        } else {
            Technique::Environment
        };
        options.refractions = match (optics >> 1) % 3 {
            0 => None,
            1 => Some(Technique::Environment),
            _ => Some(Technique::Ray),
        };
        options.max_depth = (b.u8() % 4) as u32;
        if optics & 0x20 != 0 {
            let texels: Vec<f32> = (0..4).flat_map(|_| b.color().to_array()).collect();
            scene.set_environment(ok_or_message(Environment::new(
                &texels,
                1,
                2,
                b.f32(),
                b.level(),
            )));
            options.environment_background = optics & 0x40 != 0 && scene.environment().is_some();
        }
        for o in scene.objects_mut() {
            if b.flag() {
                let m =
                    o.material()
                        .with_optics(b.color(), b.level(), b.f32(), b.flag(), b.color());
                if let Some(m) = ok_or_message(m) {
                    o.set_material(m);
                }
            }
        }
    }
    // Fourth extension block (zero: one sample): multi-sample anti-aliasing, with every
    // stage above (the secondary one included).
    options.samples = [1, 2, 4, 8, 16][(b.u8() % 5) as usize];
    Some(Case {
        scene,
        camera,
        options,
    })
}

/// `Some(value)`, or `None` after checking that the error explains itself.
fn ok_or_message<T>(r: crate::Result<T>) -> Option<T> {
    match r {
        Ok(v) => Some(v),
        Err(e) => {
            assert!(!e.to_string().is_empty(), "error without a message: {e:?}");
            None
        }
    }
}

/// Fuzz body for the pipeline: arbitrary small meshes (non-finite, huge, tiny, degenerate
/// coordinates), transforms, cameras, lights, fog and options decoded from `data`.
///
/// Invariants: see [`check_render`]. Returns whether the input decoded into a valid scene
/// (and was rendered).
pub fn pipeline(data: &[u8]) -> bool {
    let mut b = Bytes::new(data);
    match decode(&mut b) {
        Some(case) => check_render(&case.scene, &case.camera, &case.options),
        None => false,
    }
}

/// The scene, camera and options a `pipeline` input decodes to, for triaging a crash
/// (`None` when a constructor refuses it).
pub fn describe_pipeline_input(data: &[u8]) -> Option<String> {
    let case = decode(&mut Bytes::new(data))?;
    Some(format!(
        "{:#?}\n{:#?}\n{:#?}",
        case.scene, case.camera, case.options
    ))
}

/// Renders `scene` and asserts the pipeline invariants: no panic and no error for a valid
/// scene; float32 colour and depth contain no NaN; colour is finite; depth is `+inf` exactly where no triangle covers the
/// pixel centre (by the coverage test hook), and there the colour is exactly the
/// background (colours are finite: lighting that could overflow f32 is refused, see
/// `MAX_RADIANCE`); finite depths are ≥ 0 for a perspective camera (these per-pixel checks
/// with one sample only); uint8 output is exactly
/// `round(clamp(c, 0, 1)·255)` of the float32 output; one thread and several, and the
/// baseline and AVX2 builds of the tile stage, give the same bits. Returns `false` when the render refused the scene (only lighting beyond
/// `MAX_RADIANCE` may be refused at this point).
pub fn check_render(scene: &Scene, camera: &Camera, options: &RenderOptions) -> bool {
    let frame = match render(scene, camera, options, ColorFormat::F32, true) {
        Ok(frame) => frame,
        Err(e) => {
            let msg = e.to_string();
            assert!(
                msg.contains("can safely hold"),
                "valid scene failed to render: {msg}"
            );
            return false;
        }
    };
    let ColorBuffer::F32(color) = frame.color else {
        unreachable!("asked for f32")
    };
    let depth = frame.depth.expect("asked for depth");
    let counts = coverage_counts(scene, camera, options).expect("coverage of a valid scene");
    let bg = options.background;
    let perspective = !matches!(camera.projection(), Projection::Orthographic { .. });
    // Transparent surfaces blended straight through are not in the depth output (only the
    // opaque layer is), and the environment background is not the background colour.
    let blended = options.refractions.is_none()
        && scene.objects().iter().any(|o| {
            o.material().is_transparent()
                || o.material_for(true, scene.two_sided()).is_transparent()
        });
    for (i, (&d, &n)) in depth.iter().zip(&counts).enumerate() {
        let c = Vec3::from_slice(&color[3 * i..3 * i + 3]);
        assert!(!d.is_nan(), "NaN depth at pixel {i}");
        assert!(
            c.is_finite(),
            "non-finite colour {c} at pixel {i} (depth {d})"
        );
        // Several samples: the depth is the majority surface's and the colour a mix, so
        // neither follows the coverage of the pixel centre.
        if options.samples > 1 {
            continue;
        }
        if blended || options.environment_background {
            assert!(
                d == f32::INFINITY || n > 0,
                "pixel {i}: depth {d}, no triangle"
            );
            continue;
        }
        assert_eq!(
            d == f32::INFINITY,
            n == 0,
            "pixel {i}: depth {d} but {n} covering triangles"
        );
        if n == 0 {
            assert_eq!(c, bg, "uncovered pixel {i} is not the background");
        } else if perspective {
            assert!(d >= 0.0, "negative eye depth {d} at pixel {i}");
        }
    }
    let frame8 = render(scene, camera, options, ColorFormat::U8, false).expect("u8 render");
    let ColorBuffer::U8(c8) = frame8.color else {
        unreachable!("asked for u8")
    };
    for (i, (&q, &c)) in c8.iter().zip(&color).enumerate() {
        let want = (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        assert_eq!(
            q, want,
            "uint8 sample {i} is {q}, float32 {c} rounds to {want}"
        );
    }
    let mut one = options.clone();
    one.threads = Some(if options.threads == Some(1) { 3 } else { 1 });
    let again = render(scene, camera, &one, ColorFormat::F32, true).expect("re-render");
    let ColorBuffer::F32(color2) = again.color else {
        unreachable!("asked for f32")
    };
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert!(
        bits(&color) == bits(&color2) && bits(&depth) == bits(&again.depth.expect("depth")),
        "thread count changed the result"
    );
    let mut other_isa = options.clone();
    other_isa.baseline_isa = !options.baseline_isa;
    let again = render(scene, camera, &other_isa, ColorFormat::F32, true).expect("re-render");
    let ColorBuffer::F32(color3) = again.color else {
        unreachable!("asked for f32")
    };
    assert!(
        bits(&color) == bits(&color3) && bits(&depth) == bits(&again.depth.expect("depth")),
        "the instruction set (baseline or AVX2) changed the result"
    );
    true
}
