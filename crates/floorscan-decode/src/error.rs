//! The one error type of the decode crate; every variant maps to a Python exception class
//! (`crates/floorscan-py/src/decode.rs`). Messages are one line.

/// Errors returned by floorscan-decode. Decoding never panics on the bytes it is given.
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
}

/// Result alias of the decode crate.
pub type Result<T> = std::result::Result<T, Error>;

/// One line of a library's error text (its messages never need more).
pub(crate) fn one_line(text: impl std::fmt::Display) -> String {
    text.to_string()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}
