//! `Texture`: image textures (arrays, Pillow images, files) and procedural ones.

use std::sync::Arc;

use numpy::PyUntypedArrayMethods;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use shadelab_raster as core;
use shadelab_raster::texture::Image;

use crate::convert;
use crate::errors::{to_py, type_error, value_error};

/// A texture: an image sampled with a filter and wrap modes, or a procedural pattern.
#[pyclass(name = "Texture", module = "shadelab_rs._core", frozen)]
pub struct PyTexture {
    pub inner: Arc<core::Texture>,
}

fn filter_arg(name: &str) -> PyResult<core::Filter> {
    core::Filter::from_name(name).ok_or_else(|| {
        value_error(
            "filter",
            format!("filter must be 'nearest', 'bilinear' or 'trilinear', got {name:?}"),
        )
    })
}

/// "repeat" | "clamp" | "mirror", or a (u, v) pair of them.
fn wrap_arg(w: &Bound<'_, PyAny>) -> PyResult<[core::Wrap; 2]> {
    let one = |s: &str| {
        core::Wrap::from_name(s).ok_or_else(|| {
            value_error(
                "wrap",
                format!("wrap must be 'repeat', 'clamp' or 'mirror' (or a (u, v) pair), got {s:?}"),
            )
        })
    };
    if let Ok(s) = w.extract::<String>() {
        let m = one(&s)?;
        return Ok([m, m]);
    }
    if let Ok((a, b)) = w.extract::<(String, String)>() {
        return Ok([one(&a)?, one(&b)?]);
    }
    Err(type_error(
        "wrap",
        format!(
            "wrap must be a str or a (u, v) pair of str, got {}",
            w.get_type().name()?
        ),
    ))
}

/// The same texture with `a` probes of anisotropic filtering (1 to 16).
fn with_anisotropy(t: core::Texture, a: i64) -> PyResult<core::Texture> {
    let a = u32::try_from(a).unwrap_or(0);
    t.with_anisotropy(a).map_err(to_py)
}

/// An (H, W, 3|4) array (or anything `numpy.asarray` makes one of, such as a Pillow image)
/// as f32 values in their own scale: uint8 / 255, uint16 / 65535, floats as they are.
fn texels(obj: &Bound<'_, PyAny>) -> PyResult<(usize, usize, usize, Vec<f32>)> {
    let (arr, dtype, shape) = convert::image_array(
        obj,
        "a texture needs an (H, W, 3|4) array or a Pillow image",
    )?;
    let scale = match dtype.as_str() {
        "uint8" => 1.0 / 255.0,
        "uint16" => 1.0 / 65535.0,
        "float32" | "float64" => 1.0,
        _ => {
            return Err(type_error(
                "array",
                format!(
                    "texture arrays must be uint8, uint16, float32 or float64, got dtype {dtype}"
                ),
            ))
        }
    };
    if shape.len() != 3 || !(shape[2] == 3 || shape[2] == 4) {
        return Err(value_error(
            "array",
            format!(
                "a texture array must have shape (H, W, 3) or (H, W, 4), got {shape:?} (a \
                 grey or palette Pillow image: convert it with .convert('RGB'))"
            ),
        ));
    }
    let ro = convert::f64_values(&arr)?;
    let data = ro
        .as_slice()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    if let Some(k) = data.iter().position(|v| !v.is_finite()) {
        let (w, ch) = (shape[1], shape[2]);
        return Err(value_error(
            "array",
            format!(
                "texture array[{}, {}, {}] = {} is not finite",
                k / (w * ch),
                (k / ch) % w,
                k % ch,
                data[k]
            ),
        ));
    }
    let _ = ro.shape();
    Ok((
        shape[0],
        shape[1],
        shape[2],
        data.iter().map(|&v| (v * scale) as f32).collect(),
    ))
}

impl PyTexture {
    /// Wraps a core texture.
    pub fn of(inner: Arc<core::Texture>) -> Self {
        PyTexture { inner }
    }
}

