//! The lighting equation (OpenGL 2.1 §2.14.1 with the local viewer on).
//!
//! For one surface point with unit normal `n`, position `p` and the eye at `e`:
//!
//! ```text
//! c = ka·Ia + Σ_i [ kd·Id_i·max(n·l_i, 0) + ks·Is_i·S_i ]        S_i = 0 unless n·l_i > 0
//! Blinn-Phong: S = max(n·h, 0)^f, h = normalize(l + v)      Phong: S = max(r·v, 0)^f, r = 2(n·l)n − l
//! ```
//!
//! `v = normalize(e − p)`; `l` points from the surface to the light. The per-light products
//! `kd·Id` and `ks·Is` are folded once per (material, light) in [`PreparedMaterial`], and the
//! specular loop is skipped entirely when `ks = 0`.

use std::str::FromStr;

use glam::Vec3;

use crate::error::RasterError;
use crate::light::{Light, SpotLight, MIN_ATTENUATION_DENOMINATOR};
use crate::material::Material;

/// Where lighting is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShadingMode {
    /// One colour per triangle: face normal, lit at the centroid.
    Flat,
    /// Lit at the vertices, colours interpolated (perspective-correct).
    Gouraud,
    /// Normals and positions interpolated, renormalised and lit per pixel.
    Phong,
}

/// Which specular lobe.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpecularModel {
    /// `max(n·h, 0)^f` with the half vector (OpenGL's fixed function).
    BlinnPhong,
    /// Phong's own `max(r·v, 0)^f`.
    Phong,
    /// Blinn-Phong scaled by `(f + 8) / 8π`, so the highlight's total energy stays about the
    /// same as the shininess changes (sharper highlights get brighter peaks). The classic
    /// form's highlight instead dims as it narrows.
    NormalizedBlinnPhong,
}

impl FromStr for ShadingMode {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self, RasterError> {
        match s.to_ascii_lowercase().as_str() {
            "flat" => Ok(ShadingMode::Flat),
            "gouraud" => Ok(ShadingMode::Gouraud),
            "phong" => Ok(ShadingMode::Phong),
            _ => Err(RasterError::invalid(format!(
                "unknown shading mode '{s}'; expected 'flat', 'gouraud' or 'phong'"
            ))),
        }
    }
}

impl FromStr for SpecularModel {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self, RasterError> {
        match s.to_ascii_lowercase().as_str() {
            "blinn" | "blinn-phong" | "blinn_phong" => Ok(SpecularModel::BlinnPhong),
            "blinn-normalized" | "blinn_normalized" | "normalized-blinn" => {
                Ok(SpecularModel::NormalizedBlinnPhong)
            }
            "phong" => Ok(SpecularModel::Phong),
            _ => Err(RasterError::invalid(format!(
                "unknown specular model '{s}'; expected 'blinn', 'phong' or 'blinn-normalized'"
            ))),
        }
    }
}

#[derive(Debug, Clone, Copy)]
enum LightGeometry {
    /// Unit vector toward the light.
    Directional(Vec3),
    Point(Vec3),
    Spot {
        position: Vec3,
        /// Unit direction the cone points.
        direction: Vec3,
        cos_cutoff: f32,
        /// cos of the smooth edge's inner angle; > 1 when there is none.
        cos_inner: f32,
        exponent: f32,
    },
}

#[derive(Debug, Clone, Copy)]
struct PreparedLight {
    geometry: LightGeometry,
    diffuse: Vec3,
    specular: Vec3,
    /// `ka·Ia_i` of an attenuated or spot light, scaled per pixel (the others' is folded
    /// into `base`, and this is zero).
    ambient: Vec3,
    /// `(kc, kl, kq)` of an attenuated point light; `None` costs nothing per pixel.
    attenuation: Option<[f32; 3]>,
}

