//! `shading="auto"`: per object, an upper estimate of the RMSE (8-bit levels, against the
//! exact surface the mesh approximates) of flat, Gouraud and Phong shading, from what is known
//! before shading: the triangles' size on screen, the spread of their vertex normals, the
//! material's specular lobe and the lights. The cheapest mode within the tolerance is used.
//!
//! [`bound`] is the error of one triangle under one light; this file projects the triangles,
//! weighs them by their screen area and picks the modes. The derivation is in
//! docs/LIGHTING.md.

mod bound;
mod cost;
mod nodal;
use crate::trig;

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use crate::camera::{Camera, Projection};
use crate::error::Result;
use crate::lighting::{Geometry, LightSet};
use crate::lights::Shadows;
use crate::options::{
    check_tolerance, EdgeMode, GouraudMethod, Interpolation, RenderOptions, ShadingMode,
    SpecularModel,
};
use crate::scene::{Object, Scene};
use bound::{quantized_square, sensitivity, Spread};
use cost::Work;
use nodal::Nodal;

/// The tolerance `shading="auto"` uses when none is given: RMSE of 1 level of 255.
pub const DEFAULT_TOLERANCE: f32 = 1.0;

/// At most this many triangles of an object are evaluated (evenly strided); the estimate is
/// an area-weighted mean, so a uniform sample of a large mesh estimates it, and the estimate
/// costs a bounded time (it runs inside every render, where a frame of a small scene takes
/// about a millisecond): fewer on cheap frames, see [`sample_budget`].
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
            let (estimates, work) = object_estimate(o, scene, &view, &lights, options, tolerance);
            let pick = cost::pick(estimates, cost::mode_costs(&work), tolerance);
            ShadingEstimate {
                mode: pick.map_or(ShadingMode::Phong, |k| MODES[k]),
                estimates,
                meets: pick.is_some(),
                pixels: work.pixels,
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
    /// Whether the source surely reaches every point that faces it at its full strength (no
    /// shadow, no spot cone): only then does it count in the colour's lower bound.
    sure: bool,
}

/// What one object's estimate reads, fixed over its triangles.
struct Shading<'a> {
    sources: &'a [Light],
    kd: DVec3,
    ks: DVec3,
    /// The lobe's exponent in `cos^f β` and its half width; `None`: no specular term.
    lobe: Option<(f64, f64)>,
    /// The unlit part of the colour: `[low, high]` (emission and ambient terms).
    base: [DVec3; 2],
    /// Whether a channel whose lower bound reaches 1 can be taken as clamped in every mode
    /// and in the truth (no texture, fog, reflection or transparency changes the colour).
    clamps: bool,
}

/// The float-rounding of the renderer's own lighting (f32 throughout, the lobe by
/// `pow01`), relative: a few units in the last place of the colour, and `pow01`'s bound
/// of 2·10⁻⁵ on the lobe (lighting/pow.rs). Exact surfaces (a plane) are otherwise
/// estimated at 0 while the rounding flips a level here and there.
const F32_RELATIVE: f64 = 1.0 / (1u64 << 20) as f64;
const POW_RELATIVE: f64 = 2e-5;

/// Per sampled triangle: `[front, back] ×` the slots: `Σa` (`a` its screen area), `Σa·x_m`
/// (`x_m` its mean squared error in mode `m`), the count of triangles on screen, `Σa²`,
/// `Σa²·x_m` and `Σa²·x_m²` (the last three for the sampling error, see [`upper_rmse`]).
type Sums = [[f64; SLOTS]; 2];
const SLOTS: usize = 12;

fn add(mut s: Sums, b: Sums) -> Sums {
    for side in 0..2 {
        for k in 0..SLOTS {
            s[side][k] += b[side][k];
        }
    }
    s
}

/// The samples are taken in this many interleaved batches, each a uniform subsample of the
/// whole sample (every `BATCHES`-th), so that the estimate after any number of batches is
/// an estimate of the same mean and the choice can be settled early.
const BATCHES: usize = 8;
/// The batches' order: bit-reversed, so the samples taken so far stay evenly spread.
const BATCH_ORDER: [usize; BATCHES] = [0, 4, 2, 6, 1, 5, 3, 7];
/// The choice is settled early only after this many samples (or all of them)...
const MIN_SETTLED: usize = 512;
/// ...and when every cheaper mode's estimate is above `SETTLE_MARGIN` × the tolerance and
/// the chosen one's below 1/`SETTLE_MARGIN` of it (or is Phong, the only one left).
const SETTLE_MARGIN: f32 = 2.0;

/// How many triangles of an object the estimate samples: its cost (about 0.1 to 0.2 µs per
/// sampled front triangle and light on this project's 2-core test machine) is kept to a few percent of the cheapest frame the object can be drawn in,
/// whose cost grows with the image's pixels (clearing and resolving, ~0.5 ns each) and the
/// object's triangles (set-up, ~75 ns each): at most `MAX_SAMPLED`, at least
/// `MIN_SAMPLED` (or every triangle of a smaller mesh).
fn sample_budget(triangles: usize, lights: usize, pixels: f64) -> usize {
    let frame_ns = 0.5 * pixels + 75.0 * triangles as f64;
    let per_sample_ns = 150.0 * lights.max(1) as f64;
    let n = (0.04 * frame_ns / per_sample_ns) as usize;
    n.clamp(MIN_SAMPLED, MAX_SAMPLED).min(triangles)
}

/// The fewest triangles sampled on a mesh that has more (see [`sample_budget`]).
const MIN_SAMPLED: usize = 1024;

