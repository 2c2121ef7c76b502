//! `Fog`.

use pyo3::prelude::*;
use shadelab_raster as core;

use crate::convert;
use crate::errors::{to_py, value_error};

/// Depth cueing: colours blend toward `color` with the Euclidean distance from the eye.
#[pyclass(name = "Fog", module = "shadelab_rs._core", frozen)]
#[derive(Clone)]
pub struct PyFog {
    pub inner: core::Fog,
}

#[pymethods]
impl PyFog {
    /// Pickle support: `_core._restore("Fog", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "Fog", crate::pickle::fog_state(&self.inner))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    #[new]
    #[pyo3(signature = (mode="linear", start=0.0, end=1.0, density=1.0, color=None))]
    fn new(
        mode: &str,
        start: f64,
        end: f64,
        density: f64,
        color: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let color = color.map_or(Ok(glam::Vec3::splat(0.5)), |c| convert::vec3(c, "color"))?;
        let mode = match mode {
            "linear" => core::FogMode::Linear {
                start: start as f32,
                end: end as f32,
            },
            "exp" => core::FogMode::Exp {
                density: density as f32,
            },
            "exp2" => core::FogMode::Exp2 {
                density: density as f32,
            },
            other => {
                return Err(value_error(
                    "mode",
                    format!("unknown fog mode '{other}'; expected 'linear', 'exp' or 'exp2'"),
                ))
            }
        };
        Ok(PyFog {
            inner: core::Fog::new(mode, color).map_err(to_py)?,
        })
    }

    /// "linear", "exp" or "exp2".
    #[getter]
    fn mode(&self) -> &'static str {
        match self.inner.mode() {
            core::FogMode::Linear { .. } => "linear",
            core::FogMode::Exp { .. } => "exp",
            core::FogMode::Exp2 { .. } => "exp2",
        }
    }

    /// Linear fog: where it starts (None otherwise).
    #[getter]
    fn start(&self) -> Option<f32> {
        match self.inner.mode() {
            core::FogMode::Linear { start, .. } => Some(start),
            _ => None,
        }
    }

    /// Linear fog: where only fog is left (None otherwise).
    #[getter]
    fn end(&self) -> Option<f32> {
        match self.inner.mode() {
            core::FogMode::Linear { end, .. } => Some(end),
            _ => None,
        }
    }

    /// Exp/exp2 fog: the density (None for linear).
    #[getter]
    fn density(&self) -> Option<f32> {
        match self.inner.mode() {
            core::FogMode::Exp { density } | core::FogMode::Exp2 { density } => Some(density),
            core::FogMode::Linear { .. } => None,
        }
    }

    /// The colour far objects fade to.
    #[getter]
    fn color(&self) -> (f32, f32, f32) {
        self.inner.color().into()
    }

    /// The fog factor f in [0, 1] at eye distance `d` (1: no fog).
    fn factor(&self, d: f64) -> f32 {
        self.inner.factor(d as f32)
    }

    fn __repr__(&self) -> String {
        match self.inner.mode() {
            core::FogMode::Linear { start, end } => format!(
                "Fog(mode='linear', start={start}, end={end}, color={:?})",
                self.inner.color().to_array()
            ),
            core::FogMode::Exp { density } | core::FogMode::Exp2 { density } => format!(
                "Fog(mode='{}', density={density}, color={:?})",
                self.mode(),
                self.inner.color().to_array()
            ),
        }
    }
}
