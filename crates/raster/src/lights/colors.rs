//! A light's colours: split diffuse/specular colours and the checks every kind shares.

use glam::Vec3;

use crate::error::{RasterError, Result};

/// A light's own diffuse and specular colours (OpenGL's `GL_DIFFUSE` / `GL_SPECULAR` of a
/// light), each overriding `color` for its term when set; both are scaled by `intensity`.
/// `color` is the shorthand that sets the two at once.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SplitColors {
    /// Diffuse colour `Id` before `intensity`; `None` takes `color`.
    pub diffuse: Option<Vec3>,
    /// Specular colour `Is` before `intensity`; `None` takes `color`.
    pub specular: Option<Vec3>,
}

impl SplitColors {
    /// Checks both colours (finite, ≥ 0).
    pub fn new(diffuse: Option<Vec3>, specular: Option<Vec3>) -> Result<Self> {
        for (name, c) in [("diffuse", diffuse), ("specular", specular)] {
            if let Some(c) = c {
                if !c.is_finite() || c.min_element() < 0.0 {
                    return Err(RasterError::invalid_field(
                        name,
                        format!(
                            "light {name} colour must be finite and >= 0, got {:?}",
                            c.to_array()
                        ),
                    ));
                }
            }
        }
        Ok(SplitColors { diffuse, specular })
    }

    /// `(Id, Is)`: the diffuse and specular light of `color` at `intensity`.
    pub fn radiance(&self, color: Vec3, intensity: f32) -> (Vec3, Vec3) {
        (
            self.diffuse.unwrap_or(color) * intensity,
            self.specular.unwrap_or(color) * intensity,
        )
    }
}

pub(crate) fn check_ambient(ambient: Vec3) -> Result<()> {
    if !ambient.is_finite() || ambient.min_element() < 0.0 {
        return Err(RasterError::invalid_field(
            "ambient",
            format!(
                "light ambient must be finite and >= 0, got {:?}",
                ambient.to_array()
            ),
        ));
    }
    Ok(())
}

pub(crate) fn check_color(color: Vec3, intensity: f32) -> Result<()> {
    if !color.is_finite() || color.min_element() < 0.0 {
        return Err(RasterError::invalid_field(
            "color",
            format!(
                "light color must be finite and >= 0, got {:?}",
                color.to_array()
            ),
        ));
    }
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(RasterError::invalid_field(
            "intensity",
            format!("light intensity must be finite and >= 0, got {intensity}"),
        ));
    }
    Ok(())
}
