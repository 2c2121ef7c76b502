//! Shadow maps, the lectures' shadow z-buffer: the depth-only pass (`passes::depth_pass`,
//! the same vertex, clip, setup and raster stages as the colour pass) rendered from the
//! light, then each shaded point transformed into the light's view and compared with it.
//!
//! - directional: an orthographic map fitted, seen along the light, to the part of the
//!   scene the camera can see ([`super::fit`]; to the whole scene box where points off
//!   the view are shaded too), or with cascades one map per slice of the view;
//! - spot (cutoff ≤ 60°): one perspective map covering the cone;
//! - point, wide spot, area light's sample points: a cube map (six 90° faces).
//!
//! Bias without a constant a user has to tune: each texel of the filter is compared with the
//! depth at which the light's ray through that texel's centre meets the shaded point's own
//! (geometric) plane -- a receiver-plane depth, which is the slope-scaled bias made exact for
//! every texel of the kernel -- minus a tolerance of one texel's world size at the point
//! (times the settings' `bias`). A surface therefore never shadows
//! itself however grazing the light, and a caster's shadow starts within about a texel of
//! the contact. The filter is the plain comparison (`filter="none"`) or percentage-closer
//! over a `k × k` kernel.

use std::mem::MaybeUninit;

use glam::{DMat4, DVec3, DVec4, Vec3};

use super::fit;
use crate::camera::{Camera, Projection};
use crate::error::{RasterError, Result};
use crate::lighting::{Geometry, Source};
use crate::lights::{ShadowFilter, ShadowSettings};
use crate::options::RenderOptions;

/// The depth-only pass over the render's scene from a camera into a row-major buffer
/// (`passes::depth_pass`, handed in by the pipeline so this room does not import it).
pub(crate) type DepthPass<'a> =
    &'a (dyn Fn(&Camera, &RenderOptions, &mut [MaybeUninit<f32>]) -> Result<()> + Sync);

/// One face: the light's camera and its depths as eye distances along its axis
/// (`f32::INFINITY` where nothing was drawn).
#[derive(Debug)]
struct Face {
    camera: Camera,
    view_proj: DMat4,
    view: DMat4,
    depth: Vec<f32>,
    /// World size of a texel at eye depth 1 (perspective) or anywhere (orthographic).
    texel: f64,
    /// Half the view's extent: `tan(fov/2)` (perspective) or half the height (orthographic).
    half: f64,
    /// Orthographic: the unit direction toward the light (the view's back axis).
    toward: DVec3,
    perspective: bool,
}

/// A light's shadow map: one face, six for a cube, or one per cascade.
#[derive(Debug)]
pub(crate) struct ShadowMap {
    faces: Vec<Face>,
    /// For a cube: the light's position (the face is chosen by the dominant axis).
    cube_at: Option<Vec3>,
    /// For cascades: the camera's eye and view axis, and the far depth of every cascade but
    /// the last (a point's view depth picks the first cascade reaching it).
    cascades: Option<(DVec3, DVec3, Vec<f64>)>,
    res: usize,
    filter: ShadowFilter,
    bias: f32,
}

/// Widest spot cone (half-angle, degrees) rendered as one perspective map; wider cones
/// take a cube map.
const MAX_SPOT_MAP_DEGREES: f64 = 60.0;

/// The cube's faces: view direction and up, in the order +x, −x, +y, −y, +z, −z.
const CUBE: [(DVec3, DVec3); 6] = [
    (DVec3::X, DVec3::NEG_Y),
    (DVec3::NEG_X, DVec3::NEG_Y),
    (DVec3::Y, DVec3::Z),
    (DVec3::NEG_Y, DVec3::NEG_Z),
    (DVec3::Z, DVec3::NEG_Y),
    (DVec3::NEG_Z, DVec3::NEG_Y),
];

