//! Wavefront OBJ (+ MTL) loading through tobj.
//!
//! Polygons are triangulated (fan), positions/normals/UVs are re-indexed to one index per
//! vertex, and `Ka`/`Kd`/`Ks`/`Ns` from the MTL file become [`Material`]s. Recovery rules:
//! a missing or unreadable MTL file leaves the parts without material (geometry still
//! loads); normals are used only when every vertex of a part has one, otherwise they are
//! generated; points and lines are ignored. Parse errors name the file and, where a line can
//! be found, the line.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};

use crate::error::{RasterError, Result};
use crate::material::Material;
use crate::mesh::Mesh;

/// One `o`/`g` group of an OBJ file.
#[derive(Debug)]
pub struct ObjPart {
    /// The group name from the file.
    pub name: String,
    /// Its triangles.
    pub mesh: Mesh,
    /// Its MTL material, if the file named one that could be loaded.
    pub material: Option<Material>,
}

/// Loads every part of an OBJ file.
pub fn load_obj_parts(path: impl AsRef<Path>) -> Result<Vec<ObjPart>> {
    let path = path.as_ref();
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => RasterError::NotFound(path.to_path_buf()),
        _ => RasterError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        },
    })?;
    if meta.is_dir() {
        return Err(RasterError::Io {
            path: path.to_path_buf(),
            message: "is a directory".into(),
        });
    }
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, materials) = tobj::load_obj(path, &options).map_err(|e| convert_error(path, e))?;
    let materials = materials.unwrap_or_default();
    let mut parts = Vec::new();
    for m in models {
        let mesh = &m.mesh;
        if mesh.indices.is_empty() {
            continue;
        }
        let positions: Vec<Vec3> = mesh
            .positions
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        let indices: Vec<[u32; 3]> = mesh
            .indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let normals = (mesh.normals.len() == mesh.positions.len()).then(|| {
            mesh.normals
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
                .collect()
        });
        let uvs = (mesh.texcoords.len() / 2 == positions.len() && !mesh.texcoords.is_empty()).then(
            || {
                mesh.texcoords
                    .chunks_exact(2)
                    .map(|c| Vec2::new(c[0], c[1]))
                    .collect()
            },
        );
        let built =
            Mesh::new(positions, indices, normals, uvs).map_err(|e| RasterError::Parse {
                path: path.to_path_buf(),
                line: None,
                message: format!("group '{}': {e}", m.name),
            })?;
        let material = mesh
            .material_id
            .and_then(|i| materials.get(i))
            .map(|mtl| material_from_mtl(path, mtl))
            .transpose()?;
        parts.push(ObjPart {
            name: m.name,
            mesh: built,
            material,
        });
    }
    if parts.is_empty() {
        return Err(RasterError::Parse {
            path: path.to_path_buf(),
            line: None,
            message: "the file contains no triangles".into(),
        });
    }
    Ok(parts)
}

/// Loads an OBJ file as one mesh (all parts merged, in file order).
pub fn load_obj(path: impl AsRef<Path>) -> Result<Mesh> {
    let parts = load_obj_parts(path)?;
    merge_parts(parts)
}

fn merge_parts(mut parts: Vec<ObjPart>) -> Result<Mesh> {
    if parts.len() == 1 {
        return Ok(parts.pop().expect("one part").mesh);
    }
    let all_normals = parts.iter().all(|p| p.mesh.given_normals().is_some());
    let all_uvs = parts.iter().all(|p| p.mesh.uvs().is_some());
    let (mut pos, mut idx, mut nrm, mut uv) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for p in &parts {
        let base = pos.len() as u32;
        pos.extend_from_slice(p.mesh.positions());
        idx.extend(p.mesh.indices().iter().map(|t| t.map(|i| i + base)));
        if all_normals {
            nrm.extend_from_slice(p.mesh.given_normals().unwrap_or_default());
        }
        if all_uvs {
            uv.extend_from_slice(p.mesh.uvs().unwrap_or_default());
        }
    }
    Mesh::new(pos, idx, all_normals.then_some(nrm), all_uvs.then_some(uv))
}

fn material_from_mtl(path: &Path, m: &tobj::Material) -> Result<Material> {
    let d = Material::default();
    let v = |c: Option<[f32; 3]>, default: Vec3| c.map(Vec3::from_array).unwrap_or(default);
    Material::new(
        v(m.ambient, d.ambient),
        v(m.diffuse, d.diffuse),
        v(m.specular, d.specular),
        m.shininess.unwrap_or(d.shininess),
    )
    .map_err(|e| RasterError::Parse {
        path: path.to_path_buf(),
        line: None,
        message: format!("material '{}': {e}", m.name),
    })
}

