//! Triangle setup: viewport transform, 16.8 fixed-point snapping, exact orientation and
//! culling from the integer doubled area, and the pixel bounding box.

use glam::{DVec4, Vec3};

/// Sub-pixel bits of the fixed-point screen coordinates.
pub(crate) const SUBPIXEL_BITS: u32 = 8;
/// One pixel in fixed-point units.
pub(crate) const ONE: i64 = 1 << SUBPIXEL_BITS;
/// Half a pixel: pixel `x` has its centre at `x·ONE + HALF`.
pub(crate) const HALF: i64 = ONE / 2;

/// A triangle ready for rasterization. Vertices are ordered so the doubled area is positive
/// in y-down screen space; `v` indexes the post-transform vertex arrays in the same order.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SetupTri {
    pub x: [i32; 3],
    pub y: [i32; 3],
    pub v: [u32; 3],
    pub z: [f32; 3],
    pub inv_w: [f32; 3],
    /// Inclusive pixel bounds, already clipped to the image: x0, y0, x1, y1.
    pub bbox: [u16; 4],
    pub area2: i64,
    pub object: u32,
    /// Counter-clockwise on screen (front facing); the vertex order was swapped to make
    /// `area2` positive.
    pub front: bool,
    /// A piece of a clipped triangle (its vertices are not the original ones).
    pub clipped: bool,
    /// Flat mode: the (original) triangle's flat colour.
    pub flat: Vec3,
}

/// Integer edge-function coefficients of one triangle: `E_k(P) = a_k·Px + b_k·Py + c_k` over
/// fixed-point `P`, for the edge opposite vertex k, so `E_k / area2` is barycentric λ_k.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Edges {
    pub a: [i64; 3],
    pub b: [i64; 3],
    pub c: [i64; 3],
    /// 0 on top-left edges, −1 elsewhere: `E_k + bias_k >= 0` is the top-left fill rule.
    pub bias: [i64; 3],
}

impl SetupTri {
    pub fn edges(&self) -> Edges {
        edges_of(self.x.map(i64::from), self.y.map(i64::from))
    }
}

/// [`SetupTri::edges`] of vertices `(x[k], y[k])` (positive doubled area).
#[inline(always)]
fn edges_of(x: [i64; 3], y: [i64; 3]) -> Edges {
    let mut e = Edges {
        a: [0; 3],
        b: [0; 3],
        c: [0; 3],
        bias: [0; 3],
    };
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let (ax, ay) = (x[i], y[i]);
        let (bx, by) = (x[j], y[j]);
        let (dx, dy) = (bx - ax, by - ay);
        e.a[k] = -dy;
        e.b[k] = dx;
        e.c[k] = dy * ax - dx * ay;
        e.bias[k] = fill_bias(dx, dy);
    }
    e
}

/// The top-left fill rule's bias of an edge running `(dx, dy)`: 0 on top and left edges,
/// −1 elsewhere (one function for the rasterizer and setup's early coverage test).
#[inline(always)]
fn fill_bias(dx: i64, dy: i64) -> i64 {
    // Positive area in y-down space: a top edge runs in +x, a left edge runs up.
    let top_left = (dy == 0 && dx > 0) || dy < 0;
    if top_left {
        0
    } else {
        -1
    }
}

/// Whether any pixel centre of the (at most 2 × 2) pixel box `x0..=x1`, `y0..=y1` passes
/// the rasterizer's coverage test, `E_k + bias_k ≥ 0` for the three edges at `x·ONE + HALF`
/// ([`edges_of`]). With the vertices taken relative to the first centre `P`, the edge
/// function of edge `i → j` there, `a·Px + b·Py + c`, is the same integer as
/// `X_i·Y_j − X_j·Y_i`; the other corners add exact integer steps (`a·ONE`, `b·ONE`), as the
/// rasterizer steps them. A value is non-negative iff its sign bit is clear, so "all three
/// edges pass at some corner" is an OR per corner and an AND over the corners.
#[inline(always)]
fn covers_a_centre(x: [i64; 3], y: [i64; 3], (x0, y0, x1, y1): (i64, i64, i64, i64)) -> bool {
    let (cx, cy) = (x0 * ONE + HALF, y0 * ONE + HALF);
    let (sx, sy) = ((x1 - x0) * ONE, (y1 - y0) * ONE);
    let (rx, ry) = (x.map(|v| v - cx), y.map(|v| v - cy));
    let (mut m00, mut m10, mut m01, mut m11) = (0i64, 0i64, 0i64, 0i64);
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let (dx, dy) = (x[j] - x[i], y[j] - y[i]);
        let v = rx[i] * ry[j] - rx[j] * ry[i] + fill_bias(dx, dy);
        let (ax, by) = (-dy * sx, dx * sy);
        m00 |= v;
        m10 |= v + ax;
        m01 |= v + by;
        m11 |= v + ax + by;
    }
    (m00 & m10 & m01 & m11) >= 0
}

