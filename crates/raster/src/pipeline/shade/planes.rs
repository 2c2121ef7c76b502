//! Interpolation planes: the perspective weights of a triangle as planes over pixel
//! coordinates, cached per tile, and what flat and Gouraud step along a run.

use std::mem::MaybeUninit;

use super::{ShadeContext, GOURAUD};
use crate::pipeline::raster::NO_TRIANGLE;
use crate::pipeline::setup::{SetupTri, ONE};

/// The perspective weight planes of `t` in pixel units: λ_k / w_k at the pixel-space point
/// (x, y) is `plane[k][0]·x + plane[k][1]·y + plane[k][2]` (f64, so no cancellation matters).
///
/// Coverage uses the snapped vertices, but attributes are interpolated over the unsnapped
/// screen triangle (from the f32 clip coordinates, to ~1e-4 px instead of the snap's 1/512
/// px), as GPUs do: snapping then moves no colour or normal. Where snapping changed the
/// triangle's area by more than 2× (slivers), the unsnapped planes would extrapolate far
/// outside the triangle at covered pixels, so the exact planes of the snapped triangle are
/// used instead.
///
/// With `AFFINE` (screen-space interpolation, [`crate::Interpolation::Screen`]) the planes
/// are the plain barycentrics λ_k (the 1/w_k dropped): the lectures' scan-line
/// interpolation, which over a triangle is the same linear function of (x, y).
pub(super) fn weight_planes<const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    t: &SetupTri,
) -> [[f64; 3]; 3] {
    weight_planes_inline::<AFFINE>(ctx, t)
}

/// [`weight_planes`], inlined into its caller's instruction set.
#[inline(always)]
fn weight_planes_inline<const AFFINE: bool>(ctx: &ShadeContext<'_>, t: &SetupTri) -> [[f64; 3]; 3] {
    let (w, h) = ctx.size;
    let screen = |k: u32| {
        let c = ctx.verts.clip[k as usize].as_dvec4();
        let iw = 1.0 / c.w;
        ((c.x * iw + 1.0) * 0.5 * w, (1.0 - c.y * iw) * 0.5 * h)
    };
    let s = [screen(t.v[0]), screen(t.v[1]), screen(t.v[2])];
    let area = (s[1].0 - s[0].0) * (s[2].1 - s[0].1) - (s[1].1 - s[0].1) * (s[2].0 - s[0].0);
    let snapped_area = t.area2 as f64 / (ONE * ONE) as f64;
    let mut plane = [[0.0; 3]; 3];
    if area.is_finite() && area > 0.5 * snapped_area && area < 2.0 * snapped_area {
        let inv_area = 1.0 / area;
        for (k, pk) in plane.iter_mut().enumerate() {
            let ((ax, ay), (bx, by)) = (s[(k + 1) % 3], s[(k + 2) % 3]);
            let q = inv_w::<AFFINE>(t, k) * inv_area;
            *pk = [
                -(by - ay) * q,
                (bx - ax) * q,
                ((by - ay) * ax - (bx - ax) * ay) * q,
            ];
        }
    } else {
        // E_k(P) over fixed-point P = ONE·(x, y), divided by the snapped area.
        let e = t.edges();
        let one = ONE as f64;
        for (k, pk) in plane.iter_mut().enumerate() {
            let q = inv_w::<AFFINE>(t, k) / t.area2 as f64;
            *pk = [
                e.a[k] as f64 * one * q,
                e.b[k] as f64 * one * q,
                e.c[k] as f64 * q,
            ];
        }
    }
    plane
}

/// The weight of vertex `k` beside its barycentric: 1/w_k, or 1 for screen-space weights.
#[inline(always)]
fn inv_w<const AFFINE: bool>(t: &SetupTri, k: usize) -> f64 {
    if AFFINE {
        1.0
    } else {
        t.inv_w[k] as f64
    }
}

/// A plane `p[0]·x + p[1]·y + p[2]` over pixel coordinates.
pub(super) type Plane = [f64; 3];

/// Entries of the per-tile plane caches (by default).
pub(super) const PLANE_CACHE: usize = 64;

