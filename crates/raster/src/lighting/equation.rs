//! The lighting equation, written once, over [`LANES`] points at a time:
//!
//! ```text
//! c = ke + ka·Ia + Σ_i att_i·spot_i·[ ka·Ia_i + kd·Id_i·max(n·l_i, 0) + ks·Is_i·S_i ]
//! Blinn-Phong: S = max(n·h, 0)^f, h = normalize(l + v)      Phong: S = max(r·v, 0)^f
//! ```
//!
//! (`S_i = 0` unless `n·l_i > 0`; `v = normalize(eye − p)` or the infinite viewer's constant.)
//! Where the terms go is the [`Terms`] target: [`Folded`] sums them into one colour (the
//! material was folded into the lights), [`Split`] keeps ambient, diffuse and specular apart
//! for a unit surface, so a texture, a shadow or a reflection can weigh each. A single point
//! is one lane ([`Surface::shade`]).

use glam::Vec3;

use super::lanes::{from_lanes, normalize_lanes, Lanes, LANES};
use super::light_set::Geometry;
use super::pow::pow01;
use super::surface::{Surface, SurfaceLight};
use crate::options::SpecularModel;

/// Where a light's terms are added, per lane and channel.
pub(crate) trait Terms {
    /// The constant part (`base`) in every lane.
    fn new(base: Vec3) -> Self;
    /// Ambient terms.
    fn ambient(&mut self) -> &mut [Lanes; 3];
    /// Diffuse terms.
    fn diffuse(&mut self) -> &mut [Lanes; 3];
    /// Specular terms.
    fn specular(&mut self) -> &mut [Lanes; 3];
}

/// Every term summed into one colour.
pub(crate) struct Folded(pub [Lanes; 3]);

impl Terms for Folded {
    #[inline(always)]
    fn new(base: Vec3) -> Self {
        Folded([[base.x; LANES], [base.y; LANES], [base.z; LANES]])
    }
    #[inline(always)]
    fn ambient(&mut self) -> &mut [Lanes; 3] {
        &mut self.0
    }
    #[inline(always)]
    fn diffuse(&mut self) -> &mut [Lanes; 3] {
        &mut self.0
    }
    #[inline(always)]
    fn specular(&mut self) -> &mut [Lanes; 3] {
        &mut self.0
    }
}

/// Ambient (with the constant base), diffuse and specular apart.
// Read by the tests today; the texture stage (a per-point material) is its first user.
#[allow(dead_code)]
#[derive(Clone, Copy, Default)]
pub(crate) struct Split {
    pub ambient: [Lanes; 3],
    pub diffuse: [Lanes; 3],
    pub specular: [Lanes; 3],
}

impl Terms for Split {
    #[inline(always)]
    fn new(base: Vec3) -> Self {
        Split {
            ambient: [[base.x; LANES], [base.y; LANES], [base.z; LANES]],
            diffuse: [[0.0; LANES]; 3],
            specular: [[0.0; LANES]; 3],
        }
    }
    #[inline(always)]
    fn ambient(&mut self) -> &mut [Lanes; 3] {
        &mut self.ambient
    }
    #[inline(always)]
    fn diffuse(&mut self) -> &mut [Lanes; 3] {
        &mut self.diffuse
    }
    #[inline(always)]
    fn specular(&mut self) -> &mut [Lanes; 3] {
        &mut self.specular
    }
}

/// `1 / max(kc + kl·d + kq·d², MIN_ATTENUATION_DENOMINATOR)`.
#[inline(always)]
fn attenuation(k: [f32; 3], d: f32) -> f32 {
    1.0 / (k[0] + d * (k[1] + d * k[2])).max(crate::lights::MIN_ATTENUATION_DENOMINATOR)
}

/// What the lane loop may read per point beyond its normal and position: each light's
/// visibility (`None`: fully visible, evaluated exactly as without shadows) and the specular
/// exponent (`None`: the surface's shininess).
pub(crate) trait Visibility: Copy {
    /// Light `i`'s visibility per lane, or `None` (fully visible).
    fn of(&self, i: usize) -> Option<&Lanes>;
    /// The specular exponent per lane (a shininess map), or `None` (the surface's).
    #[inline(always)]
    fn shininess(&self) -> Option<&Lanes> {
        None
    }
}

/// Every light fully visible: the plain equation (no scene with shadows reaches it).
#[derive(Clone, Copy)]
pub(crate) struct AllVisible;

impl Visibility for AllVisible {
    #[inline(always)]
    fn of(&self, _: usize) -> Option<&Lanes> {
        None
    }
}

/// One entry per light of the surface (a shadow effect's answer).
impl Visibility for &[Option<Lanes>] {
    #[inline(always)]
    fn of(&self, i: usize) -> Option<&Lanes> {
        self.get(i).and_then(Option::as_ref)
    }
}