/// The camera whose visible points are shaded, for fitting directional maps to its view:
/// `None` when points off the view are shaded too (vertices and face centres of flat and
/// Gouraud, hits of secondary rays), which the map must then cover.
pub(crate) type ViewFit<'a> = Option<&'a Camera>;

impl ShadowMap {
    /// Renders the map of source `s` (through `depth`) over a scene whose world bounds are
    /// `bounds`; a directional map is fitted to `view`'s visible part of them.
    pub fn new(
        s: &Source,
        settings: ShadowSettings,
        bounds: (Vec3, Vec3),
        view: ViewFit<'_>,
        options: &RenderOptions,
        depth: DepthPass<'_>,
    ) -> Result<Self> {
        let res = settings.resolution() as usize;
        let (lo, hi) = (bounds.0.as_dvec3(), bounds.1.as_dvec3());
        let center = (lo + hi) / 2.0;
        let radius = ((hi - lo).length() / 2.0).max(1e-30);
        let mut opts = RenderOptions::new(res as u32, res as u32);
        opts.threads = options.threads;
        opts.baseline_isa = options.baseline_isa;
        let mut faces = Vec::new();
        let mut cube_at = None;
        let mut cascades = None;
        let bad = |e: RasterError| {
            RasterError::invalid_field(
                "shadows",
                format!("cannot place a shadow map for this light and scene: {e}"),
            )
        };
        match s.geometry {
            Geometry::Directional(toward) => {
                let d = toward.as_dvec3().normalize();
                let aspect = options.width as f64 / options.height as f64;
                let range = view.and_then(|c| fit::depth_range(c, lo, hi).map(|r| (c, r)));
                let parts: Vec<Vec<DVec3>> = match range {
                    Some((cam, (near, far))) => {
                        let z = fit::splits(near, far, settings.cascades());
                        let parts = z
                            .windows(2)
                            .map(|w| fit::visible_part(cam, aspect, w[0], w[1], lo, hi))
                            .collect();
                        if settings.cascades() > 1 {
                            let (eye, axis) = fit::axis(cam);
                            let ends = z[1..z.len() - 1].to_vec();
                            cascades = Some((eye, axis, ends));
                        }
                        parts
                    }
                    None => vec![Vec::new()],
                };
                let kernel = match settings.filter() {
                    ShadowFilter::None => 1,
                    ShadowFilter::Pcf(k) => k as usize,
                };
                for part in parts {
                    // A slice that sees none of the box (or no view to fit) covers the box.
                    let box_corners;
                    let pts: &[DVec3] = if part.is_empty() {
                        box_corners = box_corners_of(lo, hi);
                        &box_corners
                    } else {
                        &part
                    };
                    let (cam, height) =
                        directional_camera(d, pts, lo, hi, res, kernel).map_err(bad)?;
                    faces.push(render_face(
                        depth,
                        cam,
                        &opts,
                        res,
                        false,
                        height / res as f64,
                    )?);
                }
            }
            Geometry::Spot { position, cone } if cone.cutoff_degrees() <= MAX_SPOT_MAP_DEGREES => {
                let q = position.as_dvec3();
                let dir = cone.direction.as_dvec3();
                let up = if dir.y.abs() < 0.9 {
                    DVec3::Y
                } else {
                    DVec3::X
                };
                let fov = (2.0 * cone.cutoff_degrees() + 2.0).min(150.0);
                let (near, far) = planes(q, center, radius);
                let cam = Camera::look_at(q, q + dir, up, fov, near, far).map_err(bad)?;
                let texel = 2.0 * (fov.to_radians() / 2.0).tan() / res as f64;
                faces.push(render_face(depth, cam, &opts, res, true, texel)?);
            }
            Geometry::Point(position) | Geometry::Spot { position, .. } => {
                let q = position.as_dvec3();
                let (near, far) = planes(q, center, radius);
                for (dir, up) in CUBE {
                    let cam = Camera::look_at(q, q + dir, up, 90.0, near, far).map_err(bad)?;
                    faces.push(render_face(depth, cam, &opts, res, true, 2.0 / res as f64)?);
                }
                cube_at = Some(position);
            }
        }
        Ok(ShadowMap {
            faces,
            cube_at,
            cascades,
            res,
            filter: settings.filter(),
            bias: settings.bias(),
        })
    }

