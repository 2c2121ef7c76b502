//! `render` and `render_frame`: argument conversion, GIL release, array hand-off.

use numpy::ndarray::{Array2, Array3};
use numpy::IntoPyArray;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use shadelab_raster as core;

use crate::camera::PyCamera;
use crate::convert;
use crate::errors::{no_panic, to_py, value_error, with_field};
use crate::scene::PyScene;

/// An integer argument; huge values become `None` (out of any range) instead of an
/// OverflowError, non-integers a TypeError naming the argument.
fn int_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<i64>> {
    if obj.is_instance_of::<pyo3::types::PyBool>() || obj.is_instance_of::<pyo3::types::PyFloat>() {
        return Err(PyTypeError::new_err(format!(
            "{name} must be an integer, got {}",
            obj.get_type().name()?
        )));
    }
    match obj.extract::<i64>() {
        Ok(v) => Ok(Some(v)),
        Err(e) if e.is_instance_of::<pyo3::exceptions::PyOverflowError>(obj.py()) => Ok(None),
        Err(_) => Err(PyTypeError::new_err(format!(
            "{name} must be an integer, got {}",
            obj.get_type().name()?
        ))),
    }
}

fn size(obj: Option<&Bound<'_, PyAny>>, default: u32, name: &str) -> PyResult<u32> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(default);
    };
    match int_arg(obj, name)? {
        Some(v) if (1..=core::MAX_IMAGE_SIZE as i64).contains(&v) => Ok(v as u32),
        _ => Err(value_error(
            name,
            format!(
                "{name} must be between 1 and {}, got {obj}",
                core::MAX_IMAGE_SIZE
            ),
        )),
    }
}

fn threads_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    match int_arg(obj, "threads")? {
        Some(n) if (1..=core::MAX_THREADS as i64).contains(&n) => Ok(Some(n as usize)),
        _ => Err(value_error(
            "threads",
            format!(
                "threads must be between 1 and {} (or None for all cores), got {obj}",
                core::MAX_THREADS
            ),
        )),
    }
}

/// A small count (`samples`, `supersample`; None is 1). Values beyond u32 are refused here
/// (`expected` says what is allowed); the rest is the core's check, which names the field.
fn count_arg(obj: Option<&Bound<'_, PyAny>>, name: &str, expected: &str) -> PyResult<u32> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(1);
    };
    int_arg(obj, name)?
        .and_then(|v| u32::try_from(v).ok())
        .ok_or_else(|| value_error(name, format!("{name} must be {expected}, got {obj}")))
}

/// A float argument (`edge_width`, `edge_angle`; None keeps `default`); the range is the
/// core's check, which names the field.
fn float_arg(obj: Option<&Bound<'_, PyAny>>, name: &str, default: f32) -> PyResult<f32> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(default);
    };
    if obj.is_instance_of::<pyo3::types::PyBool>() {
        return Err(crate::errors::type_error(
            name,
            format!("{name} must be a number, got bool"),
        ));
    }
    obj.extract::<f64>().map(|v| v as f32).map_err(|_| {
        crate::errors::type_error(
            name,
            format!(
                "{name} must be a number, got {}",
                obj.get_type().name().map_or("?".into(), |n| n.to_string())
            ),
        )
    })
}

/// `edges`: None or one of the mode names.
fn edges_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<core::EdgeMode> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(core::EdgeMode::None);
    };
    let name: String = obj.extract().map_err(|_| {
        crate::errors::type_error(
            "edges",
            "edges must be None, 'all', 'visible' or 'features'",
        )
    })?;
    if name.eq_ignore_ascii_case("none") {
        return Err(value_error(
            "edges",
            "edges must be None (not the string 'none'), 'all', 'visible' or 'features'",
        ));
    }
    name.parse().map_err(to_py)
}

fn edges_name(mode: core::EdgeMode) -> Option<&'static str> {
    match mode {
        core::EdgeMode::None => None,
        core::EdgeMode::All => Some("all"),
        core::EdgeMode::Visible => Some("visible"),
        core::EdgeMode::Features => Some("features"),
    }
}