/// Area-weighted rms estimate of each mode over an object, and what its modes' costs scale
/// with (its projected pixels among them).
fn object_estimate(
    object: &Object,
    scene: &Scene,
    view: &View,
    lights: &LightSet,
    options: &RenderOptions,
    tolerance: f32,
) -> ([f32; 3], Work) {
    let model = options.specular;
    let mesh = object.mesh();
    let m = object.material();
    let to_world = object.transform().as_dmat4();
    let normal_matrix = object.normal_matrix().as_dmat3();
    let positions = mesh.positions();
    let normals = mesh.vertex_normals();
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
    let specular_on = m.has_specular() && f.is_finite() && f > 0.0;
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
            sure: matches!(s.shadows, Shadows::Off) && !matches!(s.geometry, Geometry::Spot { .. }),
        })
        .collect();
    let ka = m.ambient.as_dvec3();
    let emission = m.emission.as_dvec3();
    let light_ambient: DVec3 = lights.sources.iter().map(|s| s.ambient.as_dvec3()).sum();
    let shading = Shading {
        sources: &sources,
        kd: m.diffuse.as_dvec3(),
        ks: m.specular.as_dvec3() * ks_scale,
        lobe: specular_on.then(|| (f, bound::lobe_half_width(f))),
        base: [
            emission + ka * scene.ambient().as_dvec3(),
            emission + ka * (scene.ambient().as_dvec3() + light_ambient),
        ],
        clamps: !object.is_textured()
            && scene.fog().is_none()
            && m.reflectivity == glam::Vec3::ZERO
            && m.transparency == 0.0,
    };
    // The lighting itself at seven points of each front triangle where it is smooth there
    // (nodal.rs); Gouraud's only for its vertex-normal method and perspective-correct
    // interpolation, which blends the vertex colours linearly over the world triangle.
    let nodal = Nodal::new(
        scene,
        m,
        view.eye,
        view.infinite,
        model,
        shading.clamps,
        options.gouraud == GouraudMethod::Normals
            && options.interpolation == Interpolation::Perspective,
    )
    .with_wide_lanes(!options.baseline_isa);
    let indices = mesh.indices();
    let n_tri = indices.len();
    let mut work = Work {
        pixels: 0.0,
        front_triangles: 0.0,
        vertices: positions.len() as f64,
        lights: sources.len(),
        specular: specular_on,
    };
    if n_tri == 0 {
        return ([0.0; 3], work);
    }
    let n = sample_budget(n_tri, sources.len(), view.size.0 * view.size.1);
    let world = |k: u32| to_world.transform_point3(positions[k as usize].as_dvec3());
    let normal = |k: u32| (normal_matrix * normals[k as usize].as_dvec3()).normalize_or_zero();
    // Sample j of n is triangle ⌊j·T/n⌋: evenly strided over the index order.
    // j < n ≤ MAX_SAMPLED: the product fits 64 bits for any mesh that fits in memory.
    let triangle_of = |j: usize| &indices[(j as u64 * n_tri as u64 / n as u64) as usize];
    let one = |j: usize, back_wanted: bool| -> Sums {
        let mut acc = [[0.0f64; SLOTS]; 2];
        let t = triangle_of(j);
        let p = t.map(world);
        let Some(foot) = Footprint::new(p, view) else {
            return acc;
        };
        let face = foot.face;
        let side = foot.back as usize;
        acc[side][0] = foot.area;
        acc[side][4] = (foot.area > 0.0) as u8 as f64;
        // The lighting only where it counts: on screen, and front faces unless the object
        // shows only back faces (a second pass then).
        if foot.area <= 0.0 || foot.back != back_wanted {
            return acc;
        }
        let nv = t.map(normal);
        let tri = Triangle::new(p, nv, view, &foot);
        acc[side][5] = tri.area * tri.area;
        let sq = tri.squared_errors(
            &shading,
            (nodal.covers_gouraud() && !tri.back && nv.iter().all(|v| *v != DVec3::ZERO))
                .then_some(|fine: bool| {
                    if fine {
                        nodal.errors_fine(p, nv, face)
                    } else {
                        nodal.errors(p, nv, face, tri.offset.as_ref())
                    }
                }),
        );
        for k in 0..3 {
            let a = tri.area;
            acc[side][k + 1] = a * sq[k];
            acc[side][k + 6] = a * a * sq[k];
            acc[side][k + 9] = a * a * sq[k] * sq[k];
        }
        acc
    };
    // Fixed chunks summed in order: the estimate, and so the choice, is the same for any
    // thread count (a parallel reduce's association depends on the work stealing).
    let pass = |batch: usize, back: bool| -> Sums {
        let js: Vec<usize> = (batch..n).step_by(BATCHES).collect();
        js.par_chunks(64)
            .map(|c| c.iter().map(|&j| one(j, back)).fold([[0.0; SLOTS]; 2], add))
            .collect::<Vec<_>>()
            .into_iter()
            .fold([[0.0; SLOTS]; 2], add)
    };
    // The share of the mesh not sampled scales the sampling variance (none when every
    // triangle was seen).
    let rmse = |acc: &[f64; SLOTS], taken: usize| {
        upper_rmse(acc, 1.0 - (taken as f64 / n_tri as f64).min(1.0))
    };
    // The counts scaled from the samples taken to the whole mesh.
    let scaled = |acc: &[f64; SLOTS], taken: usize| {
        let scale = n_tri as f64 / taken.max(1) as f64;
        Work {
            pixels: acc[0] * scale,
            front_triangles: acc[4] * scale,
            ..work
        }
    };
    // Several batches in one parallel pass, summed in their order (the same sums as one
    // after the other, with fewer joins and both threads busy: one batch is two chunks).
    let passes = |batches: &[usize], back: bool| -> Sums {
        let sums: Vec<Sums> = batches.par_iter().map(|&b| pass(b, back)).collect();
        sums.into_iter().fold([[0.0; SLOTS]; 2], add)
    };
    let size = |batch: usize| (batch..n).step_by(BATCHES).len();
    let needed = MIN_SETTLED.min(n);
    // The batches before the first that may settle the choice (`taken >= needed` after it)
    // go together; the rest one at a time, each followed by the test.
    let (mut head, mut taken) = (0, 0);
    while head < BATCHES && taken < needed {
        taken += size(BATCH_ORDER[head]);
        head += 1;
    }
    let stop = |sums: &Sums, taken: usize, done: usize| {
        done + 1 < BATCHES
            && taken >= needed
            && sums[0][0] > 0.0
            && settled(
                rmse(&sums[0], taken),
                cost::mode_costs(&scaled(&sums[0], taken)),
                tolerance,
            )
    };
    let mut sums = passes(&BATCH_ORDER[..head], false);
    if !stop(&sums, taken, head - 1) {
        for (done, &batch) in BATCH_ORDER.iter().enumerate().skip(head) {
            sums = add(sums, pass(batch, false));
            taken += size(batch);
            if stop(&sums, taken, done) {
                break;
            }
        }
    }
    // Back faces count only for an object seen from behind everywhere (an open surface):
    // a closed one hides them behind its front faces.
    let acc = if sums[0][0] > 0.0 {
        sums[0]
    } else if sums[1][0] > 0.0 {
        // The back faces' area was summed over the batches taken; their lighting now.
        let back = passes(&BATCH_ORDER, true);
        taken = n;
        back[1]
    } else {
        return ([0.0; 3], work);
    };
    work = scaled(&acc, taken);
    (rmse(&acc, taken), work)
}

