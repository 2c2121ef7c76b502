//! The one error type of the core crate.

use std::fmt;
use std::path::PathBuf;

/// Everything that can go wrong when building a scene or rendering it.
///
/// Every variant carries a message that names the offending input, so the Python layer can
/// forward it unchanged.
#[derive(Debug, Clone, PartialEq)]
pub enum RasterError {
    /// A value is out of its documented domain (non-finite number, bad index, bad size...).
    InvalidInput(String),
    /// One named argument of a constructor is out of its domain (`field` is the argument's
    /// name: `"intensity"`, `"cutoff"`), so a caller can point at its own spelling of it
    /// (a scene file's `lights[2].cutoff`) without checking the value again.
    InvalidField {
        /// The argument's name, as the constructor's documentation spells it.
        field: &'static str,
        /// What is wrong, naming the value.
        message: String,
    },
    /// A file does not exist.
    NotFound(PathBuf),
    /// A file exists but could not be read.
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        message: String,
    },
    /// A file was read but its content is malformed.
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number, when known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// A buffer of this many bytes could not be allocated.
    OutOfMemory {
        /// The size of the failed allocation.
        bytes: usize,
    },
}

impl RasterError {
    pub(crate) fn invalid(msg: impl Into<String>) -> Self {
        RasterError::InvalidInput(msg.into())
    }

    pub(crate) fn invalid_field(field: &'static str, msg: impl Into<String>) -> Self {
        RasterError::InvalidField {
            field,
            message: msg.into(),
        }
    }

    /// The name of the offending argument, when the error is about one.
    pub fn field(&self) -> Option<&'static str> {
        match self {
            RasterError::InvalidField { field, .. } => Some(field),
            _ => None,
        }
    }
}

impl fmt::Display for RasterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RasterError::InvalidInput(m) | RasterError::InvalidField { message: m, .. } => {
                f.write_str(m)
            }
            RasterError::NotFound(p) => write!(f, "no such file: '{}'", p.display()),
            RasterError::Io { path, message } => {
                write!(f, "cannot read '{}': {message}", path.display())
            }
            RasterError::Parse {
                path,
                line: Some(line),
                message,
            } => write!(f, "{}:{line}: {message}", path.display()),
            RasterError::Parse {
                path,
                line: None,
                message,
            } => write!(f, "{}: {message}", path.display()),
            RasterError::OutOfMemory { bytes } => {
                write!(f, "cannot allocate {bytes} bytes for the image buffers")
            }
        }
    }
}

impl std::error::Error for RasterError {}

/// Result alias used throughout the crate.
pub type Result<T> = std::result::Result<T, RasterError>;

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::{Camera, DirectionalLight, Fog, FogMode, Material, PointLight, SpotLight};

    #[test]
    fn value_errors_name_their_argument() {
        let point = PointLight::new(Vec3::ZERO, Vec3::ONE, 1.0).unwrap();
        let cases = [
            (
                SpotLight::new(point, Vec3::Z, 100.0, 0.0).unwrap_err(),
                "cutoff",
            ),
            (
                SpotLight::new(point, Vec3::Z, 30.0, -1.0).unwrap_err(),
                "exponent",
            ),
            (
                SpotLight::new(point, Vec3::Z, 30.0, 0.0)
                    .and_then(|s| s.with_inner(40.0))
                    .unwrap_err(),
                "inner",
            ),
            (
                DirectionalLight::new(Vec3::ZERO, Vec3::ONE, 1.0).unwrap_err(),
                "direction",
            ),
            (
                PointLight::new(Vec3::ZERO, Vec3::ONE, -1.0).unwrap_err(),
                "intensity",
            ),
            (
                point.with_attenuation(0.0, 0.0, 0.0).unwrap_err(),
                "attenuation",
            ),
            (
                Material::new(Vec3::ONE, Vec3::ONE, Vec3::ONE, -1.0).unwrap_err(),
                "shininess",
            ),
            (
                Fog::new(
                    FogMode::Linear {
                        start: 2.0,
                        end: 1.0,
                    },
                    Vec3::ONE,
                )
                .unwrap_err(),
                "end",
            ),
            (
                Camera::look_at(
                    glam::DVec3::Z,
                    glam::DVec3::ZERO,
                    glam::DVec3::Y,
                    45.0,
                    0.0,
                    10.0,
                )
                .unwrap_err(),
                "near",
            ),
        ];
        for (e, field) in cases {
            assert_eq!(e.field(), Some(field), "{e}");
        }
    }
}
