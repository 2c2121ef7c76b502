//! The vertex stage's per-vertex work on AVX lanes: four vertices at a time in f64 (the
//! clip transform, outcode and snapping) and eight in f32 (world positions and normals).
//!
//! Each function is the lane form of a scalar one in [`super::vertex`], with the same
//! operations in the same order (no fused multiply-add, IEEE-exact division and square
//! root), so both give the same bits; `vertex`'s tests and the fuzzer's ISA comparison
//! check it. Compiled for the baseline (SSE2), the scalar loop took about 150 instructions
//! a vertex for the clip transform alone (the 998,000-triangle sphere: 77M a frame).
//!
//! Each function does the whole groups of its slices and returns how many vertices it did;
//! the caller finishes the rest with the scalar form.

#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;
use std::mem::MaybeUninit;

use glam::{DMat4, Mat3, Mat4, Vec3, Vec4};

use super::clip::INVALID;
use super::setup::{Snapped, MAGIC, ONE};

/// `vertex::clip_vertex` on four vertices at a time: clip coordinates (f64, rounded to
/// f32 for `clip`), the outcode of the rounded ones and the snapped screen position.
///
/// # Safety
/// The CPU must support AVX2. `clip`, `code` and `screen` are at least as long as `pos`.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn clip_vertices(
    mvp: &DMat4,
    guard: (f64, f64),
    (width, height): (f64, f64),
    pos: &[Vec3],
    clip: &mut [MaybeUninit<Vec4>],
    code: &mut [MaybeUninit<u8>],
    screen: &mut [MaybeUninit<Snapped>],
) -> usize {
    let n = pos.len() / 4 * 4;
    let (clip, code, screen) = (&mut clip[..n], &mut code[..n], &mut screen[..n]);
    let m = mvp.to_cols_array_2d().map(|c| c.map(|v| _mm256_set1_pd(v)));
    let zero = _mm256_setzero_pd();
    let lt0 = |v: __m256d| _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(v, zero)) as u32;
    let abs_mask = _mm256_set1_pd(-0.0);
    let below = |v: __m256d, lim: f64| {
        let a = _mm256_andnot_pd(abs_mask, v);
        _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(a, _mm256_set1_pd(lim))) as u32
    };
    let (gx, gy) = (_mm256_set1_pd(guard.0), _mm256_set1_pd(guard.1));
    let (one, half) = (_mm256_set1_pd(1.0), _mm256_set1_pd(0.5));
    let (w, h) = (_mm256_set1_pd(width), _mm256_set1_pd(height));
    let (sub, magic) = (_mm256_set1_pd(ONE as f64), _mm256_set1_pd(MAGIC));
    let round = |v: __m256d| _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(v, sub), magic), magic);
    for i in (0..n).step_by(4) {
        let p = &pos[i..i + 4];
        let x = _mm256_cvtps_pd(_mm_setr_ps(p[0].x, p[1].x, p[2].x, p[3].x));
        let y = _mm256_cvtps_pd(_mm_setr_ps(p[0].y, p[1].y, p[2].y, p[3].y));
        let z = _mm256_cvtps_pd(_mm_setr_ps(p[0].z, p[1].z, p[2].z, p[3].z));
        // `DMat4 * DVec4` as glam computes it, each row's sum in the same order; the w
        // column is multiplied by 1, which is exact.
        let row = |r: usize| {
            let mut s = _mm256_mul_pd(m[0][r], x);
            s = _mm256_add_pd(s, _mm256_mul_pd(m[1][r], y));
            s = _mm256_add_pd(s, _mm256_mul_pd(m[2][r], z));
            _mm256_add_pd(s, m[3][r])
        };
        let c = [row(0), row(1), row(2), row(3)];
        let c32 = c.map(|v| _mm256_cvtpd_ps(v));
        let finite = c32.iter().fold(0xf, |acc, v| {
            acc & below(_mm256_cvtps_pd(*v), f64::INFINITY)
        });
        // `ClipPlanes::outcode_finite` on the rounded coordinates (`-a + b` is `b - a`).
        let [bx, by, bz, bw] = c32.map(|v| _mm256_cvtps_pd(v));
        let (gxw, gyw) = (_mm256_mul_pd(gx, bw), _mm256_mul_pd(gy, bw));
        let bits = [
            lt0(_mm256_sub_pd(bw, bz)),
            lt0(bz),
            lt0(_mm256_sub_pd(gxw, bx)),
            lt0(_mm256_add_pd(bx, gxw)),
            lt0(_mm256_sub_pd(gyw, by)),
            lt0(_mm256_add_pd(by, gyw)),
        ];
        // `setup::snap` on the f64 coordinates.
        let inv_w = _mm256_div_pd(one, c[3]);
        let sx = _mm256_mul_pd(
            _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(c[0], inv_w), one), half),
            w,
        );
        let sy = _mm256_mul_pd(
            _mm256_mul_pd(_mm256_sub_pd(one, _mm256_mul_pd(c[1], inv_w)), half),
            h,
        );
        let (fx, fy) = (round(sx), round(sy));
        let lim = (1u64 << 24) as f64;
        let snapped = below(fx, lim) & below(fy, lim) & below(inv_w, f64::INFINITY);
        let mut ix = [0i32; 4];
        let mut iy = [0i32; 4];
        let mut sz = [0f32; 4];
        let mut iw = [0f32; 4];
        let mut cs = [[0f32; 4]; 4];
        // SAFETY: stores of four lanes into arrays of four.
        unsafe {
            _mm_storeu_si128(ix.as_mut_ptr().cast(), _mm256_cvttpd_epi32(fx));
            _mm_storeu_si128(iy.as_mut_ptr().cast(), _mm256_cvttpd_epi32(fy));
            _mm_storeu_ps(sz.as_mut_ptr(), _mm256_cvtpd_ps(_mm256_mul_pd(c[2], inv_w)));
            _mm_storeu_ps(iw.as_mut_ptr(), _mm256_cvtpd_ps(inv_w));
            for (k, v) in c32.iter().enumerate() {
                _mm_storeu_ps(cs[k].as_mut_ptr(), *v);
            }
        }
        for l in 0..4 {
            let mut k = if finite >> l & 1 == 0 {
                INVALID
            } else {
                bits.iter()
                    .enumerate()
                    .fold(0u8, |acc, (b, m)| acc | ((m >> l & 1) as u8) << b)
            };
            let mut s = Snapped::default();
            if k == 0 {
                if snapped >> l & 1 == 1 {
                    s = (ix[l], iy[l], sz[l], iw[l]);
                } else {
                    k = INVALID;
                }
            }
            clip[i + l].write(Vec4::new(cs[0][l], cs[1][l], cs[2][l], cs[3][l]));
            code[i + l].write(k);
            screen[i + l].write(s);
        }
    }
    n
}

