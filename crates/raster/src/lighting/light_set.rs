//! The scene's lights, prepared once per render: geometry in the form the lanes read, the
//! light's own colours, and area lights expanded into their point sources. Nothing here knows
//! a material; [`super::Surface`] combines the two.

use glam::Vec3;

use super::spot::Cone;
use crate::lights::{AreaLight, Light, PointLight, Shadows, SpotLight};

/// Where a light is, as the lanes read it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Geometry {
    /// Unit vector toward the light.
    Directional(Vec3),
    Point(Vec3),
    Spot {
        position: Vec3,
        cone: Cone,
    },
}

/// One point source of a render: geometry and the light's own colours.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Source {
    pub geometry: Geometry,
    /// `Id`: diffuse radiance (colour × intensity).
    pub diffuse: Vec3,
    /// `Is`: specular radiance.
    pub specular: Vec3,
    /// `Ia_i`: the light's own ambient colour.
    pub ambient: Vec3,
    /// `(kc, kl, kq)` of an attenuated light; `None` costs nothing per pixel.
    pub attenuation: Option<[f32; 3]>,
    /// Whether and how the source casts shadows (an area light's points: the light's).
    pub shadows: Shadows,
}

impl Source {
    /// Whether the source's terms are scaled per point (attenuation or a cone), so its
    /// ambient term cannot be folded into a constant.
    pub fn scaled(&self) -> bool {
        self.attenuation.is_some() || matches!(self.geometry, Geometry::Spot { .. })
    }

    /// Whether the source adds exactly nothing to any point: its ambient, diffuse and
    /// specular colours all zero (every term it would add is a product with one of them, and
    /// `x + 0 = x`, so dropping it leaves every pixel's bits as they were; a NaN colour is
    /// not dark and stays).
    pub fn dark(&self) -> bool {
        self.diffuse == Vec3::ZERO && self.specular == Vec3::ZERO && self.ambient == Vec3::ZERO
    }
}

/// A render's point sources, in the scene's order (area lights in place, as their points).
#[derive(Debug, Clone, Default)]
pub(crate) struct LightSet {
    pub sources: Vec<Source>,
}

impl LightSet {
    /// The sources of `lights`, without those that add nothing anywhere ([`Source::dark`]):
    /// a black light costs no lighting, and no shadow map, per pixel.
    pub fn new(lights: &[Light]) -> Self {
        let mut sources = Vec::with_capacity(lights.len());
        for l in lights {
            match l {
                // An area light is its point sources: no per-pixel code of its own.
                Light::Area(a) => sources.extend(area_points(a).iter().map(source)),
                _ => sources.push(source(l)),
            }
        }
        sources.retain(|s| !s.dark());
        LightSet { sources }
    }
}

fn source(l: &Light) -> Source {
    let point = |p: &PointLight, geometry| {
        let (diffuse, specular) = p.split.radiance(p.color, p.intensity);
        Source {
            geometry,
            diffuse,
            specular,
            ambient: p.ambient,
            attenuation: p.is_attenuated().then_some(p.attenuation),
            shadows: p.shadows,
        }
    };
    match l {
        Light::Directional(d) => {
            let (diffuse, specular) = d.split.radiance(d.color, d.intensity);
            Source {
                geometry: Geometry::Directional(-d.direction()),
                diffuse,
                specular,
                ambient: d.ambient,
                attenuation: None,
                shadows: d.shadows,
            }
        }
        Light::Point(p) => point(p, Geometry::Point(p.position)),
        // OpenGL: a cutoff of 180 is no cone at all, whatever the exponent.
        Light::Spot(s) if s.cutoff() == 180.0 => point(&s.point, Geometry::Point(s.point.position)),
        Light::Spot(s) => point(
            &s.point,
            Geometry::Spot {
                position: s.point.position,
                cone: Cone {
                    direction: s.direction(),
                    cos_cutoff: (s.cutoff() as f64).to_radians().cos() as f32,
                    cos_inner: s
                        .inner()
                        .map_or(2.0, |i| (i as f64).to_radians().cos() as f32),
                    exponent: s.exponent(),
                },
            },
        ),
        Light::Area(_) => unreachable!("area lights are expanded by LightSet::new"),
    }
}

