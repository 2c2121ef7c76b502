//! `Scene`.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Mat4;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use shadelab_raster as core;

use crate::area_light::PyAreaLight;
use crate::convert;
use crate::environment::PyEnvironment;
use crate::errors::to_py;
use crate::fog::PyFog;
use crate::light::{PyDirectionalLight, PyPointLight, PySpotLight};
use crate::material::PyMaterial;
use crate::mesh::PyMesh;

/// One object of a scene, read back: its mesh, material and model matrix (a snapshot;
/// changing it does not change the scene).
#[pyclass(name = "SceneObject", module = "shadelab_rs._core", frozen)]
pub struct PySceneObject {
    mesh: Arc<core::Mesh>,
    material: core::Material,
    back_material: Option<core::Material>,
    maps: Option<Arc<core::Maps>>,
    transform: Mat4,
}

impl PySceneObject {
    /// The same snapshot with texture maps (checked against the mesh's UVs).
    pub fn with_maps(self, maps: Option<Arc<core::Maps>>) -> PyResult<Self> {
        if maps.is_some() && self.mesh.uvs().is_none() {
            return Err(crate::errors::value_error(
                "uvs",
                "the material has texture maps but the mesh has no UVs",
            ));
        }
        Ok(PySceneObject { maps, ..self })
    }

    /// The snapshot of a scene's object.
    pub fn from_object(o: &core::Object) -> Self {
        PySceneObject {
            mesh: o.mesh().clone(),
            material: *o.material(),
            back_material: o.back_material().copied(),
            maps: o.maps().cloned(),
            transform: o.transform(),
        }
    }
}

#[pymethods]
impl PySceneObject {
    /// Pickle support: `_core._restore("SceneObject", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        if let Some(maps) = &self.maps {
            let base = crate::pickle::scene_object_state(
                py,
                &self.mesh,
                &self.material,
                self.back_material.as_ref(),
                &self.transform,
            )?;
            let state = (base, crate::texture::maps_state(maps));
            return crate::pickle::reduce(py, "TexturedSceneObject", state);
        }
        crate::pickle::reduce(
            py,
            "SceneObject",
            crate::pickle::scene_object_state(
                py,
                &self.mesh,
                &self.material,
                self.back_material.as_ref(),
                &self.transform,
            )?,
        )
    }

    fn __copy__(&self) -> Self {
        PySceneObject {
            mesh: self.mesh.clone(),
            material: self.material,
            back_material: self.back_material,
            maps: self.maps.clone(),
            transform: self.transform,
        }
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        PySceneObject {
            mesh: self.mesh.clone(),
            material: self.material,
            back_material: self.back_material,
            maps: self.maps.clone(),
            transform: self.transform,
        }
    }
    /// The mesh (shared with the scene, not copied).
    #[getter]
    fn mesh(&self) -> PyMesh {
        PyMesh {
            inner: self.mesh.clone(),
        }
    }

    /// The material.
    #[getter]
    fn material(&self) -> PyMaterial {
        PyMaterial {
            inner: self.material,
            maps: self.maps.clone(),
        }
    }

    /// The material of back faces under two-sided lighting, or None (`material` then).
    #[getter]
    fn back_material(&self) -> Option<PyMaterial> {
        self.back_material.map(|inner| PyMaterial {
            inner,
            maps: self.maps.clone(),
        })
    }

    /// The 4x4 model matrix as float64 (its float32 values exactly).
    #[getter]
    fn transform<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        // glam is column-major; NumPy rows are the matrix rows.
        let rows: Vec<f64> = self
            .transform
            .transpose()
            .to_cols_array()
            .iter()
            .map(|&v| f64::from(v))
            .collect();
        Array2::from_shape_vec((4, 4), rows)
            .expect("16 values")
            .into_pyarray(py)
    }

    fn __repr__(&self) -> String {
        format!(
            "SceneObject(mesh=Mesh(n_vertices={}, n_faces={}), material={:?})",
            self.mesh.positions().len(),
            self.mesh.triangle_count(),
            self.material
        )
    }
}

/// The Python function `name` of the pure-Python module `shadelab_rs.scene_file`, which
/// holds the scene-file schema (parsing and validation live in Python, not here).
fn scene_file_fn<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("shadelab_rs.scene_file")?.getattr(name)
}

