//! The environment: an equirectangular (latitude–longitude) image of the light arriving
//! from every direction, read by reflections and refractions and, optionally, shown as the
//! background.
//!
//! A unit direction `d` (after the environment's rotation) maps to
//! `u = 0.5 + atan2(d.x, −d.z)/(2π)`, `v = acos(d.y)/π`; the image is read at column `u·W`
//! and row `v·H` (texel centres at half-integers), so row 0 looks straight up (+y) and the
//! centre column looks along −z. Sampling is bilinear, wrapping in u and clamped in v.

use std::sync::Arc;

use glam::{DVec3, Vec3};

use crate::error::{RasterError, Result};

/// Largest environment side in texels.
pub const MAX_ENVIRONMENT_SIZE: usize = 16384;

/// Largest texel value (the lighting's float32 headroom, as for textures).
const MAX_TEXEL: f32 = 1e30;

/// An equirectangular environment image with a rotation about +y and an intensity.
#[derive(Debug, Clone, PartialEq)]
pub struct Environment {
    /// Linear RGB texels, row-major from the top row (+y).
    texels: Arc<[Vec3]>,
    width: usize,
    height: usize,
    /// Degrees about +y (right-handed: positive turns what was seen along −z toward −x).
    rotation: f32,
    intensity: f32,
    /// cos and sin of the rotation, applied as `R_y(−rotation)` to a looked-up direction.
    cos_sin: (f64, f64),
}

impl Environment {
    /// An environment from `height × width` linear RGB texels (`data`: row-major from the
    /// top, 3 floats a texel). `width` must be `2·height`; every texel finite and in
    /// [0, 1e30]; `rotation` (degrees) finite; `intensity` finite and ≥ 0.
    pub fn new(
        data: &[f32],
        height: usize,
        width: usize,
        rotation: f32,
        intensity: f32,
    ) -> Result<Self> {
        if height == 0 || width == 0 {
            return Err(RasterError::invalid_field(
                "array",
                format!("an environment image must not be empty, got {height}x{width}"),
            ));
        }
        if width != 2 * height {
            return Err(RasterError::invalid_field(
                "array",
                format!(
                    "an equirectangular environment must be twice as wide as it is high \
                     ((H, 2H, 3)), got height {height} and width {width}"
                ),
            ));
        }
        if width > MAX_ENVIRONMENT_SIZE {
            return Err(RasterError::invalid_field(
                "array",
                format!("environment width {width} is above the limit of {MAX_ENVIRONMENT_SIZE}"),
            ));
        }
        if data.len() != height * width * 3 {
            return Err(RasterError::invalid_field(
                "array",
                format!(
                    "environment data holds {} values, expected {height}x{width}x3",
                    data.len()
                ),
            ));
        }
        if let Some(k) = data
            .iter()
            .position(|v| !v.is_finite() || *v < 0.0 || *v > MAX_TEXEL)
        {
            return Err(RasterError::invalid_field(
                "array",
                format!(
                    "environment array[{}, {}, {}] = {} must be finite and in [0, {MAX_TEXEL:e}]",
                    k / (width * 3),
                    (k / 3) % width,
                    k % 3,
                    data[k]
                ),
            ));
        }
        if !rotation.is_finite() {
            return Err(RasterError::invalid_field(
                "rotation",
                format!("environment rotation must be finite (degrees), got {rotation}"),
            ));
        }
        if !intensity.is_finite() || intensity < 0.0 {
            return Err(RasterError::invalid_field(
                "intensity",
                format!("environment intensity must be finite and >= 0, got {intensity}"),
            ));
        }
        let texels: Arc<[Vec3]> = data
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        let r = (rotation as f64).to_radians();
        Ok(Environment {
            texels,
            width,
            height,
            rotation,
            intensity,
            cos_sin: (r.cos(), r.sin()),
        })
    }

    /// Height in texels (the width is twice it).
    pub fn height(&self) -> usize {
        self.height
    }

    /// Width in texels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rotation about +y in degrees.
    pub fn rotation(&self) -> f32 {
        self.rotation
    }

    /// The factor every looked-up colour is multiplied by.
    pub fn intensity(&self) -> f32 {
        self.intensity
    }

    /// The texels, row-major from the top, linear RGB.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// Largest looked-up value (intensity × largest texel).
    pub fn max_value(&self) -> f64 {
        let m = self
            .texels
            .iter()
            .map(|t| t.max_element())
            .fold(0.0, f32::max);
        m as f64 * self.intensity as f64
    }

    /// The (u, v) of a direction (any length; zero or non-finite gives the centre column
    /// at the horizon), after the rotation.
    pub fn uv(&self, d: Vec3) -> (f64, f64) {
        let d = d.as_dvec3();
        let len = d.length();
        let d = if len > 0.0 && len.is_finite() {
            d / len
        } else {
            DVec3::NEG_Z
        };
        // R_y(−θ)·d: what the unrotated image shows in that direction.
        let (c, s) = self.cos_sin;
        let x = c * d.x - s * d.z;
        let z = s * d.x + c * d.z;
        let u = 0.5 + x.atan2(-z) / std::f64::consts::TAU;
        let v = d.y.clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
        (u, v)
    }

