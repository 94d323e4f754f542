//! Bindings of the image formats (`floorscan._native.formats`): PNG decoding and reading ahead, the
//! overlay's GIF stream.

pub mod gif;
pub mod png;
pub mod read_ahead;