/// `shading="auto"`: each object's mode chosen for `tolerance`.
const AUTO: &str = "auto";

fn shading_name(mode: core::ShadingMode) -> &'static str {
    match mode {
        core::ShadingMode::Flat => "flat",
        core::ShadingMode::Gouraud => "gouraud",
        core::ShadingMode::Phong => "phong",
    }
}

fn gouraud_name(method: core::GouraudMethod) -> &'static str {
    match method {
        core::GouraudMethod::Normals => "normals",
        core::GouraudMethod::FaceIntensities => "face-intensities",
    }
}

fn interpolation_name(i: core::Interpolation) -> &'static str {
    match i {
        core::Interpolation::Perspective => "perspective",
        core::Interpolation::Screen => "screen",
    }
}

fn specular_name(model: core::SpecularModel) -> &'static str {
    match model {
        core::SpecularModel::BlinnPhong => "blinn",
        core::SpecularModel::Phong => "phong",
        core::SpecularModel::NormalizedBlinnPhong => "blinn-normalized",
    }
}

fn technique_name(t: core::Technique) -> &'static str {
    match t {
        core::Technique::Environment => "environment",
        core::Technique::Ray => "ray",
    }
}

/// How to render: the one spelling of the options shared by `render`, `render_frame`,
/// scene files' `[render]` table and the command line. Checked when built; immutable.
#[pyclass(name = "RenderOptions", module = "shadelab_rs._core", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyRenderOptions {
    pub inner: core::RenderOptions,
}

