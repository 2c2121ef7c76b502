//! OpenGL-style materials and the classic preset table.

use glam::Vec3;

use crate::error::{RasterError, Result};

/// Reflectances of a surface, as in OpenGL's `glMaterial`: ambient, diffuse and specular RGB
/// and the specular exponent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Ambient reflectance `ka` (RGB).
    pub ambient: Vec3,
    /// Diffuse reflectance `kd` (RGB).
    pub diffuse: Vec3,
    /// Specular reflectance `ks` (RGB).
    pub specular: Vec3,
    /// Specular exponent `f` (≥ 0).
    pub shininess: f32,
    /// Emitted colour `ke` (RGB), added unlit (OpenGL's `GL_EMISSION`); black by default.
    pub emission: Vec3,
    /// The share of light mirrored (RGB, each in [0, 1]; a colour for metals): the weight
    /// of the reflected colour in `c = (1 − R − T)·local + R·reflected + T·transmitted`
    /// (see [`crate::reflect`]). 0 (the default) reflects nothing.
    pub reflectivity: Vec3,
    /// The share of light transmitted, `T` in [0, 1]; `reflectivity + transparency ≤ 1`
    /// per channel. 0 (the default) is opaque.
    pub transparency: f32,
    /// Index of refraction of the material (> 0; 1 = air, no bending and no Fresnel
    /// reflection). Read only where light crosses the surface or Fresnel is on.
    pub ior: f32,
    /// Weigh reflection and transmission by Schlick's Fresnel approximation (the default);
    /// `false` keeps the constant coefficients of the lectures.
    pub fresnel: bool,
    /// Beer–Lambert absorption per unit distance (RGB, ≥ 0) of light travelling inside the
    /// material (ray-traced refraction only): transmitted light is scaled by `exp(−a·d)`.
    pub absorption: Vec3,
}

impl Default for Material {
    /// A neutral grey plastic.
    fn default() -> Self {
        Material {
            ambient: Vec3::splat(0.2),
            diffuse: Vec3::splat(0.8),
            specular: Vec3::splat(0.5),
            shininess: 32.0,
            emission: Vec3::ZERO,
            ..OPAQUE
        }
    }
}

/// The optical parameters of an opaque, non-reflective material (every preset's).
const OPAQUE: Material = Material {
    ambient: Vec3::ZERO,
    diffuse: Vec3::ZERO,
    specular: Vec3::ZERO,
    shininess: 0.0,
    emission: Vec3::ZERO,
    reflectivity: Vec3::ZERO,
    transparency: 0.0,
    ior: 1.0,
    fresnel: true,
    absorption: Vec3::ZERO,
};

/// Named indices of refraction (the lectures' table): air 1, water 1.33, glass 1.5,
/// diamond 2.4.
pub const IOR_PRESETS: [(&str, f32); 4] = [
    ("air", 1.0),
    ("water", 1.33),
    ("glass", 1.5),
    ("diamond", 2.4),
];

/// The index of refraction called `name` ([`IOR_PRESETS`], case-insensitive).
pub fn ior_preset(name: &str) -> Result<f32> {
    let key = name.trim().to_ascii_lowercase();
    IOR_PRESETS
        .iter()
        .find(|(n, _)| *n == key)
        .map(|(_, v)| *v)
        .ok_or_else(|| {
            RasterError::invalid_field(
                "ior",
                format!(
                    "unknown ior preset '{name}'; expected a number > 0 or one of air, water, \
                     glass, diamond"
                ),
            )
        })
}

impl Material {
    /// Builds a material, checking that every colour is finite and ≥ 0 and the shininess
    /// ≥ 0; `shininess = +inf` is a perfect mirror lobe (specular only where the lobe's base
    /// `n·h` or `r·v` is exactly 1: see [`crate::options::SpecularModel`]).
    pub fn new(ambient: Vec3, diffuse: Vec3, specular: Vec3, shininess: f32) -> Result<Self> {
        for (name, v) in [
            ("ambient", ambient),
            ("diffuse", diffuse),
            ("specular", specular),
        ] {
            if !v.is_finite() || v.min_element() < 0.0 {
                return Err(RasterError::invalid_field(
                    name,
                    format!(
                        "material {name} must be finite and >= 0, got {:?}",
                        v.to_array()
                    ),
                ));
            }
        }
        // +inf is the lectures' perfect mirror (`pow01(x, inf)` is 1 at x ≥ 1, else 0).
        if shininess.is_nan() || shininess < 0.0 {
            return Err(RasterError::invalid_field(
                "shininess",
                format!(
                    "material shininess must be >= 0 (inf for a perfect mirror), got {shininess}"
                ),
            ));
        }
        Ok(Material {
            ambient,
            diffuse,
            specular,
            shininess,
            emission: Vec3::ZERO,
            ..OPAQUE
        })
    }

