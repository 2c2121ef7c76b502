//! `shading="auto"`: per object, an upper estimate of the RMSE (8-bit levels, against the
//! exact surface the mesh approximates) of flat, Gouraud and Phong shading, from what is known
//! before shading: the triangles' size on screen, the spread of their vertex normals, the
//! material's specular lobe and the lights. The cheapest mode within the tolerance is used.
//!
//! [`bound`] is the error of one triangle under one light; this file projects the triangles,
//! weighs them by their screen area and picks the modes. The derivation is in
//! docs/LIGHTING.md.

mod bound;

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use crate::camera::{Camera, Projection};
use crate::error::Result;
use crate::lighting::{Geometry, LightSet};
use crate::options::{check_tolerance, EdgeMode, RenderOptions, ShadingMode, SpecularModel};
use crate::scene::{Object, Scene};
use bound::{quantized_square, sensitivity, Spread};

/// The tolerance `shading="auto"` uses when none is given: RMSE of 1 level of 255.
pub const DEFAULT_TOLERANCE: f32 = 1.0;

/// At most this many triangles of an object are evaluated (evenly strided); the estimate is
/// an area-weighted mean, so a uniform sample of a large mesh estimates it, and the estimate
/// costs a bounded time (about a microsecond per triangle and light on one core: it runs
/// inside every render, where a frame of a small scene takes about a millisecond).
const MAX_SAMPLED: usize = 2048;

/// What `shading="auto"` estimated and chose for one object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadingEstimate {
    /// The mode the object is shaded with.
    pub mode: ShadingMode,
    /// Estimated RMSE in 8-bit levels of flat, Gouraud and Phong (in that order).
    pub estimates: [f32; 3],
    /// Whether the mode's estimate is within the tolerance (false: no mode met it, and
    /// Phong, the most accurate, is used).
    pub meets: bool,
    /// Estimated pixels the object's front faces cover (projected area, occlusion ignored).
    pub pixels: f64,
}

impl ShadingEstimate {
    /// The estimate of `mode`.
    pub fn estimate(&self, mode: ShadingMode) -> f32 {
        self.estimates[mode_index(mode)]
    }
}

fn mode_index(mode: ShadingMode) -> usize {
    match mode {
        ShadingMode::Flat => 0,
        ShadingMode::Gouraud => 1,
        ShadingMode::Phong => 2,
    }
}

const MODES: [ShadingMode; 3] = [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong];

/// Per object in scene order, the estimated error of each mode and the cheapest mode (flat <
/// Gouraud < Phong) whose estimate is within `tolerance`, Phong when none is; nothing is
/// rendered. The modes are those a render with `shading="auto"` and these options uses,
/// including the single mode it falls back to where objects cannot be mixed ([`plan`]).
pub fn explain_shading(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    tolerance: f32,
) -> Result<Vec<ShadingEstimate>> {
    options.validate()?;
    check_tolerance(tolerance)?;
    crate::pool::run(options.threads, || {
        Ok(plan(scene, options, estimate(scene, camera, options, tolerance)).0)
    })?
}

/// Whether a scene's objects can be shaded with different modes in one frame: the mixed
/// tile body covers the untextured, single-sample, line-free scenes without the secondary
/// stage. Elsewhere every object takes the most accurate mode any of them needs.
pub(crate) fn can_mix(scene: &Scene, options: &RenderOptions) -> bool {
    options.samples == 1
        && options.edges == EdgeMode::None
        && !scene.objects().iter().any(Object::is_textured)
        && !crate::reflect::SecondaryEffect::wanted(scene, options)
}

/// The modes a render uses: per object when they differ and the scene can mix them
/// (`Some`), otherwise one mode for all (`None`, with `shading` set to it). Each estimate's
/// `mode` and `meets` are updated to the mode actually used.
pub(crate) fn plan(
    scene: &Scene,
    options: &RenderOptions,
    mut estimates: Vec<ShadingEstimate>,
) -> (
    Vec<ShadingEstimate>,
    RenderOptions,
    Option<Vec<ShadingMode>>,
) {
    let most = estimates
        .iter()
        .map(|e| e.mode)
        .max_by_key(|m| mode_index(*m))
        .unwrap_or(ShadingMode::Flat);
    let mut opts = options.clone();
    let uniform = estimates.iter().all(|e| e.mode == most);
    if uniform || !can_mix(scene, options) {
        for e in &mut estimates {
            e.mode = most;
        }
        opts.shading = most;
        return (estimates, opts, None);
    }
    // Mixed: the options' mode is the most accurate one, so the stages every mode needs
    // (vertex normals, shadows per pixel) are prepared; each object then uses its own.
    opts.shading = most;
    let modes = estimates.iter().map(|e| e.mode).collect();
    (estimates, opts, Some(modes))
}

