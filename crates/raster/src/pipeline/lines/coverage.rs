//! Line coverage: a sample point is covered by a segment of width `w` when it lies within
//! `w / 2` of the segment (a capsule: round caps, so lines meeting at a vertex join without
//! notches). Evaluated per visibility sample, so lines are anti-aliased exactly as
//! triangles are when `samples > 1`; with one sample the point is the pixel centre.

/// A projected segment in pixel coordinates (x right, y down; pixel (x, y) has its centre at
/// (x + 0.5, y + 0.5)).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Capsule {
    pub a: [f64; 2],
    pub b: [f64; 2],
    /// (w / 2)².
    pub r2: f64,
}

impl Capsule {
    /// A segment from `a` to `b` drawn `width` pixels wide.
    pub fn new(a: [f64; 2], b: [f64; 2], width: f64) -> Self {
        Capsule {
            a,
            b,
            r2: 0.25 * width * width,
        }
    }

    /// The parameter `t` in [0, 1] of the segment point nearest `p`, when `p` is within
    /// `width / 2` of the segment (boundary included); `None` otherwise.
    #[inline]
    pub fn covers(&self, p: [f64; 2]) -> Option<f64> {
        let d = [self.b[0] - self.a[0], self.b[1] - self.a[1]];
        let ap = [p[0] - self.a[0], p[1] - self.a[1]];
        let dd = d[0] * d[0] + d[1] * d[1];
        let t = if dd > 0.0 {
            ((ap[0] * d[0] + ap[1] * d[1]) / dd).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (ex, ey) = (ap[0] - t * d[0], ap[1] - t * d[1]);
        (ex * ex + ey * ey <= self.r2).then_some(t)
    }

    /// The columns whose sample points (within `reach` of the pixel centre on each axis)
    /// can be covered on the row of pixel centres `cy`, as a closed interval of x
    /// coordinates; `None` when the row misses the capsule.
    #[inline]
    pub fn row_span(&self, cy: f64, reach: f64) -> Option<(f64, f64)> {
        let r = self.r2.sqrt();
        let (y0, y1) = (cy - reach, cy + reach);
        let (ay, by) = (self.a[1], self.b[1]);
        if y1 < ay.min(by) - r || y0 > ay.max(by) + r {
            return None;
        }
        // The segment's x over the band's y range, widened by the radius along x.
        let (ax, bx) = (self.a[0], self.b[0]);
        let dy = by - ay;
        let (lo, hi) = if dy.abs() < 1e-12 {
            (ax.min(bx), ax.max(bx))
        } else {
            let at = |y: f64| ax + (bx - ax) * ((y - ay) / dy).clamp(0.0, 1.0);
            let (p, q) = (at(y0 - r), at(y1 + r));
            (p.min(q), p.max(q))
        };
        Some((lo - r - reach, hi + r + reach))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn covers_within_half_the_width() {
        let c = Capsule::new([10.0, 10.0], [20.0, 10.0], 2.0);
        assert_eq!(c.covers([15.0, 10.0]), Some(0.5));
        assert!(c.covers([15.0, 11.0]).is_some(), "boundary is covered");
        assert!(c.covers([15.0, 11.0 + 1e-9]).is_none());
        assert!(c.covers([15.0, 8.9]).is_none());
        // Round caps: distance to the end point.
        assert_eq!(c.covers([9.0, 10.0]), Some(0.0));
        assert!(c.covers([9.3, 10.7]).is_some());
        assert!(c.covers([9.2, 10.7]).is_none());
        assert_eq!(c.covers([21.0, 10.0]), Some(1.0));
    }

    #[test]
    fn a_point_segment_is_a_disc() {
        let c = Capsule::new([3.0, 4.0], [3.0, 4.0], 1.0);
        assert!(c.covers([3.5, 4.0]).is_some());
        assert!(c.covers([3.36, 4.36]).is_none());
    }

    #[test]
    fn one_sample_covers_pixel_centres_within_half_the_width() {
        // A 1-pixel line along y = 5.5 (through the centres of row 5) covers exactly row 5;
        // moved to y = 6.0 (between rows 5 and 6), both rows' centres are at 0.5 = w/2.
        let on = Capsule::new([0.0, 5.5], [10.0, 5.5], 1.0);
        let between = Capsule::new([0.0, 6.0], [10.0, 6.0], 1.0);
        for y in 0..10 {
            let c = [4.5, y as f64 + 0.5];
            assert_eq!(on.covers(c).is_some(), y == 5, "row {y}");
            assert_eq!(between.covers(c).is_some(), y == 5 || y == 6, "row {y}");
        }
    }

    proptest! {
        /// Coverage agrees with the distance to a densely sampled segment, and every
        /// covered point lies in the row span.
        #[test]
        fn coverage_matches_the_distance(
            ax in -20.0f64..20.0, ay in -20.0f64..20.0,
            bx in -20.0f64..20.0, by in -20.0f64..20.0,
            px in -25.0f64..25.0, py in -25.0f64..25.0,
            w in 0.1f64..8.0,
        ) {
            let c = Capsule::new([ax, ay], [bx, by], w);
            let mut best = f64::INFINITY;
            for k in 0..=4000 {
                let t = k as f64 / 4000.0;
                let (qx, qy) = (ax + t * (bx - ax), ay + t * (by - ay));
                best = best.min(((px - qx).powi(2) + (py - qy).powi(2)).sqrt());
            }
            let len = ((bx - ax).powi(2) + (by - ay).powi(2)).sqrt();
            let slack = len / 8000.0 + 1e-9;
            if best < w / 2.0 - slack {
                prop_assert!(c.covers([px, py]).is_some());
            }
            if best > w / 2.0 + 1e-9 {
                prop_assert!(c.covers([px, py]).is_none());
            }
            if c.covers([px, py]).is_some() {
                let (lo, hi) = c.row_span(py, 0.0).expect("covered row has a span");
                prop_assert!(lo <= px && px <= hi, "{lo} {px} {hi}");
            }
        }
    }
}