#[pymethods]
impl PyRenderOptions {
    /// Pickle support: `_core._restore("RenderOptions", state)` rebuilds this value; the
    /// state is `to_dict()`, checked again by the constructor.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        crate::pickle::reduce(py, "RenderOptions", self.to_dict(py)?)
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    #[new]
    #[pyo3(signature = (width=None, height=None, shading="phong", specular="blinn",
                        background=None, cull_backfaces=false, threads=None,
                        gouraud="normals", interpolation="perspective", samples=None,
                        supersample=None, edges=None, edge_color=None, edge_width=None,
                        edge_angle=None, edges_only=false, reflections="environment",
                        refractions=None, max_depth=None, tolerance=None, cull_hidden=true),
           text_signature = "(width=800, height=600, shading='phong', specular='blinn', background=None, cull_backfaces=False, threads=None, gouraud='normals', interpolation='perspective', samples=1, supersample=1, edges=None, edge_color=(0.0, 0.0, 0.0), edge_width=1.0, edge_angle=30.0, edges_only=False, reflections='environment', refractions=None, max_depth=5, tolerance=None, cull_hidden=True)")]
    #[allow(clippy::too_many_arguments)]
    fn new(
        width: Option<&Bound<'_, PyAny>>,
        height: Option<&Bound<'_, PyAny>>,
        shading: &str,
        specular: &str,
        background: Option<&Bound<'_, PyAny>>,
        cull_backfaces: bool,
        threads: Option<&Bound<'_, PyAny>>,
        gouraud: &str,
        interpolation: &str,
        samples: Option<&Bound<'_, PyAny>>,
        supersample: Option<&Bound<'_, PyAny>>,
        edges: Option<&Bound<'_, PyAny>>,
        edge_color: Option<&Bound<'_, PyAny>>,
        edge_width: Option<&Bound<'_, PyAny>>,
        edge_angle: Option<&Bound<'_, PyAny>>,
        edges_only: bool,
        reflections: &str,
        refractions: Option<&str>,
        max_depth: Option<&Bound<'_, PyAny>>,
        tolerance: Option<&Bound<'_, PyAny>>,
        cull_hidden: bool,
    ) -> PyResult<Self> {
        let mut inner =
            core::RenderOptions::new(size(width, 800, "width")?, size(height, 600, "height")?);
        let given_tolerance = tolerance.is_some_and(|t| !t.is_none());
        if shading.eq_ignore_ascii_case(AUTO) {
            // The mode each object is shaded with is chosen per render (auto_shading).
            inner.tolerance = Some(float_arg(tolerance, "tolerance", core::DEFAULT_TOLERANCE)?);
        } else {
            if given_tolerance {
                return Err(value_error(
                    "tolerance",
                    format!(
                        "tolerance is the error budget of shading='auto'; with \
                         shading={shading:?} it has no meaning: drop it or use shading='auto'"
                    ),
                ));
            }
            inner.shading = shading
                .parse()
                .map_err(|e| with_field(to_py(e), "shading"))?;
        }
        inner.specular = specular
            .parse()
            .map_err(|e| with_field(to_py(e), "specular"))?;
        inner.gouraud = gouraud
            .parse()
            .map_err(|e| with_field(to_py(e), "gouraud"))?;
        inner.interpolation = interpolation
            .parse()
            .map_err(|e| with_field(to_py(e), "interpolation"))?;
        match background.filter(|b| !b.is_none()) {
            Some(bg) if bg.extract::<String>().is_ok() => {
                let name: String = bg.extract()?;
                if name != "environment" {
                    return Err(value_error(
                        "background",
                        format!("background must be an RGB colour or 'environment', got {name:?}"),
                    ));
                }
                inner.environment_background = true;
            }
            Some(bg) => inner.background = convert::vec3(bg, "background")?,
            None => {}
        }
        inner.reflections = reflections
            .parse()
            .map_err(|e| with_field(to_py(e), "reflections"))?;
        inner.refractions = match refractions {
            None => None,
            Some(r) => Some(r.parse().map_err(|e| with_field(to_py(e), "refractions"))?),
        };
        if let Some(d) = max_depth.filter(|d| !d.is_none()) {
            let max = core::MAX_TRACE_DEPTH;
            let v = int_arg(d, "max_depth")?.unwrap_or(-1);
            inner.max_depth = u32::try_from(v).ok().filter(|v| *v <= max).ok_or_else(|| {
                value_error(
                    "max_depth",
                    format!("max_depth must be an int between 0 and {max}, got {v}"),
                )
            })?;
        }
        inner.cull_backfaces = cull_backfaces;
        inner.cull_hidden = cull_hidden;
        inner.threads = threads_arg(threads)?;
        inner.samples = count_arg(samples, "samples", "1, 2, 4, 8 or 16")?;
        let max_ss = core::MAX_SUPERSAMPLE;
        inner.supersample = count_arg(supersample, "supersample", &format!("1 to {max_ss}"))?;
        inner.edges = edges_arg(edges)?;
        if let Some(c) = edge_color.filter(|c| !c.is_none()) {
            inner.edge_color = convert::vec3(c, "edge_color")?;
        }
        inner.edge_width = float_arg(edge_width, "edge_width", 1.0)?;
        inner.edge_angle = float_arg(edge_angle, "edge_angle", core::DEFAULT_EDGE_ANGLE)?;
        inner.edges_only = edges_only;
        inner.validate().map_err(to_py)?;
        Ok(Self { inner })
    }

    /// The names `shading` takes (it also accepts them in any case).
    #[classattr]
    fn shading_names() -> (&'static str, &'static str, &'static str, &'static str) {
        use core::ShadingMode::*;
        (
            shading_name(Flat),
            shading_name(Gouraud),
            shading_name(Phong),
            AUTO,
        )
    }

    /// The names `specular` takes (it also accepts them in any case).
    #[classattr]
    fn specular_names() -> (&'static str, &'static str, &'static str) {
        use core::SpecularModel::*;
        (
            specular_name(BlinnPhong),
            specular_name(Phong),
            specular_name(NormalizedBlinnPhong),
        )
    }

    /// The names `gouraud` takes (it also accepts them in any case, and `_` for `-`).
    #[classattr]
    fn gouraud_names() -> (&'static str, &'static str) {
        use core::GouraudMethod::*;
        (gouraud_name(Normals), gouraud_name(FaceIntensities))
    }

    /// The names `interpolation` takes (it also accepts them in any case).
    #[classattr]
    fn interpolation_names() -> (&'static str, &'static str) {
        use core::Interpolation::*;
        (interpolation_name(Perspective), interpolation_name(Screen))
    }

    /// The same options with the given ones changed (checked like the constructor's).
    #[pyo3(signature = (**changes))]
    fn replace<'py>(
        &self,
        py: Python<'py>,
        changes: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let all = self.to_dict(py)?;
        if let Some(c) = changes {
            all.update(c.as_mapping())?;
        }
        py.get_type::<Self>().call((), Some(&all))
    }

    /// Every option by name (the constructor's keywords): `RenderOptions(**o.to_dict())`
    /// equals `o`.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("width", self.inner.width)?;
        d.set_item("height", self.inner.height)?;
        d.set_item("shading", self.shading())?;
        d.set_item("specular", specular_name(self.inner.specular))?;
        d.set_item("background", self.background(py)?)?;
        d.set_item("cull_backfaces", self.inner.cull_backfaces)?;
        d.set_item("threads", self.inner.threads)?;
        d.set_item("gouraud", gouraud_name(self.inner.gouraud))?;
        d.set_item(
            "interpolation",
            interpolation_name(self.inner.interpolation),
        )?;
        d.set_item("samples", self.inner.samples)?;
        d.set_item("supersample", self.inner.supersample)?;
        d.set_item("edges", edges_name(self.inner.edges))?;
        d.set_item("edge_color", self.edge_color())?;
        d.set_item("edge_width", self.inner.edge_width)?;
        d.set_item("edge_angle", self.inner.edge_angle)?;
        d.set_item("edges_only", self.inner.edges_only)?;
        d.set_item("reflections", technique_name(self.inner.reflections))?;
        d.set_item("refractions", self.inner.refractions.map(technique_name))?;
        d.set_item("max_depth", self.inner.max_depth)?;
        d.set_item("tolerance", self.inner.tolerance)?;
        d.set_item("cull_hidden", self.inner.cull_hidden)?;
        Ok(d)
    }

    /// How reflections find the mirrored light: "environment" or "ray".
    #[getter]
    fn reflections(&self) -> &'static str {
        technique_name(self.inner.reflections)
    }

    /// How refractions find the transmitted light: None (straight see-through blending),
    /// "environment" or "ray".
    #[getter]
    fn refractions(&self) -> Option<&'static str> {
        self.inner.refractions.map(technique_name)
    }

    /// Secondary rays followed at most from the first surface.
    #[getter]
    fn max_depth(&self) -> u32 {
        self.inner.max_depth
    }

    /// Visibility samples per pixel: 1, or 2, 4, 8, 16 for multi-sample anti-aliasing.
    #[getter]
    fn samples(&self) -> u32 {
        self.inner.samples
    }

    /// Which edges are drawn as lines: None, "all", "visible" or "features".
    #[getter]
    fn edges(&self) -> Option<&'static str> {
        edges_name(self.inner.edges)
    }

    /// Linear RGB of the lines.
    #[getter]
    fn edge_color(&self) -> (f32, f32, f32) {
        self.inner.edge_color.into()
    }

    /// Line width in pixels.
    #[getter]
    fn edge_width(&self) -> f32 {
        self.inner.edge_width
    }

    /// Crease angle in degrees ("features").
    #[getter]
    fn edge_angle(&self) -> f32 {
        self.inner.edge_angle
    }

    /// Whether the lines are drawn alone (surfaces painted as the background).
    #[getter]
    fn edges_only(&self) -> bool {
        self.inner.edges_only
    }

    /// The names `edges` takes besides None (it also accepts them in any case).
    #[classattr]
    fn edges_names() -> (&'static str, &'static str, &'static str) {
        ("all", "visible", "features")
    }

    /// Supersampling factor k (k×k pixels rendered and box-filtered per output pixel).
    #[getter]
    fn supersample(&self) -> u32 {
        self.inner.supersample
    }

    /// Image width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.inner.width
    }

    /// Image height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.inner.height
    }

    /// "flat", "gouraud", "phong", or "auto" (each object's mode chosen for `tolerance`).
    #[getter]
    fn shading(&self) -> &'static str {
        match self.inner.tolerance {
            Some(_) => AUTO,
            None => shading_name(self.inner.shading),
        }
    }

    /// The error budget of `shading="auto"` (RMSE in 8-bit levels), None for a fixed mode.
    #[getter]
    fn tolerance(&self) -> Option<f32> {
        self.inner.tolerance
    }

    /// "blinn", "phong" or "blinn-normalized".
    #[getter]
    fn specular(&self) -> &'static str {
        specular_name(self.inner.specular)
    }

    /// "normals" (lit at each vertex with its normal) or "face-intensities" (the mean of the
    /// flat-lit colours of the faces around each vertex); Gouraud only.
    #[getter]
    fn gouraud(&self) -> &'static str {
        gouraud_name(self.inner.gouraud)
    }

    /// "perspective" (perspective-correct) or "screen" (affine, the lectures' scan-line
    /// formulas) interpolation of Gouraud colours and Phong normals and positions.
    #[getter]
    fn interpolation(&self) -> &'static str {
        interpolation_name(self.inner.interpolation)
    }

    /// Linear RGB of empty pixels, or "environment" (the scene's environment along each
    /// pixel's view ray).
    #[getter]
    fn background(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        if self.inner.environment_background {
            return Ok("environment".into_pyobject(py)?.into_any().unbind());
        }
        let c: (f32, f32, f32) = self.inner.background.into();
        Ok(c.into_pyobject(py)?.into_any().unbind())
    }

    /// Whether clockwise (back) faces are skipped.
    #[getter]
    fn cull_backfaces(&self) -> bool {
        self.inner.cull_backfaces
    }

    /// Whether the back faces that cannot show (of opaque closed solids seen from outside)
    /// are skipped.
    #[getter]
    fn cull_hidden(&self) -> bool {
        self.inner.cull_hidden
    }

    /// Worker threads, or None for all cores.
    #[getter]
    fn threads(&self) -> Option<usize> {
        self.inner.threads
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let items = self
            .to_dict(py)?
            .iter()
            .map(|(k, v)| Ok(format!("{k}={}", v.repr()?)))
            .collect::<PyResult<Vec<_>>>()?;
        Ok(format!("RenderOptions({})", items.join(", ")))
    }
}

