//! `Material` and its presets.

use pyo3::prelude::*;
use shadelab_raster as core;

use std::sync::Arc;

use crate::convert;
use crate::errors::{to_py, value_error};
use crate::texture::PyTexture;

/// OpenGL-style material: ambient, diffuse, specular RGB and shininess.
#[pyclass(name = "Material", module = "shadelab_rs._core", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyMaterial {
    pub inner: core::Material,
    /// Texture maps (`None`: untextured); equal when they hold the same textures.
    pub maps: Option<Arc<core::Maps>>,
}

impl PyMaterial {
    /// An untextured material.
    pub fn plain(inner: core::Material) -> Self {
        PyMaterial { inner, maps: None }
    }
}

fn map_arg(t: Option<PyRef<'_, PyTexture>>) -> Option<Arc<core::Texture>> {
    t.map(|t| t.inner.clone())
}

/// Maps with their scales checked by the core; `None` when no map is set (the scales of
/// a material without maps are not kept).
fn checked_maps(maps: core::Maps) -> PyResult<Option<Arc<core::Maps>>> {
    maps.check_scales().map_err(to_py)?;
    Ok((!maps.is_empty()).then(|| Arc::new(maps)))
}

fn map_out(t: Option<&Arc<core::Texture>>) -> Option<PyTexture> {
    t.map(|t| PyTexture::of(t.clone()))
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

/// A number or an RGB colour (reflectivity).
fn scalar_or_rgb(v: &Bound<'_, PyAny>, name: &str) -> PyResult<glam::Vec3> {
    if let Ok(x) = v.extract::<f64>() {
        return Ok(glam::Vec3::splat(x as f32));
    }
    convert::vec3(v, name)
}

/// An index of refraction: a number > 0 or a preset name ("air", "water", "glass",
/// "diamond").
fn ior_arg(v: Option<&Bound<'_, PyAny>>) -> PyResult<f32> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(1.0);
    };
    if let Ok(name) = v.extract::<String>() {
        return core::ior_preset(&name).map_err(to_py);
    }
    match v.extract::<f64>() {
        Ok(x) => Ok(x as f32),
        Err(_) => Err(crate::errors::type_error(
            "ior",
            format!(
                "ior must be a number or a preset name, got {}",
                v.get_type().name()?
            ),
        )),
    }
}

/// `m` with its optical parameters (the constructor's keywords), checked by the core.
pub(crate) fn with_optics(
    m: core::Material,
    reflectivity: Option<&Bound<'_, PyAny>>,
    transparency: f64,
    ior: Option<&Bound<'_, PyAny>>,
    fresnel: bool,
    absorption: Option<&Bound<'_, PyAny>>,
) -> PyResult<core::Material> {
    let reflectivity = match reflectivity.filter(|v| !v.is_none()) {
        Some(v) => scalar_or_rgb(v, "reflectivity")?,
        None => glam::Vec3::ZERO,
    };
    let absorption = match absorption.filter(|v| !v.is_none()) {
        Some(v) => scalar_or_rgb(v, "absorption")?,
        None => glam::Vec3::ZERO,
    };
    m.with_optics(
        reflectivity,
        transparency as f32,
        ior_arg(ior)?,
        fresnel,
        absorption,
    )
    .map_err(to_py)
}

