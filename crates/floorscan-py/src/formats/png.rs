//! Bindings of `floorscan_codec`'s PNG decoder (bytes to numpy pixels), with the GIL released
//! while decoding.

use floorscan_codec::{DecodedImage, Error, Samples};
use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;

use crate::errors::{codec_to_pyerr as to_pyerr, guard};

/// A decoded image as a numpy array: (H, W) for one channel, (H, W, C) otherwise.
pub fn to_numpy<'py>(py: Python<'py>, img: DecodedImage) -> PyResult<Bound<'py, PyAny>> {
    let shape: Vec<usize> = if img.channels == 1 {
        vec![img.height, img.width]
    } else {
        vec![img.height, img.width, img.channels]
    };
    Ok(match img.samples {
        Samples::U8(v) => v.into_pyarray(py).reshape(shape)?.into_any(),
        Samples::U16(v) => v.into_pyarray(py).reshape(shape)?.into_any(),
    })
}

fn decode(py: Python<'_>, data: &[u8], max_pixels: u64, grey: bool) -> Result<DecodedImage, Error> {
    py.detach(|| {
        let img = floorscan_codec::decode_png(data, max_pixels)?;
        Ok(if grey { img.into_grey() } else { img })
    })
}

/// PNG file bytes to pixels: uint8, or uint16 for 16-bit grey; (H, W) grey, (H, W, 2) grey +
/// alpha, (H, W, 3) RGB or (H, W, 4) RGBA (palettes expanded, other 16-bit types to their
/// high byte, as Pillow reads them). `max_pixels` bounds width x height, checked on the header.
#[pyfunction]
pub fn png_to_array<'py>(
    py: Python<'py>,
    data: &[u8],
    max_pixels: u64,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| to_numpy(py, decode(py, data, max_pixels, false).map_err(to_pyerr)?))
}

/// PNG file bytes to one grey channel (H, W): uint8, or uint16 for 16-bit grey files; colour
/// becomes BT.601 luma exactly as Pillow's `convert("L")`, alpha is dropped. `max_pixels`
/// bounds width x height, checked on the header.
#[pyfunction]
pub fn png_to_grey<'py>(
    py: Python<'py>,
    data: &[u8],
    max_pixels: u64,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| to_numpy(py, decode(py, data, max_pixels, true).map_err(to_pyerr)?))
}

/// Most bytes a PNG file of `max_pixels` pixels is read into memory for (larger files go to
/// Pillow, which reads lazily and checks the header first).
#[pyfunction]
pub fn max_png_file_bytes(max_pixels: u64) -> u64 {
    floorscan_codec::max_png_file_bytes(max_pixels)
}
