//! Python bindings of shadelab_rs: conversion of arguments and mapping of errors only; all
//! rendering lives in the `shadelab-raster` crate.

mod area_light;
mod batch;
mod camera;
mod convert;
mod defaults;
mod environment;
mod errors;
mod fog;
mod light;
mod material;
mod mesh;
mod pickle;
mod png;
mod render;
mod scene;
mod shadow;
mod texture;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MAX_IMAGE_SIZE", shadelab_raster::MAX_IMAGE_SIZE)?;
    m.add("MAX_THREADS", shadelab_raster::MAX_THREADS)?;
    m.add("ObjParseError", m.py().get_type::<errors::ObjParseError>())?;
    m.add_class::<mesh::PyMesh>()?;
    m.add_class::<material::PyMaterial>()?;
    m.add_class::<texture::PyTexture>()?;
    m.add(
        "MAX_TEXTURE_SIZE",
        shadelab_raster::texture::MAX_TEXTURE_SIZE,
    )?;
    m.add_class::<light::PyDirectionalLight>()?;
    m.add_class::<light::PyPointLight>()?;
    m.add_class::<light::PySpotLight>()?;
    m.add_class::<area_light::PyAreaLight>()?;
    m.add("MAX_AREA_SAMPLES", shadelab_raster::MAX_AREA_SAMPLES)?;
    m.add_class::<shadow::PyShadowSettings>()?;
    m.add(
        "MAX_SHADOW_RESOLUTION",
        shadelab_raster::MAX_SHADOW_RESOLUTION,
    )?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<scene::PySceneObject>()?;
    m.add_class::<fog::PyFog>()?;
    m.add_class::<environment::PyEnvironment>()?;
    m.add(
        "MAX_ENVIRONMENT_SIZE",
        shadelab_raster::MAX_ENVIRONMENT_SIZE,
    )?;
    m.add("MAX_TRACE_DEPTH", shadelab_raster::MAX_TRACE_DEPTH)?;
    m.add("DEFAULT_TOLERANCE", shadelab_raster::DEFAULT_TOLERANCE)?;
    m.add_class::<camera::PyCamera>()?;
    m.add_function(wrap_pyfunction!(mesh::load_obj, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::load_obj_parts, m)?)?;
    m.add_class::<render::PyRenderOptions>()?;
    m.add_function(wrap_pyfunction!(png::encode_png, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::render_frame, m)?)?;
    m.add_function(wrap_pyfunction!(render::explain, m)?)?;
    m.add_function(wrap_pyfunction!(batch::render_batch, m)?)?;
    // Pickle's reconstructor and the test hooks are set as attributes, out of `__all__`.
    m.setattr("_restore", wrap_pyfunction!(pickle::_restore, m)?)?;
    m.setattr(
        "_set_rendezvous",
        wrap_pyfunction!(batch::_set_rendezvous, m)?,
    )?;
    m.setattr(
        "_max_in_flight",
        wrap_pyfunction!(batch::_max_in_flight, m)?,
    )?;
    // A test hook: set as an attribute, so it stays out of `__all__`.
    m.setattr(
        "_panic_for_tests",
        wrap_pyfunction!(errors::_panic_for_tests, m)?,
    )?;
    Ok(())
}
