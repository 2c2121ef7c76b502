//! `Environment`: an image of the light from every direction (equirectangular, or six
//! cube faces).

use numpy::PyReadonlyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use shadelab_raster as core;

use crate::errors::{to_py, type_error, value_error};

/// An equirectangular (latitude–longitude) environment: an (H, 2H, 3) float32/float64
/// (linear, HDR allowed) or uint8 array (divided by 255, or sRGB-decoded with `srgb=True`).
/// A unit direction d maps to u = 0.5 + atan2(d.x, -d.z)/(2 pi), v = acos(d.y)/pi: column
/// u*W, row v*H (in float32: u and v within 3e-7 of the exact values), so row 0 looks
/// straight up (+y) and the centre column along -z; sampled bilinearly, wrapping in u. `rotation` turns it about +y (degrees; positive turns what
/// was seen along -z toward -x); `intensity` scales every value. Six cube faces:
/// `Environment.from_cube`.
#[pyclass(name = "Environment", module = "shadelab_rs._core", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyEnvironment {
    pub inner: core::Environment,
    /// The files it was read from (`sl.load_environment`: one image, or six cube faces),
    /// written to scene files.
    pub path: Option<Vec<std::path::PathBuf>>,
}

/// The texels of one image: (height, width, linear RGB values). `field` names the
/// argument in errors, `needs` what it must be.
fn texels(
    obj: &Bound<'_, PyAny>,
    srgb: bool,
    field: &str,
    needs: &str,
) -> PyResult<(usize, usize, Vec<f32>)> {
    let (arr, dtype, shape) = crate::convert::image_array(obj, needs)?;
    let scale = match dtype.as_str() {
        "uint8" => 1.0 / 255.0,
        "float32" | "float64" => 1.0,
        _ => {
            return Err(type_error(
                field,
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
        return Err(value_error(field, format!("{needs}, got shape {shape:?}")));
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
        let (h, w, data) = texels(
            array,
            srgb,
            "array",
            "an environment needs an (H, 2H, 3) array",
        )?;
        let inner = crate::errors::no_panic("Environment", || {
            core::Environment::new(&data, h, w, rotation as f32, intensity as f32)
        })?
        .map_err(to_py)?;
        Ok(PyEnvironment {
            inner,
            path: path.map(|p| vec![p]),
        })
    }

    /// An environment from six square cube faces of one size, in the OpenGL cube-map
    /// convention: `faces` a sequence (or an (6, N, N, 3) array) in the order +X, -X, +Y,
    /// -Y, +Z, -Z, or a dict with the keys "+x", "-x", "+y", "-y", "+z", "-z"; each an
    /// (N, N, 3) array as for `Environment` (float linear, HDR allowed, or uint8). A
    /// direction's major axis picks the face; (sc, tc, ma) = (-z, -y, x) on +X, (z, -y, x)
    /// on -X, (x, z, y) on +Y, (x, -z, y) on -Y, (x, -y, z) on +Z, (-x, -y, z) on -Z, and
    /// s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2 are read at column s*N, row t*N (row 0 the
    /// image's first row). Bilinear, seamless across faces. `rotation`, `intensity` and
    /// `srgb` as for `Environment`; `paths`: the six files (see `load_environment`).
    #[staticmethod]
    #[pyo3(signature = (faces, rotation=0.0, intensity=1.0, srgb=false, *, paths=None))]
    fn from_cube(
        faces: &Bound<'_, PyAny>,
        rotation: f64,
        intensity: f64,
        srgb: bool,
        paths: Option<Vec<std::path::PathBuf>>,
    ) -> PyResult<Self> {
        let faces = cube_faces(faces)?;
        let mut data = Vec::new();
        let mut size = 0;
        for (k, face) in faces.iter().enumerate() {
            let name = core::FACE_NAMES[k];
            let needs = format!("cube face {name} needs an (N, N, 3) array");
            let (h, w, texels) = texels(face, srgb, "faces", &needs)?;
            if h != w {
                return Err(value_error(
                    "faces",
                    format!("cube face {name} must be square, got {h}x{w}"),
                ));
            }
            if k > 0 && h != size {
                return Err(value_error(
                    "faces",
                    format!(
                        "cube faces must all have one size: +x is {size}x{size}, {name} is {h}x{w}"
                    ),
                ));
            }
            size = h;
            data.extend(texels);
        }
        if let Some(p) = &paths {
            if p.len() != 6 {
                return Err(value_error(
                    "paths",
                    format!("a cube environment has 6 face files, got {}", p.len()),
                ));
            }
        }
        let inner = crate::errors::no_panic("Environment", || {
            core::Environment::cube(&data, size, rotation as f32, intensity as f32)
        })?
        .map_err(to_py)?;
        Ok(PyEnvironment { inner, path: paths })
    }

    /// "equirectangular" or "cube".
    #[getter]
    fn layout(&self) -> &'static str {
        match self.inner.layout() {
            core::EnvironmentLayout::Equirectangular => "equirectangular",
            core::EnvironmentLayout::Cube => "cube",
        }
    }

    /// The file the equirectangular image was read from (None for an array or a cube).
    #[getter]
    fn path(&self) -> Option<std::path::PathBuf> {
        match self.path.as_deref() {
            Some([p]) => Some(p.clone()),
            _ => None,
        }
    }

    /// The six files the cube faces were read from, +X, -X, +Y, -Y, +Z, -Z (None for
    /// arrays or an equirectangular image).
    #[getter]
    fn face_paths(&self) -> Option<Vec<std::path::PathBuf>> {
        self.path.clone().filter(|p| p.len() == 6)
    }

    /// Pickle support: rebuilt from its linear float32 texels, rotation and intensity.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let args = (
            self.array(py),
            self.inner.rotation() as f64,
            self.inner.intensity() as f64,
        );
        let cube = self.inner.layout() == core::EnvironmentLayout::Cube;
        let cls = py.get_type::<Self>();
        let make = if cube {
            cls.getattr("from_cube")?
        } else {
            cls.into_any()
        };
        match &self.path {
            // The paths are keyword-only: rebuilt through functools.partial.
            Some(p) => {
                let kwargs = PyDict::new(py);
                if cube {
                    kwargs.set_item("paths", p)?;
                } else {
                    kwargs.set_item("path", &p[0])?;
                }
                let partial = py
                    .import("functools")?
                    .getattr("partial")?
                    .call((make,), Some(&kwargs))?;
                (partial, args).into_pyobject(py)
            }
            None => (make, args).into_pyobject(py),
        }
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    /// The texels as float32 (linear, before the intensity): (H, 2H, 3) for an
    /// equirectangular image, (6, N, N, 3) for a cube (+X, -X, +Y, -Y, +Z, -Z).
    #[getter]
    fn array<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let (h, w) = (self.inner.height(), self.inner.width());
        let flat: Vec<f32> = self
            .inner
            .texels()
            .iter()
            .flat_map(|t| t.to_array())
            .collect();
        let shape = if self.inner.layout() == core::EnvironmentLayout::Cube {
            vec![6, h, w, 3]
        } else {
            vec![h, w, 3]
        };
        let a = numpy::ndarray::ArrayD::from_shape_vec(shape, flat).expect("texels");
        numpy::IntoPyArray::into_pyarray(a, py).into_any()
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

    /// (height, width) in texels (a cube: one face's).
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
        let (h, w) = (self.inner.height(), self.inner.width());
        let shape = match self.inner.layout() {
            core::EnvironmentLayout::Cube => format!("cube, faces=({h}, {w}, 3)"),
            core::EnvironmentLayout::Equirectangular => format!("shape=({h}, {w}, 3)"),
        };
        format!(
            "Environment({shape}, rotation={}, intensity={})",
            self.inner.rotation(),
            self.inner.intensity()
        )
    }
}

