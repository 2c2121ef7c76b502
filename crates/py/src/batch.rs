//! `render_batch`: many views in one call. Every scene and camera is converted and checked
//! (and each view's near/far planes fitted, as `render` fits them) before the first frame; each frame then renders with the GIL released, straight into its
//! slice of one (N, H, W, 3) array (or into its own array handed to a callback). Between
//! frames the GIL is taken back briefly to check for Ctrl-C and report progress.

use numpy::{Element, PyArray3, PyArray4, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use shadelab_raster as core;

use crate::camera::PyCamera;
use crate::defaults::{fit_planes, lit_scene};
use crate::errors::{no_panic, to_py};
use crate::render::{format_of, frame_arrays, options_of, PyRenderOptions};
use crate::scene::PyScene;

/// A scene as a batch holds it: the core scene and whether `render` would add the default
/// light rig to it (`Scene.default_lights`).
type BatchScene = (core::Scene, bool);

/// One view: its scene's index and its camera with the planes fitted to that scene.
type View = (usize, core::Camera);

/// Renders one view as `render` does: the light rig added when the scene asks for it
/// (defaults.rs), so a batch frame is bit-identical to a single render.
fn render_view(
    py: Python<'_>,
    scene: &BatchScene,
    camera: &core::Camera,
    options: &core::RenderOptions,
    format: core::ColorFormat,
    return_depth: bool,
) -> PyResult<core::Frame> {
    py.detach(|| {
        no_panic("render_batch", || {
            let lit = lit_scene(&scene.0, scene.1, camera);
            core::render(&lit, camera, options, format, return_depth)
        })
    })
    .and_then(|r| r.map_err(to_py))
}

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

/// A new (n, h, w, 3) array of `dtype`, every view rendered into it.
#[allow(clippy::too_many_arguments)]
fn batch_images<'py, P: core::Pixel + Element + Send>(
    py: Python<'py>,
    dtype: &str,
    [n, h, w]: [usize; 3],
    views: &[View],
    scenes: &[BatchScene],
    options: &core::RenderOptions,
    depth: Option<&mut [f32]>,
    progress: Option<&Bound<'_, PyAny>>,
    index_base: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let a = zeros(py, vec![n, h, w, 3], dtype)?.cast_into::<PyArray4<P>>()?;
    fill(
        py,
        views,
        scenes,
        options,
        a.readwrite().as_slice_mut().expect("contiguous"),
        depth,
        progress,
        index_base,
    )?;
    Ok(a.into_any())
}

/// Renders frame after frame into slices of `color` / `depth`.
#[allow(clippy::too_many_arguments)]
fn fill<P: core::Pixel + Element + Send>(
    py: Python<'_>,
    views: &[View],
    scenes: &[BatchScene],
    options: &core::RenderOptions,
    color: &mut [P],
    mut depth: Option<&mut [f32]>,
    progress: Option<&Bound<'_, PyAny>>,
    index_base: usize,
) -> PyResult<()> {
    let n = options.pixel_count();
    for (i, (s, camera)) in views.iter().enumerate() {
        let col = &mut color[i * n * 3..(i + 1) * n * 3];
        let dep = depth.as_deref_mut().map(|d| &mut d[i * n..(i + 1) * n]);
        let scene = &scenes[*s];
        py.detach(|| {
            no_panic("render_batch", || {
                let lit = lit_scene(&scene.0, scene.1, camera);
                core::render_into(&lit, camera, options, col, dep)
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
/// sequences are paired and must have the same length. The render options are `render`'s
/// (positional after `cameras`, by keyword, or `options=`), and each view is prepared as
/// `render` prepares it (fitted planes, default light rig). Returns an (N, H, W, 3) array
/// (and an (N, H, W) depth array with `return_depth`), or None when `callback` is given:
/// it is then called as `callback(i, image)` (or `callback(i, image, depth)`) after each
/// frame. `progress(done)` is called after each frame. The GIL is released while rendering.
#[pyfunction]
#[pyo3(signature = (scene, cameras, *args, dtype=None, return_depth=false, options=None,
                    callback=None, progress=None, index_base=0, **kwargs))]
#[allow(clippy::too_many_arguments)]
pub fn render_batch<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    cameras: &Bound<'py, PyAny>,
    args: &Bound<'py, PyTuple>,
    dtype: Option<&Bound<'py, PyAny>>,
    return_depth: bool,
    options: Option<PyRef<'py, PyRenderOptions>>,
    callback: Option<&Bound<'py, PyAny>>,
    progress: Option<&Bound<'py, PyAny>>,
    index_base: usize,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let options = options_of(py, options.as_deref(), args, kwargs)?;
    let format = match dtype {
        Some(d) => format_of(d)?,
        None => core::ColorFormat::U8,
    };
    let (scenes, one_scene) = one_or_many(scene, "scene", "Scene", index_base, |o| {
        o.extract::<PyRef<'_, PyScene>>()
            .ok()
            .map(|s| (s.inner.clone(), s.default_lights))
    })?;
    let (cams, one_camera) = one_or_many(cameras, "cameras", "Camera", index_base, |o| {
        o.extract::<PyRef<'_, PyCamera>>().ok().map(|c| c.clone())
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
    // The planes each view leaves open, fitted to its scene as `render` fits them: a view
    // whose fit fails is an error naming it before any frame renders.
    let views: Vec<View> = (0..n)
        .map(|i| {
            let (s, c) = (
                if one_scene { 0 } else { i },
                if one_camera { 0 } else { i },
            );
            let camera = fit_planes(&cams[c], &scenes[s].0)
                .map_err(|e| frame_error(py, index_base + i, e))?;
            Ok((s, camera))
        })
        .collect::<PyResult<_>>()?;
    let (h, w) = (options.height as usize, options.width as usize);

    if let Some(cb) = callback {
        for (i, (s, camera)) in views.iter().enumerate() {
            let frame = render_view(py, &scenes[*s], camera, &options, format, return_depth)
                .map_err(|e| frame_error(py, index_base + i, e))?;
            let (image, depth) =
                frame_arrays(py, frame.color, frame.depth, frame.width, frame.height);
            py.check_signals()?;
            let index = (index_base + i).into_pyobject(py)?.into_any();
            match depth {
                Some(d) => cb.call1(PyTuple::new(py, [index, image, d])?)?,
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
    let (views, scenes) = (&views[..], &scenes[..]);
    let image = match format {
        core::ColorFormat::U8 => batch_images::<u8>(
            py,
            "uint8",
            [n, h, w],
            views,
            scenes,
            &options,
            depth_slice,
            progress,
            index_base,
        )?,
        core::ColorFormat::F32 => batch_images::<f32>(
            py,
            "float32",
            [n, h, w],
            views,
            scenes,
            &options,
            depth_slice,
            progress,
            index_base,
        )?,
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
