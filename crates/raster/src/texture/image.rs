//! Image storage: linear f32 RGB texels in OpenGL's row order (row 0 at v = 0, the bottom of
//! the picture), and the mip pyramid made by a box filter of each level above.

use crate::error::{RasterError, Result};

/// Largest width or height of a texture image, in texels.
pub const MAX_TEXTURE_SIZE: usize = 16384;

/// Largest number of texels of a texture image (level 0): 2^26, 768 MiB of f32 RGB.
pub const MAX_TEXELS: usize = 1 << 26;

/// Largest texel value (linear): texture colours weigh reflectances, so with the lighting
/// bound (`MAX_RADIANCE`) this keeps every shaded value finite in f32.
pub const MAX_TEXEL_VALUE: f32 = 1e6;

/// One level of the pyramid: `width × height` RGB texels, row 0 at the bottom (v = 0).
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// `width × height` texels, then one zero texel of padding (see [`Level::new`]).
    texels: Vec<[f32; 3]>,
}

impl Level {
    /// A level of `width × height` texels (`texels`, rows from the bottom), followed by one
    /// zero texel of padding: the lane fetch reads four floats from a texel's first channel
    /// (one 16-byte load a texel), which for the last texel is its three and the padding's
    /// first.
    fn new(width: usize, height: usize, mut texels: Vec<[f32; 3]>) -> Self {
        debug_assert_eq!(texels.len(), width * height);
        texels.push([0.0; 3]);
        Level {
            width,
            height,
            texels,
        }
    }

    /// Texel at column `i`, row `j` counted from the bottom (OpenGL's (i, j)).
    #[inline(always)]
    pub fn texel(&self, i: usize, j: usize) -> [f32; 3] {
        self.texels[j * self.width + i]
    }

    /// Number of texels (`width × height`).
    #[inline(always)]
    pub(crate) fn texel_count(&self) -> usize {
        self.width * self.height
    }

    /// The texels' channels in one slice (texel k's channel c at `3k + c`), then the
    /// padding texel's three zeros.
    #[inline(always)]
    pub(crate) fn channels(&self) -> &[f32] {
        self.texels.as_flattened()
    }
}

/// A texture image: level 0 (the image) and its mip levels down to 1 × 1.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    levels: Vec<Level>,
}

/// sRGB electro-optical transfer (IEC 61966-2-1), one channel in [0, 1].
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

impl Image {
    /// An image from `width × height` texels given top row first (as image files, Pillow
    /// and NumPy arrays store them), `channels` (3 or 4; alpha is dropped) values per texel.
    /// `srgb` decodes sRGB-encoded values (in [0, 1]) to linear ones. Every value must be
    /// finite; sizes are limited by [`MAX_TEXTURE_SIZE`] and [`MAX_TEXELS`].
    pub fn from_top_rows(
        width: usize,
        height: usize,
        channels: usize,
        data: &[f32],
        srgb: bool,
    ) -> Result<Self> {
        check_size(width, height)?;
        if channels != 3 && channels != 4 {
            return Err(RasterError::invalid(format!(
                "a texture has 3 (RGB) or 4 (RGBA) channels, got {channels}"
            )));
        }
        if data.len() != width * height * channels {
            return Err(RasterError::invalid(format!(
                "texture data has {} values, expected {width} x {height} x {channels}",
                data.len()
            )));
        }
        if let Some(k) = data.iter().position(|v| !v.is_finite()) {
            let (texel, ch) = (k / channels, k % channels);
            return Err(RasterError::invalid(format!(
                "texture value at row {}, column {}, channel {ch} is {} (must be finite)",
                texel / width,
                texel % width,
                data[k]
            )));
        }
        // Colour channels only: alpha is dropped, whatever its value.
        if let Some(k) = (0..data.len())
            .filter(|k| k % channels < 3)
            .find(|&k| !(0.0..=MAX_TEXEL_VALUE).contains(&data[k]))
        {
            let (texel, ch) = (k / channels, k % channels);
            return Err(RasterError::invalid(format!(
                "texture value at row {}, column {}, channel {ch} is {}; texture colours must \
                 be in [0, {MAX_TEXEL_VALUE:e}]",
                texel / width,
                texel % width,
                data[k]
            )));
        }
        let mut texels = Vec::new();
        texels
            .try_reserve_exact(width * height + 1)
            .map_err(|_| RasterError::OutOfMemory {
                bytes: width * height * 12,
            })?;
        // OpenGL's row j is the picture's row height − 1 − j.
        for j in 0..height {
            let row = &data[(height - 1 - j) * width * channels..][..width * channels];
            for px in row.chunks_exact(channels) {
                let mut t = [px[0], px[1], px[2]];
                if srgb {
                    t = t.map(srgb_to_linear);
                }
                texels.push(t);
            }
        }
        Ok(Image::from_level(Level::new(width, height, texels)))
    }

