//! The textured rows' common case in AVX2 registers: a flat or Gouraud triangle whose only
//! map is a diffuse image filtered nearest, bilinear or trilinear (isotropic) under `Repeat`
//! on power-of-two sizes ([`Texture::image_lanes`]), without vertex colours: most textured
//! meshes, and the texture report's floor.
//!
//! The generic row path ([`super::textured_rows`]) interpolates a group into arrays
//! ([`Group::set`]), samples them through [`Texture::sample_many`], fills four arrays of
//! maps' colours (ones for the missing maps) and combines them ([`super::textured_color`]),
//! each step storing its lanes and the next loading them (perf put a fifth of the
//! nearest-filtered floor's frame on one of the stores of ones). Here a group stays in
//! registers from the weight planes to the row buffer, with the same operations in the same
//! order (the missing maps' ones are left out: x·1 = x exactly), so the same bits
//! (`tests/textures.rs`: `diffuse_only_rows_give_the_batch_paths_bits`).
//!
//! [`Group::set`]: super::Group::set

use std::arch::x86_64::*;
use std::ops::Range;

use super::{Current, Footprint, Material, Terms3, Texture, LANES};
use crate::pipeline::shade::store::RowColors;
use crate::texture::{F64x8, ImageLanes};

/// [`lean_groups`]' `FILTER`s.
pub(super) const NEAREST: u8 = 0;
pub(super) const BILINEAR: u8 = 1;
pub(super) const TRILINEAR: u8 = 2;

/// The map of a run the lean path draws: the object's diffuse map as [`ImageLanes`], when
/// it is the only map `m` reads and the object has no vertex colours; else `None`.
pub(super) fn lean_map<'a>(
    maps: Option<&'a crate::texture::Maps>,
    colors: bool,
    m: &Material,
) -> Option<(&'a Texture, ImageLanes<'a>)> {
    let maps = maps?;
    let emission_read = m.emission != glam::Vec3::ZERO && maps.emission.is_some();
    if colors || maps.specular.is_some() || maps.ambient.is_some() || emission_read {
        return None;
    }
    let t = maps.diffuse.as_deref()?;
    Some((t, t.image_lanes()?))
}

