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
    #[pyo3(signature = (direction, color=None, intensity=1.0, ambient=None))]
    fn new(
        direction: &Bound<'_, PyAny>,
        color: Option<&Bound<'_, PyAny>>,
        intensity: f64,
        ambient: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let color = color.map_or(Ok(glam::Vec3::ONE), |c| convert::vec3(c, "color"))?;
        let ambient = ambient.map_or(Ok(glam::Vec3::ZERO), |a| convert::vec3(a, "ambient"))?;
        let direction = convert::vec3(direction, "direction")?;
        let inner = core::DirectionalLight::new(direction, color, intensity as f32)
            .and_then(|l| l.with_ambient(ambient))
            .map_err(to_py)?;
        Ok(Self { inner })
    }

    /// The light's own ambient colour (r, g, b).
    #[getter]
    fn ambient(&self) -> (f32, f32, f32) {
        self.inner.ambient.into()
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
    #[pyo3(signature = (position, color=None, intensity=1.0, attenuation=None, ambient=None))]
    fn new(
        position: &Bound<'_, PyAny>,
        color: Option<&Bound<'_, PyAny>>,
        intensity: f64,
        attenuation: Option<&Bound<'_, PyAny>>,
        ambient: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let color = color.map_or(Ok(glam::Vec3::ONE), |c| convert::vec3(c, "color"))?;
        let ambient = ambient.map_or(Ok(glam::Vec3::ZERO), |a| convert::vec3(a, "ambient"))?;
        let k = attenuation.map_or(Ok(glam::Vec3::X), |a| convert::vec3(a, "attenuation"))?;
        let position = convert::vec3(position, "position")?;
        let inner = core::PointLight::new(position, color, intensity as f32)
            .and_then(|l| l.with_ambient(ambient))
            .and_then(|l| l.with_attenuation(k.x, k.y, k.z))
            .map_err(to_py)?;
        Ok(Self { inner })
    }

    /// The light's own ambient colour (r, g, b), attenuated like the rest.
    #[getter]
    fn ambient(&self) -> (f32, f32, f32) {
        self.inner.ambient.into()
    }

    /// Distance attenuation (kc, kl, kq): the light is divided by kc + kl·d + kq·d².
    #[getter]
    fn attenuation(&self) -> (f32, f32, f32) {
        let [a, b, c] = self.inner.attenuation;
        (a, b, c)
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
