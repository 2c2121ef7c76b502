//! Wavefront OBJ (+ MTL) loading through tobj.
//!
//! Polygons are triangulated (fan), positions/normals/UVs are re-indexed to one index per
//! distinct corner, and `Ka`/`Kd`/`Ks`/`Ns`/`Ke` from the MTL file become [`Material`]s.
//! Recovery rules: a missing, unreadable or malformed MTL file leaves the parts without
//! material (geometry still loads), except that its texture maps (`map_Kd`...: see
//! `mtl_maps`) must load: a missing or undecodable texture is an error naming the file and
//! the MTL line; normals are used only when every face corner of a group has one,
//! otherwise they are generated per OBJ position (shared across UV seams); points (`p`) and
//! lines (`l`) are ignored. A face (`f`) with fewer than three vertex references is an
//! error naming its line. Parse errors name the file and, where a line can be found, the
//! line.

use std::collections::HashMap;
use std::path::Path;

use glam::{Vec2, Vec3};

use crate::error::{RasterError, Result};
use crate::material::Material;
use crate::mesh::{generate_vertex_normals, Mesh};

/// One `o`/`g` group of an OBJ file.
#[derive(Debug)]
pub struct ObjPart {
    /// The group name from the file.
    pub name: String,
    /// Its triangles.
    pub mesh: Mesh,
    /// Its MTL material, if the file named one that could be loaded.
    pub material: Option<Material>,
    /// The MTL material's texture maps (`map_Kd`...), if it names any.
    pub maps: Option<std::sync::Arc<crate::texture::Maps>>,
}

/// Loads every part of an OBJ file. A `mtllib` file is looked up next to the OBJ file.
pub fn load_obj_parts(path: impl AsRef<Path>) -> Result<Vec<ObjPart>> {
    let path = path.as_ref();
    let io_error = |e: std::io::Error| match e.kind() {
        std::io::ErrorKind::NotFound => RasterError::NotFound(path.to_path_buf()),
        _ => RasterError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        },
    };
    let meta = std::fs::metadata(path).map_err(io_error)?;
    if meta.is_dir() {
        return Err(RasterError::Io {
            path: path.to_path_buf(),
            message: "is a directory".into(),
        });
    }
    let bytes = std::fs::read(path).map_err(io_error)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    parse_obj_parts(&bytes, path, |mtl| std::fs::read(dir.join(mtl)).ok())
}

