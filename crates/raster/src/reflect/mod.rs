//! The reflection and refraction room: what arrives at a surface point along its mirror and
//! refracted directions, and how a material mixes it with the point's local colour.
//!
//! - [`optics`]: the mirror direction, Snell's law with total internal reflection, Schlick's
//!   Fresnel and a material's split `c = L·local + R·reflected + T·transmitted`;
//! - [`trace`]: the scene as seen by secondary rays (the rays room's BVH plus what each
//!   triangle is) and the Whitted recursion;
//! - [`SecondaryEffect`] (here): what is constant per render.
//!
//! It is built only for scenes with a reflective or transparent material or an environment
//! background; the pipeline then shades through a tile body of its own
//! (`shade/secondary.rs`).

pub mod optics;
mod trace;

pub(crate) use trace::{RayScene, World};

use glam::{DMat4, DVec3, DVec4, Vec3};

use crate::camera::Camera;
use crate::effects::FogEffect;
use crate::environment::Environment;
use crate::lighting::{set_lane, Lanes, LANES};
use crate::material::Material;
use crate::options::{RenderOptions, Technique};
use crate::scene::Scene;

/// What the secondary stage does with an object.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// Neither reflective nor transparent: its local colour as the loops shade it.
    Opaque,
    /// Reflective, or transparent with a refraction technique: its first surface mixes the
    /// local colour with the reflected and refracted light.
    Optical,
    /// Transparent without a refraction technique: drawn behind nothing in the visibility
    /// pass, its fragments in front of the opaque surface are sorted and blended per pixel.
    Blended,
}

/// A surface point as the mix sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Point {
    /// Position (world).
    pub p: Vec3,
    /// Unit shading normal on the side of `v`.
    pub n: Vec3,
    /// Unit geometric normal on the side of `v` (ray offsets).
    pub g: Vec3,
    /// Unit direction toward the viewer (or the ray's origin).
    pub v: Vec3,
    /// Whether the light crosses into the object here (a front face): indices (1, ior).
    pub entering: bool,
    /// The object and the side (0 front, 1 back as lit) whose material applies.
    pub object: u32,
    pub side: usize,
}

/// The colour a point sends toward its viewer, split into what it adds itself (local,
/// reflected and, unless the caller composites it, transmitted light) and how much of what
/// lies straight behind it still shows through.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Mixed {
    pub color: Vec3,
    /// The share of the light from behind (straight-through transmission) still to add.
    pub behind: f32,
}

/// How the secondary stage mixes an object's first surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FirstSurface {
    /// Its local colour as the loops shaded it, unchanged: a [`Kind::Opaque`] object when
    /// there is no fog.
    Plain,
    /// [`SecondaryEffect::mix`], a pixel at a time (not optical, or a secondary ray to follow),
    /// then the fog.
    Mix,
    /// A mirror reading its reflected direction from the environment: one look-up
    /// ([`Lookup::of`]).
    Mirror,
    /// Glass reading its reflected and refracted directions from the environment: two.
    Glass,
}

/// A first-surface mix that reads every direction it follows from the environment
/// ([`Lookup::of`]): `base + reflect·sky(reflected) +
/// transmit·sky(refracted)`, so that callers can look the directions up over lanes.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Lookup {
    /// The local colour's share, `L·local`.
    pub base: Vec3,
    /// Weight of the light along `reflected` (zero: nothing is reflected).
    pub reflect: Vec3,
    /// The mirror direction (the lanes' callers keep theirs in lanes).
    #[cfg_attr(not(test), allow(dead_code))]
    pub reflected: Vec3,
    /// Weight of the light along `refracted` (zero: nothing is transmitted, or total
    /// internal reflection; `refracted` is then zero).
    pub transmit: f32,
    /// The refracted direction (zero where nothing is transmitted).
    #[cfg_attr(not(test), allow(dead_code))]
    pub refracted: Vec3,
}

impl Lookup {
    /// The look-ups of a first-surface point of a [`FirstSurface::Mirror`] or
    /// [`FirstSurface::Glass`] whose material splits the light as `s`
    /// ([`SecondaryEffect::indices`] and [`optics::split`] at the point), local colour
    /// `local`: its colour, given the sky along its two directions, is `mix(w, pt, local, 0,
    /// 0, false).color` bit for bit (the same operations in the same order), so that the
    /// caller can look the directions up with other pixels' over lanes.
    #[inline(always)]
    #[cfg_attr(not(test), allow(dead_code))] // the one-point statement the lanes are tested on
    pub fn of(s: optics::Split, local: Vec3) -> Self {
        // As `mix`: the refracted light is added where something is transmitted along a
        // refracted direction (a lookup-only transparent object has a refraction technique).
        let (transmit, refracted) = match s.refracted {
            Some(t) if s.transmit > 0.0 => (s.transmit, t),
            _ => (0.0, Vec3::ZERO),
        };
        Lookup {
            base: local * s.local,
            reflect: s.reflect,
            reflected: s.reflected,
            transmit,
            refracted,
        }
    }