/// `1 / max(kc + kl·d + kq·d², MIN_ATTENUATION_DENOMINATOR)`.
#[inline(always)]
fn attenuation(k: [f32; 3], d: f32) -> f32 {
    1.0 / (k[0] + d * (k[1] + d * k[2])).max(MIN_ATTENUATION_DENOMINATOR)
}

/// A material combined with the scene's lights: everything constant per render folded once.
#[derive(Debug, Clone)]
pub struct PreparedMaterial {
    base: Vec3,
    lights: Vec<PreparedLight>,
    shininess: f32,
    specular_on: bool,
    model: SpecularModel,
    /// Infinite viewer: the constant unit view vector; `None` for the local viewer.
    infinite_view: Option<Vec3>,
}

impl PreparedMaterial {
    /// Folds `material`, the scene ambient `ambient` and `lights` for one render.
    pub fn new(material: &Material, ambient: Vec3, lights: &[Light], model: SpecularModel) -> Self {
        // c = ke + ka·Ia + Σ att·[ka·Ia_i + ...]: constant terms are summed once here.
        // The normalised lobe's (f + 8)/8π is a constant too: folded into ks·Is.
        let spec_scale = match model {
            SpecularModel::NormalizedBlinnPhong => {
                ((material.shininess as f64 + 8.0) / (8.0 * std::f64::consts::PI)) as f32
            }
            _ => 1.0,
        };
        let mut base = material.emission + material.ambient * ambient;
        let mut prepare = |l: &Light| {
            let point = |p: &crate::light::PointLight| {
                (
                    p.split.radiance(p.color, p.intensity),
                    p.ambient,
                    p.is_attenuated().then_some(p.attenuation),
                )
            };
            let (geometry, ((id, is), light_ambient, att)) = match l {
                Light::Directional(d) => (
                    LightGeometry::Directional(-d.direction()),
                    (d.split.radiance(d.color, d.intensity), d.ambient, None),
                ),
                Light::Point(p) => (LightGeometry::Point(p.position), point(p)),
                // OpenGL: a cutoff of 180 is no cone at all, whatever the exponent.
                Light::Spot(s) if s.cutoff() == 180.0 => {
                    (LightGeometry::Point(s.point.position), point(&s.point))
                }
                Light::Area(_) => unreachable!("area lights are expanded by the caller"),
                Light::Spot(s) => (
                    LightGeometry::Spot {
                        position: s.point.position,
                        direction: s.direction(),
                        cos_cutoff: (s.cutoff() as f64).to_radians().cos() as f32,
                        cos_inner: s
                            .inner()
                            .map_or(2.0, |i| (i as f64).to_radians().cos() as f32),
                        exponent: s.exponent(),
                    },
                    point(&s.point),
                ),
            };
            let per_pixel = att.is_some() || matches!(geometry, LightGeometry::Spot { .. });
            let light_ambient = material.ambient * light_ambient;
            if !per_pixel {
                base += light_ambient;
            }
            PreparedLight {
                geometry,
                diffuse: material.diffuse * id,
                specular: material.specular * is * spec_scale,
                ambient: if per_pixel { light_ambient } else { Vec3::ZERO },
                attenuation: att,
            }
        };
        let mut prepared = Vec::with_capacity(lights.len());
        for l in lights {
            match l {
                // An area light is its point sources: no per-pixel code of its own.
                Light::Area(a) => prepared.extend(a.point_lights().iter().map(&mut prepare)),
                _ => prepared.push(prepare(l)),
            }
        }
        let lights = prepared;
        PreparedMaterial {
            base,
            lights,
            shininess: material.shininess,
            specular_on: material.has_specular(),
            model,
            infinite_view: None,
        }
    }