    /// The share of the filter's texels (one for `filter="none"`) that see the point `p`
    /// (shading normal `n`, geometric normal `g`) lit.
    pub fn visibility(&self, n: Vec3, p: Vec3, g: Vec3) -> f32 {
        let face = match (self.cube_at, &self.cascades) {
            (Some(q), _) => &self.faces[cube_face(p - q)],
            (None, Some((eye, axis, ends))) => {
                let z = (p.as_dvec3() - *eye).dot(*axis);
                &self.faces[ends.iter().take_while(|&&e| z > e).count()]
            }
            (None, None) => &self.faces[0],
        };
        let toward = if face.perspective {
            (face.camera.eye() - p.as_dvec3()).normalize_or_zero()
        } else {
            face.toward
        };
        if n.as_dvec3().dot(toward) <= 0.0 {
            return 1.0; // faces away: no diffuse or specular whatever the map says
        }
        let g = g.as_dvec3().normalize_or_zero();
        let g = if g.dot(n.as_dvec3()) < 0.0 { -g } else { g };
        // In the light's view space (looking down −z): the point, its plane's normal.
        let pv = face.view.transform_point3(p.as_dvec3());
        let gv = face.view.transform_vector3(g);
        let depth = -pv.z;
        if face.perspective && depth.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return 1.0; // behind the light: the face does not see it
        }
        // World size of a texel at the point; the tolerance is one texel (times `bias`).
        let s = if face.perspective {
            face.texel * depth
        } else {
            face.texel
        };
        let tolerance = s * self.bias as f64 + 1e-6 * depth.abs();
        // The point's texel coordinates.
        let c = face.view_proj * DVec4::new(p.x as f64, p.y as f64, p.z as f64, 1.0);
        let res = self.res as f64;
        let (sx, sy) = ((c.x / c.w + 1.0) / 2.0 * res, (1.0 - c.y / c.w) / 2.0 * res);
        if !(sx.is_finite() && sy.is_finite()) {
            return 1.0;
        }
        // Far outside the map (clamped so the kernel offsets cannot overflow) reads its edge.
        let (tx, ty) = (
            floor(sx).clamp(-(1 << 40), 1 << 40),
            floor(sy).clamp(-(1 << 40), 1 << 40),
        );
        let r = self.res as i64;
        // Receiver-plane depth: the depth at which the light's ray through a texel's centre
        // meets the point's own plane, so a sloped receiver compares with its own depth at
        // every texel of the kernel (no acne at grazing light, no large constant bias).
        // The ray through texel (x, y) leaves o (orthographic: (ndc_x, ndc_y, 0)·half) along
        // d (perspective: (ndc_x·half, ndc_y·half, −1); orthographic −z) and meets the plane
        // at t = g·(p − o) / g·d: numerator and denominator are affine in (x, y), since
        // ndc_x = a·x + a/2 − 1 and ndc_y = 1 − a/2 − a·y with a = 2/res.
        let a = 2.0 / res;
        let (gx, gy) = (gv.x * face.half, gv.y * face.half);
        let (cx, cy) = (a / 2.0 - 1.0, 1.0 - a / 2.0);
        let gp = gv.dot(pv);
        let (num, den) = if face.perspective {
            ((gp, 0.0, 0.0), (gx * cx + gy * cy - gv.z, gx * a, -gy * a))
        } else {
            ((gp - gx * cx - gy * cy, -gx * a, gy * a), (-gv.z, 0.0, 0.0))
        };
        let (h, k) = match self.filter {
            ShadowFilter::None if tx < 0 || ty < 0 || tx >= r || ty >= r => {
                return 1.0; // outside the map: nothing there casts a shadow
            }
            ShadowFilter::None => (0, 1),
            ShadowFilter::Pcf(k) => ((k / 2) as i64, k),
        };
        // The share of the k × k texels around (tx, ty) (clamped to the map's edge) whose
        // stored depth is not nearer than the receiver's, less the tolerance.
        // Along the plane (denominator ≈ 0) or behind: the point's own depth.
        let receiver = |t: f64, d: f64| {
            if d.abs() > 1e-9 && t.is_finite() && t > 0.0 {
                t
            } else {
                depth
            }
        };
        let mut lit = 0u32;
        if face.perspective {
            for y in ty - h..=ty + h {
                let row = &face.depth[(y.clamp(0, r - 1) * r) as usize..][..r as usize];
                let yf = y as f64;
                let d_row = den.0 + den.2 * yf;
                for x in tx - h..=tx + h {
                    let d = d_row + den.1 * x as f64;
                    let t = receiver(num.0 / d, d);
                    lit += (t - tolerance <= row[x.clamp(0, r - 1) as usize] as f64) as u32;
                }
            }
        } else {
            // Orthographic: one denominator, so one division per point.
            let inv = 1.0 / den.0;
            for y in ty - h..=ty + h {
                let row = &face.depth[(y.clamp(0, r - 1) * r) as usize..][..r as usize];
                let n_row = num.0 + num.2 * y as f64;
                for x in tx - h..=tx + h {
                    let t = receiver((n_row + num.1 * x as f64) * inv, den.0);
                    lit += (t - tolerance <= row[x.clamp(0, r - 1) as usize] as f64) as u32;
                }
            }
        }
        lit as f32 / (k * k) as f32
    }
}