    /// `base` and `reflected` of [`Lookup::of`] of [`optics::split`] over [`LANES`] points
    /// of one material `m`, lane k from the normal `n`, the direction toward the viewer `v`
    /// and the local colour `local` at lane k: the local share is the material's and the
    /// direction the mirror's, whatever the material, the same bits per lane.
    #[inline(always)]
    pub(crate) fn base_and_mirror_lanes(
        m: &Material,
        n: &[Lanes; 3],
        v: &[Lanes; 3],
        local: &[Lanes; 3],
        base: &mut [Lanes; 3],
        reflected: &mut [Lanes; 3],
    ) {
        let share = (Vec3::ONE - m.reflectivity - Vec3::splat(m.transparency)).to_array();
        for k in 0..LANES {
            // `optics::reflect`: 2(n·v)n − v.
            let d2 = 2.0 * (n[0][k] * v[0][k] + n[1][k] * v[1][k] + n[2][k] * v[2][k]);
            for c in 0..3 {
                reflected[c][k] = d2 * n[c][k] - v[c][k];
                base[c][k] = local[c][k] * share[c];
            }
        }
    }

    /// The weights and refracted directions of [`Lookup::of`] of [`optics::split`] over
    /// [`LANES`] points of one material `m` with `m.transparency > 0` (a glass batch; its
    /// `base` and `reflected` are [`Lookup::base_and_mirror_lanes`]'), lane k from the
    /// normal `n` and the direction toward the viewer `v` at lane k, the light going from
    /// index `n1` into `n2`: the same bits per lane (the same operations in the same order,
    /// `split`'s branches as selects, so the lanes vectorise; keeping its `Option` per lane
    /// cost more). A lane whose point transmits nothing has `transmit` 0 and a zero
    /// `refracted`, as `of` gives it.
    #[inline(always)]
    pub(crate) fn transparent_weights_lanes(
        m: &Material,
        n: &[Lanes; 3],
        v: &[Lanes; 3],
        (n1, n2): (f32, f32),
        reflect: &mut [Lanes; 3],
        transmit: &mut Lanes,
        refracted: &mut [Lanes; 3],
    ) {
        debug_assert!(m.transparency > 0.0);
        let (r, t) = (m.reflectivity.to_array(), m.transparency);
        let eta = n1 / n2;
        for k in 0..LANES {
            let (nk, vk) = ([n[0][k], n[1][k], n[2][k]], [v[0][k], v[1][k], v[2][k]]);
            // `optics::refract`: None (total internal reflection) where sin²θ2 > 1.
            let cos1 = (nk[0] * vk[0] + nk[1] * vk[1] + nk[2] * vk[2]).clamp(0.0, 1.0);
            let sin2_sq = eta * eta * (1.0 - cos1 * cos1);
            let tir = sin2_sq > 1.0;
            let cos2 = (1.0 - sin2_sq).sqrt();
            let a = eta * cos1 - cos2;
            let d = [0, 1, 2].map(|c| -eta * vk[c] + a * nk[c]);
            // `split`'s Fresnel weight, from the refracted direction's cosine.
            let f = if m.fresnel {
                let cos2 = (-(d[0] * nk[0] + d[1] * nk[1] + d[2] * nk[2])).clamp(0.0, 1.0);
                optics::schlick(cos1, Some(cos2), n1, n2)
            } else {
                0.0
            };
            let tf = if m.fresnel { t * f } else { 0.0 };
            let through = if m.fresnel { t * (1.0 - f) } else { t };
            let through = if tir { 0.0 } else { through };
            // `of`: the refracted light counts where something is transmitted.
            let counts = !tir && through > 0.0;
            transmit[k] = if counts { through } else { 0.0 };
            for c in 0..3 {
                let w = if m.fresnel { r[c] + tf } else { r[c] };
                reflect[c][k] = if tir { r[c] + t } else { w };
                refracted[c][k] = if counts { d[c] } else { 0.0 };
            }
        }
    }

    /// The colour, given the light along `reflected` and along `refracted`:
    /// [`SecondaryEffect::mix`]'s operations in its order, so the same bits.
    #[inline(always)]
    pub fn color(&self, reflected: Vec3, refracted: Vec3) -> Vec3 {
        let mut c = self.base;
        if self.reflect != Vec3::ZERO {
            c += self.reflect * reflected;
        }
        if self.transmit > 0.0 {
            c += self.transmit * refracted;
        }
        c
    }
}

