//! The spot factor, the one place that says how a cone dims its light.

use glam::Vec3;

use super::lanes::{Lanes, LANES};
use super::pow::pow01;

/// A spot light's cone, its angles as cosines (fixed per render).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cone {
    /// Unit direction the cone points.
    pub direction: Vec3,
    pub cos_cutoff: f32,
    /// cos of the smooth edge's inner angle; > 1 when there is none.
    pub cos_inner: f32,
    pub exponent: f32,
}

impl Cone {
    /// The cone's half-angle in degrees (what a shadow map's frustum must cover).
    pub fn cutoff_degrees(&self) -> f64 {
        (self.cos_cutoff as f64).acos().to_degrees()
    }

    /// The spot factor for `cos_angle = −l·d`: 0 outside the cutoff, `cos^exponent` inside,
    /// times a smoothstep across the soft edge when there is one (OpenGL's cone plus the
    /// common inner-angle fade).
    #[inline(always)]
    pub fn factor(&self, cos_angle: f32) -> f32 {
        if cos_angle < self.cos_cutoff {
            return 0.0;
        }
        // Exponents 0 and 1 exactly (no polynomial pow): 1 is every one-sided area light's.
        let base = if self.exponent == 0.0 {
            1.0
        } else if self.exponent == 1.0 {
            cos_angle.max(0.0)
        } else {
            pow01(cos_angle.max(0.0), self.exponent)
        };
        if self.cos_inner > 1.0 {
            base
        } else {
            let t = ((cos_angle - self.cos_cutoff) / (self.cos_inner - self.cos_cutoff))
                .clamp(0.0, 1.0);
            base * t * t * (3.0 - 2.0 * t)
        }
    }

    /// Multiplies `att` by the factor for the unit vectors `l` toward the light.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    pub fn scale_lanes(&self, l: &[Lanes; 3], att: &mut Lanes) {
        let d = self.direction;
        if self.cos_inner > 1.0 && (self.exponent == 0.0 || self.exponent == 1.0) {
            // Hard edge with exponent 0 or 1 (one-sided area lights' points): `factor`'s
            // values as branch-free selects, which vectorise (tested equal below).
            let flat = self.exponent == 0.0;
            for k in 0..LANES {
                let cos_angle = -(l[0][k] * d.x + l[1][k] * d.y + l[2][k] * d.z);
                let base = if flat { 1.0 } else { cos_angle.max(0.0) };
                att[k] *= if cos_angle < self.cos_cutoff {
                    0.0
                } else {
                    base
                };
            }
        } else {
            for k in 0..LANES {
                let cos_angle = -(l[0][k] * d.x + l[1][k] * d.y + l[2][k] * d.z);
                att[k] *= self.factor(cos_angle);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::needless_range_loop)] // lanes of several arrays
    fn lanes_equal_the_scalar_factor_for_every_cone_kind() {
        for (cos_cutoff, cos_inner, exponent) in [
            (0.0, 2.0, 1.0),
            (0.0, 2.0, 0.0),
            (0.5, 2.0, 1.0),
            (0.5, 0.8, 1.0),
            (0.7, 2.0, 3.5),
            (0.7, 0.9, 0.0),
        ] {
            let cone = Cone {
                direction: Vec3::new(0.0, 0.0, -1.0),
                cos_cutoff,
                cos_inner,
                exponent,
            };
            for start in (0..40).map(|i| i as f32 * 0.05 - 1.0) {
                let mut l = [[0.0; LANES]; 3];
                for k in 0..LANES {
                    let z = (start + k as f32 * 0.006).clamp(-1.0, 1.0);
                    l[0][k] = (1.0 - z * z).sqrt();
                    l[2][k] = z;
                }
                let mut att = [1.0; LANES];
                cone.scale_lanes(&l, &mut att);
                for k in 0..LANES {
                    assert_eq!(att[k].to_bits(), cone.factor(l[2][k]).to_bits());
                }
            }
        }
    }
}
