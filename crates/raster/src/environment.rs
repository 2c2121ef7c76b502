//! The environment: an image of the light arriving from every direction, read by
//! reflections and refractions and, optionally, shown as the background. Two layouts:
//!
//! - **Equirectangular** (latitude–longitude): a unit direction `d` (after the
//!   environment's rotation) maps to `u = 0.5 + atan2(d.x, −d.z)/(2π)`, `v = acos(d.y)/π`;
//!   the image is read at column `u·W` and row `v·H` (texel centres at half-integers), so
//!   row 0 looks straight up (+y) and the centre column looks along −z. Sampling is
//!   bilinear, wrapping in u and clamped in v. u and v are computed in f32, the polar
//!   angle as `atan2(√(x² + z²), y)` ([`Environment::uv`]: within 3·10⁻⁷ of the exact
//!   values).
//! - **Cube** (six square faces, in the order +X, −X, +Y, −Y, +Z, −Z): the OpenGL cube-map
//!   convention (OpenGL 4.6 §8.13, table 8.19). The face is the direction's major axis; its
//!   coordinates `(sc, tc, ma)` are `(−z, −y, x)` on +X, `(z, −y, x)` on −X, `(x, z, y)` on
//!   +Y, `(x, −z, y)` on −Y, `(x, −y, z)` on +Z, `(−x, −y, z)` on −Z, and
//!   `s = (sc/|ma| + 1)/2`, `t = (tc/|ma| + 1)/2` are read at column `s·N`, row `t·N` of the
//!   face (row 0 its first row: face images load as files store them). Sampling is
//!   bilinear and seamless: a tap beyond a face's border reads the neighbouring face's
//!   texel in that direction (as `GL_TEXTURE_CUBE_MAP_SEAMLESS`), so no seam shows.

use std::f32::consts::{FRAC_1_PI, TAU};
use std::sync::Arc;

use glam::{DVec3, Vec3};

use crate::error::{RasterError, Result};
use crate::lighting::{lane, set_lane, Lanes, LANES};
use crate::trig;

/// Largest environment side in texels.
pub const MAX_ENVIRONMENT_SIZE: usize = 16384;

/// `1/(2π)`: the turn of an angle as a product.
const INV_TAU: f32 = 1.0 / TAU;

/// Largest texel value (the lighting's float32 headroom, as for textures).
const MAX_TEXEL: f32 = 1e30;

/// Whole number `v` clamped to `[lo, hi]` (NaN to `lo`) as an `i32`. `as i32` saturates and
/// maps NaN to 0, which LLVM compiles to a scalar conversion per lane (a twentieth of a
/// glass frame's instructions); this vectorises. Within the range the value is the same.
/// The bounds' only other effect is on a NaN coordinate, whose blend is NaN whichever
/// texels it reads (its weights are).
#[inline(always)]
fn whole(v: f32, lo: f32, hi: f32) -> i32 {
    // Not `clamp`, which keeps a NaN (and the unchecked conversion of NaN is undefined).
    #[allow(clippy::manual_clamp)]
    let v = v.max(lo).min(hi);
    // SAFETY: `max` and `min` return the non-NaN operand, so `v` is finite and within the
    // callers' bounds (at most 2·16384 in magnitude), inside the `i32` range.
    unsafe { v.to_int_unchecked::<i32>() }
}

/// How an environment's texels cover the directions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// One latitude–longitude image, twice as wide as high.
    Equirectangular,
    /// Six square faces +X, −X, +Y, −Y, +Z, −Z (the OpenGL cube-map convention).
    Cube,
}

/// An environment image (equirectangular or six cube faces) with a rotation about +y and
/// an intensity.
#[derive(Debug, Clone, PartialEq)]
pub struct Environment {
    /// Linear RGB texels, row-major from the top row (+y); a cube's six faces one after
    /// the other.
    texels: Arc<[Vec3]>,
    layout: Layout,
    /// Of the image, or of one cube face.
    width: usize,
    height: usize,
    /// Degrees about +y (right-handed: positive turns what was seen along −z toward −x).
    rotation: f32,
    intensity: f32,
    /// cos and sin of the rotation, applied as `R_y(−rotation)` to a looked-up direction:
    /// in f64 for the cube's look-up, rounded to f32 for the equirectangular one's.
    cos_sin: (f64, f64),
    cos_sin_f32: (f32, f32),
}

