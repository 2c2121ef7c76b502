//! The batched shadow-map look-up: a batch of [`LANES`] shaded points against one face at a
//! time, in f32 relative to the light camera's eye, written as lane loops the compiler
//! vectorises (the render's AVX2 copy doubles their width, [`super::ShadowEffect`] picks it).
//!
//! Per point: its view coordinates `pv = R·(p − eye)` (the face's rotation; relative to the
//! eye so the f32 arithmetic keeps the precision of the point itself at any scene scale),
//! its texel coordinates, and the receiver plane of its geometric normal across the kernel.
//! The plane's depth at the centre of the texel `dx, dy` steps from the point's texel is
//! affine in `(dx, dy)` for an orthographic face,
//!
//! `t = depth + texel·(g.x·(dx + ox) − g.y·(dy + oy)) / g.z`,
//!
//! (`ox, oy`: from the point to its texel's centre, in texels; `g` the normal in view
//! space), and the quotient of a constant by an affine function for a perspective one,
//!
//! `t = (g·pv) / ((g·pv)/depth + texel·(g.x·(dx + ox) − g.y·(dy + oy)))`,
//!
//! both exact rearrangements of the ray–plane intersection of the map's doc. Along the plane
//! (denominator within 1e-9 of zero), behind the light or not finite, the point's own depth
//! is used, as before.

use glam::{DMat4, Vec3};

use crate::lighting::{Lanes, LANES};

/// One face's constants for the batched look-up (f32 copies of its f64 camera).
#[derive(Debug, Clone, Copy)]
pub(super) struct FaceLanes {
    /// The light camera's eye: the origin of the points' view coordinates.
    eye: Vec3,
    /// Rows of the view's rotation (world → view axes).
    rot: [Vec3; 3],
    /// World size of a texel at eye depth 1 (perspective) or anywhere (orthographic); its
    /// inverse maps view units (over depth, for perspective) to texels.
    texel: f32,
    inv_texel: f32,
    /// Half the map's resolution: the texel coordinate of the view axis.
    centre: f32,
    perspective: bool,
}

impl FaceLanes {
    /// The constants of a face whose camera has view matrix `view`, eye `eye`, texel size
    /// `texel` and resolution `res`.
    pub fn new(view: &DMat4, eye: glam::DVec3, texel: f64, res: usize, perspective: bool) -> Self {
        let row = |i: usize| view.row(i).truncate().as_vec3();
        FaceLanes {
            eye: eye.as_vec3(),
            rot: [row(0), row(1), row(2)],
            texel: texel as f32,
            inv_texel: (1.0 / texel) as f32,
            centre: res as f32 / 2.0,
            perspective,
        }
    }
}

/// Far outside the map a texel coordinate is clamped to this (the kernel reads the edge,
/// and `i32` texel arithmetic cannot overflow).
const FAR: f32 = (1 << 24) as f32;

/// The map and the filter one look-up reads.
#[derive(Clone, Copy)]
pub(super) struct Kernel<'a> {
    /// The face's depths, row-major, `res × res`.
    pub depth: &'a [f32],
    pub res: usize,
    /// The filter's half width (0: the plain comparison).
    pub half: i32,
    /// Whether points outside the map read its edge (filtering) or are lit (plain).
    pub clamp_outside: bool,
    /// The tolerance in texel sizes (the settings' `bias`).
    pub bias: f32,
}

/// Per-lane inputs of one batch: unit shading normals `n`, points `p`, geometric normals
/// `g` (any length, any side).
pub(super) struct Points<'a> {
    pub n: &'a [Lanes; 3],
    pub p: &'a [Lanes; 3],
    pub g: &'a [Lanes; 3],
}

/// The share of the kernel's texels that see each lane's point lit, for the lanes where
/// `active` is set (the others are left as they are in `out`).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
pub(super) fn visibility<const WIDE: bool>(
    face: &FaceLanes,
    k: Kernel<'_>,
    pts: &Points<'_>,
    active: &[bool; LANES],
    out: &mut Lanes,
) {
    if face.perspective {
        lanes::<true, WIDE>(face, k, pts, active, out)
    } else {
        lanes::<false, WIDE>(face, k, pts, active, out)
    }
}

