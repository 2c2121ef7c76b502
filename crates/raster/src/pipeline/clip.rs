//! Homogeneous clipping (Sutherland–Hodgman) before the perspective divide.
//!
//! Triangles are always clipped against the near and far planes (`0 ≤ z ≤ w` with the
//! reversed-Z [0, 1] range), and against x/y only when a vertex leaves the guard band, a
//! rectangle reaching [`GUARD_PX`] pixels beyond each image border. Inside the guard band,
//! 16.8 fixed-point coordinates stay below 2^23 and the i64 edge functions are exact.

use glam::{DVec4, Vec4};

/// How far beyond the image border (in pixels) vertices are kept unclipped.
pub(crate) const GUARD_PX: f64 = 16384.0;

/// Outcode bit of a vertex whose snapped coordinates are unusable (non-finite): the vertex
/// stage sets it beside the planes' bits.
pub(crate) const INVALID: u8 = 0x80;

/// Outcode bit of a vertex in front of the near plane (nearer the eye than it, or behind it).
pub(crate) const NEAR: u8 = 1;

/// The six clip planes as `dot(plane, p) >= 0` tests, plus the guard-band extents.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ClipPlanes {
    planes: [DVec4; 6],
    /// The guard band's x and y extents in units of w (the planes' w coefficients).
    guard: (f64, f64),
}

impl ClipPlanes {
    pub fn new(width: u32, height: u32) -> Self {
        let gx = 1.0 + 2.0 * GUARD_PX / width as f64;
        let gy = 1.0 + 2.0 * GUARD_PX / height as f64;
        ClipPlanes {
            planes: [
                DVec4::new(0.0, 0.0, -1.0, 1.0), // near: z <= w
                DVec4::new(0.0, 0.0, 1.0, 0.0),  // far: z >= 0
                DVec4::new(-1.0, 0.0, 0.0, gx),  // x <= gx w
                DVec4::new(1.0, 0.0, 0.0, gx),   // x >= -gx w
                DVec4::new(0.0, -1.0, 0.0, gy),  // y <= gy w
                DVec4::new(0.0, 1.0, 0.0, gy),   // y >= -gy w
            ],
            guard: (gx, gy),
        }
    }

    /// The guard band's x and y extents in units of w.
    pub fn guard(&self) -> (f64, f64) {
        self.guard
    }

    /// [`ClipPlanes::outcode`] of a finite `p`, with the planes' zero coefficients left
    /// out: the vertex stage classifies every vertex (six four-term dot products were about
    /// a fifth of its instructions). Bit-identical for finite `p`: `0·v` is ±0, adding ±0
    /// changes no other value, `±1·v` is exact, so each dot product is the one rounded sum
    /// below, and the sign of a zero does not change `< 0`.
    #[inline(always)]
    pub fn outcode_finite(&self, p: Vec4) -> u8 {
        let (x, y, z, w) = (p.x as f64, p.y as f64, p.z as f64, p.w as f64);
        let (gx, gy) = self.guard;
        let (gxw, gyw) = (gx * w, gy * w);
        (-z + w < 0.0) as u8
            | ((z < 0.0) as u8) << 1
            | ((-x + gxw < 0.0) as u8) << 2
            | ((x + gxw < 0.0) as u8) << 3
            | ((-y + gyw < 0.0) as u8) << 4
            | ((y + gyw < 0.0) as u8) << 5
    }

    /// Bit `i` set when `p` is outside plane `i`: the reference form of
    /// [`ClipPlanes::outcode_finite`] (tests).
    #[cfg(test)]
    pub fn outcode(&self, p: Vec4) -> u8 {
        let p = p.as_dvec4();
        let mut code = 0;
        for (i, plane) in self.planes.iter().enumerate() {
            if plane.dot(p) < 0.0 {
                code |= 1 << i;
            }
        }
        code
    }

    /// Clips the segment `a`–`b` against every plane (the lines' stage): the part inside,
    /// if any.
    pub fn clip_segment(&self, a: DVec4, b: DVec4) -> Option<(DVec4, DVec4)> {
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for plane in &self.planes {
            let (da, db) = (plane.dot(a), plane.dot(b));
            if da < 0.0 && db < 0.0 {
                return None;
            }
            if da < 0.0 {
                t0 = t0.max(da / (da - db));
            } else if db < 0.0 {
                t1 = t1.min(da / (da - db));
            }
        }
        (t0 < t1).then(|| (a + (b - a) * t0, a + (b - a) * t1))
    }

