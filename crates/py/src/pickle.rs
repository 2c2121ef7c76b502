//! Pickling: every class reduces to `_core._restore(kind, state)`, where `state` holds the
//! core values exactly (f32 and f64 numbers survive Python floats unchanged) and mesh
//! buffers as NumPy arrays, so pickle protocol 5 can hand them out of band. Restoring goes
//! through the same validating constructors as user input: a pickle is untrusted input too.

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};
use pyo3::BoundObject;
use shadelab_raster as core;

use crate::area_light::PyAreaLight;
use crate::camera::PyCamera;
use crate::convert;
use crate::errors::to_py;
use crate::fog::PyFog;
use crate::light::{PyDirectionalLight, PyPointLight, PySpotLight};
use crate::material::PyMaterial;
use crate::mesh::PyMesh;
use crate::render::PyRenderOptions;
use crate::scene::{PyScene, PySceneObject};
use crate::shadow::{shadows, shadows_state, PyShadowSettings, ShadowsState};

type V3 = (f32, f32, f32);

fn v3(v: V3) -> Vec3 {
    Vec3::new(v.0, v.1, v.2)
}

/// `(_core._restore, (kind, state))`: the value `__reduce__` returns.
pub fn reduce<'py>(
    py: Python<'py>,
    kind: &str,
    state: impl IntoPyObject<'py>,
) -> PyResult<Bound<'py, PyTuple>> {
    let restore = py.import("shadelab_rs._core")?.getattr("_restore")?;
    let state = state
        .into_pyobject(py)
        .map_err(Into::into)?
        .into_any()
        .into_bound();
    let args = PyTuple::new(py, [kind.into_pyobject(py)?.into_any(), state])?;
    PyTuple::new(py, [restore, args.into_any()])
}

fn rows<'py, const N: usize>(py: Python<'py>, v: &[[f32; N]]) -> Bound<'py, PyAny> {
    Array2::from_shape_vec((v.len(), N), v.iter().flatten().copied().collect())
        .expect("length matches")
        .into_pyarray(py)
        .into_any()
}

fn vec3s<'py>(py: Python<'py>, v: &[Vec3]) -> Bound<'py, PyAny> {
    let a: Vec<[f32; 3]> = v.iter().map(|p| p.to_array()).collect();
    rows(py, &a)
}

/// Rows of an (n, N) float32 array, read directly when it is one (the pickled form), else
/// through the general converter.
fn read_rows<const N: usize>(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[f32; N]>> {
    if let Ok(a) = obj.extract::<PyReadonlyArray2<f32>>() {
        if a.shape()[1] == N {
            if let Ok(s) = a.as_slice() {
                return Ok(s
                    .chunks_exact(N)
                    .map(|c| c.try_into().expect("N values"))
                    .collect());
            }
        }
    }
    if N == 3 {
        let v = convert::vec3_rows(obj, name)?;
        Ok(v.iter()
            .map(|p| p.to_array()[..N].try_into().expect("3 values"))
            .collect())
    } else {
        let v = convert::vec2_rows(obj, name)?;
        Ok(v.iter()
            .map(|p| p.to_array()[..N].try_into().expect("2 values"))
            .collect())
    }
}

fn read_vec3s(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<Vec3>> {
    Ok(read_rows::<3>(obj, name)?
        .into_iter()
        .map(Vec3::from_array)
        .collect())
}

// ---- Mesh ----

/// (vertices, faces, given normals or None, loader normals or None, uvs or None).
pub fn mesh_state<'py>(py: Python<'py>, m: &core::Mesh) -> PyResult<Bound<'py, PyTuple>> {
    let faces = Array2::from_shape_vec(
        (m.triangle_count(), 3),
        m.indices().iter().flatten().copied().collect(),
    )
    .expect("length matches")
    .into_pyarray(py)
    .into_any();
    let opt = |v: Option<&[Vec3]>| {
        v.map(|v| vec3s(py, v))
            .unwrap_or_else(|| py.None().into_bound(py))
    };
    let uvs = m
        .uvs()
        .map(|uv| {
            let a: Vec<[f32; 2]> = uv.iter().map(|p| p.to_array()).collect();
            rows(py, &a)
        })
        .unwrap_or_else(|| py.None().into_bound(py));
    PyTuple::new(
        py,
        [
            vec3s(py, m.positions()),
            faces,
            opt(m.given_normals()),
            opt(m.loader_normals()),
            uvs,
            opt(m.colors()),
        ],
    )
}