#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
fn lanes<const PERSPECTIVE: bool, const WIDE: bool>(
    face: &FaceLanes,
    k: Kernel<'_>,
    pts: &Points<'_>,
    active: &[bool; LANES],
    out: &mut Lanes,
) {
    let (n, p, g) = (pts.n, pts.p, pts.g);
    let e = face.eye;
    let [r0, r1, r2] = face.rot;
    let r = k.res as i32;
    // Per lane: whether the map decides (else lit), texel, receiver coefficients.
    let mut decide = [false; LANES];
    let (mut tx, mut ty) = ([0i32; LANES], [0i32; LANES]);
    let (mut c0, mut cx, mut cy) = ([0f32; LANES], [0f32; LANES], [0f32; LANES]);
    let (mut num, mut own, mut tol) = ([0f32; LANES], [0f32; LANES], [0f32; LANES]);
    for l in 0..LANES {
        let d = Vec3::new(p[0][l] - e.x, p[1][l] - e.y, p[2][l] - e.z);
        let nl = Vec3::new(n[0][l], n[1][l], n[2][l]);
        // Faces away from the light: no diffuse or specular whatever the map says.
        let toward = if PERSPECTIVE { -d } else { r2 };
        let facing = nl.dot(toward) > 0.0;
        // The geometric normal, unit, on the shading normal's side, in view space.
        let gl = Vec3::new(g[0][l], g[1][l], g[2][l]);
        let len2 = gl.length_squared();
        let gl = if len2 > 0.0 && len2.is_finite() {
            gl / len2.sqrt()
        } else {
            Vec3::ZERO
        };
        let gl = if gl.dot(nl) < 0.0 { -gl } else { gl };
        let gv = Vec3::new(r0.dot(gl), r1.dot(gl), r2.dot(gl));
        let pv = Vec3::new(r0.dot(d), r1.dot(d), r2.dot(d));
        let depth = -pv.z;
        // Texel coordinates (x right, y down) of the point.
        let (u, v) = if PERSPECTIVE {
            (pv.x / depth, pv.y / depth)
        } else {
            (pv.x, pv.y)
        };
        let sx = u * face.inv_texel + face.centre;
        let sy = face.centre - v * face.inv_texel;
        let seen = !PERSPECTIVE || depth > 0.0;
        let finite = sx.is_finite() && sy.is_finite();
        let (fx, fy) = (floor_near(sx), floor_near(sy));
        let inside = fx >= 0 && fy >= 0 && fx < r && fy < r;
        decide[l] = active[l] && facing && seen && finite && (k.clamp_outside || inside);
        // Lanes the map does not decide read texel (1, 1), inside any map of 4 texels or
        // more, so they keep the AVX2 kernel on its gather-free path (`rows_3x3`).
        (tx[l], ty[l]) = if decide[l] { (fx, fy) } else { (1, 1) };
        // From the point to its texel's centre, in texels.
        let (ox, oy) = (fx as f32 + 0.5 - sx, fy as f32 + 0.5 - sy);
        let (wx, wy) = (face.texel * gv.x, -face.texel * gv.y);
        if PERSPECTIVE {
            let gp = gv.dot(pv);
            num[l] = gp;
            c0[l] = gp / depth + wx * ox + wy * oy;
            (cx[l], cy[l]) = (wx, wy);
            tol[l] = face.texel * depth * k.bias + 1e-6 * depth;
        } else {
            // Along the plane (light grazing it edge-on): the point's own depth everywhere.
            let q = if gv.z.abs() > 1e-9 { 1.0 / gv.z } else { 0.0 };
            c0[l] = depth + (wx * ox + wy * oy) * q;
            (cx[l], cy[l]) = (wx * q, wy * q);
            tol[l] = face.texel * k.bias + 1e-6 * depth.abs();
        }
        own[l] = depth;
    }
    let q = Receivers {
        tx,
        ty,
        c0,
        cx,
        cy,
        num,
        own,
        tol,
    };
    let mut lit = [0.0f32; LANES];
    #[cfg(target_arch = "x86_64")]
    if WIDE {
        // SAFETY: `WIDE` is only set by the AVX2+FMA copy of the look-up (`ShadowEffect`
        // picks it when the render's instruction set has them).
        unsafe { kernel_avx2::<PERSPECTIVE>(&k, &q, &mut lit) };
    } else {
        kernel::<PERSPECTIVE>(&k, &q, &mut lit);
    }
    #[cfg(not(target_arch = "x86_64"))]
    kernel::<PERSPECTIVE>(&k, &q, &mut lit);
    let share = 1.0 / ((2 * k.half + 1) * (2 * k.half + 1)) as f32;
    for l in 0..LANES {
        // A select, not a store under a branch: this form vectorises (perf: the scalar
        // stores were 8 % of the look-up).
        let v = if decide[l] { lit[l] * share } else { 1.0 };
        out[l] = if active[l] { v } else { out[l] };
    }
}

