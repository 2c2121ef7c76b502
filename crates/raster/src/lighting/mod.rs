//! The lighting room: the classic local illumination model and nothing else.
//!
//! - [`LightSet`]: the scene's lights prepared once per render (area lights expanded into
//!   their point sources), independent of any material;
//! - [`Surface`]: a material folded with a light set (the fast path for surfaces whose
//!   material does not vary), or a unit surface whose terms stay apart;
//! - the equation itself, written once over [`LANES`] points ([`Surface::terms_lanes`]),
//!   into a [`Terms`] target: [`Folded`] (one colour) or [`Split`] (ambient, diffuse and
//!   specular apart); one point is one lane ([`Surface::shade`]);
//! - the spot factor (`spot::Cone`) and the branch-free power (`pow01`).
//!
//! The pipeline calls this room; this room knows nothing of the pipeline.

mod equation;
mod lanes;
mod light_set;
mod pow;
mod spot;
mod surface;
mod visible;

#[allow(unused_imports)] // the split target is for per-point materials (textures)
pub(crate) use equation::{Folded, Split, Terms};
pub(crate) use lanes::{lane, normalize_lanes, set_lane, Lanes, LANES};
pub(crate) use light_set::{Geometry, LightSet, Source};
pub(crate) use pow::pow01;
pub(crate) use surface::{check_mirror, Surface};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::{DirectionalLight, Light, PointLight, SpotLight};
    use crate::material::Material;
    use crate::options::SpecularModel;
    use glam::Vec3;

    fn fold(m: &Material, ambient: Vec3, lights: &[Light], model: SpecularModel) -> Surface {
        Surface::folded(m, ambient, &LightSet::new(lights), model)
    }

    #[test]
    fn attenuation_emission_and_light_ambient_hand_computed() {
        // Light 2 units above the point: d = 2, att = 1 / (0.5 + 0.25·2 + 0.125·4) = 2/3.
        let light = PointLight::new(Vec3::new(0.0, 0.0, 2.0), Vec3::ONE, 3.0)
            .unwrap()
            .with_attenuation(0.5, 0.25, 0.125)
            .unwrap()
            .with_ambient(Vec3::splat(0.3))
            .unwrap();
        let sun = DirectionalLight::new(Vec3::X, Vec3::ONE, 1.0) // grazing: n·l = 0
            .unwrap()
            .with_ambient(Vec3::splat(0.1))
            .unwrap();
        let m = Material::new(Vec3::splat(0.5), Vec3::splat(0.4), Vec3::ZERO, 1.0)
            .unwrap()
            .with_emission(Vec3::new(0.01, 0.02, 0.03))
            .unwrap();
        let pm = fold(
            &m,
            Vec3::splat(0.2),
            &[light.into(), sun.into()],
            SpecularModel::BlinnPhong,
        );
        let c = pm.shade(Vec3::Z, Vec3::ZERO, Vec3::new(0.0, 0.0, 5.0));
        let att = 2.0 / 3.0;
        // ke + ka·Ia + ka·Ia_sun + att·(ka·Ia_point + kd·Id·1)
        let want = Vec3::new(0.01, 0.02, 0.03)
            + Vec3::splat(0.5 * 0.2 + 0.5 * 0.1 + att * (0.5 * 0.3 + 0.4 * 3.0));
        assert!((c - want).abs().max_element() < 1e-6, "{c} vs {want}");
        // Light exactly at the surface with kc = 0: large but finite.
        let at = PointLight::new(Vec3::ZERO, Vec3::ONE, 1.0)
            .unwrap()
            .with_attenuation(0.0, 0.0, 1.0)
            .unwrap();
        let pm = fold(&m, Vec3::ZERO, &[at.into()], SpecularModel::BlinnPhong);
        assert!(pm.shade(Vec3::Z, Vec3::ZERO, Vec3::Z).is_finite());
    }

    #[test]
    fn area_light_shades_as_its_point_sources() {
        use crate::lights::{AreaLight, AreaShape};
        let m = Material::preset("gold").unwrap();
        let area = AreaLight::new(
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::X,
            Vec3::Y,
            AreaShape::Rectangle,
            2,
        )
        .unwrap()
        .with_color(Vec3::new(1.0, 0.9, 0.8), 4.0)
        .unwrap();
        let points: Vec<Light> = [(-0.25, -0.25), (0.25, -0.25), (-0.25, 0.25), (0.25, 0.25)]
            .map(|(x, y)| {
                PointLight::new(Vec3::new(x, y, 2.0), Vec3::new(1.0, 0.9, 0.8), 1.0)
                    .unwrap()
                    .into()
            })
            .to_vec();
        let a = fold(&m, Vec3::splat(0.2), &[area.into()], SpecularModel::Phong);
        let b = fold(&m, Vec3::splat(0.2), &points, SpecularModel::Phong);
        let eye = Vec3::new(0.3, 0.2, 3.0);
        for p in [Vec3::ZERO, Vec3::new(0.4, -0.3, 0.1)] {
            let n = Vec3::new(0.1, 0.2, 1.0).normalize();
            assert_eq!(a.shade(n, p, eye), b.shade(n, p, eye));
        }
        // One-sided: the same light seen from behind (n faces the back) gives no direct light,
        // and in front each point is scaled by the cosine of its emission angle: a point on
        // the axis far away gets ≈ the unscaled light.
        let one = area.with_one_sided(true); // normal x × y = +z: emits upward
        let pm = fold(&m, Vec3::ZERO, &[one.into()], SpecularModel::Phong);
        let below = pm.shade(Vec3::Z, Vec3::ZERO, eye);
        assert_eq!(below, m.emission);
        let above = Vec3::new(0.0, 0.0, 1e3);
        let lit = pm.shade(-Vec3::Z, above, above + Vec3::Z);
        let two = fold(&m, Vec3::ZERO, &[area.into()], SpecularModel::Phong);
        let both = two.shade(-Vec3::Z, above, above + Vec3::Z);
        assert!(
            (lit - both).abs().max_element() < 1e-6 * both.max_element(),
            "{lit} {both}"
        );
    }

    /// The perfect mirror (`shininess = inf`): the whole lobe where `n·h` is exactly 1, none
    /// a hair away; refused with the normalised lobe unless there is no specular term.
    #[test]
    fn infinite_shininess_is_the_mirror_step() {
        let l: Light = DirectionalLight::new(-Vec3::Z, Vec3::ONE, 1.0)
            .unwrap()
            .into();
        let m = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::ONE, f32::INFINITY).unwrap();
        for model in [SpecularModel::BlinnPhong, SpecularModel::Phong] {
            let s = fold(&m, Vec3::ZERO, &[l], model).with_infinite_viewer(Vec3::Z);
            assert_eq!(
                s.shade(Vec3::Z, Vec3::ZERO, Vec3::Z),
                Vec3::ONE,
                "{model:?}"
            );
            let tilted = Vec3::new(1e-3, 0.0, 1.0).normalize();
            assert_eq!(
                s.shade(tilted, Vec3::ZERO, Vec3::Z),
                Vec3::ZERO,
                "{model:?}"
            );
            assert!(s.max_value().is_finite());
        }
        assert!(check_mirror(&m, SpecularModel::BlinnPhong).is_ok());
        let e = check_mirror(&m, SpecularModel::NormalizedBlinnPhong).unwrap_err();
        assert!(e.to_string().contains("blinn-normalized"), "{e}");
        let dull = Material::new(Vec3::ONE, Vec3::ONE, Vec3::ZERO, f32::INFINITY).unwrap();
        assert!(check_mirror(&dull, SpecularModel::NormalizedBlinnPhong).is_ok());
        let folded = fold(&dull, Vec3::ZERO, &[l], SpecularModel::NormalizedBlinnPhong);
        assert!(folded.max_value().is_finite());
        assert!(Material::new(Vec3::ONE, Vec3::ONE, Vec3::ONE, f32::NEG_INFINITY).is_err());
        assert!(Material::new(Vec3::ONE, Vec3::ONE, Vec3::ONE, f32::NAN).is_err());
    }

    #[test]
    fn normalized_blinn_scales_the_lobe_by_f_plus_8_over_8_pi() {
        let l: Light = DirectionalLight::new(-Vec3::Z, Vec3::ONE, 1.0)
            .unwrap()
            .into();
        for f in [1.0f32, 32.0, 512.0] {
            let m = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::ONE, f).unwrap();
            let plain = fold(&m, Vec3::ZERO, &[l], SpecularModel::BlinnPhong);
            let norm = fold(&m, Vec3::ZERO, &[l], SpecularModel::NormalizedBlinnPhong);
            let (n, eye) = (
                Vec3::new(0.1, 0.0, 1.0).normalize(),
                Vec3::new(0.0, 0.0, 4.0),
            );
            let ratio = norm.shade(n, Vec3::ZERO, eye).x / plain.shade(n, Vec3::ZERO, eye).x;
            let want = (f + 8.0) / (8.0 * std::f32::consts::PI);
            assert!(
                (ratio - want).abs() < 1e-5 * want,
                "f = {f}: {ratio} vs {want}"
            );
        }
    }

    #[test]
    fn spot_cone_edge_hand_computed() {
        // Spot 2 above the plane z = 0 pointing down, cutoff 30°, exponent 2. At (x, 0, 0),
        // cos(angle) = 2 / sqrt(x² + 4): inside the cone for x ≤ 2·tan 30° = 1.1547.
        let point = PointLight::new(Vec3::new(0.0, 0.0, 2.0), Vec3::ONE, 1.0).unwrap();
        let spot = SpotLight::new(point, -Vec3::Z, 30.0, 2.0).unwrap();
        let m = Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ZERO, 1.0).unwrap();
        let pm = fold(&m, Vec3::ZERO, &[spot.into()], SpecularModel::BlinnPhong);
        let eye = Vec3::new(0.0, 0.0, 5.0);
        for (x, inside) in [(0.0f32, true), (1.15, true), (1.16, false), (3.0, false)] {
            let c = pm.shade(Vec3::Z, Vec3::new(x, 0.0, 0.0), eye).x;
            let cos = 2.0 / (x * x + 4.0).sqrt();
            let want = if inside { cos * cos * cos } else { 0.0 }; // spot cos² × n·l = cos
            assert!((c - want).abs() < 1e-5, "x = {x}: {c} vs {want}");
        }
        // A 180° cutoff is a plain point light, whatever the exponent.
        let flood = SpotLight::new(point, -Vec3::Z, 180.0, 50.0).unwrap();
        let a = fold(&m, Vec3::ZERO, &[flood.into()], SpecularModel::BlinnPhong);
        let b = fold(&m, Vec3::ZERO, &[point.into()], SpecularModel::BlinnPhong);
        let q = Vec3::new(5.0, 0.0, 0.0);
        assert_eq!(a.shade(Vec3::Z, q, eye), b.shade(Vec3::Z, q, eye));
        // Smooth edge: full inside the inner cone, 0 at the cutoff, in between monotone.
        let soft = spot.with_inner(20.0).unwrap();
        let pm = fold(&m, Vec3::ZERO, &[soft.into()], SpecularModel::BlinnPhong);
        let at = |deg: f32| {
            pm.shade(
                Vec3::Z,
                Vec3::new(2.0 * deg.to_radians().tan(), 0.0, 0.0),
                eye,
            )
            .x
        };
        let cos = |deg: f32| deg.to_radians().cos();
        assert!((at(10.0) - cos(10.0).powi(3)).abs() < 1e-5);
        assert!(at(29.99) < 1e-3 && at(25.0) < cos(25.0).powi(3) && at(25.0) > 0.0);
    }

    fn mat() -> Material {
        Material::new(
            Vec3::new(0.1, 0.2, 0.3),
            Vec3::new(0.5, 0.6, 0.7),
            Vec3::new(0.25, 0.25, 0.25),
            10.0,
        )
        .unwrap()
    }

    #[test]
    fn head_on_directional_is_ambient_plus_diffuse_plus_specular() {
        let l: Light = DirectionalLight::new(-Vec3::Z, Vec3::ONE, 1.0)
            .unwrap()
            .into();
        let pm = fold(&mat(), Vec3::splat(0.5), &[l], SpecularModel::BlinnPhong);
        let c = pm.shade(Vec3::Z, Vec3::ZERO, Vec3::new(0.0, 0.0, 3.0));
        let want = Vec3::new(0.05, 0.1, 0.15) + Vec3::new(0.5, 0.6, 0.7) + Vec3::splat(0.25);
        assert!((c - want).abs().max_element() < 1e-6, "{c} vs {want}");
    }

    #[test]
    fn oblique_point_light_hand_computed() {
        // Light at (1,0,1) over the origin, eye at (0,0,1): l = (1,0,1)/√2, v = (0,0,1).
        let l: Light = PointLight::new(Vec3::new(1.0, 0.0, 1.0), Vec3::ONE, 2.0)
            .unwrap()
            .into();
        let m = mat();
        let eye = Vec3::Z;
        let s2 = std::f32::consts::FRAC_1_SQRT_2;
        let n_dot_l = s2;
        // Blinn: h = normalize(l + v); n·h = cos(22.5°)
        let nh = (std::f32::consts::PI / 8.0).cos();
        let blinn = fold(&m, Vec3::ZERO, &[l], SpecularModel::BlinnPhong);
        let want = m.diffuse * 2.0 * n_dot_l + m.specular * 2.0 * nh.powf(10.0);
        assert!(
            (blinn.shade(Vec3::Z, Vec3::ZERO, eye) - want)
                .abs()
                .max_element()
                < 1e-5
        );
        // Phong: r = (−1,0,1)/√2, r·v = 1/√2.
        let phong = fold(&m, Vec3::ZERO, &[l], SpecularModel::Phong);
        let want = m.diffuse * 2.0 * n_dot_l + m.specular * 2.0 * s2.powf(10.0);
        assert!(
            (phong.shade(Vec3::Z, Vec3::ZERO, eye) - want)
                .abs()
                .max_element()
                < 1e-5
        );
    }

    #[test]
    fn no_light_from_behind_and_no_nan() {
        let l: Light = DirectionalLight::new(Vec3::Z, Vec3::ONE, 1.0)
            .unwrap()
            .into();
        let m = Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ONE, 0.0).unwrap();
        let pm = fold(&m, Vec3::ZERO, &[l], SpecularModel::BlinnPhong);
        assert_eq!(pm.shade(Vec3::Z, Vec3::ZERO, Vec3::Z), Vec3::ZERO);
        // Zero normal, eye on the surface, light at the point: finite.
        let pl: Light = PointLight::new(Vec3::ZERO, Vec3::ONE, 1.0).unwrap().into();
        let pm = fold(&m, Vec3::ZERO, &[pl, l], SpecularModel::BlinnPhong);
        assert!(pm.shade(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO).is_finite());
        assert!(pm.shade(Vec3::Z, Vec3::ZERO, Vec3::ZERO).is_finite());
    }

    /// One light of every kind: a spot with an inner cone and its own ambient, an attenuated
    /// point light with ambient, a plain point light and a directional one.
    fn every_light_kind() -> Vec<Light> {
        vec![
            SpotLight::new(
                PointLight::new(Vec3::new(0.5, 2.0, 0.5), Vec3::ONE, 2.0)
                    .unwrap()
                    .with_ambient(Vec3::splat(0.1))
                    .unwrap(),
                Vec3::new(-0.2, -1.0, -0.1),
                60.0,
                3.0,
            )
            .unwrap()
            .with_inner(30.0)
            .unwrap()
            .into(),
            PointLight::new(Vec3::new(-1.0, 1.0, 2.0), Vec3::new(0.9, 0.8, 0.7), 2.0)
                .unwrap()
                .with_attenuation(0.5, 0.2, 0.1)
                .unwrap()
                .with_ambient(Vec3::splat(0.2))
                .unwrap()
                .into(),
            PointLight::new(Vec3::new(2.0, 3.0, 4.0), Vec3::new(0.4, 0.4, 0.5), 1.0)
                .unwrap()
                .into(),
            DirectionalLight::new(Vec3::new(-1.0, -0.5, -1.0), Vec3::new(1.0, 0.9, 0.8), 1.0)
                .unwrap()
                .with_ambient(Vec3::splat(0.05))
                .unwrap()
                .into(),
        ]
    }

    #[test]
    #[allow(clippy::needless_range_loop)] // lanes of several arrays
    fn split_terms_recombine_to_the_folded_colour() {
        // Every light kind; a unit surface's ambient, diffuse and specular, weighed by the
        // material, give the folded colour (up to the order of float additions).
        let lights = every_light_kind();
        let m = Material::preset("brass")
            .unwrap()
            .with_emission(Vec3::new(0.1, 0.0, 0.05))
            .unwrap();
        let set = LightSet::new(&lights);
        let eye = Vec3::new(0.2, 0.3, 3.0);
        let mut n = [[0.0; LANES]; 3];
        let mut p = [[0.0; LANES]; 3];
        for k in 0..LANES {
            let a = k as f32 * 0.9;
            let nn = Vec3::new(a.cos(), 0.3, a.sin()).normalize();
            let pp = Vec3::new(a.sin(), 0.1 * k as f32, a.cos());
            for ax in 0..3 {
                n[ax][k] = nn[ax];
                p[ax][k] = pp[ax];
            }
        }
        for model in [
            SpecularModel::BlinnPhong,
            SpecularModel::Phong,
            SpecularModel::NormalizedBlinnPhong,
        ] {
            let folded = Surface::folded(&m, Vec3::splat(0.2), &set, model);
            let unit = Surface::unit(&m, Vec3::splat(0.2), &set, model);
            let c = folded.shade_lanes(&n, &p, eye);
            let t: Split = unit.terms_lanes(&n, &p, eye);
            for k in 0..LANES {
                for ch in 0..3 {
                    let want = m.emission[ch]
                        + m.ambient[ch] * t.ambient[ch][k]
                        + m.diffuse[ch] * t.diffuse[ch][k]
                        + m.specular[ch] * t.specular[ch][k];
                    assert!(
                        (c[ch][k] - want).abs() < 1e-6,
                        "{model:?} lane {k} channel {ch}: {} vs {want}",
                        c[ch][k]
                    );
                }
            }
        }
    }
    #[test]
    fn wide_lanes_give_the_same_bits() {
        // The AVX2 + FMA copy of the out-of-line loops (point and spot lights) against the
        // baseline one: every light kind, local and infinite viewer, every model,
        // folded and split terms, bit for bit. On a CPU without AVX2 both are the baseline.
        let lights = every_light_kind();
        let set = LightSet::new(&lights);
        let m = Material::preset("gold").unwrap();
        let eye = Vec3::new(0.2, 0.3, 3.0);
        let bits = |c: &[Lanes; 3]| c.map(|ch| ch.map(f32::to_bits));
        let wide_cpu = Surface::folded(&m, Vec3::ZERO, &set, SpecularModel::BlinnPhong)
            .with_wide_lanes(true)
            .wide();
        #[cfg(target_arch = "x86_64")]
        assert_eq!(
            wide_cpu,
            std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
        );
        assert!(!Surface::folded(&m, Vec3::ZERO, &set, SpecularModel::Phong)
            .with_wide_lanes(false)
            .wide());
        for seed in 0..50 {
            let mut n = [[0.0; LANES]; 3];
            let mut p = [[0.0; LANES]; 3];
            for k in 0..LANES {
                let a = (seed * LANES + k) as f32 * 0.37;
                let nn = Vec3::new(a.cos(), (0.7 * a).sin(), a.sin()).normalize();
                let pp = Vec3::new(a.sin(), 0.1 * k as f32 - 0.3, (1.3 * a).cos());
                set_lane(&mut n, k, nn);
                set_lane(&mut p, k, pp);
            }
            for model in [
                SpecularModel::BlinnPhong,
                SpecularModel::Phong,
                SpecularModel::NormalizedBlinnPhong,
            ] {
                for infinite in [false, true] {
                    let make = |unit: bool, wide: bool| {
                        let s = if unit {
                            Surface::unit(&m, Vec3::splat(0.2), &set, model)
                        } else {
                            Surface::folded(&m, Vec3::splat(0.2), &set, model)
                        };
                        let s = s.with_wide_lanes(wide);
                        if infinite {
                            s.with_infinite_viewer(Vec3::new(0.1, 0.2, 1.0))
                        } else {
                            s
                        }
                    };
                    let (a, b) = (make(false, false), make(false, true));
                    assert_eq!(
                        bits(&a.shade_lanes(&n, &p, eye)),
                        bits(&b.shade_lanes(&n, &p, eye)),
                        "{model:?} infinite {infinite} seed {seed}"
                    );
                    let (a, b) = (make(true, false), make(true, true));
                    let (ta, tb): (Split, Split) =
                        (a.terms_lanes(&n, &p, eye), b.terms_lanes(&n, &p, eye));
                    for (x, y) in [
                        (&ta.ambient, &tb.ambient),
                        (&ta.diffuse, &tb.diffuse),
                        (&ta.specular, &tb.specular),
                    ] {
                        assert_eq!(bits(x), bits(y), "{model:?} split, seed {seed}");
                    }
                }
            }
        }
    }
}