/// Per object, the estimates and the cheapest mode within `tolerance`.
pub(crate) fn estimate(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    tolerance: f32,
) -> Vec<ShadingEstimate> {
    let view = View::new(scene, camera, options);
    let lights = LightSet::new(scene.lights());
    scene
        .objects()
        .iter()
        .map(|o| {
            let (estimates, pixels) = object_estimate(o, &view, &lights, options.specular);
            let pick = MODES
                .into_iter()
                .find(|m| estimates[mode_index(*m)] <= tolerance);
            ShadingEstimate {
                mode: pick.unwrap_or(ShadingMode::Phong),
                estimates,
                meets: pick.is_some(),
                pixels,
            }
        })
        .collect()
}

/// The camera as the estimate needs it.
struct View {
    view_proj: glam::DMat4,
    size: (f64, f64),
    eye: DVec3,
    /// Unit vector toward the viewer when it is at infinity (orthographic camera, or the
    /// scene's infinite viewer); `None`: the local viewer at `eye`.
    infinite: Option<DVec3>,
    ortho: bool,
    /// Unit vector from the target toward the eye.
    axis: DVec3,
}

impl View {
    fn new(scene: &Scene, camera: &Camera, options: &RenderOptions) -> Self {
        let (w, h) = (options.width as f64, options.height as f64);
        let ortho = matches!(camera.projection(), Projection::Orthographic { .. });
        let toward = (camera.eye() - camera.target()).normalize_or_zero();
        View {
            view_proj: camera.projection_matrix(w / h) * camera.view_matrix(),
            size: (w, h),
            eye: camera.eye(),
            infinite: (!scene.local_viewer()).then_some(toward),
            ortho,
            axis: toward,
        }
    }

    /// Screen position (pixels) of a world point, `None` behind the eye.
    fn screen(&self, p: DVec3) -> Option<(f64, f64)> {
        let c: DVec4 = self.view_proj * p.extend(1.0);
        if c.w <= 1e-12 || !c.is_finite() {
            return None;
        }
        let (x, y) = (c.x / c.w, c.y / c.w);
        Some(((x + 1.0) * 0.5 * self.size.0, (1.0 - y) * 0.5 * self.size.1))
    }
}

/// Where a source is.
enum Place {
    /// Unit vector toward a directional light.
    Direction(DVec3),
    /// A point or spot light's position (the spot cone is not modelled: its factor ≤ 1).
    Position(DVec3),
}

/// One source as the estimate reads it.
struct Light {
    geometry: Place,
    diffuse: DVec3,
    specular: DVec3,
    attenuation: Option<[f64; 3]>,
}