/// Per mode, the rms estimate from the sampled triangles' area-weighted mean squared error
/// `R = Σa·x/Σa`, raised by two standard errors of that ratio, `√(Σa²(x − R)²)/Σa` (the
/// usual variance of a ratio estimator): a triangle's error is estimated closely where its
/// lighting is smooth ([`nodal`]), so what is left is that only a sample of the triangles
/// was seen, and a highlight on a few of them may fall between the samples. `unseen`: the
/// share of the mesh's triangles not sampled (the finite-population correction).
fn upper_rmse(acc: &[f64; SLOTS], unseen: f64) -> [f32; 3] {
    if acc[0] <= 0.0 {
        return [0.0; 3];
    }
    [0, 1, 2].map(|m| {
        let r = acc[m + 1] / acc[0];
        let spread = acc[m + 9] - 2.0 * r * acc[m + 6] + r * r * acc[5];
        let se = (spread.max(0.0) * unseen).sqrt() / acc[0];
        (r + 2.0 * se).sqrt() as f32
    })
}

/// Whether more samples can no longer change the choice: every mode cheaper (by `costs`)
/// than the one chosen is estimated well above the tolerance, and the chosen one well below
/// it (or is Phong, used whatever its estimate).
fn settled(estimates: [f32; 3], costs: [f64; 3], tolerance: f32) -> bool {
    let far = |m: &usize| estimates[*m] >= SETTLE_MARGIN * tolerance;
    let Some(pick) = cost::pick(estimates, costs, tolerance) else {
        return [0, 1].iter().all(far);
    };
    let order = cost::by_cost(costs);
    let rank = order.iter().position(|&m| m == pick).unwrap_or(0);
    order[..rank].iter().all(far) && (pick == 2 || estimates[pick] * SETTLE_MARGIN <= tolerance)
}

/// What [`Triangle::light_terms`] sums over the lights.
struct LightTerms {
    e: [[f64; 3]; 3],
    low: DVec3,
    high: DVec3,
    pow_err: DVec3,
    smooth: bool,
    /// Whether every light's lobe is smooth over the triangle (only a terminator may not be).
    lobes_smooth: bool,
}

/// One triangle in world space, as the bound reads it.
struct Triangle {
    centroid: DVec3,
    /// Normal at the centroid (the normalised mean of the vertex normals).
    normal: DVec3,
    /// The face normal's component across `normal` (flat shades with the face normal).
    face_offset: DVec3,
    /// Largest angle between two vertex normals.
    spread: f64,
    /// The angles between the vertex normals at each edge's ends.
    edge_turns: [f64; 3],
    /// The normal's turn along each edge as a vector (the difference of the end normals,
    /// scaled to the angle): its direction splits the turn along and across a gradient.
    edge_dn: [DVec3; 3],
    /// Each edge's length over the longest's.
    edge_shares: [f64; 3],
    /// Longest edge (world units).
    longest: f64,
    /// The geometric normal error (rad, rms) and its largest value: see
    /// [`Spread::geometric`].
    geometric: f64,
    geometric_max: f64,
    /// Unit vector toward the viewer from the centroid.
    view: DVec3,
    /// Angle the triangle subtends from the eye (0 for a viewer at infinity).
    view_span: f64,
    /// Screen area in pixels.
    area: f64,
    /// Facing away from the viewer.
    back: bool,
    /// Where the true surface is, with signs (`None`: a planar region, a degenerate fit, or
    /// normals facing away from the eye).
    offset: Option<Offset>,
}

/// Where a triangle lands on screen: what every sampled triangle needs (its area counts
/// toward the front or back side), before the lighting only front faces on screen need.
#[derive(Clone, Copy)]
struct Footprint {
    /// Unit face normal (from the winding) and twice the world area.
    face: DVec3,
    world_area2: f64,
    centroid: DVec3,
    /// Unit vector along the pixels' rays toward the eye (the axis for an orthographic
    /// camera).
    ray: DVec3,
    /// Cosine between the face normal and `ray` (negative: a back face).
    cos_a: f64,
    back: bool,
    /// Screen area in pixels (0 off screen or crossing the eye plane).
    area: f64,
}

