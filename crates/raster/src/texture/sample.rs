//! Filtering, exactly as OpenGL 4.6 §8.14–8.15 defines it: `Nearest` and `Bilinear` read
//! level 0 at every scale (`GL_NEAREST` / `GL_LINEAR` as both minification and magnification
//! filter); `Trilinear` is `GL_LINEAR_MIPMAP_LINEAR` when minified (λ > 0) and `GL_LINEAR`
//! when magnified, with λ = log2 max(‖(W·∂u/∂x, H·∂v/∂x)‖₂, ‖(W·∂u/∂y, H·∂v/∂y)‖₂) from the
//! exact derivatives of the caller's [`Footprint`] (W × H the level-0 size).

use glam::Vec3;

use super::image::{Image, Level};
use super::wrap::Wrap;

/// How an image texture is filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filter {
    /// The texel that contains the point, on level 0.
    Nearest,
    /// The weighted four texels around the point, on level 0.
    Bilinear,
    /// Bilinear on the two mip levels around the level of detail, blended; bilinear on
    /// level 0 when magnified.
    Trilinear,
}

impl Filter {
    /// The filter named `name` ("nearest", "bilinear", "trilinear").
    pub fn from_name(name: &str) -> Option<Filter> {
        match name {
            "nearest" => Some(Filter::Nearest),
            "bilinear" => Some(Filter::Bilinear),
            "trilinear" => Some(Filter::Trilinear),
            _ => None,
        }
    }

    /// The filter's name.
    pub fn name(self) -> &'static str {
        match self {
            Filter::Nearest => "nearest",
            Filter::Bilinear => "bilinear",
            Filter::Trilinear => "trilinear",
        }
    }
}

/// The screen-space derivatives of the texture coordinates at the sampled point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Footprint {
    /// ∂u/∂x (per pixel).
    pub du_dx: f64,
    /// ∂v/∂x.
    pub dv_dx: f64,
    /// ∂u/∂y.
    pub du_dy: f64,
    /// ∂v/∂y.
    pub dv_dy: f64,
}

impl Footprint {
    /// The level of detail λ on an image of level-0 size `w × h`: −∞ for a zero footprint,
    /// +∞ for an infinite one, and +∞ for NaN (the coarsest level: a footprint that cannot be
    /// measured is read as large rather than as sharp).
    ///
    /// λ = log2 max(‖(w·∂u/∂x, h·∂v/∂x)‖, ‖(w·∂u/∂y, h·∂v/∂y)‖), computed as ½·log2 of
    /// the larger squared length with [`log2_normal`] (within 5.2·10⁻¹⁰ of the exact λ where
    /// that square is between 10⁻³⁰⁰ and 10³⁰⁰), else (a zero, huge or NaN footprint)
    /// through `hypot` and libm's log2. [`lod_lanes`] gives the same values for many.
    pub fn lod(&self, w: usize, h: usize) -> f64 {
        let (sx, sy) = self.squares(w, h);
        let (lambda, ok) = lod_of_squares(sx, sy);
        if ok {
            lambda
        } else {
            self.lod_wide(w, h)
        }
    }

    /// The squared lengths of the footprint's two axes in texels of a `w × h` image.
    #[inline(always)]
    fn squares(&self, w: usize, h: usize) -> (f64, f64) {
        let (w, h) = (w as f64, h as f64);
        let sq = |a: f64, b: f64| a * a + b * b;
        (
            sq(self.du_dx * w, self.dv_dx * h),
            sq(self.du_dy * w, self.dv_dy * h),
        )
    }

    /// [`Footprint::lod`] where the squares leave the normal range: the norms through
    /// `hypot` where needed, libm's log2, NaN read as +∞.
    #[cold]
    fn lod_wide(&self, w: usize, h: usize) -> f64 {
        let (w, h) = (w as f64, h as f64);
        let rx = norm(self.du_dx * w, self.dv_dx * h);
        let ry = norm(self.du_dy * w, self.dv_dy * h);
        // `max` would drop a NaN: test both.
        if rx.is_nan() || ry.is_nan() {
            f64::INFINITY
        } else {
            rx.max(ry).log2()
        }
    }

    /// Whether `filter` with `aniso` probes reads the footprint at all: only the mipmapped
    /// filter (its λ) and anisotropic probing do, so the caller may pass a default one to
    /// the others.
    pub fn read_by(filter: Filter, aniso: u32) -> bool {
        filter == Filter::Trilinear || aniso > 1
    }
}

/// [`Footprint::lod`] of each of the first `n` footprints `fp` (already in texture
/// coordinates) on a `w × h` image; lanes from `n` on are garbage. The common case is a
/// fixed-length loop with no branch or libm call (it widens), the rest per lane.
#[inline(always)]
pub(super) fn lod_lanes<const N: usize>(
    fp: &[Footprint; N],
    n: usize,
    w: usize,
    h: usize,
) -> [f64; N] {
    let mut lambda = [0.0; N];
    let mut good = [false; N];
    for k in 0..N {
        let (sx, sy) = fp[k].squares(w, h);
        (lambda[k], good[k]) = lod_of_squares(sx, sy);
    }
    let all = (0..N).fold(true, |all, k| all & (good[k] | (k >= n)));
    if !all {
        for k in 0..n.min(N) {
            if !good[k] {
                lambda[k] = fp[k].lod_wide(w, h);
            }
        }
    }
    lambda
}

/// ½·log2 max(`sx`, `sy`) and whether it is valid: both not NaN and the larger between
/// 10⁻³⁰⁰ and 10³⁰⁰ (a normal number, as [`log2_normal`] needs). Branch-free.
#[inline(always)]
fn lod_of_squares(sx: f64, sy: f64) -> (f64, bool) {
    let s = sx.max(sy);
    let ok = !sx.is_nan() & !sy.is_nan() & (s > 1e-300) & (s < 1e300);
    let s = if ok { s } else { 1.0 };
    (0.5 * log2_normal(s), ok)
}

/// [`log2_normal`]'s series: 2/(ln 2·(2k + 1)), k = 0 … 4.
pub(super) const LOG2_SERIES: [f64; 5] = [
    2.885_390_081_777_926_8,
    0.961_796_693_925_975_7,
    0.577_078_016_355_585_3,
    0.412_198_583_111_132_44,
    0.320_598_897_975_325_2,
];

