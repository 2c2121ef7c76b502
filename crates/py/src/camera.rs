//! `Camera`.

use pyo3::prelude::*;
use shadelab_raster as core;

use crate::convert;
use crate::errors::to_py;

/// A look-at camera with perspective, pinhole (pixel intrinsics) or orthographic projection
/// (OpenGL conventions).
#[pyclass(name = "Camera", module = "shadelab_rs._core", frozen)]
#[derive(Clone)]
pub struct PyCamera {
    /// The camera; when a plane is fitted, `inner` holds a placeholder for it (0.1 or 100,
    /// moved so that near < far) until `render` fits it to the scene.
    pub inner: core::Camera,
    /// Whether `render` fits the near plane to the scene's bounds (near=None was given).
    pub fit_near: bool,
    /// Whether `render` fits the far plane to the scene's bounds (far=None was given).
    pub fit_far: bool,
}

impl PyCamera {
    /// A camera built by `make(near, far)`, whose planes given as None are placeholders
    /// ([`planes`]) that `render` fits to the scene's bounds.
    pub(crate) fn fitted_later(
        near: Option<f64>,
        far: Option<f64>,
        perspective: bool,
        make: impl FnOnce(f64, f64) -> core::Result<core::Camera>,
    ) -> PyResult<Self> {
        let (n, f) = planes(near, far, perspective);
        Ok(PyCamera {
            inner: make(n, f).map_err(to_py)?,
            fit_near: near.is_none(),
            fit_far: far.is_none(),
        })
    }
}

/// Placeholder near/far planes for the ones left to `render` to fit, keeping the given one
/// valid: a perspective near must stay > 0 and below far.
pub(crate) fn planes(near: Option<f64>, far: Option<f64>, perspective: bool) -> (f64, f64) {
    match (near, far) {
        (Some(n), Some(f)) => (n, f),
        (Some(n), None) => (
            n,
            if n.is_finite() {
                (n.abs() * 1e3).max(100.0)
            } else {
                n
            },
        ),
        (None, Some(f)) if perspective => (
            if f.is_finite() {
                (f * 1e-3).min(0.1)
            } else {
                0.1
            },
            f,
        ),
        (None, Some(f)) => (
            if f.is_finite() {
                f - 100.0_f64.max(f.abs())
            } else {
                0.1
            },
            f,
        ),
        (None, None) => (0.1, 100.0),
    }
}

fn up_or_y(up: Option<&Bound<'_, PyAny>>) -> PyResult<glam::DVec3> {
    up.map_or(Ok(glam::DVec3::Y), |u| convert::dvec3(u, "up"))
}

#[pymethods]
impl PyCamera {
    /// Pickle support: `_core._restore("Camera", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "Camera", crate::pickle::camera_state(self))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    /// Perspective camera; `fov_y` is the full vertical angle in degrees.
    /// `near` / `far` None (the default): fitted to the scene's bounds at render time.
    #[staticmethod]
    #[pyo3(signature = (eye, target, up=None, fov_y=45.0, near=None, far=None))]
    fn look_at(
        eye: &Bound<'_, PyAny>,
        target: &Bound<'_, PyAny>,
        up: Option<&Bound<'_, PyAny>>,
        fov_y: f64,
        near: Option<f64>,
        far: Option<f64>,
    ) -> PyResult<Self> {
        let (eye, target, up) = (
            convert::dvec3(eye, "eye")?,
            convert::dvec3(target, "target")?,
            up_or_y(up)?,
        );
        PyCamera::fitted_later(near, far, true, |n, f| {
            core::Camera::look_at(eye, target, up, fov_y, n, f)
        })
    }

    /// Pinhole camera from pixel intrinsics K = [[fx, skew, cx], [0, fy, cy], [0, 0, 1]] of a
    /// `width` x `height` image (computer-vision convention: x right, y down, pixel centres
    /// at half-integers); the optical axis passes through `target`.
    #[staticmethod]
    #[pyo3(signature = (
        eye, target, up=None, *, fx, fy, cx, cy, width, height, skew=0.0, near=None, far=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn from_intrinsics(
        eye: &Bound<'_, PyAny>,
        target: &Bound<'_, PyAny>,
        up: Option<&Bound<'_, PyAny>>,
        fx: f64,
        fy: f64,
        cx: f64,
        cy: f64,
        width: i64,
        height: i64,
        skew: f64,
        near: Option<f64>,
        far: Option<f64>,
    ) -> PyResult<Self> {
        let size = |name: &str, v: i64| {
            u32::try_from(v).ok().filter(|&v| v >= 1).ok_or_else(|| {
                crate::errors::value_error(
                    name,
                    format!(
                        "{name} (the intrinsics' reference image size) must be an integer in \
                         [1, 2^32), got {v}"
                    ),
                )
            })
        };
        let k = core::Intrinsics {
            fx,
            fy,
            cx,
            cy,
            skew,
            width: size("width", width)?,
            height: size("height", height)?,
        };
        let (eye, target, up) = (
            convert::dvec3(eye, "eye")?,
            convert::dvec3(target, "target")?,
            up_or_y(up)?,
        );
        PyCamera::fitted_later(near, far, true, |n, f| {
            core::Camera::from_intrinsics(eye, target, up, k, n, f)
        })
    }

