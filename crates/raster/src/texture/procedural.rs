//! Procedural textures: patterns evaluated at the shaded point's (u, v), during shading ("any
//! function … generate radiance on the fly"). They are point-evaluated (not filtered), so
//! fine patterns far away alias as in the lectures' examples; bake one into an image to
//! have it mipmapped.

use glam::Vec3;

use super::sample::floor;
use crate::error::{RasterError, Result};

/// Most octaves a noise texture may sum.
pub const MAX_OCTAVES: u32 = 16;

/// A pattern over the (u, v) plane; `scale` is the number of cells (checks, grid cells,
/// stripe pairs, noise lattice cells) per unit of u and v.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Procedural {
    /// `a` where ⌊u·scale⌋ + ⌊v·scale⌋ is even, `b` where it is odd.
    Checker {
        /// Checks per unit.
        scale: f64,
        /// Colour of the even checks (the one at the origin).
        a: Vec3,
        /// Colour of the odd checks.
        b: Vec3,
    },
    /// Lines `b` of `width` (a fraction of a cell) centred on the cell borders, over `a`.
    Grid {
        /// Cells per unit.
        scale: f64,
        /// Line width as a fraction of a cell, in (0, 1).
        width: f64,
        /// Background colour.
        a: Vec3,
        /// Line colour.
        b: Vec3,
    },
    /// Stripes across u: `a` where ⌊u·scale⌋ is even, `b` where it is odd.
    Stripes {
        /// Stripes per unit.
        scale: f64,
        /// Colour of the even stripes.
        a: Vec3,
        /// Colour of the odd stripes.
        b: Vec3,
    },
    /// Value noise summed over `octaves` (each twice the frequency and half the amplitude of
    /// the one before), normalised to [0, 1], mixing `a` (0) to `b` (1).
    Noise {
        /// Lattice cells per unit of the first octave.
        scale: f64,
        /// Number of octaves, 1 to [`MAX_OCTAVES`].
        octaves: u32,
        /// Picks the lattice's random values.
        seed: u32,
        /// Colour at noise 0.
        a: Vec3,
        /// Colour at noise 1.
        b: Vec3,
    },
}

impl Procedural {
    /// Checks the parameters: a finite scale > 0, finite colours ≥ 0, a grid width in
    /// (0, 1), 1 to [`MAX_OCTAVES`] octaves.
    pub fn validated(self) -> Result<Self> {
        let (scale, a, b) = match self {
            Procedural::Checker { scale, a, b }
            | Procedural::Stripes { scale, a, b }
            | Procedural::Grid { scale, a, b, .. }
            | Procedural::Noise { scale, a, b, .. } => (scale, a, b),
        };
        if !(scale.is_finite() && scale > 0.0) {
            return Err(RasterError::invalid_field(
                "scale",
                format!("texture scale must be finite and > 0, got {scale}"),
            ));
        }
        for (name, c) in [("color_a", a), ("color_b", b)] {
            if !c.is_finite() || c.min_element() < 0.0 {
                return Err(RasterError::invalid_field(
                    name,
                    format!(
                        "texture {name} must be finite and >= 0, got {:?}",
                        c.to_array()
                    ),
                ));
            }
        }
        if let Procedural::Grid { width, .. } = self {
            if !(width > 0.0 && width < 1.0) {
                return Err(RasterError::invalid_field(
                    "width",
                    format!(
                        "grid line width must be in (0, 1) (a fraction of a cell), got {width}"
                    ),
                ));
            }
        }
        if let Procedural::Noise { octaves, .. } = self {
            if !(1..=MAX_OCTAVES).contains(&octaves) {
                return Err(RasterError::invalid_field(
                    "octaves",
                    format!("noise octaves must be 1 to {MAX_OCTAVES}, got {octaves}"),
                ));
            }
        }
        Ok(self)
    }

    /// The largest channel of its colours (every value it returns is a mix of them).
    pub fn max_value(&self) -> f32 {
        let (Procedural::Checker { a, b, .. }
        | Procedural::Stripes { a, b, .. }
        | Procedural::Grid { a, b, .. }
        | Procedural::Noise { a, b, .. }) = *self;
        a.max(b).max_element()
    }

    /// The pattern's name ("checker", "grid", "stripes", "noise").
    pub fn name(&self) -> &'static str {
        match self {
            Procedural::Checker { .. } => "checker",
            Procedural::Grid { .. } => "grid",
            Procedural::Stripes { .. } => "stripes",
            Procedural::Noise { .. } => "noise",
        }
    }

    /// The colour at (u, v) (finite).
    pub fn eval(&self, u: f64, v: f64) -> Vec3 {
        match *self {
            Procedural::Checker { scale, a, b } => {
                let k = floor(u * scale) + floor(v * scale);
                if odd(k) {
                    b
                } else {
                    a
                }
            }
            Procedural::Stripes { scale, a, b } => {
                if odd(floor(u * scale)) {
                    b
                } else {
                    a
                }
            }
            Procedural::Grid { scale, width, a, b } => {
                let near_line = |t: f64| {
                    let f = t - floor(t);
                    f < 0.5 * width || f > 1.0 - 0.5 * width
                };
                if near_line(u * scale) || near_line(v * scale) {
                    b
                } else {
                    a
                }
            }
            Procedural::Noise {
                scale,
                octaves,
                seed,
                a,
                b,
            } => {
                let (mut sum, mut amp, mut total, mut f) = (0.0, 1.0, 0.0, scale);
                for o in 0..octaves {
                    sum += amp * value_noise(u * f, v * f, seed.wrapping_add(o));
                    total += amp;
                    amp *= 0.5;
                    f *= 2.0;
                }
                let t = (sum / total) as f32;
                a + (b - a) * t
            }
        }
    }
}