    /// The colour seen along direction `d` (bilinear, wrapping in u, clamped in v), times
    /// the intensity.
    pub fn sample(&self, d: Vec3) -> Vec3 {
        let (u, v) = self.uv(d);
        let (w, h) = (self.width as f64, self.height as f64);
        let x = u * w - 0.5;
        let y = (v * h - 0.5).clamp(0.0, h - 1.0);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let wrap = |i: f64| (i.rem_euclid(w) as usize).min(self.width - 1);
        let (c0, c1) = (wrap(x0), wrap(x0 + 1.0));
        let r0 = y0 as usize;
        let r1 = (r0 + 1).min(self.height - 1);
        let t = |r: usize, c: usize| self.texels[r * self.width + c];
        let top = t(r0, c0) * (1.0 - fx) + t(r0, c1) * fx;
        let bottom = t(r1, c0) * (1.0 - fx) + t(r1, c1) * fx;
        (top * (1.0 - fy) + bottom * fy) * self.intensity
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(h: usize) -> Environment {
        // Texel (row, col) = (row, col, 1).
        let w = 2 * h;
        let data: Vec<f32> = (0..h * w)
            .flat_map(|k| [(k / w) as f32, (k % w) as f32, 1.0])
            .collect();
        Environment::new(&data, h, w, 0.0, 1.0).unwrap()
    }

    #[test]
    fn axes_map_to_the_documented_texels() {
        let e = env(8);
        // −z: u = 0.5, v = 0.5: column 8 (between texels 7 and 8), row 4 (between 3, 4).
        let c = e.sample(Vec3::NEG_Z);
        assert!((c.x - 3.5).abs() < 1e-5 && (c.y - 7.5).abs() < 1e-5, "{c}");
        assert_eq!(e.uv(Vec3::Y).1, 0.0);
        assert_eq!(e.uv(-Vec3::Y).1, 1.0);
        // +x: u = 0.75; −x: u = 0.25; +z: u = 1 (wraps to 0).
        assert!((e.uv(Vec3::X).0 - 0.75).abs() < 1e-12);
        assert!((e.uv(-Vec3::X).0 - 0.25).abs() < 1e-12);
        assert!((e.uv(Vec3::Z).0 - 1.0).abs() < 1e-12);
        // Straight up reads row 0 (clamped), whatever u.
        assert_eq!(e.sample(Vec3::Y).x, 0.0);
        assert_eq!(e.sample(-Vec3::Y).x, 7.0);
    }

    #[test]
    fn wraps_in_u_and_rotates_about_y() {
        let e = env(4);
        // Just either side of +z (the seam) blend columns 7 and 0 alike.
        let a = e.sample(Vec3::new(1e-7, 0.0, 1.0));
        let b = e.sample(Vec3::new(-1e-7, 0.0, 1.0));
        assert!((a - b).abs().max_element() < 1e-3, "{a} {b}");
        assert!((a.y - 3.5).abs() < 1e-3, "{a}");
        let data: Vec<f32> = e.texels().iter().flat_map(|t| t.to_array()).collect();
        let r = Environment::new(&data, 4, 8, 90.0, 2.0).unwrap();
        // Turned 90° about +y: what was seen along −z is now seen along −x.
        let want = e.sample(Vec3::NEG_Z) * 2.0;
        assert!((r.sample(Vec3::NEG_X) - want).abs().max_element() < 1e-4);
    }

    #[test]
    fn rejects_bad_images() {
        let field = |r: Result<Environment>| match r {
            Err(RasterError::InvalidField { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        assert_eq!(field(Environment::new(&[], 0, 0, 0.0, 1.0)), "array");
        assert_eq!(field(Environment::new(&[0.0; 9], 1, 3, 0.0, 1.0)), "array");
        assert_eq!(field(Environment::new(&[0.0; 5], 1, 2, 0.0, 1.0)), "array");
        let mut d = [0.5f32; 6];
        d[4] = f32::NAN;
        assert_eq!(field(Environment::new(&d, 1, 2, 0.0, 1.0)), "array");
        d[4] = -1.0;
        assert_eq!(field(Environment::new(&d, 1, 2, 0.0, 1.0)), "array");
        assert_eq!(
            field(Environment::new(&[0.5; 6], 1, 2, f32::NAN, 1.0)),
            "rotation"
        );
        assert_eq!(
            field(Environment::new(&[0.5; 6], 1, 2, 0.0, -1.0)),
            "intensity"
        );
        assert!(Environment::new(&[0.5; 6], 1, 2, 0.0, 0.0).is_ok());
    }
}