/// log2 x for a positive normal `x`, branch-free so lane loops of it widen (libm's log2
/// was a sixth of a trilinear frame's instructions, one call per pixel). x = 2^e · m with
/// m in [√½, √2); log2 m = (2/ln 2)·atanh(t), t = (m − 1)/(m + 1), |t| ≤ 3 − 2√2 (0.1716),
/// by its series through t⁹. The rest is at most (2/ln 2)·t¹¹/(11·(1 − t²)) = 1.03·10⁻⁹,
/// so λ (half of this) is within 5.2·10⁻¹⁰ of exact: below the f32 rounding of the blend
/// fraction made from it wherever that fraction is at least 1/64. The series through t²³,
/// within 2 ulp, was a tenth of a trilinear frame's time in its eleven dependent steps
/// (`log2_normal_is_within_its_bound`). Exact at powers of two (t = 0).
#[inline(always)]
fn log2_normal(x: f64) -> f64 {
    const C: [f64; 5] = LOG2_SERIES;
    const MANTISSA: u64 = (1 << 52) - 1;
    let bits = x.to_bits();
    let m = f64::from_bits((bits & MANTISSA) | (1023 << 52)); // [1, 2), exact
    let big = m > std::f64::consts::SQRT_2;
    let m = if big { m * 0.5 } else { m };
    // The biased exponent as an f64 without an i64 conversion (none in AVX2): placed in
    // the mantissa of 2⁵², which is then subtracted (exact).
    let biased = f64::from_bits((bits >> 52) | 0x4330_0000_0000_0000) - 4_503_599_627_370_496.0;
    let e = biased - 1023.0 + if big { 1.0 } else { 0.0 };
    let t = (m - 1.0) / (m + 1.0);
    let t2 = t * t;
    let mut p = C[4];
    for c in C[..4].iter().rev() {
        p = p * t2 + c;
    }
    e + t * p
}

/// ‖(a, b)‖₂: √(a² + b²), which is within an ulp of `hypot` and several times cheaper
/// (libm's `hypot` was a fifth of a textured frame), with `hypot` where the squares would
/// overflow or underflow.
#[inline]
fn norm(a: f64, b: f64) -> f64 {
    let s = a * a + b * b;
    if s < 1e300 && s > 1e-300 {
        s.sqrt()
    } else {
        a.hypot(b)
    }
}

/// ⌊x⌋, exactly as `f64::floor` (except that −0 gives +0), without the libm call that the
/// baseline x86-64 target makes for it (no `roundsd` before SSE4.1): |x| < 2⁵² truncates
/// through an integer and steps down for negative fractions; larger magnitudes are already
/// integers; NaN stays NaN.
#[inline(always)]
pub(super) fn floor(x: f64) -> f64 {
    if x.abs() < 4_503_599_627_370_496.0 {
        // SAFETY: |x| < 2⁵² (so not NaN) fits an i64.
        let t = unsafe { x.to_int_unchecked::<i64>() } as f64;
        t - (t > x) as u8 as f64
    } else {
        x
    }
}

/// Largest `anisotropy` (probes along the footprint's major axis).
pub const MAX_ANISOTROPY: u32 = 16;

/// The filtered colour of `image` at (u, v) (finite), with up to `aniso` probes.
///
/// Anisotropic filtering as EXT_texture_filter_anisotropic suggests it, written out
/// exactly: with P_x = ‖(W·∂u/∂x, H·∂v/∂x)‖, P_y likewise, P_max and P_min their larger
/// and smaller, N = min(⌈P_max / P_min⌉, `aniso`) probes (`aniso` when P_min is 0) are taken
/// at (u, v) + ((i + ½)/N − ½)·(∂u, ∂v) along the major axis (i = 0 … N − 1), each filtered
/// with λ = log2(P_max / N), and averaged. With `aniso` = 1 this is the isotropic filter.
pub(super) fn sample(
    image: &Image,
    filter: Filter,
    wrap: [Wrap; 2],
    aniso: u32,
    u: f64,
    v: f64,
    fp: &Footprint,
) -> Vec3 {
    if aniso <= 1 {
        // λ is read by the mipmapped filter only (a log2 and two norms per sample).
        let lambda = match filter {
            Filter::Trilinear => fp.lod(image.width(), image.height()),
            Filter::Nearest | Filter::Bilinear => 0.0,
        };
        return sample_at(image, filter, wrap, u, v, lambda);
    }
    let (w, h) = (image.width() as f64, image.height() as f64);
    let (n, lambda, du, dv) = probes(w, h, aniso, fp);
    if n == 1 {
        return sample_at(image, filter, wrap, u, v, lambda);
    }
    let mut sum = Vec3::ZERO;
    for i in 0..n {
        let t = (i as f64 + 0.5) / n as f64 - 0.5;
        sum += sample_at(image, filter, wrap, u + t * du, v + t * dv, lambda);
    }
    sum / n as f32
}

/// The probes of [`sample`]'s anisotropic look-up (`aniso` > 1) on a `w × h` image with
/// the footprint `fp`: their count N, their level of detail λ and the major axis (∂u, ∂v)
/// they are spread along. A NaN footprint gives one probe at the coarsest level (λ = +∞).
#[inline(always)]
fn probes(w: f64, h: f64, aniso: u32, fp: &Footprint) -> (u32, f64, f64, f64) {
    let px = norm(fp.du_dx * w, fp.dv_dx * h);
    let py = norm(fp.du_dy * w, fp.dv_dy * h);
    if px.is_nan() || py.is_nan() {
        return (1, f64::INFINITY, 0.0, 0.0);
    }
    let (pmax, pmin, du, dv) = if px >= py {
        (px, py, fp.du_dx, fp.dv_dx)
    } else {
        (py, px, fp.du_dy, fp.dv_dy)
    };
    let ratio = (pmax / pmin).ceil();
    let n = if ratio.is_finite() {
        ratio.clamp(1.0, aniso as f64) as u32
    } else {
        aniso
    };
    (n, (pmax / n as f64).log2(), du, dv)
}