/// Whether an integer-valued float is odd (exact for any magnitude).
#[inline(always)]
fn odd(k: f64) -> bool {
    k.rem_euclid(2.0) == 1.0
}

/// Value noise in [0, 1]: random values at the integer lattice points, blended with the
/// smoothstep of the fractions. Lattice indices beyond i64 saturate (finite, no overflow).
fn value_noise(x: f64, y: f64, seed: u32) -> f64 {
    let (x0, y0) = (floor(x), floor(y));
    let (fx, fy) = (smooth(x - x0), smooth(y - y0));
    let (i, j) = (x0 as i64, y0 as i64);
    let r = |di: i64, dj: i64| lattice(i.wrapping_add(di), j.wrapping_add(dj), seed);
    let top = r(0, 0) + (r(1, 0) - r(0, 0)) * fx;
    let bottom = r(0, 1) + (r(1, 1) - r(0, 1)) * fx;
    top + (bottom - top) * fy
}

#[inline(always)]
fn smooth(t: f64) -> f64 {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    t * t * (3.0 - 2.0 * t)
}

/// A random value in [0, 1) for lattice point (i, j) (a 64-bit mix, SplitMix64's finaliser).
fn lattice(i: i64, j: i64, seed: u32) -> f64 {
    let mut z = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (j as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ (seed as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: Vec3 = Vec3::ONE;
    const K: Vec3 = Vec3::ZERO;

    #[test]
    fn checker_stripes_and_grid_cells() {
        let c = Procedural::Checker {
            scale: 4.0,
            a: W,
            b: K,
        };
        assert_eq!(c.eval(0.1, 0.1), W);
        assert_eq!(c.eval(0.3, 0.1), K);
        assert_eq!(c.eval(0.3, 0.3), W);
        assert_eq!(c.eval(-0.1, 0.1), K);
        let s = Procedural::Stripes {
            scale: 2.0,
            a: W,
            b: K,
        };
        assert_eq!(s.eval(0.2, 0.9), W);
        assert_eq!(s.eval(0.7, 0.1), K);
        let g = Procedural::Grid {
            scale: 2.0,
            width: 0.2,
            a: W,
            b: K,
        };
        assert_eq!(g.eval(0.25, 0.25), W); // a cell's centre
        assert_eq!(g.eval(0.51, 0.25), K); // on the line at u = 0.5
        assert_eq!(g.eval(0.25, 0.97), K); // on the line at v = 1
    }

    #[test]
    fn noise_is_in_range_continuous_and_seeded() {
        let n = |seed| Procedural::Noise {
            scale: 5.0,
            octaves: 4,
            seed,
            a: K,
            b: W,
        };
        let mut prev = n(0).eval(0.0, 0.3).x;
        for k in 1..2000 {
            let c = n(0).eval(k as f64 * 1e-4, 0.3).x;
            assert!((0.0..=1.0).contains(&c));
            assert!((c - prev).abs() < 0.05, "jump at {k}");
            prev = c;
        }
        assert_ne!(n(0).eval(0.37, 0.41), n(1).eval(0.37, 0.41));
    }

    #[test]
    fn huge_coordinates_are_finite() {
        for p in [
            Procedural::Checker {
                scale: 3.0,
                a: W,
                b: K,
            },
            Procedural::Grid {
                scale: 3.0,
                width: 0.1,
                a: W,
                b: K,
            },
            Procedural::Noise {
                scale: 3.0,
                octaves: 16,
                seed: 2,
                a: K,
                b: W,
            },
        ] {
            for (u, v) in [(1e30, -1e30), (f64::MAX, 0.5), (-f64::MAX, -f64::MAX)] {
                assert!(p.eval(u, v).is_finite(), "{p:?} {u} {v}");
            }
        }
    }

    #[test]
    fn bad_parameters_are_named() {
        let bad = Procedural::Grid {
            scale: 1.0,
            width: 1.5,
            a: W,
            b: K,
        };
        assert!(bad.validated().unwrap_err().to_string().contains("width"));
        let bad = Procedural::Checker {
            scale: f64::NAN,
            a: W,
            b: K,
        };
        assert!(bad.validated().unwrap_err().to_string().contains("scale"));
        let bad = Procedural::Noise {
            scale: 1.0,
            octaves: 0,
            seed: 0,
            a: W,
            b: K,
        };
        assert!(bad.validated().unwrap_err().to_string().contains("octaves"));
    }
}
