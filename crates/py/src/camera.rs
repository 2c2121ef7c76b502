//! `Camera`.

use pyo3::prelude::*;
use shadelab_raster as core;

use crate::convert;
use crate::errors::to_py;

/// A look-at camera with perspective or orthographic projection (OpenGL conventions).
#[pyclass(name = "Camera", module = "shadelab_rs._core", frozen)]
#[derive(Clone)]
pub struct PyCamera {
    pub inner: core::Camera,
}

fn up_or_y(up: Option<&Bound<'_, PyAny>>) -> PyResult<glam::DVec3> {
    up.map_or(Ok(glam::DVec3::Y), |u| convert::dvec3(u, "up"))
}

#[pymethods]
impl PyCamera {
    /// Pickle support: `_core._restore("Camera", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "Camera", crate::pickle::camera_state(&self.inner))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    /// Perspective camera; `fov_y` is the full vertical angle in degrees.
    #[staticmethod]
    #[pyo3(signature = (eye, target, up=None, fov_y=45.0, near=0.1, far=100.0))]
    fn look_at(
        eye: &Bound<'_, PyAny>,
        target: &Bound<'_, PyAny>,
        up: Option<&Bound<'_, PyAny>>,
        fov_y: f64,
        near: f64,
        far: f64,
    ) -> PyResult<Self> {
        let inner = core::Camera::look_at(
            convert::dvec3(eye, "eye")?,
            convert::dvec3(target, "target")?,
            up_or_y(up)?,
            fov_y,
            near,
            far,
        )
        .map_err(to_py)?;
        Ok(Self { inner })
    }

    /// Orthographic camera; `height` is the view's vertical extent in world units.
    #[staticmethod]
    #[pyo3(signature = (eye, target, up=None, height=2.0, near=0.1, far=100.0))]
    fn orthographic(
        eye: &Bound<'_, PyAny>,
        target: &Bound<'_, PyAny>,
        up: Option<&Bound<'_, PyAny>>,
        height: f64,
        near: f64,
        far: f64,
    ) -> PyResult<Self> {
        let inner = core::Camera::orthographic(
            convert::dvec3(eye, "eye")?,
            convert::dvec3(target, "target")?,
            up_or_y(up)?,
            height,
            near,
            far,
        )
        .map_err(to_py)?;
        Ok(Self { inner })
    }

    /// Eye position.
    #[getter]
    fn eye(&self) -> (f64, f64, f64) {
        self.inner.eye().into()
    }

    /// Point looked at.
    #[getter]
    fn target(&self) -> (f64, f64, f64) {
        self.inner.target().into()
    }

    /// Up hint.
    #[getter]
    fn up(&self) -> (f64, f64, f64) {
        self.inner.up().into()
    }

    /// Near plane distance.
    #[getter]
    fn near(&self) -> f64 {
        self.inner.near()
    }

    /// Far plane distance.
    #[getter]
    fn far(&self) -> f64 {
        self.inner.far()
    }

    /// "perspective" or "orthographic".
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner.projection() {
            core::Projection::Perspective { .. } => "perspective",
            core::Projection::Orthographic { .. } => "orthographic",
        }
    }

    /// Vertical field of view in degrees (None for orthographic).
    #[getter]
    fn fov_y(&self) -> Option<f64> {
        match self.inner.projection() {
            core::Projection::Perspective { fov_y } => Some(fov_y),
            core::Projection::Orthographic { .. } => None,
        }
    }

    /// Vertical extent (None for perspective).
    #[getter]
    fn height(&self) -> Option<f64> {
        match self.inner.projection() {
            core::Projection::Orthographic { height } => Some(height),
            core::Projection::Perspective { .. } => None,
        }
    }

    fn __repr__(&self) -> String {
        let c = &self.inner;
        let proj = match c.projection() {
            core::Projection::Perspective { fov_y } => format!("fov_y={fov_y}"),
            core::Projection::Orthographic { height } => format!("height={height}"),
        };
        format!(
            "Camera.{}(eye={:?}, target={:?}, up={:?}, {proj}, near={}, far={})",
            if self.fov_y().is_some() {
                "look_at"
            } else {
                "orthographic"
            },
            c.eye().to_array(),
            c.target().to_array(),
            c.up().to_array(),
            c.near(),
            c.far()
        )
    }
}