/// What is made per triangle for shading (its planes; Phong's whole inputs; flat's stored
/// colour) for recently seen triangles, `N` entries direct-mapped by id: a triangle's rows
/// alternate with its neighbours' within a tile and each row segment needs them again, so
/// without this they (a dozen f64 products and four divisions at least) were recomputed per
/// segment.
///
/// Only the ids are initialised when a tile starts; an entry's value is written with its
/// id (initialising every value, 14 KB per tile for Phong's, cost about 1 % of a 1080p
/// Phong frame). The slot is `id % N`: neighbouring triangles mostly have nearby ids, which
/// then rarely collide (a multiplicative hash, which spreads ids that differ by multiples of
/// a power of two, made a Gouraud frame of Spot 4 % slower and did not miss less).
pub(super) struct PlaneCache<T, const N: usize = PLANE_CACHE> {
    ids: [u32; N],
    values: [MaybeUninit<T>; N],
}

impl<T: Copy, const N: usize> PlaneCache<T, N> {
    pub(super) fn new() -> Self {
        PlaneCache {
            ids: [NO_TRIANGLE; N],
            values: [MaybeUninit::uninit(); N],
        }
    }

    #[inline]
    pub(super) fn get(&mut self, id: u32, make: impl FnOnce() -> T) -> T {
        *self.get_ref(id, make)
    }

    /// The entry of `id`, made by `make` if it is not cached: by reference, for entries
    /// too large to copy each time a row changes triangle.
    #[inline]
    pub(super) fn get_ref(&mut self, id: u32, make: impl FnOnce() -> T) -> &T {
        let k = id as usize % N;
        // `NO_TRIANGLE` marks an empty slot, so it is never taken as cached.
        if self.ids[k] != id || id == NO_TRIANGLE {
            self.values[k] = MaybeUninit::new(make());
            self.ids[k] = id;
        }
        // SAFETY: slot `k` holds `id` (not `NO_TRIANGLE`), so its value was written when
        // the id was, here or by an earlier call.
        unsafe { self.values[k].assume_init_ref() }
    }
}

/// What flat and Gouraud interpolate, as planes over pixel coordinates: the interpolated
/// 1/w (Σ λ_k/w_k) and Gouraud's colour planes Σ λ_k/w_k · colour_k\[c\], so a pixel's colour
/// is `color / inv_w`: four planes instead of three weights and nine products. Stored by
/// coefficient, the four planes side by side (1/w, red, green, blue): plane `q` at (x, y) is
/// `dx[q]·x + dy[q]·y + c[q]`, so a run's four start values are a few vector operations.
#[derive(Clone, Copy, Default)]
pub(super) struct RunPlanes {
    dx: [f64; 4],
    dy: [f64; 4],
    c: [f64; 4],
}

impl RunPlanes {
    /// The planes of triangle `t`: 1/w, and with `MODE` Gouraud the colour/w, from the
    /// perspective weight planes ([`weight_planes`]). Out of line, on AVX2 + FMA where the
    /// render runs on it (compiled once for the baseline it took about 56 instructions more
    /// per set-up, a quarter; the same operations in the same order, so the same bits).
    #[inline(always)]
    pub(super) fn new<const MODE: u8, const AFFINE: bool>(
        ctx: &ShadeContext<'_>,
        t: &SetupTri,
    ) -> Self {
        #[cfg(target_arch = "x86_64")]
        if ctx.wide() {
            // SAFETY: `wide` only when `Isa::detect` found AVX2 and FMA.
            return unsafe { Self::new_avx2::<MODE, AFFINE>(ctx, t) };
        }
        Self::new_baseline::<MODE, AFFINE>(ctx, t)
    }

    #[inline(never)]
    fn new_baseline<const MODE: u8, const AFFINE: bool>(
        ctx: &ShadeContext<'_>,
        t: &SetupTri,
    ) -> Self {
        Self::of::<MODE, AFFINE>(ctx, t)
    }

    /// # Safety
    /// The CPU must support AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    #[inline(never)]
    unsafe fn new_avx2<const MODE: u8, const AFFINE: bool>(
        ctx: &ShadeContext<'_>,
        t: &SetupTri,
    ) -> Self {
        Self::of::<MODE, AFFINE>(ctx, t)
    }