/// The six faces of `faces` in the order +X, -X, +Y, -Y, +Z, -Z: from a dict by the keys
/// "+x" ... "-z", or from any sequence of six.
fn cube_faces<'py>(faces: &Bound<'py, PyAny>) -> PyResult<Vec<Bound<'py, PyAny>>> {
    if let Ok(d) = faces.cast::<PyDict>() {
        let mut out = Vec::with_capacity(6);
        for name in core::FACE_NAMES {
            match d.get_item(name)? {
                Some(v) => out.push(v),
                None => {
                    return Err(value_error(
                        "faces",
                        format!(
                            "cube faces need the keys '+x', '-x', '+y', '-y', '+z', '-z'; \
                             '{name}' is missing"
                        ),
                    ))
                }
            }
        }
        if d.len() != 6 {
            return Err(value_error(
                "faces",
                format!(
                    "cube faces need exactly the keys '+x', '-x', '+y', '-y', '+z', '-z', got {} keys",
                    d.len()
                ),
            ));
        }
        return Ok(out);
    }
    let items: Vec<Bound<'py, PyAny>> = faces
        .try_iter()
        .map_err(|_| {
            type_error(
                "faces",
                "cube faces must be a sequence of six arrays (+x, -x, +y, -y, +z, -z) or a dict",
            )
        })?
        .collect::<PyResult<_>>()?;
    if items.len() != 6 {
        return Err(value_error(
            "faces",
            format!(
                "a cube environment needs 6 faces (+x, -x, +y, -y, +z, -z), got {}",
                items.len()
            ),
        ));
    }
    Ok(items)
}