/// `⌊v⌋` of a finite `v` in the `i64` range, without the libm call `f64::floor` is on the
/// baseline instruction set.
fn floor(v: f64) -> i64 {
    let i = v as i64;
    i - ((i as f64) > v) as i64
}

/// The settings of one sample point of an area light with `side` samples per side: its
/// resolution divided by `side` (at least 64, at most the light's), since the soft shadow
/// averages `side²` maps; other lights (`side` 1) keep theirs.
pub(super) fn per_point(settings: ShadowSettings, side: u32) -> ShadowSettings {
    if side <= 1 {
        return settings;
    }
    let res = (settings.resolution() / side)
        .max(64)
        .min(settings.resolution());
    ShadowSettings::new(res, settings.filter(), settings.bias())
        .expect("a smaller valid resolution of valid settings")
}

/// Texels of the map of source `s` with `settings` (six faces for a cube).
pub(super) fn texels(s: &Source, settings: &ShadowSettings) -> u64 {
    let faces = match s.geometry {
        Geometry::Directional(_) => settings.cascades() as u64,
        Geometry::Spot { cone, .. } if cone.cutoff_degrees() <= MAX_SPOT_MAP_DEGREES => 1,
        _ => 6,
    };
    let r = settings.resolution() as u64;
    faces * r * r
}

/// The corners of the box `[lo, hi]`.
fn box_corners_of(lo: DVec3, hi: DVec3) -> Vec<DVec3> {
    (0..8)
        .map(|i| {
            DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        })
        .collect()
}