/// Loads eight `Vec3`s as three lanes of x, y and z.
#[target_feature(enable = "avx2")]
#[inline]
fn load8(p: &[Vec3]) -> [__m256; 3] {
    let p = &p[..8];
    let get = |f: fn(&Vec3) -> f32| {
        _mm256_setr_ps(
            f(&p[0]),
            f(&p[1]),
            f(&p[2]),
            f(&p[3]),
            f(&p[4]),
            f(&p[5]),
            f(&p[6]),
            f(&p[7]),
        )
    };
    [get(|v| v.x), get(|v| v.y), get(|v| v.z)]
}

/// Writes three lanes of x, y and z as eight `Vec3`s.
#[target_feature(enable = "avx2")]
#[inline]
fn store8(v: [__m256; 3], out: &mut [MaybeUninit<Vec3>]) {
    let mut a = [[0f32; 8]; 3];
    for (k, v) in v.iter().enumerate() {
        // SAFETY: a store of eight lanes into an array of eight.
        unsafe { _mm256_storeu_ps(a[k].as_mut_ptr(), *v) };
    }
    for (l, o) in out[..8].iter_mut().enumerate() {
        o.write(Vec3::new(a[0][l], a[1][l], a[2][l]));
    }
}

/// A matrix's columns (`to_cols_array_2d`) as lanes of each element.
#[target_feature(enable = "avx2")]
#[inline]
fn splat_cols<const R: usize, const C: usize>(cols: [[f32; R]; C]) -> [[__m256; R]; C] {
    cols.map(|c| c.map(|v| _mm256_set1_ps(v)))
}

/// Row `r` of the first three columns of `m` times `(x, y, z)`: `(m0·x + m1·y) + m2·z`,
/// glam's sums for `Mat3 * Vec3` and for `Mat4::transform_point3` before its w column
/// (glam adds `m1·y + s` there, `s + m1·y` in `Mat3`; IEEE addition commutes exactly).
#[target_feature(enable = "avx2")]
#[inline]
fn mul_row<const R: usize>(m: &[[__m256; R]], r: usize, [x, y, z]: [__m256; 3]) -> __m256 {
    let s = _mm256_add_ps(_mm256_mul_ps(m[0][r], x), _mm256_mul_ps(m[1][r], y));
    _mm256_add_ps(s, _mm256_mul_ps(m[2][r], z))
}