#[pymethods]
impl PyMaterial {
    /// Pickle support: `_core._restore("Material", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        if let Some(maps) = &self.maps {
            let state = (
                crate::pickle::material_state(&self.inner),
                crate::texture::maps_state(maps),
            );
            return crate::pickle::reduce(py, "TexturedMaterial", state);
        }
        crate::pickle::reduce(py, "Material", crate::pickle::material_state(&self.inner))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    #[new]
    #[pyo3(signature = (ambient=None, diffuse=None, specular=None, shininess=None, emission=None,
                         diffuse_map=None, ambient_map=None, specular_map=None, emission_map=None,
                         shininess_map=None, reflectivity=None, transparency=0.0, ior=None,
                         fresnel=true, absorption=None, normal_map=None, normal_scale=1.0,
                         bump_map=None, bump_scale=1.0))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        ambient: Option<&Bound<'_, PyAny>>,
        diffuse: Option<&Bound<'_, PyAny>>,
        specular: Option<&Bound<'_, PyAny>>,
        shininess: Option<f64>,
        emission: Option<&Bound<'_, PyAny>>,
        diffuse_map: Option<PyRef<'_, PyTexture>>,
        ambient_map: Option<PyRef<'_, PyTexture>>,
        specular_map: Option<PyRef<'_, PyTexture>>,
        emission_map: Option<PyRef<'_, PyTexture>>,
        shininess_map: Option<PyRef<'_, PyTexture>>,
        reflectivity: Option<&Bound<'_, PyAny>>,
        transparency: f64,
        ior: Option<&Bound<'_, PyAny>>,
        fresnel: bool,
        absorption: Option<&Bound<'_, PyAny>>,
        normal_map: Option<PyRef<'_, PyTexture>>,
        normal_scale: f64,
        bump_map: Option<PyRef<'_, PyTexture>>,
        bump_scale: f64,
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
        let inner = with_optics(inner, reflectivity, transparency, ior, fresnel, absorption)?;
        let maps = core::Maps {
            diffuse: map_arg(diffuse_map),
            ambient: map_arg(ambient_map),
            specular: map_arg(specular_map),
            emission: map_arg(emission_map),
            shininess: map_arg(shininess_map),
            normal: map_arg(normal_map),
            normal_scale: normal_scale as f32,
            bump: map_arg(bump_map),
            bump_scale: bump_scale as f32,
        };
        Ok(PyMaterial {
            inner,
            maps: checked_maps(maps)?,
        })
    }

    /// The same material with other texture maps (each a Texture or None; the others
    /// are dropped).
    #[pyo3(signature = (diffuse_map=None, ambient_map=None, specular_map=None, emission_map=None,
                         shininess_map=None, normal_map=None, normal_scale=1.0, bump_map=None,
                         bump_scale=1.0))]
    #[allow(clippy::too_many_arguments)]
    fn with_maps(
        &self,
        diffuse_map: Option<PyRef<'_, PyTexture>>,
        ambient_map: Option<PyRef<'_, PyTexture>>,
        specular_map: Option<PyRef<'_, PyTexture>>,
        emission_map: Option<PyRef<'_, PyTexture>>,
        shininess_map: Option<PyRef<'_, PyTexture>>,
        normal_map: Option<PyRef<'_, PyTexture>>,
        normal_scale: f64,
        bump_map: Option<PyRef<'_, PyTexture>>,
        bump_scale: f64,
    ) -> PyResult<Self> {
        let maps = core::Maps {
            diffuse: map_arg(diffuse_map),
            ambient: map_arg(ambient_map),
            specular: map_arg(specular_map),
            emission: map_arg(emission_map),
            shininess: map_arg(shininess_map),
            normal: map_arg(normal_map),
            normal_scale: normal_scale as f32,
            bump: map_arg(bump_map),
            bump_scale: bump_scale as f32,
        };
        Ok(PyMaterial {
            inner: self.inner,
            maps: checked_maps(maps)?,
        })
    }

    /// The diffuse map (a Texture) or None.
    #[getter]
    fn diffuse_map(&self) -> Option<PyTexture> {
        map_out(self.maps.as_ref().and_then(|m| m.diffuse.as_ref()))
    }

    /// The ambient map or None (None with a diffuse map: the diffuse map weighs ambient).
    #[getter]
    fn ambient_map(&self) -> Option<PyTexture> {
        map_out(self.maps.as_ref().and_then(|m| m.ambient.as_ref()))
    }

    /// The specular map or None.
    #[getter]
    fn specular_map(&self) -> Option<PyTexture> {
        map_out(self.maps.as_ref().and_then(|m| m.specular.as_ref()))
    }

    /// The emission map or None.
    #[getter]
    fn emission_map(&self) -> Option<PyTexture> {
        map_out(self.maps.as_ref().and_then(|m| m.emission.as_ref()))
    }

    /// The shininess map or None (its texels' mean over r, g, b multiplies the shininess).
    #[getter]
    fn shininess_map(&self) -> Option<PyTexture> {
        map_out(self.maps.as_ref().and_then(|m| m.shininess.as_ref()))
    }

    /// The normal map (tangent space) or None.
    #[getter]
    fn normal_map(&self) -> Option<PyTexture> {
        map_out(self.maps.as_ref().and_then(|m| m.normal.as_ref()))
    }

    /// Scale of the normal map's x and y (1.0 without maps).
    #[getter]
    fn normal_scale(&self) -> f32 {
        self.maps.as_ref().map_or(1.0, |m| m.normal_scale)
    }

    /// The bump (height) map or None.
    #[getter]
    fn bump_map(&self) -> Option<PyTexture> {
        map_out(self.maps.as_ref().and_then(|m| m.bump.as_ref()))
    }

    /// The height of a bump-map value 1, in UV units (1.0 without maps).
    #[getter]
    fn bump_scale(&self) -> f32 {
        self.maps.as_ref().map_or(1.0, |m| m.bump_scale)
    }

    /// The named classic preset (case-insensitive; "polished_silver" = "polished silver").
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        Ok(PyMaterial::plain(
            core::Material::preset(name).map_err(to_py)?,
        ))
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

    /// Share of light mirrored (r, g, b), each in [0, 1].
    #[getter]
    fn reflectivity(&self) -> (f32, f32, f32) {
        self.inner.reflectivity.into()
    }

    /// Share of light transmitted, in [0, 1].
    #[getter]
    fn transparency(&self) -> f32 {
        self.inner.transparency
    }

    /// Index of refraction.
    #[getter]
    fn ior(&self) -> f32 {
        self.inner.ior
    }

    /// Whether reflection and transmission are weighed by Schlick's Fresnel term.
    #[getter]
    fn fresnel(&self) -> bool {
        self.inner.fresnel
    }

    /// Beer–Lambert absorption per unit distance inside the material (r, g, b).
    #[getter]
    fn absorption(&self) -> (f32, f32, f32) {
        self.inner.absorption.into()
    }

    /// The same material with other optical parameters (the constructor's keywords; maps
    /// kept).
    #[pyo3(signature = (reflectivity=None, transparency=0.0, ior=None, fresnel=true, absorption=None))]
    fn with_optics(
        &self,
        reflectivity: Option<&Bound<'_, PyAny>>,
        transparency: f64,
        ior: Option<&Bound<'_, PyAny>>,
        fresnel: bool,
        absorption: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        Ok(PyMaterial {
            inner: with_optics(
                self.inner,
                reflectivity,
                transparency,
                ior,
                fresnel,
                absorption,
            )?,
            maps: self.maps.clone(),
        })
    }

    fn __repr__(&self) -> String {
        let m = &self.inner;
        let maps = self.maps.as_ref().map_or(String::new(), |mp| {
            [
                ("diffuse_map", &mp.diffuse),
                ("ambient_map", &mp.ambient),
                ("specular_map", &mp.specular),
                ("emission_map", &mp.emission),
                ("shininess_map", &mp.shininess),
                ("normal_map", &mp.normal),
                ("bump_map", &mp.bump),
            ]
            .iter()
            .filter(|(_, t)| t.is_some())
            .map(|(n, _)| format!(", {n}=Texture(...)"))
            .chain(
                [
                    ("normal_scale", mp.normal_scale),
                    ("bump_scale", mp.bump_scale),
                ]
                .iter()
                .filter(|(_, x)| *x != 1.0)
                .map(|(n, x)| format!(", {n}={x}")),
            )
            .collect()
        });
        let optics = if m.is_reflective() || m.is_transparent() || m.ior != 1.0 {
            format!(
                ", reflectivity={:?}, transparency={}, ior={}, fresnel={}, absorption={:?}",
                m.reflectivity.to_array(),
                m.transparency,
                m.ior,
                if m.fresnel { "True" } else { "False" },
                m.absorption.to_array()
            )
        } else {
            String::new()
        };
        format!(
            "Material(ambient={:?}, diffuse={:?}, specular={:?}, shininess={}, emission={:?}{optics}{maps})",
            m.ambient.to_array(),
            m.diffuse.to_array(),
            m.specular.to_array(),
            m.shininess,
            m.emission.to_array()
        )
    }
}