impl Environment {
    /// An environment from `height × width` linear RGB texels (`data`: row-major from the
    /// top, 3 floats a texel). `width` must be `2·height`; every texel finite and in
    /// [0, 1e30]; `rotation` (degrees) finite; `intensity` finite and ≥ 0.
    pub fn new(
        data: &[f32],
        height: usize,
        width: usize,
        rotation: f32,
        intensity: f32,
    ) -> Result<Self> {
        if height == 0 || width == 0 {
            return Err(RasterError::invalid_field(
                "array",
                format!("an environment image must not be empty, got {height}x{width}"),
            ));
        }
        if width != 2 * height {
            return Err(RasterError::invalid_field(
                "array",
                format!(
                    "an equirectangular environment must be twice as wide as it is high \
                     ((H, 2H, 3)), got height {height} and width {width}"
                ),
            ));
        }
        if width > MAX_ENVIRONMENT_SIZE {
            return Err(RasterError::invalid_field(
                "array",
                format!("environment width {width} is above the limit of {MAX_ENVIRONMENT_SIZE}"),
            ));
        }
        if data.len() != height * width * 3 {
            return Err(RasterError::invalid_field(
                "array",
                format!(
                    "environment data holds {} values, expected {height}x{width}x3",
                    data.len()
                ),
            ));
        }
        if let Some(k) = data
            .iter()
            .position(|v| !v.is_finite() || *v < 0.0 || *v > MAX_TEXEL)
        {
            return Err(RasterError::invalid_field(
                "array",
                format!(
                    "environment array[{}, {}, {}] = {} must be finite and in [0, {MAX_TEXEL:e}]",
                    k / (width * 3),
                    (k / 3) % width,
                    k % 3,
                    data[k]
                ),
            ));
        }
        Self::build(
            data,
            Layout::Equirectangular,
            (height, width),
            rotation,
            intensity,
        )
    }

    /// An environment from six square cube faces of `size × size` linear RGB texels, in the
    /// order +X, −X, +Y, −Y, +Z, −Z (`data`: each face row-major from its first row, 3
    /// floats a texel, the faces one after the other), with the OpenGL cube-map
    /// orientation (see the module documentation). Texels, `rotation` and `intensity` as
    /// for [`Environment::new`].
    pub fn cube(data: &[f32], size: usize, rotation: f32, intensity: f32) -> Result<Self> {
        if size == 0 {
            return Err(RasterError::invalid_field(
                "faces",
                "cube faces must not be empty",
            ));
        }
        if size > MAX_ENVIRONMENT_SIZE {
            return Err(RasterError::invalid_field(
                "faces",
                format!("cube face size {size} is above the limit of {MAX_ENVIRONMENT_SIZE}"),
            ));
        }
        if data.len() != 6 * size * size * 3 {
            return Err(RasterError::invalid_field(
                "faces",
                format!(
                    "cube face data holds {} values, expected 6x{size}x{size}x3",
                    data.len()
                ),
            ));
        }
        if let Some(k) = data
            .iter()
            .position(|v| !v.is_finite() || *v < 0.0 || *v > MAX_TEXEL)
        {
            let per_face = size * size * 3;
            return Err(RasterError::invalid_field(
                "faces",
                format!(
                    "cube face {} ({})[{}, {}, {}] = {} must be finite and in [0, {MAX_TEXEL:e}]",
                    k / per_face,
                    FACE_NAMES[k / per_face],
                    (k % per_face) / (size * 3),
                    (k / 3) % size,
                    k % 3,
                    data[k]
                ),
            ));
        }
        Self::build(data, Layout::Cube, (size, size), rotation, intensity)
    }

