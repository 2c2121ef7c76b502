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
        let (fx, fy) = (floor(sx.clamp(-FAR, FAR)), floor(sy.clamp(-FAR, FAR)));
        let inside = fx >= 0 && fy >= 0 && fx < r && fy < r;
        decide[l] = active[l] && facing && seen && finite && (k.clamp_outside || inside);
        (tx[l], ty[l]) = if decide[l] { (fx, fy) } else { (0, 0) };
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
        if active[l] {
            out[l] = if decide[l] { lit[l] * share } else { 1.0 };
        }
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
/// texels fetched by one gather per kernel texel.
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
    for dy in -k.half..=k.half {
        let y = _mm256_min_epi32(
            _mm256_max_epi32(_mm256_add_epi32(ty, _mm256_set1_epi32(dy)), zero_i),
            last,
        );
        let row = _mm256_mullo_epi32(y, res);
        let fdy = _mm256_set1_ps(dy as f32);
        for dx in -k.half..=k.half {
            let x = _mm256_min_epi32(
                _mm256_max_epi32(_mm256_add_epi32(tx, _mm256_set1_epi32(dx)), zero_i),
                last,
            );
            // SAFETY: both coordinates are clamped to [0, res), so every index is below
            // res², the length of the face's depth buffer.
            let stored = unsafe { _mm256_i32gather_ps::<4>(base, _mm256_add_epi32(row, x)) };
            let fdx = _mm256_set1_ps(dx as f32);
            let lin = _mm256_add_ps(
                _mm256_add_ps(c0, _mm256_mul_ps(cx, fdx)),
                _mm256_mul_ps(cy, fdy),
            );
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
            acc = _mm256_add_ps(acc, _mm256_and_ps(pass, one));
        }
    }
    // SAFETY: `lit` holds exactly one vector of 8 lanes.
    unsafe { _mm256_storeu_ps(lit.as_mut_ptr(), acc) };
}

/// `⌊v⌋` of a finite `v` in the `i32` range, without the libm call `f32::floor` is on the
/// baseline instruction set.
#[inline(always)]
fn floor(v: f32) -> i32 {
    let i = v as i32;
    i - ((i as f32) > v) as i32
}
