//! `render` and `render_frame`: argument conversion, GIL release, array hand-off.

use numpy::ndarray::{Array2, Array3};
use numpy::IntoPyArray;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use shadelab_raster as core;

use crate::camera::PyCamera;
use crate::convert;
use crate::errors::{no_panic, to_py};
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
    let Some(obj) = obj else { return Ok(default) };
    match int_arg(obj, name)? {
        Some(v) if (1..=core::MAX_IMAGE_SIZE as i64).contains(&v) => Ok(v as u32),
        _ => Err(PyValueError::new_err(format!(
            "{name} must be between 1 and {}, got {obj}",
            core::MAX_IMAGE_SIZE
        ))),
    }
}

fn threads_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    match int_arg(obj, "threads")? {
        Some(n) if (1..=core::MAX_THREADS as i64).contains(&n) => Ok(Some(n as usize)),
        _ => Err(PyValueError::new_err(format!(
            "threads must be between 1 and {} (or None for all cores), got {obj}",
            core::MAX_THREADS
        ))),
    }
}

fn format_of(dtype: &Bound<'_, PyAny>) -> PyResult<core::ColorFormat> {
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

/// The arguments every render entry point shares.
pub struct RenderArgs<'a, 'py> {
    pub width: Option<&'a Bound<'py, PyAny>>,
    pub height: Option<&'a Bound<'py, PyAny>>,
    pub shading: &'a str,
    pub specular: &'a str,
    pub background: Option<&'a Bound<'py, PyAny>>,
    pub dtype: Option<&'a Bound<'py, PyAny>>,
    pub cull_backfaces: bool,
    pub threads: Option<&'a Bound<'py, PyAny>>,
}

/// Checked render options and colour format.
pub fn options_from(a: RenderArgs<'_, '_>) -> PyResult<(core::RenderOptions, core::ColorFormat)> {
    let mut options =
        core::RenderOptions::new(size(a.width, 800, "width")?, size(a.height, 600, "height")?);
    options.shading = a.shading.parse().map_err(to_py)?;
    options.specular = a.specular.parse().map_err(to_py)?;
    if let Some(bg) = a.background {
        options.background = convert::vec3(bg, "background")?;
    }
    options.cull_backfaces = a.cull_backfaces;
    options.threads = threads_arg(a.threads)?;
    let format = match a.dtype {
        Some(d) => format_of(d)?,
        None => core::ColorFormat::U8,
    };
    Ok((options, format))
}

struct Rendered<'py> {
    image: Bound<'py, PyAny>,
    depth: Option<Bound<'py, PyAny>>,
    stats: core::RenderStats,
}

#[allow(clippy::too_many_arguments)]
fn render_impl<'py>(
    py: Python<'py>,
    scene: &PyScene,
    camera: &PyCamera,
    width: Option<&Bound<'py, PyAny>>,
    height: Option<&Bound<'py, PyAny>>,
    shading: &str,
    specular: &str,
    background: Option<&Bound<'py, PyAny>>,
    dtype: Option<&Bound<'py, PyAny>>,
    return_depth: bool,
    cull_backfaces: bool,
    threads: Option<&Bound<'py, PyAny>>,
) -> PyResult<Rendered<'py>> {
    let (options, format) = options_from(RenderArgs {
        width,
        height,
        shading,
        specular,
        background,
        dtype,
        cull_backfaces,
        threads,
    })?;
    let scene_copy = scene.inner.clone();
    let cam = camera.inner;
    let frame = py
        .detach(|| {
            no_panic("render", || {
                core::render(&scene_copy, &cam, &options, format, return_depth)
            })
        })?
        .map_err(to_py)?;
    let (h, w) = (frame.height as usize, frame.width as usize);
    let image = match frame.color {
        core::ColorBuffer::U8(v) => Array3::from_shape_vec((h, w, 3), v)
            .expect("size checked")
            .into_pyarray(py)
            .into_any(),
        core::ColorBuffer::F32(v) => Array3::from_shape_vec((h, w, 3), v)
            .expect("size checked")
            .into_pyarray(py)
            .into_any(),
    };
    let depth = frame.depth.map(|d| {
        Array2::from_shape_vec((h, w), d)
            .expect("size checked")
            .into_pyarray(py)
            .into_any()
    });
    Ok(Rendered {
        image,
        depth,
        stats: frame.stats,
    })
}

/// Renders `scene` through `camera` into a C-contiguous (height, width, 3) array, or a
/// tuple (image, depth) with `return_depth=True`. The GIL is released while rendering.
#[pyfunction]
#[pyo3(signature = (scene, camera, width=None, height=None, shading="phong", specular="blinn",
                    background=None, dtype=None, return_depth=false, cull_backfaces=false, threads=None),
       text_signature = "(scene, camera, width=800, height=600, shading='phong', specular='blinn', background=None, dtype=None, return_depth=False, cull_backfaces=False, threads=None)")]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    scene: &PyScene,
    camera: &PyCamera,
    width: Option<&Bound<'py, PyAny>>,
    height: Option<&Bound<'py, PyAny>>,
    shading: &str,
    specular: &str,
    background: Option<&Bound<'py, PyAny>>,
    dtype: Option<&Bound<'py, PyAny>>,
    return_depth: bool,
    cull_backfaces: bool,
    threads: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let r = render_impl(
        py,
        scene,
        camera,
        width,
        height,
        shading,
        specular,
        background,
        dtype,
        return_depth,
        cull_backfaces,
        threads,
    )?;
    match r.depth {
        Some(d) => Ok(PyTuple::new(py, [r.image, d])?.into_any()),
        None => Ok(r.image),
    }
}

/// Like `render`, returning a dict with "image", "depth" (or None) and "stats" (triangle
/// counters and per-stage times in milliseconds: vertex_ms, setup_ms (assembly, clipping,
/// setup and binning), raster_shade_ms).
#[pyfunction]
#[pyo3(signature = (scene, camera, width=None, height=None, shading="phong", specular="blinn",
                    background=None, dtype=None, return_depth=false, cull_backfaces=false, threads=None),
       text_signature = "(scene, camera, width=800, height=600, shading='phong', specular='blinn', background=None, dtype=None, return_depth=False, cull_backfaces=False, threads=None)")]
#[allow(clippy::too_many_arguments)]
pub fn render_frame<'py>(
    py: Python<'py>,
    scene: &PyScene,
    camera: &PyCamera,
    width: Option<&Bound<'py, PyAny>>,
    height: Option<&Bound<'py, PyAny>>,
    shading: &str,
    specular: &str,
    background: Option<&Bound<'py, PyAny>>,
    dtype: Option<&Bound<'py, PyAny>>,
    return_depth: bool,
    cull_backfaces: bool,
    threads: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let r = render_impl(
        py,
        scene,
        camera,
        width,
        height,
        shading,
        specular,
        background,
        dtype,
        return_depth,
        cull_backfaces,
        threads,
    )?;
    let s = r.stats;
    let stats = PyDict::new(py);
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
    out.set_item("stats", stats)?;
    Ok(out)
}