    /// Clips the triangle `tri` against the planes in `mask`. Each output vertex carries its
    /// clip position and its barycentric weights with respect to `tri`. Returns the convex
    /// polygon (empty when nothing remains).
    pub fn clip(&self, tri: [Vec4; 3], mask: u8) -> Vec<(DVec4, [f64; 3])> {
        let mut poly: Vec<(DVec4, [f64; 3])> = vec![
            (tri[0].as_dvec4(), [1.0, 0.0, 0.0]),
            (tri[1].as_dvec4(), [0.0, 1.0, 0.0]),
            (tri[2].as_dvec4(), [0.0, 0.0, 1.0]),
        ];
        for (i, plane) in self.planes.iter().enumerate() {
            if mask & (1 << i) == 0 {
                continue;
            }
            let mut out = Vec::with_capacity(poly.len() + 1);
            for k in 0..poly.len() {
                let a = poly[k];
                let b = poly[(k + 1) % poly.len()];
                let (da, db) = (plane.dot(a.0), plane.dot(b.0));
                if da >= 0.0 {
                    out.push(a);
                }
                if (da >= 0.0) != (db >= 0.0) {
                    // Interpolate from the inside end so an edge shared by two triangles is
                    // split at bit-identical points whichever way round they walk it.
                    let ((pi, di), (po, dout)) = if da >= 0.0 {
                        ((a, da), (b, db))
                    } else {
                        ((b, db), (a, da))
                    };
                    let t = di / (di - dout);
                    let pos = pi.0 + (po.0 - pi.0) * t;
                    let w = [0, 1, 2].map(|j| pi.1[j] + (po.1[j] - pi.1[j]) * t);
                    out.push((pos, w));
                }
            }
            poly = out;
            if poly.len() < 3 {
                return Vec::new();
            }
        }
        poly
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_clip_cuts_at_the_plane() {
        let planes = ClipPlanes::new(100, 100);
        // One vertex behind the near plane (z > w).
        let tri = [
            Vec4::new(0.0, 0.0, 0.5, 1.0),
            Vec4::new(1.0, 0.0, 0.5, 1.0),
            Vec4::new(0.0, 1.0, 2.0, 1.0),
        ];
        let mask = tri.iter().fold(0, |m, p| m | planes.outcode(*p));
        assert_eq!(mask, 1);
        let poly = planes.clip(tri, mask);
        assert_eq!(poly.len(), 4);
        for (p, w) in &poly {
            assert!(p.z <= p.w + 1e-12);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn segments_are_cut_at_the_near_plane() {
        let planes = ClipPlanes::new(100, 100);
        let a = DVec4::new(0.0, 0.0, 0.5, 1.0);
        let b = DVec4::new(0.0, 0.0, 1.5, 1.0);
        let (p, q) = planes.clip_segment(a, b).unwrap();
        assert_eq!(p, a);
        assert!((q.z - q.w).abs() < 1e-12);
        assert!(planes.clip_segment(b, b * 1.1).is_none());
    }

    /// The shortened classification equals the six dot products on finite points,
    /// including points on and near every plane and signed zeros.
    #[test]
    fn finite_outcode_matches_the_dot_products() {
        let planes = ClipPlanes::new(640, 480);
        let (gx, gy) = planes.guard;
        let vals = [
            0.0f32, -0.0, 1.0, -1.0, 0.5, 2.0, -3.0, 1e-30, -1e-30, 7.5e6, -7.5e6, 1e30,
        ];
        let mut n = 0;
        for &w in &vals {
            let edges = [w, -w, (gx * w as f64) as f32, -(gx * w as f64) as f32];
            let yedges = [(gy * w as f64) as f32, -(gy * w as f64) as f32];
            for &x in vals.iter().chain(&edges) {
                for &y in vals.iter().chain(&yedges) {
                    for &z in vals.iter().chain(&[w, w * 0.999_999_9]) {
                        let p = Vec4::new(x, y, z, w);
                        assert_eq!(planes.outcode_finite(p), planes.outcode(p), "{p:?}");
                        n += 1;
                    }
                }
            }
        }
        assert!(n > 10_000);
    }

    #[test]
    fn fully_outside_is_empty() {
        let planes = ClipPlanes::new(10, 10);
        let tri = [Vec4::new(0.0, 0.0, 2.0, 1.0); 3];
        assert!(planes.clip(tri, 1).is_empty());
    }
}