/// Everything the secondary stage reads that is constant per render.
pub(crate) struct SecondaryEffect {
    environment: Option<Environment>,
    background: Vec3,
    /// Show the environment where no triangle is.
    pub env_background: bool,
    reflections: Technique,
    refractions: Option<Technique>,
    max_depth: u32,
    /// Per object: the materials of its two sides (front, back as lit).
    optics: Vec<[Material; 2]>,
    /// Per object.
    pub kinds: Vec<Kind>,
    /// Whether any object is [`Kind::Blended`].
    pub any_blended: bool,
    /// Per object.
    first_surface: Vec<FirstSurface>,
    rays: Option<RayScene>,
    /// The fog, applied by the secondary stage after the mix (the loops then run without).
    pub fog: Option<FogEffect>,
    /// The view ray through pixel centre (px, py), not normalised: `ray[0]·px + ray[1]·py +
    /// ray[2]` ([`view_ray_planes`]).
    ray: [DVec3; 3],
    /// Unit direction the camera looks along.
    forward: DVec3,
}

impl SecondaryEffect {
    /// Whether a render of `scene` with `options` needs the stage.
    pub fn wanted(scene: &Scene, options: &RenderOptions) -> bool {
        options.environment_background || scene.has_optics()
    }

    /// The stage's render constants. `world` and the triangles' vertex indices are the
    /// vertex stage's (every object's vertices in scene order).
    pub fn new(
        scene: &Scene,
        camera: &Camera,
        options: &RenderOptions,
        world: &[Vec3],
        fog: Option<FogEffect>,
    ) -> Self {
        let two_sided = scene.two_sided();
        let optics: Vec<[Material; 2]> = scene
            .objects()
            .iter()
            .map(|o| [*o.material(), *o.material_for(true, two_sided)])
            .collect();
        let kinds: Vec<Kind> = optics
            .iter()
            .map(|ms| {
                let transparent = ms.iter().any(|m| m.is_transparent());
                let reflective = ms.iter().any(|m| m.is_reflective());
                match (transparent, options.refractions) {
                    (true, None) => Kind::Blended,
                    (true, Some(_)) => Kind::Optical,
                    (false, _) if reflective => Kind::Optical,
                    _ => Kind::Opaque,
                }
            })
            .collect();
        let any_blended = kinds.contains(&Kind::Blended);
        let uses_rays = scene.has_optics()
            && options.max_depth > 0
            && (options.reflections == Technique::Ray
                || options.refractions == Some(Technique::Ray));
        let rays = uses_rays.then(|| RayScene::new(scene, world));
        // Opaque objects without fog keep the loops' colour (plain). Optical objects whose
        // first surface follows no secondary ray: the reflected direction, and the
        // refracted one of a transparent object, are read from the environment (an Optical
        // transparent object always has a refraction technique).
        let first_surface = optics
            .iter()
            .zip(&kinds)
            .map(|(ms, &k)| {
                let transparent = ms.iter().any(|m| m.is_transparent());
                let follows_rays = rays.is_some()
                    && (options.reflections == Technique::Ray
                        || (transparent && options.refractions == Some(Technique::Ray)));
                if k == Kind::Opaque && fog.is_none() {
                    return FirstSurface::Plain;
                }
                match (k == Kind::Optical && !follows_rays, transparent) {
                    (false, _) => FirstSurface::Mix,
                    (true, false) => FirstSurface::Mirror,
                    (true, true) => FirstSurface::Glass,
                }
            })
            .collect();
        let (w, h) = (options.width as f64, options.height as f64);
        let view_proj = camera.projection_matrix(w / h) * camera.view_matrix();
        SecondaryEffect {
            environment: scene.environment().cloned(),
            background: options.background,
            env_background: options.environment_background,
            reflections: options.reflections,
            refractions: options.refractions,
            max_depth: options.max_depth,
            optics,
            kinds,
            any_blended,
            first_surface,
            rays,
            fog,
            ray: view_ray_planes(view_proj.inverse(), w, h),
            forward: (camera.target() - camera.eye()).normalize(),
        }
    }

    /// The light arriving along `d` from outside the scene: the environment, or the
    /// background colour without one.
    #[inline]
    pub fn sky(&self, d: Vec3) -> Vec3 {
        match &self.environment {
            Some(e) => e.sample(d),
            None => self.background,
        }
    }