#[pymethods]
impl PyTexture {
    #[new]
    #[pyo3(signature = (array, filter="trilinear", wrap=None, srgb=false, anisotropy=1))]
    fn new(
        py: Python<'_>,
        array: &Bound<'_, PyAny>,
        filter: &str,
        wrap: Option<&Bound<'_, PyAny>>,
        srgb: bool,
        anisotropy: i64,
    ) -> PyResult<Self> {
        let filter = filter_arg(filter)?;
        let wrap = wrap.map_or(Ok([core::Wrap::Repeat; 2]), wrap_arg)?;
        let (h, w, ch, data) = texels(array)?;
        let image = py
            .detach(|| {
                crate::errors::no_panic("Texture", || Image::from_top_rows(w, h, ch, &data, srgb))
            })?
            .map_err(|e| crate::errors::with_field(to_py(e), "array"))?;
        let tex = core::Texture::from_image(Arc::new(image), filter, wrap);
        Ok(PyTexture {
            inner: Arc::new(with_anisotropy(tex, anisotropy)?),
        })
    }

    /// Decodes an image file (PNG 8/16-bit, JPEG) into a texture.
    #[staticmethod]
    #[pyo3(signature = (path, filter="trilinear", wrap=None, srgb=false, anisotropy=1))]
    fn load(
        py: Python<'_>,
        path: std::path::PathBuf,
        filter: &str,
        wrap: Option<&Bound<'_, PyAny>>,
        srgb: bool,
        anisotropy: i64,
    ) -> PyResult<Self> {
        let filter = filter_arg(filter)?;
        let wrap = wrap.map_or(Ok([core::Wrap::Repeat; 2]), wrap_arg)?;
        let tex = py
            .detach(|| {
                crate::errors::no_panic("Texture.load", || {
                    core::Texture::load(&path, filter, wrap, srgb)
                })
            })?
            .map_err(to_py)?;
        Ok(PyTexture {
            inner: Arc::new(with_anisotropy(tex, anisotropy)?),
        })
    }

    /// A procedural texture by name: "checker", "grid", "stripes" or "noise" (value noise
    /// with octaves), with `scale` cells per unit of u and v, colours `color_a` and
    /// `color_b`, the grid's line `width` (a fraction of a cell), the noise's `octaves` and
    /// `seed`.
    #[staticmethod]
    #[pyo3(signature = (name, scale=8.0, color_a=None, color_b=None, width=0.1, octaves=4, seed=0))]
    #[allow(clippy::too_many_arguments)]
    fn procedural(
        name: &str,
        scale: f64,
        color_a: Option<&Bound<'_, PyAny>>,
        color_b: Option<&Bound<'_, PyAny>>,
        width: f64,
        octaves: i64,
        seed: i64,
    ) -> PyResult<Self> {
        let a = color_a.map_or(Ok(glam::Vec3::ONE), |c| convert::vec3(c, "color_a"))?;
        let b = color_b.map_or(Ok(glam::Vec3::ZERO), |c| convert::vec3(c, "color_b"))?;
        let p = match name {
            "checker" => core::Procedural::Checker { scale, a, b },
            "stripes" => core::Procedural::Stripes { scale, a, b },
            "grid" => core::Procedural::Grid { scale, width, a, b },
            "noise" => core::Procedural::Noise {
                scale,
                octaves: u32::try_from(octaves).unwrap_or(0),
                seed: u32::try_from(seed).map_err(|_| {
                    value_error("seed", format!("seed must be in 0..2^32, got {seed}"))
                })?,
                a,
                b,
            },
            _ => {
                return Err(value_error(
                    "name",
                    format!(
                        "procedural texture must be 'checker', 'grid', 'stripes' or 'noise', \
                         got {name:?}"
                    ),
                ))
            }
        };
        let p = p.validated().map_err(to_py)?;
        Ok(PyTexture {
            inner: Arc::new(core::Texture::procedural(p)),
        })
    }