/// The options of a `render` call: `options`, updated by the arguments of `RenderOptions`
/// given positionally (`args`) or by keyword.
pub(crate) fn options_of(
    py: Python<'_>,
    options: Option<&PyRenderOptions>,
    args: &Bound<'_, PyTuple>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<core::RenderOptions> {
    let built = match options {
        Some(o) if args.is_empty() && kwargs.map_or(true, |k| k.is_empty()) => {
            return Ok(o.inner.clone())
        }
        Some(_) if !args.is_empty() => {
            return Err(PyTypeError::new_err(
                "give the render options either as options= or as arguments, not both",
            ))
        }
        Some(o) => o.replace(py, kwargs)?,
        None => py.get_type::<PyRenderOptions>().call(args, kwargs)?,
    };
    Ok(built.extract::<PyRenderOptions>()?.inner)
}

/// A frame's colour as an (h, w, 3) array and its depth, if any, as (h, w): the buffers are
/// moved into NumPy, not copied.
pub(crate) fn frame_arrays(
    py: Python<'_>,
    color: core::ColorBuffer,
    depth: Option<Vec<f32>>,
    width: u32,
    height: u32,
) -> (Bound<'_, PyAny>, Option<Bound<'_, PyAny>>) {
    let (h, w) = (height as usize, width as usize);
    let image = match color {
        core::ColorBuffer::U8(v) => Array3::from_shape_vec((h, w, 3), v)
            .expect("size checked")
            .into_pyarray(py)
            .into_any(),
        core::ColorBuffer::F32(v) => Array3::from_shape_vec((h, w, 3), v)
            .expect("size checked")
            .into_pyarray(py)
            .into_any(),
    };
    let depth = depth.map(|d| {
        Array2::from_shape_vec((h, w), d)
            .expect("size checked")
            .into_pyarray(py)
            .into_any()
    });
    (image, depth)
}