    /// [`SecondaryEffect::sky`] along the directions `d` (channel-major) of lanes `..n`:
    /// the same values, bit for bit.
    #[inline(always)]
    pub(crate) fn sky_dirs(&self, d: &[Lanes; 3], n: usize, out: &mut [Lanes; 3]) {
        match &self.environment {
            Some(e) => e.sample_lanes(d, n, out),
            None => {
                for (o, c) in out.iter_mut().zip(self.background.to_array()) {
                    o[..n].fill(c);
                }
            }
        }
    }

    /// [`SecondaryEffect::sky`] along the view rays of pixels `(x0 + k, y)` for lanes
    /// `k < n`, channel-major: the same values, bit for bit.
    #[inline(always)]
    pub(crate) fn sky_lanes(&self, x0: usize, y: usize, n: usize, out: &mut [Lanes; 3]) {
        let mut d = [[0.0; LANES]; 3];
        if self.environment.is_some() {
            self.view_rays(x0, y, &mut d);
        }
        self.sky_dirs(&d, n, out);
    }

    /// Unit direction of the view ray through the centre of pixel (x, y) (away from the
    /// camera; parallel rays for an orthographic camera).
    #[inline]
    pub fn view_ray(&self, x: usize, y: usize) -> Vec3 {
        Vec3::from(self.ray_at(x as f64 + 0.5, y as f64 + 0.5))
    }

    /// [`SecondaryEffect::view_ray`] of pixels `(x0 + k, y)`, `k` over the lanes,
    /// channel-major: the same values, bit for bit, computed over the lanes at once.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    pub(crate) fn view_rays(&self, x0: usize, y: usize, out: &mut [Lanes; 3]) {
        let px = std::array::from_fn(|k| (x0 + k) as f64 + 0.5);
        self.view_rays_at(&px, y as f64 + 0.5, out);
    }

    /// The unit view rays through pixel coordinates `(px[k], py)`, channel-major (the
    /// centre of pixel (x, y) is (x + 0.5, y + 0.5)): [`SecondaryEffect::view_ray`]'s
    /// values, bit for bit, over the lanes at once.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    pub(crate) fn view_rays_at(&self, px: &[f64; LANES], py: f64, out: &mut [Lanes; 3]) {
        for k in 0..LANES {
            let d = self.ray_at(px[k], py);
            set_lane(out, k, Vec3::from(d));
        }
    }

    /// The unit view ray through pixel coordinates (px, py): plain arithmetic and a select
    /// (glam's `normalize` and `dot` written out in their order), so that it vectorises.
    #[inline(always)]
    fn ray_at(&self, px: f64, py: f64) -> [f32; 3] {
        // Written out: array `map`s here stayed calls to `try_map` in the tile body.
        let [dx, dy, d0] = self.ray;
        let x = dx.x * px + dy.x * py + d0.x;
        let y = dx.y * px + dy.y * py + d0.y;
        let z = dx.z * px + dy.z * py + d0.z;
        let inv = 1.0 / (x * x + y * y + z * z).sqrt();
        let (x, y, z) = (x * inv, y * inv, z * inv);
        let f = self.forward;
        let s = if x * f.x + y * f.y + z * f.z < 0.0 {
            -1.0
        } else {
            1.0
        };
        [(x * s) as f32, (y * s) as f32, (z * s) as f32]
    }

    /// The material of a point's side.
    #[inline]
    pub fn material(&self, object: u32, side: usize) -> &Material {
        &self.optics[object as usize][side]
    }

    /// The colour point `pt` (local colour `local`, reached `depth` segments from the eye
    /// through a medium absorbing `medium`) sends toward its viewer:
    /// `L·local + R·reflected + T·transmitted` ([`optics::split`]). With `composite` the
    /// straight-through transmission of a [`Kind::Blended`] surface is left to the caller
    /// ([`Mixed::behind`]); otherwise it is followed like any other direction.
    pub fn mix(
        &self,
        w: &World<'_>,
        pt: &Point,
        local: Vec3,
        depth: u32,
        medium: Vec3,
        composite: bool,
    ) -> Mixed {
        let m = self.material(pt.object, pt.side);
        let s = self.split(m, pt);
        let mut c = local * s.local;
        if s.reflect != Vec3::ZERO {
            let r = self.follow(self.reflections, w, pt, s.reflected, depth, medium);
            c += s.reflect * r;
        }
        let mut behind = 0.0;
        if s.transmit > 0.0 {
            let inside = if pt.entering {
                m.absorption
            } else {
                Vec3::ZERO
            };
            match (self.refractions, s.refracted) {
                (None, _) if composite => behind = s.transmit,
                // Straight through, seen by a secondary ray.
                (None, _) => {
                    c += s.transmit * self.follow(Technique::Ray, w, pt, -pt.v, depth, inside)
                }
                (Some(tech), Some(t)) => {
                    c += s.transmit * self.follow(tech, w, pt, t, depth, inside);
                }
                (Some(_), None) => {}
            }
        }
        Mixed { color: c, behind }
    }

    /// How `pt`'s material `m` splits the light ([`optics::split`]) at the interface its
    /// side and the refraction technique make.
    #[inline]
    fn split(&self, m: &Material, pt: &Point) -> optics::Split {
        let (n1, n2) = self.indices(m, pt.entering);
        optics::split(m, pt.n, pt.v, n1, n2)
    }

    /// The refractive indices `(n1, n2)` on the two sides of material `m`'s interface, the
    /// light `entering` the object or leaving it. Without a refraction technique
    /// transparency is a see-through blend: no interface is modelled (no bending, no
    /// Fresnel, no total internal reflection), `(1, 1)`.
    #[inline]
    pub(crate) fn indices(&self, m: &Material, entering: bool) -> (f32, f32) {
        match (self.refractions, entering) {
            (None, _) => (1.0, 1.0),
            (Some(_), true) => (1.0, m.ior),
            (Some(_), false) => (m.ior, 1.0),
        }
    }

    /// How `object`'s first surface is mixed: where it only looks directions up in the
    /// environment, [`Lookup::of`] may stand in for
    /// [`SecondaryEffect::mix`].
    #[inline]
    pub(crate) fn first_surface(&self, object: u32) -> FirstSurface {
        self.first_surface[object as usize]
    }

    /// The light arriving at `pt` along `dir` by technique `tech`: the environment, or a
    /// secondary ray while the depth allows (then the environment at the limit).
    fn follow(
        &self,
        tech: Technique,
        w: &World<'_>,
        pt: &Point,
        dir: Vec3,
        depth: u32,
        medium: Vec3,
    ) -> Vec3 {
        let rays = match (&self.rays, tech) {
            (Some(r), Technique::Ray) if depth < self.max_depth => r,
            _ => return self.sky(dir),
        };
        match rays.hit(w, pt.p, pt.g, dir) {
            None => self.sky(dir) * absorb(medium, f32::INFINITY),
            Some((q, dist)) => {
                let local = w.light(&q);
                let c = self.mix(w, &q, local, depth + 1, medium, false).color;
                c * absorb(medium, dist)
            }
        }
    }
}

