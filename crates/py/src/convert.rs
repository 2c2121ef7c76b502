//! Conversion of Python values (NumPy arrays, sequences) into validated Rust values.
//!
//! Arrays of any memory layout (C, Fortran, strided, read-only) are accepted: they are read
//! through `numpy.ascontiguousarray`, which copies only when needed. Floating inputs may be
//! any float or integer dtype; bool, complex, object and string dtypes are a `TypeError`.
//! Every error carries the argument's name as its `field` attribute.

use glam::{Mat4, Vec2, Vec3};
use numpy::{PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::with_field;

/// An array as contiguous f64 plus its shape.
struct Floats {
    shape: Vec<usize>,
    data: Vec<f64>,
}

/// `numpy.asarray(obj)` with its dtype kind (`"f"`, `"i"`, ...) and dtype name.
fn as_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<(Bound<'py, PyAny>, String, String)> {
    let np = obj.py().import("numpy")?;
    let arr = np
        .call_method1("asarray", (obj,))
        .map_err(|e| PyTypeError::new_err(format!("{name} must be array-like of numbers: {e}")))?;
    let dtype = arr.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    let dname: String = dtype.getattr("name")?.extract()?;
    Ok((arr, kind, dname))
}

fn floats(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Floats> {
    let py = obj.py();
    let (arr, kind, dname) = as_array(obj, name)?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(PyTypeError::new_err(format!(
            "{name} must be a real numeric array (float or int), got dtype {dname}"
        )));
    }
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", "float64")?;
    let np = py.import("numpy")?;
    let c = np.call_method("ascontiguousarray", (arr,), Some(&kwargs))?;
    let ro: PyReadonlyArrayDyn<f64> = c.extract()?;
    let shape = ro.shape().to_vec();
    let data = ro
        .as_slice()
        .map_err(|e| PyValueError::new_err(e.to_string()))?
        .to_vec();
    Ok(Floats { shape, data })
}

fn shape_str(shape: &[usize]) -> String {
    format!(
        "({})",
        shape
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    )
}

fn first_non_finite(name: &str, data: &[f64], cols: usize) -> PyResult<()> {
    if let Some(i) = data
        .iter()
        .position(|v| !v.is_finite() || v.abs() > f32::MAX as f64)
    {
        let what = if cols > 1 {
            format!("{name}[{}, {}]", i / cols, i % cols)
        } else {
            format!("{name}[{i}]")
        };
        return Err(PyValueError::new_err(format!(
            "{what} = {} is not a finite float32 value",
            data[i]
        )));
    }
    Ok(())
}

/// An `(N, cols)` float array as rows, checked finite (and representable in f32).
fn rows(obj: &Bound<'_, PyAny>, name: &str, cols: usize) -> PyResult<Vec<f32>> {
    rows_unnamed(obj, name, cols).map_err(|e| with_field(e, name))
}

fn rows_unnamed(obj: &Bound<'_, PyAny>, name: &str, cols: usize) -> PyResult<Vec<f32>> {
    let a = floats(obj, name)?;
    if a.shape.len() != 2 || a.shape[1] != cols {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (N, {cols}), got {}",
            shape_str(&a.shape)
        )));
    }
    first_non_finite(name, &a.data, cols)?;
    Ok(a.data.iter().map(|&v| v as f32).collect())
}