/// 1.5·2^52: adding and subtracting it rounds an f64 below 2^51 in magnitude to an integer,
/// ties to even (the vertex lanes repeat it).
pub(crate) const MAGIC: f64 = 6_755_399_441_055_744.0;

/// Round to nearest, ties to even, for |x| < 2^51 (larger or non-finite values are rejected
/// by the caller). Adding and removing 1.5·2^52 leaves no fraction bits and needs no libm call
/// (`f64::round` is one on baseline x86-64).
#[inline(always)]
fn round_even(x: f64) -> f64 {
    (x + MAGIC) - MAGIC
}

/// A snapped vertex: 16.8 fixed-point x and y, reversed-Z depth, 1/w.
pub(crate) type Snapped = (i32, i32, f32, f32);

/// Viewport transform and snapping of one clip-space vertex; `None` if not finite.
#[inline]
pub(crate) fn snap(clip: DVec4, width: f64, height: f64) -> Option<Snapped> {
    let inv_w = 1.0 / clip.w;
    let sx = (clip.x * inv_w + 1.0) * 0.5 * width;
    let sy = (1.0 - clip.y * inv_w) * 0.5 * height;
    let fx = round_even(sx * ONE as f64);
    let fy = round_even(sy * ONE as f64);
    // Inside the guard band |fx|, |fy| < 2^23; anything else is a non-finite input.
    let lim = (1u64 << 24) as f64;
    if !(fx.abs() < lim && fy.abs() < lim && inv_w.is_finite()) {
        return None;
    }
    Some((fx as i32, fy as i32, (clip.z * inv_w) as f32, inv_w as f32))
}

/// What setup decided about a triangle.
pub(crate) enum Setup {
    Draw(SetupTri),
    /// Zero area after snapping, entirely outside the image, or covering no pixel centre.
    Skip,
    /// Back facing and culling is on.
    Culled,
}