/// [`sample`] with `aniso` > 1 at the first `n` of the points (`u`, `v`) (finite) with
/// footprints `fp`, into lane k of `out`, the same values: each lane's probes as `sample`
/// places them, probe i of every lane read at once by the isotropic lane filters
/// ([`nearest_lanes`], [`bilinear_lanes`], [`trilinear_lanes`]) and summed per lane in
/// `sample`'s order, as many rounds as the most probes any lane takes (a lane with fewer
/// reads its point again and drops it). Lanes from `n` on may be overwritten.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // `sample`'s inputs, per lane
pub(super) fn anisotropic_lanes<const N: usize>(
    image: &Image,
    filter: Filter,
    wrap: [Wrap; 2],
    aniso: u32,
    u: &[f64; N],
    v: &[f64; N],
    fp: &[Footprint; N],
    n: usize,
    out: &mut [[f32; N]; 3],
    wide: bool,
) {
    let n = n.min(N);
    let (w, h) = (image.width() as f64, image.height() as f64);
    // Lanes from `n` on: one probe at their point (they are dropped).
    let mut count = [1u32; N];
    let mut lambda = [0.0f64; N];
    let (mut du, mut dv) = ([0.0f64; N], [0.0f64; N]);
    for k in 0..n {
        (count[k], lambda[k], du[k], dv[k]) = probes(w, h, aniso, &fp[k]);
    }
    let rounds = count[..n].iter().copied().max().unwrap_or(0);
    let levels = image.levels();
    let mut sum = [[0.0f32; N]; 3];
    let mut probe = [[0.0f32; N]; 3];
    for i in 0..rounds {
        // A lane of one probe reads its own point, as `sample` does (not u + 0·∂u).
        let (mut pu, mut pv) = (*u, *v);
        for k in 0..N {
            let t = (i as f64 + 0.5) / count[k] as f64 - 0.5;
            let spread = count[k] > 1;
            pu[k] = if spread { u[k] + t * du[k] } else { u[k] };
            pv[k] = if spread { v[k] + t * dv[k] } else { v[k] };
        }
        let at = if i == 0 { &mut *out } else { &mut probe };
        match filter {
            Filter::Nearest => nearest_lanes(&levels[0], wrap, &pu, &pv, n, at, wide),
            Filter::Bilinear => bilinear_lanes(&levels[0], wrap, &pu, &pv, n, at, wide),
            Filter::Trilinear => trilinear_lanes(levels, wrap, &pu, &pv, &lambda, n, at, wide),
        }
        let at = if i == 0 { &*out } else { &probe };
        for (s, p) in sum.iter_mut().zip(at) {
            for k in 0..N {
                // `sample`'s sum starts at zero and takes probes 0 … N − 1 in order.
                let add = if i == 0 { 0.0 + p[k] } else { s[k] + p[k] };
                s[k] = if i < count[k] { add } else { s[k] };
            }
        }
    }
    if rounds > 1 {
        for (o, s) in out.iter_mut().zip(&sum) {
            for k in 0..N {
                // One probe: the probe itself (already in `out`), as `sample` returns it.
                o[k] = if count[k] > 1 {
                    s[k] / count[k] as f32
                } else {
                    o[k]
                };
            }
        }
    }
}

/// One probe at (u, v) with level of detail `lambda` (read by `Trilinear` only).
fn sample_at(image: &Image, filter: Filter, wrap: [Wrap; 2], u: f64, v: f64, lambda: f64) -> Vec3 {
    let levels = image.levels();
    match filter {
        Filter::Nearest => nearest(&levels[0], wrap, u, v),
        Filter::Bilinear => bilinear(&levels[0], wrap, u, v),
        Filter::Trilinear => trilinear(levels, wrap, u, v, lambda),
    }
}

/// `GL_LINEAR_MIPMAP_LINEAR` at level of detail `lambda` (`GL_LINEAR` on level 0 when
/// magnified or NaN, on the last level beyond it).
#[inline(always)]
pub(super) fn trilinear(levels: &[Level], wrap: [Wrap; 2], u: f64, v: f64, lambda: f64) -> Vec3 {
    if lambda.is_nan() || lambda <= 0.0 {
        return bilinear(&levels[0], wrap, u, v);
    }
    let q = (levels.len() - 1) as f64;
    if lambda >= q {
        return bilinear(&levels[levels.len() - 1], wrap, u, v);
    }
    let d1 = floor(lambda);
    let f = (lambda - d1) as f32;
    let a = bilinear(&levels[d1 as usize], wrap, u, v);
    let b = bilinear(&levels[d1 as usize + 1], wrap, u, v);
    a * (1.0 - f) + b * f
}

/// One axis of a level as the filters index it: the wrap mode and size, and for `Repeat`
/// on a power-of-two size (most textures) the mask that wraps an integer coordinate, so
/// the common case is a truncation and an AND (made per call; inlined into a loop over
/// points, it is made once for the loop).
#[derive(Clone, Copy)]
struct Axis {
    wrap: Wrap,
    size: usize,
    mask: Option<i64>,
}

/// 2⁵²: below it an f64 truncates exactly through an i64 and `t + 1` stays exact.
const EXACT_INT: f64 = 4_503_599_627_370_496.0;

impl Axis {
    #[inline(always)]
    fn new(wrap: Wrap, size: usize) -> Self {
        let mask = (wrap == Wrap::Repeat && size.is_power_of_two()).then_some(size as i64 - 1);
        Axis { wrap, size, mask }
    }

    /// ⌊x⌋ through an i64 where |x| < 2⁵² (as [`floor`] computes it), or `None`.
    #[inline(always)]
    fn floor_int(x: f64) -> Option<i64> {
        if x.abs() < EXACT_INT {
            // SAFETY: |x| < 2⁵² (so not NaN) fits an i64.
            let t = unsafe { x.to_int_unchecked::<i64>() };
            Some(t - ((t as f64) > x) as i64)
        } else {
            None
        }
    }

    /// The texel that ⌊x⌋ reads: [`Wrap::index`] of [`floor`]`(x)`, the same index.
    #[inline(always)]
    fn nearest(&self, x: f64) -> usize {
        if let (Some(m), Some(t)) = (self.mask, Self::floor_int(x)) {
            // The Euclidean remainder by a power of two, in two's complement.
            return (t & m) as usize;
        }
        self.wrap.index(floor(x), self.size)
    }

    /// The texels ⌊x⌋ and ⌊x⌋ + 1 read and the fraction x − ⌊x⌋: [`Wrap::pair`] of
    /// [`floor`]`(x)`, the same values.
    #[inline(always)]
    fn pair(&self, x: f64) -> (usize, usize, f32) {
        if let (Some(m), Some(t)) = (self.mask, Self::floor_int(x)) {
            return (
                (t & m) as usize,
                ((t + 1) & m) as usize,
                (x - t as f64) as f32,
            );
        }
        let x0 = floor(x);
        let (i0, i1) = self.wrap.pair(x0, self.size);
        (i0, i1, (x - x0) as f32)
    }
}

/// Below 2³¹ an f64 truncates exactly through an i32, which SIMD converts eight lanes at
/// a time (an i64 conversion has no AVX2 instruction).
const LANE_INT: f64 = 2_147_483_648.0;