pub(crate) fn format_of(dtype: &Bound<'_, PyAny>) -> PyResult<core::ColorFormat> {
    let np = dtype.py().import("numpy")?;
    let name: String = np
        .call_method1("dtype", (dtype,))
        .and_then(|d| d.getattr("name"))
        .and_then(|n| n.extract())
        .map_err(|_| {
            PyTypeError::new_err(format!("dtype must be 'uint8' or 'float32', got {dtype}"))
        })?;
    match name.as_str() {
        "uint8" => Ok(core::ColorFormat::U8),
        "float32" => Ok(core::ColorFormat::F32),
        _ => Err(PyValueError::new_err(format!(
            "dtype must be 'uint8' or 'float32', got '{name}'"
        ))),
    }
}

struct Rendered<'py> {
    image: Bound<'py, PyAny>,
    depth: Option<Bound<'py, PyAny>>,
    alpha: Option<Bound<'py, PyAny>>,
    stats: core::RenderStats,
}

fn render_impl<'py>(
    py: Python<'py>,
    scene: &PyScene,
    camera: &PyCamera,
    mut options: core::RenderOptions,
    dtype: Option<&Bound<'py, PyAny>>,
    outputs: core::Outputs,
) -> PyResult<Rendered<'py>> {
    if outputs.coverage {
        // Premultiplied alpha: the colour over a transparent (black) background.
        options.background = glam::Vec3::ZERO;
    }
    let format = match dtype {
        Some(d) => format_of(d)?,
        None => core::ColorFormat::U8,
    };
    // The planes and lights the user left out (defaults.rs).
    let (scene_copy, cam) = crate::defaults::prepare(scene, camera)?;
    let frame = py
        .detach(|| {
            no_panic("render", || {
                core::render_with(&scene_copy, &cam, &options, format, outputs)
            })
        })?
        .map_err(to_py)?;
    let (image, depth) = frame_arrays(py, frame.color, frame.depth, frame.width, frame.height);
    let (h, w) = (frame.height as usize, frame.width as usize);
    let alpha = frame.coverage.map(|a| {
        Array2::from_shape_vec((h, w), a)
            .expect("size checked")
            .into_pyarray(py)
            .into_any()
    });
    Ok(Rendered {
        image,
        depth,
        alpha,
        stats: frame.stats,
    })
}