/// Each lane's texel and receiver depth coefficients (see the module's doc): the depth the
/// kernel texel `dx, dy` is compared with is `c0 + cx·dx + cy·dy` (orthographic) or
/// `num / (c0 + cx·dx + cy·dy)` (perspective), `own` where that is unusable, less `tol`.
struct Receivers {
    tx: [i32; LANES],
    ty: [i32; LANES],
    c0: Lanes,
    cx: Lanes,
    cy: Lanes,
    num: Lanes,
    own: Lanes,
    tol: Lanes,
}

/// The kernel's comparisons, a lane at a time: adds to `lit` the number of texels of each
/// lane's kernel (clamped to the map's edge) that see its receiver lit.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
fn kernel<const PERSPECTIVE: bool>(k: &Kernel<'_>, q: &Receivers, lit: &mut Lanes) {
    let r = k.res as i32;
    for dy in -k.half..=k.half {
        let mut row = [0usize; LANES];
        for l in 0..LANES {
            row[l] = ((q.ty[l] + dy).clamp(0, r - 1) * r) as usize;
        }
        let fdy = dy as f32;
        for dx in -k.half..=k.half {
            let fdx = dx as f32;
            for l in 0..LANES {
                let at = row[l] + (q.tx[l] + dx).clamp(0, r - 1) as usize;
                debug_assert!(at < k.depth.len());
                // SAFETY: both coordinates are clamped to [0, res), so `at < res²`, the
                // length of every face's depth buffer.
                let stored = unsafe { *k.depth.get_unchecked(at) };
                let t = if PERSPECTIVE {
                    let den = q.c0[l] + q.cx[l] * fdx + q.cy[l] * fdy;
                    let t = q.num[l] / den;
                    if den.abs() > 1e-9 && t.is_finite() && t > 0.0 {
                        t
                    } else {
                        q.own[l]
                    }
                } else {
                    let t = q.c0[l] + q.cx[l] * fdx + q.cy[l] * fdy;
                    if t.is_finite() && t > 0.0 {
                        t
                    } else {
                        q.own[l]
                    }
                };
                lit[l] += if t - q.tol[l] <= stored { 1.0 } else { 0.0 };
            }
        }
    }
}

