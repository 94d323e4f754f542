//! Image file decoding for floorscan's recorded input: PNG bytes to pixels, with a bound on the
//! decoded size checked on the header before anything is allocated.
//!
//! A crate of its own, apart from floorscan-core: decoding is compute, but it parses an outside
//! file format with outside dependencies (the `png` crate and its inflate), which the core (pure
//! ranging and mapping, its own types only) does not need; the simulator and the core stay free
//! of them. One error enum for the crate ([`Error`]); the bindings map each variant to a Python
//! class under `floorscan.FloorscanError`. Never panics on any input.

mod error;
mod pixels;
mod png;

pub use error::{Error, Result};
pub use pixels::{DecodedImage, Samples};
pub use png::{decode_png, is_png, PNG_SIGNATURE};
