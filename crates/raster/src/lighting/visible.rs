//! The equation with a visibility per light and lane (shadows): each shadowed light's
//! diffuse and specular are scaled by its visibility, its ambient is not. A light without a
//! visibility (`None`) is evaluated exactly as in [`Surface::terms_lanes`]: both are the one
//! lane loop of `equation.rs`, which scenes without shadows compile with `AllVisible`, so
//! their loops carry no visibility code.

use glam::Vec3;

use super::equation::{Terms, WithShininess};
use super::lanes::Lanes;
use super::surface::Surface;

impl Surface {
    /// The terms of [`LANES`](super::LANES) points into `T`, light `i`'s diffuse and specular scaled by
    /// `visibility[i]` per lane when it is `Some` (one entry per light of the surface).
    #[inline(always)]
    pub fn terms_lanes_visible<T: Terms>(
        &self,
        n: &[Lanes; 3],
        p: &[Lanes; 3],
        eye: Vec3,
        visibility: &[Option<Lanes>],
    ) -> T {
        self.terms_lanes_with(n, p, eye, visibility)
    }

    /// [`Surface::terms_lanes_visible`] with the specular exponent `shininess` per lane (a
    /// shininess map) instead of the surface's; `visibility` may be empty (no shadows).
    #[inline(always)]
    pub fn terms_lanes_shininess<T: Terms>(
        &self,
        n: &[Lanes; 3],
        p: &[Lanes; 3],
        eye: Vec3,
        visibility: &[Option<Lanes>],
        shininess: &Lanes,
    ) -> T {
        let per_point = WithShininess {
            visibility,
            shininess,
        };
        self.terms_lanes_with(n, p, eye, per_point)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{normalize_lanes, Folded, LightSet, Split, LANES};
    use super::*;
    use crate::lights::{DirectionalLight, Light, PointLight, SpotLight};
    use crate::material::Material;
    use crate::options::SpecularModel;

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn visibility_scales_diffuse_and_specular_not_ambient() {
        let lights: Vec<Light> = vec![
            DirectionalLight::new(Vec3::new(-0.3, -1.0, -0.2), Vec3::ONE, 1.0)
                .unwrap()
                .with_ambient(Vec3::splat(0.1))
                .unwrap()
                .into(),
            PointLight::new(Vec3::new(0.5, 2.0, 1.0), Vec3::new(0.9, 0.8, 0.7), 2.0)
                .unwrap()
                .with_attenuation(1.0, 0.2, 0.0)
                .unwrap()
                .with_ambient(Vec3::splat(0.2))
                .unwrap()
                .into(),
            SpotLight::new(
                PointLight::new(Vec3::new(0.0, 3.0, 0.0), Vec3::ONE, 1.0).unwrap(),
                -Vec3::Y,
                60.0,
                1.0,
            )
            .unwrap()
            .into(),
        ];
        let m = Material::preset("brass").unwrap();
        let set = LightSet::new(&lights);
        let unit = Surface::unit(&m, Vec3::splat(0.2), &set, SpecularModel::BlinnPhong);
        let folded = Surface::folded(&m, Vec3::splat(0.2), &set, SpecularModel::BlinnPhong);
        let n = [[0.1; LANES], [1.0; LANES], [0.05; LANES]];
        let mut nn = [[0.0; LANES]; 3];
        normalize_lanes(&mut nn, &n, false);
        let p = [[0.0; LANES], [0.0; LANES], [0.3; LANES]];
        let eye = Vec3::new(0.0, 1.0, 4.0);
        let vis: Lanes = std::array::from_fn(|k| k as f32 / (LANES - 1) as f32);
        // All visible (None or ones) is the plain evaluation.
        let plain = folded.shade_lanes(&nn, &p, eye);
        let none: Folded = folded.terms_lanes_visible(&nn, &p, eye, &[None, None, None]);
        assert_eq!(none.0, plain);
        let ones: Folded = folded.terms_lanes_visible(&nn, &p, eye, &[Some([1.0; LANES]); 3]);
        for ch in 0..3 {
            for k in 0..LANES {
                assert!((ones.0[ch][k] - plain[ch][k]).abs() < 1e-6);
            }
        }
        // Each light alone at visibility `vis`: ambient unchanged, diffuse and specular
        // scaled by `vis` per lane.
        let all: Split = unit.terms_lanes_visible(&nn, &p, eye, &[None, None, None]);
        for i in 0..3 {
            let mut v = [None, None, None];
            v[i] = Some(vis);
            let t: Split = unit.terms_lanes_visible(&nn, &p, eye, &v);
            let mut only = [None, None, None];
            only[i] = Some([0.0; LANES]);
            let dark: Split = unit.terms_lanes_visible(&nn, &p, eye, &only);
            for ch in 0..3 {
                for k in 0..LANES {
                    assert_eq!(t.ambient[ch][k], all.ambient[ch][k]);
                    let lit_d = all.diffuse[ch][k] - dark.diffuse[ch][k];
                    let want = dark.diffuse[ch][k] + vis[k] * lit_d;
                    assert!((t.diffuse[ch][k] - want).abs() < 1e-5, "light {i}");
                    let lit_s = all.specular[ch][k] - dark.specular[ch][k];
                    let want = dark.specular[ch][k] + vis[k] * lit_s;
                    assert!((t.specular[ch][k] - want).abs() < 1e-5, "light {i}");
                }
            }
            assert!(lit_sum(&all) > lit_sum(&dark), "light {i} lights the point");
        }
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn per_lane_shininess_is_a_surface_of_that_shininess() {
        let lights: Vec<Light> = vec![
            DirectionalLight::new(Vec3::new(-0.3, -1.0, -0.2), Vec3::ONE, 1.0)
                .unwrap()
                .into(),
            PointLight::new(Vec3::new(0.5, 2.0, 1.0), Vec3::ONE, 2.0)
                .unwrap()
                .with_attenuation(1.0, 0.2, 0.0)
                .unwrap()
                .into(),
        ];
        let set = LightSet::new(&lights);
        let n = [[0.1; LANES], [1.0; LANES], [0.05; LANES]];
        let mut nn = [[0.0; LANES]; 3];
        normalize_lanes(&mut nn, &n, false);
        let p = [[0.0; LANES], [0.0; LANES], [0.3; LANES]];
        let eye = Vec3::new(0.0, 1.0, 4.0);
        let f: Lanes = std::array::from_fn(|k| 5.0 * (k + 1) as f32);
        for model in [SpecularModel::BlinnPhong, SpecularModel::Phong] {
            let mut m = Material::preset("brass").unwrap();
            let unit = Surface::unit(&m, Vec3::splat(0.2), &set, model);
            let got: Split = unit.terms_lanes_shininess(&nn, &p, eye, &[], &f);
            for k in 0..LANES {
                m.shininess = f[k];
                let want: Split =
                    Surface::unit(&m, Vec3::splat(0.2), &set, model).terms_lanes(&nn, &p, eye);
                for ch in 0..3 {
                    assert_eq!(got.specular[ch][k], want.specular[ch][k], "lane {k}");
                    assert_eq!(got.diffuse[ch][k], want.diffuse[ch][k]);
                }
            }
        }
    }

    fn lit_sum(s: &Split) -> f32 {
        s.diffuse.iter().flatten().sum::<f32>() + s.specular.iter().flatten().sum::<f32>()
    }
}