impl Footprint {
    /// `None` for a degenerate world triangle `p` (no face normal).
    fn new(p: [DVec3; 3], view: &View) -> Option<Self> {
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let world_area2 = cross.length();
        if world_area2 <= 0.0 || !world_area2.is_finite() {
            return None;
        }
        let face = cross / world_area2;
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let ray = if view.ortho {
            view.axis
        } else {
            (view.eye - centroid).normalize_or_zero()
        };
        let cos_a = face.dot(ray);
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
        Some(Footprint {
            face,
            world_area2,
            centroid,
            ray,
            cos_a,
            back: cos_a < 0.0,
            area,
        })
    }
}

/// The surface's second fundamental form over a triangle, from its vertex normals: the
/// symmetric 2×2 `H` (in an orthonormal basis of the triangle's plane) with `Δn ≈ H·Δp`
/// along the edges, as its eigenvalues' magnitudes and `Σ_k e_kᵀ|H|e_k` over the edges.
struct Shape {
    /// `‖H‖`: the largest magnitude of a principal curvature.
    norm: f64,
    /// `Σ_k e_kᵀ|H|e_k` over the three edges (`|H|`: `H` with its eigenvalues' magnitudes).
    edges: f64,
    /// `|H|·t` for the unit tangent `t` (2-D, in the plane's basis).
    abs: [[f64; 2]; 2],
    /// `H` itself (symmetric, signed), in the plane's basis.
    signed: [[f64; 2]; 2],
}

impl Shape {
    /// From the edges `e` (2-D) and the normals' differences along them projected on the
    /// plane `d` (2-D); `None` when the edges are degenerate.
    fn fit(e: [[f64; 2]; 3], d: [[f64; 2]; 3]) -> Option<Self> {
        // Two edges determine M with M·e_k = d_k (the third is minus their sum); H is its
        // symmetric part (the normal field of a surface has a symmetric derivative).
        let [a, b] = [e[0], e[1]];
        let det = a[0] * b[1] - a[1] * b[0];
        if det.abs() <= 1e-300 || !det.is_finite() {
            return None;
        }
        // M = D·E⁻¹ with E = [a b] (columns), D = [d0 d1].
        let inv = [[b[1] / det, -b[0] / det], [-a[1] / det, a[0] / det]];
        let (d0, d1) = (d[0], d[1]);
        let mm = |r: usize, c: usize| d0[r] * inv[0][c] + d1[r] * inv[1][c];
        let (h11, h22, h12) = (mm(0, 0), mm(1, 1), 0.5 * (mm(0, 1) + mm(1, 0)));
        let mean = 0.5 * (h11 + h22);
        let r = (0.25 * (h11 - h22) * (h11 - h22) + h12 * h12).sqrt();
        let (l1, l2) = (mean + r, mean - r);
        let (p, q) = (0.5 * (l1.abs() + l2.abs()), 0.5 * (l1.abs() - l2.abs()));
        // |H| = p·I + q·(H − mean·I)/r.
        let abs = if r > 0.0 {
            [
                [p + q * (h11 - mean) / r, q * h12 / r],
                [q * h12 / r, p + q * (h22 - mean) / r],
            ]
        } else {
            [[p, 0.0], [0.0, p]]
        };
        let quad = |v: [f64; 2]| {
            v[0] * (abs[0][0] * v[0] + abs[0][1] * v[1])
                + v[1] * (abs[1][0] * v[0] + abs[1][1] * v[1])
        };
        Some(Shape {
            norm: l1.abs().max(l2.abs()),
            edges: quad(e[0]) + quad(e[1]) + quad(e[2]),
            abs,
            signed: [[h11, h12], [h12, h22]],
        })
    }

    /// `‖|H|·t‖`: how fast the normal turns per unit length along the unit tangent `t`.
    fn turn_rate(&self, t: [f64; 2]) -> f64 {
        let a = &self.abs;
        (a[0][0] * t[0] + a[0][1] * t[1]).hypot(a[1][0] * t[0] + a[1][1] * t[1])
    }
}

impl Triangle {
    /// `foot`: the triangle's [`Footprint`] (computed first, for every sample).
    fn new(p: [DVec3; 3], n: [DVec3; 3], view: &View, foot: &Footprint) -> Self {
        let Footprint {
            face,
            world_area2,
            centroid,
            ray,
            cos_a,
            back,
            area,
        } = *foot;
        let pairs = [(0usize, 1usize), (1, 2), (2, 0)];
        let edge = pairs.map(|(i, j)| p[j] - p[i]);
        let len = edge.map(|e| e.length());
        let turns = pairs.map(|(i, j)| trig::acos(n[i].dot(n[j])));
        let longest = len[0].max(len[1]).max(len[2]);
        let spread = turns[0].max(turns[1]).max(turns[2]);
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
        let (geometric, geometric_max, offset) = if spread > 0.0 {
            geometric_error(&edge, &len, &n, face, ray, cos_a, world_area2, spread)
        } else {
            // Equal vertex normals: the mesh is the surface (a planar region).
            (0.0, 0.0, None)
        };
        let edge_dn = [0, 1, 2].map(|k| {
            let (i, j) = pairs[k];
            let d = n[j] - n[i];
            let len = d.length();
            if len > 0.0 {
                d * (turns[k] / len)
            } else {
                DVec3::ZERO
            }
        });
        // Oriented as the vertex normals, and flipped with them for a back face below.
        let face_n = if face.dot(normal) < 0.0 { -face } else { face };
        let face_offset = face_n - normal * face_n.dot(normal);
        Triangle {
            centroid,
            face_offset: if back { -face_offset } else { face_offset },
            edge_turns: turns,
            edge_dn,
            edge_shares: len.map(|l| l / longest),
            normal: if back { -normal } else { normal },
            spread,
            longest,
            geometric,
            geometric_max,
            view: toward,
            view_span: if dist.is_finite() {
                longest / dist
            } else {
                0.0
            },
            area,
            back,
            offset,
        }
    }