    /// An upper bound (in f64) on every channel [`PreparedMaterial::shade`] can return: the
    /// constant terms plus, per light, its largest attenuation (`1 / max(kc, MIN_ATTENUATION_DENOMINATOR)`)
    /// times its ambient, diffuse and specular colours (spot factors, `n·l` and the
    /// specular power are at most 1). Infinite when folding the terms already overflowed
    /// (or met a zero as `0·inf = NaN`).
    pub(crate) fn max_value(&self) -> f64 {
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

    /// Uses an infinite viewer (OpenGL's `GL_LIGHT_MODEL_LOCAL_VIEWER` off): `v` is the
    /// constant unit vector `toward_eye` instead of the direction from each point to the eye.
    pub fn with_infinite_viewer(mut self, toward_eye: Vec3) -> Self {
        self.infinite_view = Some(toward_eye.normalize_or_zero());
        self
    }

    /// Colour at a point with unit (or zero) normal `n`, position `p`, eye `eye`.
    #[inline]
    pub fn shade(&self, n: Vec3, p: Vec3, eye: Vec3) -> Vec3 {
        if self.specular_on {
            match self.model {
                SpecularModel::BlinnPhong | SpecularModel::NormalizedBlinnPhong => {
                    self.shade_with::<true, true>(n, p, eye)
                }
                SpecularModel::Phong => self.shade_with::<true, false>(n, p, eye),
            }
        } else {
            self.shade_with::<false, true>(n, p, eye)
        }
    }

    #[inline(always)]
    fn shade_with<const SPECULAR: bool, const BLINN: bool>(
        &self,
        n: Vec3,
        p: Vec3,
        eye: Vec3,
    ) -> Vec3 {
        let mut c = self.base;
        let v = match (SPECULAR, self.infinite_view) {
            (false, _) => Vec3::ZERO,
            (true, Some(v)) => v,
            (true, None) => (eye - p).normalize_or_zero(),
        };
        for light in &self.lights {
            let (l, att) = match light.geometry {
                LightGeometry::Directional(l) => (l, 1.0),
                LightGeometry::Point(pos) => {
                    let to_light = pos - p;
                    let att = light
                        .attenuation
                        .map_or(1.0, |k| attenuation(k, to_light.length()));
                    (to_light.normalize_or_zero(), att)
                }
                LightGeometry::Spot {
                    position,
                    direction,
                    cos_cutoff,
                    cos_inner,
                    exponent,
                } => {
                    let to_light = position - p;
                    let l = to_light.normalize_or_zero();
                    let spot =
                        SpotLight::factor(-l.dot(direction), cos_cutoff, cos_inner, exponent);
                    let att = light
                        .attenuation
                        .map_or(1.0, |k| attenuation(k, to_light.length()));
                    (l, att * spot)
                }
            };
            c += light.ambient * att; // zero unless the light is attenuated or a spot
            let n_dot_l = n.dot(l);
            if n_dot_l > 0.0 {
                c += light.diffuse * (n_dot_l * att);
                if SPECULAR {
                    let s = if BLINN {
                        let h = l + v;
                        let len2 = h.length_squared();
                        if len2 > 0.0 {
                            (n.dot(h) / len2.sqrt()).max(0.0)
                        } else {
                            f32::NAN // no half vector: no highlight
                        }
                    } else {
                        let r = 2.0 * n_dot_l * n - l;
                        r.dot(v).max(0.0)
                    };
                    // `s` is in [0, 1] (or NaN → skipped), so powf never sees a negative base;
                    // 0^0 = 1 by IEEE pow.
                    if s >= 0.0 {
                        c += light.specular * (pow01(s, self.shininess) * att);
                    }
                }
            }
        }
        c
    }
}

/// `x^f` for `x` in [0, 1] and `f ≥ 0`, as `2^(f·log2 x)` with polynomial log2/exp2.
///
/// Faster than `powf` and branch-free, so lane loops over it vectorise. Relative error below
/// 2e-5 (0.005 of an 8-bit level) for the `f ≤ 128` of real materials (see the tests); the
/// absolute error stays below 1e-6 even at `f = 10 000`. Results below 2^-126 flush to 0;
/// `0^0 = 1` as with `powf`.
#[inline(always)]
pub(crate) fn pow01(x: f32, f: f32) -> f32 {
    let bits = x.max(1e-30).to_bits();
    let mant = bits & 0x007f_ffff;
    // Mantissa folded into [sqrt(1/2), sqrt(2)) so the series argument stays small.
    let big = mant > 0x0035_04f3;
    let e = (((bits >> 23) & 0xff) as i32 - 127 + big as i32) as f32;
    let m = f32::from_bits(mant | if big { 0x3f00_0000 } else { 0x3f80_0000 });
    let t = (m - 1.0) / (m + 1.0);
    let t2 = t * t;
    // log2(m) = 2/ln 2 · atanh(t), |t| ≤ 0.1716: five odd terms reach f32 precision.
    let log2m =
        t * (2.885_39 + t2 * (0.961_796_7 + t2 * (0.577_078 + t2 * (0.412_198 + t2 * 0.320_6))));
    // Clamped to ≤ 0 too: a dot product of unit vectors can exceed 1 by rounding, and with a
    // huge exponent y then overflowed `i + 127` below (a NaN colour in release builds; found
    // by fuzzing). x ≥ 1 gives 1.
    let y = (f * (e + log2m)).clamp(-126.0, 0.0);
    // Round to nearest by truncating y − 0.5 (y ≤ ~0): no libm call on baseline x86-64.
    let i = (y - 0.5) as i32;
    let z = (y - i as f32) * std::f32::consts::LN_2; // |z| ≤ ln2 / 2
                                                     // e^z by its Taylor series to degree 7 (relative error < 2e-8).
    let p = 1.0
        + z * (1.0
            + z * (0.5
                + z * (1.0 / 6.0
                    + z * (1.0 / 24.0
                        + z * (1.0 / 120.0 + z * (1.0 / 720.0 + z * (1.0 / 5040.0)))))));
    let r = p * f32::from_bits(((i + 127) as u32) << 23);
    let r = if y <= -126.0 { 0.0 } else { r };
    if x > 0.0 {
        r
    } else if f == 0.0 {
        1.0
    } else {
        0.0
    }
}

/// Pixels shaded together by [`PreparedMaterial::shade_lanes`].
pub(crate) const LANES: usize = 8;

/// One value per lane.
pub(crate) type Lanes = [f32; LANES];

impl PreparedMaterial {
    /// [`PreparedMaterial::shade`] for [`LANES`] points at once, in structure-of-arrays form
    /// (`n[axis][lane]`, unit or zero normals), written as plain lane loops that the compiler
    /// turns into SIMD. Same equation, same guards.
    #[inline(always)]
    pub(crate) fn shade_lanes(&self, n: &[Lanes; 3], p: &[Lanes; 3], eye: Vec3) -> [Lanes; 3] {
        if self.specular_on {
            match self.model {
                SpecularModel::BlinnPhong | SpecularModel::NormalizedBlinnPhong => {
                    self.lanes_with::<true, true>(n, p, eye)
                }
                SpecularModel::Phong => self.lanes_with::<true, false>(n, p, eye),
            }
        } else {
            self.lanes_with::<false, true>(n, p, eye)
        }
    }

    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    fn lanes_with<const SPECULAR: bool, const BLINN: bool>(
        &self,
        n: &[Lanes; 3],
        p: &[Lanes; 3],
        eye: Vec3,
    ) -> [Lanes; 3] {
        let mut c = [
            [self.base.x; LANES],
            [self.base.y; LANES],
            [self.base.z; LANES],
        ];
        let mut v = [[0.0; LANES]; 3];
        if let (true, Some(d)) = (SPECULAR, self.infinite_view) {
            v = [[d.x; LANES], [d.y; LANES], [d.z; LANES]];
        } else if SPECULAR {
            normalize_lanes(&mut v, |k| {
                (eye.x - p[0][k], eye.y - p[1][k], eye.z - p[2][k])
            });
        }
        for light in &self.lights {
            match light.geometry {
                // Its own arm with a constant `l`, so the compiler keeps the splat in
                // registers (a shared `l` that point_lanes writes through memory cost the
                // one-directional-light scene 5 % more instructions).
                LightGeometry::Directional(d) => {
                    let l = [[d.x; LANES], [d.y; LANES], [d.z; LANES]];
                    self.light_loop::<SPECULAR, BLINN, false>(
                        light,
                        n,
                        &l,
                        &v,
                        &[1.0; LANES],
                        &mut c,
                    );
                }
                LightGeometry::Point(q) | LightGeometry::Spot { position: q, .. } => {
                    let mut l = [[0.0; LANES]; 3];
                    let mut att = [1.0; LANES];
                    point_lanes(light, q, p, &mut l, &mut att, &mut c);
                    // Unscaled lights (no attenuation, no cone) take the plain loop, which
                    // vectorises; reading `att` in it defeats the vectoriser (measured: 40 %
                    // slower Phong).
                    if light.attenuation.is_some()
                        || matches!(light.geometry, LightGeometry::Spot { .. })
                    {
                        self.light_loop::<SPECULAR, BLINN, true>(light, n, &l, &v, &att, &mut c);
                    } else {
                        self.light_loop::<SPECULAR, BLINN, false>(light, n, &l, &v, &att, &mut c);
                    }
                }
            }
        }
        c
    }