/// The groups of [`LANES`] pixels at `groups` (the run's `whole_lanes`, ending its live
/// pixels at `end`) of tile row centre `y` (tile origin column `x0`) of triangle `c`
/// with material `m` and diffuse map `map` (`t`'s [`ImageLanes`]), into the row buffer
/// `lin`, as [`super::textured_rows`] writes them. `GOURAUD`: `c` is shaded Gouraud (its
/// vertices' terms blended), else flat (its face's); `FILTER`: the map's filter
/// ([`ImageLanes::filter`]) as [`NEAREST`], [`BILINEAR`] or [`TRILINEAR`].
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
#[inline(never)]
#[allow(clippy::too_many_arguments)] // a run, its triangle and where it goes
pub(super) unsafe fn lean_groups<const FILTER: u8, const GOURAUD: bool>(
    c: &Current,
    m: &Material,
    t: &Texture,
    map: &ImageLanes<'_>,
    x0: usize,
    y: f64,
    groups: Range<usize>,
    end: usize,
    lin: &mut RowColors,
) {
    let set = _mm256_set1_pd;
    let pl = &c.plane;
    let by = [0, 1, 2].map(|k| pl[k][1] * y);
    let us = c.uv.map(|t| set(t.x as f64));
    let vs = c.uv.map(|t| set(t.y as f64));
    // `Group::footprints`' per-triangle sums: ∂(Σ q_k·a_k)/∂x and ∂W/∂x (likewise y); only
    // trilinear reads footprints.
    let zero = _mm256_setzero_pd();
    let (dq, dw) = if FILTER == TRILINEAR {
        let da = |a: [f32; 3], axis: usize| {
            let a = a.map(f64::from);
            set(pl[0][axis] * a[0] + pl[1][axis] * a[1] + pl[2][axis] * a[2])
        };
        let (uu, vv) = (c.uv.map(|t| t.x), c.uv.map(|t| t.y));
        let dw = [0, 1].map(|axis| set(pl[0][axis] + pl[1][axis] + pl[2][axis]));
        ([da(uu, 0), da(vv, 0), da(uu, 1), da(vv, 1)], dw)
    } else {
        ([zero; 4], [zero; 2])
    };
    let half = [
        _mm256_setr_pd(0.5, 1.5, 2.5, 3.5),
        _mm256_setr_pd(4.5, 5.5, 6.5, 7.5),
    ];
    // The run's constants per channel, broadcast once: the material's coefficients and the
    // terms (the face's, or, Gouraud, the three vertices').
    let lanes = |v: glam::Vec3| v.to_array().map(|x| _mm256_set1_ps(x));
    let (ke, ka, kd, ks) = (
        lanes(m.emission),
        lanes(m.ambient),
        lanes(m.diffuse),
        lanes(m.specular),
    );
    let [ta, tdf, tsp] = [|t: &Terms3| t.a, |t: &Terms3| t.d, |t: &Terms3| t.s]
        .map(|pick| c.terms.map(|t| lanes(pick(&t))));
    let mut s = groups.start;
    while s < groups.end {
        let live = LANES.min(end - s);
        // `Group::set`: x = base + k + ½ (exact either way: integers below 2⁵²), q_m the
        // planes there, W their sum, b_m = q_m·(1/W), u and v the weights' blends.
        let base = set((x0 + s) as f64);
        let mut b = [[_mm256_setzero_pd(); 2]; 3];
        let mut u = [_mm256_setzero_pd(); 2];
        let mut v = [_mm256_setzero_pd(); 2];
        let mut fp = [[_mm256_setzero_pd(); 2]; 4];
        for h in 0..2 {
            let x = _mm256_add_pd(base, half[h]);
            let q = [0, 1, 2].map(|k| {
                let a = _mm256_add_pd(_mm256_mul_pd(set(pl[k][0]), x), set(by[k]));
                _mm256_add_pd(a, set(pl[k][2]))
            });
            let w = _mm256_add_pd(_mm256_add_pd(q[0], q[1]), q[2]);
            let r = _mm256_div_pd(set(1.0), w);
            for k in 0..3 {
                b[k][h] = _mm256_mul_pd(q[k], r);
            }
            let blend = |a: &[__m256d; 3]| {
                let s = _mm256_add_pd(_mm256_mul_pd(a[0], b[0][h]), _mm256_mul_pd(a[1], b[1][h]));
                _mm256_add_pd(s, _mm256_mul_pd(a[2], b[2][h]))
            };
            u[h] = blend(&us);
            v[h] = blend(&vs);
            if FILTER == TRILINEAR {
                // `Group::footprints`: (∂(Σ q_k·a_k)/∂x − a·∂W/∂x) / W, likewise y.
                let d = |k: usize, a: __m256d, axis: usize| {
                    _mm256_mul_pd(_mm256_sub_pd(dq[k], _mm256_mul_pd(a, dw[axis])), r)
                };
                fp[0][h] = d(0, u[h], 0);
                fp[1][h] = d(1, v[h], 0);
                fp[2][h] = d(2, u[h], 1);
                fp[3][h] = d(3, v[h], 1);
            }
        }
        // SAFETY: AVX2, the caller's promise (all three).
        let td = unsafe {
            match FILTER {
                NEAREST => map.sample8::<false>(u, v, live),
                BILINEAR => map.sample8::<true>(u, v, live),
                _ => map.trilinear8(u, v, fp, live),
            }
        };
        let td = match td {
            Some(td) => td,
            // SAFETY: AVX2, the caller's promise.
            None => unsafe { sample_stored(t, u, v, fp, live) },
        };
        // As `vertex_terms`: Gouraud blends the vertices' terms by the weights in f32, any
        // other mode takes the face's.
        let bf = [0, 1, 2].map(|k| {
            if GOURAUD {
                _mm256_set_m128(_mm256_cvtpd_ps(b[k][1]), _mm256_cvtpd_ps(b[k][0]))
            } else {
                _mm256_setzero_ps()
            }
        });
        let terms = |t: &[[__m256; 3]; 3], ch: usize| {
            if !GOURAUD {
                return t[0][ch];
            }
            let s = _mm256_add_ps(
                _mm256_mul_ps(t[0][ch], bf[0]),
                _mm256_mul_ps(t[1][ch], bf[1]),
            );
            _mm256_add_ps(s, _mm256_mul_ps(t[2][ch], bf[2]))
        };
        for ch in 0..3 {
            // `textured_color`: ((ke + (ka·T)·A) + (kd·T)·D) + ks·S, T the diffuse map.
            let ad = _mm256_mul_ps(_mm256_mul_ps(ka[ch], td[ch]), terms(&ta, ch));
            let dd = _mm256_mul_ps(_mm256_mul_ps(kd[ch], td[ch]), terms(&tdf, ch));
            let sp = _mm256_mul_ps(ks[ch], terms(&tsp, ch));
            let col = _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(ke[ch], ad), dd), sp);
            let dst = &mut lin[ch][s..s + LANES];
            // SAFETY: `dst` is eight floats.
            unsafe { _mm256_storeu_ps(dst.as_mut_ptr(), col) };
        }
        s += LANES;
    }
}

/// The diffuse map at the group's points through [`Texture::sample_many`], which handles
/// every point (the lean sampler gives up on coordinates beyond 2³¹ texels).
///
/// # Safety
/// The CPU must support AVX2.
#[cold]
#[inline(never)]
#[target_feature(enable = "avx2")]
unsafe fn sample_stored(
    t: &Texture,
    u: F64x8,
    v: F64x8,
    fp: [F64x8; 4],
    live: usize,
) -> [__m256; 3] {
    let lanes = |c: [__m256d; 2]| {
        let mut a = [0.0f64; LANES];
        // SAFETY: `a` is eight f64, each half four.
        unsafe {
            _mm256_storeu_pd(a.as_mut_ptr(), c[0]);
            _mm256_storeu_pd(a.as_mut_ptr().add(4), c[1]);
        }
        a
    };
    let d = fp.map(lanes);
    let fp: [Footprint; LANES] = std::array::from_fn(|k| Footprint {
        du_dx: d[0][k],
        dv_dx: d[1][k],
        du_dy: d[2][k],
        dv_dy: d[3][k],
    });
    let mut out = [[0.0f32; LANES]; 3];
    t.sample_many(&lanes(u), &lanes(v), &fp, live, &mut out, false);
    // SAFETY: loads of eight floats each.
    out.map(|row| unsafe { _mm256_loadu_ps(row.as_ptr()) })
}