/// The lanes' texel indices ⌊x⌋ (`BILINEAR`: ⌊x⌋ and ⌊x⌋ + 1, and the fraction) along
/// `axis` for the first `n` of `x`: under `Repeat` on a power-of-two size, a truncation
/// and an AND over all lanes at once (lanes beyond 2³¹ then per lane), otherwise per lane;
/// the same values as [`Axis::nearest`] and [`Axis::pair`].
#[inline(always)]
fn lane_indices<const N: usize, const BILINEAR: bool>(
    axis: Axis,
    x: &[f64; N],
    n: usize,
) -> ([u32; N], [u32; N], [f32; N]) {
    // u32 lanes: indices are below MAX_TEXTURE_SIZE, and half as wide as usize ones.
    let mut i0 = [0u32; N];
    let mut i1 = [0u32; N];
    let mut frac = [0.0f32; N];
    let mut rest = 0..n;
    if let Some(m) = axis.mask {
        let m = m as i32; // sizes are at most MAX_TEXTURE_SIZE
        let mut fits = true;
        for k in 0..N {
            let ok = x[k].abs() < LANE_INT;
            fits &= ok | (k >= n);
            let xk = if ok { x[k] } else { 0.0 };
            // SAFETY: |xk| < 2³¹ (NaN fails the test and reads 0).
            let t = unsafe { xk.to_int_unchecked::<i32>() };
            let t = t - ((t as f64) > xk) as i32;
            i0[k] = (t & m) as u32;
            if BILINEAR {
                i1[k] = (t.wrapping_add(1) & m) as u32;
                frac[k] = (xk - t as f64) as f32;
            }
        }
        if fits {
            rest = 0..0;
        }
    }
    for k in rest {
        if BILINEAR {
            let (a, b, f) = axis.pair(x[k]);
            (i0[k], i1[k], frac[k]) = (a as u32, b as u32, f);
        } else {
            i0[k] = axis.nearest(x[k]) as u32;
        }
    }
    (i0, i1, frac)
}

/// [`nearest`] at the first `n` of the points (`u`, `v`) (finite), into lane k of `out`.
#[inline(always)]
pub(super) fn nearest_lanes<const N: usize>(
    l: &Level,
    wrap: [Wrap; 2],
    u: &[f64; N],
    v: &[f64; N],
    n: usize,
    out: &mut [[f32; N]; 3],
    wide: bool,
) {
    let scaled = |c: &[f64; N], s: usize| c.map(|c| c * s as f64);
    let (i, _, _) = lane_indices::<N, false>(Axis::new(wrap[0], l.width), &scaled(u, l.width), n);
    let (j, _, _) = lane_indices::<N, false>(Axis::new(wrap[1], l.height), &scaled(v, l.height), n);
    fetch(l, &i, &j, n, out, wide);
}

/// The texels (`i[k]`, `j[k]`) of `l` into lane k of the channel-major `out`, for the
/// first `n` lanes (lanes from `n` on may be overwritten). Eight lanes with `wide` (the
/// render's ISA is AVX2): one 16-byte load a texel and a transpose into the three channel
/// vectors, in registers. Written a lane at a time, the lanes' loads by the blend after it
/// waited on the stores (perf put that stall at about a tenth of a nearest-filtered frame);
/// AVX2's gathers instead were no faster (perf then put the wait on the gathers). Same
/// values either way.
#[inline(always)]
fn fetch<const N: usize>(
    l: &Level,
    i: &[u32; N],
    j: &[u32; N],
    n: usize,
    out: &mut [[f32; N]; 3],
    wide: bool,
) {
    #[cfg(target_arch = "x86_64")]
    if wide && N == 8 {
        // Every lane's index, live or not, is a texel of the level (`lane_indices` gives
        // dead lanes one too); the `min` keeps the loads in bounds whatever they hold.
        // Texel indices are below MAX_TEXELS < 2³²: u32 lanes.
        let (w, last) = (l.width as u32, l.texel_count() as u32 - 1);
        let mut at = [0u32; 8];
        for (k, a) in at.iter_mut().enumerate() {
            *a = (j[k] * w + i[k]).min(last) * 3;
        }
        // SAFETY: `wide` only where the render's ISA is AVX2, detected on this CPU; every
        // offset is at most the last texel's, whose four floats (with the padding texel's
        // first, `Level::new`) are in `channels()`; N is 8.
        unsafe { fetch8_avx(l.channels(), &at, out) };
        return;
    }
    let _ = wide;
    for k in 0..n.min(N) {
        let t = l.texel(i[k] as usize, j[k] as usize);
        (out[0][k], out[1][k], out[2][k]) = (t[0], t[1], t[2]);
    }
}

/// `out[ch][k] = channels[at[k] + ch]` for the eight lanes and three channels
/// ([`texels8_avx`], stored).
///
/// # Safety
/// The CPU must support AVX, `at[k] + 3` must be within `channels` for every k, and N must
/// be 8.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn fetch8_avx<const N: usize>(channels: &[f32], at: &[u32; 8], out: &mut [[f32; N]; 3]) {
    use std::arch::x86_64::*;
    debug_assert_eq!(N, 8);
    // SAFETY: AVX and `at` within `channels` (the caller's promises); each `out` row is
    // eight floats (N = 8).
    unsafe {
        let c = texels8_avx(channels, at);
        for (row, c) in out.iter_mut().zip(c) {
            _mm256_storeu_ps(row.as_mut_ptr(), c);
        }
    }
}

/// `channels[at[k] + ch]` for the eight lanes and three channels: each texel read as four
/// floats (r, g, b and the next one), two texels to a 256-bit register (lanes k and
/// k + 4), then transposed.
///
/// # Safety
/// The CPU must support AVX, and `at[k] + 3` must be within `channels` for every k.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
pub(super) unsafe fn texels8_avx(
    channels: &[f32],
    at: &[u32; 8],
) -> [std::arch::x86_64::__m256; 3] {
    use std::arch::x86_64::*;
    debug_assert!(at.iter().all(|&a| a as usize + 3 < channels.len()));
    // SAFETY: AVX (the caller's promise); every load is four floats from `at[k]`, within
    // `channels`.
    unsafe {
        let p = channels.as_ptr();
        let pair = |a: usize, b: usize| {
            let lo = _mm_loadu_ps(p.add(at[a] as usize));
            let hi = _mm_loadu_ps(p.add(at[b] as usize));
            _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(lo), hi)
        };
        // Rows (r, g, b, ·) of texels k | k + 4.
        let (t0, t1, t2, t3) = (pair(0, 4), pair(1, 5), pair(2, 6), pair(3, 7));
        let rg01 = _mm256_unpacklo_ps(t0, t1); // r0 r1 g0 g1 | r4 r5 g4 g5
        let b01 = _mm256_unpackhi_ps(t0, t1); // b0 b1 · · | b4 b5 · ·
        let rg23 = _mm256_unpacklo_ps(t2, t3);
        let b23 = _mm256_unpackhi_ps(t2, t3);
        [
            _mm256_shuffle_ps::<0b01_00_01_00>(rg01, rg23),
            _mm256_shuffle_ps::<0b11_10_11_10>(rg01, rg23),
            _mm256_shuffle_ps::<0b01_00_01_00>(b01, b23),
        ]
    }
}