/// Objects, lights and the global ambient light.
#[pyclass(name = "Scene", module = "shadelab_rs._core")]
pub struct PyScene {
    pub inner: core::Scene,
    /// Per light (parallel to `inner.lights()`), the direction as the user gave it, for
    /// the directional and spot lights that have one: `lights` hands them back unchanged.
    pub(crate) given_directions: Vec<Option<[f64; 3]>>,
    /// Whether `render` lights a scene without lights with the camera's light rig.
    pub default_lights: bool,
    /// The file the environment was read from, if any (scene files name it).
    pub(crate) environment_path: Option<Vec<std::path::PathBuf>>,
}

/// A material argument: a Material, a preset name, or None for the default.
fn material_arg(m: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<core::Material>> {
    let Some(m) = m.filter(|m| !m.is_none()) else {
        return Ok(None);
    };
    if let Ok(m) = m.extract::<PyRef<'_, PyMaterial>>() {
        return Ok(Some(m.inner));
    }
    if let Ok(preset) = m.extract::<String>() {
        return core::Material::preset(&preset).map(Some).map_err(to_py);
    }
    Err(PyTypeError::new_err(format!(
        "{name} must be a Material or a preset name (str), got {}",
        m.get_type().name()?
    )))
}

/// The texture maps of a material argument (a preset name has none).
fn maps_arg(m: Option<&Bound<'_, PyAny>>) -> Option<Arc<core::Maps>> {
    m.and_then(|m| m.extract::<PyRef<'_, PyMaterial>>().ok())
        .and_then(|m| m.maps.clone())
}

/// The (mesh, transform, material) parts of a mesh argument: a Mesh is one part; anything
/// else (trimesh.Trimesh / Scene, a (vertices, faces) pair, PyVista PolyData) is converted
/// by `shadelab_rs.io.mesh_parts`, in Python where those libraries live.
#[allow(clippy::type_complexity)]
fn mesh_parts(
    obj: &Bound<'_, PyAny>,
) -> PyResult<
    Vec<(
        std::sync::Arc<core::Mesh>,
        Option<Mat4>,
        Option<(core::Material, Option<Arc<core::Maps>>)>,
    )>,
> {
    if let Ok(m) = obj.extract::<PyRef<'_, PyMesh>>() {
        return Ok(vec![(m.inner.clone(), None, None)]);
    }
    let parts = obj
        .py()
        .import("shadelab_rs.io")?
        .getattr("mesh_parts")?
        .call1((obj,))?;
    let mut out = Vec::new();
    for part in parts.try_iter()? {
        let (mesh, transform, material): (
            PyRef<'_, PyMesh>,
            Option<Bound<'_, PyAny>>,
            Option<PyRef<'_, PyMaterial>>,
        ) = part?.extract()?;
        let transform = transform
            .map(|t| convert::mat4(&t, "transform"))
            .transpose()?;
        out.push((
            mesh.inner.clone(),
            transform,
            material.map(|m| (m.inner, m.maps.clone())),
        ));
    }
    Ok(out)
}

/// A Python index into a list of `len` items (negative counts from the end).
fn index(i: isize, len: usize, what: &str) -> PyResult<usize> {
    let j = if i < 0 { i + len as isize } else { i };
    if j < 0 || j as usize >= len {
        return Err(pyo3::exceptions::PyIndexError::new_err(format!(
            "{what} index {i} out of range (the scene has {len})"
        )));
    }
    Ok(j as usize)
}

/// A light argument as the core's light, with the direction as the user gave it for the
/// directional and spot lights (`Scene.lights` hands it back unchanged).
pub(crate) fn light_arg(
    light: &Bound<'_, PyAny>,
    what: &str,
) -> PyResult<(core::Light, Option<[f64; 3]>)> {
    if let Ok(l) = light.extract::<PyRef<'_, PyDirectionalLight>>() {
        Ok((l.inner.into(), Some(l.given)))
    } else if let Ok(l) = light.extract::<PyRef<'_, PyPointLight>>() {
        Ok((l.inner.into(), None))
    } else if let Ok(l) = light.extract::<PyRef<'_, PySpotLight>>() {
        Ok((l.inner.into(), Some(l.given)))
    } else if let Ok(l) = light.extract::<PyRef<'_, PyAreaLight>>() {
        Ok((l.inner.into(), None))
    } else {
        Err(PyTypeError::new_err(format!(
            "{what} expects a DirectionalLight, PointLight, SpotLight or AreaLight, got {}",
            light.get_type().name()?
        )))
    }
}

impl PyScene {
    /// A copy sharing the (immutable) meshes.
    fn copied(&self) -> Self {
        PyScene {
            inner: self.inner.clone(),
            given_directions: self.given_directions.clone(),
            default_lights: self.default_lights,
            environment_path: self.environment_path.clone(),
        }
    }
}