/// Visibilities (possibly none: an empty slice) and a specular exponent per lane.
#[derive(Clone, Copy)]
pub(crate) struct WithShininess<'a> {
    pub visibility: &'a [Option<Lanes>],
    pub shininess: &'a Lanes,
}

impl Visibility for WithShininess<'_> {
    #[inline(always)]
    fn of(&self, i: usize) -> Option<&Lanes> {
        self.visibility.of(i)
    }
    #[inline(always)]
    fn shininess(&self) -> Option<&Lanes> {
        Some(self.shininess)
    }
}

impl Surface {
    /// Colour at one point with unit (or zero) normal `n`, position `p`, eye `eye`: the
    /// lane evaluation with every lane at that point.
    pub fn shade(&self, n: Vec3, p: Vec3, eye: Vec3) -> Vec3 {
        let splat = |v: Vec3| [[v.x; LANES], [v.y; LANES], [v.z; LANES]];
        let c = self.shade_lanes(&splat(n), &splat(p), eye);
        Vec3::new(c[0][0], c[1][0], c[2][0])
    }

    /// Colours of [`LANES`] points (`n[axis][lane]`, unit or zero normals).
    #[inline(always)]
    pub fn shade_lanes(&self, n: &[Lanes; 3], p: &[Lanes; 3], eye: Vec3) -> [Lanes; 3] {
        self.terms_lanes::<Folded>(n, p, eye).0
    }

    /// The terms of [`LANES`] points into the target `T`.
    #[inline(always)]
    pub fn terms_lanes<T: Terms>(&self, n: &[Lanes; 3], p: &[Lanes; 3], eye: Vec3) -> T {
        self.terms_lanes_with(n, p, eye, AllVisible)
    }

    /// The terms of [`LANES`] points into `T`, each light's diffuse and specular scaled per
    /// lane by its visibility from `vis` (see [`Visibility`]; [`AllVisible`] compiles to the
    /// plain equation).
    #[inline(always)]
    pub(super) fn terms_lanes_with<T: Terms, V: Visibility>(
        &self,
        n: &[Lanes; 3],
        p: &[Lanes; 3],
        eye: Vec3,
        vis: V,
    ) -> T {
        if self.specular_on {
            match self.model {
                SpecularModel::BlinnPhong | SpecularModel::NormalizedBlinnPhong => {
                    self.lanes_with::<T, V, true, true>(n, p, eye, vis)
                }
                SpecularModel::Phong => self.lanes_with::<T, V, true, false>(n, p, eye, vis),
            }
        } else {
            self.lanes_with::<T, V, false, true>(n, p, eye, vis)
        }
    }

    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    fn lanes_with<T: Terms, V: Visibility, const SPECULAR: bool, const BLINN: bool>(
        &self,
        n: &[Lanes; 3],
        p: &[Lanes; 3],
        eye: Vec3,
        vis: V,
    ) -> T {
        let mut c = T::new(self.base);
        let mut v = [[0.0; LANES]; 3];
        if let (true, Some(d)) = (SPECULAR, self.infinite_view) {
            v = [[d.x; LANES], [d.y; LANES], [d.z; LANES]];
        } else if SPECULAR {
            normalize_lanes(&mut v, &from_lanes(eye, p), self.wide());
        }
        // `None` under `AllVisible` (and for every light): the branches below fold away.
        let shin = vis.shininess();
        for (i, light) in self.lights.iter().enumerate() {
            let seen = vis.of(i);
            match light.geometry {
                // Its own arm with a constant `l`, so the compiler keeps the splat in
                // registers (a shared `l` that point_lanes writes through memory cost the
                // one-directional-light scene 5 % more instructions).
                Geometry::Directional(d) => {
                    let l = [[d.x; LANES], [d.y; LANES], [d.z; LANES]];
                    match seen {
                        Some(s) => self.light_loop::<T, SPECULAR, BLINN, true>(
                            light, n, &l, &v, s, shin, &mut c,
                        ),
                        None => self.light_loop::<T, SPECULAR, BLINN, false>(
                            light,
                            n,
                            &l,
                            &v,
                            &[1.0; LANES],
                            shin,
                            &mut c,
                        ),
                    }
                }
                Geometry::Point(q) | Geometry::Spot { position: q, .. } => {
                    let mut l = [[0.0; LANES]; 3];
                    let mut att = [1.0; LANES];
                    // The ambient term is added here, before a visibility scales `att`.
                    point_lanes(light, q, p, &mut l, &mut att, c.ambient(), self.wide());
                    if let Some(s) = seen {
                        for k in 0..LANES {
                            att[k] *= s[k];
                        }
                    }
                    // Unscaled lights (no attenuation, no cone, no visibility) take the plain
                    // loop, which vectorises; reading `att` in it defeats the vectoriser
                    // (measured: 40 % slower Phong).
                    if light.attenuation.is_some()
                        || matches!(light.geometry, Geometry::Spot { .. })
                        || seen.is_some()
                    {
                        self.light_loop::<T, SPECULAR, BLINN, true>(
                            light, n, &l, &v, &att, shin, &mut c,
                        );
                    } else {
                        self.light_loop::<T, SPECULAR, BLINN, false>(
                            light, n, &l, &v, &att, shin, &mut c,
                        );
                    }
                }
            }
        }
        c
    }