/// Maps a tobj error to ours, finding the offending line where the error kind allows.
fn convert_error(path: &Path, e: tobj::LoadError) -> RasterError {
    use tobj::LoadError as E;
    let p = path.to_path_buf();
    let (prefix, message): (Option<&str>, String) = match e {
        E::OpenFileFailed => {
            return RasterError::Io {
                path: p,
                message: "cannot open the file".into(),
            }
        }
        E::ReadError => (None, "read error (not a text OBJ file?)".into()),
        E::PositionParseError => (Some("v"), "malformed vertex position".into()),
        E::NormalParseError => (Some("vn"), "malformed vertex normal".into()),
        E::TexcoordParseError => (Some("vt"), "malformed texture coordinate".into()),
        E::FaceParseError => (Some("f"), "malformed face".into()),
        E::FaceVertexOutOfBounds => (Some("f"), "face vertex index out of range".into()),
        E::FaceTexCoordOutOfBounds => (Some("f"), "face texture index out of range".into()),
        E::FaceNormalOutOfBounds => (Some("f"), "face normal index out of range".into()),
        E::InvalidPolygon => (Some("f"), "face with fewer than 3 vertices".into()),
        other => (None, other.to_string()),
    };
    let line = prefix.and_then(|kw| find_bad_line(&p, kw));
    RasterError::Parse {
        path: p,
        line,
        message,
    }
}

/// Best effort: the first line starting with `keyword` that does not parse, by our own
/// light check of the same grammar (tobj does not report lines).
fn find_bad_line(path: &PathBuf, keyword: &str) -> Option<usize> {
    let text = std::fs::read(path).ok()?;
    let text = String::from_utf8_lossy(&text);
    let (mut nv, mut nvt, mut nvn) = (0i64, 0i64, 0i64);
    for (i, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        let Some(kw) = it.next() else { continue };
        let fields: Vec<&str> = it.collect();
        let floats_ok =
            |min: usize| fields.len() >= min && fields.iter().all(|f| f.parse::<f32>().is_ok());
        let bad = match kw {
            "v" => {
                nv += 1;
                !floats_ok(3)
            }
            "vt" => {
                nvt += 1;
                !floats_ok(1)
            }
            "vn" => {
                nvn += 1;
                !floats_ok(3)
            }
            "f" => fields.len() < 3 || !fields.iter().all(|f| face_ref_ok(f, nv, nvt, nvn)),
            _ => false,
        };
        if kw == keyword && bad {
            return Some(i + 1);
        }
    }
    None
}

fn face_ref_ok(f: &str, nv: i64, nvt: i64, nvn: i64) -> bool {
    let check = |s: Option<&str>, n: i64, required: bool| match s {
        None | Some("") => !required,
        Some(s) => s
            .parse::<i64>()
            .ok()
            .is_some_and(|i| (i > 0 && i <= n) || (i < 0 && -i <= n)),
    };
    let mut parts = f.split('/');
    check(parts.next(), nv, true)
        && check(parts.next(), nvt, false)
        && check(parts.next(), nvn, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("shadelab-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn loads_quads_and_negative_indices() {
        let p = write(
            "quad.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\n",
        );
        let m = load_obj(&p).unwrap();
        assert_eq!(m.triangle_count(), 2);
        assert_eq!(m.positions().len(), 4);
    }

    #[test]
    fn errors_name_file_and_line() {
        let p = write("bad.obj", "v 0 0 0\nv 1 0 0\nv 1 x 0\nf 1 2 3\n");
        let e = load_obj(&p).unwrap_err();
        assert!(matches!(e, RasterError::Parse { line: Some(3), .. }), "{e}");
        assert!(e.to_string().contains("bad.obj:3"), "{e}");
        let p = write("oob.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 7\n");
        let e = load_obj(&p).unwrap_err();
        assert!(matches!(e, RasterError::Parse { line: Some(4), .. }), "{e}");
        let e = load_obj(write("empty.obj", "")).unwrap_err();
        assert!(e.to_string().contains("no triangles"), "{e}");
        let e = load_obj("/definitely/not/here.obj").unwrap_err();
        assert!(matches!(e, RasterError::NotFound(_)));
    }

    #[test]
    fn non_finite_values_in_the_file_are_errors_naming_the_group() {
        let p = write(
            "nan.obj",
            "o broken\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn nan 0 1\nvn 0 0 1\nvn 0 0 1\nf 1//1 2//2 3//3\n",
        );
        let e = load_obj(&p).unwrap_err();
        assert!(matches!(e, RasterError::Parse { .. }), "{e}");
        let msg = e.to_string();
        assert!(
            msg.contains("nan.obj") && msg.contains("broken") && msg.contains("normal"),
            "{msg}"
        );
        let p = write("inf.obj", "v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n");
        let msg = load_obj(&p).unwrap_err().to_string();
        assert!(
            msg.contains("vertex 1") && msg.contains("non-finite"),
            "{msg}"
        );
    }

    #[test]
    fn reads_mtl_and_tolerates_missing_mtl() {
        write(
            "m.mtl",
            "newmtl shiny\nKa 0.1 0.2 0.3\nKd 0.4 0.5 0.6\nKs 1 1 1\nNs 64\n",
        );
        let p = write(
            "withmtl.obj",
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl shiny\nf 1 2 3\n",
        );
        let parts = load_obj_parts(&p).unwrap();
        let m = parts[0].material.unwrap();
        assert_eq!(m.diffuse, Vec3::new(0.4, 0.5, 0.6));
        assert_eq!(m.shininess, 64.0);
        let p = write(
            "nomtl.obj",
            "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n",
        );
        let parts = load_obj_parts(&p).unwrap();
        assert!(parts[0].material.is_none());
    }
}
