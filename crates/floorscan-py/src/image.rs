//! numpy greyscale images (uint8 or uint16, any positive strides) as core `ImageView`s, with no
//! copy. Arrays with negative or zero strides are copied to C order first.

use floorscan_core::{ImageView, Pixel};
use numpy::{Element, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::errors::error;

/// A borrowed numpy image that stays valid while it lives.
pub struct BorrowedImage<'py, P: Pixel + Element> {
    array: PyReadonlyArray2<'py, P>,
    /// Strides in elements, both > 0.
    strides: (usize, usize),
}

impl<'py, P: Pixel + Element> BorrowedImage<'py, P> {
    pub fn new(array: &Bound<'py, PyArray2<P>>) -> PyResult<Self> {
        let shape = array.shape();
        if shape[0] == 0 || shape[1] == 0 {
            return Err(error(
                "ImageError",
                format!("image is empty: shape ({}, {}) (H, W)", shape[0], shape[1]),
            ));
        }
        let item = std::mem::size_of::<P>() as isize;
        let s = array.strides();
        let usable = s[0] > 0 && s[1] > 0 && s[0] % item == 0 && s[1] % item == 0;
        let array = if usable {
            array.readonly()
        } else {
            // Negative, zero or misaligned strides: take a C-ordered copy.
            let copy = array.to_owned_array();
            PyArray2::from_owned_array(array.py(), copy).readonly()
        };
        let s = array.strides();
        let strides = ((s[0] / item) as usize, (s[1] / item) as usize);
        Ok(Self { array, strides })
    }

    pub fn view(&self) -> PyResult<ImageView<'_, P>> {
        let shape = self.array.shape();
        let (h, w) = (shape[0], shape[1]);
        let len = (h - 1) * self.strides.0 + (w - 1) * self.strides.1 + 1;
        // SAFETY: the array is borrowed read-only for the lifetime of `self`; with positive
        // element strides every pixel lies in [ptr, ptr + len).
        let data = unsafe { std::slice::from_raw_parts(self.array.data() as *const P, len) };
        ImageView::with_strides(data, w, h, self.strides.0, self.strides.1)
            .map_err(crate::errors::to_pyerr)
    }
}