/// Area-weighted rms estimate of each mode over an object, and its projected pixels.
fn object_estimate(
    object: &Object,
    view: &View,
    lights: &LightSet,
    model: SpecularModel,
) -> ([f32; 3], f64) {
    let mesh = object.mesh();
    let m = object.material();
    let to_world = object.transform().as_dmat4();
    let normal_matrix = object.normal_matrix().as_dmat3();
    let positions = mesh.positions();
    let normals = mesh.vertex_normals();
    let kd = m.diffuse.as_dvec3();
    let shininess = m.shininess as f64;
    // The lobe as a function of the angle between the normal and the half vector: Phong's
    // own r·v turns twice as fast (r moves 2β when n moves β), cos^f(2β) ≈ cos^(4f) β.
    let (f, ks_scale) = match model {
        SpecularModel::BlinnPhong => (shininess, 1.0),
        SpecularModel::Phong => (4.0 * shininess, 1.0),
        SpecularModel::NormalizedBlinnPhong => {
            (shininess, (shininess + 8.0) / (8.0 * std::f64::consts::PI))
        }
    };
    let specular_on = m.has_specular() && shininess.is_finite();
    let ks = m.specular.as_dvec3() * ks_scale;
    let sources: Vec<Light> = lights
        .sources
        .iter()
        .map(|s| Light {
            geometry: match s.geometry {
                Geometry::Directional(d) => Place::Direction(d.as_dvec3()),
                Geometry::Point(p) => Place::Position(p.as_dvec3()),
                Geometry::Spot { position, .. } => Place::Position(position.as_dvec3()),
            },
            diffuse: s.diffuse.as_dvec3(),
            specular: s.specular.as_dvec3(),
            attenuation: s.attenuation.map(|a| a.map(|v| v as f64)),
        })
        .collect();
    let indices = mesh.indices();
    let stride = indices.len().div_ceil(MAX_SAMPLED).max(1);
    let world = |k: u32| to_world.transform_point3(positions[k as usize].as_dvec3());
    let normal = |k: u32| (normal_matrix * normals[k as usize].as_dvec3()).normalize_or_zero();
    // [front, back] × (area, Σ area·squared error per mode)
    let one = |t: &[u32; 3]| {
        let mut acc = [[0.0f64; 4]; 2];
        let p = t.map(world);
        let n = t.map(normal);
        let Some(tri) = Triangle::new(p, n, view) else {
            return acc;
        };
        let mut e = [[0.0f64; 3]; 3]; // [mode][channel], linear rms
        for light in &sources {
            let (l, dist) = match light.geometry {
                Place::Direction(d) => (d, f64::INFINITY),
                Place::Position(pos) => {
                    let d = pos - tri.centroid;
                    (d.normalize_or_zero(), d.length())
                }
            };
            let att = light.attenuation.map_or(1.0, |[kc, kl, kq]| {
                1.0 / (kc + kl * dist + kq * dist * dist).max(1e-12)
            });
            let spread = tri.spread(l, dist);
            let sens = sensitivity(&spread, specular_on.then_some(f));
            let d = kd * light.diffuse * att;
            let s = ks * light.specular * att;
            for (mode, k) in [sens.flat, sens.gouraud, sens.phong].iter().zip(0..) {
                let c = d * mode[0] + s * mode[1];
                for ch in 0..3 {
                    e[k][ch] += c[ch];
                }
            }
        }
        let side = tri.back as usize;
        acc[side][0] = tri.area;
        for k in 0..3 {
            let sq: f64 = e[k].iter().map(|c| quantized_square(c * 255.0)).sum();
            acc[side][k + 1] = tri.area * sq / 3.0;
        }
        acc
    };
    // Fixed chunks summed in order: the estimate, and so the choice, is the same for any
    // thread count (a parallel reduce's association depends on the work stealing).
    let add = |mut s: [[f64; 4]; 2], b: [[f64; 4]; 2]| {
        for side in 0..2 {
            for k in 0..4 {
                s[side][k] += b[side][k];
            }
        }
        s
    };
    let sampled: Vec<&[u32; 3]> = indices.iter().step_by(stride).collect();
    let partial: Vec<[[f64; 4]; 2]> = sampled
        .par_chunks(256)
        .map(|chunk| chunk.iter().map(|t| one(t)).fold([[0.0; 4]; 2], add))
        .collect();
    let sums = partial.into_iter().fold([[0.0; 4]; 2], add);
    // Back faces count only for an object seen from behind everywhere (an open surface):
    // a closed one hides them behind its front faces.
    let acc = if sums[0][0] > 0.0 { sums[0] } else { sums[1] };
    if acc[0] <= 0.0 {
        return ([0.0; 3], 0.0);
    }
    let rmse = |k: usize| (acc[k + 1] / acc[0]).sqrt() as f32;
    ([rmse(0), rmse(1), rmse(2)], acc[0] * stride as f64)
}

/// One triangle in world space, as the bound reads it.
struct Triangle {
    centroid: DVec3,
    /// Normal at the centroid (the normalised mean of the vertex normals).
    normal: DVec3,
    /// Largest angle between two vertex normals.
    spread: f64,
    /// The angles between the vertex normals at each edge's ends.
    edge_turns: [f64; 3],
    /// Each edge's length over the longest's.
    edge_shares: [f64; 3],
    /// Longest edge (world units).
    longest: f64,
    /// The geometric normal error (rad, rms): see [`Spread::geometric`].
    geometric: f64,
    /// Unit vector toward the viewer from the centroid.
    view: DVec3,
    /// Angle the triangle subtends from the eye (0 for a viewer at infinity).
    view_span: f64,
    /// Screen area in pixels.
    area: f64,
    /// Facing away from the viewer.
    back: bool,
}

