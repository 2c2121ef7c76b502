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

    /// The texel index in `0..size` that integer coordinate `i` reads.
    #[inline(always)]
    pub fn index(self, i: f64, size: usize) -> usize {
        let s = size as f64;
        // Inside the image every mode reads texel i.
        if i >= 0.0 && i < s {
            return i as usize;
        }
        // Integer remainders where i fits an i64 (all but absurd coordinates): the f64
        // `rem_euclid` below is a software `fmod`, a tenth of a repeating floor's frame.
        if i.abs() < 9.2e18 {
            let (i, n) = (i as i64, size as i64);
            let k = match self {
                Wrap::Repeat => i.rem_euclid(n),
                Wrap::Clamp => i.clamp(0, n - 1),
                Wrap::Mirror => {
                    let a = i.rem_euclid(2 * n) - n;
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
    fn huge_coordinates_stay_in_range() {
        for w in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
            for i in [1e30, -1e30, f64::MAX, -f64::MAX, 2f64.powi(60) + 1.0] {
                assert!(w.index(i.floor(), 7) < 7, "{w:?} {i}");
            }
        }
    }
}