/// [`kernel`] with AVX2: the same operations in the same order over a vector of 8 lanes, the
/// texels fetched by one gather per kernel texel, or, for the 3 × 3 kernel with every lane's
/// texels inside the map, a row at a time by [`rows_3x3`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn kernel_avx2<const PERSPECTIVE: bool>(k: &Kernel<'_>, q: &Receivers, lit: &mut Lanes) {
    use std::arch::x86_64::*;
    const _: () = assert!(LANES == 8, "one AVX2 vector holds the lanes");
    // SAFETY: each array holds exactly one vector of 8 lanes.
    let (tx, ty) = unsafe {
        (
            _mm256_loadu_si256(q.tx.as_ptr().cast()),
            _mm256_loadu_si256(q.ty.as_ptr().cast()),
        )
    };
    let [c0, cx, cy, num, own, tol] = [&q.c0, &q.cx, &q.cy, &q.num, &q.own, &q.tol]
        // SAFETY: each array holds exactly one vector of 8 lanes.
        .map(|a| unsafe { _mm256_loadu_ps(a.as_ptr()) });
    let zero_i = _mm256_setzero_si256();
    let last = _mm256_set1_epi32(k.res as i32 - 1);
    let res = _mm256_set1_epi32(k.res as i32);
    let zero = _mm256_setzero_ps();
    let one = _mm256_set1_ps(1.0);
    let inf = _mm256_set1_ps(f32::INFINITY);
    let sign = _mm256_set1_ps(-0.0);
    let tiny = _mm256_set1_ps(1e-9);
    let base = k.depth.as_ptr();
    // SAFETY: `lit` holds exactly one vector of 8 lanes.
    let mut acc = unsafe { _mm256_loadu_ps(lit.as_ptr()) };
    // The receiver's affine terms `c0 + cx·dx` of a kernel column and `cy·dy` of a row,
    // each computed once per look-up: the sum of the two is `kernel`'s `lin`, in its order.
    let column = |dx: f32| _mm256_add_ps(c0, _mm256_mul_ps(cx, _mm256_set1_ps(dx)));
    let row_term = |dy: f32| _mm256_mul_ps(cy, _mm256_set1_ps(dy));
    // The comparison of each kernel texel: `stored` its depths, `col` and `row` its terms.
    let compare = |stored: __m256, col: __m256, row: __m256| {
        let lin = _mm256_add_ps(col, row);
        let t = if PERSPECTIVE {
            let t = _mm256_div_ps(num, lin);
            let ok = _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_GT_OQ>(_mm256_andnot_ps(sign, lin), tiny),
                _mm256_and_ps(
                    _mm256_cmp_ps::<_CMP_LT_OQ>(_mm256_andnot_ps(sign, t), inf),
                    _mm256_cmp_ps::<_CMP_GT_OQ>(t, zero),
                ),
            );
            _mm256_blendv_ps(own, t, ok)
        } else {
            let ok = _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_LT_OQ>(_mm256_andnot_ps(sign, lin), inf),
                _mm256_cmp_ps::<_CMP_GT_OQ>(lin, zero),
            );
            _mm256_blendv_ps(own, lin, ok)
        };
        let pass = _mm256_cmp_ps::<_CMP_LE_OQ>(_mm256_sub_ps(t, tol), stored);
        _mm256_and_ps(pass, one)
    };
    if k.half == 1 && k.res >= 4 {
        // The 3 × 3 kernel (the default filter) with every lane's kernel inside the map:
        // each row's texels from one 4-texel load per lane, transposed, instead of a gather
        // per texel (perf: on AMD Zen the gathers were half the look-up's time).
        let lo = _mm256_set1_epi32(1);
        let inside = _mm256_andnot_si256(
            _mm256_or_si256(
                _mm256_or_si256(_mm256_cmpgt_epi32(lo, tx), _mm256_cmpgt_epi32(lo, ty)),
                _mm256_or_si256(
                    _mm256_cmpgt_epi32(tx, _mm256_set1_epi32(k.res as i32 - 3)),
                    _mm256_cmpgt_epi32(ty, _mm256_set1_epi32(k.res as i32 - 2)),
                ),
            ),
            _mm256_set1_epi32(-1),
        );
        if _mm256_movemask_epi8(inside) == -1 {
            // Each lane's first texel of its middle row, ty·res + tx − 1 (below res² ≤ 2³⁰:
            // no overflow), once for the three rows.
            let mut first = [0i32; LANES];
            let at = _mm256_add_epi32(_mm256_mullo_epi32(ty, res), _mm256_sub_epi32(tx, lo));
            // SAFETY: `first` holds exactly one vector of 8 lanes.
            unsafe { _mm256_storeu_si256(first.as_mut_ptr().cast(), at) };
            let cols = [column(-1.0), column(0.0), column(1.0)];
            for dy in -1..=1 {
                // SAFETY: every lane has 1 <= tx <= res - 3 and 1 <= ty <= res - 2 (just
                // checked), so row ty + dy and texels tx - 1 ..= tx + 2 are in the map.
                let stored = unsafe { rows_3x3(base, k.res, &first, dy) };
                let row = row_term(dy as f32);
                for (col, stored) in cols.into_iter().zip(stored) {
                    acc = _mm256_add_ps(acc, compare(stored, col, row));
                }
            }
            // SAFETY: `lit` holds exactly one vector of 8 lanes.
            unsafe { _mm256_storeu_ps(lit.as_mut_ptr(), acc) };
            return;
        }
    }
    for dy in -k.half..=k.half {
        let y = _mm256_min_epi32(
            _mm256_max_epi32(_mm256_add_epi32(ty, _mm256_set1_epi32(dy)), zero_i),
            last,
        );
        let row = _mm256_mullo_epi32(y, res);
        let fdy = row_term(dy as f32);
        for dx in -k.half..=k.half {
            let x = _mm256_min_epi32(
                _mm256_max_epi32(_mm256_add_epi32(tx, _mm256_set1_epi32(dx)), zero_i),
                last,
            );
            // SAFETY: both coordinates are clamped to [0, res), so every index is below
            // res², the length of the face's depth buffer.
            let stored = unsafe { _mm256_i32gather_ps::<4>(base, _mm256_add_epi32(row, x)) };
            acc = _mm256_add_ps(acc, compare(stored, column(dx as f32), fdy));
        }
    }
    // SAFETY: `lit` holds exactly one vector of 8 lanes.
    unsafe { _mm256_storeu_ps(lit.as_mut_ptr(), acc) };
}