/// `Mat4::transform_point3` on eight points at a time (glam's order of operations).
///
/// # Safety
/// The CPU must support AVX2. `out` is at least as long as `pos`.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn world_points(
    model: &Mat4,
    pos: &[Vec3],
    out: &mut [MaybeUninit<Vec3>],
) -> usize {
    let n = pos.len() / 8 * 8;
    let m = splat_cols(model.to_cols_array_2d());
    for i in (0..n).step_by(8) {
        let p = load8(&pos[i..]);
        let row = |r: usize| _mm256_add_ps(mul_row(&m, r, p), m[3][r]);
        store8([row(0), row(1), row(2)], &mut out[i..]);
    }
    n
}

/// `(nm * n).normalize_or_zero()` on eight normals at a time (glam's order of operations:
/// `Mat3 * Vec3`, then the reciprocal of the square root of the dot product, zero where it
/// is not finite and positive).
///
/// # Safety
/// The CPU must support AVX2. `out` is at least as long as `normals`.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn world_normals(
    nm: &Mat3,
    normals: &[Vec3],
    out: &mut [MaybeUninit<Vec3>],
) -> usize {
    let n = normals.len() / 8 * 8;
    let m = splat_cols(nm.to_cols_array_2d());
    let (one, inf) = (_mm256_set1_ps(1.0), _mm256_set1_ps(f32::INFINITY));
    let zero = _mm256_setzero_ps();
    for i in (0..n).step_by(8) {
        let p = load8(&normals[i..]);
        let v = [0, 1, 2].map(|r| mul_row(&m, r, p));
        let dot = _mm256_add_ps(
            _mm256_add_ps(_mm256_mul_ps(v[0], v[0]), _mm256_mul_ps(v[1], v[1])),
            _mm256_mul_ps(v[2], v[2]),
        );
        let rcp = _mm256_div_ps(one, _mm256_sqrt_ps(dot));
        // `rcp.is_finite() && rcp > 0`: false for NaN (ordered compares).
        let ok = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_LT_OQ>(rcp, inf),
            _mm256_cmp_ps::<_CMP_GT_OQ>(rcp, zero),
        );
        let scaled = v.map(|c| _mm256_and_ps(_mm256_mul_ps(c, rcp), ok));
        store8(scaled, &mut out[i..]);
    }
    n
}

#[cfg(test)]
mod tests {
    use glam::{DMat4, DVec3, Mat3, Mat4, Quat, Vec3};
    use proptest::prelude::*;

    use super::*;
    use crate::pipeline::clip::ClipPlanes;
    use crate::pipeline::vertex::clip_vertex;

    fn avx2() -> bool {
        std::arch::is_x86_feature_detected!("avx2")
    }

    fn uninit<T>(n: usize) -> Vec<MaybeUninit<T>> {
        (0..n).map(|_| MaybeUninit::uninit()).collect()
    }

    /// The lanes give the scalar form's bits for every vertex of a whole group.
    fn check_clip(mvp: DMat4, pos: &[Vec3], (w, h): (u32, u32)) {
        let planes = ClipPlanes::new(w, h);
        let size = (w as f64, h as f64);
        let n = pos.len();
        let (mut c, mut k, mut s) = (uninit(n), uninit(n), uninit(n));
        // SAFETY: AVX2 checked by the caller; outputs as long as `pos`.
        let done =
            unsafe { clip_vertices(&mvp, planes.guard(), size, pos, &mut c, &mut k, &mut s) };
        assert_eq!(done, n / 4 * 4);
        for i in 0..done {
            let (wc, wk, ws) = clip_vertex(&mvp, &planes, size, pos[i]);
            // SAFETY: `clip_vertices` wrote the first `done`.
            let (gc, gk, gs) =
                unsafe { (c[i].assume_init(), k[i].assume_init(), s[i].assume_init()) };
            let bits = |v: Vec4| v.to_array().map(f32::to_bits);
            assert_eq!(bits(gc), bits(wc), "clip of {:?}", pos[i]);
            assert_eq!(gk, wk, "outcode of {:?}", pos[i]);
            let sb = |s: Snapped| (s.0, s.1, s.2.to_bits(), s.3.to_bits());
            assert_eq!(sb(gs), sb(ws), "snapped {:?}", pos[i]);
        }
    }

