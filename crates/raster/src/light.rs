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
    /// Diffuse and specular colours when they differ; see [`SplitColors`].
    pub split: SplitColors,
}

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
                    return Err(RasterError::invalid(format!(
                        "light {name} colour must be finite and >= 0, got {:?}",
                        c.to_array()
                    )));
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
    /// See [`SpotLight`].
    Spot(SpotLight),
    /// See [`AreaLight`](crate::AreaLight): shaded as its point sources.
    Area(crate::area_light::AreaLight),
}

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
    /// A spot light at `point`'s position shining along `direction` (normalised; finite and
    /// non-zero), with `cutoff` in degrees in (0, 90] or exactly 180, and `exponent` ≥ 0.
    pub fn new(point: PointLight, direction: Vec3, cutoff: f32, exponent: f32) -> Result<Self> {
        let direction = direction
            .try_normalize()
            .filter(|_| direction.is_finite())
            .ok_or_else(|| {
                RasterError::invalid(format!(
                    "spot direction must be finite and non-zero, got {:?}",
                    direction.to_array()
                ))
            })?;
        if !(cutoff.is_finite() && ((cutoff > 0.0 && cutoff <= 90.0) || cutoff == 180.0)) {
            return Err(RasterError::invalid(format!(
                "spot cutoff must be in (0, 90] degrees or exactly 180 (no cone), got {cutoff}"
            )));
        }
        if !(exponent.is_finite() && exponent >= 0.0) {
            return Err(RasterError::invalid(format!(
                "spot exponent must be finite and >= 0, got {exponent}"
            )));
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
            return Err(RasterError::invalid(format!(
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
    /// [`DirectionalLight::with_unit_direction`].
    pub fn with_unit_direction(mut self, unit: Vec3) -> Result<Self> {
        self.direction = check_unit(unit)?;
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

    /// The spot factor for `cos_angle = −l·d`.
    #[inline(always)]
    pub fn factor(cos_angle: f32, cos_cutoff: f32, cos_inner: f32, exponent: f32) -> f32 {
        // cos_inner > 1 marks "no smooth edge" (the smoothstep is then 1 inside the cone).
        if cos_angle < cos_cutoff {
            return 0.0;
        }
        // Exponents 0 and 1 exactly (no polynomial pow): 1 is every one-sided area light's.
        let base = if exponent == 0.0 {
            1.0
        } else if exponent == 1.0 {
            cos_angle.max(0.0)
        } else {
            crate::shading::pow01(cos_angle.max(0.0), exponent)
        };
        if cos_inner > 1.0 {
            base
        } else {
            let t = ((cos_angle - cos_cutoff) / (cos_inner - cos_cutoff)).clamp(0.0, 1.0);
            base * t * t * (3.0 - 2.0 * t)
        }
    }
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
            split: SplitColors::default(),
        })
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
        self.direction = check_unit(unit)?;
        Ok(self)
    }
}

fn check_unit(unit: Vec3) -> Result<Vec3> {
    if unit.is_finite() && (unit.length() - 1.0).abs() <= 1e-5 {
        Ok(unit)
    } else {
        Err(RasterError::invalid(format!(
            "a stored light direction must be a finite unit vector, got {:?}",
            unit.to_array()
        )))
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
            split: SplitColors::default(),
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

impl From<crate::area_light::AreaLight> for Light {
    fn from(l: crate::area_light::AreaLight) -> Self {
        Light::Area(l)
    }
}

impl From<SpotLight> for Light {
    fn from(l: SpotLight) -> Self {
        Light::Spot(l)
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
        assert!(SpotLight::new(p, Vec3::ZERO, 30.0, 0.0).is_err());
        assert!(SpotLight::new(p, -Vec3::Z, 91.0, 0.0).is_err());
        assert!(SpotLight::new(p, -Vec3::Z, 0.0, 0.0).is_err());
        assert!(SpotLight::new(p, -Vec3::Z, 180.0, 0.0).is_ok());
        assert!(SpotLight::new(p, -Vec3::Z, 30.0, -1.0).is_err());
        let s = SpotLight::new(p, -Vec3::Z * 3.0, 30.0, 2.0).unwrap();
        assert_eq!(s.direction(), -Vec3::Z);
        assert!(s.with_inner(30.0).is_err());
        assert!(s.with_inner(20.0).is_ok());
        assert!(p.with_split_colors(Some(-Vec3::ONE), None).is_err());
        assert!(d.with_split_colors(None, Some(Vec3::NAN)).is_err());
        let q = p.with_split_colors(Some(Vec3::X), None).unwrap();
        assert_eq!(
            q.split.radiance(Vec3::ONE, 2.0),
            (2.0 * Vec3::X, Vec3::splat(2.0))
        );
    }
}
