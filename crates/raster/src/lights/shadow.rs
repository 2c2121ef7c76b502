//! Whether and how a light casts shadows: off, a shadow map ([`ShadowSettings`]), or exact
//! shadow rays against the scene's triangles. Only the description; the shadow room
//! (`crate::shadows`) computes visibility.

use crate::error::{RasterError, Result};

/// Largest shadow-map side in texels (a cube map holds six such faces).
pub const MAX_SHADOW_RESOLUTION: u32 = 8192;
/// Largest percentage-closer filter kernel (texels per side, odd).
pub const MAX_PCF_KERNEL: u32 = 9;
/// Largest number of cascades of a directional light's shadow map.
pub const MAX_CASCADES: u32 = 4;

/// How a shadow map's depth comparison is filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowFilter {
    /// The lectures' plain comparison: one texel, lit or not.
    None,
    /// Percentage-closer filtering over a `k × k` texel kernel (`k` odd, 3 to
    /// [`MAX_PCF_KERNEL`]): the share of texels that pass.
    Pcf(u32),
}

/// A shadow map's resolution, filter, bias and (directional lights) cascades.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowSettings {
    resolution: u32,
    filter: ShadowFilter,
    bias: f32,
    cascades: u32,
}

impl Default for ShadowSettings {
    /// 2048 texels a side, 3 × 3 PCF, bias scale 1, one cascade.
    fn default() -> Self {
        ShadowSettings {
            resolution: 2048,
            filter: ShadowFilter::Pcf(3),
            bias: 1.0,
            cascades: 1,
        }
    }
}

impl ShadowSettings {
    /// Validated settings. `bias` scales the depth tolerance of one texel's world size at
    /// the point (the comparison is with the receiver-plane depth, the exact slope-scaled
    /// bias): 1 is the default, 0 none (acne).
    pub fn new(resolution: u32, filter: ShadowFilter, bias: f32) -> Result<Self> {
        if !(16..=MAX_SHADOW_RESOLUTION).contains(&resolution) {
            return Err(RasterError::invalid_field(
                "resolution",
                format!(
                    "shadow map resolution must be 16 to {MAX_SHADOW_RESOLUTION} texels, \
                     got {resolution}"
                ),
            ));
        }
        if let ShadowFilter::Pcf(k) = filter {
            if !(3..=MAX_PCF_KERNEL).contains(&k) || k % 2 == 0 {
                return Err(RasterError::invalid_field(
                    "kernel",
                    format!("PCF kernel must be odd, 3 to {MAX_PCF_KERNEL}, got {k}"),
                ));
            }
        }
        if !(bias.is_finite() && (0.0..=100.0).contains(&bias)) {
            return Err(RasterError::invalid_field(
                "bias",
                format!("shadow bias scale must be finite, 0 to 100, got {bias}"),
            ));
        }
        Ok(ShadowSettings {
            resolution,
            filter,
            bias,
            cascades: 1,
        })
    }

    /// These settings with `cascades` maps (1 to [`MAX_CASCADES`]) for a directional light:
    /// the camera's view is cut along its axis (practical split) and each slice gets a map
    /// of `resolution` texels a side fitted to it. Other lights have one map (a cube for
    /// point lights) whatever this says.
    pub fn with_cascades(self, cascades: u32) -> Result<Self> {
        if !(1..=MAX_CASCADES).contains(&cascades) {
            return Err(RasterError::invalid_field(
                "cascades",
                format!("shadow cascades must be 1 to {MAX_CASCADES}, got {cascades}"),
            ));
        }
        Ok(ShadowSettings { cascades, ..self })
    }

    /// Texels per side of the map (of each cube face for a point light).
    pub fn resolution(&self) -> u32 {
        self.resolution
    }

    /// The depth comparison's filter.
    pub fn filter(&self) -> ShadowFilter {
        self.filter
    }

    /// The bias scale (1: a tolerance of one texel's world size at the point).
    pub fn bias(&self) -> f32 {
        self.bias
    }

    /// Cascades of a directional light's map (1: one map).
    pub fn cascades(&self) -> u32 {
        self.cascades
    }
}

/// Whether a light casts shadows, and how.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Shadows {
    /// No shadows (the default): the light reaches every point that faces it.
    #[default]
    Off,
    /// A shadow map rendered from the light (the lectures' shadow z-buffer).
    Map(ShadowSettings),
    /// Shadow rays cast against the scene's triangles: the exact hard shadow (per sample
    /// point of an area light).
    Exact,
}

impl Shadows {
    /// Whether the light casts any shadow.
    pub fn on(&self) -> bool {
        !matches!(self, Shadows::Off)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_validate_and_name_the_field() {
        assert!(ShadowSettings::new(1024, ShadowFilter::None, 1.0).is_ok());
        let e = ShadowSettings::new(MAX_SHADOW_RESOLUTION + 1, ShadowFilter::None, 1.0);
        assert!(e.unwrap_err().to_string().contains("resolution"));
        let e = ShadowSettings::new(1024, ShadowFilter::Pcf(4), 1.0).unwrap_err();
        assert!(e.to_string().contains("kernel"));
        for bad in [f32::NAN, -1.0, f32::INFINITY] {
            let e = ShadowSettings::new(1024, ShadowFilter::None, bad).unwrap_err();
            assert!(e.to_string().contains("bias"), "{e}");
        }
        assert!(!Shadows::default().on() && Shadows::Exact.on());
        let s = ShadowSettings::default();
        assert_eq!(s.with_cascades(3).unwrap().cascades(), 3);
        for bad in [0, MAX_CASCADES + 1] {
            let e = s.with_cascades(bad).unwrap_err();
            assert!(e.to_string().contains("cascades"), "{e}");
        }
    }
}
