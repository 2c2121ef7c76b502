//! `Material` and its presets.

use pyo3::prelude::*;
use shadelab_raster as core;

use crate::convert;
use crate::errors::{to_py, value_error};

/// OpenGL-style material: ambient, diffuse, specular RGB and shininess.
#[pyclass(name = "Material", module = "shadelab_rs._core", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyMaterial {
    pub inner: core::Material,
}

/// The shininess as float32; a finite value beyond float32's range is refused rather than
/// becoming the perfect mirror's `inf`.
fn shininess_f32(s: Option<f64>, default: f32) -> PyResult<f32> {
    match s {
        None => Ok(default),
        Some(s) if s.is_finite() && (s as f32).is_infinite() => Err(value_error(
            "shininess",
            format!(
                "material shininess {s:e} is beyond float32's range; use inf for a perfect mirror"
            ),
        )),
        Some(s) => Ok(s as f32),
    }
}

#[pymethods]
impl PyMaterial {
    /// Pickle support: `_core._restore("Material", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "Material", crate::pickle::material_state(&self.inner))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    #[new]
    #[pyo3(signature = (ambient=None, diffuse=None, specular=None, shininess=None, emission=None))]
    fn new(
        ambient: Option<&Bound<'_, PyAny>>,
        diffuse: Option<&Bound<'_, PyAny>>,
        specular: Option<&Bound<'_, PyAny>>,
        shininess: Option<f64>,
        emission: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let d = core::Material::default();
        let pick = |v: Option<&Bound<'_, PyAny>>, name: &str, dflt| -> PyResult<glam::Vec3> {
            v.map_or(Ok(dflt), |v| convert::vec3(v, name))
        };
        let emission = pick(emission, "emission", glam::Vec3::ZERO)?;
        let inner = core::Material::new(
            pick(ambient, "ambient", d.ambient)?,
            pick(diffuse, "diffuse", d.diffuse)?,
            pick(specular, "specular", d.specular)?,
            shininess_f32(shininess, d.shininess)?,
        )
        .and_then(|m| m.with_emission(emission))
        .map_err(to_py)?;
        Ok(PyMaterial { inner })
    }

    /// The named classic preset (case-insensitive; "polished_silver" = "polished silver").
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        Ok(PyMaterial {
            inner: core::Material::preset(name).map_err(to_py)?,
        })
    }

    /// Names of all presets.
    #[staticmethod]
    fn preset_names() -> Vec<&'static str> {
        core::preset_names()
    }

    /// Ambient reflectance (r, g, b).
    #[getter]
    fn ambient(&self) -> (f32, f32, f32) {
        self.inner.ambient.into()
    }

    /// Diffuse reflectance (r, g, b).
    #[getter]
    fn diffuse(&self) -> (f32, f32, f32) {
        self.inner.diffuse.into()
    }

    /// Specular reflectance (r, g, b).
    #[getter]
    fn specular(&self) -> (f32, f32, f32) {
        self.inner.specular.into()
    }

    /// Specular exponent.
    #[getter]
    fn shininess(&self) -> f32 {
        self.inner.shininess
    }

    /// Emitted colour (r, g, b), added unlit.
    #[getter]
    fn emission(&self) -> (f32, f32, f32) {
        self.inner.emission.into()
    }

    fn __repr__(&self) -> String {
        let m = &self.inner;
        format!(
            "Material(ambient={:?}, diffuse={:?}, specular={:?}, shininess={}, emission={:?})",
            m.ambient.to_array(),
            m.diffuse.to_array(),
            m.specular.to_array(),
            m.shininess,
            m.emission.to_array()
        )
    }
}
