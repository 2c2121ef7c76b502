//! `AreaLight`.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use shadelab_raster as core;

use crate::convert;
use crate::errors::{to_py, type_error, value_error};

/// A rectangle or disk light modelled by `samples**2` point sources.
#[pyclass(name = "AreaLight", module = "shadelab_rs._core", frozen)]
#[derive(Clone)]
pub struct PyAreaLight {
    pub inner: core::AreaLight,
}

fn shape_arg(shape: &str) -> PyResult<core::AreaShape> {
    match shape {
        "rectangle" => Ok(core::AreaShape::Rectangle),
        "disk" => Ok(core::AreaShape::Disk),
        _ => Err(value_error(
            "shape",
            format!("unknown area light shape '{shape}'; expected 'rectangle' or 'disk'"),
        )),
    }
}

fn samples_arg(obj: &Bound<'_, PyAny>) -> PyResult<u32> {
    let bad_type = || -> PyResult<PyErr> {
        Ok(type_error(
            "samples",
            format!("samples must be an integer, got {}", obj.get_type().name()?),
        ))
    };
    if obj.is_instance_of::<pyo3::types::PyBool>() || obj.is_instance_of::<pyo3::types::PyFloat>() {
        return Err(bad_type()?);
    }
    let out_of_range = || {
        value_error(
            "samples",
            format!(
                "area light samples must be between 1 and {} per side, got {obj}",
                core::MAX_AREA_SAMPLES
            ),
        )
    };
    match obj.extract::<i64>() {
        Ok(v) => u32::try_from(v).map_err(|_| out_of_range()),
        Err(e) if e.is_instance_of::<pyo3::exceptions::PyOverflowError>(obj.py()) => {
            Err(out_of_range())
        }
        Err(_) => Err(bad_type()?),
    }
}

#[pymethods]
impl PyAreaLight {
    /// Pickle support: `_core._restore("AreaLight", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "AreaLight", crate::pickle::area_state(&self.inner))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    #[new]
    #[pyo3(signature = (position, u, v, shape="rectangle", samples=None, color=None,
                        intensity=1.0, attenuation=None, ambient=None, one_sided=false,
                        diffuse=None, specular=None, shadows=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        position: &Bound<'_, PyAny>,
        u: &Bound<'_, PyAny>,
        v: &Bound<'_, PyAny>,
        shape: &str,
        samples: Option<&Bound<'_, PyAny>>,
        color: Option<&Bound<'_, PyAny>>,
        intensity: f64,
        attenuation: Option<&Bound<'_, PyAny>>,
        ambient: Option<&Bound<'_, PyAny>>,
        one_sided: bool,
        diffuse: Option<&Bound<'_, PyAny>>,
        specular: Option<&Bound<'_, PyAny>>,
        shadows: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let shadows = crate::shadow::shadows_arg(shadows)?;
        let (diffuse, specular) = crate::light::split_colors(diffuse, specular)?;
        let shape = shape_arg(shape)?;
        let samples = samples.map_or(Ok(4), samples_arg)?;
        let color = color.map_or(Ok(glam::Vec3::ONE), |c| convert::vec3(c, "color"))?;
        let ambient = ambient.map_or(Ok(glam::Vec3::ZERO), |a| convert::vec3(a, "ambient"))?;
        let k = attenuation.map_or(Ok(glam::Vec3::X), |a| convert::vec3(a, "attenuation"))?;
        let position = convert::vec3(position, "position")?;
        let u = convert::vec3(u, "u")?;
        let v = convert::vec3(v, "v")?;
        let inner = core::AreaLight::new(position, u, v, shape, samples)
            .and_then(|l| l.with_color(color, intensity as f32))
            .and_then(|l| l.with_ambient(ambient))
            .and_then(|l| l.with_attenuation(k.x, k.y, k.z))
            .and_then(|l| l.with_split_colors(diffuse, specular))
            .map(|l| l.with_one_sided(one_sided).with_shadows(shadows))
            .map_err(to_py)?;
        Ok(Self { inner })
    }

    /// Centre.
    #[getter]
    fn position(&self) -> (f32, f32, f32) {
        self.inner.position().into()
    }

    /// First edge vector.
    #[getter]
    fn u(&self) -> (f32, f32, f32) {
        self.inner.u().into()
    }

    /// Second edge vector.
    #[getter]
    fn v(&self) -> (f32, f32, f32) {
        self.inner.v().into()
    }

    /// Unit normal u × v / |u × v|: the emitting side of a one-sided light.
    #[getter]
    fn normal(&self) -> (f32, f32, f32) {
        self.inner.normal().into()
    }

    /// "rectangle" or "disk".
    #[getter]
    fn shape(&self) -> &'static str {
        match self.inner.shape() {
            core::AreaShape::Rectangle => "rectangle",
            core::AreaShape::Disk => "disk",
        }
    }

    /// Points per side.
    #[getter]
    fn samples(&self) -> u32 {
        self.inner.samples()
    }

    /// Number of point sources (samples**2): the per-pixel cost in point lights.
    #[getter]
    fn n_points(&self) -> usize {
        self.inner.n_points()
    }

    /// Whether only the side the normal points to emits (with a cosine fall-off).
    #[getter]
    fn one_sided(&self) -> bool {
        self.inner.one_sided()
    }

    /// RGB colour of the whole light.
    #[getter]
    fn color(&self) -> (f32, f32, f32) {
        self.inner.color.into()
    }

    /// Multiplier of `color`, shared equally by the points.
    #[getter]
    fn intensity(&self) -> f32 {
        self.inner.intensity
    }

    /// The light's own diffuse colour, or None when `color` sets it.
    #[getter]
    fn diffuse(&self) -> Option<(f32, f32, f32)> {
        self.inner.split.diffuse.map(Into::into)
    }

    /// The light's own specular colour, or None when `color` sets it.
    #[getter]
    fn specular(&self) -> Option<(f32, f32, f32)> {
        self.inner.split.specular.map(Into::into)
    }

    /// Distance attenuation (kc, kl, kq), applied per point.
    #[getter]
    fn attenuation(&self) -> (f32, f32, f32) {
        let [a, b, c] = self.inner.attenuation;
        (a, b, c)
    }

    /// The light's own ambient colour, shared by the points and attenuated like the rest.
    #[getter]
    fn ambient(&self) -> (f32, f32, f32) {
        self.inner.ambient.into()
    }

    /// The sample positions as an (n_points, 3) float32 array.
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        let pts = self.inner.points();
        let flat: Vec<f32> = pts.iter().flat_map(|p| p.to_array()).collect();
        Array2::from_shape_vec((pts.len(), 3), flat)
            .expect("n x 3 values")
            .into_pyarray(py)
    }

    /// False, True (a shadow map, default settings), "exact" (shadow rays) or the
    /// ShadowSettings of its map.
    #[getter]
    fn shadows(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        crate::shadow::shadows_object(py, self.inner.shadows)
    }

    fn __repr__(&self) -> String {
        format!(
            "AreaLight(position={:?}, u={:?}, v={:?}, shape='{}', samples={}, one_sided={})",
            self.inner.position().to_array(),
            self.inner.u().to_array(),
            self.inner.v().to_array(),
            self.shape(),
            self.inner.samples(),
            if self.inner.one_sided() {
                "True"
            } else {
                "False"
            }
        )
    }
}
