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

use glam::{DMat4, DVec3, Vec3};

use super::fit;
use super::lookup::{self, FaceLanes, Kernel, Points};
use crate::camera::Camera;
use crate::error::{RasterError, Result};
use crate::lighting::{Geometry, Lanes, Source, LANES};
use crate::lights::{ShadowFilter, ShadowSettings};
use crate::options::RenderOptions;

/// The depth-only pass over the render's scene from a camera into a row-major buffer of eye
/// depths, infinite where nothing is drawn, writing every element (`passes::depth_pass`,
/// handed in by the pipeline so this room does not import it).
pub(crate) type DepthPass<'a> =
    &'a (dyn Fn(&Camera, &RenderOptions, &mut [MaybeUninit<f32>]) -> Result<()> + Sync);

/// One face: the light's camera and its depths as eye distances along its axis
/// (`f32::INFINITY` where nothing was drawn).
#[derive(Debug)]
struct Face {
    /// Read by the tests' f64 reference look-up.
    #[cfg_attr(not(test), allow(dead_code))]
    camera: Camera,
    depth: Vec<f32>,
    /// The constants of the batched look-up ([`lookup`]).
    lanes: FaceLanes,
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

    /// The share of the filter's texels (one for `filter="none"`) that see each of the
    /// first `live` lanes' points lit ([`lookup`]; `out` is left as it is beyond `live`).
    /// `WIDE`: the caller is compiled for AVX2 + FMA (the kernel then gathers its texels).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays
    pub fn visibility_lanes<const WIDE: bool>(
        &self,
        pts: &Points<'_>,
        live: usize,
        out: &mut Lanes,
    ) {
        let live_lanes: [bool; LANES] = std::array::from_fn(|l| l < live);
        if self.faces.len() == 1 {
            let f = &self.faces[0];
            lookup::visibility::<WIDE>(&f.lanes, self.kernel(&f.depth), pts, &live_lanes, out);
            return;
        }
        // Several faces (cube, cascades): each lane's face, then one pass per face present.
        let mut which = [usize::MAX; LANES];
        for l in 0..live {
            let p = Vec3::new(pts.p[0][l], pts.p[1][l], pts.p[2][l]);
            which[l] = self.face_of(p);
        }
        for (i, f) in self.faces.iter().enumerate() {
            let active: [bool; LANES] = std::array::from_fn(|l| which[l] == i);
            if active.iter().any(|&a| a) {
                lookup::visibility::<WIDE>(&f.lanes, self.kernel(&f.depth), pts, &active, out);
            }
        }
    }

    /// The look-up's view of one face's depths under this map's filter and bias.
    fn kernel<'m>(&self, depth: &'m [f32]) -> Kernel<'m> {
        Kernel {
            depth,
            res: self.res,
            half: match self.filter {
                ShadowFilter::None => 0,
                ShadowFilter::Pcf(k) => (k / 2) as i32,
            },
            clamp_outside: self.filter != ShadowFilter::None,
            bias: self.bias,
        }
    }

    /// The index of the face that holds point `p`: the cube face seeing it, or the first
    /// cascade reaching its view depth.
    fn face_of(&self, p: Vec3) -> usize {
        match (self.cube_at, &self.cascades) {
            (Some(q), _) => cube_face(p - q),
            (None, Some((eye, axis, ends))) => {
                let z = (p.as_dvec3() - *eye).dot(*axis);
                ends.iter().take_while(|&&e| z > e).count()
            }
            (None, None) => 0,
        }
    }
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

/// The depth pass from `camera` into a face of eye distances; `texel` is the world size
/// of one texel at eye depth 1 (perspective) or anywhere (orthographic).
fn render_face(
    depth_pass: DepthPass<'_>,
    camera: Camera,
    opts: &RenderOptions,
    res: usize,
    perspective: bool,
    texel: f64,
) -> Result<Face> {
    let n = res * res;
    let mut depth: Vec<f32> = Vec::with_capacity(n);
    depth_pass(&camera, opts, &mut depth.spare_capacity_mut()[..n])?;
    // SAFETY: the pass succeeded, so it wrote all `n` eye depths (every tile writes every
    // pixel of its rows, see `passes::depth_pass`); the vector has that capacity.
    unsafe { depth.set_len(n) };
    Ok(Face {
        lanes: FaceLanes::new(&camera.view_matrix(), camera.eye(), texel, res, perspective),
        camera,
        depth,
    })
}

#[cfg(test)]
mod tests {
    use glam::DVec4;

    use super::*;
    use crate::camera::Projection;
    use crate::lighting::LightSet;
    use crate::lights::{DirectionalLight, Light, PointLight, Shadows, SpotLight};
    use crate::shadows::lcg::Lcg;

