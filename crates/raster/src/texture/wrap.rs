//! Wrap modes: where an integer texel coordinate outside the image reads, as OpenGL 4.6
//! Table 8.20 defines them. Coordinates are integer-valued f64 (the floor of a scaled
//! texture coordinate), so 1e30 wraps in one exact `rem_euclid`, without overflow or a loop.

/// How texture coordinates outside [0, 1] read the image, per axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wrap {
    /// `GL_REPEAT`: the image tiles the plane.
    Repeat,
    /// `GL_CLAMP_TO_EDGE`: the edge texels extend outward.
    Clamp,
    /// `GL_MIRRORED_REPEAT`: every other copy is flipped.
    Mirror,
}

impl Wrap {
    /// The mode named `name` ("repeat", "clamp", "mirror").
    pub fn from_name(name: &str) -> Option<Wrap> {
        match name {
            "repeat" => Some(Wrap::Repeat),
            "clamp" => Some(Wrap::Clamp),
            "mirror" => Some(Wrap::Mirror),
            _ => None,
        }
    }

    /// The mode's name.
    pub fn name(self) -> &'static str {
        match self {
            Wrap::Repeat => "repeat",
            Wrap::Clamp => "clamp",
            Wrap::Mirror => "mirror",
        }
    }

    /// The texel indices that integer coordinates `i` and `i + 1` read (a bilinear
    /// footprint), as two [`Wrap::index`] calls would give them: with `i + 1` still inside
    /// the image, or any `i` under `Repeat`, the second follows from the first.
    #[inline(always)]
    pub fn pair(self, i: f64, size: usize) -> (usize, usize) {
        let k = self.index(i, size);
        if i >= 0.0 && i + 1.0 < size as f64 {
            return (k, k + 1);
        }
        if self == Wrap::Repeat && i.abs() < 4_503_599_627_370_496.0 {
            // (i + 1) mod size = (i mod size) + 1, or 0 past the last column (below 2⁵²,
            // where i + 1 is exact).
            return (k, if k + 1 == size { 0 } else { k + 1 });
        }
        (k, self.index(i + 1.0, size))
    }

    /// The texel index in `0..size` that integer coordinate `i` reads.
    #[inline(always)]
    pub fn index(self, i: f64, size: usize) -> usize {
        let s = size as f64;
        // Inside the image every mode reads texel i.
        if i >= 0.0 && i < s {
            // SAFETY: i is an integer in [0, size), so it converts exactly (the checked
            // `as` would add NaN and overflow handling to every texel read).
            return unsafe { i.to_int_unchecked::<usize>() };
        }
        // Integer remainders where i fits an i64 (all but absurd coordinates): the f64
        // `rem_euclid` below is a software `fmod`, a tenth of a repeating floor's frame.
        if i.abs() < 9.2e18 {
            // SAFETY: |i| < 9.2e18 < 2⁶³ and i is not NaN (NaN fails the comparison).
            let (i, n) = (unsafe { i.to_int_unchecked::<i64>() }, size as i64);
            // A power-of-two size (most textures) takes a mask, which is the Euclidean
            // remainder in two's complement; others an integer division.
            let rem = |i: i64, m: i64| {
                if m & (m - 1) == 0 {
                    i & (m - 1)
                } else {
                    i.rem_euclid(m)
                }
            };
            let k = match self {
                Wrap::Repeat => rem(i, n),
                Wrap::Clamp => i.clamp(0, n - 1),
                Wrap::Mirror => {
                    let a = rem(i, 2 * n) - n;
                    (n - 1) - if a >= 0 { a } else { -(1 + a) }
                }
            };
            return k as usize;
        }
        let k = match self {
            Wrap::Repeat => i.rem_euclid(s),
            Wrap::Clamp => i.clamp(0.0, s - 1.0),
            Wrap::Mirror => {
                // (size − 1) − mirror((i mod 2·size) − size), mirror(a) = a ≥ 0 ? a : −(1 + a)
                let a = i.rem_euclid(2.0 * s) - s;
                let m = if a >= 0.0 { a } else { -(1.0 + a) };
                (s - 1.0) - m
            }
        };
        // NaN never reaches here (the sampler zeroes it); the min guards rounding at the top.
        (k as usize).min(size - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_8_20_on_a_size_3_axis() {
        let got = |w: Wrap| (-7..8).map(|i| w.index(i as f64, 3)).collect::<Vec<_>>();
        assert_eq!(
            got(Wrap::Repeat),
            [2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1]
        );
        assert_eq!(
            got(Wrap::Clamp),
            [0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2]
        );
        // Mirror: 0 1 2 | 2 1 0 | 0 1 2 ..., and to the left of 0 the flipped copy: -1 -> 0.
        assert_eq!(
            got(Wrap::Mirror),
            [0, 0, 1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1]
        );
    }

    #[test]
    fn pairs_are_two_indices() {
        for w in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
            for size in [1, 2, 3, 8] {
                for i in -40..40 {
                    let i = i as f64;
                    let want = (w.index(i, size), w.index(i + 1.0, size));
                    assert_eq!(w.pair(i, size), want, "{w:?} {size} {i}");
                }
            }
            for i in [1e30, -1e30, 9.3e18, -9.3e18, 2f64.powi(60)] {
                assert_eq!(
                    w.pair(i, 7),
                    (w.index(i, 7), w.index(i + 1.0, 7)),
                    "{w:?} {i}"
                );
            }
        }
    }

    #[test]
    fn huge_coordinates_stay_in_range() {
        for w in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
            for i in [1e30, -1e30, f64::MAX, -f64::MAX, 2f64.powi(60) + 1.0] {
                assert!(w.index(i.floor(), 7) < 7, "{w:?} {i}");
            }
        }
    }
}
