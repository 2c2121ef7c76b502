//! The lighting equation (OpenGL 2.1 §2.14.1 with the local viewer on).
//!
//! For one surface point with unit normal `n`, position `p` and the eye at `e`:
//!
//! ```text
//! c = ka·Ia + Σ_i [ kd·Id_i·max(n·l_i, 0) + ks·Is_i·S_i ]        S_i = 0 unless n·l_i > 0
//! Blinn-Phong: S = max(n·h, 0)^f, h = normalize(l + v)      Phong: S = max(r·v, 0)^f, r = 2(n·l)n − l
//! ```
//!
//! `v = normalize(e − p)`; `l` points from the surface to the light. The per-light products
//! `kd·Id` and `ks·Is` are folded once per (material, light) in [`PreparedMaterial`], and the
//! specular loop is skipped entirely when `ks = 0`.

use std::str::FromStr;

use glam::Vec3;

use crate::error::RasterError;
use crate::light::Light;
use crate::material::Material;

/// Where lighting is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShadingMode {
    /// One colour per triangle: face normal, lit at the centroid.
    Flat,
    /// Lit at the vertices, colours interpolated (perspective-correct).
    Gouraud,
    /// Normals and positions interpolated, renormalised and lit per pixel.
    Phong,
}

/// Which specular lobe.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpecularModel {
    /// `max(n·h, 0)^f` with the half vector (OpenGL's fixed function).
    BlinnPhong,
    /// Phong's own `max(r·v, 0)^f`.
    Phong,
}

impl FromStr for ShadingMode {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self, RasterError> {
        match s.to_ascii_lowercase().as_str() {
            "flat" => Ok(ShadingMode::Flat),
            "gouraud" => Ok(ShadingMode::Gouraud),
            "phong" => Ok(ShadingMode::Phong),
            _ => Err(RasterError::invalid(format!(
                "unknown shading mode '{s}'; expected 'flat', 'gouraud' or 'phong'"
            ))),
        }
    }
}

impl FromStr for SpecularModel {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self, RasterError> {
        match s.to_ascii_lowercase().as_str() {
            "blinn" | "blinn-phong" | "blinn_phong" => Ok(SpecularModel::BlinnPhong),
            "phong" => Ok(SpecularModel::Phong),
            _ => Err(RasterError::invalid(format!(
                "unknown specular model '{s}'; expected 'blinn' or 'phong'"
            ))),
        }
    }
}

#[derive(Debug, Clone, Copy)]
enum LightGeometry {
    /// Unit vector toward the light.
    Directional(Vec3),
    Point(Vec3),
}

#[derive(Debug, Clone, Copy)]
struct PreparedLight {
    geometry: LightGeometry,
    diffuse: Vec3,
    specular: Vec3,
}

/// A material combined with the scene's lights: everything constant per render folded once.
#[derive(Debug, Clone)]
pub struct PreparedMaterial {
    base: Vec3,
    lights: Vec<PreparedLight>,
    shininess: f32,
    specular_on: bool,
    model: SpecularModel,
}

impl PreparedMaterial {
    /// Folds `material`, the scene ambient `ambient` and `lights` for one render.
    pub fn new(material: &Material, ambient: Vec3, lights: &[Light], model: SpecularModel) -> Self {
        let lights = lights
            .iter()
            .map(|l| {
                let (geometry, radiance) = match l {
                    Light::Directional(d) => (
                        LightGeometry::Directional(-d.direction()),
                        d.color * d.intensity,
                    ),
                    Light::Point(p) => (LightGeometry::Point(p.position), p.color * p.intensity),
                };
                PreparedLight {
                    geometry,
                    diffuse: material.diffuse * radiance,
                    specular: material.specular * radiance,
                }
            })
            .collect();
        PreparedMaterial {
            base: material.ambient * ambient,
            lights,
            shininess: material.shininess,
            specular_on: material.has_specular(),
            model,
        }
    }

    /// Colour at a point with unit (or zero) normal `n`, position `p`, eye `eye`.
    #[inline]
    pub fn shade(&self, n: Vec3, p: Vec3, eye: Vec3) -> Vec3 {
        if self.specular_on {
            match self.model {
                SpecularModel::BlinnPhong => self.shade_with::<true, true>(n, p, eye),
                SpecularModel::Phong => self.shade_with::<true, false>(n, p, eye),
            }
        } else {
            self.shade_with::<false, true>(n, p, eye)
        }
    }