    /// The point-at-a-time f64 look-up (the form before the batched one): each kernel
    /// texel's receiver depth from the light's ray through its centre and the point's plane,
    /// through the face camera's f64 matrices.
    fn reference(map: &ShadowMap, n: Vec3, p: Vec3, g: Vec3) -> f32 {
        let face = &map.faces[map.face_of(p)];
        let cam = &face.camera;
        let res = map.res as f64;
        let (perspective, half) = match cam.projection() {
            Projection::Perspective { fov_y } => (true, (fov_y.to_radians() / 2.0).tan()),
            Projection::Orthographic { height } => (false, height / 2.0),
            Projection::Pinhole(_) => unreachable!(),
        };
        let texel = 2.0 * half / res;
        let (view, view_proj) = (
            cam.view_matrix(),
            cam.projection_matrix(1.0) * cam.view_matrix(),
        );
        let toward = if perspective {
            (cam.eye() - p.as_dvec3()).normalize_or_zero()
        } else {
            (cam.eye() - cam.target()).normalize()
        };
        if n.as_dvec3().dot(toward) <= 0.0 {
            return 1.0;
        }
        let g = g.as_dvec3().normalize_or_zero();
        let g = if g.dot(n.as_dvec3()) < 0.0 { -g } else { g };
        let pv = view.transform_point3(p.as_dvec3());
        let gv = view.transform_vector3(g);
        let depth = -pv.z;
        if perspective && depth.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return 1.0;
        }
        let s = if perspective { texel * depth } else { texel };
        let tolerance = s * map.bias as f64 + 1e-6 * depth.abs();
        let c = view_proj * DVec4::new(p.x as f64, p.y as f64, p.z as f64, 1.0);
        let (sx, sy) = ((c.x / c.w + 1.0) / 2.0 * res, (1.0 - c.y / c.w) / 2.0 * res);
        if !(sx.is_finite() && sy.is_finite()) {
            return 1.0;
        }
        let (tx, ty) = (sx.floor() as i64, sy.floor() as i64);
        let r = map.res as i64;
        let (h, k) = match map.filter {
            ShadowFilter::None if tx < 0 || ty < 0 || tx >= r || ty >= r => return 1.0,
            ShadowFilter::None => (0, 1),
            ShadowFilter::Pcf(k) => ((k / 2) as i64, k as i64),
        };
        let mut lit = 0;
        for y in ty - h..=ty + h {
            for x in tx - h..=tx + h {
                // The ray through the texel's centre, in view space, and the plane's depth on it.
                let ndc = DVec3::new(
                    (x as f64 + 0.5) / res * 2.0 - 1.0,
                    1.0 - (y as f64 + 0.5) / res * 2.0,
                    0.0,
                );
                let (o, d) = if perspective {
                    (DVec3::ZERO, DVec3::new(ndc.x * half, ndc.y * half, -1.0))
                } else {
                    (DVec3::new(ndc.x * half, ndc.y * half, 0.0), DVec3::NEG_Z)
                };
                let den = gv.dot(d);
                let t = gv.dot(pv - o) / den;
                let t = if den.abs() > 1e-9 && t.is_finite() && t > 0.0 {
                    t
                } else {
                    depth
                };
                let stored = face.depth[(y.clamp(0, r - 1) * r + x.clamp(0, r - 1)) as usize];
                lit += (t - tolerance <= stored as f64) as i64;
            }
        }
        lit as f32 / (k * k) as f32
    }

    /// The batched f32 look-up agrees with the f64 reference for every light kind and
    /// filter, over points of all kinds (lit, shadowed, in penumbrae, behind the light,
    /// outside the map, facing away): a lane may differ only where a comparison is within
    /// rounding of its threshold, so by one texel of the kernel, on a tiny share of points.
    #[test]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays
    fn batched_lookup_matches_the_f64_reference() {
        let lights: Vec<Light> = vec![
            DirectionalLight::new(Vec3::new(-0.3, -1.0, -0.4), Vec3::ONE, 1.0)
                .unwrap()
                .into(),
            SpotLight::new(
                PointLight::new(Vec3::new(0.2, 3.0, 0.5), Vec3::ONE, 1.0).unwrap(),
                Vec3::new(-0.1, -1.0, -0.2),
                40.0,
                1.0,
            )
            .unwrap()
            .into(),
            PointLight::new(Vec3::new(0.1, 0.2, -0.3), Vec3::ONE, 1.0)
                .unwrap()
                .into(),
        ];
        let set = LightSet::new(&lights);
        let bounds = (Vec3::splat(-2.0), Vec3::splat(2.0));
        // A bumpy depth field over the whole NDC depth range.
        let pass = |cam: &Camera, o: &RenderOptions, out: &mut [MaybeUninit<f32>]| {
            let w = o.width as usize;
            for (i, z) in out.iter_mut().enumerate() {
                let (x, y) = ((i % w) as f32, (i / w) as f32);
                let v = 0.5 + 0.45 * (x * 0.031).sin() * (y * 0.017 + 0.3).cos();
                *z = MaybeUninit::new(if (i * 7919) % 97 == 0 {
                    f32::INFINITY
                } else {
                    cam.eye_depth_from_z(v)
                });
            }
            Ok(())
        };
        let options = RenderOptions::new(64, 48);
        for (li, s) in set.sources.iter().enumerate() {
            for filter in [
                ShadowFilter::None,
                ShadowFilter::Pcf(3),
                ShadowFilter::Pcf(5),
            ] {
                let settings = ShadowSettings::new(256, filter, 1.0).unwrap();
                let map = ShadowMap::new(s, settings, bounds, None, &options, &pass).unwrap();
                let mut rng = Lcg(li as u64 * 31 + 7);
                let (mut differ, mut total) = (0, 0);
                let (mut lit, mut dark, mut partial) = (0, 0, 0);
                for _ in 0..400 {
                    let mut pts = [[[0.0f32; LANES]; 3]; 3];
                    for l in 0..LANES {
                        let p = rng.in_box(-2.5, 2.5);
                        let g = (rng.in_box(-1.0, 1.0) + Vec3::Y).normalize_or_zero();
                        let n = (g + 0.3 * rng.in_box(-1.0, 1.0)).normalize_or_zero();
                        for a in 0..3 {
                            (pts[0][a][l], pts[1][a][l], pts[2][a][l]) = (n[a], p[a], g[a]);
                        }
                    }
                    let mut out = [f32::NAN; LANES];
                    let points = Points {
                        n: &pts[0],
                        p: &pts[1],
                        g: &pts[2],
                    };
                    map.visibility_lanes::<false>(&points, LANES, &mut out);
                    #[cfg(target_arch = "x86_64")]
                    if std::arch::is_x86_feature_detected!("avx2")
                        && std::arch::is_x86_feature_detected!("fma")
                    {
                        let mut wide = [f32::NAN; LANES];
                        // SAFETY: the CPU has the features the wide copy is compiled for.
                        unsafe { wide_lanes(&map, &points, &mut wide) };
                        assert_eq!(out, wide, "the AVX2 kernel gives the same shares");
                    }
                    for l in 0..LANES {
                        let at = |a: usize| Vec3::new(pts[a][0][l], pts[a][1][l], pts[a][2][l]);
                        let want = reference(&map, at(0), at(1), at(2));
                        let tap = 1.0 / (filter_taps(filter) as f32);
                        assert!(
                            (out[l] - want).abs() <= tap + 1e-6,
                            "light {li} {filter:?}: {} vs {want}",
                            out[l]
                        );
                        differ += ((out[l] - want).abs() > 1e-6) as u32;
                        total += 1;
                        if want == 1.0 {
                            lit += 1;
                        } else if want == 0.0 {
                            dark += 1;
                        } else {
                            partial += 1;
                        }
                    }
                }
                assert!(
                    differ * 500 <= total,
                    "light {li} {filter:?}: {differ} of {total}"
                );
                assert!(
                    lit > total / 20 && dark > total / 20,
                    "{lit} lit, {dark} dark"
                );
                if filter != ShadowFilter::None {
                    assert!(partial > total / 50, "{partial} partial of {total}");
                }
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn wide_lanes(map: &ShadowMap, points: &Points<'_>, out: &mut Lanes) {
        map.visibility_lanes::<true>(points, LANES, out)
    }

    fn filter_taps(f: ShadowFilter) -> u32 {
        match f {
            ShadowFilter::None => 1,
            ShadowFilter::Pcf(k) => k * k,
        }
    }

    /// Lanes beyond `live` are left as they were.
    #[test]
    fn lanes_beyond_live_are_untouched() {
        let light: Light = DirectionalLight::new(-Vec3::Y, Vec3::ONE, 1.0)
            .unwrap()
            .with_shadows(Shadows::Map(ShadowSettings::default()))
            .into();
        let set = LightSet::new(std::slice::from_ref(&light));
        let pass = |cam: &Camera, _: &RenderOptions, out: &mut [MaybeUninit<f32>]| {
            out.fill(MaybeUninit::new(cam.eye_depth_from_z(0.5)));
            Ok(())
        };
        let options = RenderOptions::new(8, 8);
        let bounds = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let map = ShadowMap::new(
            &set.sources[0],
            ShadowSettings::default(),
            bounds,
            None,
            &options,
            &pass,
        )
        .unwrap();
        let up = [[0.0; LANES], [1.0; LANES], [0.0; LANES]];
        let p = [[0.0; LANES], [-0.9; LANES], [0.0; LANES]];
        let mut out = [7.0; LANES];
        let points = Points {
            n: &up,
            p: &p,
            g: &up,
        };
        map.visibility_lanes::<false>(&points, 3, &mut out);
        assert_eq!(&out[3..], &[7.0; LANES - 3]);
        assert!(out[..3].iter().all(|&v| v == 0.0), "{out:?}");
    }
}