/// The point (or, one-sided, spot) lights an area light stands for: its sample points, each
/// with an equal share of its intensity and ambient.
pub(crate) fn area_points(a: &AreaLight) -> Vec<Light> {
    let share = 1.0 / a.n_points() as f32;
    let normal = a.normal();
    a.points()
        .into_iter()
        .map(|position| {
            let point = PointLight {
                position,
                color: a.color,
                intensity: a.intensity * share,
                ambient: a.ambient * share,
                attenuation: a.attenuation,
                split: a.split,
                shadows: a.shadows,
            };
            if a.one_sided() {
                // cutoff 90°, exponent 1: max(−l·(−n), 0) = cos of the emission angle.
                SpotLight::new(point, normal, 90.0, 1.0)
                    .expect("unit normal, cutoff 90 and exponent 1 are valid")
                    .into()
            } else {
                point.into()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::AreaShape;

    /// Fuzzing found a one-sided light with huge edges whose f32 normal overflowed to zero
    /// (`fuzz/seeds/pipeline/crash-area-light-normal-overflow`): `area_points` then
    /// panicked building its spot lights. Normals and the edge check are now in f64.
    #[test]
    fn huge_and_tiny_edges_have_a_unit_normal() {
        for scale in [1e-30f32, 1e-20, 1e20, 1e30, 3e38] {
            let light = AreaLight::new(
                Vec3::ZERO,
                Vec3::X * scale,
                Vec3::Y * scale,
                AreaShape::Rectangle,
                2,
            )
            .unwrap()
            .with_one_sided(true);
            assert_eq!(light.normal(), Vec3::Z, "scale {scale}");
            assert_eq!(area_points(&light).len(), 4);
        }
    }

    /// A light whose every colour is zero is dropped (it adds exactly nothing); a light with
    /// only an ambient colour, or only a specular one, is not.
    #[test]
    fn dark_lights_are_dropped() {
        use crate::lights::DirectionalLight;
        let dir = |c: Vec3| DirectionalLight::new(Vec3::NEG_Y, c, 1.0).unwrap();
        let black = dir(Vec3::ZERO);
        let ambient_only = dir(Vec3::ZERO).with_ambient(Vec3::splat(0.1)).unwrap();
        let lit = dir(Vec3::ONE);
        let set = LightSet::new(&[black.into(), ambient_only.into(), lit.into()]);
        assert_eq!(set.sources.len(), 2);
        assert_eq!(set.sources[0].ambient, Vec3::splat(0.1));
        assert_eq!(set.sources[1].diffuse, Vec3::ONE);
        let dark_area = rect(2).with_color(Vec3::ZERO, 1.0).unwrap();
        assert!(LightSet::new(&[dark_area.into()]).sources.is_empty());
        assert_eq!(LightSet::new(&[rect(2).into()]).sources.len(), 4);
    }

    fn rect(samples: u32) -> AreaLight {
        AreaLight::new(
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            AreaShape::Rectangle,
            samples,
        )
        .unwrap()
    }

    #[test]
    fn points_share_the_light() {
        let l = rect(3)
            .with_color(Vec3::new(1.0, 0.5, 0.25), 9.0)
            .unwrap()
            .with_ambient(Vec3::splat(0.9))
            .unwrap()
            .with_attenuation(1.0, 0.5, 0.0)
            .unwrap();
        let lights = area_points(&l);
        assert_eq!(lights.len(), 9);
        for light in lights {
            let Light::Point(p) = light else {
                panic!("two-sided points are point lights")
            };
            assert_eq!(p.intensity, 1.0);
            assert_eq!(p.color, Vec3::new(1.0, 0.5, 0.25));
            assert!((p.ambient - Vec3::splat(0.1)).abs().max_element() < 1e-7);
            assert_eq!(p.attenuation, [1.0, 0.5, 0.0]);
        }
        let one = rect(2).with_one_sided(true);
        assert_eq!(one.normal(), -Vec3::Y); // u × v = x × z = −y: emits downward
        for light in area_points(&one) {
            let Light::Spot(s) = light else {
                panic!("one-sided points are spots")
            };
            assert_eq!(
                (s.cutoff(), s.exponent(), s.direction()),
                (90.0, 1.0, -Vec3::Y)
            );
        }
    }
}
