//! Where a directional light's shadow map looks: the part of the scene the camera can see.
//!
//! A map fitted to the whole scene spends its texels on ground the camera never shows. The
//! points that are shaded lie in the camera's view frustum *and* in the scene's bounding
//! box, so the map only has to cover that intersection (a convex polytope) seen along the
//! light; its depth range still spans the whole box along the light, so every caster
//! between the light and a visible receiver is drawn. With cascades the frustum is cut
//! along the view axis at the practical split (the mean of the logarithmic and uniform
//! splits, λ = ½) and each slice gets a map of its own: near receivers get small texels,
//! far ones large texels, about the same size on screen.

use glam::{DMat4, DVec3, DVec4};

use crate::camera::Camera;

/// Weight of the logarithmic split against the uniform one (the "practical" split).
const LAMBDA: f64 = 0.5;

/// The view-axis depth range `[near, far]` of the camera in which scene points can lie: the
/// camera's planes narrowed to the box's extent along the view axis, or `None` when the box
/// lies wholly outside them.
pub(super) fn depth_range(camera: &Camera, lo: DVec3, hi: DVec3) -> Option<(f64, f64)> {
    let (eye, fwd) = axis(camera);
    let (mut dmin, mut dmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for c in corners(lo, hi) {
        let d = (c - eye).dot(fwd);
        dmin = dmin.min(d);
        dmax = dmax.max(d);
    }
    let (near, far) = (camera.near().max(dmin), camera.far().min(dmax));
    (near < far).then_some((near, far))
}

/// The `n + 1` split depths of `n` cascades over `[near, far]` (first `near`, last `far`).
pub(super) fn splits(near: f64, far: f64, n: u32) -> Vec<f64> {
    (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let uniform = near + (far - near) * t;
            // A logarithmic split needs near > 0 (an orthographic camera's near may be ≤ 0).
            let log = if near > 0.0 {
                near * (far / near).powf(t)
            } else {
                uniform
            };
            if i == 0 {
                near
            } else if i == n {
                far
            } else {
                LAMBDA * log + (1.0 - LAMBDA) * uniform
            }
        })
        .collect()
}

/// The camera's eye and unit view axis (view depth of `p` is `(p − eye)·axis`).
pub(super) fn axis(camera: &Camera) -> (DVec3, DVec3) {
    let eye = camera.eye();
    (eye, (camera.target() - eye).normalize())
}

/// The vertices of the part of the box `[lo, hi]` that the camera (image aspect `aspect`)
/// sees between view depths `z0 < z1`: the corners of the intersection of the frustum slice
/// and the box. Empty when they do not meet.
pub(super) fn visible_part(
    camera: &Camera,
    aspect: f64,
    z0: f64,
    z1: f64,
    lo: DVec3,
    hi: DVec3,
) -> Vec<DVec3> {
    let slice = frustum_slice(camera, aspect, z0, z1);
    let slice_faces = hull_faces(&slice);
    let box_corners = corners(lo, hi);
    let box_faces = hull_faces(&box_corners);
    // Each vertex of the intersection of two convex solids lies on a face of one of them,
    // inside the other: clip every face of each by the other's planes.
    let slice_planes: Vec<(DVec3, f64)> = slice_faces.iter().map(plane).collect();
    let box_planes: Vec<(DVec3, f64)> = box_faces.iter().map(plane).collect();
    let mut out = Vec::new();
    for f in &slice_faces {
        out.extend(clip(f.to_vec(), &box_planes));
    }
    for f in &box_faces {
        out.extend(clip(f.to_vec(), &slice_planes));
    }
    out
}

/// The 8 corners of the box `[lo, hi]`, in the order [`hull_faces`] expects.
fn corners(lo: DVec3, hi: DVec3) -> [DVec3; 8] {
    let c = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    // Bottom ring (z = lo) then top ring (z = hi), each counter-clockwise seen from +z.
    [c(0), c(1), c(3), c(2), c(4), c(5), c(7), c(6)]
}

/// The 8 corners of the camera's frustum between view depths `z0` and `z1`: the ring at
/// `z0` then the ring at `z1`, each in the same winding as [`corners`].
fn frustum_slice(camera: &Camera, aspect: f64, z0: f64, z1: f64) -> [DVec3; 8] {
    let inv: DMat4 = (camera.projection_matrix(aspect) * camera.view_matrix()).inverse();
    let (eye, fwd) = axis(camera);
    let ndc = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut out = [DVec3::ZERO; 8];
    for (k, &(x, y)) in ndc.iter().enumerate() {
        // Two points of the corner's ray (reversed Z: 1 at near, 0 at far) and, since view
        // depth is affine along the ray, the points at depths z0 and z1 by interpolation.
        let a = unproject(inv, x, y, 1.0);
        let b = unproject(inv, x, y, 0.0);
        let (da, db) = ((a - eye).dot(fwd), (b - eye).dot(fwd));
        let at = |z: f64| a + (b - a) * ((z - da) / (db - da));
        out[k] = at(z0);
        out[k + 4] = at(z1);
    }
    out
}

fn unproject(inv: DMat4, x: f64, y: f64, z: f64) -> DVec3 {
    let p = inv * DVec4::new(x, y, z, 1.0);
    p.truncate() / p.w
}

