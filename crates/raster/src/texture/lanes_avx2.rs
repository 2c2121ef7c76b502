//! Eight points sampled in AVX2 registers, for callers that hold their (u, v) there (the
//! textured rows' common case, `pipeline::shade::textured::lean`): the nearest, bilinear
//! and (isotropic) trilinear filters of an image texture wrapped by `Repeat` on
//! power-of-two sizes (most textures; every mip level of one is a power of two too).
//!
//! The operations are [`Texture::sample_many`]'s for these filters, in the same order:
//! the coordinates scaled, offset and made finite (`lanes`), the texel indices as
//! `lane_indices` takes them (⌊x⌋ here by `roundpd`, which equals its truncation minus
//! one where that exceeds x, for |x| < 2³¹), the texels as `fetch` reads them and
//! bilinear's blend; for trilinear, λ as `lod_lanes` computes it (`log2_normal` on four
//! lanes) and the two levels' blend as `trilinear_lanes` makes it. So every value is the
//! same, bit for bit (the unit and property tests hold each against `sample_many`). Where
//! `sample_many` would take a slower road for a live lane (a coordinate beyond 2³¹ texels;
//! for trilinear also a footprint whose squared length leaves the normal range, or lanes
//! on different levels), these give up (`None`) and the caller takes `sample_many`.

use std::arch::x86_64::*;

use glam::DVec2;

use super::image::Level;
use super::sample::{texels8_avx, Filter};
use super::wrap::Wrap;
use super::{Source, Texture};

/// An image texture as [`ImageLanes::sample8`] reads it: its levels, the (u, v) transform
/// and the filter.
pub(crate) struct ImageLanes<'a> {
    levels: &'a [Level],
    /// Level 0, made once (nearest and bilinear read it alone).
    base: LevelLanes<'a>,
    scale: DVec2,
    offset: DVec2,
    filter: Filter,
}

/// One level as the lanes index it: its channels, its size and the masks that wrap a texel
/// index (`Repeat` on powers of two).
struct LevelLanes<'a> {
    channels: &'a [f32],
    size: [f64; 2],
    /// The texel index wrap, `size − 1`.
    mask: [i32; 2],
    width: i32,
    /// The last texel's index.
    last: i32,
}

impl<'a> LevelLanes<'a> {
    #[inline(always)]
    fn new(l: &'a Level) -> Self {
        // Sizes are at most MAX_TEXTURE_SIZE and texel counts below MAX_TEXELS: i32.
        LevelLanes {
            channels: l.channels(),
            size: [l.width as f64, l.height as f64],
            mask: [l.width as i32 - 1, l.height as i32 - 1],
            width: l.width as i32,
            last: l.texel_count() as i32 - 1,
        }
    }
}

impl Texture {
    /// The texture as [`ImageLanes`] reads it: an image filtered nearest, bilinear or
    /// trilinear (isotropic), wrapped by `Repeat` on power-of-two sizes (so every mip level
    /// is one too); `None` for anything else.
    pub(crate) fn image_lanes(&self) -> Option<ImageLanes<'_>> {
        let Source::Image {
            image,
            filter,
            wrap,
            aniso: 0 | 1,
        } = &self.source
        else {
            return None;
        };
        let pow2 = image.width().is_power_of_two() && image.height().is_power_of_two();
        if *wrap != [Wrap::Repeat; 2] || !pow2 {
            return None;
        }
        Some(ImageLanes {
            levels: image.levels(),
            base: LevelLanes::new(&image.levels()[0]),
            scale: self.uv_scale,
            offset: self.uv_offset,
            filter: *filter,
        })
    }
}

/// Eight f64 lanes, lanes 0–3 in the first register and 4–7 in the second.
pub(crate) type F64x8 = [__m256d; 2];

