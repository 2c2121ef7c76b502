//! Spot lights: a point light restricted to a cone.

use glam::Vec3;

use crate::error::{RasterError, Result};

use super::directional::check_unit_direction;
use super::point::PointLight;

/// A point light restricted to a cone, with OpenGL's `GL_SPOT_CUTOFF` / `GL_SPOT_EXPONENT`
/// meaning: with `l` the unit vector from the surface to the light and `d` the spot
/// direction, the spot factor is `max(−l·d, 0)^exponent` inside the cone (`−l·d ≥ cos
/// cutoff`) and 0 outside. `cutoff = 180` is OpenGL's "no cone" (a plain point light).
/// An optional inner angle fades the edge smoothly: between the inner and the outer
/// (cutoff) cone the factor is further multiplied by a smoothstep of `−l·d` from
/// `cos cutoff` to `cos inner`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpotLight {
    /// Position, colour, intensity, ambient and attenuation, as for a point light.
    pub point: PointLight,
    direction: Vec3,
    cutoff: f32,
    exponent: f32,
    inner: Option<f32>,
}

impl SpotLight {
    /// The same light casting shadows as `shadows` says (stored on its point light).
    pub fn with_shadows(mut self, shadows: super::Shadows) -> Self {
        self.point.shadows = shadows;
        self
    }

    /// A spot light at `point`'s position shining along `direction` (normalised; finite and
    /// non-zero), with `cutoff` in degrees in (0, 90] or exactly 180, and `exponent` ≥ 0.
    pub fn new(point: PointLight, direction: Vec3, cutoff: f32, exponent: f32) -> Result<Self> {
        let direction = direction
            .try_normalize()
            .filter(|_| direction.is_finite())
            .ok_or_else(|| {
                RasterError::invalid_field(
                    "direction",
                    format!(
                        "spot direction must be finite and non-zero, got {:?}",
                        direction.to_array()
                    ),
                )
            })?;
        if !(cutoff.is_finite() && ((cutoff > 0.0 && cutoff <= 90.0) || cutoff == 180.0)) {
            return Err(RasterError::invalid_field(
                "cutoff",
                format!(
                    "spot cutoff must be in (0, 90] degrees or exactly 180 (no cone), got {cutoff}"
                ),
            ));
        }
        if !(exponent.is_finite() && exponent >= 0.0) {
            return Err(RasterError::invalid_field(
                "exponent",
                format!("spot exponent must be finite and >= 0, got {exponent}"),
            ));
        }
        Ok(SpotLight {
            point,
            direction,
            cutoff,
            exponent,
            inner: None,
        })
    }

    /// The same light whose edge fades smoothly from `inner` degrees (0 ≤ inner < cutoff)
    /// out to the cutoff.
    pub fn with_inner(mut self, inner: f32) -> Result<Self> {
        if !(inner.is_finite() && inner >= 0.0 && inner < self.cutoff && self.cutoff <= 90.0) {
            return Err(RasterError::invalid_field("inner", format!(
                "spot inner angle must be in [0, cutoff) with cutoff <= 90, got inner={inner}, cutoff={}",
                self.cutoff
            )));
        }
        self.inner = Some(inner);
        Ok(self)
    }

    /// Unit direction the cone points.
    pub fn direction(&self) -> Vec3 {
        self.direction
    }

    /// The same spot pointing along `unit`, stored as given; see
    /// [`DirectionalLight::with_unit_direction`](super::DirectionalLight::with_unit_direction).
    pub fn with_unit_direction(mut self, unit: Vec3) -> Result<Self> {
        self.direction = check_unit_direction(unit)?;
        Ok(self)
    }

    /// Cone half-angle in degrees (180: no cone).
    pub fn cutoff(&self) -> f32 {
        self.cutoff
    }

    /// Fall-off exponent.
    pub fn exponent(&self) -> f32 {
        self.exponent
    }

    /// Inner angle of the smooth edge, if any.
    pub fn inner(&self) -> Option<f32> {
        self.inner
    }
}