    /// One light's diffuse and specular terms over the lanes; `SCALED` multiplies them by
    /// `att` (attenuation × spot factor).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    fn light_loop<const SPECULAR: bool, const BLINN: bool, const SCALED: bool>(
        &self,
        light: &PreparedLight,
        n: &[Lanes; 3],
        l: &[Lanes; 3],
        v: &[Lanes; 3],
        att: &Lanes,
        c: &mut [Lanes; 3],
    ) {
        for k in 0..LANES {
            let (nx, ny, nz) = (n[0][k], n[1][k], n[2][k]);
            let (lx, ly, lz) = (l[0][k], l[1][k], l[2][k]);
            let ndl = nx * lx + ny * ly + nz * lz;
            let lit = ndl > 0.0;
            let d = if lit {
                if SCALED {
                    ndl * att[k]
                } else {
                    ndl
                }
            } else {
                0.0
            };
            c[0][k] += light.diffuse.x * d;
            c[1][k] += light.diffuse.y * d;
            c[2][k] += light.diffuse.z * d;
            if SPECULAR {
                let (vx, vy, vz) = (v[0][k], v[1][k], v[2][k]);
                let (s, ok) = if BLINN {
                    let (hx, hy, hz) = (lx + vx, ly + vy, lz + vz);
                    let h2 = hx * hx + hy * hy + hz * hz;
                    let nh = (nx * hx + ny * hy + nz * hz) / h2.max(1e-30).sqrt();
                    (nh.max(0.0), h2 > 0.0)
                } else {
                    let (rx, ry, rz) = (
                        2.0 * ndl * nx - lx,
                        2.0 * ndl * ny - ly,
                        2.0 * ndl * nz - lz,
                    );
                    ((rx * vx + ry * vy + rz * vz).max(0.0), true)
                };
                let sp = pow01(s, self.shininess);
                let sp = if lit && ok {
                    if SCALED {
                        sp * att[k]
                    } else {
                        sp
                    }
                } else {
                    0.0
                };
                c[0][k] += light.specular.x * sp;
                c[1][k] += light.specular.y * sp;
                c[2][k] += light.specular.z * sp;
            }
        }
    }
}