    /// The image file this texture was loaded from (None when made from an array or
    /// procedural).
    #[getter]
    fn path(&self) -> Option<std::path::PathBuf> {
        self.inner.file().map(|(p, _)| p.to_path_buf())
    }

    /// Whether the image file was decoded as sRGB (False when not loaded from a file).
    #[getter]
    fn srgb(&self) -> bool {
        self.inner.file().is_some_and(|(_, s)| s)
    }

    /// The (scale, offset) applied to (u, v) before sampling (MTL's -s and -o).
    #[getter]
    fn uv_transform(&self) -> ((f64, f64), (f64, f64)) {
        let (s, o) = self.inner.uv_transform();
        ((s.x, s.y), (o.x, o.y))
    }

    /// The same texture read at (u, v)·scale + offset (each a finite (u, v) pair).
    fn with_uv_transform(&self, scale: (f64, f64), offset: (f64, f64)) -> PyResult<Self> {
        let all = [scale.0, scale.1, offset.0, offset.1];
        if all.iter().any(|v| !v.is_finite()) {
            return Err(value_error(
                "uv_transform",
                format!("uv scale and offset must be finite, got {scale:?}, {offset:?}"),
            ));
        }
        let t = (*self.inner)
            .clone()
            .with_uv_transform(scale.into(), offset.into());
        Ok(PyTexture::of(Arc::new(t)))
    }

    /// "image" or the procedural pattern's name.
    #[getter]
    fn kind(&self) -> &'static str {
        self.inner.pattern().map_or("image", |p| p.name())
    }

    /// Width of the image in texels (None for a procedural texture).
    #[getter]
    fn width(&self) -> Option<usize> {
        self.inner.image().map(|i| i.width())
    }

    /// Height of the image in texels (None for a procedural texture).
    #[getter]
    fn height(&self) -> Option<usize> {
        self.inner.image().map(|i| i.height())
    }

    /// Number of mip levels (1 for a procedural texture).
    #[getter]
    fn levels(&self) -> usize {
        self.inner.image().map_or(1, |i| i.levels().len())
    }

    /// Probes of anisotropic filtering (1: off).
    #[getter]
    fn anisotropy(&self) -> u32 {
        self.inner.anisotropy()
    }

    /// The filter's name.
    #[getter]
    fn filter(&self) -> &'static str {
        self.inner.filter().name()
    }

    /// The wrap modes (u, v).
    #[getter]
    fn wrap(&self) -> (&'static str, &'static str) {
        let [u, v] = self.inner.wrap();
        (u.name(), v.name())
    }

    /// Level 0 as linear float32 RGB, shape (H, W, 3), row 0 the top of the image (None for
    /// a procedural texture).
    fn to_array<'py>(&self, py: Python<'py>) -> Option<Bound<'py, numpy::PyArray3<f32>>> {
        use numpy::IntoPyArray;
        self.inner.image().map(|img| {
            numpy::ndarray::Array3::from_shape_vec((img.height(), img.width(), 3), img.top_rows())
                .expect("length matches")
                .into_pyarray(py)
        })
    }

    /// The colour at (u, v) as the renderer reads it with the screen-space derivatives
    /// `derivatives` = (du/dx, dv/dx, du/dy, dv/dy) (None: zero, the sharpest level).
    #[pyo3(signature = (u, v, derivatives=None))]
    fn sample(&self, u: f64, v: f64, derivatives: Option<(f64, f64, f64, f64)>) -> (f32, f32, f32) {
        let (du_dx, dv_dx, du_dy, dv_dy) = derivatives.unwrap_or_default();
        let fp = core::Footprint {
            du_dx,
            dv_dx,
            du_dy,
            dv_dy,
        };
        self.inner.sample(u, v, &fp).into()
    }

    /// Pickle support: `_core._restore("Texture", state)` rebuilds this texture exactly
    /// (an image from its linear level 0, so the pyramid is the same bit for bit).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        crate::pickle::reduce(py, "Texture", texture_state(py, &self.inner)?)
    }

    fn __copy__(&self) -> Self {
        PyTexture::of(self.inner.clone())
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        // Immutable: a copy may share the texels.
        PyTexture::of(self.inner.clone())
    }

    fn __repr__(&self) -> String {
        match self.inner.image() {
            Some(img) => {
                let [u, v] = self.inner.wrap();
                format!(
                    "Texture({}x{}, filter={:?}, wrap=({:?}, {:?}), anisotropy={})",
                    img.width(),
                    img.height(),
                    self.inner.filter().name(),
                    u.name(),
                    v.name(),
                    self.inner.anisotropy(),
                )
            }
            None => format!("Texture.procedural({:?})", self.kind()),
        }
    }
}