/// The orthographic camera of a directional light travelling `−d` whose square view covers
/// the points `pts` seen along the light (plus a border of the filter kernel's half width
/// and a texel, so the kernel reads drawn texels at the edge), with depth planes spanning
/// the whole box `[lo, hi]` along the light, so every caster in front of a covered point is
/// drawn. The view's centre snaps to the texel grid, so a camera that moves does not make
/// the shadow edges crawl. Returns the camera and its view height.
fn directional_camera(
    d: DVec3,
    pts: &[DVec3],
    lo: DVec3,
    hi: DVec3,
    res: usize,
    kernel: usize,
) -> Result<(Camera, f64)> {
    let up = if d.y.abs() < 0.9 { DVec3::Y } else { DVec3::X };
    // The light's frame at the origin: x, y across the light, z = p·d along it.
    let frame = DMat4::look_at_rh(DVec3::ZERO, -d, up);
    let (mut mn, mut mx) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for p in pts {
        let q = frame.transform_point3(*p);
        mn = mn.min(q);
        mx = mx.max(q);
    }
    let (mut zmin, mut zmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for c in box_corners_of(lo, hi) {
        let z = frame.transform_point3(c).z;
        zmin = zmin.min(z);
        zmax = zmax.max(z);
    }
    let scale = (hi - lo).length().max(lo.abs().max(hi.abs()).max_element());
    let tiny = 1e-6 * scale.max(1e-30);
    let size = (mx.x - mn.x).max(mx.y - mn.y).max(tiny);
    let border = (kernel / 2 + 1) as f64;
    let height = size * res as f64 / (res as f64 - 2.0 * border).max(res as f64 / 2.0);
    let texel = height / res as f64;
    let cx = ((mn.x + mx.x) / 2.0 / texel).round() * texel;
    let cy = ((mn.y + mx.y) / 2.0 / texel).round() * texel;
    // Snapping moves the centre by up to half a texel: the border above absorbs it.
    let pad = ((zmax - zmin) * 1e-3).max(tiny);
    let inverse = frame.inverse();
    let eye = inverse.transform_point3(DVec3::new(cx, cy, zmax + 2.0 * pad));
    let cam = Camera::orthographic(eye, eye - d, up, height, pad, zmax - zmin + 3.0 * pad)?;
    Ok((cam, height))
}

/// Near and far planes of a light at `q` over a scene in the sphere (`center`, `radius`).
fn planes(q: DVec3, center: DVec3, radius: f64) -> (f64, f64) {
    let far = (q - center).length() + radius;
    (far * 1e-4, far * 1.01)
}

/// The cube face (index into [`CUBE`]) that sees direction `d` from the light.
fn cube_face(d: Vec3) -> usize {
    let a = d.abs();
    if a.x >= a.y && a.x >= a.z {
        if d.x >= 0.0 {
            0
        } else {
            1
        }
    } else if a.y >= a.z {
        if d.y >= 0.0 {
            2
        } else {
            3
        }
    } else if d.z >= 0.0 {
        4
    } else {
        5
    }
}

/// The depth pass from `camera` into a face of eye distances.
fn render_face(
    depth_pass: DepthPass<'_>,
    camera: Camera,
    opts: &RenderOptions,
    res: usize,
    perspective: bool,
    texel: f64,
) -> Result<Face> {
    let half = match camera.projection() {
        Projection::Perspective { fov_y } => (fov_y.to_radians() / 2.0).tan(),
        Projection::Orthographic { height } => height / 2.0,
        Projection::Pinhole(_) => unreachable!("light cameras are look_at or orthographic"),
    };
    // Initialised (to "nothing drawn"), so reading every sample is sound whatever the pass did.
    let mut out = vec![MaybeUninit::new(-1.0f32); res * res];
    depth_pass(&camera, opts, &mut out)?;
    let depth = out
        .into_iter()
        .map(|z| {
            // SAFETY: every sample was initialised above (and the pass only writes values).
            let z = unsafe { z.assume_init() };
            if z < 0.0 {
                f32::INFINITY
            } else {
                camera.eye_depth_from_z(z)
            }
        })
        .collect();
    Ok(Face {
        toward: (camera.eye() - camera.target()).normalize(),
        view_proj: camera.projection_matrix(1.0) * camera.view_matrix(),
        view: camera.view_matrix(),
        camera,
        depth,
        texel,
        half,
        perspective,
    })
}