    /// Checks the rotation and intensity and stores the (checked) texels.
    fn build(
        data: &[f32],
        layout: Layout,
        (height, width): (usize, usize),
        rotation: f32,
        intensity: f32,
    ) -> Result<Self> {
        if !rotation.is_finite() {
            return Err(RasterError::invalid_field(
                "rotation",
                format!("environment rotation must be finite (degrees), got {rotation}"),
            ));
        }
        if !intensity.is_finite() || intensity < 0.0 {
            return Err(RasterError::invalid_field(
                "intensity",
                format!("environment intensity must be finite and >= 0, got {intensity}"),
            ));
        }
        let texels: Arc<[Vec3]> = data
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        let r = (rotation as f64).to_radians();
        Ok(Environment {
            texels,
            layout,
            width,
            height,
            rotation,
            intensity,
            cos_sin: (r.cos(), r.sin()),
            cos_sin_f32: (r.cos() as f32, r.sin() as f32),
        })
    }

    /// The layout of the texels.
    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// Height in texels (equirectangular: the width is twice it; cube: one face's side).
    pub fn height(&self) -> usize {
        self.height
    }

    /// Width in texels (cube: one face's side).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rotation about +y in degrees.
    pub fn rotation(&self) -> f32 {
        self.rotation
    }

    /// The factor every looked-up colour is multiplied by.
    pub fn intensity(&self) -> f32 {
        self.intensity
    }

    /// The texels, row-major from the top, linear RGB (a cube: its six faces in order).
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// Largest looked-up value (intensity × largest texel).
    pub fn max_value(&self) -> f64 {
        let m = self
            .texels
            .iter()
            .map(|t| t.max_element())
            .fold(0.0, f32::max);
        m as f64 * self.intensity as f64
    }

    /// The unit direction of the unrotated image that `d` (any length; zero or non-finite
    /// gives −z) looks along: `R_y(−θ)·d`. The cube's look-up; the equirectangular one
    /// takes [`Environment::uv_xyz`].
    fn unrotated(&self, d: Vec3) -> DVec3 {
        let (x, y, z) = (d.x as f64, d.y as f64, d.z as f64);
        let len = (x * x + y * y + z * z).sqrt();
        let (x, y, z) = if len > 0.0 && len.is_finite() {
            (x / len, y / len, z / len)
        } else {
            (0.0, 0.0, -1.0)
        };
        let (c, s) = self.cos_sin;
        DVec3::new(c * x - s * z, y, s * x + c * z)
    }

    /// The equirectangular (u, v) of a direction (any length; zero, non-finite, or with no
    /// component of magnitude at least `f32::MIN_POSITIVE`, gives the centre column at the
    /// horizon), after the rotation.
    ///
    /// In f32, eight lanes to an AVX register: `u = 0.5 + atan2(x, −z)/(2π)` and
    /// `v = atan2(√(x² + z²), y)/π` (the polar angle as an `atan2`, well conditioned at
    /// the poles where `acos(y)` of a rounded `y` is not), from [`trig::atan2_f32`]. No
    /// normalisation is needed: the direction is only scaled by its largest component, so
    /// that the squares cannot overflow. u and v are within 3·10⁻⁷ of the exact angles'
    /// (tested): under 1/200 of a texel at the largest width, 16384, with the texel
    /// position's own rounding.
    pub fn uv(&self, d: Vec3) -> (f32, f32) {
        self.uv_xyz(d.x, d.y, d.z)
    }

    /// [`Environment::uv`] of (x, y, z) as plain arithmetic and selects, so that it
    /// vectorises over lanes.
    #[inline(always)]
    fn uv_xyz(&self, x: f32, y: f32, z: f32) -> (f32, f32) {
        // A compare and select (not f32::max, whose NaN rule costs a blend): a NaN lane is
        // caught by the finiteness test.
        let larger = |a: f32, b: f32| if a > b { a } else { b };
        let m = larger(larger(x.abs(), y.abs()), z.abs());
        let finite = x * 0.0 + y * 0.0 + z * 0.0 == 0.0;
        let ok = finite && m >= f32::MIN_POSITIVE;
        let inv = 1.0 / if ok { m } else { 1.0 };
        let (x, y, z) = if ok {
            (x * inv, y * inv, z * inv)
        } else {
            (0.0, 0.0, -1.0)
        };
        let (c, s) = self.cos_sin_f32;
        let (x, z) = (c * x - s * z, s * x + c * z);
        let u = 0.5 + trig::atan2_f32(x, -z) * INV_TAU;
        let v = trig::atan2_f32((x * x + z * z).sqrt(), y) * FRAC_1_PI;
        (u, v)
    }

