//! Eight points sampled in AVX2 registers, for callers that hold their (u, v) there (the
//! textured rows' common case, `pipeline::shade::textured::lean`): the nearest and bilinear
//! filters of an image texture wrapped by `Repeat` on power-of-two sizes (most textures).
//!
//! The operations are [`Texture::sample_many`]'s for these filters, in the same order:
//! the coordinates scaled, offset and made finite (`lanes`), the texel indices as
//! `lane_indices` takes them (⌊x⌋ here by `roundpd`, which equals its truncation minus
//! one where that exceeds x, for |x| < 2³¹), the texels as `fetch` reads them and
//! bilinear's blend. So every value is the same, bit for bit (the unit tests hold each
//! against `sample_many`). A live lane beyond 2³¹ texels makes [`ImageLanes::sample8`]
//! give up (`None`); its caller then takes `sample_many`, which handles every point.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

use glam::DVec2;

use super::image::Level;
use super::sample::Filter;
use super::wrap::Wrap;
use super::{Source, Texture};

/// An image texture as [`ImageLanes::sample8`] reads it: level 0's channels, its size and
/// the masks that wrap a texel index, the (u, v) transform and the filter.
pub(crate) struct ImageLanes<'a> {
    channels: &'a [f32],
    size: [f64; 2],
    /// The texel index wrap, `size − 1` (`Repeat` on a power of two).
    mask: [i32; 2],
    width: i32,
    /// The last texel's index.
    last: i32,
    scale: DVec2,
    offset: DVec2,
    bilinear: bool,
}

impl Texture {
    /// The texture as [`ImageLanes`] reads it: an image filtered nearest or bilinear
    /// (isotropic), wrapped by `Repeat` on power-of-two sizes; `None` for anything else.
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
        let bilinear = match filter {
            Filter::Nearest => false,
            Filter::Bilinear => true,
            Filter::Trilinear => return None,
        };
        let l: &Level = &image.levels()[0];
        let pow2 = l.width.is_power_of_two() && l.height.is_power_of_two();
        if *wrap != [Wrap::Repeat; 2] || !pow2 {
            return None;
        }
        // Sizes are at most MAX_TEXTURE_SIZE and texel counts below MAX_TEXELS: i32.
        Some(ImageLanes {
            channels: l.channels(),
            size: [l.width as f64, l.height as f64],
            mask: [l.width as i32 - 1, l.height as i32 - 1],
            width: l.width as i32,
            last: l.texel_count() as i32 - 1,
            scale: self.uv_scale,
            offset: self.uv_offset,
            bilinear,
        })
    }
}