#[pymethods]
impl PyScene {
    /// Pickle support: `_core._restore("Scene", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "Scene", crate::pickle::scene_state(py, self)?)
    }

    fn __copy__(&self) -> Self {
        // Meshes are immutable and stay shared; everything else is copied.
        self.copied()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        // Meshes are immutable and stay shared; everything else is copied.
        self.copied()
    }

    #[new]
    #[pyo3(signature = (ambient=None, fog=None, two_sided=false, local_viewer=true, default_lights=true, environment=None))]
    fn new(
        ambient: Option<&Bound<'_, PyAny>>,
        fog: Option<PyFog>,
        two_sided: bool,
        local_viewer: bool,
        default_lights: bool,
        environment: Option<PyEnvironment>,
    ) -> PyResult<Self> {
        let ambient =
            ambient.map_or(Ok(glam::Vec3::splat(0.2)), |a| convert::vec3(a, "ambient"))?;
        let mut inner = core::Scene::new(ambient).map_err(to_py)?;
        inner.set_fog(fog.map(|f| f.inner));
        let environment_path = environment.as_ref().and_then(|e| e.path.clone());
        inner.set_environment(environment.map(|e| e.inner));
        inner.set_two_sided(two_sided);
        inner.set_local_viewer(local_viewer);
        Ok(PyScene {
            inner,
            given_directions: Vec::new(),
            default_lights,
            environment_path,
        })
    }

    /// Two-sided lighting: back faces (clockwise on screen) lit with the flipped normal.
    #[getter]
    fn get_two_sided(&self) -> bool {
        self.inner.two_sided()
    }

    #[setter]
    fn set_two_sided(&mut self, on: bool) {
        self.inner.set_two_sided(on);
    }

    /// Whether `render` lights this scene with the camera's light rig while it has no
    /// lights (default True); assignable.
    #[getter]
    fn get_default_lights(&self) -> bool {
        self.default_lights
    }

    #[setter]
    fn set_default_lights(&mut self, on: bool) {
        self.default_lights = on;
    }

    /// Local viewer (True, default) or OpenGL's infinite viewer (False).
    #[getter]
    fn get_local_viewer(&self) -> bool {
        self.inner.local_viewer()
    }

    #[setter]
    fn set_local_viewer(&mut self, local: bool) {
        self.inner.set_local_viewer(local);
    }

    /// The environment (an Environment) or None; assignable. Reflections and refractions
    /// read it; `background="environment"` shows it.
    #[getter]
    fn get_environment(&self) -> Option<PyEnvironment> {
        self.inner.environment().map(|e| PyEnvironment {
            inner: e.clone(),
            path: self.environment_path.clone(),
        })
    }

    #[setter]
    fn set_environment(&mut self, environment: Option<PyEnvironment>) {
        self.environment_path = environment.as_ref().and_then(|e| e.path.clone());
        self.inner.set_environment(environment.map(|e| e.inner));
    }

    /// The fog (a Fog) or None; assignable.
    #[getter]
    fn get_fog(&self) -> Option<PyFog> {
        self.inner.fog().map(|f| PyFog { inner: *f })
    }

    #[setter]
    fn set_fog(&mut self, fog: Option<PyFog>) {
        self.inner.set_fog(fog.map(|f| f.inner));
    }

    /// Adds `mesh` with `material` (default: grey plastic) placed by the 4x4 model matrix
    /// `transform` (column vectors: p_world = transform @ [x, y, z, 1]); `back_material`
    /// lights its back faces when the scene is two-sided.
    /// `mesh` may also be a trimesh.Trimesh or trimesh.Scene (its parts with their
    /// transforms and colours), a (vertices, faces) pair or a PyVista PolyData; materials
    /// may be preset names. Returns the number of objects added.
    #[pyo3(signature = (mesh, material=None, transform=None, back_material=None))]
    fn add(
        &mut self,
        mesh: &Bound<'_, PyAny>,
        material: Option<&Bound<'_, PyAny>>,
        transform: Option<&Bound<'_, PyAny>>,
        back_material: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let maps = maps_arg(material);
        let material = material_arg(material, "material")?;
        let back_material = material_arg(back_material, "back_material")?;
        let transform = transform
            .filter(|t| !t.is_none())
            .map(|t| convert::mat4(t, "transform"))
            .transpose()?;
        let mut objects = Vec::new();
        // Build every object before adding any, so a bad part adds nothing.
        for (mesh, part_transform, part_material) in mesh_parts(mesh)? {
            let m = match (transform, part_transform) {
                (Some(t), Some(p)) => t * p,
                (t, p) => t.or(p).unwrap_or(Mat4::IDENTITY),
            };
            let (part_material, part_maps) = part_material.unzip();
            // The given material (with its maps, or none) wins over the part's own.
            let maps = if material.is_some() {
                maps.clone()
            } else {
                part_maps.flatten()
            };
            let mat = material.or(part_material).unwrap_or_default();
            objects.push(
                core::Object::new(mesh, mat, m)
                    .and_then(|o| o.with_back_material(back_material).with_maps(maps))
                    .map_err(to_py)?,
            );
        }
        let n = objects.len();
        for o in objects {
            self.inner.add_object(o);
        }
        Ok(n)
    }

    /// Removes the object at `index` (negative counts from the end).
    fn remove_object(&mut self, index: isize) -> PyResult<()> {
        let i = self::index(index, self.inner.objects().len(), "object")?;
        self.inner.objects_mut().remove(i);
        Ok(())
    }

    /// Removes the light at `index` (negative counts from the end).
    fn remove_light(&mut self, index: isize) -> PyResult<()> {
        let i = self::index(index, self.inner.lights().len(), "light")?;
        self.inner.lights_mut().remove(i);
        self.given_directions.remove(i);
        Ok(())
    }

    /// Replaces the light at `index`.
    fn set_light(&mut self, index: isize, light: &Bound<'_, PyAny>) -> PyResult<()> {
        let i = self::index(index, self.inner.lights().len(), "light")?;
        let (light, given) = light_arg(light, "set_light")?;
        self.inner.lights_mut()[i] = light;
        self.given_directions[i] = given;
        Ok(())
    }

    /// Removes every object.
    fn clear_objects(&mut self) {
        self.inner.objects_mut().clear();
    }

    /// Removes every light (the scene then renders under the default light rig unless
    /// `default_lights` is False).
    fn clear_lights(&mut self) {
        self.inner.lights_mut().clear();
        self.given_directions.clear();
    }

    /// Moves the object at `index`: its model matrix becomes `transform`.
    fn set_transform(&mut self, index: isize, transform: &Bound<'_, PyAny>) -> PyResult<()> {
        let i = self::index(index, self.inner.objects().len(), "object")?;
        let m = convert::mat4(transform, "transform")?;
        let o = &self.inner.objects()[i];
        let object = core::Object::new(o.mesh().clone(), *o.material(), m)
            .and_then(|n| {
                n.with_back_material(o.back_material().copied())
                    .with_maps(o.maps().cloned())
            })
            .map_err(to_py)?;
        self.inner.objects_mut()[i] = object;
        Ok(())
    }

    /// Gives the object at `index` a new material (a Material or a preset name).
    fn set_material(&mut self, index: isize, material: &Bound<'_, PyAny>) -> PyResult<()> {
        let i = self::index(index, self.inner.objects().len(), "object")?;
        let mat = material_arg(Some(material), "material")?.unwrap_or_default();
        let o = &self.inner.objects()[i];
        let object = core::Object::new(o.mesh().clone(), mat, o.transform())
            .and_then(|n| {
                n.with_back_material(o.back_material().copied())
                    .with_maps(maps_arg(Some(material)))
            })
            .map_err(to_py)?;
        self.inner.objects_mut()[i] = object;
        Ok(())
    }

    /// The world-space axis-aligned bounding box of all objects as ((x0, y0, z0),
    /// (x1, y1, z1)), or None for an empty scene.
    #[allow(clippy::type_complexity)]
    fn bounds(&self) -> Option<((f64, f64, f64), (f64, f64, f64))> {
        crate::defaults::world_bounds(&self.inner).map(|(lo, hi)| (lo.into(), hi.into()))
    }

    /// Loads an OBJ file and adds each of its parts (per group and per `usemtl`) as an
    /// object with its MTL material, or with `material` for all of them when given; returns
    /// the number of objects added.
    #[pyo3(signature = (path, material=None, transform=None, back_material=None))]
    fn add_obj(
        &mut self,
        py: Python<'_>,
        path: std::path::PathBuf,
        material: Option<&Bound<'_, PyAny>>,
        transform: Option<&Bound<'_, PyAny>>,
        back_material: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let maps = maps_arg(material);
        let material = material_arg(material, "material")?;
        let back_material = material_arg(back_material, "back_material")?;
        let transform = transform.map_or(Ok(Mat4::IDENTITY), |t| convert::mat4(t, "transform"))?;
        let parts = py
            .detach(|| crate::errors::no_panic("add_obj", || core::load_obj_parts(&path)))?
            .map_err(to_py)?;
        if maps.is_some() {
            if let Some(p) = parts.iter().find(|p| p.mesh.uvs().is_none()) {
                return Err(crate::errors::value_error(
                    "material",
                    format!(
                        "the material has texture maps but part '{}' of {} has no UVs",
                        p.name,
                        path.display()
                    ),
                ));
            }
        }
        let first = self.inner.objects().len();
        let n = self
            .inner
            .add_obj_parts(parts, material, back_material, transform)
            .map_err(to_py)?;
        if maps.is_some() {
            // The given material's maps on every part (their UVs were checked above).
            for o in &mut self.inner.objects_mut()[first..] {
                *o = o.clone().with_maps(maps.clone()).map_err(to_py)?;
            }
        }
        Ok(n)
    }

    /// Adds a DirectionalLight, PointLight, SpotLight or AreaLight.
    fn add_light(&mut self, light: &Bound<'_, PyAny>) -> PyResult<()> {
        let (light, given) = light_arg(light, "add_light")?;
        self.inner.add_light(light);
        self.given_directions.push(given);
        Ok(())
    }

    /// The objects, in the order they were added: a tuple of snapshots (read-only; change
    /// the scene with remove_object, set_transform, set_material, clear_objects).
    #[getter]
    fn objects<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let items = self
            .inner
            .objects()
            .iter()
            .map(|o| Bound::new(py, PySceneObject::from_object(o)))
            .collect::<PyResult<Vec<_>>>()?;
        PyTuple::new(py, items)
    }

    /// The lights, in the order they were added, as a tuple of DirectionalLight,
    /// PointLight, SpotLight and AreaLight objects (read-only; change the scene with
    /// add_light, remove_light, set_light, clear_lights).
    #[getter]
    fn lights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let items = self
            .inner
            .lights()
            .iter()
            .zip(&self.given_directions)
            .map(|(l, given)| -> PyResult<Bound<'py, PyAny>> {
                let given = given.unwrap_or_default();
                Ok(match *l {
                    core::Light::Directional(inner) => {
                        Bound::new(py, PyDirectionalLight { inner, given })?.into_any()
                    }
                    core::Light::Point(inner) => Bound::new(py, PyPointLight { inner })?.into_any(),
                    core::Light::Spot(inner) => {
                        Bound::new(py, PySpotLight { inner, given })?.into_any()
                    }
                    core::Light::Area(inner) => Bound::new(py, PyAreaLight { inner })?.into_any(),
                })
            })
            .collect::<PyResult<Vec<_>>>()?;
        PyTuple::new(py, items)
    }

    /// The scene of a scene file (TOML); see `shadelab_rs.load_scene` for the camera and
    /// render options too.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Py<PyAny>> {
        Ok(scene_file_fn(py, "scene_from_file")?
            .call1((path,))?
            .unbind())
    }

    /// The scene described by `d` (the scene-file schema as plain Python data); relative
    /// mesh paths are resolved against `base_dir` (default: the current directory).
    #[staticmethod]
    #[pyo3(signature = (d, base_dir=None))]
    fn from_dict(
        py: Python<'_>,
        d: &Bound<'_, PyAny>,
        base_dir: Option<PathBuf>,
    ) -> PyResult<Py<PyAny>> {
        Ok(scene_file_fn(py, "scene_from_dict")?
            .call1((d, base_dir))?
            .unbind())
    }

    /// This scene as plain Python data in the scene-file schema (meshes inline or as
    /// primitives); `Scene.from_dict(scene.to_dict())` renders bit-identically.
    fn to_dict<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        Ok(scene_file_fn(slf.py(), "scene_to_dict")?
            .call1((slf,))?
            .cast_into::<PyDict>()?)
    }

    /// Global ambient light (r, g, b).
    #[getter]
    fn ambient(&self) -> (f32, f32, f32) {
        self.inner.ambient().into()
    }

    /// Number of objects.
    #[getter]
    fn n_objects(&self) -> usize {
        self.inner.objects().len()
    }

    /// Number of lights.
    #[getter]
    fn n_lights(&self) -> usize {
        self.inner.lights().len()
    }

    /// Total triangles over all objects.
    #[getter]
    fn n_triangles(&self) -> usize {
        self.inner.triangle_count()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(ambient={:?}, two_sided={}, local_viewer={}, fog={}, objects={}, lights={}, triangles={})",
            self.inner.ambient().to_array(),
            self.inner.two_sided(),
            self.inner.local_viewer(),
            self.inner.fog().is_some(),
            self.inner.objects().len(),
            self.inner.lights().len(),
            self.inner.triangle_count()
        )
    }
}