type Arrays<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Option<Bound<'py, PyAny>>,
    Option<Bound<'py, PyAny>>,
    Option<Bound<'py, PyAny>>,
);

/// [`Arrays`] and the vertex colours.
type Arrays6<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Option<Bound<'py, PyAny>>,
    Option<Bound<'py, PyAny>>,
    Option<Bound<'py, PyAny>>,
    Option<Bound<'py, PyAny>>,
);

fn restore_mesh(state: &Bound<'_, PyAny>) -> PyResult<PyMesh> {
    // Pickles from before vertex colours have five items.
    let (vertices, faces, given, loader, uvs, colors) = match state.extract::<Arrays<'_>>() {
        Ok((a, b, c, d, e)) => (a, b, c, d, e, None),
        Err(_) => {
            let (a, b, c, d, e, f): Arrays6<'_> = state.extract()?;
            (a, b, c, d, e, f)
        }
    };
    let positions = read_vec3s(&vertices, "vertices")?;
    let indices = match faces.extract::<PyReadonlyArray2<u32>>() {
        Ok(a) if a.shape()[1] == 3 && a.as_slice().is_ok() => a
            .as_slice()
            .expect("checked")
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
        _ => convert::faces(&faces, positions.len())?,
    };
    let from_loader = loader.is_some();
    let normals = given
        .or(loader)
        .map(|n| read_vec3s(&n, "normals"))
        .transpose()?;
    let uvs = uvs
        .map(|u| read_rows::<2>(&u, "uvs").map(|r| r.into_iter().map(Vec2::from_array).collect()))
        .transpose()?;
    let mut mesh = core::Mesh::new(positions, indices, normals, uvs).map_err(to_py)?;
    if from_loader {
        mesh = mesh.with_generated_normals();
    }
    if let Some(c) = colors {
        mesh = mesh.with_colors(read_vec3s(&c, "colors")?).map_err(to_py)?;
    }
    Ok(PyMesh {
        inner: Arc::new(mesh),
    })
}

// ---- Material, Fog, Camera ----

/// ambient, diffuse, specular, shininess, emission, then the optics: reflectivity,
/// transparency, ior, fresnel, absorption.
type MaterialState = (V3, V3, V3, f32, V3, V3, f32, f32, bool, V3);

pub fn material_state(m: &core::Material) -> MaterialState {
    (
        m.ambient.into(),
        m.diffuse.into(),
        m.specular.into(),
        m.shininess,
        m.emission.into(),
        m.reflectivity.into(),
        m.transparency,
        m.ior,
        m.fresnel,
        m.absorption.into(),
    )
}

/// A material from its pickled state: the ten values of [`MaterialState`], or the first
/// five alone (states written before the optics existed: an opaque material).
fn material_any(state: &Bound<'_, PyAny>) -> PyResult<core::Material> {
    if state.len()? == 5 {
        let s: (V3, V3, V3, f32, V3) = state.extract()?;
        let zero = (0.0, 0.0, 0.0);
        return material((s.0, s.1, s.2, s.3, s.4, zero, 0.0, 1.0, true, zero));
    }
    material(state.extract()?)
}

fn material(s: MaterialState) -> PyResult<core::Material> {
    core::Material::new(v3(s.0), v3(s.1), v3(s.2), s.3)
        .and_then(|m| m.with_emission(v3(s.4)))
        .and_then(|m| m.with_optics(v3(s.5), s.6, s.7, s.8, v3(s.9)))
        .map_err(to_py)
}

type FogState = (String, f32, f32, V3);