    /// Per mode, the squared error in 8-bit levels summed over the channels over 3 (the
    /// triangle's mean square error), all lights together.
    /// `nodal`: flat's and Gouraud's errors from the lighting itself: at seven points
    /// ([`Nodal::errors`], called with `false`) where every light is smooth over the
    /// triangle, on the fine grid ([`Nodal::errors_fine`], with `true`) where only a
    /// terminator is not; the bound's elsewhere, and everywhere for `None`.
    fn squared_errors(
        &self,
        sh: &Shading,
        nodal: Option<impl FnOnce(bool) -> nodal::Errors>,
    ) -> [f64; 3] {
        // The seven-point errors replace the bound's flat and Gouraud terms where every
        // light is smooth over the triangle; the bound's are then not evaluated at all (a
        // triangle found not smooth takes a second, detailed pass). The geometric error
        // (Phong's whole estimate) is still added to them in magnitude.
        let mut t = self.light_terms(sh, nodal.is_none());
        match nodal {
            Some(errors) if t.smooth || t.lobes_smooth => {
                // Only a terminator is not smooth: the fine grid, which needs the bound's
                // detailed terms for what it cannot resolve.
                let fine = !t.smooth;
                if fine {
                    t = self.light_terms(sh, true);
                }
                let nodal::Errors {
                    flat,
                    gouraud,
                    against_truth,
                } = errors(fine);
                // Against Phong only: the geometric error (Phong's estimate) added.
                let geo = if against_truth { [0.0; 3] } else { t.e[2] };
                for ch in 0..3 {
                    // What the grid cannot resolve: a share of the bound's Gouraud term (the
                    // truth's own deviation from linear over the triangle).
                    let unresolved = if fine {
                        nodal::FINE_UNRESOLVED * t.e[1][ch]
                    } else {
                        0.0
                    };
                    t.e[0][ch] = flat[ch] + unresolved + geo[ch];
                    t.e[1][ch] = gouraud[ch] + unresolved + geo[ch];
                }
            }
            Some(_) => t = self.light_terms(sh, true),
            None => {}
        }
        let LightTerms {
            e,
            low,
            high,
            pow_err,
            ..
        } = t;
        let rounding = high * F32_RELATIVE + pow_err * POW_RELATIVE;
        let mut out = [0.0; 3];
        for (k, o) in out.iter_mut().enumerate() {
            *o = (0..3)
                .map(|ch| {
                    // A channel at or above 1 over the whole triangle, in the truth and in
                    // the mode, is 255 in both: no error (flat's face normal may leave the
                    // vertex normals' range, so only Gouraud and Phong).
                    if sh.clamps && k > 0 && low[ch] >= 1.0 {
                        0.0
                    } else {
                        quantized_square((e[k][ch] + rounding[ch]) * 255.0)
                    }
                })
                .sum::<f64>()
                / 3.0;
        }
        out
    }

    /// The lights' terms: each mode's error per channel (linear rms, added over the
    /// lights), the colour's range and the lobe's largest value for the rounding, and
    /// whether every light is smooth over the triangle. `detailed`: with the bound's flat
    /// and Gouraud interpolation terms (zero otherwise).
    fn light_terms(&self, sh: &Shading, detailed: bool) -> LightTerms {
        let mut e = [[0.0f64; 3]; 3]; // [mode][channel], linear rms
        let mut smooth = true;
        let mut lobes_smooth = true;
        let (mut low, mut high) = (sh.base[0], sh.base[1]);
        let mut pow_err = DVec3::ZERO;
        for light in sh.sources {
            let (l, dist) = self.toward(light);
            // The attenuation at the centroid, and its range over the triangle.
            let att_at = |r: f64| {
                light.attenuation.map_or(1.0, |[kc, kl, kq]| {
                    1.0 / (kc + kl * r + kq * r * r).max(1e-12)
                })
            };
            let att = att_at(dist);
            let (att_lo, att_hi) = if dist.is_finite() {
                (
                    att_at(dist + self.longest),
                    att_at((dist - self.longest).max(0.0)),
                )
            } else {
                (att, att)
            };
            let spread = self.spread(l, dist, detailed);
            let (sens, range) = sensitivity(&spread, sh.lobe, detailed);
            smooth &= range.smooth;
            lobes_smooth &= range.lobe_smooth;
            let d = sh.kd * light.diffuse;
            let s = sh.ks * light.specular;
            for (mode, k) in [sens.flat, sens.gouraud, sens.phong].iter().zip(0..) {
                let c = (d * mode[0] + s * mode[1]) * att;
                for ch in 0..3 {
                    e[k][ch] += c[ch];
                }
            }
            if light.sure {
                low += (d * range.diffuse[0] + s * range.specular[0]) * att_lo;
            }
            high += (d * range.diffuse[1] + s * range.specular[1]) * att_hi;
            pow_err += s * range.specular[1] * att_hi;
        }
        LightTerms {
            e,
            low,
            high,
            pow_err,
            smooth,
            lobes_smooth,
        }
    }

    /// Unit vector from the centroid toward `light`, and its distance (infinite for a
    /// directional light).
    fn toward(&self, light: &Light) -> (DVec3, f64) {
        match light.geometry {
            Place::Direction(d) => (d, f64::INFINITY),
            Place::Position(pos) => {
                let d = pos - self.centroid;
                (d.normalize_or_zero(), d.length())
            }
        }
    }