type V3 = (f32, f32, f32);

/// The pickled state of a texture: `("image", w, h, texels, filter, wrap, uv)` or
/// `("procedural", name, scale, a, b, width, octaves, seed, uv)`, `uv` = (scale, offset).
pub fn texture_state<'py>(py: Python<'py>, t: &core::Texture) -> PyResult<Bound<'py, PyTuple>> {
    use numpy::IntoPyArray;
    let (s, o) = t.uv_transform();
    let uv = ((s.x, s.y), (o.x, o.y)).into_pyobject(py)?.into_any();
    if let Some(img) = t.image() {
        let [wu, wv] = t.wrap();
        return PyTuple::new(
            py,
            [
                "image".into_pyobject(py)?.into_any(),
                img.width().into_pyobject(py)?.into_any(),
                img.height().into_pyobject(py)?.into_any(),
                img.top_rows().into_pyarray(py).into_any(),
                t.filter().name().into_pyobject(py)?.into_any(),
                (wu.name(), wv.name()).into_pyobject(py)?.into_any(),
                uv,
                t.file()
                    .map(|(p, s)| (p.to_path_buf(), s))
                    .into_pyobject(py)?
                    .into_any(),
                t.anisotropy().into_pyobject(py)?.into_any(),
            ],
        );
    }
    let p = t.pattern().expect("a texture is an image or a pattern");
    let (scale, a, b, width, octaves, seed) = match *p {
        core::Procedural::Checker { scale, a, b } | core::Procedural::Stripes { scale, a, b } => {
            (scale, a, b, 0.1, 4, 0)
        }
        core::Procedural::Grid { scale, width, a, b } => (scale, a, b, width, 4, 0),
        core::Procedural::Noise {
            scale,
            octaves,
            seed,
            a,
            b,
        } => (scale, a, b, 0.1, octaves, seed),
    };
    let (a, b): (V3, V3) = (a.into(), b.into());
    PyTuple::new(
        py,
        [
            "procedural".into_pyobject(py)?.into_any(),
            p.name().into_pyobject(py)?.into_any(),
            scale.into_pyobject(py)?.into_any(),
            a.into_pyobject(py)?.into_any(),
            b.into_pyobject(py)?.into_any(),
            width.into_pyobject(py)?.into_any(),
            octaves.into_pyobject(py)?.into_any(),
            seed.into_pyobject(py)?.into_any(),
            uv,
        ],
    )
}

type Uv = ((f64, f64), (f64, f64));

