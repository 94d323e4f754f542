//! Fuzzing the PNG decoder (issue 14): mutated valid files (flipped, cut, spliced bytes, with
//! and without fixed-up chunk CRCs) and hostile headers (any size, bit depth, colour type,
//! interlace). Each property: no panic, a typed error or an image of the header's size, and
//! nothing allocated past the pixel limit.
//!
//! `cargo test` runs a short deterministic corpus (fixed seed, 200 cases per property);
//! `make fuzz` sets FLOORSCAN_FUZZ=1 and PROPTEST_CASES for a longer random search.

use floorscan_codec::{decode_png, Error};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

fn config() -> Config {
    let base = Config::default(); // reads PROPTEST_CASES and PROPTEST_RNG_SEED
    if std::env::var_os("FLOORSCAN_FUZZ").is_some() {
        Config {
            failure_persistence: None,
            ..base
        }
    } else {
        Config {
            cases: 200,
            rng_seed: RngSeed::Fixed(0x1551_0014),
            failure_persistence: None,
            ..base
        }
    }
}

const LIMIT: u64 = 1 << 16;

fn crc(kind_and_data: &[u8]) -> [u8; 4] {
    crc32fast::hash(kind_and_data).to_be_bytes()
}

fn chunk(kind: &[u8; 4], data: &[u8]) -> Vec<u8> {
    let mut out = (data.len() as u32).to_be_bytes().to_vec();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let mut body = kind.to_vec();
    body.extend_from_slice(data);
    out.extend_from_slice(&crc(&body));
    out
}

/// A PNG with the given header fields and `raw` (filter bytes and samples) as its image data.
fn png(w: u32, h: u32, depth: u8, colour: u8, interlace: u8, raw: &[u8]) -> Vec<u8> {
    let mut ihdr = w.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[depth, colour, 0, 0, interlace]);
    let compressed = stored_zlib(raw);
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    out.extend(chunk(b"IHDR", &ihdr));
    out.extend(chunk(b"IDAT", &compressed));
    out.extend(chunk(b"IEND", &[]));
    out
}

/// zlib stream of stored (uncompressed) blocks: no compressor needed.
fn stored_zlib(raw: &[u8]) -> Vec<u8> {
    let mut out = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = if raw.is_empty() {
        vec![&[][..]]
    } else {
        raw.chunks(65535).collect()
    };
    for (k, block) in blocks.iter().enumerate() {
        out.push(u8::from(k + 1 == blocks.len()));
        let len = block.len() as u16;
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&(!len).to_le_bytes());
        out.extend_from_slice(block);
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &byte in raw {
        a = (a + byte as u32) % 65521;
        b = (b + a) % 65521;
    }
    out.extend_from_slice(&((b << 16) | a).to_be_bytes());
    out
}

fn check(data: &[u8]) -> Result<(), TestCaseError> {
    match decode_png(data, LIMIT) {
        Ok(img) => {
            prop_assert!((img.width * img.height) as u64 <= LIMIT);
            prop_assert!((1..=4).contains(&img.channels));
        }
        Err(Error::TooLarge { pixels, limit, .. }) => prop_assert!(pixels > limit),
        Err(e) => prop_assert!(!e.to_string().contains('\n')),
    }
    Ok(())
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn hostile_headers_never_panic(
        w in prop_oneof![0u32..40, Just(u32::MAX), Just(1 << 31), any::<u32>()],
        h in prop_oneof![0u32..40, Just(u32::MAX), any::<u32>()],
        depth in prop_oneof![Just(1u8), Just(2), Just(4), Just(8), Just(16), any::<u8>()],
        colour in prop_oneof![Just(0u8), Just(2), Just(3), Just(4), Just(6), any::<u8>()],
        interlace in 0u8..3,
        raw in proptest::collection::vec(any::<u8>(), 0..2000),
    ) {
        check(&png(w, h, depth, colour, interlace, &raw))?;
    }

    #[test]
    fn mutated_valid_files_never_panic(
        w in 1u32..30, h in 1u32..30, interlace in 0u8..2,
        flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 0..6),
        cut in any::<prop::sample::Index>(),
        do_cut in any::<bool>(),
    ) {
        let raw: Vec<u8> = (0..h).flat_map(|y| {
            std::iter::once(0u8).chain((0..w).map(move |x| (x * 7 + y * 13) as u8))
        }).collect();
        let mut data = png(w, h, 8, 0, interlace, &raw);
        if interlace == 0 {
            prop_assert!(decode_png(&data, LIMIT).is_ok());
        }
        for (at, value) in flips {
            let i = at.index(data.len());
            data[i] ^= value;
        }
        if do_cut {
            data.truncate(cut.index(data.len() + 1));
        }
        check(&data)?;
    }
}