    #[inline(always)]
    fn shade_with<const SPECULAR: bool, const BLINN: bool>(
        &self,
        n: Vec3,
        p: Vec3,
        eye: Vec3,
    ) -> Vec3 {
        let mut c = self.base;
        let v = if SPECULAR {
            (eye - p).normalize_or_zero()
        } else {
            Vec3::ZERO
        };
        for light in &self.lights {
            let l = match light.geometry {
                LightGeometry::Directional(l) => l,
                LightGeometry::Point(pos) => (pos - p).normalize_or_zero(),
            };
            let n_dot_l = n.dot(l);
            if n_dot_l > 0.0 {
                c += light.diffuse * n_dot_l;
                if SPECULAR {
                    let s = if BLINN {
                        let h = l + v;
                        let len2 = h.length_squared();
                        if len2 > 0.0 {
                            (n.dot(h) / len2.sqrt()).max(0.0)
                        } else {
                            f32::NAN // no half vector: no highlight
                        }
                    } else {
                        let r = 2.0 * n_dot_l * n - l;
                        r.dot(v).max(0.0)
                    };
                    // `s` is in [0, 1] (or NaN → skipped), so powf never sees a negative base;
                    // 0^0 = 1 by IEEE pow.
                    if s >= 0.0 {
                        c += light.specular * s.powf(self.shininess);
                    }
                }
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::{DirectionalLight, PointLight};

    fn mat() -> Material {
        Material::new(
            Vec3::new(0.1, 0.2, 0.3),
            Vec3::new(0.5, 0.6, 0.7),
            Vec3::new(0.25, 0.25, 0.25),
            10.0,
        )
        .unwrap()
    }

    #[test]
    fn head_on_directional_is_ambient_plus_diffuse_plus_specular() {
        let l: Light = DirectionalLight::new(-Vec3::Z, Vec3::ONE, 1.0)
            .unwrap()
            .into();
        let pm = PreparedMaterial::new(&mat(), Vec3::splat(0.5), &[l], SpecularModel::BlinnPhong);
        let c = pm.shade(Vec3::Z, Vec3::ZERO, Vec3::new(0.0, 0.0, 3.0));
        let want = Vec3::new(0.05, 0.1, 0.15) + Vec3::new(0.5, 0.6, 0.7) + Vec3::splat(0.25);
        assert!((c - want).abs().max_element() < 1e-6, "{c} vs {want}");
    }

    #[test]
    fn oblique_point_light_hand_computed() {
        // Light at (1,0,1) over the origin, eye at (0,0,1): l = (1,0,1)/√2, v = (0,0,1).
        let l: Light = PointLight::new(Vec3::new(1.0, 0.0, 1.0), Vec3::ONE, 2.0)
            .unwrap()
            .into();
        let m = mat();
        let eye = Vec3::Z;
        let s2 = std::f32::consts::FRAC_1_SQRT_2;
        let n_dot_l = s2;
        // Blinn: h = normalize(l + v); n·h = cos(22.5°)
        let nh = (std::f32::consts::PI / 8.0).cos();
        let blinn = PreparedMaterial::new(&m, Vec3::ZERO, &[l], SpecularModel::BlinnPhong);
        let want = m.diffuse * 2.0 * n_dot_l + m.specular * 2.0 * nh.powf(10.0);
        assert!(
            (blinn.shade(Vec3::Z, Vec3::ZERO, eye) - want)
                .abs()
                .max_element()
                < 1e-5
        );
        // Phong: r = (−1,0,1)/√2, r·v = 1/√2.
        let phong = PreparedMaterial::new(&m, Vec3::ZERO, &[l], SpecularModel::Phong);
        let want = m.diffuse * 2.0 * n_dot_l + m.specular * 2.0 * s2.powf(10.0);
        assert!(
            (phong.shade(Vec3::Z, Vec3::ZERO, eye) - want)
                .abs()
                .max_element()
                < 1e-5
        );
    }

    #[test]
    fn no_light_from_behind_and_no_nan() {
        let l: Light = DirectionalLight::new(Vec3::Z, Vec3::ONE, 1.0)
            .unwrap()
            .into();
        let m = Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ONE, 0.0).unwrap();
        let pm = PreparedMaterial::new(&m, Vec3::ZERO, &[l], SpecularModel::BlinnPhong);
        assert_eq!(pm.shade(Vec3::Z, Vec3::ZERO, Vec3::Z), Vec3::ZERO);
        // Zero normal, eye on the surface, light at the point: finite.
        let pl: Light = PointLight::new(Vec3::ZERO, Vec3::ONE, 1.0).unwrap().into();
        let pm = PreparedMaterial::new(&m, Vec3::ZERO, &[pl, l], SpecularModel::BlinnPhong);
        assert!(pm.shade(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO).is_finite());
        assert!(pm.shade(Vec3::Z, Vec3::ZERO, Vec3::ZERO).is_finite());
    }

    #[test]
    fn parses_names() {
        assert_eq!("Phong".parse::<ShadingMode>().unwrap(), ShadingMode::Phong);
        assert!("toon".parse::<ShadingMode>().is_err());
        assert_eq!(
            "blinn".parse::<SpecularModel>().unwrap(),
            SpecularModel::BlinnPhong
        );
    }
}