    /// The colour seen along direction `d` (bilinear: equirectangular wrapping in u and
    /// clamped in v; cube seamless across faces), times the intensity.
    pub fn sample(&self, d: Vec3) -> Vec3 {
        if self.layout == Layout::Cube {
            return self.sample_cube(self.unrotated(d)) * self.intensity;
        }
        let (u, v) = self.uv(d);
        self.bilinear(u, v)
    }

    /// [`Environment::sample`] along the directions `d` (channel-major) of lanes `..n`,
    /// into `out`: the same values, bit for bit, with the angles, the texel coordinates and
    /// the blend computed over all lanes at once (they vectorise; the texel reads stay a
    /// lane at a time).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    pub(crate) fn sample_lanes(&self, d: &[Lanes; 3], n: usize, out: &mut [Lanes; 3]) {
        let n = n.min(LANES);
        if self.layout == Layout::Cube {
            for k in 0..n {
                set_lane(out, k, self.sample(lane(d, k)));
            }
            return;
        }
        let (mut u, mut v) = ([0.0f32; LANES], [0.0f32; LANES]);
        for k in 0..LANES {
            (u[k], v[k]) = self.uv_xyz(d[0][k], d[1][k], d[2][k]);
        }
        self.bilinear_lanes(&u, &v, n, out);
    }

    /// [`Environment::bilinear`] of lanes `..n` (`u` in [0, 1]), into `out`: the texel
    /// coordinates, weights and blend over all lanes, the texel reads a lane at a time; the
    /// same operations per lane, so the same bits.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane loops index several arrays; this form vectorises
    fn bilinear_lanes(&self, u: &[f32; LANES], v: &[f32; LANES], n: usize, out: &mut [Lanes; 3]) {
        let (mut fx, mut fy) = ([0.0f32; LANES], [0.0f32; LANES]);
        let mut at = [[0usize; LANES]; 4];
        for k in 0..LANES {
            let corners;
            (corners, fx[k], fy[k]) = self.corners(u[k], v[k]);
            for (a, c) in at.iter_mut().zip(corners) {
                a[k] = c;
            }
        }
        let mut t = [[[0.0f32; LANES]; 3]; 4];
        for (corner, at) in t.iter_mut().zip(&at) {
            for k in 0..n {
                debug_assert!(at[k] < self.texels.len());
                // SAFETY: `corners` gives indices of texels (rows clamped to the height,
                // columns wrapped and clamped to the width).
                set_lane(corner, k, unsafe { *self.texels.get_unchecked(at[k]) });
            }
        }
        let s = self.intensity;
        let mut blend = [[0.0f32; LANES]; 3];
        for c in 0..3 {
            for k in 0..LANES {
                let top = t[0][c][k] * (1.0 - fx[k]) + t[1][c][k] * fx[k];
                let bottom = t[2][c][k] * (1.0 - fx[k]) + t[3][c][k] * fx[k];
                blend[c][k] = (top * (1.0 - fy[k]) + bottom * fy[k]) * s;
            }
        }
        // Lanes past `n` are left as they were.
        for (o, b) in out.iter_mut().zip(&blend) {
            o[..n].copy_from_slice(&b[..n]);
        }
    }

    /// The column of whole-number `x` (in [−width, 2·width): one turn either way) wrapped
    /// into the image, `x.rem_euclid(width)` as compares: the lanes' form vectorises (in
    /// 32 bits: AVX2 has no 64-bit conversions from f64 nor 64-bit products).
    #[inline(always)]
    fn wrap(&self, x: i32) -> i32 {
        let w = self.width as i32;
        let c = if x < 0 {
            x + w
        } else if x >= w {
            x - w
        } else {
            x
        };
        c.clamp(0, w - 1)
    }

    /// The bilinear look-up of an equirectangular image at (u, v) (u in [0, 1]), times the
    /// intensity.
    #[inline(always)]
    fn bilinear(&self, u: f32, v: f32) -> Vec3 {
        let ([a, b, c, d], fx, fy) = self.corners(u, v);
        let t = &self.texels;
        let top = t[a] * (1.0 - fx) + t[b] * fx;
        let bottom = t[c] * (1.0 - fx) + t[d] * fx;
        (top * (1.0 - fy) + bottom * fy) * self.intensity
    }

    /// The texels around equirectangular (u, v) (u in [0, 1] up to rounding) and the
    /// blend's weights: the indices of the top-left, top-right, bottom-left and
    /// bottom-right texels (wrapping in u, clamped in v) and the fractions (fx, fy) toward
    /// the right and the bottom.
    #[inline(always)]
    fn corners(&self, u: f32, v: f32) -> ([usize; 4], f32, f32) {
        // Widths are at most 16384 = 2¹⁴: x is within 2⁻⁹ of a texel of u·w − 0.5.
        let (w, h) = (self.width as f32, self.height as f32);
        let x = u * w - 0.5;
        let y = (v * h - 0.5).clamp(0.0, h - 1.0);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        // x0 is a whole number in [−1, width] (u is in [0, 1] up to rounding): wrapped in
        // integers, the same columns as rem_euclid without its libm call. Sizes are at
        // most MAX_ENVIRONMENT_SIZE, so every index fits 32 bits.
        let (c0, c1) = {
            let x0 = whole(x0, -(w + 1.0), 2.0 * w);
            (self.wrap(x0), self.wrap(x0 + 1))
        };
        let r0 = whole(y0, 0.0, h - 1.0);
        let r1 = (r0 + 1).min(self.height as i32 - 1);
        let wd = self.width as i32;
        let at = |r: i32, c: i32| (r * wd + c) as usize;
        ([at(r0, c0), at(r0, c1), at(r1, c0), at(r1, c1)], fx, fy)
    }

    /// Bilinear lookup of the cube along the unit direction `d` (unrotated), seamless.
    fn sample_cube(&self, d: DVec3) -> Vec3 {
        let n = self.width;
        let nf = n as f64;
        let (face, s, t) = cube_face(d);
        let x = s * nf - 0.5;
        let y = t * nf - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let texel = |f: usize, i: usize, j: usize| self.texels[(f * n + j) * n + i];
        let tap = |i: f64, j: f64| -> Vec3 {
            if i >= 0.0 && j >= 0.0 && i < nf && j < nf {
                return texel(face, i as usize, j as usize);
            }
            // Beyond the border: the texel of the face the tap's direction falls on.
            let dir = face_direction(face, (i + 0.5) / nf, (j + 0.5) / nf);
            let (f, s, t) = cube_face(dir);
            let c = |v: f64| ((v * nf).floor().max(0.0) as usize).min(n - 1);
            texel(f, c(s), c(t))
        };
        let top = tap(x0, y0) * (1.0 - fx) + tap(x0 + 1.0, y0) * fx;
        let bottom = tap(x0, y0 + 1.0) * (1.0 - fx) + tap(x0 + 1.0, y0 + 1.0) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// The cube faces' names, in their order.
pub const FACE_NAMES: [&str; 6] = ["+x", "-x", "+y", "-y", "+z", "-z"];

/// The face a direction (non-zero) falls on and its (s, t) in [0, 1]: OpenGL 4.6 table
/// 8.19; ties between axes go to x, then y.
fn cube_face(d: DVec3) -> (usize, f64, f64) {
    let a = d.abs();
    let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
        if d.x > 0.0 {
            (0, -d.z, -d.y, a.x)
        } else {
            (1, d.z, -d.y, a.x)
        }
    } else if a.y >= a.z {
        if d.y > 0.0 {
            (2, d.x, d.z, a.y)
        } else {
            (3, d.x, -d.z, a.y)
        }
    } else if d.z > 0.0 {
        (4, d.x, -d.y, a.z)
    } else {
        (5, -d.x, -d.y, a.z)
    };
    (face, (sc / ma + 1.0) * 0.5, (tc / ma + 1.0) * 0.5)
}

