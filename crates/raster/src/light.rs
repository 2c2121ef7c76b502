//! Light sources.

use glam::Vec3;

use crate::error::{RasterError, Result};

/// A light at infinity shining along `direction` (a sun overhead is `(0, -1, 0)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirectionalLight {
    direction: Vec3,
    /// RGB colour (diffuse and specular intensity before `intensity`).
    pub color: Vec3,
    /// Scalar multiplier of `color`.
    pub intensity: f32,
    /// The light's own ambient colour `Ia_i` (OpenGL `GL_AMBIENT` of a light), black by
    /// default; not scaled by `intensity`.
    pub ambient: Vec3,
}

/// A light at a point, shining equally in all directions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLight {
    /// World-space position.
    pub position: Vec3,
    /// RGB colour.
    pub color: Vec3,
    /// Scalar multiplier of `color`.
    pub intensity: f32,
    /// The light's own ambient colour, black by default; attenuated like the rest.
    pub ambient: Vec3,
    /// Distance attenuation `(kc, kl, kq)`: the light is scaled by `1 / (kc + kl·d + kq·d²)`.
    /// `(1, 0, 0)` (the default) is no attenuation.
    pub attenuation: [f32; 3],
}

/// Smallest attenuation denominator: a light exactly at the surface with `kc = 0` gives a
/// large but finite value instead of infinity.
pub const MIN_ATTENUATION_DENOMINATOR: f32 = 1e-6;

fn check_ambient(ambient: Vec3) -> Result<()> {
    if !ambient.is_finite() || ambient.min_element() < 0.0 {
        return Err(RasterError::invalid(format!(
            "light ambient must be finite and >= 0, got {:?}",
            ambient.to_array()
        )));
    }
    Ok(())
}

/// Any light a scene can hold.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// See [`DirectionalLight`].
    Directional(DirectionalLight),
    /// See [`PointLight`].
    Point(PointLight),
}

fn check_color(color: Vec3, intensity: f32) -> Result<()> {
    if !color.is_finite() || color.min_element() < 0.0 {
        return Err(RasterError::invalid(format!(
            "light color must be finite and >= 0, got {:?}",
            color.to_array()
        )));
    }
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(RasterError::invalid(format!(
            "light intensity must be finite and >= 0, got {intensity}"
        )));
    }
    Ok(())
}

impl DirectionalLight {
    /// A directional light; `direction` is normalised and must be finite and non-zero.
    pub fn new(direction: Vec3, color: Vec3, intensity: f32) -> Result<Self> {
        check_color(color, intensity)?;
        let unit = direction
            .try_normalize()
            .filter(|_| direction.is_finite())
            .ok_or_else(|| {
                RasterError::invalid(format!(
                    "light direction must be finite and non-zero, got {:?}",
                    direction.to_array()
                ))
            })?;
        Ok(DirectionalLight {
            direction: unit,
            color,
            intensity,
            ambient: Vec3::ZERO,
        })
    }

    /// The same light with its own ambient colour (finite, ≥ 0).
    pub fn with_ambient(mut self, ambient: Vec3) -> Result<Self> {
        check_ambient(ambient)?;
        self.ambient = ambient;
        Ok(self)
    }

    /// The unit direction the light travels.
    pub fn direction(&self) -> Vec3 {
        self.direction
    }
}

impl PointLight {
    /// A point light; every value must be finite, colour and intensity ≥ 0.
    pub fn new(position: Vec3, color: Vec3, intensity: f32) -> Result<Self> {
        check_color(color, intensity)?;
        if !position.is_finite() {
            return Err(RasterError::invalid(format!(
                "light position must be finite, got {:?}",
                position.to_array()
            )));
        }
        Ok(PointLight {
            position,
            color,
            intensity,
            ambient: Vec3::ZERO,
            attenuation: [1.0, 0.0, 0.0],
        })
    }

    /// The same light with its own ambient colour (finite, ≥ 0).
    pub fn with_ambient(mut self, ambient: Vec3) -> Result<Self> {
        check_ambient(ambient)?;
        self.ambient = ambient;
        Ok(self)
    }

    /// The same light attenuated by `1 / (kc + kl·d + kq·d²)`; each coefficient finite and
    /// ≥ 0, not all zero.
    pub fn with_attenuation(mut self, kc: f32, kl: f32, kq: f32) -> Result<Self> {
        let k = [kc, kl, kq];
        if k.iter().any(|v| !v.is_finite() || *v < 0.0) || k.iter().all(|&v| v == 0.0) {
            return Err(RasterError::invalid(format!(
                "attenuation (kc, kl, kq) must be finite, >= 0 and not all zero, got {k:?}"
            )));
        }
        self.attenuation = k;
        Ok(self)
    }

    /// Whether the attenuation is not the identity `(1, 0, 0)`.
    pub fn is_attenuated(&self) -> bool {
        self.attenuation != [1.0, 0.0, 0.0]
    }
}

impl From<DirectionalLight> for Light {
    fn from(l: DirectionalLight) -> Self {
        Light::Directional(l)
    }
}

impl From<PointLight> for Light {
    fn from(l: PointLight) -> Self {
        Light::Point(l)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validates() {
        assert!(DirectionalLight::new(Vec3::ZERO, Vec3::ONE, 1.0).is_err());
        assert!(DirectionalLight::new(Vec3::new(f32::INFINITY, 0.0, 0.0), Vec3::ONE, 1.0).is_err());
        assert!(DirectionalLight::new(Vec3::X, Vec3::ONE, -1.0).is_err());
        let d = DirectionalLight::new(Vec3::new(0.0, -2.0, 0.0), Vec3::ONE, 1.0).unwrap();
        assert_eq!(d.direction(), -Vec3::Y);
        assert!(PointLight::new(Vec3::NAN, Vec3::ONE, 1.0).is_err());
        assert!(PointLight::new(Vec3::ZERO, Vec3::new(1.0, f32::NAN, 0.0), 1.0).is_err());
        let p = PointLight::new(Vec3::ZERO, Vec3::ONE, 1.0).unwrap();
        assert!(!p.is_attenuated());
        assert!(p.with_attenuation(0.0, 0.0, 0.0).is_err());
        assert!(p.with_attenuation(1.0, -1.0, 0.0).is_err());
        assert!(p.with_attenuation(0.0, 0.0, 1.0).unwrap().is_attenuated());
        assert!(p.with_ambient(Vec3::new(-1.0, 0.0, 0.0)).is_err());
    }
}