    /// The same material with its optical parameters: `reflectivity` (RGB, each in [0, 1]),
    /// `transparency` in [0, 1] (their sum at most 1 per channel), `ior` (finite, > 0),
    /// `fresnel` (Schlick weighting) and `absorption` (RGB per unit distance, finite, ≥ 0).
    /// Errors name the field.
    pub fn with_optics(
        mut self,
        reflectivity: Vec3,
        transparency: f32,
        ior: f32,
        fresnel: bool,
        absorption: Vec3,
    ) -> Result<Self> {
        if !reflectivity.is_finite()
            || reflectivity.min_element() < 0.0
            || reflectivity.max_element() > 1.0
        {
            return Err(RasterError::invalid_field(
                "reflectivity",
                format!(
                    "material reflectivity must be in [0, 1] (a number or an RGB colour), got {:?}",
                    reflectivity.to_array()
                ),
            ));
        }
        if !(0.0..=1.0).contains(&transparency) {
            return Err(RasterError::invalid_field(
                "transparency",
                format!("material transparency must be in [0, 1], got {transparency}"),
            ));
        }
        if reflectivity.max_element() + transparency > 1.0 {
            return Err(RasterError::invalid_field(
                "transparency",
                format!(
                    "material reflectivity + transparency must be at most 1 per channel (the \
                     rest is the local colour's share), got {:?} + {transparency}",
                    reflectivity.to_array()
                ),
            ));
        }
        if !ior.is_finite() || ior <= 0.0 {
            return Err(RasterError::invalid_field(
                "ior",
                format!("material ior (index of refraction) must be finite and > 0, got {ior}"),
            ));
        }
        if !absorption.is_finite() || absorption.min_element() < 0.0 {
            return Err(RasterError::invalid_field(
                "absorption",
                format!(
                    "material absorption must be finite and >= 0 (per unit distance), got {:?}",
                    absorption.to_array()
                ),
            ));
        }
        self.reflectivity = reflectivity;
        self.transparency = transparency;
        self.ior = ior;
        self.fresnel = fresnel;
        self.absorption = absorption;
        Ok(self)
    }

    /// Whether the material mirrors any light (`reflectivity` not all zero).
    pub fn is_reflective(&self) -> bool {
        self.reflectivity != Vec3::ZERO
    }

    /// Whether the material transmits any light (`transparency > 0`).
    pub fn is_transparent(&self) -> bool {
        self.transparency > 0.0
    }

    /// The same material emitting `emission` (finite, ≥ 0).
    pub fn with_emission(mut self, emission: Vec3) -> Result<Self> {
        if !emission.is_finite() || emission.min_element() < 0.0 {
            return Err(RasterError::invalid_field(
                "emission",
                format!(
                    "material emission must be finite and >= 0, got {:?}",
                    emission.to_array()
                ),
            ));
        }
        self.emission = emission;
        Ok(self)
    }

    /// The preset called `name` (case-insensitive; spaces, `_` and `-` are interchangeable).
    pub fn preset(name: &str) -> Result<Self> {
        let key = normalise_name(name);
        PRESETS
            .iter()
            .find(|p| p.name == key)
            .map(|p| p.material())
            .ok_or_else(|| {
                RasterError::invalid(format!(
                    "unknown material preset '{name}'; known presets: {}",
                    preset_names().join(", ")
                ))
            })
    }

    /// Whether the specular term can contribute (`ks` not all zero).
    pub fn has_specular(&self) -> bool {
        self.specular != Vec3::ZERO
    }
}

/// One row of the preset table.
#[derive(Debug, Clone, Copy)]
pub struct Preset {
    /// Canonical name (lower case, words separated by spaces).
    pub name: &'static str,
    /// Ambient RGB.
    pub ambient: [f32; 3],
    /// Diffuse RGB.
    pub diffuse: [f32; 3],
    /// Specular RGB.
    pub specular: [f32; 3],
    /// Specular exponent.
    pub shininess: f32,
}

impl Preset {
    /// The preset as a [`Material`].
    pub fn material(&self) -> Material {
        Material {
            ambient: Vec3::from_array(self.ambient),
            diffuse: Vec3::from_array(self.diffuse),
            specular: Vec3::from_array(self.specular),
            shininess: self.shininess,
            emission: Vec3::ZERO,
            ..OPAQUE
        }
    }
}

const fn p(
    name: &'static str,
    ambient: [f32; 3],
    diffuse: [f32; 3],
    specular: [f32; 3],
    shininess: f32,
) -> Preset {
    Preset {
        name,
        ambient,
        diffuse,
        specular,
        shininess,
    }
}