impl Triangle {
    fn new(p: [DVec3; 3], n: [DVec3; 3], view: &View) -> Option<Self> {
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let world_area2 = cross.length();
        if world_area2 <= 0.0 || !world_area2.is_finite() {
            return None;
        }
        let face = cross / world_area2;
        let s: Vec<(f64, f64)> = [(0usize, 1usize), (1, 2), (2, 0)]
            .iter()
            .map(|&(i, j)| (p[i].distance(p[j]), n[i].dot(n[j]).clamp(-1.0, 1.0).acos()))
            .collect();
        let longest = s.iter().map(|e| e.0).fold(0.0, f64::max);
        let spread = s.iter().map(|e| e.1).fold(0.0, f64::max);
        // Curvature: the normal's turn per unit length along the edges.
        let kappa = s
            .iter()
            .filter(|e| e.0 > 0.0)
            .map(|e| e.1 / e.0)
            .fold(0.0, f64::max);
        // The mesh lies inside the surface by up to the sagitta κρ²/2 of the circle through
        // its vertices (ρ the circumradius; for an obtuse triangle the sagitta peaks at the
        // longest edge's midpoint, ρ = longest/2); rms over the triangle 1/√3 of it.
        let (a, b, c) = (s[0].0, s[1].0, s[2].0);
        let mut sides = [a, b, c];
        sides.sort_by(f64::total_cmp);
        let obtuse = sides[0] * sides[0] + sides[1] * sides[1] < sides[2] * sides[2];
        let rho = if obtuse {
            longest / 2.0
        } else {
            a * b * c / (2.0 * world_area2)
        };
        let sagitta = kappa * rho * rho / 2.0;
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let mean = n[0] + n[1] + n[2];
        let normal = if mean.length_squared() > 1e-24 {
            mean.normalize()
        } else {
            face
        };
        let to_eye = view.eye - centroid;
        let (toward, dist) = match view.infinite {
            Some(v) => (v, f64::INFINITY),
            None => (to_eye.normalize_or_zero(), to_eye.length()),
        };
        // The pixels' rays: parallel to the axis for an orthographic camera.
        let ray = if view.ortho {
            view.axis
        } else {
            to_eye.normalize_or_zero()
        };
        let cos_a = face.dot(ray);
        let back = cos_a < 0.0;
        let cos_a = cos_a.abs().max(1e-3);
        let tan_a = (1.0 - cos_a * cos_a).sqrt() / cos_a;
        // A pixel's ray meets the mesh up to the sagitta below the surface: the true hit is
        // sagitta·tan α away along the surface, where the normal has turned κ times that.
        // At grazing angles it is capped by the turn across the whole circle (κρ), and never
        // exceeds the spread of the vertex normals themselves (a sliver with a tiny edge
        // otherwise claims an enormous curvature).
        let geometric = (kappa * sagitta / 3f64.sqrt() * tan_a)
            .min(kappa * rho)
            .min(spread);
        let sp = p.map(|q| view.screen(q));
        let area = match sp {
            [Some(a), Some(b), Some(c)] => {
                let inside = |lo: f64, hi: f64, v: [f64; 3]| {
                    v.iter().any(|&x| x >= lo) && v.iter().any(|&x| x <= hi)
                };
                if inside(0.0, view.size.0, [a.0, b.0, c.0])
                    && inside(0.0, view.size.1, [a.1, b.1, c.1])
                {
                    0.5 * ((b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1)).abs()
                } else {
                    0.0
                }
            }
            // Crossing the eye plane: left out (the near plane clips it anyway).
            _ => 0.0,
        };
        let edge_turns = [s[0].1, s[1].1, s[2].1];
        let edge_shares = [s[0].0 / longest, s[1].0 / longest, s[2].0 / longest];
        Some(Triangle {
            centroid,
            edge_turns,
            edge_shares,
            normal: if back { -normal } else { normal },
            spread,
            longest,
            geometric,
            view: toward,
            view_span: if dist.is_finite() {
                longest / dist
            } else {
                0.0
            },
            area,
            back,
        })
    }

    /// The spread of the lighting's arguments under a light in direction `l` (unit, toward
    /// it) at distance `dist` (infinite for a directional light).
    fn spread(&self, l: DVec3, dist: f64) -> Spread {
        let light_span = if dist.is_finite() && dist > 0.0 {
            (self.longest / dist).min(std::f64::consts::PI)
        } else {
            0.0
        };
        let h = (l + self.view).normalize_or_zero();
        let angle = |a: DVec3| self.normal.dot(a).clamp(-1.0, 1.0).acos();
        // Along an edge the light direction turns by about its length over the distance.
        let edges = |extra: f64| {
            (0..3)
                .map(|k| {
                    let t = self.edge_turns[k] + extra * self.edge_shares[k];
                    t * t
                })
                .sum::<f64>()
        };
        let view_extra = 0.5 * (light_span + self.view_span);
        Spread {
            theta: angle(l),
            span_d: self.spread + light_span,
            edges_d: edges(light_span),
            edges_s: edges(view_extra),
            beta: if h == DVec3::ZERO {
                std::f64::consts::FRAC_PI_2
            } else {
                angle(h)
            },
            span_s: self.spread + view_extra,
            geometric: self.geometric,
        }
    }
}
