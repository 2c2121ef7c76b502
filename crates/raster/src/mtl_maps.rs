//! Texture maps of MTL materials: `map_Kd`, `map_Ka`, `map_Ks`, `map_Ke`, `map_Ns` (a
//! shininess map: `Maps::shininess_at`), `norm` (a tangent-space normal map) and
//! `map_bump` / `bump` (a height map; `-bm` is its `bump_scale`) with the `-s` (scale) and
//! `-o` (offset) options of the texture coordinates and `-clamp on|off`; the other standard
//! options (`-blendu`, `-blendv`, `-boost`, `-cc`, `-imfchan`, `-mm`, `-texres`, `-t`, and
//! `-bm` on other maps) are read and ignored. `map_d` and reflection maps are ignored (no
//! alpha mapping yet). A map whose file is missing or cannot be decoded, or whose options
//! are malformed, is an error naming the MTL file and line.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use glam::DVec2;

use crate::error::{RasterError, Result};
use crate::texture::{Filter, Maps, Texture, Wrap};

/// Which coefficient a map line weighs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Slot {
    Diffuse,
    Ambient,
    Specular,
    Emission,
    Shininess,
    /// `norm`: tangent-space normals.
    Normal,
    /// `map_bump`, `bump`: heights.
    Bump,
}

/// One map line of an MTL file.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct MapLine {
    pub slot: Slot,
    /// 1-based line in the MTL file.
    pub line: usize,
    pub file: String,
    pub scale: DVec2,
    pub offset: DVec2,
    pub clamp: bool,
    /// `-bm` (1 when absent).
    pub bump_multiplier: f64,
}

/// Reads the map lines of MTL text, per material name. `mtl` names the file in errors.
pub(crate) fn scan(text: &[u8], mtl: &Path) -> Result<HashMap<String, Vec<MapLine>>> {
    let text = String::from_utf8_lossy(text);
    let mut out: HashMap<String, Vec<MapLine>> = HashMap::new();
    let mut current: Option<String> = None;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let err = |message: String| RasterError::Parse {
            path: mtl.to_path_buf(),
            line: Some(line),
            message,
        };
        let mut fields = raw.split_whitespace();
        let Some(key) = fields.next() else { continue };
        let slot = match key {
            "newmtl" => {
                current = Some(fields.collect::<Vec<_>>().join(" "));
                continue;
            }
            "map_Kd" => Slot::Diffuse,
            "map_Ka" => Slot::Ambient,
            "map_Ks" => Slot::Specular,
            "map_Ke" => Slot::Emission,
            "map_Ns" => Slot::Shininess,
            "norm" => Slot::Normal,
            "map_bump" | "bump" => Slot::Bump,
            _ => continue,
        };
        let rest: Vec<&str> = fields.collect();
        let map = parse_map(slot, line, &rest).map_err(|m| err(format!("{key}: {m}")))?;
        let Some(name) = &current else {
            return Err(err(format!("{key} before any newmtl")));
        };
        out.entry(name.clone()).or_default().push(map);
    }
    Ok(out)
}

/// Options with the numbers of values they take (`None`: one to three numbers).
fn option_arity(opt: &str) -> Option<Option<usize>> {
    match opt {
        "-blendu" | "-blendv" | "-bm" | "-boost" | "-cc" | "-clamp" | "-imfchan" | "-texres" => {
            Some(Some(1))
        }
        "-mm" => Some(Some(2)),
        "-s" | "-o" | "-t" => Some(None),
        _ => None,
    }
}

fn parse_map(slot: Slot, line: usize, tokens: &[&str]) -> std::result::Result<MapLine, String> {
    let mut map = MapLine {
        slot,
        line,
        file: String::new(),
        scale: DVec2::ONE,
        offset: DVec2::ZERO,
        clamp: false,
        bump_multiplier: 1.0,
    };
    let mut k = 0;
    while k < tokens.len() && tokens[k].starts_with('-') {
        let opt = tokens[k];
        let Some(arity) = option_arity(opt) else {
            return Err(format!("unknown option {opt:?}"));
        };
        k += 1;
        let values: Vec<&str> = match arity {
            Some(n) => {
                if k + n > tokens.len() {
                    return Err(format!("option {opt} needs {n} value(s)"));
                }
                tokens[k..k + n].to_vec()
            }
            None => tokens[k..]
                .iter()
                .take(3)
                .take_while(|t| t.parse::<f64>().is_ok())
                .copied()
                .collect(),
        };
        k += values.len();
        let numbers = || -> std::result::Result<Vec<f64>, String> {
            if values.is_empty() {
                return Err(format!("option {opt} needs 1 to 3 numbers"));
            }
            values
                .iter()
                .map(|v| match v.parse::<f64>() {
                    Ok(x) if x.is_finite() => Ok(x),
                    _ => Err(format!("option {opt}: {v:?} is not a finite number")),
                })
                .collect()
        };
        match opt {
            "-s" => {
                let n = numbers()?;
                map.scale = DVec2::new(n[0], *n.get(1).unwrap_or(&n[0]));
            }
            "-o" => {
                let n = numbers()?;
                map.offset = DVec2::new(n[0], *n.get(1).unwrap_or(&0.0));
            }
            "-t" => {
                numbers()?;
            }
            "-bm" => {
                map.bump_multiplier = numbers()?[0];
            }
            "-clamp" => {
                map.clamp = match values[0] {
                    "on" => true,
                    "off" => false,
                    v => return Err(format!("option -clamp takes on or off, got {v:?}")),
                }
            }
            _ => {}
        }
    }
    if k >= tokens.len() {
        return Err("no texture file named".into());
    }
    map.file = tokens[k..].join(" ");
    Ok(map)
}