/// Parses OBJ text held in memory into its parts, by the same rules as [`load_obj_parts`].
///
/// `path` only names the source in error messages. `read_mtl` is asked for the bytes of each
/// `mtllib` file (by the name the OBJ text gives); `None` means the file is missing or
/// unreadable, and the parts then load without material.
pub fn parse_obj_parts(
    bytes: &[u8],
    path: &Path,
    read_mtl: impl Fn(&Path) -> Option<Vec<u8>>,
) -> Result<Vec<ObjPart>> {
    if let Some((line, message)) = check_faces(bytes) {
        return Err(RasterError::Parse {
            path: path.to_path_buf(),
            line: Some(line),
            message,
        });
    }
    let options = tobj::LoadOptions {
        triangulate: true,
        // We build one index per (position, uv, normal) ourselves, so that generated normals
        // can be shared by every copy of an OBJ position (UV seams must not crease shading).
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // The map lines of each MTL file read (tobj keeps neither their options nor lines).
    let map_lines = std::cell::RefCell::new(Vec::new());
    let (models, materials) = tobj::load_obj_buf(
        &mut std::io::Cursor::new(bytes),
        &options,
        |mtl| match read_mtl(mtl) {
            // tobj 4.0.5 panics on a colour line with fewer than three numbers.
            Some(text) if has_short_color(&text) => Err(tobj::LoadError::MaterialParseError),
            Some(text) => {
                let file = path.parent().unwrap_or(Path::new("")).join(mtl);
                map_lines
                    .borrow_mut()
                    .push(crate::mtl_maps::scan(&text, &file).map(|m| (file, m)));
                tobj::load_mtl_buf(&mut std::io::Cursor::new(text))
            }
            None => Err(tobj::LoadError::OpenFileFailed),
        },
    )
    .map_err(|e| convert_error(path, bytes, e))?;
    let materials = materials.unwrap_or_default();
    // A malformed map line is an error even though a malformed MTL otherwise is not: a
    // texture the file asks for is never dropped silently.
    let map_lines = map_lines
        .into_inner()
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
    let mut texture_cache = HashMap::new();
    let mut parts = Vec::new();
    for m in models {
        let mesh = &m.mesh;
        if mesh.indices.is_empty() {
            continue;
        }
        let (positions, indices, normals, uvs, generated) = single_index(mesh);
        let built =
            Mesh::new(positions, indices, normals, uvs).map_err(|e| RasterError::Parse {
                path: path.to_path_buf(),
                line: None,
                message: format!("group '{}': {e}", m.name),
            })?;
        let built = if generated {
            built.with_generated_normals()
        } else {
            built
        };
        let mtl = mesh.material_id.and_then(|i| materials.get(i));
        let material = mtl.map(|mtl| material_from_mtl(path, mtl)).transpose()?;
        let mut maps = None;
        if let Some(mtl) = mtl {
            // The last MTL file that defines the material (as tobj merges them).
            if let Some((file, lines)) = map_lines
                .iter()
                .rev()
                .find_map(|(f, m)| m.get(&mtl.name).map(|l| (f, l)))
            {
                let dir = file.parent().unwrap_or(Path::new(""));
                let loaded = crate::mtl_maps::load_maps(lines, dir, file, &mut texture_cache)?;
                if built.uvs().is_none() {
                    return Err(RasterError::Parse {
                        path: path.to_path_buf(),
                        line: None,
                        message: format!(
                            "group '{}': material '{}' has texture maps but the group has no \
                             texture coordinates (vt)",
                            m.name, mtl.name
                        ),
                    });
                }
                maps = Some(std::sync::Arc::new(loaded));
            }
        }
        parts.push(ObjPart {
            name: m.name,
            mesh: built,
            material,
            maps,
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

/// Positions, triangles, normals, UVs, and whether the normals were generated.
type Arrays = (
    Vec<Vec3>,
    Vec<[u32; 3]>,
    Option<Vec<Vec3>>,
    Option<Vec<Vec2>>,
    bool,
);

/// One vertex per distinct (position, uv, normal) triple of a group's faces. UVs and normals
/// are kept only when every face corner has one. Without normals in the file, they are
/// generated per OBJ *position* by [`generate_vertex_normals`] and shared by all copies of
/// that position, so a UV seam (which splits vertices) does not show in the shading.
fn single_index(m: &tobj::Mesh) -> Arrays {
    let n = m.indices.len();
    let has_uv = m.texcoord_indices.len() == n && !m.texcoords.is_empty();
    let has_n = m.normal_indices.len() == n && !m.normals.is_empty();
    let pos = |i: u32| {
        let i = i as usize * 3;
        Vec3::new(m.positions[i], m.positions[i + 1], m.positions[i + 2])
    };
    let generated = (!has_n).then(|| {
        let all: Vec<Vec3> = (0..m.positions.len() as u32 / 3).map(pos).collect();
        let tris: Vec<[u32; 3]> = m
            .indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        generate_vertex_normals(&all, &tris)
    });
    let mut map: HashMap<(u32, u32, u32), u32> = HashMap::with_capacity(n);
    let (mut positions, mut normals, mut uvs) = (Vec::new(), Vec::new(), Vec::new());
    let mut corners = Vec::with_capacity(n);
    for k in 0..n {
        let p = m.indices[k];
        let t = if has_uv {
            m.texcoord_indices[k]
        } else {
            u32::MAX
        };
        let q = if has_n { m.normal_indices[k] } else { u32::MAX };
        let id = *map.entry((p, t, q)).or_insert_with(|| {
            positions.push(pos(p));
            if has_uv {
                let t = t as usize * 2;
                uvs.push(Vec2::new(m.texcoords[t], m.texcoords[t + 1]));
            }
            normals.push(match &generated {
                Some(g) => g[p as usize],
                None => {
                    let q = q as usize * 3;
                    Vec3::new(m.normals[q], m.normals[q + 1], m.normals[q + 2])
                }
            });
            positions.len() as u32 - 1
        });
        corners.push(id);
    }
    let indices = corners
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (
        positions,
        indices,
        Some(normals),
        has_uv.then_some(uvs),
        !has_n,
    )
}

/// Loads an OBJ file as one mesh (all parts merged, in file order).
pub fn load_obj(path: impl AsRef<Path>) -> Result<Mesh> {
    let parts = load_obj_parts(path)?;
    merge_parts(parts)
}

pub(crate) fn merge_parts(mut parts: Vec<ObjPart>) -> Result<Mesh> {
    if parts.len() == 1 {
        return Ok(parts.pop().expect("one part").mesh);
    }
    // Every OBJ part carries normals (from the file or generated per position).
    let generated = parts.iter().any(|p| p.mesh.given_normals().is_none());
    let all_uvs = parts.iter().all(|p| p.mesh.uvs().is_some());
    let (mut pos, mut idx, mut nrm, mut uv) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for p in &parts {
        let base = pos.len() as u32;
        pos.extend_from_slice(p.mesh.positions());
        idx.extend(p.mesh.indices().iter().map(|t| t.map(|i| i + base)));
        nrm.extend_from_slice(p.mesh.vertex_normals());
        if all_uvs {
            uv.extend_from_slice(p.mesh.uvs().unwrap_or_default());
        }
    }
    let mesh = Mesh::new(pos, idx, Some(nrm), all_uvs.then_some(uv))?;
    Ok(if generated {
        mesh.with_generated_normals()
    } else {
        mesh
    })
}

fn material_from_mtl(path: &Path, m: &tobj::Material) -> Result<Material> {
    let d = Material::default();
    let v = |c: Option<[f32; 3]>, default: Vec3| c.map(Vec3::from_array).unwrap_or(default);
    let (ka, kd, ks) = (
        v(m.ambient, d.ambient),
        v(m.diffuse, d.diffuse),
        v(m.specular, d.specular),
    );
    let ke = v(m.emissive, Vec3::ZERO);
    // `illum`: 0 is a constant colour Kd (no lighting), 1 is ambient + diffuse without
    // highlights, 2 and above (reflection, refraction, ... not modelled) the full model.
    let (ka, kd, ks, ke) = match m.illumination_model {
        Some(0) => (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, ke + kd),
        Some(1) => (ka, kd, Vec3::ZERO, ke),
        _ => (ka, kd, ks, ke),
    };
    // Optics: `d` (dissolve; `Tr` = 1 − d) is the opacity, `Ni` the index of refraction,
    // `illum` 3, 5 and 8 add a mirror of reflectance Ks (capped so that R + T ≤ 1).
    let tr = m
        .unknown_param
        .get("Tr")
        .and_then(|v| v.trim().parse::<f32>().ok());
    let opacity = m.dissolve.or(tr.map(|t| 1.0 - t)).unwrap_or(1.0);
    let transparency = if opacity.is_finite() {
        (1.0 - opacity).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let ior = m
        .optical_density
        .filter(|n| n.is_finite() && *n > 0.0)
        .unwrap_or(1.0);
    let reflectivity = match m.illumination_model {
        Some(3 | 5 | 8) => ks.clamp(Vec3::ZERO, Vec3::splat(1.0 - transparency)),
        _ => Vec3::ZERO,
    };
    Material::new(ka, kd, ks, m.shininess.unwrap_or(d.shininess))
        .and_then(|mat| mat.with_emission(ke))
        .and_then(|mat| mat.with_optics(reflectivity, transparency, ior, true, Vec3::ZERO))
        .map_err(|e| RasterError::Parse {
            path: path.to_path_buf(),
            line: None,
            message: format!("material '{}': {e}", m.name),
        })
}

/// Checks every face (`f`) line before tobj parses the file, returning the first problem as
/// (1-based line, message): fewer than three vertex references (tobj would read the line as
/// a point or a line element and drop it silently), a reference that does not parse, or an
/// index outside the elements defined so far. tobj's own range checks multiply the index
/// without overflow checks, so in release builds an index near ±2^63 could wrap onto a valid
/// element (found by fuzzing); checking here makes every index error exact and names its
/// line.
fn check_faces(bytes: &[u8]) -> Option<(usize, String)> {
    // Split as tobj does (`lines`, then Unicode `split_whitespace`); lossy decoding keeps the
    // lines before any non-UTF-8 one intact (tobj parses those before failing).
    let text = String::from_utf8_lossy(bytes);
    let (mut nv, mut nvt, mut nvn) = (0i64, 0i64, 0i64);
    for (i, line) in text.lines().enumerate() {
        let mut fields = line.split_whitespace();
        match fields.next() {
            Some("v") => nv += 1,
            Some("vt") => nvt += 1,
            Some("vn") => nvn += 1,
            Some("f") => {
                let refs: Vec<&str> = fields.collect();
                if refs.len() < 3 {
                    let n = refs.len();
                    return Some((
                        i + 1,
                        format!("face with {n} vertex indices; a face needs at least 3"),
                    ));
                }
                for r in refs {
                    if let Err(message) = face_ref(r, nv, nvt, nvn) {
                        return Some((i + 1, message));
                    }
                }
            }
            _ => {}
        }
    }
    None
}

/// Checks one `v`, `v/vt`, `v//vn` or `v/vt/vn` reference against the element counts.
fn face_ref(r: &str, nv: i64, nvt: i64, nvn: i64) -> std::result::Result<(), String> {
    let parts: Vec<&str> = r.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(format!(
            "malformed face: '{r}' (expected v, v/vt, v//vn or v/vt/vn)"
        ));
    }
    for (part, (n, what)) in parts
        .iter()
        .zip([(nv, "vertex"), (nvt, "texture"), (nvn, "normal")])
    {
        if part.is_empty() {
            continue;
        }
        let Ok(k) = part.parse::<i64>() else {
            return Err(format!(
                "malformed face: '{r}' ('{part}' is not an integer)"
            ));
        };
        if !((k > 0 && k <= n) || (k < 0 && k >= -n)) {
            return Err(format!(
                "face {what} index out of range: '{r}' refers to {k}, with {n} defined so far \
                 (indices are 1-based; negative ones count back from the last)"
            ));
        }
    }
    Ok(())
}

/// Whether an MTL text has a `Ka`/`Kd`/`Ks`/`Ke` line with fewer than three values: tobj's
/// `parse_float3` unwraps a conversion that then fails (a panic, found by fuzzing), so such
/// a file is treated as malformed before tobj sees it.
fn has_short_color(text: &[u8]) -> bool {
    // Split as tobj does (`lines`, then Unicode `split_whitespace`). tobj reads line by line
    // and parses every line before the first one that is not UTF-8, so check those too
    // (fuzzing found that case): lossy decoding keeps them intact.
    String::from_utf8_lossy(text).lines().any(|line| {
        let mut fields = line.split_whitespace();
        matches!(fields.next(), Some("Ka" | "Kd" | "Ks" | "Ke")) && fields.count() < 3
    })
}

/// Maps a tobj error to ours, finding the offending line where the error kind allows.
fn convert_error(path: &Path, text: &[u8], e: tobj::LoadError) -> RasterError {
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
    let line = prefix.and_then(|kw| find_bad_line(text, kw));
    RasterError::Parse {
        path: p,
        line,
        message,
    }
}

/// Best effort: the first line starting with `keyword` that does not parse, by our own
/// light check of the same grammar (tobj does not report lines).
fn find_bad_line(text: &[u8], keyword: &str) -> Option<usize> {
    let text = String::from_utf8_lossy(text);
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
    use std::path::PathBuf;

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
    fn faces_with_fewer_than_three_indices_are_errors_naming_the_line() {
        for (face, n) in [
            ("f 1 2", 2),
            ("f 3", 1),
            ("f", 0),
            ("f\t1/1 \t2/2\r", 2),
            ("f\u{a0}1\u{2003}2", 2),
        ] {
            let text =
                format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nf 1 2 3\n{face}\nf 1 2 3\n");
            let e = load_obj(write("short.obj", &text)).unwrap_err();
            assert!(matches!(e, RasterError::Parse { line: Some(7), .. }), "{e}");
            let want =
                format!("short.obj:7: face with {n} vertex indices; a face needs at least 3");
            assert!(e.to_string().ends_with(&want), "{e}");
        }
        // `l` (line) and `p` (point) elements are not faces: they are ignored, as documented.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\nf 1 2 3\n";
        assert_eq!(
            load_obj(write("lines.obj", text)).unwrap().triangle_count(),
            1
        );
    }

    /// Fuzzing found tobj overflowing `index * 2` on a relative texture index beyond the
    /// file's start (`fuzz/seeds/obj_loader/crash-relative-uv-index-overflow`); in release
    /// builds such products wrap, and an index near ±2^63 could alias a valid element. Every
    /// face reference is now range-checked first, with its line.
    #[test]
    fn every_face_index_is_range_checked_with_its_line() {
        let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvn 0 0 1\n";
        for (face, want) in [
            (
                "f 1/1 2/-12 3/1",
                "face texture index out of range: '2/-12' refers to -12, with 2",
            ),
            (
                "f 1 2 -9223372036854775807",
                "face vertex index out of range: '-9223372036854775807'",
            ),
            (
                "f 1 2 6148914691236517206",
                "face vertex index out of range: '6148914691236517206'",
            ),
            (
                "f 1/0 2/1 3/1",
                "face texture index out of range: '1/0' refers to 0",
            ),
            (
                "f 1//2 2//1 3//1",
                "face normal index out of range: '1//2' refers to 2, with 1",
            ),
            (
                "f 1 2 4",
                "face vertex index out of range: '4' refers to 4, with 3",
            ),
            ("f 1/1/1/1 2 3", "malformed face: '1/1/1/1'"),
            ("f /1 2 3", "malformed face: '/1'"),
            ("f 1 2 3x", "malformed face: '3x' ('3x' is not an integer)"),
        ] {
            let text = format!("{head}f 1 2 3\n{face}\n");
            let e = load_obj(write("range.obj", &text)).unwrap_err();
            let msg = e.to_string();
            assert!(msg.contains(&format!("range.obj:8: {want}")), "{msg}");
        }
        // Indices count only the elements defined before the face.
        let e = load_obj(write("later.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n"));
        assert!(e
            .unwrap_err()
            .to_string()
            .contains("later.obj:3: face vertex index"));
    }

    #[test]
    fn polygons_are_fan_triangulated_with_relative_indices() {
        // A pentagon given with negative (relative) indices, then a triangle mixing both.
        let text = "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf -5 -4 -3 -2 -1\n\
                    v 5 5 5\nf 1 -1 -3\n";
        let m = load_obj(write("penta.obj", text)).unwrap();
        let tris: Vec<[Vec3; 3]> = m
            .indices()
            .iter()
            .map(|t| t.map(|i| m.positions()[i as usize]))
            .collect();
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let (p0, p1, p2, p3, p4) = (
            v(0., 0., 0.),
            v(2., 0., 0.),
            v(3., 1., 0.),
            v(1., 2., 0.),
            v(-1., 1., 0.),
        );
        assert_eq!(
            tris,
            vec![
                [p0, p1, p2],
                [p0, p2, p3],
                [p0, p3, p4],
                [p0, v(5., 5., 5.), p3]
            ]
        );
    }

    #[test]
    fn truncated_and_binary_files_are_errors() {
        let e = load_obj(write("trunc.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2")).unwrap_err();
        assert!(e.to_string().contains("trunc.obj:4: face with 2"), "{e}");
        let e = load_obj(write("trunc2.obj", "v 0 0 0\nv 1 0 0\nv 0 1")).unwrap_err();
        assert!(
            e.to_string()
                .contains("trunc2.obj:3: malformed vertex position"),
            "{e}"
        );
        let garbage: Vec<u8> = (0..=255u8).cycle().take(2048).collect();
        let e = parse_obj_parts(&garbage, Path::new("bin.obj"), |_| None).unwrap_err();
        assert!(matches!(e, RasterError::Parse { .. }), "{e}");
        assert!(e.to_string().starts_with("bin.obj"), "{e}");
    }

    /// Fuzzing found that tobj panics on an MTL colour line with fewer than three numbers
    /// (`fuzz/seeds/obj_loader/crash-mtl-short-color`): such an MTL is malformed, so the
    /// parts load without material, as for any malformed MTL.
    #[test]
    fn mtl_colour_with_fewer_than_three_values_is_malformed_not_a_panic() {
        let obj = b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
        for line in ["Ka 0.5", "Kd 1 2", "Ks", "Ke 0 0", "Kd\u{a0}1\u{2003}2"] {
            let mtl = format!("newmtl m\n{line}\n").into_bytes();
            let parts = parse_obj_parts(obj, Path::new("x.obj"), |_| Some(mtl.clone())).unwrap();
            assert!(parts[0].material.is_none(), "{line}");
        }
        // Three values (or more: tobj reads the first three) are fine.
        // A short colour line before a line that is not UTF-8 (tobj parses the lines before).
        let mtl = b"newmtl m\nKa 0.1 0\nKd \xff\xff 1\n".to_vec();
        let parts = parse_obj_parts(obj, Path::new("x.obj"), |_| Some(mtl.clone())).unwrap();
        assert!(parts[0].material.is_none());
        let mtl = b"newmtl m\nKd 0.5 0.25 1 9\n".to_vec();
        let parts = parse_obj_parts(obj, Path::new("x.obj"), |_| Some(mtl.clone())).unwrap();
        assert_eq!(
            parts[0].material.unwrap().diffuse,
            Vec3::new(0.5, 0.25, 1.0)
        );
    }

    #[test]
    fn mtl_naming_a_missing_texture_is_an_error_naming_file_and_line() {
        write(
            "tex.mtl",
            "newmtl t\nKd 0.25 0.5 0.75\nmap_Kd does-not-exist.png\nmap_Ks nope.png\n",
        );
        let p = write(
            "tex.obj",
            "mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl t\nf 1/1 2/1 3/1\n",
        );
        let e = load_obj_parts(&p).unwrap_err().to_string();
        assert!(
            e.contains("tex.mtl:3:") && e.contains("does-not-exist.png"),
            "{e}"
        );
        // A texture that does not decode: the same, naming it.
        write("bad.png", "not a png");
        write("badtex.mtl", "newmtl t\nmap_Kd -s 2 2 bad.png\n");
        let p = write(
            "badtex.obj",
            "mtllib badtex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl t\nf 1/1 2/1 3/1\n",
        );
        let e = load_obj_parts(&p).unwrap_err().to_string();
        assert!(e.contains("badtex.mtl:2:") && e.contains("bad.png"), "{e}");
        // A malformed MTL is treated like a missing one: geometry without material.
        let mtl = b"newmtl x\nKd 1 nope 1\n".to_vec();
        let obj = b"mtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n";
        let parts = parse_obj_parts(obj, Path::new("x.obj"), |_| Some(mtl.clone())).unwrap();
        assert!(parts[0].material.is_none());
    }

    #[test]
    fn mtl_maps_load_with_their_options() {
        let dir = std::env::temp_dir().join(format!("shadelab-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let img = image::RgbImage::from_fn(2, 1, |x, _| image::Rgb([x as u8 * 255, 0, 0]));
        img.save(dir.join("two.png")).unwrap();
        write(
            "maps.mtl",
            "newmtl t\nKd 1 1 1\nmap_Kd -s 0.5 1 -o 0.5 0 two.png\n",
        );
        let p = write(
            "maps.obj",
            "mtllib maps.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl t\nf 1/1 2/1 3/1\n",
        );
        let parts = load_obj_parts(&p).unwrap();
        let maps = parts[0].maps.as_ref().expect("maps");
        let d = maps.diffuse.as_ref().unwrap();
        // u = 0.5 → 0.5·0.5 + 0.5 = 0.75: the right texel's centre (red).
        let c = d.sample(0.5, 0.5, &crate::texture::Footprint::default());
        assert_eq!(c, glam::Vec3::new(1.0, 0.0, 0.0));
        assert!(maps.ambient.is_none());
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
    fn uv_seams_do_not_crease_generated_normals() {
        // A quad folded along the diagonal 1-3, each half with its own UVs: the diagonal's
        // positions are split into two vertices each, but share one averaged normal.
        let p = write(
            "seam.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 1\nv 0 1 0\n\
             vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\nvt 0.2 0.2\n\
             f 1/1 2/2 4/4\nf 2/5 3/3 4/6\n",
        );
        let m = load_obj(&p).unwrap();
        assert_eq!(m.positions().len(), 6);
        assert!(m.uvs().is_some());
        let n = m.vertex_normals();
        let at = |q: Vec3| -> Vec<Vec3> {
            (0..6)
                .filter(|&i| m.positions()[i] == q)
                .map(|i| n[i])
                .collect()
        };
        for q in [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)] {
            let ns = at(q);
            assert_eq!(ns.len(), 2);
            assert_eq!(ns[0], ns[1]);
            let a = Vec3::Z; // face 1
            let b = (Vec3::ONE - Vec3::X).cross(Vec3::Y - Vec3::X).normalize(); // face 2
            assert!((ns[0] - (a + b).normalize()).length() < 1e-6, "{:?}", ns[0]);
        }
    }

    #[test]
    fn reads_mtl_and_tolerates_missing_mtl() {
        write(
            "m.mtl",
            "newmtl shiny\nKa 0.1 0.2 0.3\nKd 0.4 0.5 0.6\nKs 1 1 1\nNs 64\nKe 0.5 0 0\n",
        );
        let p = write(
            "withmtl.obj",
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl shiny\nf 1 2 3\n",
        );
        let parts = load_obj_parts(&p).unwrap();
        let m = parts[0].material.unwrap();
        assert_eq!(m.diffuse, Vec3::new(0.4, 0.5, 0.6));
        assert_eq!(m.shininess, 64.0);
        assert_eq!(m.emission, Vec3::new(0.5, 0.0, 0.0));
        let p = write(
            "nomtl.obj",
            "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n",
        );
        let parts = load_obj_parts(&p).unwrap();
        assert!(parts[0].material.is_none());
    }
}