/// Unit vectors toward a point or spot light, the attenuation × spot factor per lane, and
/// the light's attenuated ambient term. Kept out of line so the per-light lane loop of
/// [`PreparedMaterial::shade_lanes`] stays small enough to vectorise.
#[inline(never)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
fn point_lanes(
    light: &PreparedLight,
    q: Vec3,
    p: &[Lanes; 3],
    l: &mut [Lanes; 3],
    att: &mut Lanes,
    c: &mut [Lanes; 3],
) {
    normalize_lanes(l, |k| (q.x - p[0][k], q.y - p[1][k], q.z - p[2][k]));
    match light.attenuation {
        Some(kk) => {
            for k in 0..LANES {
                let (dx, dy, dz) = (q.x - p[0][k], q.y - p[1][k], q.z - p[2][k]);
                att[k] = attenuation(kk, (dx * dx + dy * dy + dz * dz).sqrt());
            }
        }
        None => *att = [1.0; LANES],
    }
    if let LightGeometry::Spot {
        direction: d,
        cos_cutoff,
        cos_inner,
        exponent,
        ..
    } = light.geometry
    {
        if cos_inner > 1.0 && (exponent == 0.0 || exponent == 1.0) {
            // Hard edge with exponent 0 or 1 (one-sided area lights' points): the same
            // values as SpotLight::factor, as branch-free selects that vectorise.
            let flat = exponent == 0.0;
            for k in 0..LANES {
                let cos_angle = -(l[0][k] * d.x + l[1][k] * d.y + l[2][k] * d.z);
                let base = if flat { 1.0 } else { cos_angle.max(0.0) };
                att[k] *= if cos_angle < cos_cutoff { 0.0 } else { base };
            }
        } else {
            for k in 0..LANES {
                let cos_angle = -(l[0][k] * d.x + l[1][k] * d.y + l[2][k] * d.z);
                att[k] *= SpotLight::factor(cos_angle, cos_cutoff, cos_inner, exponent);
            }
        }
    }
    if light.ambient != Vec3::ZERO {
        for k in 0..LANES {
            c[0][k] += light.ambient.x * att[k];
            c[1][k] += light.ambient.y * att[k];
            c[2][k] += light.ambient.z * att[k];
        }
    }
}