    fn check_world(model: Mat4, nm: Mat3, pos: &[Vec3]) {
        let n = pos.len();
        let (mut p, mut q) = (uninit(n), uninit(n));
        // SAFETY: AVX2 checked by the caller; outputs as long as `pos`.
        let (dp, dq) = unsafe {
            (
                world_points(&model, pos, &mut p),
                world_normals(&nm, pos, &mut q),
            )
        };
        assert_eq!((dp, dq), (n / 8 * 8, n / 8 * 8));
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        for i in 0..dp {
            // SAFETY: both wrote the first `dp`.
            let (gp, gq) = unsafe { (p[i].assume_init(), q[i].assume_init()) };
            assert_eq!(
                bits(gp),
                bits(model.transform_point3(pos[i])),
                "{:?}",
                pos[i]
            );
            assert_eq!(
                bits(gq),
                bits((nm * pos[i]).normalize_or_zero()),
                "{:?}",
                pos[i]
            );
        }
    }

    fn camera(w: u32, h: u32) -> DMat4 {
        let view = DMat4::look_at_rh(DVec3::new(0.3, 0.4, 3.0), DVec3::ZERO, DVec3::Y);
        // Reversed Z as the renderer's cameras make it (near 0.1 maps to 1, infinity to 0).
        let proj = DMat4::perspective_infinite_reverse_rh(0.8, w as f64 / h as f64, 0.1);
        proj * view
    }

    /// Points on purpose at the edges: behind the eye, on the eye plane (w = 0), across
    /// the near plane, beyond the guard band, non-finite, huge, zero and denormal.
    fn awkward() -> Vec<Vec3> {
        let mut v = vec![
            Vec3::ZERO,
            Vec3::new(0.3, 0.4, 3.0),
            Vec3::new(0.3, 0.4, 2.9),
            Vec3::new(0.3, 0.4, 3.1),
            Vec3::new(0.0, 0.0, 2.95),
            Vec3::new(1e4, 0.0, 0.0),
            Vec3::new(-1e4, 3e3, 0.0),
            Vec3::new(0.0, -2e4, 2.5),
            Vec3::new(f32::NAN, 0.0, 0.0),
            Vec3::new(0.0, f32::INFINITY, 0.0),
            Vec3::new(0.0, 0.0, f32::NEG_INFINITY),
            Vec3::splat(f32::MAX),
            Vec3::splat(-f32::MAX),
            Vec3::splat(f32::MIN_POSITIVE / 4.0),
            Vec3::new(1e-30, -1e-30, 1e-30),
            Vec3::new(0.5, 0.5, 0.5),
        ];
        for i in 0..48 {
            let t = i as f32 / 47.0;
            v.push(Vec3::new(
                -3.0 + 6.0 * t,
                (t * 17.0).sin() * 2.0,
                3.0 - 7.0 * t,
            ));
        }
        v
    }

    #[test]
    fn clip_lanes_match_the_scalar_vertex_at_awkward_points() {
        if !avx2() {
            return;
        }
        for (w, h) in [(512, 512), (1920, 1080), (1, 1), (7, 3)] {
            check_clip(camera(w, h), &awkward(), (w, h));
            let model = Mat4::from_scale_rotation_translation(
                Vec3::new(2.0, 0.5, 1.0),
                Quat::from_rotation_y(0.7),
                Vec3::new(0.1, -0.2, 0.3),
            );
            check_clip(camera(w, h) * model.as_dmat4(), &awkward(), (w, h));
        }
    }

    #[test]
    fn world_lanes_match_the_scalar_vertex_at_awkward_points() {
        if !avx2() {
            return;
        }
        let model = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, -0.5, 1e-3),
            Quat::from_rotation_z(1.1),
            Vec3::new(5.0, -0.2, 0.3),
        );
        let nm = Mat3::from_mat4(model).inverse().transpose();
        check_world(model, nm, &awkward());
        check_world(Mat4::ZERO, Mat3::ZERO, &awkward());
    }

    fn any_f32() -> impl Strategy<Value = f32> {
        prop_oneof![4 => -20f32..20.0, 1 => any::<f32>()]
    }

    proptest! {
        #[test]
        fn vertex_lanes_match_the_scalar_vertex(
            pos in prop::collection::vec((any_f32(), any_f32(), any_f32()), 0..40),
            m in prop::array::uniform16(-3f64..3.0),
            size in (1u32..4000, 1u32..4000),
        ) {
            if avx2() {
                let pos: Vec<Vec3> = pos.into_iter().map(|(x, y, z)| Vec3::new(x, y, z)).collect();
                let mvp = DMat4::from_cols_array(&m);
                check_clip(mvp, &pos, size);
                check_clip(camera(size.0, size.1) * mvp, &pos, size);
                let m32 = mvp.as_mat4();
                check_world(m32, Mat3::from_mat4(m32), &pos);
            }
        }
    }
}
