//! Image files through the `image` crate: PNG (8 and 16 bit), JPEG and the other formats it
//! decodes, to linear f32 texels.

use std::path::Path;

use super::image::{Image, MAX_TEXTURE_SIZE};
use crate::error::{RasterError, Result};

/// Decodes the file at `path` (values scaled to [0, 1]; `srgb` decodes them to linear).
pub(super) fn load(path: &Path, srgb: bool) -> Result<Image> {
    let meta = std::fs::metadata(path).map_err(|_| RasterError::NotFound(path.to_path_buf()))?;
    // A device or pipe (an MTL naming /dev/stdin) could block or never end.
    if !meta.is_file() {
        return Err(RasterError::Io {
            path: path.to_path_buf(),
            message: "not a regular file".into(),
        });
    }
    let parse = |message: String| RasterError::Parse {
        path: path.to_path_buf(),
        line: None,
        message,
    };
    let reader = ::image::ImageReader::open(path)
        .map_err(|e| RasterError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?
        .with_guessed_format()
        .map_err(|e| parse(format!("cannot read the image: {e}")))?;
    // Refuse sizes beyond the texture limit before decoding allocates them.
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| parse(format!("cannot decode the image: {e}")))?;
    if w as usize > MAX_TEXTURE_SIZE || h as usize > MAX_TEXTURE_SIZE {
        return Err(parse(format!(
            "image is {w} x {h}; at most {MAX_TEXTURE_SIZE} texels per side are supported"
        )));
    }
    let img = ::image::ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| parse(format!("cannot read the image: {e}")))?
        .decode()
        .map_err(|e| parse(format!("cannot decode the image: {e}")))?;
    let rgb = img.to_rgb32f();
    Image::from_top_rows(w as usize, h as usize, 3, rgb.as_raw(), srgb).map_err(|e| match e {
        RasterError::InvalidInput(m) => parse(m),
        other => other,
    })
}