    /// [`Self::new`]'s body: each plane is `Σ_k w_k·a_k` over the vertices, with `a_k`
    /// (1, r, g, b) (1 alone for flat), four planes side by side as lanes.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane q of several arrays
    fn of<const MODE: u8, const AFFINE: bool>(ctx: &ShadeContext<'_>, t: &SetupTri) -> Self {
        let w = weight_planes_inline::<AFFINE>(ctx, t);
        let mut out = RunPlanes::default();
        if MODE == GOURAUD {
            let colors = if ctx.two_sided && !t.front {
                &ctx.verts.color_back
            } else {
                &ctx.verts.color
            };
            let a = t.v.map(|k| {
                let c = colors[k as usize].as_dvec3();
                [1.0, c.x, c.y, c.z]
            });
            // Lane 0: w0·1 + w1·1 + w2·1, exactly the sum of the weights.
            for q in 0..4 {
                out.dx[q] = w[0][0] * a[0][q] + w[1][0] * a[1][q] + w[2][0] * a[2][q];
                out.dy[q] = w[0][1] * a[0][q] + w[1][1] * a[1][q] + w[2][1] * a[2][q];
                out.c[q] = w[0][2] * a[0][q] + w[1][2] * a[1][q] + w[2][2] * a[2][q];
            }
        } else {
            out.dx[0] = w[0][0] + w[1][0] + w[2][0];
            out.dy[0] = w[0][1] + w[1][1] + w[2][1];
            out.c[0] = w[0][2] + w[1][2] + w[2][2];
        }
        out
    }
}

/// The 1/w plane of [`RunPlanes`] evaluated at a run's first pixel, with its step along the
/// run (f64: the depth output and fog read it).
#[derive(Clone, Copy)]
pub(super) struct RunStart {
    inv_w: (f64, f64),
}

impl RunStart {
    #[inline(always)]
    pub(super) fn new(pl: &RunPlanes, x: f64, y: f64) -> Self {
        RunStart {
            inv_w: (pl.dx[0] * x + pl.dy[0] * y + pl.c[0], pl.dx[0]),
        }
    }

    /// Interpolated 1/w at the run's pixel `k`.
    #[inline(always)]
    pub(super) fn inv_w(&self, k: f64) -> f64 {
        self.inv_w.0 + self.inv_w.1 * k
    }
}

/// Gouraud's colour planes and 1/w along a tile row, in f32: eight pixels a SIMD operation
/// instead of four. They start at the row's first pixel, not a run's, so a pixel's colour
/// does not depend on where its run starts (the layers of a multi-sample tile split rows
/// into other runs, and must give the single-sample colour). Each pixel's values are
/// `start + step·k` (not accumulated, k < 64): the rounding of the start values (larger
/// where a row's start lies far outside a small triangle with steep planes) and a few
/// roundings per pixel are the error. Against the f64 planes this replaced, on spheres of
/// 288 to 998,000 triangles at 910 × 512 and 1920 × 1080: at most 8.4·10⁻⁶ in f32 output
/// (2·10⁻³ of an 8-bit level), and at most 13 of 6.2 M u8 samples one level apart.
#[derive(Clone, Copy)]
pub(super) struct RunColors {
    /// 1/w, red, green, blue at the row's first pixel.
    start: [f32; 4],
    /// Their steps per pixel in x.
    step: [f32; 4],
}