pub fn fog_state(f: &core::Fog) -> FogState {
    let color = f.color().into();
    match f.mode() {
        core::FogMode::Linear { start, end } => ("linear".into(), start, end, color),
        core::FogMode::Exp { density } => ("exp".into(), density, 0.0, color),
        core::FogMode::Exp2 { density } => ("exp2".into(), density, 0.0, color),
    }
}

fn fog(s: FogState) -> PyResult<core::Fog> {
    let mode = match s.0.as_str() {
        "linear" => core::FogMode::Linear {
            start: s.1,
            end: s.2,
        },
        "exp" => core::FogMode::Exp { density: s.1 },
        "exp2" => core::FogMode::Exp2 { density: s.1 },
        other => return Err(PyValueError::new_err(format!("unknown fog mode '{other}'"))),
    };
    core::Fog::new(mode, v3(s.3)).map_err(to_py)
}

type D3 = (f64, f64, f64);
/// A pinhole camera's (fx, fy, cx, cy, skew, width, height).
type IntrinsicsState = (f64, f64, f64, f64, f64, u32, u32);
/// (kind, eye, target, up, fov_y or height (0 for a pinhole), near, far, intrinsics of a
/// pinhole); a plane left to `render` to fit is None, as it was given.
type CameraState = (
    String,
    D3,
    D3,
    D3,
    f64,
    Option<f64>,
    Option<f64>,
    Option<IntrinsicsState>,
);

pub fn camera_state(cam: &PyCamera) -> CameraState {
    let c = &cam.inner;
    let (kind, p, k) = match c.projection() {
        core::Projection::Perspective { fov_y } => ("perspective", fov_y, None),
        core::Projection::Orthographic { height } => ("orthographic", height, None),
        core::Projection::Pinhole(k) => (
            "pinhole",
            0.0,
            Some((k.fx, k.fy, k.cx, k.cy, k.skew, k.width, k.height)),
        ),
    };
    (
        kind.into(),
        c.eye().into(),
        c.target().into(),
        c.up().into(),
        p,
        (!cam.fit_near).then_some(c.near()),
        (!cam.fit_far).then_some(c.far()),
        k,
    )
}

/// The camera as `Camera.look_at` / `Camera.orthographic` build it from the same values
/// (placeholder planes for the fitted ones).
fn camera(s: CameraState) -> PyResult<PyCamera> {
    let d = |v: D3| glam::DVec3::new(v.0, v.1, v.2);
    if s.0 == "pinhole" {
        let Some((fx, fy, cx, cy, skew, width, height)) = s.7 else {
            return Err(PyValueError::new_err(
                "a pinhole camera's state has no intrinsics",
            ));
        };
        let k = core::Intrinsics {
            fx,
            fy,
            cx,
            cy,
            skew,
            width,
            height,
        };
        return PyCamera::fitted_later(s.5, s.6, true, |n, f| {
            core::Camera::from_intrinsics(d(s.1), d(s.2), d(s.3), k, n, f)
        });
    }
    let (make, perspective): (fn(_, _, _, _, _, _) -> _, bool) = match s.0.as_str() {
        "perspective" => (core::Camera::look_at, true),
        "orthographic" => (core::Camera::orthographic, false),
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown camera kind '{other}'"
            )))
        }
    };
    PyCamera::fitted_later(s.5, s.6, perspective, |n, f| {
        make(d(s.1), d(s.2), d(s.3), s.4, n, f)
    })
}

// ---- Lights ----

type Split = (Option<V3>, Option<V3>);

fn split_state(s: &core::SplitColors) -> Split {
    (s.diffuse.map(Into::into), s.specular.map(Into::into))
}

type PointState = (V3, V3, f32, V3, (f32, f32, f32), Split, ShadowsState);

pub fn point_state(l: &core::PointLight) -> PointState {
    let [a, b, c] = l.attenuation;
    (
        l.position.into(),
        l.color.into(),
        l.intensity,
        l.ambient.into(),
        (a, b, c),
        split_state(&l.split),
        shadows_state(&l.shadows),
    )
}

