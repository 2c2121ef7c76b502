//! `Scene`.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Mat4;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use shadelab_raster as core;

use crate::area_light::PyAreaLight;
use crate::convert;
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
    transform: Mat4,
}

impl PySceneObject {
    /// The snapshot of a scene's object.
    pub fn from_object(o: &core::Object) -> Self {
        PySceneObject {
            mesh: o.mesh().clone(),
            material: *o.material(),
            back_material: o.back_material().copied(),
            transform: o.transform(),
        }
    }
}

#[pymethods]
impl PySceneObject {
    /// Pickle support: `_core._restore("SceneObject", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
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
            transform: self.transform,
        }
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        PySceneObject {
            mesh: self.mesh.clone(),
            material: self.material,
            back_material: self.back_material,
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
        }
    }

    /// The material of back faces under two-sided lighting, or None (`material` then).
    #[getter]
    fn back_material(&self) -> Option<PyMaterial> {
        self.back_material.map(|inner| PyMaterial { inner })
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
}

#[pymethods]
impl PyScene {
    /// Pickle support: `_core._restore("Scene", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "Scene", crate::pickle::scene_state(py, &self.inner)?)
    }

    fn __copy__(&self) -> Self {
        // Meshes are immutable and stay shared; everything else is copied.
        PyScene {
            inner: self.inner.clone(),
        }
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        // Meshes are immutable and stay shared; everything else is copied.
        PyScene {
            inner: self.inner.clone(),
        }
    }
    #[new]
    #[pyo3(signature = (ambient=None, fog=None, two_sided=false, local_viewer=true))]
    fn new(
        ambient: Option<&Bound<'_, PyAny>>,
        fog: Option<PyFog>,
        two_sided: bool,
        local_viewer: bool,
    ) -> PyResult<Self> {
        let ambient =
            ambient.map_or(Ok(glam::Vec3::splat(0.2)), |a| convert::vec3(a, "ambient"))?;
        let mut inner = core::Scene::new(ambient).map_err(to_py)?;
        inner.set_fog(fog.map(|f| f.inner));
        inner.set_two_sided(two_sided);
        inner.set_local_viewer(local_viewer);
        Ok(PyScene { inner })
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

    /// Local viewer (True, default) or OpenGL's infinite viewer (False).
    #[getter]
    fn get_local_viewer(&self) -> bool {
        self.inner.local_viewer()
    }

    #[setter]
    fn set_local_viewer(&mut self, local: bool) {
        self.inner.set_local_viewer(local);
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
    #[pyo3(signature = (mesh, material=None, transform=None, back_material=None))]
    fn add(
        &mut self,
        mesh: &PyMesh,
        material: Option<&PyMaterial>,
        transform: Option<&Bound<'_, PyAny>>,
        back_material: Option<&PyMaterial>,
    ) -> PyResult<()> {
        let material = material.map_or_else(core::Material::default, |m| m.inner);
        let transform = transform.map_or(Ok(Mat4::IDENTITY), |t| convert::mat4(t, "transform"))?;
        let object = core::Object::new(mesh.inner.clone(), material, transform)
            .map_err(to_py)?
            .with_back_material(back_material.map(|m| m.inner));
        self.inner.add_object(object);
        Ok(())
    }

    /// Loads an OBJ file and adds each of its parts (per group and per `usemtl`) as an
    /// object with its MTL material, or with `material` for all of them when given; returns
    /// the number of objects added.
    #[pyo3(signature = (path, material=None, transform=None, back_material=None))]
    fn add_obj(
        &mut self,
        py: Python<'_>,
        path: std::path::PathBuf,
        material: Option<&PyMaterial>,
        transform: Option<&Bound<'_, PyAny>>,
        back_material: Option<&PyMaterial>,
    ) -> PyResult<usize> {
        let transform = transform.map_or(Ok(Mat4::IDENTITY), |t| convert::mat4(t, "transform"))?;
        let parts = py
            .detach(|| crate::errors::no_panic("add_obj", || core::load_obj_parts(&path)))?
            .map_err(to_py)?;
        self.inner
            .add_obj_parts(
                parts,
                material.map(|m| m.inner),
                back_material.map(|m| m.inner),
                transform,
            )
            .map_err(to_py)
    }

    /// Adds a DirectionalLight, PointLight, SpotLight or AreaLight.
    fn add_light(&mut self, light: &Bound<'_, PyAny>) -> PyResult<()> {
        if let Ok(l) = light.extract::<PyRef<'_, PyDirectionalLight>>() {
            self.inner.add_light(l.inner);
        } else if let Ok(l) = light.extract::<PyRef<'_, PyPointLight>>() {
            self.inner.add_light(l.inner);
        } else if let Ok(l) = light.extract::<PyRef<'_, PySpotLight>>() {
            self.inner.add_light(l.inner);
        } else if let Ok(l) = light.extract::<PyRef<'_, PyAreaLight>>() {
            self.inner.add_light(l.inner);
        } else {
            return Err(PyTypeError::new_err(format!(
                "add_light expects a DirectionalLight, PointLight, SpotLight or AreaLight, got {}",
                light.get_type().name()?
            )));
        }
        Ok(())
    }

    /// The objects, in the order they were added (snapshots).
    #[getter]
    fn objects(&self) -> Vec<PySceneObject> {
        self.inner
            .objects()
            .iter()
            .map(PySceneObject::from_object)
            .collect()
    }

    /// The lights, in the order they were added, as DirectionalLight, PointLight,
    /// SpotLight and AreaLight objects.
    #[getter]
    fn lights<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        self.inner
            .lights()
            .iter()
            .map(|l| -> PyResult<Bound<'py, PyAny>> {
                Ok(match *l {
                    core::Light::Directional(inner) => {
                        Bound::new(py, PyDirectionalLight { inner })?.into_any()
                    }
                    core::Light::Point(inner) => Bound::new(py, PyPointLight { inner })?.into_any(),
                    core::Light::Spot(inner) => Bound::new(py, PySpotLight { inner })?.into_any(),
                    core::Light::Area(inner) => Bound::new(py, PyAreaLight { inner })?.into_any(),
                })
            })
            .collect()
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