impl ImageLanes<'_> {
    /// The filter.
    pub(crate) fn filter(&self) -> Filter {
        self.filter
    }

    /// The colours at the eight points (`u`, `v`), channel by channel, as
    /// [`Texture::sample_many`] gives them with the nearest (`BILINEAR` false) or bilinear
    /// filter; `None` when one of the first `live` lanes lies beyond 2³¹ texels (the other
    /// lanes are computed whatever they hold, and read texels of the level). `BILINEAR`
    /// must match [`ImageLanes::filter`], which must not be trilinear.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(crate) unsafe fn sample8<const BILINEAR: bool>(
        &self,
        u: F64x8,
        v: F64x8,
        live: usize,
    ) -> Option<[__m256; 3]> {
        debug_assert_eq!(BILINEAR, self.filter == Filter::Bilinear);
        // SAFETY: AVX2, the caller's promise.
        unsafe {
            let (x, y) = (self.coord(u, 0), self.coord(v, 1));
            self.base.filter8::<BILINEAR>(x, y, live)
        }
    }

    /// The trilinear filter's colours at the eight points (`u`, `v`) with the footprints
    /// `fp` (∂u/∂x, ∂v/∂x, ∂u/∂y, ∂v/∂y, before the (u, v) transform), as
    /// [`Texture::sample_many`] gives them; `None` when one of the first `live` lanes lies
    /// beyond 2³¹ texels, has a footprint whose squared length leaves the normal range
    /// (`lod_lanes` then takes `hypot` and libm), or reads other levels than lane 0 (the
    /// per-lane `trilinear` of `trilinear_lanes`).
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(crate) unsafe fn trilinear8(
        &self,
        u: F64x8,
        v: F64x8,
        fp: [F64x8; 4],
        live: usize,
    ) -> Option<[__m256; 3]> {
        debug_assert_eq!(self.filter, Filter::Trilinear);
        let live_bits = (1u32 << live.min(8)) - 1;
        // `scale_footprint` (×1 is exact, so always) and `lod_lanes`: λ = ½·log2 of the
        // larger squared axis in level-0 texels, where that is a normal number.
        let l0 = &self.levels[0];
        let (w, h) = (
            _mm256_set1_pd(l0.width as f64),
            _mm256_set1_pd(l0.height as f64),
        );
        let (su, sv) = (_mm256_set1_pd(self.scale.x), _mm256_set1_pd(self.scale.y));
        // `trilinear_lanes`' choice of levels, as a key per lane: −1 where magnified or
        // NaN (level 0 alone), `last` + ½ beyond the last level (it alone; −1 too when
        // level 0 is the last, the same choice), else ⌊λ⌋ (the pair ⌊λ⌋, ⌊λ⌋ + 1). Every
        // live lane must have lane 0's key. Compared in lanes: a scalar choice per lane
        // (with its NaN and range branches) was about a third of this function's
        // instructions on the texture report's floor.
        let last = self.levels.len() - 1;
        let beyond_key = if last == 0 { -1.0 } else { last as f64 + 0.5 };
        let mut lambda = [_mm256_setzero_pd(); 2];
        let mut key = [_mm256_setzero_pd(); 2];
        let mut ok = 0u32;
        #[allow(clippy::needless_range_loop)] // half h2 of fp's four lanes and of `lambda`
        for h2 in 0..2 {
            let axis = |du: __m256d, dv: __m256d| {
                let a = _mm256_mul_pd(_mm256_mul_pd(du, su), w);
                let b = _mm256_mul_pd(_mm256_mul_pd(dv, sv), h);
                _mm256_add_pd(_mm256_mul_pd(a, a), _mm256_mul_pd(b, b))
            };
            let sx = axis(fp[0][h2], fp[1][h2]);
            let sy = axis(fp[2][h2], fp[3][h2]);
            // `lod_of_squares`: valid where neither is NaN and the larger is normal.
            let s = _mm256_max_pd(sx, sy);
            let valid = _mm256_and_pd(
                _mm256_and_pd(
                    _mm256_cmp_pd::<_CMP_ORD_Q>(sx, sy),
                    _mm256_cmp_pd::<_CMP_GT_OQ>(s, _mm256_set1_pd(1e-300)),
                ),
                _mm256_cmp_pd::<_CMP_LT_OQ>(s, _mm256_set1_pd(1e300)),
            );
            ok |= (_mm256_movemask_pd(valid) as u32) << (4 * h2);
            let s = _mm256_blendv_pd(_mm256_set1_pd(1.0), s, valid);
            // SAFETY: AVX2, the caller's promise.
            let l = _mm256_mul_pd(_mm256_set1_pd(0.5), unsafe { log2_normal4(s) });
            lambda[h2] = l;
            let floor = _mm256_round_pd::<{ _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC }>(l);
            let k = _mm256_blendv_pd(
                floor,
                _mm256_set1_pd(beyond_key),
                _mm256_cmp_pd::<_CMP_GE_OQ>(l, _mm256_set1_pd(last as f64)),
            );
            // Not above 0 (NaN included): magnified.
            key[h2] = _mm256_blendv_pd(
                _mm256_set1_pd(-1.0),
                k,
                _mm256_cmp_pd::<_CMP_GT_OQ>(l, _mm256_setzero_pd()),
            );
        }
        if ok & live_bits != live_bits {
            return None;
        }
        let first = _mm256_permute4x64_pd::<0>(key[0]);
        let same = (_mm256_movemask_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(key[0], first))
            | (_mm256_movemask_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(key[1], first)) << 4))
            as u32;
        if same & live_bits != live_bits {
            return None;
        }
        let k0 = _mm256_cvtsd_f64(key[0]);
        let (d1, pair) = if k0 < 0.0 {
            (0, false)
        } else if k0 == beyond_key {
            (last, false)
        } else {
            (k0 as usize, true)
        };
        // SAFETY: AVX2, the caller's promise.
        unsafe {
            let (x, y) = (self.coord(u, 0), self.coord(v, 1));
            let a = LevelLanes::new(&self.levels[d1]).filter8::<true>(x, y, live)?;
            if !pair {
                return Some(a);
            }
            let b = LevelLanes::new(&self.levels[d1 + 1]).filter8::<true>(x, y, live)?;
            // a·(1 − f) + b·f, f = (λ − d1) in f32.
            // Written out: with a closure for `f` and `array::from_fn` for the blend, both
            // were left out of line once the level choice above was in lanes (1.2M and
            // 2.0M instructions over five frames of the floor, callgrind).
            let d = _mm256_set1_pd(d1 as f64);
            let f = _mm256_set_m128(
                _mm256_cvtpd_ps(_mm256_sub_pd(lambda[1], d)),
                _mm256_cvtpd_ps(_mm256_sub_pd(lambda[0], d)),
            );
            let g = _mm256_sub_ps(_mm256_set1_ps(1.0), f);
            Some([
                _mm256_add_ps(_mm256_mul_ps(a[0], g), _mm256_mul_ps(b[0], f)),
                _mm256_add_ps(_mm256_mul_ps(a[1], g), _mm256_mul_ps(b[1], f)),
                _mm256_add_ps(_mm256_mul_ps(a[2], g), _mm256_mul_ps(b[2], f)),
            ])
        }
    }

    /// `lanes`: the coordinates `c` along axis `a` transformed (c·s + o), 0 where not finite.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn coord(&self, c: F64x8, a: usize) -> F64x8 {
        let (s, o) = (
            _mm256_set1_pd(self.scale[a]),
            _mm256_set1_pd(self.offset[a]),
        );
        c.map(|c| {
            let x = _mm256_add_pd(_mm256_mul_pd(c, s), o);
            let finite = _mm256_cmp_pd::<_CMP_LT_OQ>(
                _mm256_andnot_pd(_mm256_set1_pd(-0.0), x),
                _mm256_set1_pd(f64::INFINITY),
            );
            _mm256_and_pd(x, finite)
        })
    }
}