/// Rebuilds a texture from [`texture_state`].
pub fn restore_texture(state: &Bound<'_, PyAny>) -> PyResult<PyTexture> {
    let kind: String = state.get_item(0)?.extract()?;
    let tex = if kind == "image" {
        #[allow(clippy::type_complexity)]
        let (_, w, h, data, filter, (wu, wv), uv, file, aniso): (
            String,
            usize,
            usize,
            numpy::PyReadonlyArray1<'_, f32>,
            String,
            (String, String),
            Uv,
            Option<(std::path::PathBuf, bool)>,
            u32,
        ) = state.extract()?;
        let wrap = |n: &str| {
            core::Wrap::from_name(n)
                .ok_or_else(|| PyValueError::new_err(format!("unknown wrap {n:?}")))
        };
        let data = data
            .as_slice()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let image = Image::from_top_rows(w, h, 3, data, false).map_err(to_py)?;
        let t = core::Texture::from_image(
            Arc::new(image),
            filter_arg(&filter)?,
            [wrap(&wu)?, wrap(&wv)?],
        )
        .with_uv_transform(uv.0.into(), uv.1.into())
        .with_anisotropy(aniso)
        .map_err(to_py)?;
        match file {
            Some((p, srgb)) => t.with_file(p, srgb),
            None => t,
        }
    } else {
        let (_, name, scale, a, b, width, octaves, seed, uv): (
            String,
            String,
            f64,
            V3,
            V3,
            f64,
            u32,
            u32,
            Uv,
        ) = state.extract()?;
        let (a, b) = (glam::Vec3::from(a), glam::Vec3::from(b));
        let p = match name.as_str() {
            "checker" => core::Procedural::Checker { scale, a, b },
            "stripes" => core::Procedural::Stripes { scale, a, b },
            "grid" => core::Procedural::Grid { scale, width, a, b },
            "noise" => core::Procedural::Noise {
                scale,
                octaves,
                seed,
                a,
                b,
            },
            other => {
                return Err(PyValueError::new_err(format!(
                    "unknown procedural texture {other:?}"
                )))
            }
        };
        core::Texture::procedural(p.validated().map_err(to_py)?)
            .with_uv_transform(uv.0.into(), uv.1.into())
    };
    Ok(PyTexture::of(Arc::new(tex)))
}

/// A map's texture, or None.
pub type MapState = Option<PyTexture>;

/// The pickled form of a material's maps: (diffuse, ambient, specular, emission,
/// shininess, normal, normal_scale, bump, bump_scale), each map a Texture or None.
#[allow(clippy::type_complexity)]
pub fn maps_state(
    maps: &core::Maps,
) -> (
    MapState,
    MapState,
    MapState,
    MapState,
    MapState,
    MapState,
    f32,
    MapState,
    f32,
) {
    let t = |m: &Option<Arc<core::Texture>>| m.clone().map(PyTexture::of);
    (
        t(&maps.diffuse),
        t(&maps.ambient),
        t(&maps.specular),
        t(&maps.emission),
        t(&maps.shininess),
        t(&maps.normal),
        maps.normal_scale,
        t(&maps.bump),
        maps.bump_scale,
    )
}

/// Maps from [`maps_state`] (or its earlier forms: four maps, or five with shininess).
pub fn restore_maps(state: &Bound<'_, PyAny>) -> PyResult<Option<Arc<core::Maps>>> {
    type Map<'py> = Option<PyRef<'py, PyTexture>>;
    let t = |x: Option<PyRef<'_, PyTexture>>| x.map(|x| x.inner.clone());
    let mut maps = core::Maps::default();
    if let Ok((d, a, s, e)) = state.extract::<(Map<'_>, Map<'_>, Map<'_>, Map<'_>)>() {
        (maps.diffuse, maps.ambient, maps.specular, maps.emission) = (t(d), t(a), t(s), t(e));
    } else if let Ok((d, a, s, e, n)) =
        state.extract::<(Map<'_>, Map<'_>, Map<'_>, Map<'_>, Map<'_>)>()
    {
        (maps.diffuse, maps.ambient, maps.specular, maps.emission) = (t(d), t(a), t(s), t(e));
        maps.shininess = t(n);
    } else {
        #[allow(clippy::type_complexity)]
        let (d, a, s, e, n, nm, ns, bm, bs): (
            Map<'_>,
            Map<'_>,
            Map<'_>,
            Map<'_>,
            Map<'_>,
            Map<'_>,
            f32,
            Map<'_>,
            f32,
        ) = state.extract()?;
        (maps.diffuse, maps.ambient, maps.specular, maps.emission) = (t(d), t(a), t(s), t(e));
        (maps.shininess, maps.normal, maps.bump) = (t(n), t(nm), t(bm));
        (maps.normal_scale, maps.bump_scale) = (ns, bs);
        maps.check_scales().map_err(to_py)?;
    }
    Ok((!maps.is_empty()).then(|| Arc::new(maps)))
}