impl RunColors {
    /// Gouraud's planes `pl` from the row's first pixel centre (x, y): the four planes at
    /// once, `dx·x + dy·y + c` in f64 rounded to f32. Once per run: in SSE2 a few vector
    /// operations (the lane form below compiled to scalar ones, about 40 instructions).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn new(pl: &RunPlanes, x: f64, y: f64) -> Self {
        use std::arch::x86_64::*;
        // SAFETY: SSE2 is part of x86-64; each load reads two of a `[f64; 4]`'s values at
        // offset 0 or 2. Products and sums are rounded as the lane form's (no fusing), and
        // `cvtpd2ps` rounds to nearest as `as f32` does (the default MXCSR, which nothing
        // in the crate changes).
        unsafe {
            let (xs, ys) = (_mm_set1_pd(x), _mm_set1_pd(y));
            let half = |k: usize| {
                let dx = _mm_loadu_pd(pl.dx.as_ptr().add(k));
                let dy = _mm_loadu_pd(pl.dy.as_ptr().add(k));
                let c = _mm_loadu_pd(pl.c.as_ptr().add(k));
                let v = _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, xs), _mm_mul_pd(dy, ys)), c);
                (_mm_cvtpd_ps(v), _mm_cvtpd_ps(dx))
            };
            let ((v0, d0), (v1, d1)) = (half(0), half(2));
            let mut out = RunColors {
                start: [0.0; 4],
                step: [0.0; 4],
            };
            _mm_storeu_ps(out.start.as_mut_ptr(), _mm_movelh_ps(v0, v1));
            _mm_storeu_ps(out.step.as_mut_ptr(), _mm_movelh_ps(d0, d1));
            out
        }
    }

    /// [`RunColors::new`] as lane loops: the definition (other architectures, and the
    /// tests of the SSE2 form).
    #[cfg(any(test, not(target_arch = "x86_64")))]
    #[inline(always)]
    pub(super) fn new_scalar(pl: &RunPlanes, x: f64, y: f64) -> Self {
        RunColors {
            start: std::array::from_fn(|q| (pl.dx[q] * x + pl.dy[q] * y + pl.c[q]) as f32),
            step: std::array::from_fn(|q| pl.dx[q] as f32),
        }
    }

    /// [`RunColors::new`] on other architectures: the lane loops.
    #[cfg(not(target_arch = "x86_64"))]
    #[inline(always)]
    pub(super) fn new(pl: &RunPlanes, x: f64, y: f64) -> Self {
        Self::new_scalar(pl, x, y)
    }

    /// Gouraud colour at the row's pixel `k`: the colour planes over the 1/w plane. Every
    /// path computes it with this function (lanes and single pixels alike; Rust fuses no
    /// multiply-add unasked), so a pixel's colour does not depend on the path.
    /// Lit colours are never negative, but a pixel centre that the snapped triangle covers
    /// can lie a hair outside the triangle its planes interpolate, where the blend of
    /// non-negative vertex colours extrapolates below 0 (seen: −0.0005); it is clamped at 0.
    #[inline(always)]
    pub(super) fn at(&self, k: f32) -> [f32; 3] {
        let [iw0, r0, g0, b0] = self.start;
        let [diw, dr, dg, db] = self.step;
        let r = 1.0 / (iw0 + diw * k);
        [
            ((r0 + dr * k) * r).max(0.0),
            ((g0 + dg * k) * r).max(0.0),
            ((b0 + db * k) * r).max(0.0),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Awkward plane values: zeros of both signs, tiny and huge magnitudes (f32 overflow
    /// and underflow after the sum), infinities, NaN and values at f32 rounding ties.
    fn awkward() -> Vec<f64> {
        let tie = 1.0 + f64::from(f32::EPSILON) / 2.0;
        vec![
            0.0,
            -0.0,
            1.0,
            -2.5,
            1e-3,
            3.4e38,
            -1e39,
            1e-46,
            f64::from(f32::MIN_POSITIVE) / 3.0,
            tie,
            -tie,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ]
    }

    #[test]
    fn run_colors_new_gives_the_lane_loops_bits() {
        let vals = awkward();
        let n = vals.len();
        let bits = |c: &RunColors| (c.start.map(f32::to_bits), c.step.map(f32::to_bits));
        for k in 0..n * n {
            let v = |o: usize| vals[(k * (o + 1) + o * 5) % n];
            let pl = RunPlanes {
                dx: [v(0), v(1), v(2), v(3)],
                dy: [v(4), v(5), v(6), v(7)],
                c: [v(8), v(9), v(10), v(11)],
            };
            for (x, y) in [(0.5, 0.5), (1920.5, 1079.5), (33.5, 7.5)] {
                let (got, want) = (RunColors::new(&pl, x, y), RunColors::new_scalar(&pl, x, y));
                assert_eq!(bits(&got), bits(&want), "{:?} at ({x}, {y})", pl.dx);
            }
        }
    }
}