/// `log2_normal` on four lanes (positive normal numbers), the same operations.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn log2_normal4(x: __m256d) -> __m256d {
    const C: [f64; 5] = super::sample::LOG2_SERIES;
    let bits = _mm256_castpd_si256(x);
    let mantissa = _mm256_set1_epi64x((1 << 52) - 1);
    let one_exp = _mm256_set1_epi64x(1023 << 52);
    let m = _mm256_castsi256_pd(_mm256_or_si256(_mm256_and_si256(bits, mantissa), one_exp));
    let big = _mm256_cmp_pd::<_CMP_GT_OQ>(m, _mm256_set1_pd(std::f64::consts::SQRT_2));
    let m = _mm256_blendv_pd(m, _mm256_mul_pd(m, _mm256_set1_pd(0.5)), big);
    let biased = _mm256_sub_pd(
        _mm256_castsi256_pd(_mm256_or_si256(
            _mm256_srli_epi64::<52>(bits),
            _mm256_set1_epi64x(0x4330_0000_0000_0000),
        )),
        _mm256_set1_pd(4_503_599_627_370_496.0),
    );
    let e = _mm256_add_pd(
        _mm256_sub_pd(biased, _mm256_set1_pd(1023.0)),
        _mm256_and_pd(big, _mm256_set1_pd(1.0)),
    );
    let one = _mm256_set1_pd(1.0);
    let t = _mm256_div_pd(_mm256_sub_pd(m, one), _mm256_add_pd(m, one));
    let t2 = _mm256_mul_pd(t, t);
    let mut p = _mm256_set1_pd(C[4]);
    for &c in C[..4].iter().rev() {
        p = _mm256_add_pd(_mm256_mul_pd(p, t2), _mm256_set1_pd(c));
    }
    _mm256_add_pd(e, _mm256_mul_pd(t, p))
}

