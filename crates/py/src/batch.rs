//! `render_batch`: many views in one call. Every scene and camera is converted and checked
//! before the first frame; each frame then renders with the GIL released, straight into its
//! slice of one (N, H, W, 3) array (or into its own array handed to a callback). Between
//! frames the GIL is taken back briefly to check for Ctrl-C and report progress.

use numpy::ndarray::{Array2, Array3};
use numpy::{Element, IntoPyArray, PyArray3, PyArray4, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use shadelab_raster as core;

use crate::camera::PyCamera;
use crate::errors::{no_panic, to_py};
use crate::render::{options_from, RenderArgs};
use crate::scene::PyScene;

/// `obj` as one item (`Some(vec![x])` when it is a `T`) or a sequence of `T`, each
/// converted by `get`; a wrong item is a `TypeError` naming its index.
fn one_or_many<T>(
    obj: &Bound<'_, PyAny>,
    name: &str,
    class: &str,
    index_base: usize,
    get: impl Fn(&Bound<'_, PyAny>) -> Option<T>,
) -> PyResult<(Vec<T>, bool)> {
    if let Some(v) = get(obj) {
        return Ok((vec![v], true));
    }
    let iter = obj.try_iter().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name} must be a {class} or a sequence of {class} objects, got {}",
            obj.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    })?;
    let mut out = Vec::new();
    for (i, item) in iter.enumerate() {
        let item = item?;
        match get(&item) {
            Some(v) => out.push(v),
            None => {
                return Err(PyTypeError::new_err(format!(
                    "{name}[{}] must be a {class}, got {}",
                    index_base + i,
                    item.get_type().name()?
                )))
            }
        }
    }
    Ok((out, false))
}

/// The error of frame `i`, with the index in front of the core's message.
fn frame_error(py: Python<'_>, i: usize, e: PyErr) -> PyErr {
    let err = e
        .get_type(py)
        .call1((format!("view {i}: {}", e.value(py)),))
        .map(PyErr::from_value)
        .unwrap_or(e);
    err
}

/// `numpy.zeros(shape, dtype)`: too large a batch is numpy's MemoryError or ValueError
/// (rust-numpy's own constructor panics when the allocation fails).
fn zeros<'py>(py: Python<'py>, shape: Vec<usize>, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("numpy")?.call_method1("zeros", (shape, dtype))
}

/// Renders frame after frame into slices of `color` / `depth`.
#[allow(clippy::too_many_arguments)]
fn fill<P: core::Pixel + Element + Send>(
    py: Python<'_>,
    views: &[(usize, usize)],
    scenes: &[core::Scene],
    cameras: &[core::Camera],
    options: &core::RenderOptions,
    color: &mut [P],
    mut depth: Option<&mut [f32]>,
    progress: Option<&Bound<'_, PyAny>>,
    index_base: usize,
) -> PyResult<()> {
    let n = options.pixel_count();
    for (i, &(s, c)) in views.iter().enumerate() {
        let col = &mut color[i * n * 3..(i + 1) * n * 3];
        let dep = depth.as_deref_mut().map(|d| &mut d[i * n..(i + 1) * n]);
        let (scene, camera) = (&scenes[s], &cameras[c]);
        py.detach(|| {
            no_panic("render_batch", || {
                core::render_into(scene, camera, options, col, dep)
            })
        })
        .and_then(|r| r.map_err(to_py))
        .map_err(|e| frame_error(py, index_base + i, e))?;
        py.check_signals()?;
        if let Some(p) = progress {
            p.call1((i + 1,))?;
        }
    }
    Ok(())
}

/// Renders every (scene, camera) pair: one scene or camera is used for every view, two
/// sequences are paired and must have the same length. Returns an (N, H, W, 3) array (and
/// an (N, H, W) depth array with `return_depth`), or None when `callback` is given: it is
/// then called as `callback(i, image)` (or `callback(i, image, depth)`) after each frame.
/// `progress(done)` is called after each frame. The GIL is released while rendering.
#[pyfunction]
#[pyo3(signature = (scene, cameras, width=None, height=None, shading="phong", specular="blinn",
                    background=None, dtype=None, return_depth=false, cull_backfaces=false,
                    threads=None, callback=None, progress=None, index_base=0),
       text_signature = "(scene, cameras, width=800, height=600, shading='phong', specular='blinn', background=None, dtype=None, return_depth=False, cull_backfaces=False, threads=None, callback=None, progress=None, index_base=0)")]
