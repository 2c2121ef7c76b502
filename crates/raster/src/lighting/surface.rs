//! A surface under a render's lights: a material folded with the [`LightSet`] once per render
//! (`kd·Id`, `ks·Is`, the constant ambient terms), or the light set alone with a unit
//! material, whose terms stay apart for effects that change the material or a light per
//! point (textures, shadows, reflections).

use glam::Vec3;

use super::light_set::{Geometry, LightSet};
use crate::error::{RasterError, Result};
use crate::lights::MIN_ATTENUATION_DENOMINATOR;
use crate::material::Material;
use crate::options::SpecularModel;

/// One source as a surface sees it: its colours already multiplied by the material's.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SurfaceLight {
    pub geometry: Geometry,
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// `ka·Ia_i` of an attenuated or spot light, scaled per point (the others' is folded into
    /// [`Surface::base`], and this is zero).
    pub ambient: Vec3,
    pub attenuation: Option<[f32; 3]>,
}

/// A material (or the unit material) combined with a render's lights.
#[derive(Debug, Clone)]
pub(crate) struct Surface {
    /// `ke + ka·Ia + Σ ka·Ia_i` of the sources not scaled per point.
    pub base: Vec3,
    pub lights: Vec<SurfaceLight>,
    pub shininess: f32,
    pub specular_on: bool,
    pub model: SpecularModel,
    /// Infinite viewer: the constant unit view vector; `None` for the local viewer.
    pub infinite_view: Option<Vec3>,
    /// The lane loops kept out of line (point and spot lights, `point_lanes`) run their
    /// copy compiled for AVX2 + FMA: only ever true on a CPU that has them
    /// ([`Surface::with_wide_lanes`]).
    wide: bool,
}

/// Refuses the normalised Blinn-Phong lobe with an infinite shininess: its scale
/// `(f + 8) / 8π` is infinite (a zero-width lobe of finite energy, a Dirac, which a rasterizer
/// cannot show). Materials without a specular term have no lobe and pass.
pub(crate) fn check_mirror(material: &Material, model: SpecularModel) -> Result<()> {
    if model == SpecularModel::NormalizedBlinnPhong
        && material.shininess.is_infinite()
        && material.has_specular()
    {
        return Err(RasterError::invalid_field(
            "shininess",
            "shininess=inf (a perfect mirror) cannot be used with specular='blinn-normalized': \
             its scale (f + 8)/8π is infinite; use 'blinn' or 'phong', or a finite shininess"
                .to_string(),
        ));
    }
    Ok(())
}

impl Surface {
    /// Folds `material` with the scene ambient `ambient` and the sources of `set`.
    pub fn folded(
        material: &Material,
        ambient: Vec3,
        set: &LightSet,
        model: SpecularModel,
    ) -> Self {
        // c = ke + ka·Ia + Σ att·[ka·Ia_i + ...]: constant terms are summed once here.
        // The normalised lobe's (f + 8)/8π is a constant too: folded into ks·Is.
        // An infinite shininess with it is refused by `check_mirror`; without a specular
        // term the lobe is absent, and its (infinite) scale is not folded (0 · inf = NaN).
        let spec_scale = match model {
            SpecularModel::NormalizedBlinnPhong if material.shininess.is_finite() => {
                ((material.shininess as f64 + 8.0) / (8.0 * std::f64::consts::PI)) as f32
            }
            _ => 1.0,
        };
        let mut base = material.emission + material.ambient * ambient;
        let lights = set
            .sources
            .iter()
            .map(|s| {
                let scaled = s.scaled();
                let light_ambient = material.ambient * s.ambient;
                if !scaled {
                    base += light_ambient;
                }
                SurfaceLight {
                    geometry: s.geometry,
                    diffuse: material.diffuse * s.diffuse,
                    specular: material.specular * s.specular * spec_scale,
                    ambient: if scaled { light_ambient } else { Vec3::ZERO },
                    attenuation: s.attenuation,
                }
            })
            .collect();
        Surface {
            base,
            lights,
            // pow01(x, f32::MAX) is exactly [x ≥ 1] for every f32 x ≤ 1 (the largest x < 1
            // has log2 x ≈ -8.6e-8, times f32::MAX far below the -126 cut-off), which is the
            // perfect mirror's lobe; pow01(1, inf) would be inf · 0 = NaN.
            shininess: if material.shininess.is_finite() {
                material.shininess
            } else {
                f32::MAX
            },
            specular_on: material.has_specular(),
            model,
            infinite_view: None,
            wide: false,
        }
    }