impl LevelLanes<'_> {
    /// The nearest (`BILINEAR` false) or bilinear filter on this level at the transformed
    /// coordinates (`x`, `y`) (`coord`'s), as `nearest_lanes` and `bilinear_lanes` give it;
    /// `None` when one of the first `live` lanes lies beyond 2³¹ texels.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn filter8<const BILINEAR: bool>(
        &self,
        x: F64x8,
        y: F64x8,
        live: usize,
    ) -> Option<[__m256; 3]> {
        // SAFETY: AVX2, the caller's promise.
        let (ui, uf, uok) = unsafe { self.axis::<BILINEAR>(x, 0) };
        // SAFETY: as above.
        let (vi, vf, vok) = unsafe { self.axis::<BILINEAR>(y, 1) };
        let live_bits = (1u32 << live.min(8)) - 1;
        if uok & vok & live_bits != live_bits {
            return None;
        }
        let [i0, i1] = ui;
        let [j0, j1] = vi;
        if !BILINEAR {
            // SAFETY: as above.
            return Some(unsafe { self.texels(i0, j0) });
        }
        // SAFETY: as above.
        let (t0, t1, t2, t3) = unsafe {
            (
                self.texels(i0, j0),
                self.texels(i1, j0),
                self.texels(i0, j1),
                self.texels(i1, j1),
            )
        };
        // As `bilinear_lanes`: ((t0·w0 + t1·w1) + t2·w2) + t3·w3.
        let one = _mm256_set1_ps(1.0);
        let (a, b) = (uf, vf);
        let (na, nb) = (_mm256_sub_ps(one, a), _mm256_sub_ps(one, b));
        let w = [
            _mm256_mul_ps(na, nb),
            _mm256_mul_ps(a, nb),
            _mm256_mul_ps(na, b),
            _mm256_mul_ps(a, b),
        ];
        Some(std::array::from_fn(|ch| {
            let s = _mm256_add_ps(_mm256_mul_ps(t0[ch], w[0]), _mm256_mul_ps(t1[ch], w[1]));
            let s = _mm256_add_ps(s, _mm256_mul_ps(t2[ch], w[2]));
            _mm256_add_ps(s, _mm256_mul_ps(t3[ch], w[3]))
        }))
    }

    /// Along axis `a`: the texel indices ⌊x⌋ & mask (`BILINEAR`: and (⌊x⌋ + 1) & mask, and
    /// the fraction x − ⌊x⌋ in f32) of the eight transformed coordinates `c` scaled to this
    /// level (`BILINEAR`: and centred), and the bits of the lanes whose x lies below 2³¹
    /// (others read index 0, as `lane_indices` reads them).
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn axis<const BILINEAR: bool>(&self, c: F64x8, a: usize) -> ([__m256i; 2], __m256, u32) {
        let size = _mm256_set1_pd(self.size[a]);
        let sign = _mm256_set1_pd(-0.0);
        let lane_int = _mm256_set1_pd(2_147_483_648.0);
        let mut ok = 0u32;
        let mut t = [_mm_setzero_si128(); 2];
        let mut frac = [_mm_setzero_ps(); 2];
        for (h, &x) in c.iter().enumerate() {
            // `nearest_lanes` scales by the size, `bilinear_lanes` also centres.
            let x = _mm256_mul_pd(x, size);
            let x = if BILINEAR {
                _mm256_sub_pd(x, _mm256_set1_pd(0.5))
            } else {
                x
            };
            // `lane_indices`: lanes at or beyond 2³¹ read 0.
            let fits = _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_andnot_pd(sign, x), lane_int);
            ok |= (_mm256_movemask_pd(fits) as u32) << (4 * h);
            let xk = _mm256_and_pd(x, fits);
            let fl = _mm256_floor_pd(xk);
            t[h] = _mm256_cvttpd_epi32(fl);
            if BILINEAR {
                frac[h] = _mm256_cvtpd_ps(_mm256_sub_pd(xk, fl));
            }
        }
        let t = _mm256_set_m128i(t[1], t[0]);
        let m = _mm256_set1_epi32(self.mask[a]);
        let i0 = _mm256_and_si256(t, m);
        let i1 = if BILINEAR {
            _mm256_and_si256(_mm256_add_epi32(t, _mm256_set1_epi32(1)), m)
        } else {
            i0
        };
        ([i0, i1], _mm256_set_m128(frac[1], frac[0]), ok)
    }

    /// The texels (`i`, `j`) of the eight lanes, channel by channel, as `fetch` reads them.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn texels(&self, i: __m256i, j: __m256i) -> [__m256; 3] {
        let k = _mm256_add_epi32(_mm256_mullo_epi32(j, _mm256_set1_epi32(self.width)), i);
        let k = _mm256_min_epi32(k, _mm256_set1_epi32(self.last));
        let at = _mm256_add_epi32(k, _mm256_add_epi32(k, k));
        let mut lanes = [0u32; 8];
        // SAFETY: eight u32 are 256 bits.
        unsafe { _mm256_storeu_si256(lanes.as_mut_ptr().cast(), at) };
        // SAFETY: AVX2 (the caller's promise); every index is at most the last texel's (the
        // masks keep i and j in the level, the `min` whatever they hold), whose four floats
        // (with the padding texel's first) are in `channels`.
        unsafe { texels8_avx(self.channels, &lanes) }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::super::{Footprint, Image};
    use super::*;

    /// A `w × h` image of distinct texels.
    fn image(w: usize, h: usize) -> Arc<Image> {
        let d: Vec<f32> = (0..w * h)
            .flat_map(|k| [k as f32, (k % w) as f32 * 0.5, 1.0 / (1 + k) as f32])
            .collect();
        Arc::new(Image::from_top_rows(w, h, 3, &d, false).unwrap())
    }

    /// `sample8` (nearest, bilinear) or `trilinear8` against `sample_many` on the points
    /// `pts` in groups of eight, every count of live lanes, with footprints of size `e`
    /// (each lane's a little larger than the last): where it answers, the same bits in the
    /// live lanes. Nearest and bilinear give up exactly where a live lane's coordinate lies
    /// beyond 2³¹ texels. Returns how many groups it answered.
    fn sample8_matches(t: &Texture, pts: &[(f64, f64)], e: f64) -> usize {
        let Some(map) = t.image_lanes() else {
            panic!("a Repeat texture on powers of two");
        };
        let (s, o) = t.uv_transform();
        let l0 = LevelLanes::new(&map.levels[0]);
        let centre = if map.filter == Filter::Nearest {
            0.0
        } else {
            0.5
        };
        let beyond = |c: f64, a: usize| {
            let x = c * [s.x, s.y][a] + [o.x, o.y][a];
            x.is_finite() && (x * l0.size[a] - centre).abs() >= 2.147_483_648e9
        };
        let fp: [Footprint; 8] = std::array::from_fn(|k| {
            let g = e * (1.0 + 0.01 * k as f64);
            Footprint {
                du_dx: g,
                dv_dx: -0.3 * g,
                du_dy: 0.2 * g,
                dv_dy: 0.7 * g,
            }
        });
        let mut answered = 0;
        for chunk in pts.chunks(8) {
            let (mut u, mut v) = ([0.0; 8], [0.0; 8]);
            for (k, &(a, b)) in chunk.iter().enumerate() {
                (u[k], v[k]) = (a, b);
            }
            for live in 1..=chunk.len() {
                let mut want = [[0.0f32; 8]; 3];
                t.sample_many(&u, &v, &fp, live, &mut want, false);
                // SAFETY: AVX2, checked by the caller; the loads are eight f64 each.
                let got = unsafe {
                    let load = |c: &[f64; 8]| {
                        [
                            _mm256_loadu_pd(c.as_ptr()),
                            _mm256_loadu_pd(c.as_ptr().add(4)),
                        ]
                    };
                    let d = |f: fn(&Footprint) -> f64| load(&fp.map(|p| f(&p)));
                    let fps = [
                        d(|p| p.du_dx),
                        d(|p| p.dv_dx),
                        d(|p| p.du_dy),
                        d(|p| p.dv_dy),
                    ];
                    match map.filter {
                        Filter::Nearest => map.sample8::<false>(load(&u), load(&v), live),
                        Filter::Bilinear => map.sample8::<true>(load(&u), load(&v), live),
                        Filter::Trilinear => map.trilinear8(load(&u), load(&v), fps, live),
                    }
                };
                let gives_up = (0..live).any(|k| beyond(u[k], 0) || beyond(v[k], 1));
                match got {
                    None => assert!(
                        gives_up || map.filter == Filter::Trilinear,
                        "gave up on {:?}",
                        &chunk[..live]
                    ),
                    Some(got) => {
                        // Trilinear reads level 0 only where magnified: its limit is the level's.
                        assert!(
                            !gives_up || map.filter == Filter::Trilinear,
                            "answered beyond 2³¹ texels: {:?}",
                            &chunk[..live]
                        );
                        answered += 1;
                        for ch in 0..3 {
                            let mut g = [0.0f32; 8];
                            // SAFETY: eight floats.
                            unsafe { _mm256_storeu_ps(g.as_mut_ptr(), got[ch]) };
                            for k in 0..live {
                                assert_eq!(
                                    g[k].to_bits(),
                                    want[ch][k].to_bits(),
                                    "{:?} e {e} live {live}",
                                    chunk[k]
                                );
                            }
                        }
                    }
                }
            }
        }
        answered
    }

    fn avx2() -> bool {
        std::arch::is_x86_feature_detected!("avx2")
    }

    #[test]
    fn image_lanes_take_only_what_they_read_exactly() {
        let t = |w, h, f, wrap| Texture::from_image(image(w, h), f, [wrap; 2]);
        let cases = [
            (8, 4, Filter::Nearest, Wrap::Repeat, true),
            (1, 16, Filter::Bilinear, Wrap::Repeat, true),
            (8, 4, Filter::Trilinear, Wrap::Repeat, true),
            (8, 4, Filter::Nearest, Wrap::Clamp, false),
            (8, 4, Filter::Bilinear, Wrap::Mirror, false),
            (6, 4, Filter::Nearest, Wrap::Repeat, false),
        ];
        for (w, h, f, wrap, taken) in cases {
            let got = t(w, h, f, wrap).image_lanes().is_some();
            assert_eq!(got, taken, "{w}x{h} {f:?} {wrap:?}");
        }
        let aniso = t(8, 4, Filter::Bilinear, Wrap::Repeat)
            .with_anisotropy(4)
            .unwrap();
        assert!(aniso.image_lanes().is_none());
    }

    #[test]
    fn sample8_reads_what_sample_many_reads_at_every_magnitude() {
        if !avx2() {
            return;
        }
        let mut pts = Vec::new();
        for &m in &[0.3, 1.0, 7.5, 1e3, 3.3e7, 2.2e8, 1e9, 1e15, 1e300] {
            for &f in &[-1.0, -0.37, 0.0, 0.61, 1.0] {
                pts.push((m * f, m * (0.5 - f)));
                pts.push((m * f + 0.5 / 8.0, -m * f));
            }
        }
        // 2³¹ / 16 and its neighbours (where the lanes stop for 16 texels), texel edges,
        // and the non-finite coordinates `lanes` reads as 0.
        let edge = 134_217_728.0;
        pts.extend([
            (edge, 0.1),
            (-edge, 0.2),
            (edge - 1e-6, -edge + 1e-6),
            (0.999, 1.0),
            (0.5, -0.25),
            (-0.0, 0.0),
            (f64::NAN, 0.3),
            (f64::INFINITY, f64::NEG_INFINITY),
            (0.7, f64::NAN),
        ]);
        // Footprints from magnification to beyond the last level, and ones whose squares
        // leave the normal range (the general path's).
        let sizes = [0.0, 1e-310, 1e-3, 0.02, 0.05, 0.3, 3.0, 1e200, f64::NAN];
        for (w, h) in [(8, 4), (1, 1), (16, 2), (2, 16), (64, 32)] {
            for f in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
                let t = Texture::from_image(image(w, h), f, [Wrap::Repeat; 2]);
                let moved = t
                    .clone()
                    .with_uv_transform(DVec2::new(3.0, -0.75), DVec2::new(0.3, -1e9));
                let mut answered = 0;
                for e in sizes {
                    answered += sample8_matches(&t, &pts, e);
                    answered += sample8_matches(&moved, &pts, e);
                }
                assert!(answered > 100, "{f:?} {w}x{h}: {answered} groups answered");
            }
        }
    }

    /// Lanes that choose the same levels (one footprint for all eight) are answered, not
    /// handed to `sample_many`: magnified, between two levels, at the last level and beyond
    /// it, on a one-level texture (magnified and beyond are the same choice there) too.
    #[test]
    fn trilinear8_answers_lanes_that_share_their_levels() {
        if !avx2() {
            return;
        }
        for (w, h) in [(1, 1), (8, 4), (64, 32)] {
            let t = Texture::from_image(image(w, h), Filter::Trilinear, [Wrap::Repeat; 2]);
            let map = t.image_lanes().unwrap();
            for e in [1e-3, 0.02, 0.05, 0.3, 3.0, 1e3] {
                for live in 1..=8 {
                    // SAFETY: AVX2, checked above.
                    let got = unsafe {
                        let g = [_mm256_set1_pd(e); 2];
                        let z = [_mm256_setzero_pd(); 2];
                        let u = [_mm256_setr_pd(0.1, 0.2, 0.3, 0.4), _mm256_set1_pd(-0.7)];
                        map.trilinear8(u, u, [g, z, z, g], live)
                    };
                    assert!(got.is_some(), "{w}x{h} footprint {e} live {live}");
                }
            }
        }
    }

    proptest::proptest! {
        /// `sample8` and `trilinear8` read what `sample_many` reads, bit for bit, at any
        /// coordinates, footprints, power-of-two sizes and (u, v) transforms.
        #[test]
        fn sample8_matches_sample_many(
            pts in proptest::collection::vec((-1e9f64..1e9, -1e4f64..1e4), 1..20),
            w in 0u32..7, h in 0u32..7, f in 0usize..3,
            scale in -8.0f64..8.0, offset in -1e3f64..1e3, e in -12.0f64..4.0,
        ) {
            if avx2() {
                let f = [Filter::Nearest, Filter::Bilinear, Filter::Trilinear][f];
                let t = Texture::from_image(image(1 << w, 1 << h), f, [Wrap::Repeat; 2])
                    .with_uv_transform(DVec2::new(scale, 1.0), DVec2::new(offset, -offset));
                sample8_matches(&t, &pts, e.exp2());
            }
        }
    }
}