fn point(s: PointState) -> PyResult<core::PointLight> {
    let (k, (d, sp)) = (s.4, s.5);
    core::PointLight::new(v3(s.0), v3(s.1), s.2)
        .and_then(|l| l.with_ambient(v3(s.3)))
        .and_then(|l| l.with_attenuation(k.0, k.1, k.2))
        .and_then(|l| l.with_split_colors(d.map(v3), sp.map(v3)))
        .map_err(to_py)
        .and_then(|l| Ok(l.with_shadows(shadows(s.6)?)))
}

/// (unit direction, colour, intensity, ambient, split colours, direction as given).
type DirectionalState = (V3, V3, f32, V3, Split, D3, ShadowsState);

pub fn directional_state(l: &PyDirectionalLight) -> DirectionalState {
    let (g, l) = (l.given, &l.inner);
    (
        l.direction().into(),
        l.color.into(),
        l.intensity,
        l.ambient.into(),
        split_state(&l.split),
        (g[0], g[1], g[2]),
        shadows_state(&l.shadows),
    )
}

/// The given direction, checked as the constructor checks it.
fn given_direction(g: D3) -> PyResult<[f64; 3]> {
    let given = [g.0, g.1, g.2];
    if given.iter().all(|x| x.is_finite()) && given.iter().any(|&x| x != 0.0) {
        Ok(given)
    } else {
        Err(PyValueError::new_err(format!(
            "a light's given direction must be finite and non-zero, got {given:?}"
        )))
    }
}

fn directional(s: DirectionalState) -> PyResult<PyDirectionalLight> {
    let (d, sp) = s.4;
    let inner = core::DirectionalLight::new(v3(s.0), v3(s.1), s.2)
        .and_then(|l| l.with_unit_direction(v3(s.0)))
        .and_then(|l| l.with_ambient(v3(s.3)))
        .and_then(|l| l.with_split_colors(d.map(v3), sp.map(v3)))
        .map_err(to_py)?
        .with_shadows(shadows(s.6)?);
    Ok(PyDirectionalLight {
        inner,
        given: given_direction(s.5)?,
    })
}

/// (point light, unit direction, cutoff, exponent, inner cone, direction as given).
type SpotState = (PointState, V3, f32, f32, Option<f32>, D3);

pub fn spot_state(l: &PySpotLight) -> SpotState {
    let (g, l) = (l.given, &l.inner);
    (
        point_state(&l.point),
        l.direction().into(),
        l.cutoff(),
        l.exponent(),
        l.inner(),
        (g[0], g[1], g[2]),
    )
}

fn spot(s: SpotState) -> PyResult<PySpotLight> {
    let p = point(s.0)?;
    let inner = core::SpotLight::new(p, v3(s.1), s.2, s.3)
        .and_then(|l| l.with_unit_direction(v3(s.1)))
        .and_then(|l| match s.4 {
            Some(i) => l.with_inner(i),
            None => Ok(l),
        })
        .map_err(to_py)?;
    Ok(PySpotLight {
        inner,
        given: given_direction(s.5)?,
    })
}

type AreaState = (
    (V3, V3, V3, String, u32, bool),
    (V3, f32, V3, (f32, f32, f32), Split),
    ShadowsState,
);

pub fn area_state(l: &core::AreaLight) -> AreaState {
    let shape = match l.shape() {
        core::AreaShape::Rectangle => "rectangle",
        core::AreaShape::Disk => "disk",
    };
    let [a, b, c] = l.attenuation;
    (
        (
            l.position().into(),
            l.u().into(),
            l.v().into(),
            shape.into(),
            l.samples(),
            l.one_sided(),
        ),
        (
            l.color.into(),
            l.intensity,
            l.ambient.into(),
            (a, b, c),
            split_state(&l.split),
        ),
        shadows_state(&l.shadows),
    )
}

