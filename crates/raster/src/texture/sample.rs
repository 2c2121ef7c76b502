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
    pub fn lod(&self, w: usize, h: usize) -> f64 {
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
    let px = norm(fp.du_dx * w, fp.dv_dx * h);
    let py = norm(fp.du_dy * w, fp.dv_dy * h);
    if px.is_nan() || py.is_nan() {
        return sample_at(image, filter, wrap, u, v, f64::INFINITY);
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
    let lambda = (pmax / n as f64).log2();
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

/// `GL_NEAREST` on one level: the texel (⌊u·w⌋, ⌊v·h⌋), wrapped.
#[inline(always)]
pub(super) fn nearest(l: &Level, wrap: [Wrap; 2], u: f64, v: f64) -> Vec3 {
    let i = wrap[0].index(floor(u * l.width as f64), l.width);
    let j = wrap[1].index(floor(v * l.height as f64), l.height);
    Vec3::from_array(l.texel(i, j))
}

/// `GL_LINEAR` on one level: the four texels around (u·w − ½, v·h − ½), weighted by the
/// fractions α, β (eq. 8.19).
#[inline(always)]
pub(super) fn bilinear(l: &Level, wrap: [Wrap; 2], u: f64, v: f64) -> Vec3 {
    let x = u * l.width as f64 - 0.5;
    let y = v * l.height as f64 - 0.5;
    let (x0, y0) = (floor(x), floor(y));
    let (a, b) = ((x - x0) as f32, (y - y0) as f32);
    let (i0, i1) = wrap[0].pair(x0, l.width);
    let (j0, j1) = wrap[1].pair(y0, l.height);
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

    proptest! {
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