/// The classic OpenGL material table: the nine presets of the seed lecture table first, then
/// the rest of Kilgard's `teapots.c` table (SGI, 1994; also Table 3 of McReynolds & Blythe,
/// "Advanced Graphics Programming Techniques Using OpenGL", SIGGRAPH 1998 course notes, which
/// adds the polished metals). The source tables give shininess as a fraction of 128; here it
/// is already multiplied (0.6 → 76.8).
// Digits as published (e.g. 0.50980392 = 130/255), even past f32 precision, so the table
// reads like its source.
#[allow(clippy::excessive_precision)]
pub const PRESETS: &[Preset] = &[
    p(
        "black plastic",
        [0.0, 0.0, 0.0],
        [0.01, 0.01, 0.01],
        [0.5, 0.5, 0.5],
        32.0,
    ),
    p(
        "brass",
        [0.329412, 0.223529, 0.027451],
        [0.780392, 0.568627, 0.113725],
        [0.992157, 0.941176, 0.807843],
        27.8974,
    ),
    p(
        "bronze",
        [0.2125, 0.1275, 0.054],
        [0.714, 0.4284, 0.18144],
        [0.393548, 0.271906, 0.166721],
        25.6,
    ),
    p(
        "chrome",
        [0.25, 0.25, 0.25],
        [0.4, 0.4, 0.4],
        [0.774597, 0.774597, 0.774597],
        76.8,
    ),
    p(
        "copper",
        [0.19125, 0.0735, 0.0225],
        [0.7038, 0.27048, 0.0828],
        [0.256777, 0.137622, 0.086014],
        12.8,
    ),
    p(
        "gold",
        [0.24725, 0.1995, 0.0745],
        [0.75164, 0.60648, 0.22648],
        [0.628281, 0.555802, 0.366065],
        51.2,
    ),
    p(
        "pewter",
        [0.10588, 0.058824, 0.113725],
        [0.427451, 0.470588, 0.541176],
        [0.3333, 0.3333, 0.521569],
        9.84615,
    ),
    p(
        "silver",
        [0.19225, 0.19225, 0.19225],
        [0.50754, 0.50754, 0.50754],
        [0.508273, 0.508273, 0.508273],
        51.2,
    ),
    p(
        "polished silver",
        [0.23125, 0.23125, 0.23125],
        [0.2775, 0.2775, 0.2775],
        [0.773911, 0.773911, 0.773911],
        89.6,
    ),
    p(
        "emerald",
        [0.0215, 0.1745, 0.0215],
        [0.07568, 0.61424, 0.07568],
        [0.633, 0.727811, 0.633],
        76.8,
    ),
    p(
        "jade",
        [0.135, 0.2225, 0.1575],
        [0.54, 0.89, 0.63],
        [0.316228, 0.316228, 0.316228],
        12.8,
    ),
    p(
        "obsidian",
        [0.05375, 0.05, 0.06625],
        [0.18275, 0.17, 0.22525],
        [0.332741, 0.328634, 0.346435],
        38.4,
    ),
    p(
        "pearl",
        [0.25, 0.20725, 0.20725],
        [1.0, 0.829, 0.829],
        [0.296648, 0.296648, 0.296648],
        11.264,
    ),
    p(
        "ruby",
        [0.1745, 0.01175, 0.01175],
        [0.61424, 0.04136, 0.04136],
        [0.727811, 0.626959, 0.626959],
        76.8,
    ),
    p(
        "turquoise",
        [0.1, 0.18725, 0.1745],
        [0.396, 0.74151, 0.69102],
        [0.297254, 0.30829, 0.306678],
        12.8,
    ),
    p(
        "polished bronze",
        [0.25, 0.148, 0.06475],
        [0.4, 0.2368, 0.1036],
        [0.774597, 0.458561, 0.200621],
        76.8,
    ),
    p(
        "polished copper",
        [0.2295, 0.08825, 0.0275],
        [0.5508, 0.2118, 0.066],
        [0.580594, 0.223257, 0.0695701],
        51.2,
    ),
    p(
        "polished gold",
        [0.24725, 0.2245, 0.0645],
        [0.34615, 0.3143, 0.0903],
        [0.797357, 0.723991, 0.208006],
        83.2,
    ),
    p(
        "cyan plastic",
        [0.0, 0.1, 0.06],
        [0.0, 0.509_803_9, 0.509_803_9],
        [0.50196078, 0.50196078, 0.50196078],
        32.0,
    ),
    p(
        "green plastic",
        [0.0, 0.0, 0.0],
        [0.1, 0.35, 0.1],
        [0.45, 0.55, 0.45],
        32.0,
    ),
    p(
        "red plastic",
        [0.0, 0.0, 0.0],
        [0.5, 0.0, 0.0],
        [0.7, 0.6, 0.6],
        32.0,
    ),
    p(
        "white plastic",
        [0.0, 0.0, 0.0],
        [0.55, 0.55, 0.55],
        [0.7, 0.7, 0.7],
        32.0,
    ),
    p(
        "yellow plastic",
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.6, 0.6, 0.5],
        32.0,
    ),
    p(
        "black rubber",
        [0.02, 0.02, 0.02],
        [0.01, 0.01, 0.01],
        [0.4, 0.4, 0.4],
        10.0,
    ),
    p(
        "cyan rubber",
        [0.0, 0.05, 0.05],
        [0.4, 0.5, 0.5],
        [0.04, 0.7, 0.7],
        10.0,
    ),
    p(
        "green rubber",
        [0.0, 0.05, 0.0],
        [0.4, 0.5, 0.4],
        [0.04, 0.7, 0.04],
        10.0,
    ),
    p(
        "red rubber",
        [0.05, 0.0, 0.0],
        [0.5, 0.4, 0.4],
        [0.7, 0.04, 0.04],
        10.0,
    ),
    p(
        "white rubber",
        [0.05, 0.05, 0.05],
        [0.5, 0.5, 0.5],
        [0.7, 0.7, 0.7],
        10.0,
    ),
    p(
        "yellow rubber",
        [0.05, 0.05, 0.0],
        [0.5, 0.5, 0.4],
        [0.7, 0.7, 0.04],
        10.0,
    ),
];