    /// The unit material (`ka = kd = ks = 1`, no emission; `material`'s shininess and whether
    /// it has a specular term) folded with `set`: [`super::Split`] terms of this surface are
    /// `Ia + Σ att·Ia_i`, `Σ att·Id·max(n·l, 0)` and `Σ att·Is·S`, for a per-point material
    /// (a texture) to weigh: `c = ke + ka·A + kd·D + ks·S`.
    #[allow(dead_code)] // with `Split`: the texture stage's surface
    pub fn unit(material: &Material, ambient: Vec3, set: &LightSet, model: SpecularModel) -> Self {
        let unit = Material {
            ambient: Vec3::ONE,
            diffuse: Vec3::ONE,
            specular: if material.has_specular() {
                Vec3::ONE
            } else {
                Vec3::ZERO
            },
            emission: Vec3::ZERO,
            ..*material
        };
        Surface::folded(&unit, ambient, set, model)
    }

    /// Uses an infinite viewer (OpenGL's `GL_LIGHT_MODEL_LOCAL_VIEWER` off): `v` is the
    /// constant unit vector `toward_eye` instead of the direction from each point to the eye.
    pub fn with_infinite_viewer(mut self, toward_eye: Vec3) -> Self {
        self.infinite_view = Some(toward_eye.normalize_or_zero());
        self
    }

    /// Runs the out-of-line lane loops in their AVX2 + FMA copy when `wide` and the CPU has
    /// both (else the baseline one): the same bits either way (no fused multiply-adds are
    /// formed; see `pipeline/isa.rs`). The tile bodies and vertex lighting that call them
    /// are compiled for AVX2 already, but a function they do not inline is compiled once,
    /// for the baseline: point lights were lit four lanes at a time in SSE2.
    pub fn with_wide_lanes(mut self, wide: bool) -> Self {
        self.wide = wide && cpu_has_avx2_fma();
        self
    }

    /// Whether [`Surface::with_wide_lanes`] chose the AVX2 + FMA copies.
    #[inline(always)]
    pub(crate) fn wide(&self) -> bool {
        self.wide
    }

    /// An upper bound (in f64) on every channel the surface can reach: the constant terms
    /// plus, per light, its largest attenuation (`1 / max(kc, MIN_ATTENUATION_DENOMINATOR)`)
    /// times its ambient, diffuse and specular colours (spot factors, `n·l` and the specular
    /// power are at most 1). Infinite when folding already overflowed (or met `0·inf`).
    pub fn max_value(&self) -> f64 {
        // A folded term that overflowed is inf, or NaN where it met a zero (0·inf): both
        // make the bound infinite (`max_element` would skip a NaN).
        let max = |v: Vec3| {
            if v.is_finite() {
                v.max_element() as f64
            } else {
                f64::INFINITY
            }
        };
        let lights: f64 = self
            .lights
            .iter()
            .map(|l| {
                let att = l.attenuation.map_or(1.0, |k| {
                    1.0 / (k[0] as f64).max(MIN_ATTENUATION_DENOMINATOR as f64)
                });
                att * (max(l.ambient) + max(l.diffuse) + max(l.specular))
            })
            .sum();
        max(self.base) + lights
    }
}

/// Whether this CPU runs AVX2 and FMA (the standard library caches the answer).
fn cpu_has_avx2_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}