    /// Orthographic camera; `height` is the view's vertical extent in world units.
    #[staticmethod]
    #[pyo3(signature = (eye, target, up=None, height=2.0, near=None, far=None))]
    fn orthographic(
        eye: &Bound<'_, PyAny>,
        target: &Bound<'_, PyAny>,
        up: Option<&Bound<'_, PyAny>>,
        height: f64,
        near: Option<f64>,
        far: Option<f64>,
    ) -> PyResult<Self> {
        let (eye, target, up) = (
            convert::dvec3(eye, "eye")?,
            convert::dvec3(target, "target")?,
            up_or_y(up)?,
        );
        PyCamera::fitted_later(near, far, false, |n, f| {
            core::Camera::orthographic(eye, target, up, height, n, f)
        })
    }

    /// Eye position.
    #[getter]
    fn eye(&self) -> (f64, f64, f64) {
        self.inner.eye().into()
    }

    /// Point looked at.
    #[getter]
    fn target(&self) -> (f64, f64, f64) {
        self.inner.target().into()
    }

    /// Up hint.
    #[getter]
    fn up(&self) -> (f64, f64, f64) {
        self.inner.up().into()
    }

    /// Near plane distance, or None when `render` fits it to the scene.
    #[getter]
    fn near(&self) -> Option<f64> {
        (!self.fit_near).then(|| self.inner.near())
    }

    /// Far plane distance, or None when `render` fits it to the scene.
    #[getter]
    fn far(&self) -> Option<f64> {
        (!self.fit_far).then(|| self.inner.far())
    }

    /// This camera with the near/far planes `render` would use for `scene` (the given ones
    /// kept, the others fitted to the scene's bounds).
    fn fitted(&self, scene: &crate::scene::PyScene) -> PyResult<Self> {
        Ok(Self {
            inner: crate::defaults::fit_planes(self, &scene.inner)?,
            fit_near: false,
            fit_far: false,
        })
    }

    /// The 4x4 world-to-eye matrix (OpenGL's gluLookAt), float64.
    fn view_matrix<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        crate::defaults::mat_to_numpy(py, self.inner.view_matrix())
    }

    /// The 4x4 eye-to-clip matrix for `aspect` = width / height (reversed-Z, depth range
    /// [0, 1]: near maps to 1, far to 0), float64. A pinhole camera's does not depend on
    /// `aspect` (its intrinsics scale with the render size).
    fn projection_matrix<'py>(
        &self,
        py: Python<'py>,
        aspect: f64,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "aspect must be finite and > 0, got {aspect}"
            )));
        }
        Ok(crate::defaults::mat_to_numpy(
            py,
            self.inner.projection_matrix(aspect),
        ))
    }

    /// "perspective", "pinhole" or "orthographic".
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner.projection() {
            core::Projection::Perspective { .. } => "perspective",
            core::Projection::Pinhole(_) => "pinhole",
            core::Projection::Orthographic { .. } => "orthographic",
        }
    }

    /// Vertical field of view in degrees (None for pinhole and orthographic).
    #[getter]
    fn fov_y(&self) -> Option<f64> {
        match self.inner.projection() {
            core::Projection::Perspective { fov_y } => Some(fov_y),
            _ => None,
        }
    }

    /// Vertical extent (None for perspective and pinhole).
    #[getter]
    fn height(&self) -> Option<f64> {
        match self.inner.projection() {
            core::Projection::Orthographic { height } => Some(height),
            _ => None,
        }
    }

    /// (fx, fy, cx, cy, skew, width, height) of a pinhole camera, else None.
    #[getter]
    #[allow(clippy::type_complexity)]
    fn intrinsics(&self) -> Option<(f64, f64, f64, f64, f64, u32, u32)> {
        match self.inner.projection() {
            core::Projection::Pinhole(k) => {
                Some((k.fx, k.fy, k.cx, k.cy, k.skew, k.width, k.height))
            }
            _ => None,
        }
    }

    fn __repr__(&self) -> String {
        let c = &self.inner;
        let (make, proj) = match c.projection() {
            core::Projection::Perspective { fov_y } => ("look_at", format!("fov_y={fov_y}")),
            core::Projection::Orthographic { height } => {
                ("orthographic", format!("height={height}"))
            }
            core::Projection::Pinhole(k) => (
                "from_intrinsics",
                format!(
                    "fx={}, fy={}, cx={}, cy={}, width={}, height={}, skew={}",
                    k.fx, k.fy, k.cx, k.cy, k.width, k.height, k.skew
                ),
            ),
        };
        let plane = |fit: bool, v: f64| {
            if fit {
                "None".to_string()
            } else {
                v.to_string()
            }
        };
        format!(
            "Camera.{make}(eye={:?}, target={:?}, up={:?}, {proj}, near={}, far={})",
            c.eye().to_array(),
            c.target().to_array(),
            c.up().to_array(),
            plane(self.fit_near, c.near()),
            plane(self.fit_far, c.far())
        )
    }
}
