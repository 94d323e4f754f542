//! The one error type of the core crate. Every variant maps to its own Python exception class
//! (see `crates/floorscan-py/src/errors.rs`), so keep variants about *what the user did wrong*.

/// Errors returned by floorscan-core. The core never panics on user-supplied data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// The image has the wrong size, is empty, or its memory layout is unusable.
    #[error("invalid image: {0}")]
    InvalidImage(String),
    /// An option is outside its valid range (name of the option, and why).
    #[error("invalid option `{name}`: {reason}")]
    InvalidOption { name: &'static str, reason: String },
    /// A ground table (or its source data) is inconsistent.
    #[error("invalid ground table: {0}")]
    InvalidTable(String),
    /// A serialised file has a schema version this build does not read.
    #[error("unsupported {kind} file version {found} (this build reads version {expected})")]
    UnsupportedVersion {
        kind: &'static str,
        found: u32,
        expected: u32,
    },
    /// A serialised file is damaged or is not the expected kind of file.
    #[error("malformed {kind} file: {reason}")]
    Malformed { kind: &'static str, reason: String },
    /// A geometric input (pose, range, point) is not finite or not in its domain.
    #[error("invalid geometry: {0}")]
    InvalidGeometry(String),
    /// Array arguments whose lengths must agree do not.
    #[error("length mismatch: {0}")]
    LengthMismatch(String),
    /// A position lies outside a map with fixed bounds.
    #[error("out of map bounds: {0}")]
    OutOfBounds(String),
}

/// Result alias of the core crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Shorthand for an [`Error::InvalidOption`].
pub(crate) fn invalid_option(name: &'static str, reason: impl Into<String>) -> Error {
    Error::InvalidOption {
        name,
        reason: reason.into(),
    }
}