impl ImageLanes<'_> {
    /// Whether the filter is bilinear (else nearest).
    pub(crate) fn bilinear(&self) -> bool {
        self.bilinear
    }

    /// The colours at the eight points (`u`, `v`) (lanes 0–3 in the first register of
    /// each, 4–7 in the second), channel by channel, as [`Texture::sample_many`] gives
    /// them; `None` when one of the first `live` lanes lies beyond 2³¹ texels (the other
    /// lanes are computed whatever they hold, and read texels of the level). `BILINEAR`
    /// must be [`ImageLanes::bilinear`].
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(crate) unsafe fn sample8<const BILINEAR: bool>(
        &self,
        u: [__m256d; 2],
        v: [__m256d; 2],
        live: usize,
    ) -> Option<[__m256; 3]> {
        debug_assert_eq!(BILINEAR, self.bilinear);
        // SAFETY: AVX2, the caller's promise.
        let (ui, uf, uok) = unsafe { self.axis::<BILINEAR>(u, 0) };
        // SAFETY: as above.
        let (vi, vf, vok) = unsafe { self.axis::<BILINEAR>(v, 1) };
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
    /// the fraction x − ⌊x⌋ in f32) of the eight coordinates `c`, and the bits of the lanes
    /// whose x lies below 2³¹ (others read index 0, as `lane_indices` reads them).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn axis<const BILINEAR: bool>(
        &self,
        c: [__m256d; 2],
        a: usize,
    ) -> ([__m256i; 2], __m256, u32) {
        let (s, o) = (
            _mm256_set1_pd(self.scale[a]),
            _mm256_set1_pd(self.offset[a]),
        );
        let size = _mm256_set1_pd(self.size[a]);
        let sign = _mm256_set1_pd(-0.0);
        let lane_int = _mm256_set1_pd(2_147_483_648.0);
        let mut ok = 0u32;
        let mut t = [_mm_setzero_si128(); 2];
        let mut frac = [_mm_setzero_ps(); 2];
        for (h, &c) in c.iter().enumerate() {
            // `lanes`: c·s + o, 0 where not finite.
            let x = _mm256_add_pd(_mm256_mul_pd(c, s), o);
            let finite = _mm256_cmp_pd::<_CMP_LT_OQ>(
                _mm256_andnot_pd(sign, x),
                _mm256_set1_pd(f64::INFINITY),
            );
            let x = _mm256_and_pd(x, finite);
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
    #[cfg(target_arch = "x86_64")]
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

/// `channels[at[k] + ch]` for the eight lanes and three channels: each texel read as four
/// floats (r, g, b and the next one), two texels to a 256-bit register (lanes k and
/// k + 4), then transposed.
///
/// # Safety
/// The CPU must support AVX, and `at[k] + 3` must be within `channels` for every k.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
pub(super) unsafe fn texels8_avx(channels: &[f32], at: &[u32; 8]) -> [__m256; 3] {
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

#[cfg(all(test, target_arch = "x86_64"))]
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

    /// `sample8` against `sample_many` on the points `pts` in groups of eight, every count
    /// of live lanes: where it answers, the same bits in the live lanes; it gives up only
    /// where a live lane's coordinate lies beyond 2³¹ texels.
    fn sample8_matches(t: &Texture, pts: &[(f64, f64)]) {
        let Some(map) = t.image_lanes() else {
            panic!("a nearest or bilinear Repeat texture on powers of two");
        };
        let (s, o) = t.uv_transform();
        let beyond = |c: f64, a: usize| {
            let size = [map.size[0], map.size[1]][a];
            let x = c * [s.x, s.y][a] + [o.x, o.y][a];
            x.is_finite()
                && (x * size - if map.bilinear { 0.5 } else { 0.0 }).abs() >= 2.147_483_648e9
        };
        for chunk in pts.chunks(8) {
            let (mut u, mut v) = ([0.0; 8], [0.0; 8]);
            for (k, &(a, b)) in chunk.iter().enumerate() {
                (u[k], v[k]) = (a, b);
            }
            for live in 1..=chunk.len() {
                let mut want = [[0.0f32; 8]; 3];
                t.sample_many(&u, &v, &[Footprint::default(); 8], live, &mut want, false);
                // SAFETY: AVX2, checked by the caller; the loads are eight f64 each.
                let got = unsafe {
                    let load = |c: &[f64; 8]| {
                        [
                            _mm256_loadu_pd(c.as_ptr()),
                            _mm256_loadu_pd(c.as_ptr().add(4)),
                        ]
                    };
                    if map.bilinear {
                        map.sample8::<true>(load(&u), load(&v), live)
                    } else {
                        map.sample8::<false>(load(&u), load(&v), live)
                    }
                };
                let gives_up = (0..live).any(|k| beyond(u[k], 0) || beyond(v[k], 1));
                match got {
                    None => assert!(gives_up, "gave up on {:?}", &chunk[..live]),
                    Some(got) => {
                        assert!(
                            !gives_up,
                            "answered beyond 2³¹ texels: {:?}",
                            &chunk[..live]
                        );
                        for ch in 0..3 {
                            let mut g = [0.0f32; 8];
                            // SAFETY: eight floats.
                            unsafe { _mm256_storeu_ps(g.as_mut_ptr(), got[ch]) };
                            for k in 0..live {
                                assert_eq!(g[k].to_bits(), want[ch][k].to_bits(), "{:?}", chunk[k]);
                            }
                        }
                    }
                }
            }
        }
    }

    fn avx2() -> bool {
        std::arch::is_x86_feature_detected!("avx2")
    }

    #[test]
    fn image_lanes_take_only_what_they_read_exactly() {
        let t = |w, h, f, wrap| Texture::from_image(image(w, h), f, [wrap; 2]);
        assert!(t(8, 4, Filter::Nearest, Wrap::Repeat)
            .image_lanes()
            .is_some());
        assert!(t(1, 16, Filter::Bilinear, Wrap::Repeat)
            .image_lanes()
            .is_some());
        assert!(t(8, 4, Filter::Trilinear, Wrap::Repeat)
            .image_lanes()
            .is_none());
        assert!(t(8, 4, Filter::Nearest, Wrap::Clamp)
            .image_lanes()
            .is_none());
        assert!(t(8, 4, Filter::Bilinear, Wrap::Mirror)
            .image_lanes()
            .is_none());
        assert!(t(6, 4, Filter::Nearest, Wrap::Repeat)
            .image_lanes()
            .is_none());
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
        for (w, h) in [(8, 4), (1, 1), (16, 2), (2, 16)] {
            for f in [Filter::Nearest, Filter::Bilinear] {
                let t = Texture::from_image(image(w, h), f, [Wrap::Repeat; 2]);
                sample8_matches(&t, &pts);
                let moved = t.with_uv_transform(DVec2::new(3.0, -0.75), DVec2::new(0.3, -1e9));
                sample8_matches(&moved, &pts);
            }
        }
    }

    proptest::proptest! {
        /// `sample8` reads what `sample_many` reads, bit for bit, at any coordinates,
        /// power-of-two sizes and (u, v) transforms.
        #[test]
        fn sample8_matches_sample_many(
            pts in proptest::collection::vec((-1e9f64..1e9, -1e4f64..1e4), 1..20),
            w in 0u32..6, h in 0u32..6, bilinear: bool,
            scale in -8.0f64..8.0, offset in -1e3f64..1e3,
        ) {
            if avx2() {
                let f = if bilinear { Filter::Bilinear } else { Filter::Nearest };
                let t = Texture::from_image(image(1 << w, 1 << h), f, [Wrap::Repeat; 2])
                    .with_uv_transform(DVec2::new(scale, 1.0), DVec2::new(offset, -offset));
                sample8_matches(&t, &pts);
            }
        }
    }
}
