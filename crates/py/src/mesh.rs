//! `Mesh` and OBJ loading.

use std::path::PathBuf;
use std::sync::Arc;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use shadelab_raster as core;

use crate::convert;
use crate::errors::{to_py, value_error};
use crate::material::PyMaterial;

/// A validated triangle mesh (shared, immutable).
#[pyclass(name = "Mesh", module = "shadelab_rs._core", frozen)]
pub struct PyMesh {
    pub inner: Arc<core::Mesh>,
}

fn rows3<'py>(py: Python<'py>, v: &[glam::Vec3]) -> Bound<'py, PyArray2<f32>> {
    let flat: Vec<f32> = v.iter().flat_map(|p| p.to_array()).collect();
    Array2::from_shape_vec((v.len(), 3), flat)
        .expect("length matches")
        .into_pyarray(py)
}

#[pymethods]
impl PyMesh {
    /// Pickle support: `_core._restore("Mesh", state)` rebuilds this value exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        crate::pickle::reduce(py, "Mesh", crate::pickle::mesh_state(py, &self.inner)?)
    }

    fn __copy__(&self) -> Self {
        // Immutable: a copy may share the buffers.
        PyMesh {
            inner: self.inner.clone(),
        }
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        // Immutable: a copy may share the buffers.
        PyMesh {
            inner: self.inner.clone(),
        }
    }
    #[new]
    #[pyo3(signature = (vertices, faces, normals=None, uvs=None, colors=None))]
    fn new(
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        normals: Option<&Bound<'_, PyAny>>,
        uvs: Option<&Bound<'_, PyAny>>,
        colors: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let positions = convert::vec3_rows(vertices, "vertices")?;
        let indices = convert::faces(faces, positions.len())?;
        let normals = normals
            .map(|n| convert::vec3_rows(n, "normals"))
            .transpose()?;
        let uvs = uvs.map(|u| convert::vec2_rows(u, "uvs")).transpose()?;
        let colors = colors.map(convert::colors).transpose()?;
        let mut mesh = core::Mesh::new(positions, indices, normals, uvs).map_err(to_py)?;
        if let Some(c) = colors {
            mesh = mesh
                .with_colors(c)
                .map_err(|e| crate::errors::with_field(to_py(e), "colors"))?;
        }
        Ok(PyMesh {
            inner: Arc::new(mesh),
        })
    }

    /// Per-vertex linear RGB colours as float32 (N, 3), or None.
    #[getter]
    fn colors<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f32>>> {
        self.inner.colors().map(|c| rows3(py, c))
    }

    /// Builds a mesh from a `trimesh.Trimesh` (its vertices, faces and, when present,
    /// UVs). Unless `use_normals`, vertex normals are made on the welded positions with the
    /// crease angle `crease_angle` (degrees; None: no creases), as `shadelab_rs.load_mesh`.
    #[classmethod]
    #[pyo3(signature = (tm, use_normals=false, crease_angle=Some(60.0)),
           text_signature = "($cls, tm, use_normals=False, crease_angle=60.0)")]
    fn from_trimesh(
        _cls: &Bound<'_, pyo3::types::PyType>,
        tm: &Bound<'_, PyAny>,
        use_normals: bool,
        crease_angle: Option<f64>,
    ) -> PyResult<Self> {
        // Welding and crease-angle normals are array work on trimesh data: Python does it.
        let mesh = tm
            .py()
            .import("shadelab_rs.io")?
            .getattr("mesh_from_trimesh")?
            .call1((tm, use_normals, crease_angle))?;
        Ok(PyMesh {
            inner: mesh.extract::<PyRef<'_, PyMesh>>()?.inner.clone(),
        })
    }

    /// A unit UV sphere at the origin with exact normals: `rings` latitude bands (>= 2) and
    /// `segments` longitude segments (>= 3), 2·segments·(rings − 1) triangles.
    #[staticmethod]
    #[pyo3(signature = (rings=16, segments=32))]
    fn uv_sphere(rings: i64, segments: i64) -> PyResult<Self> {
        if rings < 2 || segments < 3 {
            return Err(value_error(
                if rings < 2 { "rings" } else { "segments" },
                format!("uv_sphere needs rings >= 2 and segments >= 3, got rings={rings}, segments={segments}"),
            ));
        }
        if rings.saturating_mul(segments) > 50_000_000 {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "uv_sphere with rings={rings}, segments={segments} would have more than 50 million vertices"
            )));
        }
        Ok(PyMesh {
            inner: Arc::new(core::primitives::uv_sphere(rings as u32, segments as u32)),
        })
    }

    /// A unit sphere from a regular icosahedron subdivided `subdivisions` times (0 to 10):
    /// 20·4**subdivisions nearly equal triangles with exact normals.
    #[staticmethod]
    #[pyo3(signature = (subdivisions=3))]
    fn ico_sphere(subdivisions: i64) -> PyResult<Self> {
        let max = core::primitives::MAX_ICO_SUBDIVISIONS;
        if !(0..=max as i64).contains(&subdivisions) {
            return Err(value_error(
                "subdivisions",
                format!("ico_sphere needs 0 <= subdivisions <= {max}, got {subdivisions}"),
            ));
        }
        Ok(PyMesh {
            inner: Arc::new(core::primitives::ico_sphere(subdivisions as u32)),
        })
    }

    /// The cube [-1, 1]³: 24 vertices (4 per face) with exact face normals and UVs.
    #[staticmethod]
    fn cube() -> Self {
        PyMesh {
            inner: Arc::new(core::primitives::cube()),
        }
    }

    /// The square [-1, 1]² in the xz plane at y = 0, facing +y (two triangles, with UVs).
    #[staticmethod]
    fn plane() -> Self {
        PyMesh {
            inner: Arc::new(core::primitives::plane()),
        }
    }

    /// Vertex positions, float32 (N, 3).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        rows3(py, self.inner.positions())
    }

    /// Triangles, uint32 (M, 3).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<u32>> {
        let flat: Vec<u32> = self.inner.indices().iter().flatten().copied().collect();
        Array2::from_shape_vec((self.inner.triangle_count(), 3), flat)
            .expect("length matches")
            .into_pyarray(py)
    }

    /// The vertex normals used for shading (given, or generated), float32 (N, 3).
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        rows3(py, self.inner.vertex_normals())
    }

    /// Whether normals were given (True) or are generated (False).
    #[getter]
    fn has_normals(&self) -> bool {
        self.inner.given_normals().is_some()
    }

    /// Texture coordinates, float32 (N, 2), or None.
    #[getter]
    fn uvs<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f32>>> {
        self.inner.uvs().map(|uv| {
            let flat: Vec<f32> = uv.iter().flat_map(|p| p.to_array()).collect();
            Array2::from_shape_vec((uv.len(), 2), flat)
                .expect("length matches")
                .into_pyarray(py)
        })
    }

    /// The same mesh with vertex normals recomputed with a crease angle (degrees, 0 to
    /// 180; None: every edge smooth), vertices split where the faces around them turn by
    /// more (see the user guide, "Normals with a crease angle").
    #[pyo3(signature = (crease_angle=Some(60.0)),
           text_signature = "($self, crease_angle=60.0)")]
    fn with_normals(&self, py: Python<'_>, crease_angle: Option<f64>) -> PyResult<Self> {
        let mesh = py
            .detach(|| self.inner.with_normals(crease_angle))
            .map_err(to_py)?;
        Ok(PyMesh {
            inner: Arc::new(mesh),
        })
    }

    /// Number of vertices.
    #[getter]
    fn n_vertices(&self) -> usize {
        self.inner.positions().len()
    }

    /// Number of triangles.
    #[getter]
    fn n_faces(&self) -> usize {
        self.inner.triangle_count()
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh(n_vertices={}, n_faces={}, normals={}, uvs={})",
            self.inner.positions().len(),
            self.inner.triangle_count(),
            if self.has_normals() {
                "given"
            } else {
                "generated"
            },
            self.inner.uvs().is_some()
        )
    }
}