/// The view ray through a pixel centre as an affine function of it. A pixel's ray is the
/// line of clip points `A + z·C` (`A = M·(nx, ny, 0, 1)`, `C` the clip → world matrix `M`'s
/// z column, (nx, ny) the centre's normalised device coordinates); its world points
/// `(A + z·C).xyz / (A + z·C).w` run along `A.xyz·C.w − C.xyz·A.w` (the derivative's
/// numerator, negated: from the far plane toward the near one, sign fixed by the caller).
/// `A` is affine in (nx, ny) and they in the pixel centre, so the direction is too: the
/// three planes returned, for pixel coordinates in an image of `w × h`. Orthographic
/// cameras come out constant (their `C.w` and the x and y columns' w are zero).
fn view_ray_planes(m: DMat4, w: f64, h: f64) -> [DVec3; 3] {
    let c = m.z_axis;
    let k = |a: DVec4| a.truncate() * c.w - c.truncate() * a.w;
    let (kx, ky, k0) = (k(m.x_axis), k(m.y_axis), k(m.w_axis));
    // nx = px·2/w − 1, ny = 1 − py·2/h.
    [kx * (2.0 / w), ky * (-2.0 / h), k0 - kx + ky]
}

/// Beer–Lambert: the share of light left after `d` through a medium absorbing `sigma` per
/// unit distance, `exp(−σ·d)` per channel (1 where σ = 0, even over an infinite distance).
#[inline]
fn absorb(sigma: Vec3, d: f32) -> Vec3 {
    let f = |s: f32| if s == 0.0 { 1.0 } else { (-s * d).exp() };
    Vec3::new(f(sigma.x), f(sigma.y), f(sigma.z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Intrinsics;
    use crate::effects::{Fog, FogMode};
    use crate::lighting::lane;

    /// The view ray as two clip points a pixel apart in depth: the definition
    /// [`view_ray_planes`] stands for.
    fn two_points(m: DMat4, forward: DVec3, w: f64, h: f64, x: usize, y: usize) -> DVec3 {
        let nx = (x as f64 + 0.5) / w * 2.0 - 1.0;
        let ny = 1.0 - (y as f64 + 0.5) / h * 2.0;
        let at = |z: f64| {
            let p = m * DVec4::new(nx, ny, z, 1.0);
            p.truncate() / p.w
        };
        let d = (at(0.25) - at(0.75)).normalize();
        if d.dot(forward) < 0.0 {
            -d
        } else {
            d
        }
    }

    /// An 8 × 16 equirectangular sky of distinct texels.
    fn sky() -> Vec<f32> {
        (0..8 * 16)
            .flat_map(|k| [k as f32 / 128.0, 0.5, 1.0 - k as f32 / 256.0])
            .collect()
    }

    /// A camera looking from `eye` at `target` with a field of view of `fov` degrees.
    fn camera(eye: DVec3, target: DVec3, fov: f64) -> Camera {
        Camera::look_at(eye, target, DVec3::Y, fov, 0.1, 100.0).unwrap()
    }

    #[test]
    fn lanes_give_the_view_rays_and_sky_of_one_pixel_bit_for_bit() {
        let sky = sky();
        let cam = camera(DVec3::new(0.3, 1.6, 3.4), DVec3::new(-0.2, 0.3, 0.1), 60.0);
        let mut options = RenderOptions::new(37, 23);
        options.environment_background = true;
        options.background = Vec3::new(0.25, 0.5, 0.75);
        for environment in [
            Some(Environment::new(&sky, 8, 16, 30.0, 1.0).unwrap()),
            None,
        ] {
            let mut scene = Scene::new(Vec3::splat(0.1)).unwrap();
            scene.set_environment(environment);
            let sec = SecondaryEffect::new(&scene, &cam, &options, &[], None);
            for y in 0..23 {
                for x0 in 0..30 {
                    let mut rays = [[0.0; LANES]; 3];
                    sec.view_rays(x0, y, &mut rays);
                    let n = 1 + (x0 + y) % LANES;
                    let mut c = [[-1.0; LANES]; 3];
                    sec.sky_lanes(x0, y, n, &mut c);
                    for k in 0..LANES {
                        let want = sec.view_ray(x0 + k, y);
                        let got = lane(&rays, k);
                        assert_eq!(
                            got.to_array().map(f32::to_bits),
                            want.to_array().map(f32::to_bits)
                        );
                        let got = lane(&c, k);
                        let want = if k < n {
                            sec.sky(want)
                        } else {
                            Vec3::splat(-1.0)
                        };
                        assert_eq!(
                            got.to_array().map(f32::to_bits),
                            want.to_array().map(f32::to_bits)
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn a_lookup_only_mix_is_its_lookups_mixed_bit_for_bit() {
        use crate::material::Material;
        use glam::Mat4;
        use std::sync::Arc;
        let sky = sky();
        let cam = camera(DVec3::new(0.0, 2.0, 3.0), DVec3::ZERO, 50.0);
        let base = Material::new(
            Vec3::splat(0.1),
            Vec3::new(0.6, 0.3, 0.2),
            Vec3::splat(0.4),
            20.0,
        )
        .unwrap();
        let optics = |r: Vec3, t: f32, ior: f32, fresnel: bool| {
            base.with_optics(r, t, ior, fresnel, Vec3::new(0.0, 0.5, 2.0))
                .unwrap()
        };
        let materials = [
            optics(Vec3::new(0.8, 0.5, 0.0), 0.0, 1.0, true), // a mirror
            optics(Vec3::ZERO, 0.0, 1.0, true),               // no mirror: opaque
            optics(Vec3::ZERO, 0.5, 1.5, true),               // glass with Fresnel
            optics(Vec3::new(0.1, 0.2, 0.0), 0.6, 1.33, false), // tinted, no Fresnel
            base,
        ];
        let env =
            |rot: f32, exposure: f32| Some(Environment::new(&sky, 8, 16, rot, exposure).unwrap());
        use Technique::{Environment as Env, Ray};
        for (environment, reflections, refractions) in [
            (env(10.0, 1.0), Env, Env),
            (None, Env, Env),
            (env(0.0, 2.0), Ray, Env),
            (env(0.0, 1.0), Env, Ray),
            (env(0.0, 1.0), Ray, Ray),
        ] {
            let mut scene = Scene::new(Vec3::splat(0.1)).unwrap();
            scene.set_environment(environment);
            let plane = Arc::new(crate::primitives::plane());
            for m in materials {
                scene.add(plane.clone(), m, Mat4::IDENTITY).unwrap();
            }
            let mut options = RenderOptions::new(16, 16);
            options.reflections = reflections;
            options.refractions = Some(refractions);
            // Every object's vertices in scene order, as the vertex stage gives them.
            let world = plane.positions().repeat(materials.len());
            let sec = SecondaryEffect::new(&scene, &cam, &options, &world, None);
            // Rays (max depth 5) for reflections: no object is look-ups only; for
            // refractions: the mirror still is. A zero reflectivity is no mirror: plain
            // without fog, mixed (then fogged) with it.
            use FirstSurface::{Glass, Mirror, Mix, Plain};
            let mirror = if reflections == Env { Mirror } else { Mix };
            let glass = if reflections == Env && refractions == Env {
                Glass
            } else {
                Mix
            };
            let want = [mirror, Plain, glass, glass, Plain];
            let got: Vec<FirstSurface> = (0..5).map(|o| sec.first_surface(o)).collect();
            assert_eq!(got, want, "{reflections:?} {refractions:?}");
            let fog = Fog::new(FogMode::Exp { density: 0.5 }, Vec3::ONE).unwrap();
            let fog = FogEffect::new(fog, cam.eye_distance(16, 16));
            let fogged = SecondaryEffect::new(&scene, &cam, &options, &world, Some(fog));
            let got: Vec<FirstSurface> = (0..5).map(|o| fogged.first_surface(o)).collect();
            let want = [mirror, Mix, glass, glass, Mix];
            assert_eq!(got, want, "fogged {reflections:?} {refractions:?}");
            let w = World {
                world: &world,
                normal: &[],
                surfaces: &[],
                two_sided: false,
            };
            // Points of the glass that transmit, and under total internal reflection.
            let mut seen = [0; 2];
            for object in (0..5).filter(|&o| matches!(sec.first_surface(o), Mirror | Glass)) {
                for k in 0..400 {
                    let a = k as f32 * 0.37;
                    let n = Vec3::new(a.sin() * 0.3, 1.0, a.cos() * 0.2).normalize();
                    // From grazing (total internal reflection when leaving) to head-on.
                    let v = Vec3::new(a.cos(), 0.02 + (k % 9) as f32 * 0.12, a.sin()).normalize();
                    let pt = Point {
                        p: Vec3::new(a.sin(), 0.0, a.cos()),
                        n,
                        g: Vec3::Y,
                        v,
                        entering: k % 2 == 0,
                        object,
                        side: (k / 2) % 2,
                    };
                    let local = Vec3::new(0.3, 0.6 * (k % 3) as f32, 0.9);
                    let want = sec.mix(&w, &pt, local, 0, Vec3::ZERO, false).color;
                    let m = sec.material(pt.object, pt.side);
                    let (n1, n2) = sec.indices(m, pt.entering);
                    let l = Lookup::of(optics::split(m, pt.n, pt.v, n1, n2), local);
                    if materials[object as usize].is_transparent() {
                        seen[usize::from(l.transmit > 0.0)] += 1;
                    }
                    let got = l.color(sec.sky(l.reflected), sec.sky(l.refracted));
                    assert_eq!(
                        got.to_array().map(f32::to_bits),
                        want.to_array().map(f32::to_bits),
                        "object {object}, point {k}"
                    );
                }
            }
            if glass == Glass {
                assert!(seen[0] > 20 && seen[1] > 20, "{seen:?}");
            }
        }
    }

    /// `Lookup::base_and_mirror_lanes` and `transparent_weights_lanes` give each lane
    /// `Lookup::of` of `optics::split`'s
    /// bits: with and without Fresnel, entering and leaving (total internal reflection),
    /// no interface (n1 = n2), and points with a zero or NaN normal.
    #[test]
    fn transparent_lanes_are_one_point_lookups() {
        let glass = |r: Vec3, t: f32, ior: f32, fresnel: bool| {
            Material::default()
                .with_optics(r, t, ior, fresnel, Vec3::ZERO)
                .unwrap()
        };
        let materials = [
            glass(Vec3::ZERO, 0.5, 1.5, true),
            glass(Vec3::new(0.1, 0.2, 0.0), 0.6, 1.33, false),
            glass(Vec3::new(0.3, 0.0, 0.1), 0.7, 2.4, true),
            glass(Vec3::ZERO, 1.0, 1.5, true),
        ];
        let mut points: Vec<(Vec3, Vec3)> = (0..400)
            .map(|k| {
                let a = k as f32 * 0.37;
                let n = Vec3::new(a.sin() * 0.3, 1.0, a.cos() * 0.2).normalize();
                // From grazing to head-on, and a few from behind (n·v < 0).
                let vy = -0.1 + (k % 11) as f32 * 0.11;
                (n, Vec3::new(a.cos(), vy, a.sin()).normalize())
            })
            .collect();
        points.push((Vec3::ZERO, Vec3::Y));
        points.push((Vec3::splat(f32::NAN), Vec3::Y));
        points.push((Vec3::Y, Vec3::splat(f32::NAN)));
        let mut seen = [0; 3]; // nothing transmitted, transmitted, total internal reflection
        for m in &materials {
            for (n1, n2) in [(1.0, m.ior), (m.ior, 1.0), (1.0, 1.0)] {
                for (g, group) in points.chunks(LANES).enumerate() {
                    let lanes = |f: &dyn Fn(&(Vec3, Vec3)) -> Vec3| {
                        let mut out = [[0.0; LANES]; 3];
                        for (k, p) in group.iter().enumerate() {
                            set_lane(&mut out, k, f(p));
                        }
                        out
                    };
                    let local_of = |k: usize| Vec3::new(0.3, 0.2 * (k % 4) as f32, 0.9);
                    let (nl, vl) = (lanes(&|p| p.0), lanes(&|p| p.1));
                    let mut local = [[0.0; LANES]; 3];
                    for k in 0..LANES {
                        set_lane(&mut local, k, local_of(k));
                    }
                    let mut got = Lookup::default();
                    let (mut base, mut reflect, mut reflected, mut refracted) = (
                        [[0.0; LANES]; 3],
                        [[0.0; LANES]; 3],
                        [[0.0; LANES]; 3],
                        [[0.0; LANES]; 3],
                    );
                    let mut transmit = [0.0; LANES];
                    Lookup::base_and_mirror_lanes(m, &nl, &vl, &local, &mut base, &mut reflected);
                    Lookup::transparent_weights_lanes(
                        m,
                        &nl,
                        &vl,
                        (n1, n2),
                        &mut reflect,
                        &mut transmit,
                        &mut refracted,
                    );
                    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                    let at = |a: &[[f32; LANES]; 3], k: usize| Vec3::new(a[0][k], a[1][k], a[2][k]);
                    for (k, &(n, v)) in group.iter().enumerate() {
                        let want = Lookup::of(optics::split(m, n, v, n1, n2), local_of(k));
                        got.base = at(&base, k);
                        got.reflect = at(&reflect, k);
                        got.reflected = at(&reflected, k);
                        got.transmit = transmit[k];
                        got.refracted = at(&refracted, k);
                        let what = format!("ior {} {n1}->{n2} group {g} lane {k}", m.ior);
                        assert_eq!(bits(got.base), bits(want.base), "{what}");
                        assert_eq!(bits(got.reflect), bits(want.reflect), "{what}");
                        assert_eq!(bits(got.reflected), bits(want.reflected), "{what}");
                        assert_eq!(got.transmit.to_bits(), want.transmit.to_bits(), "{what}");
                        assert_eq!(bits(got.refracted), bits(want.refracted), "{what}");
                        let tir = optics::refract(n, v, n1, n2).is_none();
                        seen[if tir {
                            2
                        } else {
                            usize::from(want.transmit > 0.0)
                        }] += 1;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&c| c > 20), "{seen:?}");
    }

    #[test]
    fn view_ray_planes_follow_every_projection() {
        let (eye, target, up) = (
            DVec3::new(0.3, 1.6, 3.4),
            DVec3::new(-0.2, 0.3, 0.1),
            DVec3::Y,
        );
        let k = Intrinsics {
            fx: 300.0,
            fy: 280.0,
            cx: 90.0,
            cy: 40.0,
            skew: 3.0,
            width: 160,
            height: 120,
        };
        let cameras = [
            Camera::look_at(eye, target, up, 45.0, 0.1, 100.0).unwrap(),
            Camera::look_at(eye, target, up, 150.0, 1e-3, 1e5).unwrap(),
            Camera::orthographic(eye, target, up, 2.5, -4.0, 20.0).unwrap(),
            Camera::from_intrinsics(eye, target, up, k, 0.05, 50.0).unwrap(),
        ];
        let (w, h) = (160.0, 120.0);
        for cam in cameras {
            let m = (cam.projection_matrix(w / h) * cam.view_matrix()).inverse();
            let forward = (cam.target() - cam.eye()).normalize();
            let planes = view_ray_planes(m, w, h);
            for (x, y) in [(0, 0), (159, 0), (0, 119), (159, 119), (80, 60), (17, 101)] {
                let want = two_points(m, forward, w, h, x, y);
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let got = (planes[0] * px + planes[1] * py + planes[2]).normalize();
                let got = if got.dot(forward) < 0.0 { -got } else { got };
                assert!(
                    (got - want).length() < 1e-9,
                    "{:?} at ({x}, {y}): {got} vs {want}",
                    cam.projection()
                );
            }
        }
    }
}
