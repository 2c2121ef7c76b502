//! PNG files of rendered images, through the `png` crate (the encoder the `image` crate uses):
//! 8- or 16-bit grey, grey + alpha, RGB and RGBA, with text chunks, at a chosen compression.
//!
//! Written here rather than in Python because zlib at level 6 over unfiltered rows took
//! longer than the render it saved (1080p: ~70 ms against a 20 ms render); the `png` crate's
//! adaptive filters with its fdeflate fast path write the same image in a few milliseconds.

use std::str::FromStr;

use crate::error::{RasterError, Result};

/// How hard [`encode_png`] compresses: from stored (no compression) to high.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PngCompression {
    /// Stored blocks, no filter: the largest file, written fastest.
    None,
    /// fdeflate's ultra-fast mode with adaptive filters.
    Fastest,
    /// fdeflate with adaptive filters (the default: smaller than zlib level 6 on renders,
    /// at a fraction of its time).
    #[default]
    Fast,
    /// zlib-style deflate, balanced.
    Balanced,
    /// The smallest files, slowest.
    High,
}

impl PngCompression {
    /// Every name [`FromStr`] takes, fastest first.
    pub const NAMES: [&'static str; 5] = ["none", "fastest", "fast", "balanced", "high"];
}

impl FromStr for PngCompression {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self> {
        Ok(match s.to_ascii_lowercase().as_str() {
            "none" => PngCompression::None,
            "fastest" => PngCompression::Fastest,
            "fast" => PngCompression::Fast,
            "balanced" => PngCompression::Balanced,
            "high" => PngCompression::High,
            _ => {
                return Err(RasterError::invalid_field(
                    "compression",
                    format!(
                        "compression must be one of {}, got '{s}'",
                        PngCompression::NAMES.join(", ")
                    ),
                ))
            }
        })
    }
}

/// The samples of an image to encode, row-major, channels interleaved.
#[derive(Debug, Clone, Copy)]
pub enum PngSamples<'a> {
    /// 8 bits per sample.
    U8(&'a [u8]),
    /// 16 bits per sample (written big-endian, as PNG stores them).
    U16(&'a [u16]),
}

impl PngSamples<'_> {
    fn len(&self) -> usize {
        match self {
            PngSamples::U8(s) => s.len(),
            PngSamples::U16(s) => s.len(),
        }
    }
}

/// The PNG file of a `width` × `height` image with `channels` samples per pixel (1 grey,
/// 2 grey + alpha, 3 RGB, 4 RGBA), with `text` as tEXt chunks (Latin-1 keywords of 1-79
/// characters).
///
/// Errors name the problem: a size of zero or above PNG's 2³¹ − 1, a channel count outside
/// 1..=4, a sample count that does not match, a keyword PNG refuses.
pub fn encode_png(
    samples: PngSamples<'_>,
    width: u32,
    height: u32,
    channels: u8,
    compression: PngCompression,
    text: &[(String, String)],
) -> Result<Vec<u8>> {
    const MAX_SIDE: u32 = (1 << 31) - 1;
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(RasterError::invalid(format!(
            "a PNG image is 1 to 2^31 - 1 pixels on each side, got {width} x {height}"
        )));
    }
    let color = match channels {
        1 => png::ColorType::Grayscale,
        2 => png::ColorType::GrayscaleAlpha,
        3 => png::ColorType::Rgb,
        4 => png::ColorType::Rgba,
        _ => {
            return Err(RasterError::invalid(format!(
                "a PNG image has 1 to 4 channels, got {channels}"
            )))
        }
    };
    let expected = (width as usize)
        .checked_mul(height as usize)
        .and_then(|n| n.checked_mul(channels as usize))
        .ok_or_else(|| RasterError::invalid("the image is too large to encode"))?;
    if samples.len() != expected {
        return Err(RasterError::invalid(format!(
            "{width} x {height} x {channels} needs {expected} samples, got {}",
            samples.len()
        )));
    }
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, width, height);
    enc.set_color(color);
    let big_endian;
    let data: &[u8] = match samples {
        PngSamples::U8(s) => {
            enc.set_depth(png::BitDepth::Eight);
            s
        }
        PngSamples::U16(s) => {
            enc.set_depth(png::BitDepth::Sixteen);
            big_endian = s.iter().flat_map(|v| v.to_be_bytes()).collect::<Vec<u8>>();
            &big_endian
        }
    };
    enc.set_compression(match compression {
        PngCompression::None => png::Compression::NoCompression,
        PngCompression::Fastest => png::Compression::Fastest,
        PngCompression::Fast => png::Compression::Fast,
        PngCompression::Balanced => png::Compression::Balanced,
        PngCompression::High => png::Compression::High,
    });
    let fail = |e: png::EncodingError| RasterError::invalid(format!("PNG encoding failed: {e}"));
    for (k, v) in text {
        if k.is_empty() || k.len() > 79 {
            return Err(RasterError::invalid(format!(
                "a PNG text keyword has 1 to 79 characters, got '{k}'"
            )));
        }
        enc.add_text_chunk(k.clone(), v.clone()).map_err(fail)?;
    }
    let mut writer = enc.write_header().map_err(fail)?;
    writer.write_image_data(data).map_err(fail)?;
    writer.finish().map_err(fail)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(bytes: &[u8]) -> (png::OutputInfo, Vec<u8>) {
        let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap();
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        let info = r.next_frame(&mut buf).unwrap();
        buf.truncate(info.buffer_size());
        (info, buf)
    }

    #[test]
    fn every_compression_round_trips_8_and_16_bit() {
        let (w, h) = (7u32, 5u32);
        for channels in 1..=4u8 {
            let n = (w * h) as usize * channels as usize;
            let s8: Vec<u8> = (0..n).map(|i| (i * 37 % 251) as u8).collect();
            let s16: Vec<u16> = (0..n).map(|i| (i * 7919 % 65521) as u16).collect();
            for name in PngCompression::NAMES {
                let c: PngCompression = name.parse().unwrap();
                let bytes = encode_png(PngSamples::U8(&s8), w, h, channels, c, &[]).unwrap();
                let (info, back) = decode(&bytes);
                assert_eq!((info.width, info.height), (w, h));
                assert_eq!(info.bit_depth, png::BitDepth::Eight);
                assert_eq!(back, s8);
                let bytes = encode_png(PngSamples::U16(&s16), w, h, channels, c, &[]).unwrap();
                let (info, back) = decode(&bytes);
                assert_eq!(info.bit_depth, png::BitDepth::Sixteen);
                let back16: Vec<u16> = back
                    .chunks(2)
                    .map(|b| u16::from_be_bytes([b[0], b[1]]))
                    .collect();
                assert_eq!(back16, s16);
            }
        }
    }

    #[test]
    fn text_chunks_are_written() {
        let text = [("depth_scale".to_string(), "0.25".to_string())];
        let bytes = encode_png(
            PngSamples::U8(&[1, 2]),
            2,
            1,
            1,
            PngCompression::Fast,
            &text,
        )
        .unwrap();
        let r = png::Decoder::new(std::io::Cursor::new(&bytes[..]))
            .read_info()
            .unwrap();
        let t = &r.info().uncompressed_latin1_text;
        assert_eq!(t.len(), 1);
        assert_eq!(
            (t[0].keyword.as_str(), t[0].text.as_str()),
            ("depth_scale", "0.25")
        );
    }

    #[test]
    fn bad_input_is_an_error_naming_it() {
        let e = |r: Result<Vec<u8>>| r.unwrap_err().to_string();
        let s = PngSamples::U8(&[0; 12]);
        assert!(e(encode_png(s, 0, 4, 3, PngCompression::Fast, &[])).contains("0 x 4"));
        assert!(e(encode_png(s, 2, 2, 5, PngCompression::Fast, &[])).contains("channels"));
        assert!(e(encode_png(s, 3, 3, 3, PngCompression::Fast, &[])).contains("needs 27"));
        let long = [("k".repeat(80), String::new())];
        assert!(e(encode_png(s, 2, 2, 3, PngCompression::Fast, &long)).contains("keyword"));
        let err = "zip".parse::<PngCompression>().unwrap_err();
        assert_eq!(err.field(), Some("compression"));
    }
}
