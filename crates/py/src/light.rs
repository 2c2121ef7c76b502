//! Light classes.

use pyo3::prelude::*;
use shadelab_raster as core;

use crate::convert;
use crate::errors::to_py;

/// Optional `diffuse` / `specular` colour arguments of a light.
pub fn split_colors(
    diffuse: Option<&Bound<'_, PyAny>>,
    specular: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Option<glam::Vec3>, Option<glam::Vec3>)> {
    Ok((
        diffuse.map(|c| convert::vec3(c, "diffuse")).transpose()?,
        specular.map(|c| convert::vec3(c, "specular")).transpose()?,
    ))
}

fn tuple(v: Option<glam::Vec3>) -> Option<(f32, f32, f32)> {
    v.map(Into::into)
}

/// A light at infinity; `direction` is where the light travels (a sun overhead: (0, -1, 0)).
#[pyclass(name = "DirectionalLight", module = "shadelab_rs._core", frozen)]
#[derive(Clone)]
pub struct PyDirectionalLight {
    pub inner: core::DirectionalLight,
    /// The direction as the user gave it (the core keeps its float32 unit vector), so
    /// writing a light and reading it back gives the same light exactly.
    pub given: [f64; 3],
}

#[pymethods]
impl PyDirectionalLight {
    /// Pickle support: `_core._restore("DirectionalLight", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(
            py,
            "DirectionalLight",
            crate::pickle::directional_state(self),
        )
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    #[new]
    #[pyo3(signature = (direction, color=None, intensity=1.0, ambient=None, diffuse=None,
                        specular=None, shadows=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        direction: &Bound<'_, PyAny>,
        color: Option<&Bound<'_, PyAny>>,
        intensity: f64,
        ambient: Option<&Bound<'_, PyAny>>,
        diffuse: Option<&Bound<'_, PyAny>>,
        specular: Option<&Bound<'_, PyAny>>,
        shadows: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let shadows = crate::shadow::shadows_arg(shadows)?;
        let (diffuse, specular) = split_colors(diffuse, specular)?;
        let color = color.map_or(Ok(glam::Vec3::ONE), |c| convert::vec3(c, "color"))?;
        let ambient = ambient.map_or(Ok(glam::Vec3::ZERO), |a| convert::vec3(a, "ambient"))?;
        let given = convert::dvec3(direction, "direction")?.to_array();
        let direction = convert::vec3(direction, "direction")?;
        let inner = core::DirectionalLight::new(direction, color, intensity as f32)
            .and_then(|l| l.with_ambient(ambient))
            .and_then(|l| l.with_split_colors(diffuse, specular))
            .map(|l| l.with_shadows(shadows))
            .map_err(to_py)?;
        Ok(Self { inner, given })
    }

    /// The light's own ambient colour (r, g, b).
    #[getter]
    fn ambient(&self) -> (f32, f32, f32) {
        self.inner.ambient.into()
    }

    /// The direction of travel as given (not normalised: the light uses its unit vector).
    #[getter]
    fn direction(&self) -> (f64, f64, f64) {
        self.given.into()
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

    /// The light's own diffuse colour, or None when `color` sets it.
    #[getter]
    fn diffuse(&self) -> Option<(f32, f32, f32)> {
        tuple(self.inner.split.diffuse)
    }

    /// The light's own specular colour, or None when `color` sets it.
    #[getter]
    fn specular(&self) -> Option<(f32, f32, f32)> {
        tuple(self.inner.split.specular)
    }

    /// False, True (a shadow map, default settings), "exact" (shadow rays) or the
    /// ShadowSettings of its map.
    #[getter]
    fn shadows(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        crate::shadow::shadows_object(py, self.inner.shadows)
    }

    fn __repr__(&self) -> String {
        format!(
            "DirectionalLight(direction={:?}, color={:?}, intensity={})",
            self.given,
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
    /// Pickle support: `_core._restore("PointLight", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "PointLight", crate::pickle::point_state(&self.inner))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    #[new]
    #[pyo3(signature = (position, color=None, intensity=1.0, attenuation=None, ambient=None,
                        diffuse=None, specular=None, shadows=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        position: &Bound<'_, PyAny>,
        color: Option<&Bound<'_, PyAny>>,
        intensity: f64,
        attenuation: Option<&Bound<'_, PyAny>>,
        ambient: Option<&Bound<'_, PyAny>>,
        diffuse: Option<&Bound<'_, PyAny>>,
        specular: Option<&Bound<'_, PyAny>>,
        shadows: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let shadows = crate::shadow::shadows_arg(shadows)?;
        let (diffuse, specular) = split_colors(diffuse, specular)?;
        let color = color.map_or(Ok(glam::Vec3::ONE), |c| convert::vec3(c, "color"))?;
        let ambient = ambient.map_or(Ok(glam::Vec3::ZERO), |a| convert::vec3(a, "ambient"))?;
        let k = attenuation.map_or(Ok(glam::Vec3::X), |a| convert::vec3(a, "attenuation"))?;
        let position = convert::vec3(position, "position")?;
        let inner = core::PointLight::new(position, color, intensity as f32)
            .and_then(|l| l.with_ambient(ambient))
            .and_then(|l| l.with_attenuation(k.x, k.y, k.z))
            .and_then(|l| l.with_split_colors(diffuse, specular))
            .map(|l| l.with_shadows(shadows))
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

    /// The light's own diffuse colour, or None when `color` sets it.
    #[getter]
    fn diffuse(&self) -> Option<(f32, f32, f32)> {
        tuple(self.inner.split.diffuse)
    }

    /// The light's own specular colour, or None when `color` sets it.
    #[getter]
    fn specular(&self) -> Option<(f32, f32, f32)> {
        tuple(self.inner.split.specular)
    }

    /// False, True (a shadow map, default settings), "exact" (shadow rays) or the
    /// ShadowSettings of its map.
    #[getter]
    fn shadows(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        crate::shadow::shadows_object(py, self.inner.shadows)
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

/// A point light restricted to a cone (OpenGL's GL_SPOT_CUTOFF / GL_SPOT_EXPONENT).
#[pyclass(name = "SpotLight", module = "shadelab_rs._core", frozen)]
#[derive(Clone)]
pub struct PySpotLight {
    pub inner: core::SpotLight,
    /// The direction as given; see `PyDirectionalLight::given`.
    pub given: [f64; 3],
}

#[pymethods]
impl PySpotLight {
    /// Pickle support: `_core._restore("SpotLight", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "SpotLight", crate::pickle::spot_state(self))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    #[new]
    #[pyo3(signature = (position, direction, cutoff=30.0, exponent=0.0, color=None, intensity=1.0,
                        attenuation=None, ambient=None, inner=None, diffuse=None, specular=None,
                        shadows=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        position: &Bound<'_, PyAny>,
        direction: &Bound<'_, PyAny>,
        cutoff: f64,
        exponent: f64,
        color: Option<&Bound<'_, PyAny>>,
        intensity: f64,
        attenuation: Option<&Bound<'_, PyAny>>,
        ambient: Option<&Bound<'_, PyAny>>,
        inner: Option<f64>,
        diffuse: Option<&Bound<'_, PyAny>>,
        specular: Option<&Bound<'_, PyAny>>,
        shadows: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let point = PyPointLight::new(
            position,
            color,
            intensity,
            attenuation,
            ambient,
            diffuse,
            specular,
            shadows,
        )?
        .inner;
        let given = convert::dvec3(direction, "direction")?.to_array();
        let direction = convert::vec3(direction, "direction")?;
        let spot = core::SpotLight::new(point, direction, cutoff as f32, exponent as f32)
            .and_then(|s| match inner {
                Some(i) => s.with_inner(i as f32),
                None => Ok(s),
            })
            .map_err(to_py)?;
        Ok(Self { inner: spot, given })
    }

    /// World position.
    #[getter]
    fn position(&self) -> (f32, f32, f32) {
        self.inner.point.position.into()
    }

    /// The direction the cone points, as given (not normalised: the light uses its unit
    /// vector).
    #[getter]
    fn direction(&self) -> (f64, f64, f64) {
        self.given.into()
    }

    /// Cone half-angle in degrees (180: no cone).
    #[getter]
    fn cutoff(&self) -> f32 {
        self.inner.cutoff()
    }

    /// Fall-off exponent.
    #[getter]
    fn exponent(&self) -> f32 {
        self.inner.exponent()
    }

    /// Inner angle of the smooth edge in degrees, or None.
    #[getter]
    fn inner(&self) -> Option<f32> {
        self.inner.inner()
    }

    /// RGB colour.
    #[getter]
    fn color(&self) -> (f32, f32, f32) {
        self.inner.point.color.into()
    }

    /// Multiplier of `color`.
    #[getter]
    fn intensity(&self) -> f32 {
        self.inner.point.intensity
    }

    /// The light's own diffuse colour, or None when `color` sets it.
    #[getter]
    fn diffuse(&self) -> Option<(f32, f32, f32)> {
        tuple(self.inner.point.split.diffuse)
    }

    /// The light's own specular colour, or None when `color` sets it.
    #[getter]
    fn specular(&self) -> Option<(f32, f32, f32)> {
        tuple(self.inner.point.split.specular)
    }

    /// Distance attenuation (kc, kl, kq).
    #[getter]
    fn attenuation(&self) -> (f32, f32, f32) {
        let [a, b, c] = self.inner.point.attenuation;
        (a, b, c)
    }

    /// The light's own ambient colour, scaled by attenuation and the spot factor.
    #[getter]
    fn ambient(&self) -> (f32, f32, f32) {
        self.inner.point.ambient.into()
    }

    /// False, True (a shadow map, default settings), "exact" (shadow rays) or the
    /// ShadowSettings of its map.
    #[getter]
    fn shadows(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        crate::shadow::shadows_object(py, self.inner.point.shadows)
    }

    fn __repr__(&self) -> String {
        format!(
            "SpotLight(position={:?}, direction={:?}, cutoff={}, exponent={}, inner={:?})",
            self.inner.point.position.to_array(),
            self.given,
            self.inner.cutoff(),
            self.inner.exponent(),
            self.inner.inner()
        )
    }
}