/// `(N, 3)` float array → points.
pub fn vec3_rows(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<Vec3>> {
    Ok(rows(obj, name, 3)?
        .chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect())
}

/// `(N, 2)` float array → UVs.
pub fn vec2_rows(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<Vec2>> {
    Ok(rows(obj, name, 2)?
        .chunks_exact(2)
        .map(|c| Vec2::new(c[0], c[1]))
        .collect())
}

/// A length-3 sequence or array → finite `Vec3`.
pub fn vec3(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec3> {
    vec3_unnamed(obj, name).map_err(|e| with_field(e, name))
}

fn vec3_unnamed(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec3> {
    let a = floats(obj, name)?;
    if a.shape != [3] {
        return Err(PyValueError::new_err(format!(
            "{name} must be 3 numbers, got shape {}",
            shape_str(&a.shape)
        )));
    }
    first_non_finite(name, &a.data, 1)?;
    Ok(Vec3::new(
        a.data[0] as f32,
        a.data[1] as f32,
        a.data[2] as f32,
    ))
}

/// A length-3 sequence → finite f64 triple (camera parameters keep double precision).
pub fn dvec3(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<glam::DVec3> {
    dvec3_unnamed(obj, name).map_err(|e| with_field(e, name))
}

fn dvec3_unnamed(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<glam::DVec3> {
    let a = floats(obj, name)?;
    if a.shape != [3] {
        return Err(PyValueError::new_err(format!(
            "{name} must be 3 numbers, got shape {}",
            shape_str(&a.shape)
        )));
    }
    first_non_finite(name, &a.data, 1)?;
    Ok(glam::DVec3::new(a.data[0], a.data[1], a.data[2]))
}

/// A `(4, 4)` matrix acting on column vectors (`p' = M @ p`), checked finite.
pub fn mat4(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Mat4> {
    mat4_unnamed(obj, name).map_err(|e| with_field(e, name))
}

fn mat4_unnamed(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Mat4> {
    let a = floats(obj, name)?;
    if a.shape != [4, 4] {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (4, 4), got {}",
            shape_str(&a.shape)
        )));
    }
    first_non_finite(name, &a.data, 4)?;
    // Row-major NumPy data → glam's column-major storage.
    let m: Vec<f32> = a.data.iter().map(|&v| v as f32).collect();
    Ok(Mat4::from_cols_slice(&m).transpose())
}

/// An `(M, 3)` integer array of vertex indices, each checked in `[0, n_vertices)`.
pub fn faces(obj: &Bound<'_, PyAny>, n_vertices: usize) -> PyResult<Vec<[u32; 3]>> {
    faces_unnamed(obj, n_vertices).map_err(|e| with_field(e, "faces"))
}

fn faces_unnamed(obj: &Bound<'_, PyAny>, n_vertices: usize) -> PyResult<Vec<[u32; 3]>> {
    let py = obj.py();
    let (arr, kind, dname) = as_array(obj, "faces")?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    if shape.iter().product::<usize>() == 0 && (shape.len() == 1 || shape.get(1) == Some(&3)) {
        // `[]` has dtype float64 in NumPy; an empty face list is "no triangles", not a dtype error.
        return Ok(Vec::new());
    }
    if !matches!(kind.as_str(), "i" | "u") {
        return Err(PyTypeError::new_err(format!(
            "faces must be an integer array, got dtype {dname}"
        )));
    }
    if shape.len() != 2 || shape[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "faces must have shape (M, 3), got {}",
            shape_str(&shape)
        )));
    }
    let np = py.import("numpy")?;
    let check = |i: usize, v: i128| -> PyResult<u32> {
        if v < 0 || v >= n_vertices as i128 {
            Err(PyValueError::new_err(format!(
                "faces[{}, {}] = {v} is out of range for {n_vertices} vertices",
                i / 3,
                i % 3
            )))
        } else {
            Ok(v as u32)
        }
    };
    // Unsigned dtypes go through uint64 so values ≥ 2^63 are not wrapped to negatives.
    fn read<T: numpy::Element + Copy + Into<i128>>(
        np: &Bound<'_, PyModule>,
        arr: Bound<'_, PyAny>,
        dtype: &str,
        check: impl Fn(usize, i128) -> PyResult<u32>,
    ) -> PyResult<Vec<u32>> {
        let kwargs = PyDict::new(np.py());
        kwargs.set_item("dtype", dtype)?;
        let c = np.call_method("ascontiguousarray", (arr,), Some(&kwargs))?;
        let ro: PyReadonlyArrayDyn<T> = c.extract()?;
        let s = ro
            .as_slice()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        s.iter()
            .enumerate()
            .map(|(i, &v)| check(i, v.into()))
            .collect()
    }
    let flat = if kind == "u" {
        read::<u64>(&np, arr, "uint64", check)?
    } else {
        read::<i64>(&np, arr, "int64", check)?
    };
    Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// Vertex colours: an (N, 3) or (N, 4) array (alpha dropped), uint8 (/ 255) or float.
pub fn colors(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Vec3>> {
    let name = "colors";
    let (_, kind, dname) = as_array(obj, name).map_err(|e| with_field(e, name))?;
    let a = floats(obj, name).map_err(|e| with_field(e, name))?;
    if a.shape.len() != 2 || !(a.shape[1] == 3 || a.shape[1] == 4) {
        return Err(with_field(
            PyValueError::new_err(format!(
                "colors must have shape (N, 3) or (N, 4), got {}",
                shape_str(&a.shape)
            )),
            name,
        ));
    }
    let cols = a.shape[1];
    first_non_finite(name, &a.data, cols).map_err(|e| with_field(e, name))?;
    let scale = match (kind.as_str(), dname.as_str()) {
        (_, "uint8") => 1.0 / 255.0,
        ("f", _) => 1.0,
        _ => {
            return Err(with_field(
                PyTypeError::new_err(format!("colors must be uint8 or float, got dtype {dname}")),
                name,
            ))
        }
    };
    Ok(a.data
        .chunks_exact(cols)
        .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) * scale)
        .collect())
}

/// `numpy.asarray(obj)` (a Pillow image too) with its dtype name and shape, for image
/// arrays (textures, environments); `needs` completes the error when NumPy cannot make an
/// array of it (e.g. "a texture needs an (H, W, 3|4) array").
pub fn image_array<'py>(
    obj: &Bound<'py, PyAny>,
    needs: &str,
) -> PyResult<(Bound<'py, PyAny>, String, Vec<usize>)> {
    let arr = obj
        .py()
        .import("numpy")?
        .call_method1("asarray", (obj,))
        .map_err(|e| crate::errors::type_error("array", format!("{needs}: {e}")))?;
    let dtype: String = arr.getattr("dtype")?.getattr("name")?.extract()?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    Ok((arr, dtype, shape))
}

/// An array from [`image_array`] as C-contiguous float64 values (a view when it already
/// is one).
pub fn f64_values<'py>(arr: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArrayDyn<'py, f64>> {
    let kwargs = PyDict::new(arr.py());
    kwargs.set_item("dtype", "float64")?;
    let c = arr
        .py()
        .import("numpy")?
        .call_method("ascontiguousarray", (arr,), Some(&kwargs))?;
    Ok(c.extract()?)
}
