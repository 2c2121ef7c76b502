//! Point lights.

use glam::Vec3;

use crate::error::{RasterError, Result};

use super::colors::{check_ambient, check_color, SplitColors};
use super::shadow::Shadows;

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
    /// Diffuse and specular colours when they differ; see [`SplitColors`].
    pub split: SplitColors,
    /// Whether and how the light casts shadows (off by default).
    pub shadows: Shadows,
}

/// Smallest attenuation denominator: a light exactly at the surface with `kc = 0` gives a
/// large but finite value instead of infinity.
pub const MIN_ATTENUATION_DENOMINATOR: f32 = 1e-6;

impl PointLight {
    /// A point light; every value must be finite, colour and intensity ≥ 0.
    pub fn new(position: Vec3, color: Vec3, intensity: f32) -> Result<Self> {
        check_color(color, intensity)?;
        if !position.is_finite() {
            return Err(RasterError::invalid_field(
                "position",
                format!(
                    "light position must be finite, got {:?}",
                    position.to_array()
                ),
            ));
        }
        Ok(PointLight {
            position,
            color,
            intensity,
            ambient: Vec3::ZERO,
            attenuation: [1.0, 0.0, 0.0],
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

    /// The same light attenuated by `1 / (kc + kl·d + kq·d²)`; each coefficient finite and
    /// ≥ 0, not all zero.
    pub fn with_attenuation(mut self, kc: f32, kl: f32, kq: f32) -> Result<Self> {
        let k = [kc, kl, kq];
        if k.iter().any(|v| !v.is_finite() || *v < 0.0) || k.iter().all(|&v| v == 0.0) {
            return Err(RasterError::invalid_field(
                "attenuation",
                format!(
                    "attenuation (kc, kl, kq) must be finite, >= 0 and not all zero, got {k:?}"
                ),
            ));
        }
        self.attenuation = k;
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

    /// Whether the attenuation is not the identity `(1, 0, 0)`.
    pub fn is_attenuated(&self) -> bool {
        self.attenuation != [1.0, 0.0, 0.0]
    }
}