/// The direction (not unit) through (s, t) of `face`: the inverse of [`cube_face`].
fn face_direction(face: usize, s: f64, t: f64) -> DVec3 {
    let (sc, tc) = (2.0 * s - 1.0, 2.0 * t - 1.0);
    match face {
        0 => DVec3::new(1.0, -tc, -sc),
        1 => DVec3::new(-1.0, -tc, sc),
        2 => DVec3::new(sc, 1.0, tc),
        3 => DVec3::new(sc, -1.0, -tc),
        4 => DVec3::new(sc, -tc, 1.0),
        _ => DVec3::new(-sc, -tc, -1.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(h: usize) -> Environment {
        // Texel (row, col) = (row, col, 1).
        let w = 2 * h;
        let data: Vec<f32> = (0..h * w)
            .flat_map(|k| [(k / w) as f32, (k % w) as f32, 1.0])
            .collect();
        Environment::new(&data, h, w, 0.0, 1.0).unwrap()
    }

    #[test]
    fn axes_map_to_the_documented_texels() {
        let e = env(8);
        // −z: u = 0.5, v = 0.5: column 8 (between texels 7 and 8), row 4 (between 3, 4).
        let c = e.sample(Vec3::NEG_Z);
        assert!((c.x - 3.5).abs() < 1e-5 && (c.y - 7.5).abs() < 1e-5, "{c}");
        assert_eq!(e.uv(Vec3::Y).1, 0.0);
        assert_eq!(e.uv(-Vec3::Y).1, 1.0);
        // +x: u = 0.75; −x: u = 0.25; +z: u = 1 (wraps to 0).
        assert_eq!(e.uv(Vec3::X).0, 0.75);
        assert_eq!(e.uv(-Vec3::X).0, 0.25);
        assert_eq!(e.uv(Vec3::Z).0, 1.0);
        assert_eq!(e.uv(Vec3::NEG_Z), (0.5, 0.5));
        // Straight up reads row 0 (clamped), whatever u.
        assert_eq!(e.sample(Vec3::Y).x, 0.0);
        assert_eq!(e.sample(-Vec3::Y).x, 7.0);
    }

    /// Directions for comparing paths: a spread over the sphere (a fixed LCG) and the ones
    /// where the look-up has edges (axes, poles, the seam, zero, NaN, infinity, tiny).
    fn directions() -> Vec<Vec3> {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        };
        let mut d: Vec<Vec3> = (0..4000)
            .map(|_| Vec3::new(next(), next(), next()))
            .collect();
        d.extend([
            Vec3::X,
            -Vec3::X,
            Vec3::Y,
            -Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(1e-7, 0.0, 1.0),
            Vec3::new(-1e-7, 0.0, 1.0),
            Vec3::new(0.0, 1.0, -0.0),
            Vec3::new(-0.0, -1.0, 0.0),
            Vec3::ZERO,
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::new(f32::INFINITY, 1.0, 0.0),
            Vec3::splat(1e-30),
            Vec3::splat(3e38),
        ]);
        d
    }

    #[test]
    fn lanes_look_up_what_one_direction_does_bit_for_bit() {
        let e = env(16);
        let data: Vec<f32> = e.texels().iter().flat_map(|t| t.to_array()).collect();
        let rotated = Environment::new(&data, 16, 32, 37.5, 1.5).unwrap();
        let cube_data: Vec<f32> = (0..6 * 4 * 4)
            .flat_map(|k| [k as f32, (k % 7) as f32, 0.5])
            .collect();
        let cube = Environment::cube(&cube_data, 4, -20.0, 1.0).unwrap();
        let dirs = directions();
        for e in [&e, &rotated, &cube] {
            for (c, chunk) in dirs.chunks(LANES).enumerate() {
                // Partial groups too: lanes past `n` are not written.
                let n = chunk.len() - (c % 3).min(chunk.len() - 1);
                let mut d = [[0.0; LANES]; 3];
                for (k, v) in chunk.iter().enumerate() {
                    set_lane(&mut d, k, *v);
                }
                let mut out = [[-1.0; LANES]; 3];
                e.sample_lanes(&d, n, &mut out);
                for (k, v) in chunk.iter().enumerate() {
                    let got = lane(&out, k);
                    if k < n {
                        let want = e.sample(*v);
                        assert_eq!(
                            got.to_array().map(f32::to_bits),
                            want.to_array().map(f32::to_bits),
                            "{v} in lane {k}"
                        );
                    } else {
                        assert_eq!(got, Vec3::splat(-1.0));
                    }
                }
            }
        }
    }

    /// The f32 angles against the exact ones (f64 libm of the f64-normalised direction,
    /// turned by the exact rotation): u (modulo a turn; any at the poles) and v within
    /// 3·10⁻⁷, over the sphere, near the poles, at the seam, at every scale.
    #[test]
    fn uv_is_within_its_bound_of_the_exact_angles() {
        let mut dirs: Vec<Vec3> = directions()
            .into_iter()
            .filter(|d| d.is_finite() && *d != Vec3::ZERO)
            .collect();
        for k in 0..=400 {
            // Within a degree of the poles, and across the seam behind (+z).
            let a = (k as f32 / 400.0 - 0.5) * 0.035;
            dirs.push(Vec3::new(a, 1.0, 0.3 * a));
            dirs.push(Vec3::new(-0.7 * a, -1.0, a));
            dirs.push(Vec3::new(a * 1e-3, 0.2, 1.0));
        }
        // Scaled down to 1e-30, keeping those whose largest component stays a normal f32
        // (the subnormal-only ones look along -z, as documented, not along themselves).
        let scaled: Vec<Vec3> = dirs
            .iter()
            .map(|d| *d * 1e-30)
            .filter(|d| d.abs().max_element() >= f32::MIN_POSITIVE)
            .collect();
        assert!(
            scaled.len() * 10 > dirs.len() * 9,
            "{} of {}",
            scaled.len(),
            dirs.len()
        );
        dirs.extend(scaled);
        let mut worst = (0.0f64, 0.0f64);
        for rotation in [0.0f32, 37.5, -123.0] {
            let e = Environment::new(&[0.5; 6], 1, 2, rotation, 1.0).unwrap();
            let (c, s) = {
                let r = (rotation as f64).to_radians();
                (r.cos(), r.sin())
            };
            for d in &dirs {
                let (x, y, z) = (d.x as f64, d.y as f64, d.z as f64);
                let (x, z) = (c * x - s * z, s * x + c * z);
                let len = (x * x + y * y + z * z).sqrt();
                let want_u = 0.5 + x.atan2(-z) / std::f64::consts::TAU;
                let want_v = (y / len).clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
                let (u, v) = e.uv(*d);
                // At the poles u is any column (signed zeros pick one): v alone counts.
                let du = if d.x == 0.0 && d.z == 0.0 {
                    0.0
                } else {
                    (u as f64 - want_u + 0.5).rem_euclid(1.0) - 0.5
                };
                let dv = v as f64 - want_v;
                // f64::max would drop a NaN silently.
                assert!(du.is_finite() && dv.is_finite(), "{d} {u} {v}");
                worst = (worst.0.max(du.abs()), worst.1.max(dv.abs()));
            }
        }
        assert!(worst.0 < 3e-7 && worst.1 < 3e-7, "{worst:?}");
    }

    #[test]
    fn wraps_in_u_and_rotates_about_y() {
        let e = env(4);
        // Just either side of +z (the seam) blend columns 7 and 0 alike.
        let a = e.sample(Vec3::new(1e-7, 0.0, 1.0));
        let b = e.sample(Vec3::new(-1e-7, 0.0, 1.0));
        assert!((a - b).abs().max_element() < 1e-3, "{a} {b}");
        assert!((a.y - 3.5).abs() < 1e-3, "{a}");
        let data: Vec<f32> = e.texels().iter().flat_map(|t| t.to_array()).collect();
        let r = Environment::new(&data, 4, 8, 90.0, 2.0).unwrap();
        // Turned 90° about +y: what was seen along −z is now seen along −x.
        let want = e.sample(Vec3::NEG_Z) * 2.0;
        assert!((r.sample(Vec3::NEG_X) - want).abs().max_element() < 1e-4);
    }

    #[test]
    fn cube_faces_follow_the_opengl_table_and_invert() {
        // Each axis looks at the centre of its own face.
        for (k, d) in [
            DVec3::X,
            DVec3::NEG_X,
            DVec3::Y,
            DVec3::NEG_Y,
            DVec3::Z,
            DVec3::NEG_Z,
        ]
        .into_iter()
        .enumerate()
        {
            assert_eq!(cube_face(d), (k, 0.5, 0.5));
        }
        // +X: s grows toward −z, t toward −y (first row up).
        let (f, s, t) = cube_face(DVec3::new(1.0, 0.5, -0.5));
        assert_eq!((f, s, t), (0, 0.75, 0.25));
        for face in 0..6 {
            for (s, t) in [(0.1, 0.2), (0.9, 0.4), (0.5, 0.99)] {
                let (f, s2, t2) = cube_face(face_direction(face, s, t));
                assert_eq!(f, face);
                assert!((s2 - s).abs() < 1e-12 && (t2 - t).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn cube_lookup_is_seamless_and_constant_faces_stay_constant() {
        // Face k filled with k: along an edge between two faces the lookup is the mean of
        // their values from either side.
        let n = 4;
        let data: Vec<f32> = (0..6)
            .flat_map(|k| std::iter::repeat(k as f32).take(n * n * 3))
            .collect();
        let e = Environment::cube(&data, n, 0.0, 1.0).unwrap();
        let a = e.sample(Vec3::new(1.0, 0.0, -1.0 + 1e-6)); // +X | −Z edge
        let b = e.sample(Vec3::new(1.0 - 1e-6, 0.0, -1.0));
        assert!((a - b).abs().max_element() < 1e-4, "{a} {b}");
        assert!((a.x - 2.5).abs() < 1e-4, "{a}");
        assert_eq!(e.sample(Vec3::new(0.1, 0.2, -1.0)).x, 5.0);
        let single = Environment::cube(&[0.25; 6 * 3], 1, 0.0, 2.0).unwrap();
        assert_eq!(single.sample(Vec3::new(0.3, -0.9, 0.2)), Vec3::splat(0.5));
    }

    #[test]
    fn rejects_bad_images() {
        let field = |r: Result<Environment>| match r {
            Err(RasterError::InvalidField { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        assert_eq!(field(Environment::new(&[], 0, 0, 0.0, 1.0)), "array");
        assert_eq!(field(Environment::new(&[0.0; 9], 1, 3, 0.0, 1.0)), "array");
        assert_eq!(field(Environment::new(&[0.0; 5], 1, 2, 0.0, 1.0)), "array");
        let mut d = [0.5f32; 6];
        d[4] = f32::NAN;
        assert_eq!(field(Environment::new(&d, 1, 2, 0.0, 1.0)), "array");
        d[4] = -1.0;
        assert_eq!(field(Environment::new(&d, 1, 2, 0.0, 1.0)), "array");
        assert_eq!(
            field(Environment::new(&[0.5; 6], 1, 2, f32::NAN, 1.0)),
            "rotation"
        );
        assert_eq!(
            field(Environment::new(&[0.5; 6], 1, 2, 0.0, -1.0)),
            "intensity"
        );
        assert!(Environment::new(&[0.5; 6], 1, 2, 0.0, 0.0).is_ok());
        assert_eq!(field(Environment::cube(&[], 0, 0.0, 1.0)), "faces");
        assert_eq!(
            field(Environment::cube(&[0.5; 5 * 3], 1, 0.0, 1.0)),
            "faces"
        );
        let mut d = [0.5f32; 6 * 3];
        d[13] = f32::INFINITY;
        assert_eq!(field(Environment::cube(&d, 1, 0.0, 1.0)), "faces");
        assert_eq!(
            field(Environment::cube(&[0.5; 6 * 3], 1, 0.0, f32::NAN)),
            "intensity"
        );
    }
}