/// [`bilinear`] at the first `n` of the points (`u`, `v`) (finite), into lane k of `out`:
/// the weights and the blend channel by channel over all lanes, in [`bilinear`]'s order
/// of operations.
#[inline(always)]
pub(super) fn bilinear_lanes<const N: usize>(
    l: &Level,
    wrap: [Wrap; 2],
    u: &[f64; N],
    v: &[f64; N],
    n: usize,
    out: &mut [[f32; N]; 3],
    wide: bool,
) {
    let centred = |c: &[f64; N], s: usize| c.map(|c| c * s as f64 - 0.5);
    let (i0, i1, a) = lane_indices::<N, true>(Axis::new(wrap[0], l.width), &centred(u, l.width), n);
    let (j0, j1, b) =
        lane_indices::<N, true>(Axis::new(wrap[1], l.height), &centred(v, l.height), n);
    let mut tex = [[[0.0f32; N]; 3]; 4];
    for (q, (i, j)) in [(&i0, &j0), (&i1, &j0), (&i0, &j1), (&i1, &j1)]
        .into_iter()
        .enumerate()
    {
        fetch(l, i, j, n, &mut tex[q], wide);
    }
    for ch in 0..3 {
        for k in 0..N {
            let (a, b) = (a[k], b[k]);
            out[ch][k] = tex[0][ch][k] * ((1.0 - a) * (1.0 - b))
                + tex[1][ch][k] * (a * (1.0 - b))
                + tex[2][ch][k] * ((1.0 - a) * b)
                + tex[3][ch][k] * (a * b);
        }
    }
}

/// [`trilinear`] at the first `n` of the points (`u`, `v`) (finite) with levels of detail
/// `lambda`, into lane k of `out`. Where every lane reads the same level or pair of levels
/// (the common case: a batch is neighbouring pixels), the whole batch is read by
/// [`bilinear_lanes`] once per level and blended per channel over all lanes; otherwise each
/// lane by [`trilinear`]. The same values either way.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // the sampler's inputs, as `trilinear` takes them, per lane
pub(super) fn trilinear_lanes<const N: usize>(
    levels: &[Level],
    wrap: [Wrap; 2],
    u: &[f64; N],
    v: &[f64; N],
    lambda: &[f64; N],
    n: usize,
    out: &mut [[f32; N]; 3],
    wide: bool,
) {
    let n = n.min(N);
    if n == 0 {
        return;
    }
    let last = levels.len() - 1;
    // As `trilinear`: level 0 when magnified or NaN, the last level beyond it, else the
    // pair ⌊λ⌋, ⌊λ⌋ + 1 (`usize::MAX` marks the single-level cases).
    let pick = |l: f64| -> (usize, usize) {
        if l.is_nan() || l <= 0.0 {
            (0, usize::MAX)
        } else if l >= last as f64 {
            (last, usize::MAX)
        } else {
            (floor(l) as usize, 0)
        }
    };
    let first = pick(lambda[0]);
    if (1..n).any(|k| pick(lambda[k]) != first) {
        for k in 0..n {
            let c = trilinear(levels, wrap, u[k], v[k], lambda[k]);
            (out[0][k], out[1][k], out[2][k]) = (c.x, c.y, c.z);
        }
        return;
    }
    let (d1, single) = first;
    if single == usize::MAX {
        bilinear_lanes(&levels[d1], wrap, u, v, n, out, wide);
        return;
    }
    let mut a = [[0.0f32; N]; 3];
    let mut b = [[0.0f32; N]; 3];
    bilinear_lanes(&levels[d1], wrap, u, v, n, &mut a, wide);
    bilinear_lanes(&levels[d1 + 1], wrap, u, v, n, &mut b, wide);
    let mut f = [0.0f32; N];
    for k in 0..n {
        f[k] = (lambda[k] - d1 as f64) as f32;
    }
    for ch in 0..3 {
        for k in 0..N {
            out[ch][k] = a[ch][k] * (1.0 - f[k]) + b[ch][k] * f[k];
        }
    }
}

/// `GL_NEAREST` on one level: the texel (⌊u·w⌋, ⌊v·h⌋), wrapped.
#[inline(always)]
pub(super) fn nearest(l: &Level, wrap: [Wrap; 2], u: f64, v: f64) -> Vec3 {
    let i = Axis::new(wrap[0], l.width).nearest(u * l.width as f64);
    let j = Axis::new(wrap[1], l.height).nearest(v * l.height as f64);
    Vec3::from_array(l.texel(i, j))
}

/// `GL_LINEAR` on one level: the four texels around (u·w − ½, v·h − ½), weighted by the
/// fractions α, β (eq. 8.19).
#[inline(always)]
pub(super) fn bilinear(l: &Level, wrap: [Wrap; 2], u: f64, v: f64) -> Vec3 {
    let x = u * l.width as f64 - 0.5;
    let y = v * l.height as f64 - 0.5;
    let (i0, i1, a) = Axis::new(wrap[0], l.width).pair(x);
    let (j0, j1, b) = Axis::new(wrap[1], l.height).pair(y);
    let t = |i, j| Vec3::from_array(l.texel(i, j));
    t(i0, j0) * ((1.0 - a) * (1.0 - b))
        + t(i1, j0) * (a * (1.0 - b))
        + t(i0, j1) * ((1.0 - a) * b)
        + t(i1, j1) * (a * b)
}

#[cfg(test)]
mod tests {
    use super::super::{Image, Texture};
    use super::*;
    use std::sync::Arc;

    /// A `w × h` image whose texel (column i, row j from the top) is (i, j, 0).
    fn ramp(w: usize, h: usize) -> Arc<Image> {
        let mut d = Vec::new();
        for j in 0..h {
            for i in 0..w {
                d.extend([i as f32, j as f32, 0.0]);
            }
        }
        Arc::new(Image::from_top_rows(w, h, 3, &d, false).unwrap())
    }

