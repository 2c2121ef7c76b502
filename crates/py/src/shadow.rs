//! `ShadowSettings` and the `shadows=` argument of every light: False (off), True (a shadow
//! map with the default settings), "exact" (shadow rays) or a `ShadowSettings`.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyString};
use shadelab_raster as core;

use crate::errors::{to_py, type_error, value_error};

/// A shadow map's resolution, filter, bias and cascades (`shadows=ShadowSettings(...)` on
/// a light).
#[pyclass(name = "ShadowSettings", module = "shadelab_rs._core", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyShadowSettings {
    pub inner: core::ShadowSettings,
}

#[pymethods]
impl PyShadowSettings {
    /// Pickle support: `_core._restore("ShadowSettings", state)` rebuilds this value.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "ShadowSettings", settings_state(&self.inner))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    #[new]
    #[pyo3(signature = (resolution=2048, filter="pcf", kernel=3, bias=1.0, cascades=1))]
    fn new(resolution: i64, filter: &str, kernel: i64, bias: f64, cascades: i64) -> PyResult<Self> {
        let resolution = u32::try_from(resolution).map_err(|_| {
            value_error(
                "resolution",
                format!(
                    "shadow map resolution must be 16 to {}, got {resolution}",
                    core::MAX_SHADOW_RESOLUTION
                ),
            )
        })?;
        let filter = match filter {
            "none" => core::ShadowFilter::None,
            "pcf" => core::ShadowFilter::Pcf(u32::try_from(kernel).map_err(|_| {
                value_error(
                    "kernel",
                    format!("PCF kernel must be odd, 3 to 9, got {kernel}"),
                )
            })?),
            other => {
                return Err(value_error(
                    "filter",
                    format!("unknown shadow filter '{other}'; expected 'pcf' or 'none'"),
                ))
            }
        };
        let cascades = u32::try_from(cascades).map_err(|_| {
            value_error(
                "cascades",
                format!(
                    "shadow cascades must be 1 to {}, got {cascades}",
                    core::MAX_CASCADES
                ),
            )
        })?;
        Ok(Self {
            inner: core::ShadowSettings::new(resolution, filter, bias as f32)
                .and_then(|s| s.with_cascades(cascades))
                .map_err(to_py)?,
        })
    }

    /// Texels per side of the map (of each cube face for point lights).
    #[getter]
    fn resolution(&self) -> u32 {
        self.inner.resolution()
    }

    /// "pcf" (percentage-closer filtering) or "none" (the plain comparison).
    #[getter]
    fn filter(&self) -> &'static str {
        match self.inner.filter() {
            core::ShadowFilter::None => "none",
            core::ShadowFilter::Pcf(_) => "pcf",
        }
    }

    /// The PCF kernel's side in texels (1 with filter="none").
    #[getter]
    fn kernel(&self) -> u32 {
        match self.inner.filter() {
            core::ShadowFilter::None => 1,
            core::ShadowFilter::Pcf(k) => k,
        }
    }

    /// Scale of the depth tolerance (one texel's world size at the point; the comparison
    /// is against the receiver-plane depth, the exact slope-scaled bias).
    #[getter]
    fn bias(&self) -> f32 {
        self.inner.bias()
    }

    /// Maps of a directional light, one per slice of the camera's view (1: one map fitted
    /// to the whole visible part). Other lights ignore it.
    #[getter]
    fn cascades(&self) -> u32 {
        self.inner.cascades()
    }

    fn __repr__(&self) -> String {
        format!(
            "ShadowSettings(resolution={}, filter='{}', kernel={}, bias={}, cascades={})",
            self.resolution(),
            self.filter(),
            self.kernel(),
            self.bias(),
            self.cascades()
        )
    }
}

/// A light's `shadows=` argument.
pub fn shadows_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<core::Shadows> {
    let Some(o) = obj.filter(|o| !o.is_none()) else {
        return Ok(core::Shadows::Off);
    };
    if let Ok(b) = o.cast::<PyBool>() {
        return Ok(if b.is_true() {
            core::Shadows::Map(core::ShadowSettings::default())
        } else {
            core::Shadows::Off
        });
    }
    if let Ok(s) = o.cast::<PyShadowSettings>() {
        return Ok(core::Shadows::Map(s.get().inner));
    }
    if let Ok(s) = o.cast::<PyString>() {
        return match s.to_cow()?.as_ref() {
            "exact" => Ok(core::Shadows::Exact),
            other => Err(value_error(
                "shadows",
                format!(
                    "unknown shadows '{other}'; expected False, True, 'exact' or a \
                     ShadowSettings"
                ),
            )),
        };
    }
    Err(type_error(
        "shadows",
        format!(
            "shadows must be False, True, 'exact' or a ShadowSettings, got {}",
            o.get_type().name()?
        ),
    ))
}

/// A light's `shadows` as Python reads it back: False, True (default map settings),
/// "exact", or the `ShadowSettings`.
pub fn shadows_object(py: Python<'_>, s: core::Shadows) -> PyResult<Py<PyAny>> {
    Ok(match s {
        core::Shadows::Off => PyBool::new(py, false).to_owned().into_any().unbind(),
        core::Shadows::Map(m) if m == core::ShadowSettings::default() => {
            PyBool::new(py, true).to_owned().into_any().unbind()
        }
        core::Shadows::Map(inner) => Bound::new(py, PyShadowSettings { inner })?
            .into_any()
            .unbind(),
        core::Shadows::Exact => PyString::new(py, "exact").into_any().unbind(),
    })
}

/// (resolution, kernel (1: no filter), bias, cascades) of a map.
pub type SettingsState = (u32, u32, f32, u32);

pub fn settings_state(s: &core::ShadowSettings) -> SettingsState {
    let kernel = match s.filter() {
        core::ShadowFilter::None => 1,
        core::ShadowFilter::Pcf(k) => k,
    };
    (s.resolution(), kernel, s.bias(), s.cascades())
}

pub fn settings(s: SettingsState) -> PyResult<core::ShadowSettings> {
    let filter = match s.1 {
        1 => core::ShadowFilter::None,
        k => core::ShadowFilter::Pcf(k),
    };
    core::ShadowSettings::new(s.0, filter, s.2)
        .and_then(|m| m.with_cascades(s.3))
        .map_err(to_py)
}

/// A light's shadows in a pickle: ("off" | "map" | "exact", map settings).
pub type ShadowsState = (String, SettingsState);

pub fn shadows_state(s: &core::Shadows) -> ShadowsState {
    let default = settings_state(&core::ShadowSettings::default());
    match s {
        core::Shadows::Off => ("off".into(), default),
        core::Shadows::Map(m) => ("map".into(), settings_state(m)),
        core::Shadows::Exact => ("exact".into(), default),
    }
}

pub fn shadows(s: ShadowsState) -> PyResult<core::Shadows> {
    match s.0.as_str() {
        "off" => Ok(core::Shadows::Off),
        "map" => Ok(core::Shadows::Map(settings(s.1)?)),
        "exact" => Ok(core::Shadows::Exact),
        other => Err(value_error(
            "shadows",
            format!("a pickled light has unknown shadows '{other}'"),
        )),
    }
}