    /// The spread of the lighting's arguments under a light in direction `l` (unit, toward
    /// it) at distance `dist` (infinite for a directional light). `detailed`: also the
    /// edges' parts along and across the gradients and the face normal's offset, which only
    /// the bound's flat and Gouraud terms read (zero otherwise).
    fn spread(&self, l: DVec3, dist: f64, detailed: bool) -> Spread {
        let light_span = if dist.is_finite() && dist > 0.0 {
            (self.longest / dist).min(std::f64::consts::PI)
        } else {
            0.0
        };
        let h = (l + self.view).normalize_or_zero();
        let angle = |a: DVec3| trig::acos(self.normal.dot(a));
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
        // The edges' turns split along the unit tangent `r` (the gradient's direction) and
        // across it; the lights' and eye's own turn, of unknown direction, added to both.
        let split = |r: DVec3, extra: f64| -> (f64, f64) {
            let r = (r - self.normal * r.dot(self.normal)).normalize_or_zero();
            (0..3).fold((0.0, 0.0), |(a, b), k| {
                let dn = self.edge_dn[k];
                let along = if r == DVec3::ZERO {
                    self.edge_turns[k]
                } else {
                    dn.dot(r).abs()
                };
                let across = (dn.length_squared() - along * along).max(0.0).sqrt();
                let x = extra * self.edge_shares[k];
                (
                    a + (along + x) * (along + x),
                    b + (across + x) * (across + x),
                )
            })
        };
        let ((along_d, _), (along_s, across_s)) = if detailed {
            (split(l, light_span), split(h, view_extra))
        } else {
            ((0.0, 0.0), (0.0, 0.0))
        };
        let offset = |r: DVec3| {
            let r = (r - self.normal * r.dot(self.normal)).normalize_or_zero();
            if r == DVec3::ZERO {
                self.face_offset.length()
            } else {
                self.face_offset.dot(r).abs()
            }
        };
        Spread {
            theta: angle(l),
            span_d: self.spread + light_span,
            edges_d: if detailed { edges(light_span) } else { 0.0 },
            along_d,
            along_s,
            across_s,
            face_d: if detailed { offset(l) } else { 0.0 },
            face_s: if detailed { offset(h) } else { 0.0 },
            beta: if h == DVec3::ZERO {
                std::f64::consts::FRAC_PI_2
            } else {
                angle(h)
            },
            span_s: self.spread + view_extra,
            geometric: self.geometric,
            geometric_max: self.geometric_max,
        }
    }
}

/// How far the normal a pixel gets from the mesh is from the true surface's normal where the
/// pixel's ray meets it: rms over the triangle and largest (radians). The derivation is in
/// docs/LIGHTING.md ("Where the mesh is not the surface").
#[allow(clippy::too_many_arguments)]
fn geometric_error(
    edge: &[DVec3; 3],
    len: &[f64; 3],
    n: &[DVec3; 3],
    face: DVec3,
    ray: DVec3,
    cos_a: f64,
    world_area2: f64,
    spread: f64,
) -> (f64, f64, Option<Offset>) {
    // An orthonormal basis of the triangle's plane.
    let u = edge[0] / len[0];
    let w = face.cross(u);
    let flat = |v: DVec3| [v.dot(u), v.dot(w)];
    let dn = [n[1] - n[0], n[2] - n[1], n[0] - n[2]];
    let Some(shape) = Shape::fit(edge.map(flat), dn.map(flat)) else {
        return (spread, spread, None);
    };
    // The mesh lies off the surface by the linear interpolation error of the surface's
    // height over the triangle, ½Σλ_i(v_i − x)ᵀH(v_i − x): at most the same with |H|, of
    // mean Σ_k e_kᵀ|H|e_k / 24 and rms at most `RMS_OVER_MEAN` times its mean.
    let depth_rms = bound::RMS_OVER_MEAN * shape.edges / 24.0;
    // Its largest value: the bubble at the circumcentre, ½‖H‖ρ² (ρ the circumradius, or half
    // the longest edge when the circumcentre is outside the triangle).
    let mut sides = *len;
    sides.sort_by(f64::total_cmp);
    let obtuse = sides[0] * sides[0] + sides[1] * sides[1] < sides[2] * sides[2];
    let rho = if obtuse {
        sides[2] / 2.0
    } else {
        len[0] * len[1] * len[2] / (2.0 * world_area2)
    };
    // A pixel's ray meets the mesh that far below the surface: the true hit is depth·tan α
    // away along the surface, in the direction of the ray's projection on the plane, where
    // the normal has turned |H|·t times that. At grazing angles it is capped by the turn
    // across the whole circle (‖H‖ρ), and never exceeds the spread of the vertex normals
    // themselves (a sliver with a tiny edge otherwise claims an enormous curvature).
    let cos_a = cos_a.abs().max(1e-3);
    let tan_a = (1.0 - cos_a * cos_a).sqrt() / cos_a;
    let tangent = ray - face * ray.dot(face);
    let t = tangent.normalize_or_zero();
    let rate = if t == DVec3::ZERO {
        0.0
    } else {
        shape.turn_rate(flat(t))
    };
    let cap = (shape.norm * rho).min(spread);
    // The same with signs, for the seven-point errors: "up" is the side the vertex normals
    // point to, where the surface lies `δ(x)` above the mesh.
    let up = if face.dot(n[0] + n[1] + n[2]) < 0.0 {
        -face
    } else {
        face
    };
    let cos_up = up.dot(ray);
    let offset = (cos_up > 1e-3).then(|| {
        let h = shape.signed;
        let form = |v: [f64; 2]| {
            v[0] * (h[0][0] * v[0] + h[0][1] * v[1]) + v[1] * (h[1][0] * v[0] + h[1][1] * v[1])
        };
        // The true hit lies δ·shift along the plane, where the normal has turned by
        // H·(δ·shift): δ times a fixed vector.
        let s = flat((ray - up * cos_up) / cos_up);
        let turn = u * (h[0][0] * s[0] + h[0][1] * s[1]) + w * (h[1][0] * s[0] + h[1][1] * s[1]);
        Offset {
            edge_forms: edge.map(|e| form(flat(e))),
            turn,
            cap,
        }
    });
    ((rate * depth_rms * tan_a).min(cap), cap, offset)
}

