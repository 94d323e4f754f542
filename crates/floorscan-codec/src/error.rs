//! The one error type of the codec crate; every variant maps to a Python exception class
//! (`class_name` in `crates/floorscan-py/src/formats/png.rs`). Messages are one line.

/// Errors returned by floorscan-codec. Never panics on the bytes it is given.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Error {
    /// The header declares more pixels than the caller's limit (checked before decoding).
    #[error("image is {width} x {height} = {pixels} pixels, more than the limit of {limit}")]
    TooLarge {
        width: u32,
        height: u32,
        pixels: u64,
        limit: u64,
    },
    /// The bytes are not a valid file of the format (truncated, corrupt, bad header).
    #[error("cannot decode {format}: {reason}")]
    Malformed {
        format: &'static str,
        reason: String,
    },
    /// A frame or palette handed to an encoder has the wrong size.
    #[error("invalid frame: {0}")]
    InvalidFrame(String),
    /// Files could not be read ahead (a decoding thread could not start).
    #[error("cannot read ahead: {reason}")]
    Read { reason: String },
    /// Writing an encoded file failed (the writer's error: a full disk, a closed file).
    #[error("cannot write {format}: {reason}")]
    Encode {
        format: &'static str,
        reason: String,
    },
}

/// Result alias of the codec crate.
pub type Result<T> = std::result::Result<T, Error>;

/// One line of a library's error text (its messages never need more).
pub(crate) fn one_line(text: impl std::fmt::Display) -> String {
    text.to_string()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}
