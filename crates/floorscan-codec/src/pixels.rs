//! A decoded image (row-major, channels interleaved) and its greyscale form, computed exactly as
//! Pillow's `convert("L")` does so that both decoders give the same pixels.

/// Samples of a decoded image: 8 or 16 bits each (native byte order).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Samples {
    U8(Vec<u8>),
    U16(Vec<u16>),
}

/// A decoded image: `height` rows of `width` pixels of `channels` samples each (1 grey, 2 grey +
/// alpha, 3 RGB, 4 RGBA); row 0 is the top (v = 0).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecodedImage {
    pub width: usize,
    pub height: usize,
    pub channels: usize,
    pub samples: Samples,
}

/// ITU-R BT.601 luma in 16-bit fixed point, rounded: Pillow's `L24(rgb) >> 16`.
fn luma(r: u8, g: u8, b: u8) -> u8 {
    ((r as u32 * 19595 + g as u32 * 38470 + b as u32 * 7471 + 0x8000) >> 16) as u8
}

impl DecodedImage {
    /// The image as one grey channel: grey images keep their samples (16-bit grey stays 16-bit),
    /// alpha is dropped, colour becomes BT.601 luma (Pillow's `convert("L")`, bit for bit).
    /// Colour and grey + alpha images are 8-bit here (see [`crate::decode_png`]).
    pub fn into_grey(self) -> DecodedImage {
        let c = self.channels;
        let samples = match self.samples {
            samples if c == 1 => samples,
            Samples::U8(v) if c == 2 => Samples::U8(v.chunks_exact(2).map(|p| p[0]).collect()),
            Samples::U8(v) => {
                Samples::U8(v.chunks_exact(c).map(|p| luma(p[0], p[1], p[2])).collect())
            }
            Samples::U16(v) if c == 2 => Samples::U16(v.chunks_exact(2).map(|p| p[0]).collect()),
            Samples::U16(v) => Samples::U8(
                v.chunks_exact(c)
                    .map(|p| luma((p[0] >> 8) as u8, (p[1] >> 8) as u8, (p[2] >> 8) as u8))
                    .collect(),
            ),
        };
        DecodedImage {
            channels: 1,
            samples,
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn luma_matches_pillows_fixed_point_formula() {
        // Pillow: L = (R * 19595 + G * 38470 + B * 7471 + 0x8000) >> 16.
        assert_eq!(luma(0, 0, 0), 0);
        assert_eq!(luma(255, 255, 255), 255);
        assert_eq!(luma(255, 0, 0), 76);
        assert_eq!(luma(0, 255, 0), 150);
        assert_eq!(luma(0, 0, 255), 29);
        assert_eq!(luma(10, 20, 30), 18);
    }

    #[test]
    fn grey_keeps_grey_and_drops_alpha() {
        let ga = DecodedImage {
            width: 2,
            height: 1,
            channels: 2,
            samples: Samples::U8(vec![7, 255, 9, 0]),
        };
        assert_eq!(ga.into_grey().samples, Samples::U8(vec![7, 9]));
        let g16 = DecodedImage {
            width: 1,
            height: 1,
            channels: 1,
            samples: Samples::U16(vec![40000]),
        };
        assert_eq!(g16.into_grey().samples, Samples::U16(vec![40000]));
    }
}