/// Renders `scene` through `camera` into a C-contiguous (height, width, 3) array, or a
/// tuple (image, depth) with `return_depth=True`. The GIL is released while rendering.
#[pyfunction]
#[pyo3(signature = (scene, camera, *args, dtype=None, return_depth=false, options=None, **kwargs))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    scene: &PyScene,
    camera: &PyCamera,
    args: &Bound<'py, PyTuple>,
    dtype: Option<&Bound<'py, PyAny>>,
    return_depth: bool,
    options: Option<PyRef<'py, PyRenderOptions>>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let options = options_of(py, options.as_deref(), args, kwargs)?;
    let outputs = core::Outputs {
        depth: return_depth,
        coverage: false,
    };
    let r = render_impl(py, scene, camera, options, dtype, outputs)?;
    match r.depth {
        Some(d) => Ok(PyTuple::new(py, [r.image, d])?.into_any()),
        None => Ok(r.image),
    }
}

/// Like `render`, returning a dict with "image", "depth" (or None), "alpha" and "stats"
/// (triangle counters and per-stage times in milliseconds: vertex_ms, setup_ms (assembly,
/// clipping, setup and binning), raster_shade_ms). With `alpha=True` the background is
/// transparent: "image" is premultiplied and "alpha" the float32 (h, w) coverage (the share
/// of each pixel's samples a triangle covers); otherwise "alpha" is None.
#[pyfunction]
#[pyo3(signature = (scene, camera, *args, dtype=None, return_depth=false, options=None, alpha=false, **kwargs))]
#[allow(clippy::too_many_arguments)]
pub fn render_frame<'py>(
    py: Python<'py>,
    scene: &PyScene,
    camera: &PyCamera,
    args: &Bound<'py, PyTuple>,
    dtype: Option<&Bound<'py, PyAny>>,
    return_depth: bool,
    options: Option<PyRef<'py, PyRenderOptions>>,
    alpha: bool,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = options_of(py, options.as_deref(), args, kwargs)?;
    let outputs = core::Outputs {
        depth: return_depth,
        coverage: alpha,
    };
    let r = render_impl(py, scene, camera, options, dtype, outputs)?;
    let s = r.stats;
    let stats = PyDict::new(py);
    if !s.shading.is_empty() {
        let (modes, estimates) = shading_stats(py, &s.shading)?;
        stats.set_item("shading", modes)?;
        stats.set_item("shading_estimates", estimates)?;
    }
    stats.set_item("triangles_in", s.triangles_in)?;
    stats.set_item("triangles_setup", s.triangles_setup)?;
    stats.set_item("triangles_clipped", s.triangles_clipped)?;
    stats.set_item("triangles_culled", s.triangles_culled)?;
    stats.set_item("triangles_dropped", s.triangles_dropped)?;
    stats.set_item("light_sources", s.light_sources)?;
    let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
    stats.set_item("vertex_ms", ms(s.timings.vertex))?;
    stats.set_item("setup_ms", ms(s.timings.setup))?;
    stats.set_item("raster_shade_ms", ms(s.timings.raster_shade))?;
    let out = PyDict::new(py);
    out.set_item("image", r.image)?;
    out.set_item("depth", r.depth)?;
    out.set_item("alpha", r.alpha)?;
    out.set_item("stats", stats)?;
    Ok(out)
}

