//! Light sources, one kind a file; [`Light`] is any of them. How a light shades is the
//! lighting room's business (`crate::lighting`), not theirs.

mod area;
mod colors;
mod directional;
mod point;
mod shadow;
mod spot;

pub use area::{AreaLight, AreaShape, MAX_AREA_SAMPLES};
pub use colors::SplitColors;
pub use directional::DirectionalLight;
pub use point::{PointLight, MIN_ATTENUATION_DENOMINATOR};
pub use shadow::{
    ShadowFilter, ShadowSettings, Shadows, MAX_CASCADES, MAX_PCF_KERNEL, MAX_SHADOW_RESOLUTION,
};
pub use spot::SpotLight;

/// Any light a scene can hold.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// See [`DirectionalLight`].
    Directional(DirectionalLight),
    /// See [`PointLight`].
    Point(PointLight),
    /// See [`SpotLight`].
    Spot(SpotLight),
    /// See [`AreaLight`]: shaded as its point sources.
    Area(AreaLight),
}

impl Light {
    /// Whether and how the light casts shadows.
    pub fn shadows(&self) -> Shadows {
        match self {
            Light::Directional(l) => l.shadows,
            Light::Point(l) => l.shadows,
            Light::Spot(l) => l.point.shadows,
            Light::Area(l) => l.shadows,
        }
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

impl From<AreaLight> for Light {
    fn from(l: AreaLight) -> Self {
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
    use glam::Vec3;

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