    /// One light's diffuse and specular terms over the lanes; `SCALED` multiplies them by
    /// `att` (attenuation × spot factor); `shin` replaces the surface's shininess per lane.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    #[allow(clippy::too_many_arguments)]
    pub(super) fn light_loop<
        T: Terms,
        const SPECULAR: bool,
        const BLINN: bool,
        const SCALED: bool,
    >(
        &self,
        light: &SurfaceLight,
        n: &[Lanes; 3],
        l: &[Lanes; 3],
        v: &[Lanes; 3],
        att: &Lanes,
        shin: Option<&Lanes>,
        c: &mut T,
    ) {
        for k in 0..LANES {
            let (nx, ny, nz) = (n[0][k], n[1][k], n[2][k]);
            let (lx, ly, lz) = (l[0][k], l[1][k], l[2][k]);
            let ndl = nx * lx + ny * ly + nz * lz;
            let lit = ndl > 0.0;
            // The scale multiplies the selected term (0 when unlit: `att` is finite and
            // ≥ 0, so the product is the same as scaling inside the select) -- so the
            // select stays a select and the loop vectorises.
            let d = if lit { ndl } else { 0.0 };
            let d = if SCALED { d * att[k] } else { d };
            let cd = c.diffuse();
            cd[0][k] += light.diffuse.x * d;
            cd[1][k] += light.diffuse.y * d;
            cd[2][k] += light.diffuse.z * d;
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
                let sp = pow01(s, shin.map_or(self.shininess, |f| f[k]));
                let sp = if lit && ok { sp } else { 0.0 };
                let sp = if SCALED { sp * att[k] } else { sp };
                let cs = c.specular();
                cs[0][k] += light.specular.x * sp;
                cs[1][k] += light.specular.y * sp;
                cs[2][k] += light.specular.z * sp;
            }
        }
    }
}

/// Unit vectors toward a point or spot light, the attenuation × spot factor per lane, and
/// the light's attenuated ambient term. Kept out of line so the per-light lane loop of
/// [`Surface::terms_lanes`] stays small enough to vectorise; being out of line, it is not
/// compiled with its caller's instruction set, so `wide` ([`Surface::with_wide_lanes`])
/// picks the copy compiled for AVX2 + FMA (the same bits).
#[inline(never)]
pub(super) fn point_lanes(
    light: &SurfaceLight,
    q: Vec3,
    p: &[Lanes; 3],
    l: &mut [Lanes; 3],
    att: &mut Lanes,
    ambient: &mut [Lanes; 3],
    wide: bool,
) {
    #[cfg(target_arch = "x86_64")]
    if wide {
        // SAFETY: `wide` is only true where the CPU reported AVX2 and FMA
        // (`Surface::with_wide_lanes`).
        return unsafe { point_lanes_avx2(light, q, p, l, att, ambient) };
    }
    let _ = wide;
    point_lanes_body(light, q, p, l, att, ambient, false)
}

/// [`point_lanes`] compiled for AVX2 + FMA.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn point_lanes_avx2(
    light: &SurfaceLight,
    q: Vec3,
    p: &[Lanes; 3],
    l: &mut [Lanes; 3],
    att: &mut Lanes,
    ambient: &mut [Lanes; 3],
) {
    point_lanes_body(light, q, p, l, att, ambient, true)
}

/// [`point_lanes`]' work, inlined into each copy.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
fn point_lanes_body(
    light: &SurfaceLight,
    q: Vec3,
    p: &[Lanes; 3],
    l: &mut [Lanes; 3],
    att: &mut Lanes,
    ambient: &mut [Lanes; 3],
    wide: bool,
) {
    normalize_lanes(l, &from_lanes(q, p), wide);
    match light.attenuation {
        Some(kk) => {
            for k in 0..LANES {
                let (dx, dy, dz) = (q.x - p[0][k], q.y - p[1][k], q.z - p[2][k]);
                att[k] = attenuation(kk, (dx * dx + dy * dy + dz * dz).sqrt());
            }
        }
        None => *att = [1.0; LANES],
    }
    if let Geometry::Spot { cone, .. } = light.geometry {
        cone.scale_lanes(l, att);
    }
    if light.ambient != Vec3::ZERO {
        for k in 0..LANES {
            ambient[0][k] += light.ambient.x * att[k];
            ambient[1][k] += light.ambient.y * att[k];
            ambient[2][k] += light.ambient.z * att[k];
        }
    }
}