/// Where the true surface is over a triangle, with signs (the quadratic surface its vertex
/// normals describe): `δ(x) = ½Σλ_i(v_i − x)ᵀH(v_i − x)` above the mesh point `x`, and the
/// pixel's ray through `x` meets it `δ(x)·shift` away along the plane, where its normal has
/// turned by `H` times that (at most `cap`). With `Σλ_i = 1` and `x = Σλ_i v_i`, `δ` is
/// `½Σ_{i<j}λ_iλ_j e_ijᵀHe_ij` over the edges (the variance identity), and the turn is `δ`
/// times a fixed vector: both are kept per triangle.
#[derive(Debug, Clone, Copy)]
pub(super) struct Offset {
    /// `e_kᵀHe_k` for the edges 0→1, 1→2 and 2→0.
    edge_forms: [f64; 3],
    /// The normal's turn per unit height: `H·shift` in world space (`shift` the ray's
    /// offset along the plane per unit height, toward the eye's side).
    turn: DVec3,
    /// The largest turn of the normal (see [`geometric_error`]).
    cap: f64,
}

impl Offset {
    /// The surface's unit normal where the pixel's ray through the mesh point with
    /// barycentrics `lambda` (and the mesh's interpolated unit normal `n` there) meets it.
    pub(super) fn true_normal(&self, lambda: [f64; 3], n: DVec3) -> DVec3 {
        let [q01, q12, q20] = self.edge_forms;
        let delta = 0.5
            * (lambda[0] * lambda[1] * q01
                + lambda[1] * lambda[2] * q12
                + lambda[2] * lambda[0] * q20);
        let dn = self.turn * delta;
        let len = dn.length();
        let dn = if len > self.cap {
            dn * (self.cap / len)
        } else {
            dn
        };
        (n + dn).normalize_or_zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape_of(p: [DVec3; 3], n: [DVec3; 3]) -> Shape {
        let edge = [p[1] - p[0], p[2] - p[1], p[0] - p[2]];
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let u = edge[0].normalize();
        let w = face.cross(u);
        let flat = |v: DVec3| [v.dot(u), v.dot(w)];
        let dn = [n[1] - n[0], n[2] - n[1], n[0] - n[2]];
        Shape::fit(edge.map(flat), dn.map(flat)).unwrap()
    }

    #[test]
    fn a_small_triangle_on_a_sphere_has_its_curvature_in_every_direction() {
        let r = 2.0;
        let dirs = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.01, 0.0, 1.0).normalize(),
            DVec3::new(0.0, 0.013, 1.0).normalize(),
        ];
        let p = dirs.map(|d| d * r);
        let s = shape_of(p, dirs);
        assert!((s.norm - 1.0 / r).abs() < 1e-3, "{}", s.norm);
        let sum: f64 = [(0, 1), (1, 2), (2, 0)]
            .iter()
            .map(|&(i, j)| p[i].distance_squared(p[j]))
            .sum();
        assert!(
            (s.edges - sum / r).abs() < 1e-3 * sum / r,
            "{} {}",
            s.edges,
            sum / r
        );
    }

    #[test]
    fn a_long_triangle_along_a_cylinder_is_curved_only_across() {
        // Axis along x, radius 1; the triangle is 1 long and 0.02 wide (around the axis).
        let at = |x: f64, a: f64| {
            (
                DVec3::new(x, a.sin(), a.cos()),
                DVec3::new(0.0, a.sin(), a.cos()),
            )
        };
        let v = [at(0.0, 0.0), at(1.0, 0.0), at(0.0, 0.02)];
        let s = shape_of(v.map(|q| q.0), v.map(|q| q.1));
        assert!((s.norm - 1.0).abs() < 1e-2, "{}", s.norm);
        // Only the across components count: 2 · 0.02² (two edges span the width), not the
        // isotropic 2 · 1² + 0.02².
        assert!(
            (s.edges - 2.0 * 0.02f64.powi(2)).abs() < 1e-5,
            "{}",
            s.edges
        );
        // Along the axis the normal does not turn.
        assert!(s.turn_rate([1.0, 0.0]) < 1e-3);
    }

    #[test]
    fn a_planar_triangle_has_no_geometric_error() {
        let view = View {
            view_proj: glam::DMat4::IDENTITY,
            size: (100.0, 100.0),
            eye: DVec3::new(0.0, 0.0, 5.0),
            infinite: None,
            ortho: false,
            axis: DVec3::Z,
        };
        let p = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let foot = Footprint::new(p, &view).unwrap();
        let t = Triangle::new(p, [DVec3::Z; 3], &view, &foot);
        assert_eq!((t.geometric, t.geometric_max), (0.0, 0.0));
    }

    #[test]
    fn the_height_from_the_edges_is_the_height_from_the_vertices() {
        // δ(x) = ½Σλ_i(v_i − x)ᵀH(v_i − x) = ½Σ_{i<j}λ_iλ_j e_ijᵀHe_ij for x = Σλ_i v_i.
        let p = [
            DVec3::new(0.1, -0.2, 0.9),
            DVec3::new(0.5, 0.1, 0.8),
            DVec3::new(-0.1, 0.4, 0.85),
        ];
        let n = [
            DVec3::new(0.15, -0.25, 1.0).normalize(),
            DVec3::new(0.6, 0.05, 0.8).normalize(),
            DVec3::new(-0.2, 0.5, 0.9).normalize(),
        ];
        let shape = shape_of(p, n);
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let u = (p[1] - p[0]).normalize();
        let w = face.cross(u);
        let flat = |v: DVec3| [v.dot(u), v.dot(w)];
        let h = shape.signed;
        let form = |v: [f64; 2]| {
            v[0] * (h[0][0] * v[0] + h[0][1] * v[1]) + v[1] * (h[1][0] * v[0] + h[1][1] * v[1])
        };
        let q = [p[1] - p[0], p[2] - p[1], p[0] - p[2]].map(|e| form(flat(e)));
        for l in [
            [0.5, 0.5, 0.0],
            [0.2, 0.3, 0.5],
            [1.0 / 3.0; 3],
            [0.7, 0.1, 0.2],
        ] {
            let x = p[0] * l[0] + p[1] * l[1] + p[2] * l[2];
            let direct = 0.5 * (0..3).map(|i| l[i] * form(flat(p[i] - x))).sum::<f64>();
            let edges = 0.5 * (l[0] * l[1] * q[0] + l[1] * l[2] * q[1] + l[2] * l[0] * q[2]);
            assert!(
                (direct - edges).abs() <= 1e-12 * direct.abs().max(1e-6),
                "{direct} {edges}"
            );
        }
    }

    #[test]
    fn the_signed_offset_finds_the_sphere_where_the_ray_meets_it() {
        // A triangle on the unit sphere seen obliquely from a nearby eye: at each interior
        // node the normal the offset gives is the sphere's where the eye's ray through the
        // mesh point meets the sphere, to well within the mesh's own normal error there.
        let dirs = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.05, 0.0, 1.0).normalize(),
            DVec3::new(0.0, 0.05, 1.0).normalize(),
        ];
        let p = dirs;
        let eye = DVec3::new(2.0, 1.0, 3.0);
        let edge = [p[1] - p[0], p[2] - p[1], p[0] - p[2]];
        let len = edge.map(|e| e.length());
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let face = cross.normalize();
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let ray = (eye - centroid).normalize();
        let spread = dirs[1].angle_between(dirs[2]);
        let (_, _, offset) = geometric_error(
            &edge,
            &len,
            &dirs,
            face,
            ray,
            face.dot(ray),
            cross.length(),
            spread,
        );
        let offset = offset.expect("a front face on a curved surface");
        for l in [[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [1.0 / 3.0; 3]] {
            let x = p[0] * l[0] + p[1] * l[1] + p[2] * l[2];
            let mesh_n = (dirs[0] * l[0] + dirs[1] * l[1] + dirs[2] * l[2]).normalize();
            // The eye's ray through x meets the unit sphere at the nearer root.
            let d = (x - eye).normalize();
            let b = eye.dot(d);
            let t = -b - (b * b - (eye.length_squared() - 1.0)).sqrt();
            let exact = (eye + d * t).normalize();
            let got = offset.true_normal(l, mesh_n);
            let before = mesh_n.angle_between(exact);
            let after = got.angle_between(exact);
            assert!(before > 1e-4, "{before}");
            assert!(after < 0.1 * before, "{l:?}: {after} against {before}");
        }
    }

    #[test]
    fn the_sampling_margin_vanishes_when_every_triangle_was_seen() {
        // Two triangles of area 1 and 3 with mean squared errors 4 and 0 in every mode.
        let mut acc = [0.0; SLOTS];
        for (a, x) in [(1.0f64, 4.0f64), (3.0, 0.0)] {
            acc[0] += a;
            acc[5] += a * a;
            for m in 0..3 {
                acc[m + 1] += a * x;
                acc[m + 6] += a * a * x;
                acc[m + 9] += a * a * x * x;
            }
        }
        // R = 1: the plain rms when nothing is unseen, more when half the mesh is.
        assert_eq!(upper_rmse(&acc, 0.0), [1.0; 3]);
        // Σa²(x − R)² = 1·9 + 9·1 = 18; SE = √(18·0.5)/4 = 0.75; √(1 + 1.5).
        let half = upper_rmse(&acc, 0.5);
        assert!((half[0] - 2.5f32.sqrt()).abs() < 1e-6, "{half:?}");
    }

    #[test]
    fn the_choice_settles_only_with_a_margin() {
        let usual = [1.0, 2.0, 3.0]; // flat < Gouraud < Phong
                                     // Flat far below: settled on flat.
        assert!(settled([0.2, 0.1, 0.05], usual, 1.0));
        // Flat near the tolerance: not settled.
        assert!(!settled([0.8, 0.1, 0.05], usual, 1.0));
        // Flat and Gouraud far above: Phong whatever its estimate.
        assert!(settled([9.0, 3.0, 1.2], usual, 1.0));
        // Gouraud chosen but flat only just above: not settled.
        assert!(!settled([1.5, 0.3, 0.1], usual, 1.0));
        assert!(settled([2.5, 0.3, 0.1], usual, 1.0));
        // Phong cheaper than Gouraud: Phong within the tolerance settles it whatever
        // Gouraud's estimate.
        let dense = [1.0, 3.0, 2.0];
        assert!(settled([2.5, 0.9, 0.1], dense, 1.0));
        assert!(!settled([1.5, 0.9, 0.1], dense, 1.0));
    }
}