/// `stats["shading"]` (each object's mode, in scene order) and `stats["shading_estimates"]`
/// (per object: the mode, the estimated RMSE of each mode, whether the mode meets the
/// tolerance, the estimated pixels).
fn shading_stats<'py>(
    py: Python<'py>,
    estimates: &[core::ShadingEstimate],
) -> PyResult<(Bound<'py, PyList>, Bound<'py, PyList>)> {
    let modes = PyList::empty(py);
    let list = PyList::empty(py);
    for e in estimates {
        modes.append(shading_name(e.mode))?;
        let d = PyDict::new(py);
        d.set_item("mode", shading_name(e.mode))?;
        for (name, v) in ["flat", "gouraud", "phong"].iter().zip(e.estimates) {
            d.set_item(*name, v)?;
        }
        d.set_item("meets", e.meets)?;
        d.set_item("pixels", e.pixels)?;
        list.append(d)?;
    }
    Ok((modes, list))
}

/// What `shading="auto"` would choose, without rendering: a dict with "shading" (each
/// object's mode, in scene order), "shading_estimates" (as `render_frame`'s stats) and
/// "tolerance". The other render options (size, camera-dependent ones) are
/// `RenderOptions`' arguments, as for `render`.
#[pyfunction]
#[pyo3(signature = (scene, camera, *args, tolerance=None, options=None, **kwargs))]
pub fn explain<'py>(
    py: Python<'py>,
    scene: &PyScene,
    camera: &PyCamera,
    args: &Bound<'py, PyTuple>,
    tolerance: Option<&Bound<'py, PyAny>>,
    options: Option<PyRef<'py, PyRenderOptions>>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = options_of(py, options.as_deref(), args, kwargs)?;
    let tolerance = match tolerance.filter(|t| !t.is_none()) {
        Some(t) => float_arg(Some(t), "tolerance", core::DEFAULT_TOLERANCE)?,
        None => options.tolerance.unwrap_or(core::DEFAULT_TOLERANCE),
    };
    let (scene_copy, cam) = crate::defaults::prepare(scene, camera)?;
    let estimates = py
        .detach(|| {
            no_panic("explain", || {
                core::explain_shading(&scene_copy, &cam, &options, tolerance)
            })
        })?
        .map_err(to_py)?;
    let (modes, list) = shading_stats(py, &estimates)?;
    let out = PyDict::new(py);
    out.set_item("shading", modes)?;
    out.set_item("shading_estimates", list)?;
    out.set_item("tolerance", tolerance)?;
    Ok(out)
}
