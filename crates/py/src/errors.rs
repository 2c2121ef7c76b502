//! Mapping of core errors to Python exceptions.

use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyIsADirectoryError, PyMemoryError, PyOSError, PyRuntimeError,
    PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use shadelab_raster::RasterError;

create_exception!(
    shadelab_rs,
    ObjParseError,
    PyValueError,
    "A mesh file was read but its content is malformed (a ValueError)."
);

/// `err` with a `field` attribute naming the offending argument, unless it has one: a
/// caller (the scene-file reader) maps it to its own key path instead of checking the value
/// again.
pub fn with_field(err: PyErr, field: &str) -> PyErr {
    Python::attach(|py| {
        let value = err.value(py);
        if !value.hasattr("field").unwrap_or(true) {
            // An exception instance always takes attributes; nothing to report if not.
            let _ = value.setattr("field", field);
        }
    });
    err
}

/// A `ValueError` about the argument `field`.
pub fn value_error(field: &str, msg: impl Into<String>) -> PyErr {
    with_field(PyValueError::new_err(msg.into()), field)
}

/// A `TypeError` about the argument `field`.
pub fn type_error(field: &str, msg: impl Into<String>) -> PyErr {
    with_field(PyTypeError::new_err(msg.into()), field)
}

/// The Python exception for a core error: `FileNotFoundError`, `IsADirectoryError`,
/// `OSError`, `ObjParseError`
/// (a `ValueError`), `MemoryError` or `ValueError`, with the core's message; a `ValueError`
/// about one argument carries its name as `field`.
pub fn to_py(e: RasterError) -> PyErr {
    let msg = e.to_string();
    match e {
        RasterError::InvalidInput(_) => PyValueError::new_err(msg),
        RasterError::InvalidField { field, .. } => value_error(field, msg),
        RasterError::NotFound(_) => PyFileNotFoundError::new_err(msg),
        RasterError::Io { path, .. } if path.is_dir() => PyIsADirectoryError::new_err(msg),
        RasterError::Io { .. } => PyOSError::new_err(msg),
        RasterError::Parse { .. } => ObjParseError::new_err(msg),
        RasterError::OutOfMemory { .. } => PyMemoryError::new_err(msg),
    }
}

/// Runs `f`, turning a Rust panic into a `RuntimeError` so none can reach Python as
/// `PanicException` (which `except Exception` does not catch).
pub fn no_panic<T>(what: &str, f: impl FnOnce() -> T) -> Result<T, PyErr> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|p| {
        let detail = p
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        PyRuntimeError::new_err(format!(
            "internal error in {what} (please report it): {detail}"
        ))
    })
}

/// Test hook: panics inside Rust behind the same guard as every entry point, so the test
/// suite can check that a panic arrives as `RuntimeError`, never as `PanicException`.
#[pyfunction]
pub fn _panic_for_tests() -> PyResult<()> {
    no_panic("_panic_for_tests", || panic!("forced by the test suite"))
}
