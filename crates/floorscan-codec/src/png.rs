//! PNG bytes to pixels (the `png` crate), sized by the header only after it has been checked
//! against the caller's pixel limit.
//!
//! The output matches what Pillow gives for the same file: palettes become RGB (RGBA with a
//! `tRNS` chunk), 1/2/4-bit grey is scaled to 8 bits (x255, x85, x17), interlaced (Adam7) files
//! are de-interlaced, 16-bit grey stays 16-bit and every other 16-bit type keeps its high byte
//! (Pillow's `RGB;16B`, `LA;16B`, `RGBA;16B` modes). Checksums are verified.

use std::io::Cursor;

use png::{BitDepth, ColorType, Decoder, Transformations};

use crate::error::{one_line, Error, Result};
use crate::pixels::{DecodedImage, Samples};

/// The eight bytes every PNG file starts with.
pub const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Whether `data` starts with the PNG signature.
pub fn is_png(data: &[u8]) -> bool {
    data.starts_with(&PNG_SIGNATURE)
}

fn malformed(e: impl std::fmt::Display) -> Error {
    Error::Malformed {
        format: "PNG",
        reason: one_line(e),
    }
}

/// Decodes the first (default) image of a PNG file. `max_pixels` bounds width x height: a larger
/// header is refused with [`Error::TooLarge`] before any pixel buffer is allocated.
pub fn decode_png(data: &[u8], max_pixels: u64) -> Result<DecodedImage> {
    if !is_png(data) {
        return Err(malformed("not a PNG file (no PNG signature)"));
    }
    let mut decoder = Decoder::new(Cursor::new(data));
    let header = decoder.read_header_info().map_err(malformed)?;
    let (width, height) = (header.width, header.height);
    let pixels = width as u64 * height as u64;
    if pixels > max_pixels {
        return Err(Error::TooLarge {
            width,
            height,
            pixels,
            limit: max_pixels,
        });
    }
    let keep_16 = header.color_type == ColorType::Grayscale;
    let transform = if keep_16 {
        Transformations::EXPAND
    } else {
        Transformations::EXPAND | Transformations::STRIP_16
    };
    decoder.set_transformations(transform);
    let mut reader = decoder.read_info().map_err(malformed)?;
    // Bounded: at most max_pixels x 4 channels x 2 bytes.
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| malformed("image too large for this machine's address space"))?;
    let mut buf = vec![0u8; size];
    let out = reader.next_frame(&mut buf).map_err(malformed)?;
    let (w, h) = (out.width as usize, out.height as usize);
    let channels = out.color_type.samples();
    let len = w * h * channels;
    let samples = match out.bit_depth {
        BitDepth::Sixteen => Samples::U16(
            buf[..2 * len]
                .chunks_exact(2)
                .map(|b| u16::from_be_bytes([b[0], b[1]]))
                .collect(),
        ),
        BitDepth::Eight => {
            buf.truncate(len);
            Samples::U8(buf)
        }
        other => return Err(malformed(format!("unexpected output bit depth {other:?}"))),
    };
    Ok(DecodedImage {
        width: w,
        height: h,
        channels,
        samples,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PNG written by the `png` crate's encoder.
    fn encode(w: u32, h: u32, colour: ColorType, depth: BitDepth, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, w, h);
            enc.set_color(colour);
            enc.set_depth(depth);
            let mut writer = enc.write_header().unwrap();
            writer.write_image_data(data).unwrap();
        }
        out
    }

    #[test]
    fn grey8_round_trips() {
        let px: Vec<u8> = (0..12).map(|i| i * 20).collect();
        let img = decode_png(
            &encode(4, 3, ColorType::Grayscale, BitDepth::Eight, &px),
            100,
        )
        .unwrap();
        assert_eq!((img.width, img.height, img.channels), (4, 3, 1));
        assert_eq!(img.samples, Samples::U8(px));
    }

    #[test]
    fn grey16_stays_16_bit_in_native_order() {
        let px: Vec<u16> = vec![0, 1, 256, 65535];
        let be: Vec<u8> = px.iter().flat_map(|v| v.to_be_bytes()).collect();
        let img = decode_png(
            &encode(2, 2, ColorType::Grayscale, BitDepth::Sixteen, &be),
            4,
        )
        .unwrap();
        assert_eq!(img.samples, Samples::U16(px));
    }

    #[test]
    fn rgb16_keeps_the_high_byte() {
        let be: Vec<u8> = vec![0x12, 0x34, 0xab, 0xcd, 0xff, 0x00];
        let img = decode_png(&encode(1, 1, ColorType::Rgb, BitDepth::Sixteen, &be), 1).unwrap();
        assert_eq!(img.channels, 3);
        assert_eq!(img.samples, Samples::U8(vec![0x12, 0xab, 0xff]));
    }

    #[test]
    fn two_bit_grey_is_scaled_to_8_bits() {
        // One row of 4 pixels: 0, 1, 2, 3 -> 0, 85, 170, 255.
        let img = decode_png(
            &encode(4, 1, ColorType::Grayscale, BitDepth::Two, &[0b00_01_10_11]),
            4,
        )
        .unwrap();
        assert_eq!(img.samples, Samples::U8(vec![0, 85, 170, 255]));
    }

    #[test]
    fn a_header_over_the_limit_is_refused_before_decoding() {
        let png = encode(4, 3, ColorType::Grayscale, BitDepth::Eight, &[0; 12]);
        let err = decode_png(&png, 11).unwrap_err();
        assert!(matches!(
            err,
            Error::TooLarge {
                width: 4,
                height: 3,
                pixels: 12,
                limit: 11
            }
        ));
    }

    #[test]
    fn truncated_and_foreign_bytes_are_malformed_with_one_line() {
        let png = encode(4, 3, ColorType::Grayscale, BitDepth::Eight, &[7; 12]);
        for bad in [
            &png[..png.len() - 20],
            &png[..20],
            &b"GIF89a...."[..],
            &[][..],
        ] {
            let err = decode_png(bad, 100).unwrap_err();
            assert!(matches!(err, Error::Malformed { .. }), "{err:?}");
            assert!(!err.to_string().contains('\n'));
        }
    }

    #[test]
    fn huge_declared_dimensions_fail_without_allocating() {
        // IHDR of 2^31-1 x 2^31-1 grey 8-bit with a valid CRC: refused on the header (no
        // 4.6 EB buffer), however large the limit.
        let mut png = encode(1, 1, ColorType::Grayscale, BitDepth::Eight, &[0]);
        png[16..20].copy_from_slice(&0x7fff_ffffu32.to_be_bytes());
        png[20..24].copy_from_slice(&0x7fff_ffffu32.to_be_bytes());
        let crc = crc32fast::hash(&png[12..29]);
        png[29..33].copy_from_slice(&crc.to_be_bytes());
        let err = decode_png(&png, 1 << 26).unwrap_err();
        assert!(
            matches!(err, Error::TooLarge { pixels, .. } if pixels == 0x7fff_ffff * 0x7fff_ffff),
            "{err:?}"
        );
        let err = decode_png(&png, u64::MAX).unwrap_err();
        assert!(matches!(err, Error::Malformed { .. }), "{err:?}");
    }
}