/// Sets up one (already clipped) triangle of snapped vertices. `margin` (fixed-point units)
/// is how far a pixel's sample points reach from its centre (0 with one sample): the pixel
/// bounds include every pixel one of whose samples the triangle's box contains.
#[inline(always)]
pub(crate) fn setup(
    s: [Snapped; 3],
    v: [u32; 3],
    object: u32,
    (width, height): (u32, u32),
    cull_backfaces: bool,
    margin: i64,
) -> Setup {
    let (x0, y0) = (s[0].0 as i64, s[0].1 as i64);
    let area2 =
        (s[1].0 as i64 - x0) * (s[2].1 as i64 - y0) - (s[1].1 as i64 - y0) * (s[2].0 as i64 - x0);
    if area2 == 0 {
        return Setup::Skip;
    }
    // y-down screen: counter-clockwise as seen (the front) has negative area here.
    let front = area2 < 0;
    if cull_backfaces && !front {
        return Setup::Culled;
    }
    let (order, area2) = if front {
        ([0, 2, 1], -area2)
    } else {
        ([0, 1, 2], area2)
    };
    let s = order.map(|k| s[k]);
    let xs = s.map(|p| p.0 as i64);
    let ys = s.map(|p| p.1 as i64);
    // Pixel x is covered only if a sample point x·ONE + HALF + o, |o| ≤ margin, lies within
    // the bounds.
    let first = |lo: i64| (lo - HALF - margin + ONE - 1).div_euclid(ONE);
    let last = |hi: i64| (hi - HALF + margin).div_euclid(ONE);
    let px0 = first(*xs.iter().min().unwrap()).max(0);
    let py0 = first(*ys.iter().min().unwrap()).max(0);
    let px1 = last(*xs.iter().max().unwrap()).min(width as i64 - 1);
    let py1 = last(*ys.iter().max().unwrap()).min(height as i64 - 1);
    if px0 > px1 || py0 > py1 {
        return Setup::Skip;
    }
    // Exact early cull: at a million triangles most are smaller than a pixel, and a box of
    // at most 2 × 2 pixel centres is tested here with the rasterizer's edge functions and
    // fill rule (`covers_a_centre`), so a triangle that covers none of them is never
    // stored, binned or rasterized; every pixel stays the same. Only with one sample at the
    // centre (with several, `margin` widens the box and the sample points move).
    if margin == 0
        && px1 - px0 <= 1
        && py1 - py0 <= 1
        && !covers_a_centre(xs, ys, (px0, py0, px1, py1))
    {
        return Setup::Skip;
    }
    Setup::Draw(SetupTri {
        x: s.map(|p| p.0),
        y: s.map(|p| p.1),
        v: order.map(|k| v[k]),
        z: s.map(|p| p.2),
        inv_w: s.map(|p| p.3),
        bbox: [px0 as u16, py0 as u16, px1 as u16, py1 as u16],
        area2,
        object,
        front,
        clipped: false,
        flat: Vec3::ZERO,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(pts: [(i32, i32); 3]) -> SetupTri {
        let s = pts.map(|(x, y)| (x * ONE as i32, y * ONE as i32, 0.5, 1.0));
        match setup(s, [0, 1, 2], 0, (100, 100), false, 0) {
            Setup::Draw(t) => t,
            _ => panic!("skipped"),
        }
    }

    #[test]
    fn orientation_and_barycentrics() {
        // Counter-clockwise as seen on a y-down screen: (0,0) → (0,10) → (10,0).
        let t = tri([(0, 0), (0, 10), (10, 0)]);
        assert!(t.front);
        assert!(t.area2 > 0);
        let e = t.edges();
        // At each vertex its own λ is 1, the others 0.
        for k in 0..3 {
            let (px, py) = (t.x[k] as i64, t.y[k] as i64);
            for j in 0..3 {
                let val = e.a[j] * px + e.b[j] * py + e.c[j];
                assert_eq!(val, if j == k { t.area2 } else { 0 });
            }
        }
        let back = tri([(0, 0), (10, 0), (0, 10)]);
        assert!(!back.front);
    }

    #[test]
    fn round_even_rounds_to_nearest() {
        for (x, want) in [
            (0.4, 0.0),
            (0.6, 1.0),
            (-0.6, -1.0),
            (2.5, 2.0),
            (3.5, 4.0),
            (-2.5, -2.0),
        ] {
            assert_eq!(round_even(x), want, "{x}");
        }
        assert_eq!(round_even(8_388_607.7), 8_388_608.0);
    }

    /// The early cull drops exactly the triangles whose pixel box holds no covered centre:
    /// on a grid of small triangles at every sub-pixel offset, a triangle is kept iff some
    /// pixel centre passes its edge functions with the fill rule.
    #[test]
    fn early_cull_keeps_exactly_the_triangles_covering_a_centre() {
        let mut kept = 0;
        let mut culled = 0;
        for shape in [[(0, 0), (90, 20), (30, 100)], [(0, 0), (300, 10), (10, 40)]] {
            for ox in (0..512).step_by(37) {
                for oy in (0..512).step_by(41) {
                    for flip in [false, true] {
                        let mut p = shape.map(|(x, y)| (x + ox + 1024, y + oy + 1024));
                        if flip {
                            p.swap(1, 2);
                        }
                        let s = p.map(|(x, y)| (x, y, 0.5, 1.0));
                        // The same triangle, ordered as setup orders it, covers a centre?
                        let (x, y) = (p.map(|q| q.0 as i64), p.map(|q| q.1 as i64));
                        let area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
                        let o = if area < 0 { [0, 2, 1] } else { [0, 1, 2] };
                        let e = edges_of(o.map(|k| x[k]), o.map(|k| y[k]));
                        let covers = (0..20i64).any(|py| {
                            (0..20i64).any(|px| {
                                let (cx, cy) = (px * ONE + HALF, py * ONE + HALF);
                                (0..3).all(|k| e.a[k] * cx + e.b[k] * cy + e.c[k] + e.bias[k] >= 0)
                            })
                        });
                        let drawn =
                            matches!(setup(s, [0, 1, 2], 0, (100, 100), false, 0), Setup::Draw(_));
                        let small = matches!(
                            setup(s, [0, 1, 2], 0, (100, 100), false, 0),
                            Setup::Draw(t) if t.bbox[2] - t.bbox[0] > 1 || t.bbox[3] - t.bbox[1] > 1
                        );
                        // Boxes wider than 2 × 2 centres are not tested (drawn regardless).
                        assert!(covers == drawn || small, "{p:?}");
                        if drawn {
                            kept += 1;
                        } else {
                            culled += 1;
                        }
                    }
                }
            }
        }
        assert!(kept > 50 && culled > 50, "{kept} {culled}");
    }

    #[test]
    fn bbox_uses_pixel_centres() {
        // x from 0.5 to 2.5 px: centres 0.5, 1.5, 2.5 → pixels 0..=2.
        let s = [
            (128, 0, 0.0, 1.0),
            (640, 0, 0.0, 1.0),
            (128, 2560, 0.0, 1.0),
        ];
        let Setup::Draw(t) = setup(s, [0, 1, 2], 0, (100, 100), false, 0) else {
            panic!()
        };
        assert_eq!(t.bbox, [0, 0, 2, 9]);
    }
}
