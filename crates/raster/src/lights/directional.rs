//! Directional lights (a sun).

use glam::Vec3;

use crate::error::{RasterError, Result};

use super::colors::{check_ambient, check_color, SplitColors};
use super::shadow::Shadows;

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
    /// Diffuse and specular colours when they differ; see [`SplitColors`].
    pub split: SplitColors,
    /// Whether and how the light casts shadows (off by default).
    pub shadows: Shadows,
}

impl DirectionalLight {
    /// A directional light; `direction` is normalised and must be finite and non-zero.
    pub fn new(direction: Vec3, color: Vec3, intensity: f32) -> Result<Self> {
        check_color(color, intensity)?;
        let unit = direction
            .try_normalize()
            .filter(|_| direction.is_finite())
            .ok_or_else(|| {
                RasterError::invalid_field(
                    "direction",
                    format!(
                        "light direction must be finite and non-zero, got {:?}",
                        direction.to_array()
                    ),
                )
            })?;
        Ok(DirectionalLight {
            direction: unit,
            color,
            intensity,
            ambient: Vec3::ZERO,
            split: SplitColors::default(),
            shadows: Shadows::Off,
        })
    }

    /// The same light casting shadows as `shadows` says.
    pub fn with_shadows(mut self, shadows: Shadows) -> Self {
        self.shadows = shadows;
        self
    }
    /// The same light with its own ambient colour (finite, ≥ 0).
    pub fn with_ambient(mut self, ambient: Vec3) -> Result<Self> {
        check_ambient(ambient)?;
        self.ambient = ambient;
        Ok(self)
    }

    /// The same light with its own diffuse and/or specular colour (see [`SplitColors`]).
    pub fn with_split_colors(
        mut self,
        diffuse: Option<Vec3>,
        specular: Option<Vec3>,
    ) -> Result<Self> {
        self.split = SplitColors::new(diffuse, specular)?;
        Ok(self)
    }

    /// The unit direction the light travels.
    pub fn direction(&self) -> Vec3 {
        self.direction
    }

    /// The same light travelling along `unit`, stored as given (not renormalised: that can
    /// move the last bit), so a light rebuilt from [`DirectionalLight::direction`] (e.g.
    /// when unpickled) is bit-identical. `unit` must be finite with length 1 ± 1e-5.
    pub fn with_unit_direction(mut self, unit: Vec3) -> Result<Self> {
        self.direction = check_unit_direction(unit)?;
        Ok(self)
    }
}

/// `unit` if it is finite with length 1 ± 1e-5 (a direction stored as given).
pub(super) fn check_unit_direction(unit: Vec3) -> Result<Vec3> {
    if unit.is_finite() && (unit.length() - 1.0).abs() <= 1e-5 {
        Ok(unit)
    } else {
        Err(RasterError::invalid_field(
            "direction",
            format!(
                "a stored light direction must be a finite unit vector, got {:?}",
                unit.to_array()
            ),
        ))
    }
}
