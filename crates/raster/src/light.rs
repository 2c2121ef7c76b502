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
}

/// A light at a point, shining equally in all directions (no attenuation in this version).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLight {
    /// World-space position.
    pub position: Vec3,
    /// RGB colour.
    pub color: Vec3,
    /// Scalar multiplier of `color`.
    pub intensity: f32,
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
        })
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
        })
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
    }
}