fn area(s: AreaState) -> PyResult<core::AreaLight> {
    let ((p, u, v, shape, samples, one_sided), (color, intensity, ambient, k, (d, sp)), sh) = s;
    let sh = shadows(sh)?;
    let shape = match shape.as_str() {
        "rectangle" => core::AreaShape::Rectangle,
        "disk" => core::AreaShape::Disk,
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown area light shape '{other}'"
            )))
        }
    };
    core::AreaLight::new(v3(p), v3(u), v3(v), shape, samples)
        .and_then(|l| l.with_color(v3(color), intensity))
        .and_then(|l| l.with_ambient(v3(ambient)))
        .and_then(|l| l.with_attenuation(k.0, k.1, k.2))
        .and_then(|l| l.with_split_colors(d.map(v3), sp.map(v3)))
        .map(|l| l.with_one_sided(one_sided).with_shadows(sh))
        .map_err(to_py)
}

// ---- Scene ----

/// A light as its Python object (each pickles itself), with the direction as given.
pub fn light_object<'py>(
    py: Python<'py>,
    l: &core::Light,
    given: Option<[f64; 3]>,
) -> PyResult<Bound<'py, PyAny>> {
    let given = given.unwrap_or_default();
    Ok(match *l {
        core::Light::Directional(inner) => {
            Bound::new(py, PyDirectionalLight { inner, given })?.into_any()
        }
        core::Light::Point(inner) => Bound::new(py, PyPointLight { inner })?.into_any(),
        core::Light::Spot(inner) => Bound::new(py, PySpotLight { inner, given })?.into_any(),
        core::Light::Area(inner) => Bound::new(py, PyAreaLight { inner })?.into_any(),
    })
}

fn light_from_object(l: &Bound<'_, PyAny>) -> PyResult<(core::Light, Option<[f64; 3]>)> {
    crate::scene::light_arg(l, "a pickled scene").map_err(|_| {
        PyValueError::new_err(format!(
            "a pickled scene holds a {} where a light belongs",
            l.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    })
}

type ObjectState = (usize, MaterialState, Option<MaterialState>, Vec<f32>);

/// (ambient, fog, two_sided, local_viewer, meshes, objects, lights, default_lights); a mesh
/// shared by several objects is stored once and the objects name it by index.
pub fn scene_state<'py>(py: Python<'py>, scene: &PyScene) -> PyResult<Bound<'py, PyTuple>> {
    let s = &scene.inner;
    let mut meshes: Vec<Arc<core::Mesh>> = Vec::new();
    let mut objects: Vec<ObjectState> = Vec::new();
    let mut maps = Vec::new();
    for o in s.objects() {
        maps.push(o.maps().map(|m| crate::texture::maps_state(m)));
        let i = match meshes.iter().position(|m| Arc::ptr_eq(m, o.mesh())) {
            Some(i) => i,
            None => {
                meshes.push(o.mesh().clone());
                meshes.len() - 1
            }
        };
        objects.push((
            i,
            material_state(o.material()),
            o.back_material().map(material_state),
            o.transform().to_cols_array().to_vec(),
        ));
    }
    let meshes = meshes
        .into_iter()
        .map(|inner| Bound::new(py, PyMesh { inner }))
        .collect::<PyResult<Vec<_>>>()?;
    let lights = s
        .lights()
        .iter()
        .zip(&scene.given_directions)
        .map(|(l, given)| light_object(py, l, *given))
        .collect::<PyResult<Vec<_>>>()?;
    let mut items = vec![
        V3::from(s.ambient()).into_pyobject(py)?.into_any(),
        s.fog().map(fog_state).into_pyobject(py)?.into_any(),
        s.two_sided().into_pyobject(py)?.to_owned().into_any(),
        s.local_viewer().into_pyobject(py)?.to_owned().into_any(),
        PyList::new(py, meshes)?.into_any(),
        objects.into_pyobject(py)?.into_any(),
        PyList::new(py, lights)?.into_any(),
        scene
            .default_lights
            .into_pyobject(py)?
            .to_owned()
            .into_any(),
    ];
    // Per-object texture maps, only when there are any (or an environment follows):
    // untextured scenes pickle as before.
    let env = s.environment();
    if maps.iter().any(Option::is_some) || env.is_some() {
        items.push(maps.into_pyobject(py)?.into_any());
    }
    if let Some(e) = env {
        let e = crate::environment::PyEnvironment {
            inner: e.clone(),
            path: scene.environment_path.clone(),
        };
        items.push(Bound::new(py, e)?.into_any());
    }
    PyTuple::new(py, items)
}

