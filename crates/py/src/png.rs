//! `encode_png`: an image array as PNG bytes, encoded by the core (`png_out.rs`) with the
//! GIL released.

use numpy::{PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use shadelab_raster as core;

use crate::errors::{no_panic, to_py, type_error, value_error};

/// (height, width, channels) of a 2-D (grey) or 3-D array.
fn dims(shape: &[usize]) -> PyResult<(u32, u32, u8)> {
    let (h, w, c) = match *shape {
        [h, w] => (h, w, 1),
        [h, w, c] => (h, w, c),
        _ => {
            return Err(value_error(
                "image",
                format!("image must be (H, W) or (H, W, C), got shape {shape:?}"),
            ))
        }
    };
    let side = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
    let channels = u8::try_from(c).unwrap_or(u8::MAX);
    Ok((side(h), side(w), channels))
}

/// The PNG file of an (H, W) or (H, W, C) C-contiguous uint8 or uint16 array (C = 1 to 4),
/// with ``text`` as tEXt chunks; ``compression`` is "none", "fastest", "fast", "balanced"
/// or "high".
#[pyfunction]
#[pyo3(signature = (image, compression = "fast", text = None))]
pub fn encode_png<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    compression: &str,
    text: Option<Vec<(String, String)>>,
) -> PyResult<Bound<'py, PyBytes>> {
    let compression: core::PngCompression = compression.parse().map_err(to_py)?;
    let text = text.unwrap_or_default();
    let contiguous = || value_error("image", "image must be a C-contiguous array");
    let bytes = if let Ok(a) = image.extract::<PyReadonlyArrayDyn<'py, u8>>() {
        let (h, w, c) = dims(a.shape())?;
        let s = a.as_slice().map_err(|_| contiguous())?;
        py.detach(|| {
            no_panic("encode_png", || {
                core::encode_png(core::PngSamples::U8(s), w, h, c, compression, &text)
            })
        })?
    } else if let Ok(a) = image.extract::<PyReadonlyArrayDyn<'py, u16>>() {
        let (h, w, c) = dims(a.shape())?;
        let s = a.as_slice().map_err(|_| contiguous())?;
        py.detach(|| {
            no_panic("encode_png", || {
                core::encode_png(core::PngSamples::U16(s), w, h, c, compression, &text)
            })
        })?
    } else {
        return Err(type_error(
            "image",
            format!(
                "image must be a uint8 or uint16 NumPy array, got {}",
                image.get_type().name()?
            ),
        ));
    }
    .map_err(to_py)?;
    Ok(PyBytes::new(py, &bytes))
}