#[allow(clippy::too_many_arguments)]
pub fn render_batch<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    cameras: &Bound<'py, PyAny>,
    width: Option<&Bound<'py, PyAny>>,
    height: Option<&Bound<'py, PyAny>>,
    shading: &str,
    specular: &str,
    background: Option<&Bound<'py, PyAny>>,
    dtype: Option<&Bound<'py, PyAny>>,
    return_depth: bool,
    cull_backfaces: bool,
    threads: Option<&Bound<'py, PyAny>>,
    callback: Option<&Bound<'py, PyAny>>,
    progress: Option<&Bound<'py, PyAny>>,
    index_base: usize,
) -> PyResult<Bound<'py, PyAny>> {
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
    let (scenes, one_scene) = one_or_many(scene, "scene", "Scene", index_base, |o| {
        o.extract::<PyRef<'_, PyScene>>()
            .ok()
            .map(|s| s.inner.clone())
    })?;
    let (cams, one_camera) = one_or_many(cameras, "cameras", "Camera", index_base, |o| {
        o.extract::<PyRef<'_, PyCamera>>().ok().map(|c| c.inner)
    })?;
    let n = match (one_scene, one_camera) {
        (true, _) => cams.len(),
        (false, true) => scenes.len(),
        (false, false) if scenes.len() == cams.len() => cams.len(),
        (false, false) => {
            return Err(PyValueError::new_err(format!(
                "{} scenes and {} cameras: pass one scene, one camera, or as many of each",
                scenes.len(),
                cams.len()
            )))
        }
    };
    let views: Vec<(usize, usize)> = (0..n)
        .map(|i| {
            (
                if one_scene { 0 } else { i },
                if one_camera { 0 } else { i },
            )
        })
        .collect();
    let (h, w) = (options.height as usize, options.width as usize);

    if let Some(cb) = callback {
        for (i, &(s, c)) in views.iter().enumerate() {
            let (scene, camera) = (&scenes[s], &cams[c]);
            let frame = py
                .detach(|| {
                    no_panic("render_batch", || {
                        core::render(scene, camera, &options, format, return_depth)
                    })
                })
                .and_then(|r| r.map_err(to_py))
                .map_err(|e| frame_error(py, index_base + i, e))?;
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
            py.check_signals()?;
            let index = (index_base + i).into_pyobject(py)?.into_any();
            match frame.depth {
                Some(d) => {
                    let d = Array2::from_shape_vec((h, w), d)
                        .expect("size checked")
                        .into_pyarray(py)
                        .into_any();
                    cb.call1(PyTuple::new(py, [index, image, d])?)?
                }
                None => cb.call1(PyTuple::new(py, [index, image])?)?,
            };
            if let Some(p) = progress {
                p.call1((i + 1,))?;
            }
        }
        return Ok(py.None().into_bound(py));
    }

    let depth = if return_depth {
        Some(zeros(py, vec![n, h, w], "float32")?.cast_into::<PyArray3<f32>>()?)
    } else {
        None
    };
    let mut depth_rw = depth.as_ref().map(|d| d.readwrite());
    let depth_slice = depth_rw
        .as_mut()
        .map(|d| d.as_slice_mut().expect("new arrays are contiguous"));
    let image = match format {
        core::ColorFormat::U8 => {
            let a = zeros(py, vec![n, h, w, 3], "uint8")?.cast_into::<PyArray4<u8>>()?;
            fill(
                py,
                &views,
                &scenes,
                &cams,
                &options,
                a.readwrite().as_slice_mut().expect("contiguous"),
                depth_slice,
                progress,
                index_base,
            )?;
            a.into_any()
        }
        core::ColorFormat::F32 => {
            let a = zeros(py, vec![n, h, w, 3], "float32")?.cast_into::<PyArray4<f32>>()?;
            fill(
                py,
                &views,
                &scenes,
                &cams,
                &options,
                a.readwrite().as_slice_mut().expect("contiguous"),
                depth_slice,
                progress,
                index_base,
            )?;
            a.into_any()
        }
    };
    drop(depth_rw);
    match depth {
        Some(d) => Ok(PyTuple::new(py, [image, d.into_any()])?.into_any()),
        None => Ok(image),
    }
}

/// Test hook: every render waits on its workers (up to `timeout` seconds) until `renders`
/// renders are in flight together; resets the high-water mark read by `_max_in_flight`.
#[pyfunction]
pub fn _set_rendezvous(renders: usize, timeout: f64) {
    core::set_rendezvous(
        renders,
        std::time::Duration::from_secs_f64(timeout.max(0.0)),
    );
}

/// Test hook: the most renders seen running at once since the last `_set_rendezvous`.
#[pyfunction]
pub fn _max_in_flight() -> usize {
    core::max_in_flight()
}
