//! A borrowed colour image as three channel views (red, green, blue) over the same pixels, so an
//! interleaved RGB buffer, three planes, or a greyscale image (the same view three times) are
//! all read without a copy. Rows count from the top (v = 0 is the top row).

use crate::error::{Error, Result};
use crate::image::{ImageView, Pixel};

/// Three channel views of equal size: `channels[0]` red, `[1]` green, `[2]` blue.
#[derive(Debug, Clone, Copy)]
pub struct ColourView<'a, P: Pixel> {
    channels: [ImageView<'a, P>; 3],
}

impl<'a, P: Pixel> ColourView<'a, P> {
    /// From three channel views; they must have the same width and height.
    pub fn from_channels(
        red: ImageView<'a, P>,
        green: ImageView<'a, P>,
        blue: ImageView<'a, P>,
    ) -> Result<Self> {
        let size = (red.width(), red.height());
        if (green.width(), green.height()) != size || (blue.width(), blue.height()) != size {
            return Err(Error::InvalidImage(format!(
                "colour channels differ in size: {} x {}, {} x {}, {} x {} (w x h)",
                red.width(),
                red.height(),
                green.width(),
                green.height(),
                blue.width(),
                blue.height()
            )));
        }
        Ok(Self {
            channels: [red, green, blue],
        })
    }

    /// A contiguous interleaved RGB buffer (`data[(v * width + u) * 3 + c]`).
    pub fn interleaved(data: &'a [P], width: usize, height: usize) -> Result<Self> {
        let needed = width
            .checked_mul(height)
            .and_then(|n| n.checked_mul(3))
            .ok_or_else(|| Error::InvalidImage("image size overflows".into()))?;
        if data.len() < needed || needed == 0 {
            return Err(Error::InvalidImage(format!(
                "{height} x {width} RGB image needs {needed} elements, buffer has {}",
                data.len()
            )));
        }
        let plane = |c: usize| ImageView::with_strides(&data[c..], width, height, 3 * width, 3);
        Self::from_channels(plane(0)?, plane(1)?, plane(2)?)
    }

    /// A greyscale image read as colour (every channel the same).
    pub fn grey(view: ImageView<'a, P>) -> Self {
        Self {
            channels: [view; 3],
        }
    }

    pub fn width(&self) -> usize {
        self.channels[0].width()
    }
    pub fn height(&self) -> usize {
        self.channels[0].height()
    }

    /// Channel `c` (0 red, 1 green, 2 blue).
    pub fn channel(&self, c: usize) -> &ImageView<'a, P> {
        &self.channels[c]
    }

    /// (red, green, blue) at column u, row v, scaled to 8 bits (16-bit pixels keep their high
    /// byte). Panics if out of bounds (internal use with checked indices).
    #[inline(always)]
    pub fn rgb8(&self, u: usize, v: usize) -> [i32; 3] {
        let shift = if P::MAX > 255 { 8 } else { 0 };
        [
            self.channels[0].get(u, v).to_i32() >> shift,
            self.channels[1].get(u, v).to_i32() >> shift,
            self.channels[2].get(u, v).to_i32() >> shift,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interleaved_channels_read_the_right_bytes() {
        let data: Vec<u8> = (0..2 * 3 * 3).map(|i| i as u8).collect();
        let c = ColourView::interleaved(&data, 3, 2).unwrap();
        assert_eq!(c.rgb8(0, 0), [0, 1, 2]);
        assert_eq!(c.rgb8(2, 1), [15, 16, 17]);
        assert!(ColourView::interleaved(&data[..10], 3, 2).is_err());
    }

    #[test]
    fn sixteen_bit_pixels_keep_their_high_byte_and_sizes_must_agree() {
        let data = vec![0x1234u16; 4];
        let v = ImageView::new(&data, 2, 2).unwrap();
        assert_eq!(ColourView::grey(v).rgb8(1, 1), [0x12; 3]);
        let small = ImageView::new(&data[..2], 2, 1).unwrap();
        assert!(ColourView::from_channels(v, v, small).is_err());
    }
}