/// The six quadrilateral faces of a hexahedron given as two rings of four (see
/// [`corners`]), each wound so that its plane's normal (by [`plane`]) points outward or
/// consistently inward; [`clip`] works out which from the solid's centre.
fn hull_faces(v: &[DVec3; 8]) -> Vec<[DVec3; 4]> {
    let centre = v.iter().sum::<DVec3>() / 8.0;
    let quads = [
        [0, 1, 2, 3],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    quads
        .iter()
        .map(|q| {
            let f = q.map(|i| v[i]);
            // Orient each face outward (normal away from the centre) for `plane`.
            let (n, d) = plane(&f);
            if n.dot(centre) - d > 0.0 {
                [f[3], f[2], f[1], f[0]]
            } else {
                f
            }
        })
        .collect()
}

/// The plane `(n, d)` (points `p` with `n·p = d`) of a planar quad, `n` by Newell's method
/// (robust for any quad, degenerate corners included), following the quad's winding.
fn plane(f: &[DVec3; 4]) -> (DVec3, f64) {
    let mut n = DVec3::ZERO;
    for i in 0..4 {
        let (a, b) = (f[i], f[(i + 1) % 4]);
        n += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    let n = n.normalize_or_zero();
    let c = f.iter().sum::<DVec3>() / 4.0;
    (n, n.dot(c))
}

/// The polygon `poly` clipped to the inside (`n·p ≤ d`, with a small tolerance) of every
/// outward plane (Sutherland–Hodgman).
fn clip(mut poly: Vec<DVec3>, planes: &[(DVec3, f64)]) -> Vec<DVec3> {
    for &(n, d) in planes {
        if n == DVec3::ZERO {
            continue; // a degenerate face (zero-size box axis) bounds nothing
        }
        let scale = poly
            .iter()
            .map(|p| p.abs().max_element())
            .fold(d.abs(), f64::max);
        let eps = 1e-9 * scale.max(1e-300);
        let mut out = Vec::with_capacity(poly.len() + 2);
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let (sa, sb) = (n.dot(a) - d, n.dot(b) - d);
            if sa <= eps {
                out.push(a);
            }
            if (sa < -eps && sb > eps) || (sa > eps && sb < -eps) {
                out.push(a + (b - a) * (sa / (sa - sb)));
            }
        }
        poly = out;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> Camera {
        Camera::look_at(
            DVec3::new(0.0, 1.0, 5.0),
            DVec3::ZERO,
            DVec3::Y,
            40.0,
            0.1,
            100.0,
        )
        .unwrap()
    }

    #[test]
    fn splits_start_and_end_at_the_range_and_grow() {
        let s = splits(0.1, 100.0, 4);
        assert_eq!((s[0], s[4]), (0.1, 100.0));
        assert!(s.windows(2).all(|w| w[0] < w[1]), "{s:?}");
        // Between the logarithmic and the uniform split at each inner point.
        for (i, &z) in s.iter().enumerate().take(4).skip(1) {
            let t = i as f64 / 4.0;
            let (lg, un) = (0.1 * 1000f64.powf(t), 0.1 + 99.9 * t);
            assert!(z > lg && z < un, "{i}: {z} not between {lg} and {un}");
        }
        assert_eq!(splits(2.0, 3.0, 1), vec![2.0, 3.0]);
    }

    #[test]
    fn depth_range_narrows_to_the_box() {
        let (n, f) = depth_range(&cam(), DVec3::splat(-1.0), DVec3::splat(1.0)).unwrap();
        let d = 26f64.sqrt();
        assert!(n > d - 2.0 && n < d - 1.0, "{n}");
        assert!(f > d + 1.0 && f < d + 2.0, "{f}");
        // A box behind the camera is not seen.
        let behind = depth_range(
            &cam(),
            DVec3::new(-1.0, -1.0, 8.0),
            DVec3::new(1.0, 1.0, 9.0),
        );
        assert!(behind.is_none());
    }

    #[test]
    fn a_box_inside_the_view_is_its_own_visible_part() {
        // A small box in the middle of the view: every corner is inside the frustum, so the
        // visible part's extent is the box's.
        let (lo, hi) = (DVec3::splat(-0.5), DVec3::splat(0.5));
        let pts = visible_part(&cam(), 1.0, 0.1, 100.0, lo, hi);
        let (mn, mx) = pts
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), p| {
                (a.min(*p), b.max(*p))
            });
        assert!((mn - lo).abs().max_element() < 1e-9, "{mn}");
        assert!((mx - hi).abs().max_element() < 1e-9, "{mx}");
    }

    #[test]
    fn a_wide_floor_is_cut_to_what_the_camera_sees() {
        // A floor 200 wide: the camera sees only the part inside its frustum; every vertex
        // of the visible part projects inside the image (within rounding).
        let c = cam();
        let (lo, hi) = (
            DVec3::new(-100.0, -0.01, -100.0),
            DVec3::new(100.0, 0.0, 100.0),
        );
        let pts = visible_part(&c, 1.5, 0.1, 100.0, lo, hi);
        assert!(pts.len() >= 3);
        let vp = c.projection_matrix(1.5) * c.view_matrix();
        let (mut xmin, mut xmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in &pts {
            let q = vp * p.extend(1.0);
            let (x, y) = (q.x / q.w, q.y / q.w);
            assert!(
                x.abs() <= 1.0 + 1e-6 && y.abs() <= 1.0 + 1e-6,
                "{p} -> {x},{y}"
            );
            assert!(p.x >= lo.x - 1e-6 && p.x <= hi.x + 1e-6);
            xmin = xmin.min(p.x);
            xmax = xmax.max(p.x);
        }
        // It reaches the image's left and right edges somewhere and is far narrower than the floor.
        assert!(xmax - xmin < 150.0 && xmax - xmin > 1.0, "{xmin} {xmax}");
        // Outside the view entirely: nothing.
        let away = visible_part(
            &c,
            1.5,
            0.1,
            100.0,
            DVec3::new(50.0, 50.0, 50.0),
            DVec3::new(51.0, 51.0, 51.0),
        );
        assert!(away.is_empty(), "{away:?}");
    }
}
