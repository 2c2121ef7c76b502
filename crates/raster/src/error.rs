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