/// Names of all presets, in table order.
pub fn preset_names() -> Vec<&'static str> {
    PRESETS.iter().map(|p| p.name).collect()
}

fn normalise_name(name: &str) -> String {
    name.trim()
        .to_ascii_lowercase()
        .split([' ', '_', '-'])
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_resolve_by_any_spelling() {
        let a = Material::preset("Polished_Silver").unwrap();
        let b = Material::preset("polished silver").unwrap();
        assert_eq!(a, b);
        assert_eq!(a.shininess, 89.6);
        assert_eq!(Material::preset("gold").unwrap().diffuse.x, 0.75164);
        let e = Material::preset("unobtainium").unwrap_err().to_string();
        assert!(e.contains("unobtainium") && e.contains("brass"), "{e}");
        assert_eq!(preset_names().len(), 29);
        assert_eq!(Material::preset("Red-Rubber").unwrap().shininess, 10.0);
    }

    #[test]
    fn rejects_bad_values() {
        let z = Vec3::ZERO;
        assert!(Material::new(Vec3::NAN, z, z, 1.0).is_err());
        assert!(Material::new(z, -Vec3::X, z, 1.0).is_err());
        assert!(Material::new(z, z, z, -1.0).is_err());
        assert!(Material::new(z, z, z, 0.0).is_ok());
    }

    #[test]
    fn optics_are_validated_by_field() {
        let m = Material::default();
        let field = |r: Result<Material>| match r {
            Err(RasterError::InvalidField { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        let z = Vec3::ZERO;
        assert_eq!(
            field(m.with_optics(Vec3::splat(1.5), 0.0, 1.0, true, z)),
            "reflectivity"
        );
        assert_eq!(
            field(m.with_optics(Vec3::NAN, 0.0, 1.0, true, z)),
            "reflectivity"
        );
        assert_eq!(field(m.with_optics(z, -0.1, 1.0, true, z)), "transparency");
        assert_eq!(
            field(m.with_optics(z, f32::NAN, 1.0, true, z)),
            "transparency"
        );
        assert_eq!(
            field(m.with_optics(Vec3::splat(0.6), 0.6, 1.0, true, z)),
            "transparency"
        );
        assert_eq!(field(m.with_optics(z, 0.5, 0.0, true, z)), "ior");
        assert_eq!(field(m.with_optics(z, 0.5, f32::INFINITY, true, z)), "ior");
        assert_eq!(
            field(m.with_optics(z, 0.5, 1.5, true, -Vec3::X)),
            "absorption"
        );
        let g = m
            .with_optics(Vec3::splat(0.1), 0.9, 1.5, false, Vec3::X)
            .unwrap();
        assert!(g.is_transparent() && g.is_reflective() && !g.fresnel);
        assert_eq!(ior_preset("Diamond").unwrap(), 2.4);
        assert!(matches!(
            ior_preset("lava"),
            Err(RasterError::InvalidField { field: "ior", .. })
        ));
        assert!(!Material::default().is_reflective() && !Material::default().is_transparent());
    }
}
