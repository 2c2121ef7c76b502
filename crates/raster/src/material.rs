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
        }
    }
}

impl Material {
    /// Builds a material, checking that every value is finite and ≥ 0.
    pub fn new(ambient: Vec3, diffuse: Vec3, specular: Vec3, shininess: f32) -> Result<Self> {
        for (name, v) in [
            ("ambient", ambient),
            ("diffuse", diffuse),
            ("specular", specular),
        ] {
            if !v.is_finite() || v.min_element() < 0.0 {
                return Err(RasterError::invalid(format!(
                    "material {name} must be finite and >= 0, got {:?}",
                    v.to_array()
                )));
            }
        }
        if !(shininess.is_finite() && shininess >= 0.0) {
            return Err(RasterError::invalid(format!(
                "material shininess must be finite and >= 0, got {shininess}"
            )));
        }
        Ok(Material {
            ambient,
            diffuse,
            specular,
            shininess,
            emission: Vec3::ZERO,
        })
    }

    /// The same material emitting `emission` (finite, ≥ 0).
    pub fn with_emission(mut self, emission: Vec3) -> Result<Self> {
        if !emission.is_finite() || emission.min_element() < 0.0 {
            return Err(RasterError::invalid(format!(
                "material emission must be finite and >= 0, got {:?}",
                emission.to_array()
            )));
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

/// The nine presets of the seed lecture table (the classic OpenGL material values).
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
        assert_eq!(preset_names().len(), 9);
    }

    #[test]
    fn rejects_bad_values() {
        let z = Vec3::ZERO;
        assert!(Material::new(Vec3::NAN, z, z, 1.0).is_err());
        assert!(Material::new(z, -Vec3::X, z, 1.0).is_err());
        assert!(Material::new(z, z, z, -1.0).is_err());
        assert!(Material::new(z, z, z, 0.0).is_ok());
    }
}
