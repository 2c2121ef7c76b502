//! `Environment`: an equirectangular image of the light from every direction.

use numpy::{PyArray3, PyReadonlyArrayDyn};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use shadelab_raster as core;

use crate::errors::{to_py, type_error, value_error};

/// An equirectangular (latitude–longitude) environment: an (H, 2H, 3) float32/float64
/// (linear, HDR allowed) or uint8 array (divided by 255, or sRGB-decoded with `srgb=True`).
/// A unit direction d maps to u = 0.5 + atan2(d.x, -d.z)/(2 pi), v = acos(d.y)/pi: column
/// u*W, row v*H, so row 0 looks straight up (+y) and the centre column along -z; sampled
/// bilinearly, wrapping in u. `rotation` turns it about +y (degrees; positive turns what
/// was seen along -z toward -x); `intensity` scales every value.
#[pyclass(name = "Environment", module = "shadelab_rs._core", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyEnvironment {
    pub inner: core::Environment,
    /// The file it was read from (`sl.load_environment`), written to scene files.
    pub path: Option<std::path::PathBuf>,
}

fn texels(obj: &Bound<'_, PyAny>, srgb: bool) -> PyResult<(usize, usize, Vec<f32>)> {
    let (arr, dtype, shape) =
        crate::convert::image_array(obj, "an environment needs an (H, 2H, 3) array")?;
    let scale = match dtype.as_str() {
        "uint8" => 1.0 / 255.0,
        "float32" | "float64" => 1.0,
        _ => {
            return Err(type_error(
                "array",
                format!("environment arrays must be float32, float64 or uint8, got dtype {dtype}"),
            ))
        }
    };
    if srgb && dtype != "uint8" {
        return Err(value_error(
            "srgb",
            "srgb=True decodes uint8 images; float arrays are linear already",
        ));
    }
    if shape.len() != 3 || shape[2] != 3 {
        return Err(value_error(
            "array",
            format!("an environment array must have shape (H, 2H, 3), got {shape:?}"),
        ));
    }
    let ro = crate::convert::f64_values(&arr)?;
    let data = ro
        .as_slice()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let data = data
        .iter()
        .map(|&v| {
            let x = v * scale;
            if srgb {
                core::texture::srgb_to_linear(x as f32)
            } else {
                x as f32
            }
        })
        .collect();
    Ok((shape[0], shape[1], data))
}

#[pymethods]
impl PyEnvironment {
    #[new]
    #[pyo3(signature = (array, rotation=0.0, intensity=1.0, srgb=false, *, path=None))]
    fn new(
        array: &Bound<'_, PyAny>,
        rotation: f64,
        intensity: f64,
        srgb: bool,
        path: Option<std::path::PathBuf>,
    ) -> PyResult<Self> {
        let (h, w, data) = texels(array, srgb)?;
        let inner = crate::errors::no_panic("Environment", || {
            core::Environment::new(&data, h, w, rotation as f32, intensity as f32)
        })?
        .map_err(to_py)?;
        Ok(PyEnvironment { inner, path })
    }

    /// The file the image was read from (None for an array).
    #[getter]
    fn path(&self) -> Option<std::path::PathBuf> {
        self.path.clone()
    }

    /// Pickle support: rebuilt from its linear float32 texels, rotation and intensity.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let args = (
            self.array(py),
            self.inner.rotation() as f64,
            self.inner.intensity() as f64,
        );
        let cls = py.get_type::<Self>();
        match &self.path {
            // The path is keyword-only: rebuilt through functools.partial.
            Some(p) => {
                let kwargs = PyDict::new(py);
                kwargs.set_item("path", p)?;
                let partial = py
                    .import("functools")?
                    .getattr("partial")?
                    .call((cls,), Some(&kwargs))?;
                (partial, args).into_pyobject(py)
            }
            None => (cls.into_any(), args).into_pyobject(py),
        }
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    /// The texels as an (H, 2H, 3) float32 array (linear, before the intensity).
    #[getter]
    fn array<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f32>> {
        let (h, w) = (self.inner.height(), self.inner.width());
        let flat: Vec<f32> = self
            .inner
            .texels()
            .iter()
            .flat_map(|t| t.to_array())
            .collect();
        let a = numpy::ndarray::Array3::from_shape_vec((h, w, 3), flat).expect("h*w*3 texels");
        numpy::IntoPyArray::into_pyarray(a, py)
    }

    /// Rotation about +y in degrees.
    #[getter]
    fn rotation(&self) -> f32 {
        self.inner.rotation()
    }

    /// The factor every looked-up value is multiplied by.
    #[getter]
    fn intensity(&self) -> f32 {
        self.inner.intensity()
    }

    /// (height, width) in texels.
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.inner.height(), self.inner.width())
    }

    /// The colour seen along each direction of `directions` (an (..., 3) array of any
    /// lengths), as reflections read it: float32 (..., 3).
    fn sample<'py>(
        &self,
        py: Python<'py>,
        directions: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let np = py.import("numpy")?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("dtype", "float32")?;
        let a = np.call_method("ascontiguousarray", (directions,), Some(&kwargs))?;
        let shape: Vec<usize> = a.getattr("shape")?.extract()?;
        if shape.last() != Some(&3) {
            return Err(value_error(
                "directions",
                format!("directions must have shape (..., 3), got {shape:?}"),
            ));
        }
        let ro: PyReadonlyArrayDyn<f32> = a.extract()?;
        let d = ro
            .as_slice()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let out: Vec<f32> = d
            .chunks_exact(3)
            .flat_map(|c| {
                self.inner
                    .sample(glam::Vec3::new(c[0], c[1], c[2]))
                    .to_array()
            })
            .collect();
        let flat = numpy::IntoPyArray::into_pyarray(out, py);
        flat.call_method1("reshape", (PyTuple::new(py, shape)?,))
    }

    fn __repr__(&self) -> String {
        format!(
            "Environment(shape=({}, {}, 3), rotation={}, intensity={})",
            self.inner.height(),
            self.inner.width(),
            self.inner.rotation(),
            self.inner.intensity()
        )
    }
}