fn transform(cols: &[f32]) -> PyResult<Mat4> {
    let cols: [f32; 16] = cols
        .try_into()
        .map_err(|_| PyValueError::new_err("a pickled transform has 16 values"))?;
    Ok(Mat4::from_cols_array(&cols))
}

#[allow(clippy::type_complexity)]
fn restore_scene(state: &Bound<'_, PyAny>) -> PyResult<PyScene> {
    // A ninth item holds the objects' texture maps (scenes with textures only).
    let environment: Option<crate::environment::PyEnvironment> = match state.len()? {
        10 => Some(state.get_item(9)?.extract()?),
        _ => None,
    };
    let environment_path = environment.as_ref().and_then(|e| e.path.clone());
    let environment = environment.map(|e| e.inner);
    let maps: Vec<Option<Arc<core::Maps>>> = match state.len()? {
        9 | 10 => state
            .get_item(8)?
            .try_iter()?
            .map(|m| {
                let m = m?;
                if m.is_none() {
                    Ok(None)
                } else {
                    crate::texture::restore_maps(&m)
                }
            })
            .collect::<PyResult<_>>()?,
        _ => Vec::new(),
    };
    let state = &state.get_item(pyo3::types::PySlice::new(state.py(), 0, 8, 1))?;
    let (ambient, fog_s, two_sided, local_viewer, meshes, objects, lights, default_lights): (
        V3,
        Option<FogState>,
        bool,
        bool,
        Vec<PyRef<'_, PyMesh>>,
        Vec<ObjectState>,
        Vec<Bound<'_, PyAny>>,
        bool,
    ) = state.extract()?;
    let mut scene = core::Scene::new(v3(ambient)).map_err(to_py)?;
    scene.set_fog(fog_s.map(fog).transpose()?);
    scene.set_environment(environment);
    scene.set_two_sided(two_sided);
    scene.set_local_viewer(local_viewer);
    for (k, (i, m, back, t)) in objects.into_iter().enumerate() {
        let mesh = meshes
            .get(i)
            .ok_or_else(|| PyValueError::new_err(format!("a pickled object names mesh {i}")))?;
        let back = back.map(material).transpose()?;
        let object = core::Object::new(mesh.inner.clone(), material(m)?, transform(&t)?)
            .and_then(|o| {
                o.with_back_material(back)
                    .with_maps(maps.get(k).cloned().flatten())
            })
            .map_err(to_py)?;
        scene.add_object(object);
    }
    let mut given_directions = Vec::with_capacity(lights.len());
    for l in lights {
        let (light, given) = light_from_object(&l)?;
        scene.add_light(light);
        given_directions.push(given);
    }
    Ok(PyScene {
        inner: scene,
        given_directions,
        default_lights,
        environment_path,
    })
}

type SceneObjectState<'py> = (
    Bound<'py, PyAny>,
    MaterialState,
    Option<MaterialState>,
    Vec<f32>,
);

pub fn scene_object_state<'py>(
    py: Python<'py>,
    mesh: &Arc<core::Mesh>,
    material: &core::Material,
    back: Option<&core::Material>,
    t: &Mat4,
) -> PyResult<SceneObjectState<'py>> {
    Ok((
        Bound::new(
            py,
            PyMesh {
                inner: mesh.clone(),
            },
        )?
        .into_any(),
        material_state(material),
        back.map(material_state),
        t.to_cols_array().to_vec(),
    ))
}