    fn tex(img: &Arc<Image>, f: Filter, w: Wrap) -> Texture {
        Texture::from_image(img.clone(), f, [w, w])
    }

    #[test]
    fn texel_centres_read_exactly_their_texel() {
        let img = ramp(5, 3);
        let none = Footprint::default();
        for f in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
            let t = tex(&img, f, Wrap::Repeat);
            for j in 0..3 {
                for i in 0..5 {
                    let (u, v) = ((i as f64 + 0.5) / 5.0, 1.0 - (j as f64 + 0.5) / 3.0);
                    let c = t.sample(u, v, &none);
                    assert_eq!(c, Vec3::new(i as f32, j as f32, 0.0), "{f:?} {i} {j}");
                }
            }
        }
    }

    /// Every texel of levels of several shapes read through the lane fetch (per lane, and
    /// the AVX loads where this CPU has AVX2), eight lanes at a time with a partial last
    /// chunk: each lane gets its texel's three channels, the last texel included (read with
    /// the padding after it), whatever the dead lanes hold.
    #[test]
    fn lane_fetch_reads_every_texel_up_to_the_last() {
        for (w, h) in [(5, 3), (4, 4), (1, 1), (7, 1), (1, 9), (16, 2)] {
            let mut d = Vec::new();
            for j in 0..h {
                for i in 0..w {
                    d.extend([i as f32, j as f32, (100 * i + j + 1) as f32]);
                }
            }
            let img = Image::from_top_rows(w, h, 3, &d, false).unwrap();
            let l = &img.levels()[0];
            let all: Vec<(u32, u32)> = (0..h as u32)
                .flat_map(|j| (0..w as u32).map(move |i| (i, j)))
                .collect();
            for wide in [false, avx2()] {
                for chunk in all.chunks(8) {
                    let n = chunk.len();
                    let (mut i, mut j) = ([0u32; 8], [0u32; 8]);
                    for (k, &(a, b)) in chunk.iter().enumerate() {
                        (i[k], j[k]) = (a, b);
                    }
                    // Dead lanes: the last texel, as far from the first as indices go.
                    for k in n..8 {
                        (i[k], j[k]) = (w as u32 - 1, h as u32 - 1);
                    }
                    let mut out = [[-7.0f32; 8]; 3];
                    fetch(l, &i, &j, n, &mut out, wide);
                    for k in 0..n {
                        let got = [out[0][k], out[1][k], out[2][k]];
                        let want = l.texel(i[k] as usize, j[k] as usize);
                        assert_eq!(got, want, "{w}x{h} {wide} lane {k}");
                    }
                }
            }
        }
    }

    #[test]
    fn bilinear_halfway_between_centres_is_the_mean() {
        let img = ramp(4, 4);
        let t = tex(&img, Filter::Bilinear, Wrap::Clamp);
        let c = t.sample(2.0 / 4.0, 1.0 - 1.5 / 4.0, &Footprint::default());
        assert_eq!(c, Vec3::new(1.5, 1.0, 0.0));
        // Repeat across the seam: between the last column (3) and the first (0).
        let t = tex(&img, Filter::Bilinear, Wrap::Repeat);
        let c = t.sample(1.0, 1.0 - 0.5 / 4.0, &Footprint::default());
        assert_eq!(c.x, 1.5);
        // Clamp at the seam: the edge texel.
        let t = tex(&img, Filter::Bilinear, Wrap::Clamp);
        assert_eq!(t.sample(1.0, 0.5, &Footprint::default()).x, 3.0);
    }

    #[test]
    fn lod_from_the_footprint() {
        let fp = Footprint {
            du_dx: 4.0 / 64.0,
            dv_dx: 0.0,
            du_dy: 0.0,
            dv_dy: 1.0 / 64.0,
        };
        assert_eq!(fp.lod(64, 64), 2.0);
        assert_eq!(Footprint::default().lod(8, 8), f64::NEG_INFINITY);
        let nan = Footprint {
            du_dx: f64::NAN,
            ..fp
        };
        assert_eq!(nan.lod(8, 8), f64::INFINITY);
    }

    #[test]
    fn log2_normal_is_within_its_bound() {
        // The series' remainder at the largest |t| = 3 − 2√2, plus a few ulp of the result.
        let t = 3.0 - 2.0 * std::f64::consts::SQRT_2;
        let rest = 2.0 / std::f64::consts::LN_2 * t.powi(11) / (11.0 * (1.0 - t * t));
        assert!(rest < 1.03e-9, "{rest}");
        let mut worst = 0.0f64;
        let mut x = 1.1e-300;
        while x < 1e300 {
            for f in [
                1.0,
                1.0 + 1e-12,
                1.2345,
                std::f64::consts::SQRT_2,
                std::f64::consts::SQRT_2 * (1.0 + 1e-15),
                1.5,
                1.999_999,
            ] {
                let y = x * f;
                let (got, want) = (log2_normal(y), y.log2());
                let ulp = f64::EPSILON * want.abs().max(1.0);
                worst = worst.max((got - want).abs() - 4.0 * ulp);
            }
            x *= 3.7;
        }
        // Reached at m = √2 (either side of the switch to m/2): the bound is tight.
        assert!(worst <= rest && worst > 0.9 * rest, "{worst} vs {rest}");
        for e in -990..=990 {
            assert_eq!(log2_normal(2f64.powi(e)), e as f64, "2^{e}");
        }
    }

    /// The lanes' λ is the one-point λ, bit for bit, for footprints in range and out of
    /// it (zero, subnormal, huge, infinite, NaN), and both are within 5.2·10⁻¹⁰ (and a few
    /// ulp) of libm's log2 of the larger norm where that is finite.
    #[test]
    fn lod_lanes_match_lod_and_libm() {
        let vals = [
            0.0,
            1e-310,
            1e-160,
            1e-20,
            3e-4,
            0.015625,
            0.3,
            1.0,
            7.5,
            1e20,
            1e160,
            1e300,
            f64::INFINITY,
            f64::NAN,
            -0.02,
            -3.0,
        ];
        let mut fps = Vec::new();
        for (i, &a) in vals.iter().enumerate() {
            for (j, &b) in vals.iter().enumerate() {
                fps.push(Footprint {
                    du_dx: a,
                    dv_dx: b * 0.5,
                    du_dy: vals[(i + j) % vals.len()],
                    dv_dy: vals[(i * 7 + j) % vals.len()] * 1.5,
                });
            }
        }
        for chunk in fps.chunks(8) {
            let mut lanes = [Footprint::default(); 8];
            lanes[..chunk.len()].copy_from_slice(chunk);
            let got = lod_lanes(&lanes, chunk.len(), 64, 32);
            for (k, fp) in chunk.iter().enumerate() {
                let one = fp.lod(64, 32);
                assert_eq!(got[k].to_bits(), one.to_bits(), "{fp:?}");
                let want = fp.lod_wide(64, 32);
                if want.is_finite() {
                    assert!(
                        (one - want).abs() <= 5.2e-10 + 4.0 * f64::EPSILON * want.abs().max(1.0),
                        "{fp:?}: {one} vs {want}"
                    );
                } else {
                    assert_eq!(one, want, "{fp:?}");
                }
            }
        }
    }

    #[test]
    fn trilinear_blends_the_two_levels_around_lambda() {
        let img = ramp(8, 8);
        let t = tex(&img, Filter::Trilinear, Wrap::Repeat);
        let at = |lambda: f64| {
            let s = lambda.exp2() / 8.0;
            let fp = Footprint {
                du_dx: s,
                dv_dy: s,
                ..Footprint::default()
            };
            t.sample(0.3, 0.6, &fp)
        };
        let l = img.levels();
        let w = [Wrap::Repeat; 2];
        let lvl = |k: usize| bilinear(&l[k], w, 0.3, 0.6);
        assert_eq!(at(-1.0), lvl(0));
        assert_eq!(at(1.0), lvl(1));
        let mid = at(1.25);
        let want = lvl(1) * 0.75 + lvl(2) * 0.25;
        assert!((mid - want).abs().max_element() < 1e-6, "{mid} {want}");
        assert_eq!(at(10.0), lvl(3)); // beyond the coarsest level
    }

    #[test]
    fn nan_and_huge_coordinates_are_finite_and_fast() {
        let img = ramp(7, 5);
        for f in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
            for w in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
                let t = tex(&img, f, w);
                for (u, v) in [
                    (f64::NAN, 0.5),
                    (1e30, -1e30),
                    (f64::INFINITY, 0.2),
                    (-3e300, 1e300),
                ] {
                    let fp = Footprint {
                        du_dx: u,
                        dv_dy: v,
                        ..Footprint::default()
                    };
                    assert!(t.sample(u, v, &fp).is_finite(), "{f:?} {w:?} {u} {v}");
                }
            }
        }
    }

    use proptest::prelude::*;

    /// `nearest_lanes` and `bilinear_lanes` against `nearest` and `bilinear` per point, bit
    /// for bit, on `n` of 8 lanes; `trilinear_lanes` against `trilinear` with levels of
    /// detail all alike (one level or one pair for the batch) and mixed.
    fn lanes_match_scalar(img: &Image, wrap: [Wrap; 2], pts: &[(f64, f64)]) {
        let l = &img.levels()[0];
        for chunk in pts.chunks(8) {
            let n = chunk.len();
            let (mut u, mut v) = ([0.0; 8], [0.0; 8]);
            for (k, &(a, b)) in chunk.iter().enumerate() {
                (u[k], v[k]) = (a, b);
            }
            // Both texel fetches: per lane, and the AVX loads where this CPU has AVX2.
            for wide in [false, avx2()] {
                let mut near = [[-7.0f32; 8]; 3];
                let mut bil = [[-7.0f32; 8]; 3];
                nearest_lanes(l, wrap, &u, &v, n, &mut near, wide);
                bilinear_lanes(l, wrap, &u, &v, n, &mut bil, wide);
                let levels = img.levels();
                let mixed = [-1.0, 0.3, 1.7, 2.2, f64::NAN, 9.0, 0.0, 1.2];
                for lambda in [[-0.5; 8], [0.25; 8], [1.5; 8], [1.01; 8], [30.0; 8], mixed] {
                    let mut tri = [[-7.0f32; 8]; 3];
                    trilinear_lanes(levels, wrap, &u, &v, &lambda, n, &mut tri, wide);
                    for k in 0..n {
                        let want = trilinear(levels, wrap, u[k], v[k], lambda[k]).to_array();
                        let got = [tri[0][k], tri[1][k], tri[2][k]];
                        assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "{lambda:?}");
                    }
                }
                for k in 0..8 {
                    let got = |o: &[[f32; 8]; 3]| [o[0][k], o[1][k], o[2][k]];
                    if k < n {
                        let want_n = nearest(l, wrap, u[k], v[k]).to_array();
                        let want_b = bilinear(l, wrap, u[k], v[k]).to_array();
                        assert_eq!(got(&near).map(f32::to_bits), want_n.map(f32::to_bits));
                        assert_eq!(got(&bil).map(f32::to_bits), want_b.map(f32::to_bits));
                    }
                }
            }
        }
    }

    /// `anisotropic_lanes` against `sample` per point, bit for bit, on `n` of 8 lanes, for
    /// every filter and the anisotropies 2, 3, 8 and 16.
    fn anisotropic_lanes_match_scalar(img: &Image, wrap: [Wrap; 2], pts: &[(f64, f64, Footprint)]) {
        for chunk in pts.chunks(8) {
            let n = chunk.len();
            let (mut u, mut v) = ([0.0; 8], [0.0; 8]);
            let mut fp = [Footprint::default(); 8];
            for (k, &(a, b, f)) in chunk.iter().enumerate() {
                (u[k], v[k], fp[k]) = (a, b, f);
            }
            for wide in [false, avx2()] {
                for filter in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
                    for aniso in [2, 3, 8, 16] {
                        let mut out = [[-7.0f32; 8]; 3];
                        anisotropic_lanes(img, filter, wrap, aniso, &u, &v, &fp, n, &mut out, wide);
                        for k in 0..n {
                            let want = sample(img, filter, wrap, aniso, u[k], v[k], &fp[k]);
                            let got = [out[0][k], out[1][k], out[2][k]];
                            assert_eq!(
                                got.map(f32::to_bits),
                                want.to_array().map(f32::to_bits),
                                "{filter:?} x{aniso} at ({}, {}) {:?}",
                                u[k],
                                v[k],
                                fp[k]
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn anisotropic_lanes_read_what_one_point_reads() {
        // Footprints isotropic, stretched along x or y up to 1:1000, sheared, zero (ratio
        // NaN), with one axis zero (ratio ∞), huge, and NaN.
        let f = |a: f64, b: f64, c: f64, d: f64| Footprint {
            du_dx: a,
            dv_dx: b,
            du_dy: c,
            dv_dy: d,
        };
        let fps = [
            f(0.01, 0.0, 0.0, 0.01),
            f(0.05, 0.0, 0.0, 0.01),
            f(0.0, 0.01, 0.3, 0.0),
            f(0.02, 0.011, -0.004, 0.09),
            f(1e-5, 0.0, 0.0, 1e-2),
            f(0.0, 0.0, 0.0, 0.0),
            f(0.0, 0.0, 0.0, 0.2),
            f(1e200, 3.0, 0.5, 1e-200),
            f(f64::NAN, 0.0, 0.0, 0.1),
            f(0.3, 0.2, 0.1, 0.25),
            f(2.0, 0.0, 0.0, 0.001),
        ];
        let mut pts = Vec::new();
        for (i, fp) in fps.iter().enumerate() {
            for &(u, v) in &[(0.1, 0.2), (-3.7, 0.55), (0.999, 12.25), (1e6, -1e5)] {
                pts.push((u + 0.01 * i as f64, v, *fp));
            }
        }
        // Chunks of neighbours with mixed probe counts and levels.
        for k in 0..24 {
            let s = 0.004 * (1.0 + k as f64);
            pts.push((
                0.3 + 0.01 * k as f64,
                0.7,
                f(s, 0.0, 0.0, s * (k % 5 + 1) as f64 * 3.0),
            ));
        }
        for (w, h) in [(8, 4), (5, 3), (1, 1), (16, 16)] {
            let img = ramp(w, h);
            for a in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
                anisotropic_lanes_match_scalar(&img, [a, Wrap::Repeat], &pts);
                anisotropic_lanes_match_scalar(&img, [Wrap::Clamp, a], &pts);
            }
        }
    }

    /// Whether this CPU has AVX2 (the gathers' precondition).
    fn avx2() -> bool {
        #[cfg(target_arch = "x86_64")]
        return std::arch::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        false
    }

    #[test]
    fn lanes_read_what_one_point_reads_at_every_magnitude() {
        let mut pts = Vec::new();
        for &m in &[0.3, 1.0, 7.5, 1e3, 2.2e9, 3.3e7, 1e15, 5e15, 1e17, 1e300] {
            for &f in &[-1.0, -0.37, 0.0, 0.61, 1.0] {
                pts.push((m * f, m * (0.5 - f)));
                pts.push((m * f + 0.5 / 8.0, -m * f));
            }
        }
        // 2³¹ / 8 and its neighbours: where the i32 lanes stop and the per-lane path starts.
        let edge = 268_435_456.0;
        pts.extend([
            (edge, 0.1),
            (-edge, 0.2),
            (edge - 1e-6, -edge + 1e-6),
            (0.999, 1.0),
        ]);
        for (w, h) in [(8, 4), (5, 3), (1, 1), (16, 7)] {
            let img = ramp(w, h);
            for a in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
                for b in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
                    lanes_match_scalar(&img, [a, b], &pts);
                }
            }
        }
    }

    proptest! {
        /// The lane samplers read what the one-point filters read, bit for bit, at any
        /// finite coordinates, sizes and wraps.
        #[test]
        fn lanes_match_one_point_filters(
            pts in prop::collection::vec((-1e10f64..1e10, -1e4f64..1e4), 1..20),
            w in 1usize..9, h in 1usize..9, a in 0usize..3, b in 0usize..3,
        ) {
            let modes = [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror];
            let size = |s: usize| if s > 4 { 1 << (s - 4) } else { s };
            lanes_match_scalar(&ramp(size(w) * 2, size(h)), [modes[a], modes[b]], &pts);
        }


        /// The anisotropic lanes read what one point reads, bit for bit, at any finite
        /// coordinates and footprints.
        #[test]
        fn anisotropic_lanes_match_one_point(
            pts in prop::collection::vec(
                (-1e4f64..1e4, -1e4f64..1e4, prop::array::uniform4(-1e2f64..1e2)),
                1..12,
            ),
            w in 1usize..9, h in 1usize..9, a in 0usize..3,
        ) {
            let modes = [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror];
            let size = |s: usize| if s > 4 { 1 << (s - 4) } else { s };
            let pts: Vec<_> = pts
                .into_iter()
                .map(|(u, v, d)| {
                    // Footprints over many scales: each entry d·10^(−|d|/20).
                    let d = d.map(|x| x * 10f64.powf(-x.abs() / 20.0));
                    (u, v, Footprint { du_dx: d[0], dv_dx: d[1], du_dy: d[2], dv_dy: d[3] })
                })
                .collect();
            anisotropic_lanes_match_scalar(&ramp(size(w) * 2, size(h)), [modes[a], modes[2 - a]], &pts);
        }

        /// Every filter is a convex combination of texels: each channel stays within the
        /// image's range, for any finite coordinates and footprint, in every wrap mode.
        #[test]
        fn samples_stay_within_the_texel_range(
            u in -1e6f64..1e6, v in -1e6f64..1e6,
            d in prop::array::uniform4(-1e3f64..1e3),
            f in 0usize..3, w in 0usize..3,
        ) {
            let img = ramp(7, 5);
            let filter = [Filter::Nearest, Filter::Bilinear, Filter::Trilinear][f];
            let wrap = [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror][w];
            let fp = Footprint { du_dx: d[0], dv_dx: d[1], du_dy: d[2], dv_dy: d[3] };
            let c = tex(&img, filter, wrap).sample(u, v, &fp);
            prop_assert!(c.x >= -1e-4 && c.x <= 6.0 + 1e-4, "{c}");
            prop_assert!(c.y >= -1e-4 && c.y <= 4.0 + 1e-4, "{c}");
        }

        /// Repeat is periodic: (u + k, v + m) reads what (u, v) reads, for integer k, m
        /// (coordinates that are exact multiples of the texel size, so no rounding differs).
        #[test]
        fn repeat_is_periodic(i in 0u32..64, j in 0u32..64, k in -50i32..50, m in -50i32..50) {
            let img = ramp(8, 4);
            let (u, v) = (i as f64 / 64.0, j as f64 / 64.0);
            for filter in [Filter::Nearest, Filter::Bilinear] {
                let t = tex(&img, filter, Wrap::Repeat);
                let fp = Footprint::default();
                prop_assert_eq!(t.sample(u, v, &fp), t.sample(u + k as f64, v + m as f64, &fp));
            }
        }
    }
}