/// Row `ty + dy` of each lane's 3 × 3 kernel: the depths at `tx - 1`, `tx` and `tx + 1` as
/// three vectors of the 8 lanes, from one unaligned 4-texel load per lane and a 4 × 4
/// transpose in each 128-bit half (lanes 0-3 low, 4-7 high). `first`: each lane's
/// `ty·res + tx − 1`.
///
/// # Safety
/// The CPU must support AVX2; `depth` must point to a `res × res` map, and every lane must
/// have `1 <= tx <= res - 3` and `0 <= ty + dy <= res - 1`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn rows_3x3(
    depth: *const f32,
    res: usize,
    first: &[i32; LANES],
    dy: i32,
) -> [std::arch::x86_64::__m256; 3] {
    use std::arch::x86_64::*;
    let step = dy as isize * res as isize;
    let load = |l: usize| {
        let at = (first[l] as isize + step) as usize;
        // SAFETY: the texels tx - 1 ..= tx + 2 of row ty + dy are in the map by the
        // caller's contract.
        unsafe { _mm_loadu_ps(depth.add(at)) }
    };
    let pair = |l: usize| _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(load(l)), load(l + 4));
    let (a0, a1, a2, a3) = (pair(0), pair(1), pair(2), pair(3));
    let (t0, t1) = (_mm256_unpacklo_ps(a0, a1), _mm256_unpackhi_ps(a0, a1));
    let (t2, t3) = (_mm256_unpacklo_ps(a2, a3), _mm256_unpackhi_ps(a2, a3));
    [
        _mm256_shuffle_ps::<0x44>(t0, t2),
        _mm256_shuffle_ps::<0xEE>(t0, t2),
        _mm256_shuffle_ps::<0x44>(t1, t3),
    ]
}