/// The maps of one material: each file loaded (relative to `dir`) once per render of
/// the file list (`cache`), sRGB not decoded (values as stored, as classic OpenGL).
pub(crate) fn load_maps(
    lines: &[MapLine],
    dir: &Path,
    mtl: &Path,
    cache: &mut HashMap<(String, bool), Arc<crate::texture::Image>>,
) -> Result<Maps> {
    let mut maps = Maps::default();
    for m in lines {
        let at = |message: String| RasterError::Parse {
            path: mtl.to_path_buf(),
            line: Some(m.line),
            message,
        };
        let image = match cache.get(&(m.file.clone(), false)) {
            Some(img) => img.clone(),
            None => {
                let file = dir.join(&m.file);
                let tex = Texture::load(&file, Filter::Trilinear, [Wrap::Repeat; 2], false)
                    .map_err(|e| at(format!("texture {:?}: {e}", m.file)))?;
                let img = tex.image().expect("an image texture").clone();
                cache.insert((m.file.clone(), false), img.clone());
                img
            }
        };
        let wrap = if m.clamp { Wrap::Clamp } else { Wrap::Repeat };
        let tex = Texture::load_shared(image, dir.join(&m.file), Filter::Trilinear, [wrap; 2])
            .with_uv_transform(m.scale, m.offset);
        let slot = match m.slot {
            Slot::Diffuse => &mut maps.diffuse,
            Slot::Ambient => &mut maps.ambient,
            Slot::Specular => &mut maps.specular,
            Slot::Emission => &mut maps.emission,
            Slot::Shininess => &mut maps.shininess,
            Slot::Normal => &mut maps.normal,
            Slot::Bump => {
                maps.bump_scale = m.bump_multiplier as f32;
                &mut maps.bump
            }
        };
        *slot = Some(Arc::new(tex));
    }
    Ok(maps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_and_file_names() {
        let text = b"newmtl a\nKd 1 1 1\nmap_Kd -s 2 3 1 -o 0.5 -clamp on my tex.png\nmap_Ks -bm 0.2 s.png\n";
        let m = scan(text, Path::new("x.mtl")).unwrap();
        let a = &m["a"];
        assert_eq!(a[0].file, "my tex.png");
        assert_eq!(a[0].line, 3);
        assert_eq!(a[0].scale, DVec2::new(2.0, 3.0));
        assert_eq!(a[0].offset, DVec2::new(0.5, 0.0));
        assert!(a[0].clamp);
        assert_eq!(a[1].slot, Slot::Specular);
        assert_eq!(a[1].file, "s.png");
        let m = scan(b"newmtl b\nmap_Ns -imfchan l n.png\n", Path::new("x.mtl")).unwrap();
        assert_eq!(m["b"][0].slot, Slot::Shininess);
        assert_eq!(m["b"][0].file, "n.png");
        let text = b"newmtl c\nnorm -s 2 n.png\nmap_bump -bm 0.25 -o 0.5 h.png\nbump b.png\n";
        let m = scan(text, Path::new("x.mtl")).unwrap();
        let c = &m["c"];
        assert_eq!((c[0].slot, c[0].scale), (Slot::Normal, DVec2::splat(2.0)));
        assert_eq!((c[1].slot, c[1].bump_multiplier), (Slot::Bump, 0.25));
        assert_eq!(
            (c[1].offset, c[1].file.as_str()),
            (DVec2::new(0.5, 0.0), "h.png")
        );
        assert_eq!((c[2].slot, c[2].bump_multiplier), (Slot::Bump, 1.0));
    }

    #[test]
    fn malformed_lines_name_the_line() {
        for (text, want) in [
            ("newmtl a\nmap_Kd -s\n", "x.mtl:2:"),
            ("newmtl a\nmap_Kd -s nan t.png\n", "x.mtl:2:"),
            ("map_Kd t.png\n", "before any newmtl"),
            ("newmtl a\n\nmap_Kd -zz 1 t.png\n", "unknown option"),
            ("newmtl a\nmap_Kd -clamp maybe t.png\n", "on or off"),
            ("newmtl a\nmap_Ns\n", "map_Ns: no texture file"),
            ("newmtl a\nmap_bump -bm inf h.png\n", "not a finite number"),
            ("newmtl a\nnorm\n", "norm: no texture file"),
        ] {
            let e = scan(text.as_bytes(), Path::new("x.mtl"))
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }
}
