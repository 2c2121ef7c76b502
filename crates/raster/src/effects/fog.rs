//! Atmospheric attenuation (depth cueing): the lit colour blends toward a fog colour with
//! the Euclidean distance from the eye, as OpenGL's `GL_FOG` with `GL_EYE_RADIAL_NV`.

use glam::Vec3;

use crate::camera::EyeDistance;
use crate::error::{RasterError, Result};

/// How the fog factor falls with distance `d`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FogMode {
    /// `f = (end − d) / (end − start)`.
    Linear {
        /// Distance where fog starts.
        start: f32,
        /// Distance where only fog is left.
        end: f32,
    },
    /// `f = e^(−density·d)`.
    Exp {
        /// Density (≥ 0).
        density: f32,
    },
    /// `f = e^(−(density·d)²)`.
    Exp2 {
        /// Density (≥ 0).
        density: f32,
    },
}

/// Fog: the final colour is `f·c + (1 − f)·color` with `f` clamped to [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fog {
    mode: FogMode,
    color: Vec3,
}

impl Fog {
    /// Builds a fog, checking that every value is finite, densities ≥ 0, `start < end`, and
    /// the colour ≥ 0.
    pub fn new(mode: FogMode, color: Vec3) -> Result<Self> {
        if !color.is_finite() || color.min_element() < 0.0 {
            return Err(RasterError::invalid_field(
                "color",
                format!(
                    "fog color must be finite and >= 0, got {:?}",
                    color.to_array()
                ),
            ));
        }
        match mode {
            FogMode::Linear { start, end } => {
                if !(start.is_finite() && end.is_finite() && start < end) {
                    let field = if start.is_finite() { "end" } else { "start" };
                    return Err(RasterError::invalid_field(
                        field,
                        format!(
                            "linear fog needs finite start < end, got start={start}, end={end}"
                        ),
                    ));
                }
            }
            FogMode::Exp { density } | FogMode::Exp2 { density } => {
                if !(density.is_finite() && density >= 0.0) {
                    return Err(RasterError::invalid_field(
                        "density",
                        format!("fog density must be finite and >= 0, got {density}"),
                    ));
                }
            }
        }
        Ok(Fog { mode, color })
    }

    /// The fall-off.
    pub fn mode(&self) -> FogMode {
        self.mode
    }

    /// The colour far objects fade to.
    pub fn color(&self) -> Vec3 {
        self.color
    }

    /// The fog factor `f` in [0, 1] at eye distance `d` (1: no fog).
    #[inline]
    pub fn factor(&self, d: f32) -> f32 {
        let f = match self.mode {
            FogMode::Linear { start, end } => (end - d) / (end - start),
            FogMode::Exp { density } => (-density * d).exp(),
            FogMode::Exp2 { density } => {
                let x = density * d;
                (-x * x).exp()
            }
        };
        f.clamp(0.0, 1.0)
    }

    /// `c` seen through the fog at eye distance `d`.
    #[inline]
    pub fn apply(&self, c: Vec3, d: f32) -> Vec3 {
        let f = self.factor(d);
        c * f + self.color * (1.0 - f)
    }
}

/// Fog as the shade stage applies it: the scene's [`Fog`] and the per-render constants that
/// turn a pixel's eye depth into its distance from the eye.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FogEffect {
    fog: Fog,
    distance: EyeDistance,
}

impl FogEffect {
    pub fn new(fog: Fog, distance: EyeDistance) -> Self {
        FogEffect { fog, distance }
    }

    /// `c` seen through the fog at pixel (x, y), whose eye depth is `depth`.
    #[inline(always)]
    pub fn apply(&self, c: Vec3, x: usize, y: usize, depth: f32) -> Vec3 {
        self.fog.apply(c, self.distance.at(x, y, depth))
    }

    /// Whether the camera's rays are centred (see [`EyeDistance::centred`]), so a batch can
    /// pick [`FogEffect::apply_with`] once instead of testing per pixel.
    #[inline(always)]
    pub fn centred(&self) -> bool {
        self.distance.centred()
    }

    /// [`FogEffect::apply`] with or without the off-centre ray terms.
    #[inline(always)]
    pub fn apply_with<const OFF_CENTRE: bool>(
        &self,
        c: Vec3,
        x: usize,
        y: usize,
        depth: f32,
    ) -> Vec3 {
        self.fog
            .apply(c, self.distance.at_with::<OFF_CENTRE>(x, y, depth))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factors_hand_computed() {
        let c = Vec3::new(0.5, 0.5, 0.5);
        let lin = Fog::new(
            FogMode::Linear {
                start: 2.0,
                end: 6.0,
            },
            c,
        )
        .unwrap();
        assert_eq!(lin.factor(1.0), 1.0);
        assert_eq!(lin.factor(3.0), 0.75);
        assert_eq!(lin.factor(10.0), 0.0);
        let exp = Fog::new(FogMode::Exp { density: 0.5 }, c).unwrap();
        assert!((exp.factor(2.0) - (-1.0f32).exp()).abs() < 1e-7);
        let exp2 = Fog::new(FogMode::Exp2 { density: 0.5 }, c).unwrap();
        assert!((exp2.factor(4.0) - (-4.0f32).exp()).abs() < 1e-7);
        assert_eq!(lin.apply(Vec3::ONE, 3.0), Vec3::splat(0.875));
        assert!(Fog::new(
            FogMode::Linear {
                start: 2.0,
                end: 2.0
            },
            c
        )
        .is_err());
        assert!(Fog::new(FogMode::Exp { density: -1.0 }, c).is_err());
        assert!(Fog::new(FogMode::Exp2 { density: 1.0 }, Vec3::NAN).is_err());
    }
}