/// `⌊v⌋` of `v` clamped to ±[`FAR`] (NaN to −`FAR`; lanes with a NaN coordinate are not
/// decided by the map, so any texel does), without the libm call `f32::floor` is on the
/// baseline instruction set. The conversion is unchecked because the value is in range:
/// the saturating `as i32` does not vectorise (LLVM made it one scalar conversion per lane,
/// a fifth of the look-up's time in perf), this does.
#[inline(always)]
fn floor_near(v: f32) -> i32 {
    // Not `clamp`, which keeps a NaN (and the unchecked conversion of NaN is undefined).
    #[allow(clippy::manual_clamp)]
    let v = v.max(-FAR).min(FAR);
    // SAFETY: `max` and `min` return the non-NaN operand, so `v` is finite and within
    // ±2²⁴, inside the `i32` range.
    let i = unsafe { v.to_int_unchecked::<i32>() };
    i - ((i as f32) > v) as i32
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "x86_64")]
    use crate::shadows::lcg::Lcg;

    /// `floor_near` is the floor of the value clamped to ±FAR (the saturating form it
    /// replaced, `floor(v.clamp(-FAR, FAR))` with `as i32`), and NaN reads −FAR.
    #[test]
    fn floor_near_is_the_floor_of_the_clamped_value() {
        let mut vals = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2047.999,
            -1e-30,
            1e-30,
            FAR,
            -FAR,
            FAR * 2.0,
            -FAR * 2.0,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        vals.extend((0..2000).map(|k| (k as f32 - 1000.0) * 0.37 + 1.0 / 3.0));
        for v in vals {
            let want = v.clamp(-FAR, FAR).floor() as i32;
            assert_eq!(floor_near(v), want, "{v}");
        }
        assert_eq!(floor_near(f32::NAN), -(FAR as i32));
    }

    /// The AVX2 kernel counts what the lane loop counts, on its gather-free 3 × 3 path
    /// (every lane inside the map) and on its gathers (lanes at and past the edges, other
    /// widths), for both projections: the same comparisons, so the same counts exactly.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn avx2_kernel_counts_what_the_lane_loop_counts() {
        if !(is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")) {
            eprintln!("no AVX2 + FMA here: the AVX2 kernel is not compared");
            return;
        }
        let mut rng = Lcg(7);
        let mut fast = 0;
        for res in [4usize, 5, 16, 61] {
            let depth: Vec<f32> = (0..res * res).map(|_| 1.0 + rng.next()).collect();
            for half in [0, 1, 2] {
                let k = Kernel {
                    depth: &depth,
                    res,
                    half,
                    clamp_outside: true,
                    bias: 0.5,
                };
                for case in 0..400 {
                    let r = res as i32;
                    // Half the batches wholly inside (the fast path), half anywhere.
                    let coord = |rng: &mut Lcg| {
                        if case % 2 == 0 {
                            1 + rng.below(r - 3)
                        } else {
                            rng.below(r + 6) - 3
                        }
                    };
                    let lanes = |rng: &mut Lcg, lo: f32, hi: f32| {
                        std::array::from_fn(|_| lo + (hi - lo) * rng.next())
                    };
                    let q = Receivers {
                        tx: std::array::from_fn(|_| coord(&mut rng)),
                        ty: std::array::from_fn(|_| coord(&mut rng)),
                        c0: lanes(&mut rng, 0.5, 2.5),
                        cx: lanes(&mut rng, -0.3, 0.3),
                        cy: lanes(&mut rng, -0.3, 0.3),
                        num: lanes(&mut rng, 0.5, 2.5),
                        own: lanes(&mut rng, 0.5, 2.5),
                        tol: lanes(&mut rng, 0.0, 0.1),
                    };
                    let inside = q.tx.iter().all(|&x| (1..=r - 3).contains(&x))
                        && q.ty.iter().all(|&y| (1..=r - 2).contains(&y));
                    fast += (half == 1 && inside) as usize;
                    for perspective in [false, true] {
                        let (mut want, mut got) = ([0.5f32; LANES], [0.5f32; LANES]);
                        // SAFETY: AVX2 and FMA were detected above.
                        unsafe {
                            if perspective {
                                kernel::<true>(&k, &q, &mut want);
                                kernel_avx2::<true>(&k, &q, &mut got);
                            } else {
                                kernel::<false>(&k, &q, &mut want);
                                kernel_avx2::<false>(&k, &q, &mut got);
                            }
                        }
                        assert_eq!(
                            want, got,
                            "res {res} half {half} case {case} perspective {perspective}"
                        );
                    }
                }
            }
        }
        assert!(fast > 500, "only {fast} batches took the 3 × 3 path");
    }
}
