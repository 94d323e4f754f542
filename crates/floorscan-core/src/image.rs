//! A borrowed, possibly strided, greyscale image. Rows count from the top (v = 0 is the top row).

use crate::error::{Error, Result};

/// A greyscale pixel type the edge filter reads: 8- or 16-bit unsigned.
pub trait Pixel: Copy + Send + Sync + 'static {
    /// The pixel's intensity as a signed integer (wide enough for sums of 2^15 pixels).
    fn to_i32(self) -> i32;
    /// Largest intensity value.
    const MAX: i32;
    /// The pixels as bytes, for 8-bit pixel types (the edge ranger's 16-bit lane kernels).
    fn as_bytes(data: &[Self]) -> Option<&[u8]> {
        let _ = data;
        None
    }
}

impl Pixel for u8 {
    #[inline(always)]
    fn to_i32(self) -> i32 {
        self as i32
    }
    const MAX: i32 = u8::MAX as i32;
    fn as_bytes(data: &[Self]) -> Option<&[u8]> {
        Some(data)
    }
}

impl Pixel for u16 {
    #[inline(always)]
    fn to_i32(self) -> i32 {
        self as i32
    }
    const MAX: i32 = u16::MAX as i32;
}

/// A view of `height` rows of `width` pixels inside `data`. Pixel (u, v) lives at
/// `data[v * row_stride + u * col_stride]` (strides in elements, not bytes).
#[derive(Debug, Clone, Copy)]
pub struct ImageView<'a, P: Pixel> {
    data: &'a [P],
    width: usize,
    height: usize,
    row_stride: usize,
    col_stride: usize,
}

impl<'a, P: Pixel> ImageView<'a, P> {
    /// A contiguous row-major image.
    pub fn new(data: &'a [P], width: usize, height: usize) -> Result<Self> {
        Self::with_strides(data, width, height, width, 1)
    }

    /// A strided image; checks that every pixel lies inside `data`.
    pub fn with_strides(
        data: &'a [P],
        width: usize,
        height: usize,
        row_stride: usize,
        col_stride: usize,
    ) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::InvalidImage(format!(
                "image is empty ({height} x {width})"
            )));
        }
        let last = (height - 1)
            .checked_mul(row_stride)
            .and_then(|a| {
                (width - 1)
                    .checked_mul(col_stride)
                    .and_then(|b| a.checked_add(b))
            })
            .ok_or_else(|| Error::InvalidImage("image strides overflow".into()))?;
        if last >= data.len() {
            return Err(Error::InvalidImage(format!(
                "{height} x {width} image with strides ({row_stride}, {col_stride}) needs {} elements, buffer has {}",
                last + 1,
                data.len()
            )));
        }
        Ok(Self {
            data,
            width,
            height,
            row_stride,
            col_stride,
        })
    }

    pub fn width(&self) -> usize {
        self.width
    }
    pub fn height(&self) -> usize {
        self.height
    }
    pub fn row_stride(&self) -> usize {
        self.row_stride
    }
    pub fn col_stride(&self) -> usize {
        self.col_stride
    }

    /// The same view typed as 8-bit pixels, if `P` is 8-bit.
    pub fn as_u8(&self) -> Option<ImageView<'a, u8>> {
        Some(ImageView {
            data: P::as_bytes(self.data)?,
            width: self.width,
            height: self.height,
            row_stride: self.row_stride,
            col_stride: self.col_stride,
        })
    }

    /// Pixel at column u, row v. Panics if out of bounds (internal use with checked indices).
    #[inline(always)]
    pub fn get(&self, u: usize, v: usize) -> P {
        self.data[v * self.row_stride + u * self.col_stride]
    }

    /// The elements of row v starting at column 0 (use with `col_stride`).
    #[inline(always)]
    pub fn row(&self, v: usize) -> &'a [P] {
        let start = v * self.row_stride;
        let end = start + (self.width - 1) * self.col_stride + 1;
        &self.data[start..end]
    }
}

#[cfg(test)]
#[path = "image_tests.rs"]
mod tests;