fn restore_scene_object(state: &Bound<'_, PyAny>) -> PyResult<PySceneObject> {
    let (mesh, m, back, t): (
        PyRef<'_, PyMesh>,
        MaterialState,
        Option<MaterialState>,
        Vec<f32>,
    ) = state.extract()?;
    // Checked like a scene's object (the matrix must be affine and invertible).
    let object = core::Object::new(mesh.inner.clone(), material(m)?, transform(&t)?)
        .map_err(to_py)?
        .with_back_material(back.map(material).transpose()?);
    Ok(PySceneObject::from_object(&object))
}

/// Rebuilds a pickled object: `kind` is its class name, `state` what its `__reduce__` gave.
#[pyfunction]
pub fn _restore<'py>(
    py: Python<'py>,
    kind: &str,
    state: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let bad = |e: PyErr| {
        let err = PyValueError::new_err(format!("cannot unpickle a {kind}: {e}"));
        err.set_cause(py, Some(e));
        err
    };
    let obj = match kind {
        "Mesh" => Bound::new(py, restore_mesh(state).map_err(bad)?)?.into_any(),
        "Material" => {
            Bound::new(py, PyMaterial::plain(material_any(state).map_err(bad)?))?.into_any()
        }
        "ShadowSettings" => Bound::new(
            py,
            PyShadowSettings {
                inner: state
                    .extract()
                    .map_err(bad)
                    .and_then(|s| crate::shadow::settings(s).map_err(bad))?,
            },
        )?
        .into_any(),
        "Fog" => Bound::new(
            py,
            PyFog {
                inner: state
                    .extract()
                    .map_err(bad)
                    .and_then(|s| fog(s).map_err(bad))?,
            },
        )?
        .into_any(),
        "Camera" => Bound::new(
            py,
            state
                .extract()
                .map_err(bad)
                .and_then(|s| camera(s).map_err(bad))?,
        )?
        .into_any(),
        "PointLight" => Bound::new(
            py,
            PyPointLight {
                inner: state
                    .extract()
                    .map_err(bad)
                    .and_then(|s| point(s).map_err(bad))?,
            },
        )?
        .into_any(),
        "DirectionalLight" => Bound::new(
            py,
            state
                .extract()
                .map_err(bad)
                .and_then(|s| directional(s).map_err(bad))?,
        )?
        .into_any(),
        "SpotLight" => Bound::new(
            py,
            state
                .extract()
                .map_err(bad)
                .and_then(|s| spot(s).map_err(bad))?,
        )?
        .into_any(),
        "AreaLight" => Bound::new(
            py,
            PyAreaLight {
                inner: state
                    .extract()
                    .map_err(bad)
                    .and_then(|s| area(s).map_err(bad))?,
            },
        )?
        .into_any(),
        "Texture" => {
            Bound::new(py, crate::texture::restore_texture(state).map_err(bad)?)?.into_any()
        }
        "TexturedMaterial" => {
            let restore = || -> PyResult<PyMaterial> {
                let inner = material(state.get_item(0)?.extract()?)?;
                let maps = crate::texture::restore_maps(&state.get_item(1)?)?;
                Ok(PyMaterial { inner, maps })
            };
            Bound::new(py, restore().map_err(bad)?)?.into_any()
        }
        "TexturedSceneObject" => {
            let restore = || -> PyResult<PySceneObject> {
                let base = restore_scene_object(&state.get_item(0)?)?;
                let maps = crate::texture::restore_maps(&state.get_item(1)?)?;
                base.with_maps(maps)
            };
            Bound::new(py, restore().map_err(bad)?)?.into_any()
        }
        "Scene" => Bound::new(py, restore_scene(state).map_err(bad)?)?.into_any(),
        "SceneObject" => Bound::new(py, restore_scene_object(state).map_err(bad)?)?.into_any(),
        // The state is the constructor's keywords (`RenderOptions.to_dict`): checked by it.
        "RenderOptions" => {
            let kwargs = state
                .cast::<pyo3::types::PyDict>()
                .map_err(|e| bad(e.into()))?;
            py.get_type::<PyRenderOptions>()
                .call((), Some(kwargs))
                .map_err(bad)?
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "cannot unpickle unknown shadelab_rs class '{other}'"
            )))
        }
    };
    Ok(obj)
}