/// Normalises the vectors `f(lane)` into `out` (zero stays zero).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
pub(crate) fn normalize_lanes(out: &mut [Lanes; 3], f: impl Fn(usize) -> (f32, f32, f32)) {
    for k in 0..LANES {
        let (x, y, z) = f(k);
        let len2 = x * x + y * y + z * z;
        let inv = if len2 > 0.0 { 1.0 / len2.sqrt() } else { 0.0 };
        out[0][k] = x * inv;
        out[1][k] = y * inv;
        out[2][k] = z * inv;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::{DirectionalLight, PointLight, SpotLight};

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
        let pm = PreparedMaterial::new(
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
        let pm = PreparedMaterial::new(&m, Vec3::ZERO, &[at.into()], SpecularModel::BlinnPhong);
        assert!(pm.shade(Vec3::Z, Vec3::ZERO, Vec3::Z).is_finite());
    }

    #[test]
    fn area_light_shades_as_its_point_sources() {
        use crate::area_light::{AreaLight, AreaShape};
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
        let a = PreparedMaterial::new(&m, Vec3::splat(0.2), &[area.into()], SpecularModel::Phong);
        let b = PreparedMaterial::new(&m, Vec3::splat(0.2), &points, SpecularModel::Phong);
        let eye = Vec3::new(0.3, 0.2, 3.0);
        for p in [Vec3::ZERO, Vec3::new(0.4, -0.3, 0.1)] {
            let n = Vec3::new(0.1, 0.2, 1.0).normalize();
            assert_eq!(a.shade(n, p, eye), b.shade(n, p, eye));
        }
        // One-sided: the same light seen from behind (n faces the back) gives no direct light,
        // and in front each point is scaled by the cosine of its emission angle: a point on
        // the axis far away gets ≈ the unscaled light.
        let one = area.with_one_sided(true); // normal x × y = +z: emits upward
        let pm = PreparedMaterial::new(&m, Vec3::ZERO, &[one.into()], SpecularModel::Phong);
        let below = pm.shade(Vec3::Z, Vec3::ZERO, eye);
        assert_eq!(below, m.emission);
        let above = Vec3::new(0.0, 0.0, 1e3);
        let lit = pm.shade(-Vec3::Z, above, above + Vec3::Z);
        let two = PreparedMaterial::new(&m, Vec3::ZERO, &[area.into()], SpecularModel::Phong);
        let both = two.shade(-Vec3::Z, above, above + Vec3::Z);
        assert!(
            (lit - both).abs().max_element() < 1e-6 * both.max_element(),
            "{lit} {both}"
        );
    }

    #[test]
    fn normalized_blinn_scales_the_lobe_by_f_plus_8_over_8_pi() {
        let l: Light = DirectionalLight::new(-Vec3::Z, Vec3::ONE, 1.0)
            .unwrap()
            .into();
        for f in [1.0f32, 32.0, 512.0] {
            let m = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::ONE, f).unwrap();
            let plain = PreparedMaterial::new(&m, Vec3::ZERO, &[l], SpecularModel::BlinnPhong);
            let norm =
                PreparedMaterial::new(&m, Vec3::ZERO, &[l], SpecularModel::NormalizedBlinnPhong);
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
        let pm = PreparedMaterial::new(&m, Vec3::ZERO, &[spot.into()], SpecularModel::BlinnPhong);
        let eye = Vec3::new(0.0, 0.0, 5.0);
        for (x, inside) in [(0.0f32, true), (1.15, true), (1.16, false), (3.0, false)] {
            let c = pm.shade(Vec3::Z, Vec3::new(x, 0.0, 0.0), eye).x;
            let cos = 2.0 / (x * x + 4.0).sqrt();
            let want = if inside { cos * cos * cos } else { 0.0 }; // spot cos² × n·l = cos
            assert!((c - want).abs() < 1e-5, "x = {x}: {c} vs {want}");
        }
        // A 180° cutoff is a plain point light, whatever the exponent.
        let flood = SpotLight::new(point, -Vec3::Z, 180.0, 50.0).unwrap();
        let a = PreparedMaterial::new(&m, Vec3::ZERO, &[flood.into()], SpecularModel::BlinnPhong);
        let b = PreparedMaterial::new(&m, Vec3::ZERO, &[point.into()], SpecularModel::BlinnPhong);
        let q = Vec3::new(5.0, 0.0, 0.0);
        assert_eq!(a.shade(Vec3::Z, q, eye), b.shade(Vec3::Z, q, eye));
        // Smooth edge: full inside the inner cone, 0 at the cutoff, in between monotone.
        let soft = spot.with_inner(20.0).unwrap();
        let pm = PreparedMaterial::new(&m, Vec3::ZERO, &[soft.into()], SpecularModel::BlinnPhong);
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

    #[test]
    fn lanes_match_scalar() {
        let lights: Vec<Light> = vec![
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
            DirectionalLight::new(Vec3::new(-1.0, -0.5, -1.0), Vec3::new(1.0, 0.9, 0.8), 1.0)
                .unwrap()
                .into(),
            PointLight::new(Vec3::new(0.5, 2.0, 1.0), Vec3::new(0.3, 0.4, 0.5), 2.0)
                .unwrap()
                .into(),
        ];
        let m = Material::preset("brass")
            .unwrap()
            .with_emission(Vec3::new(0.1, 0.0, 0.05))
            .unwrap();
        let eye = Vec3::new(0.2, 0.3, 3.0);
        for model in [SpecularModel::BlinnPhong, SpecularModel::Phong] {
            let pm = PreparedMaterial::new(&m, Vec3::splat(0.2), &lights, model);
            let mut n = [[0.0; LANES]; 3];
            let mut p = [[0.0; LANES]; 3];
            let mut pts = Vec::new();
            for k in 0..LANES {
                let a = k as f32 * 0.9;
                let nn = if k == 3 {
                    Vec3::ZERO
                } else {
                    Vec3::new(a.cos(), 0.3, a.sin()).normalize()
                };
                let pp = Vec3::new(a.sin(), 0.1 * k as f32, a.cos());
                for ax in 0..3 {
                    n[ax][k] = nn[ax];
                    p[ax][k] = pp[ax];
                }
                pts.push((nn, pp));
            }
            let c = pm.shade_lanes(&n, &p, eye);
            for (k, (nn, pp)) in pts.into_iter().enumerate() {
                let want = pm.shade(nn, pp, eye);
                let got = Vec3::new(c[0][k], c[1][k], c[2][k]);
                assert!(
                    (got - want).abs().max_element() < 1e-6,
                    "lane {k}: {got} vs {want}"
                );
            }
        }
    }

    /// Fuzzing found `n·h` a rounding step above 1 with a huge exponent overflowing the
    /// exponent arithmetic (`fuzz/seeds/pipeline/crash-pow-above-one`).
    #[test]
    fn pow01_of_a_base_just_above_one_is_one() {
        let above = 1.0 + f32::EPSILON;
        for f in [0.0, 1.0, 1e4, 1e30, f32::MAX] {
            assert_eq!(pow01(above, f), 1.0, "f = {f}");
            assert_eq!(pow01(1.0, f), 1.0, "f = {f}");
        }
    }

    #[test]
    fn pow01_is_accurate() {
        let mut worst_rel = 0.0f64;
        let mut worst_abs = 0.0f64;
        for i in 0..=20_000 {
            let x = i as f32 / 20_000.0;
            for &f in &[
                0.0f32, 0.5, 1.0, 2.0, 9.84615, 27.8974, 51.2, 89.6, 128.0, 1000.0, 10_000.0,
            ] {
                let want = (x as f64).powf(f as f64);
                let got = pow01(x, f) as f64;
                worst_abs = worst_abs.max((got - want).abs());
                if f <= 128.0 && want > 1e-30 {
                    worst_rel = worst_rel.max(((got - want) / want).abs());
                }
            }
        }
        assert!(worst_rel < 2e-5, "relative {worst_rel}");
        assert!(worst_abs < 1e-6, "absolute {worst_abs}");
        assert_eq!(pow01(0.0, 0.0), 1.0);
        assert_eq!(pow01(0.0, 3.0), 0.0);
        assert_eq!(pow01(1.0, 10_000.0), 1.0);
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
        let pm = PreparedMaterial::new(&mat(), Vec3::splat(0.5), &[l], SpecularModel::BlinnPhong);
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
        let blinn = PreparedMaterial::new(&m, Vec3::ZERO, &[l], SpecularModel::BlinnPhong);
        let want = m.diffuse * 2.0 * n_dot_l + m.specular * 2.0 * nh.powf(10.0);
        assert!(
            (blinn.shade(Vec3::Z, Vec3::ZERO, eye) - want)
                .abs()
                .max_element()
                < 1e-5
        );
        // Phong: r = (−1,0,1)/√2, r·v = 1/√2.
        let phong = PreparedMaterial::new(&m, Vec3::ZERO, &[l], SpecularModel::Phong);
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
        let pm = PreparedMaterial::new(&m, Vec3::ZERO, &[l], SpecularModel::BlinnPhong);
        assert_eq!(pm.shade(Vec3::Z, Vec3::ZERO, Vec3::Z), Vec3::ZERO);
        // Zero normal, eye on the surface, light at the point: finite.
        let pl: Light = PointLight::new(Vec3::ZERO, Vec3::ONE, 1.0).unwrap().into();
        let pm = PreparedMaterial::new(&m, Vec3::ZERO, &[pl, l], SpecularModel::BlinnPhong);
        assert!(pm.shade(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO).is_finite());
        assert!(pm.shade(Vec3::Z, Vec3::ZERO, Vec3::ZERO).is_finite());
    }

    #[test]
    fn parses_names() {
        assert_eq!("Phong".parse::<ShadingMode>().unwrap(), ShadingMode::Phong);
        assert!("toon".parse::<ShadingMode>().is_err());
        assert_eq!(
            "blinn".parse::<SpecularModel>().unwrap(),
            SpecularModel::BlinnPhong
        );
    }
}
