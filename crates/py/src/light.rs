//! Light classes.

use pyo3::prelude::*;
use shadelab_raster as core;

use crate::convert;
use crate::errors::to_py;

/// A light at infinity; `direction` is where the light travels (a sun overhead: (0, -1, 0)).
#[pyclass(name = "DirectionalLight", module = "shadelab_rs._core", frozen)]
#[derive(Clone)]
pub struct PyDirectionalLight {
    pub inner: core::DirectionalLight,
}

#[pymethods]
impl PyDirectionalLight {
    #[new]
    #[pyo3(signature = (direction, color=None, intensity=1.0))]
    fn new(
        direction: &Bound<'_, PyAny>,
        color: Option<&Bound<'_, PyAny>>,
        intensity: f64,
    ) -> PyResult<Self> {
        let color = color.map_or(Ok(glam::Vec3::ONE), |c| convert::vec3(c, "color"))?;
        let inner = core::DirectionalLight::new(
            convert::vec3(direction, "direction")?,
            color,
            intensity as f32,
        )
        .map_err(to_py)?;
        Ok(Self { inner })
    }

    /// Unit direction of travel.
    #[getter]
    fn direction(&self) -> (f32, f32, f32) {
        self.inner.direction().into()
    }

    /// RGB colour.
    #[getter]
    fn color(&self) -> (f32, f32, f32) {
        self.inner.color.into()
    }

    /// Multiplier of `color`.
    #[getter]
    fn intensity(&self) -> f32 {
        self.inner.intensity
    }

    fn __repr__(&self) -> String {
        format!(
            "DirectionalLight(direction={:?}, color={:?}, intensity={})",
            self.inner.direction().to_array(),
            self.inner.color.to_array(),
            self.inner.intensity
        )
    }
}

/// A light at a point, shining in all directions.
#[pyclass(name = "PointLight", module = "shadelab_rs._core", frozen)]
#[derive(Clone)]
pub struct PyPointLight {
    pub inner: core::PointLight,
}

#[pymethods]
impl PyPointLight {
    #[new]
    #[pyo3(signature = (position, color=None, intensity=1.0))]
    fn new(
        position: &Bound<'_, PyAny>,
        color: Option<&Bound<'_, PyAny>>,
        intensity: f64,
    ) -> PyResult<Self> {
        let color = color.map_or(Ok(glam::Vec3::ONE), |c| convert::vec3(c, "color"))?;
        let inner = core::PointLight::new(
            convert::vec3(position, "position")?,
            color,
            intensity as f32,
        )
        .map_err(to_py)?;
        Ok(Self { inner })
    }

    /// World position.
    #[getter]
    fn position(&self) -> (f32, f32, f32) {
        self.inner.position.into()
    }

    /// RGB colour.
    #[getter]
    fn color(&self) -> (f32, f32, f32) {
        self.inner.color.into()
    }

    /// Multiplier of `color`.
    #[getter]
    fn intensity(&self) -> f32 {
        self.inner.intensity
    }

    fn __repr__(&self) -> String {
        format!(
            "PointLight(position={:?}, color={:?}, intensity={})",
            self.inner.position.to_array(),
            self.inner.color.to_array(),
            self.inner.intensity
        )
    }
}