    /// The pyramid of `base`: each level half the size of the one above (rounded down, at
    /// least 1), each texel the mean of the 2 × 2 (or 2 × 1 where an axis is already 1)
    /// texels above it; an odd last row or column of a level is not read by the next.
    fn from_level(base: Level) -> Self {
        let mut levels = vec![base];
        loop {
            let up = levels.last().expect("level 0");
            if up.width == 1 && up.height == 1 {
                break;
            }
            levels.push(downsample(up));
        }
        Image { levels }
    }

    /// The levels, 0 (the image) first.
    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// Width of level 0.
    pub fn width(&self) -> usize {
        self.levels[0].width
    }

    /// Height of level 0.
    pub fn height(&self) -> usize {
        self.levels[0].height
    }

    /// Level 0 as linear RGB, top row first (as it was given, after sRGB decoding).
    pub fn top_rows(&self) -> Vec<f32> {
        let l = &self.levels[0];
        let mut out = Vec::with_capacity(l.width * l.height * 3);
        for j in (0..l.height).rev() {
            for i in 0..l.width {
                out.extend_from_slice(&l.texel(i, j));
            }
        }
        out
    }
}

fn check_size(width: usize, height: usize) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(RasterError::invalid(format!(
            "a texture must have at least one texel, got {width} x {height}"
        )));
    }
    if width > MAX_TEXTURE_SIZE || height > MAX_TEXTURE_SIZE {
        return Err(RasterError::invalid(format!(
            "texture is {width} x {height}; at most {MAX_TEXTURE_SIZE} texels per side are \
             supported"
        )));
    }
    if width * height > MAX_TEXELS {
        return Err(RasterError::invalid(format!(
            "texture is {width} x {height} = {} texels; at most {MAX_TEXELS} are supported",
            width * height
        )));
    }
    Ok(())
}

/// The next mip level of `up` by the box filter.
fn downsample(up: &Level) -> Level {
    let (w, h) = ((up.width / 2).max(1), (up.height / 2).max(1));
    let (sx, sy) = (
        if up.width > 1 { 2 } else { 1 },
        if up.height > 1 { 2 } else { 1 },
    );
    let scale = 1.0 / (sx * sy) as f32;
    let mut texels = Vec::with_capacity(w * h + 1);
    for j in 0..h {
        for i in 0..w {
            let mut sum = [0.0f32; 3];
            for b in 0..sy {
                for a in 0..sx {
                    let t = up.texel(i * sx + a, j * sy + b);
                    for c in 0..3 {
                        sum[c] += t[c];
                    }
                }
            }
            texels.push(sum.map(|s| s * scale));
        }
    }
    Level::new(w, h, texels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_stored_bottom_up_and_mips_are_box_means() {
        // 2 x 2, top row first: red, green / blue, white.
        let data = [
            1.0, 0.0, 0.0, 0.0, 1.0, 0.0, //
            0.0, 0.0, 1.0, 1.0, 1.0, 1.0,
        ];
        let img = Image::from_top_rows(2, 2, 3, &data, false).unwrap();
        let l0 = &img.levels()[0];
        assert_eq!(l0.texel(0, 0), [0.0, 0.0, 1.0]); // bottom-left: blue
        assert_eq!(l0.texel(1, 1), [0.0, 1.0, 0.0]); // top-right: green
        assert_eq!(img.levels().len(), 2);
        assert_eq!(img.levels()[1].texel(0, 0), [0.5, 0.5, 0.5]);
        assert_eq!(img.top_rows(), data.to_vec());
    }

    #[test]
    fn odd_sizes_floor_and_thin_axes_average_pairs() {
        let data: Vec<f32> = (0..5 * 3).map(|k| (k / 3) as f32).collect(); // 5 x 1 ramp
        let img = Image::from_top_rows(5, 1, 3, &data, false).unwrap();
        let sizes: Vec<_> = img.levels().iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(5, 1), (2, 1), (1, 1)]);
        assert_eq!(img.levels()[1].texel(0, 0)[0], 0.5);
        assert_eq!(img.levels()[1].texel(1, 0)[0], 2.5);
        assert_eq!(img.levels()[2].texel(0, 0)[0], 1.5);
    }

    #[test]
    fn bad_inputs_are_named() {
        let e = |r: Result<Image>| r.unwrap_err().to_string();
        assert!(e(Image::from_top_rows(0, 3, 3, &[], false)).contains("at least one texel"));
        assert!(e(Image::from_top_rows(1, 1, 2, &[0.0; 2], false)).contains("channels"));
        assert!(
            e(Image::from_top_rows(1, 1, 3, &[0.0, f32::NAN, 0.0], false))
                .contains("channel 1 is NaN")
        );
        assert!(
            e(Image::from_top_rows(MAX_TEXTURE_SIZE + 1, 1, 3, &[], false)).contains("per side")
        );
    }

    #[test]
    fn srgb_decoding_matches_the_standard() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.214_041_14).abs() < 1e-6);
    }
}
