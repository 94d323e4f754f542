//! Image files of floorscan's recorded input and of its pictures: PNG bytes to pixels, with a
//! bound on the decoded size checked on the header before anything is allocated, and the
//! overlay's animated GIF encoded frame by frame on a thread of its own; a dataset's PNG files
//! read and decoded ahead of the frame loop on threads of their own.
//!
//! A crate of its own, apart from floorscan-core: decoding is compute, but it parses outside
//! file formats with outside dependencies (the `png` crate and its inflate, the `gif` crate's
//! LZW) that the core (ranging and mapping over its own types) does not need, and the GIF
//! stream owns a thread and a writer; the core and the simulator stay free of all three. One
//! error enum for the crate ([`Error`]); the bindings map each variant to a Python class under
//! `floorscan.FloorscanError`. Never panics on any input.

mod error;
mod gif;
mod pixels;
mod png;
mod read_ahead;

pub use error::{Error, Result};
pub use gif::{GifStream, GIF_QUEUE_FRAMES};
pub use pixels::{DecodedImage, Samples};
pub use png::{decode_png, is_png, PNG_SIGNATURE};
pub use read_ahead::{max_png_file_bytes, Ahead, ReadAhead};