/// Loads an OBJ file as one mesh (all groups merged).
#[pyfunction]
pub fn load_obj(py: Python<'_>, path: PathBuf) -> PyResult<PyMesh> {
    let mesh = py
        .detach(|| crate::errors::no_panic("load_obj", || core::load_obj(&path)))?
        .map_err(to_py)?;
    Ok(PyMesh {
        inner: Arc::new(mesh),
    })
}

/// Loads every group of an OBJ file as `(name, Mesh, Material | None)` tuples.
#[pyfunction]
pub fn load_obj_parts<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Vec<Bound<'py, PyTuple>>> {
    let parts = py
        .detach(|| crate::errors::no_panic("load_obj_parts", || core::load_obj_parts(&path)))?
        .map_err(to_py)?;
    parts
        .into_iter()
        .map(|p| {
            let mesh = Py::new(
                py,
                PyMesh {
                    inner: Arc::new(p.mesh),
                },
            )?;
            let maps = p.maps;
            let mat = p
                .material
                .map(|m| Py::new(py, PyMaterial { inner: m, maps }))
                .transpose()?;
            PyTuple::new(
                py,
                [
                    p.name.into_pyobject(py)?.into_any(),
                    mesh.into_any().into_bound(py),
                    mat.into_pyobject(py)?.into_any(),
                ],
            )
        })
        .collect()
}
