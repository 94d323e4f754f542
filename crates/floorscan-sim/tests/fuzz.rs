//! Fuzzing the world file parser (issue 12): the built-in worlds' TOML with bytes mutated and
//! numbers replaced by hostile values. Property: a typed error, or a world whose scene builds
//! without a panic and whose geometry stays within MAX_WORLD_EXTENT_M (so no index or raster
//! sized by the world can take gigabytes).
//!
//! `cargo test` runs a fixed-seed corpus; `make fuzz` sets FLOORSCAN_FUZZ=1 and PROPTEST_CASES.

use floorscan_sim::world::MAX_WORLD_EXTENT_M;
use floorscan_sim::world_file::parse_world;
use floorscan_sim::Scene;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

const ROOM: &str = include_str!("../worlds/room.toml");
const LAB: &str = include_str!("../worlds/lab.toml");

fn config() -> Config {
    let base = Config::default();
    if std::env::var_os("FLOORSCAN_FUZZ").is_some() {
        Config {
            failure_persistence: None,
            ..base
        }
    } else {
        Config {
            cases: 64,
            rng_seed: RngSeed::Fixed(0x1551_0012),
            failure_persistence: None,
            ..base
        }
    }
}

/// Replaces the `k`-th number-looking token of `text` by `value`.
fn replace_number(text: &str, k: usize, value: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut seen = 0usize;
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i] as char;
        let starts = c.is_ascii_digit() && (i == 0 || !(bytes[i - 1] as char).is_alphanumeric());
        if starts {
            let mut j = i;
            while j < bytes.len() && ((bytes[j] as char).is_ascii_digit() || bytes[j] == b'.') {
                j += 1;
            }
            if seen == k {
                out.push_str(value);
            } else {
                out.push_str(&text[i..j]);
            }
            seen += 1;
            i = j;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn hostile_value() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("1e12".to_string()),
        Just("1e300".to_string()),
        Just("0".to_string()),
        Just("0.0".to_string()),
        Just("1e-12".to_string()),
        Just("2000.0".to_string()),
        Just("2001.0".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("18446744073709551615".to_string()),
        (0u32..100_000).prop_map(|v| v.to_string()),
    ]
}

fn check(text: &str) {
    if let Ok(world) = parse_world(text, "fuzz") {
        let b = world.bounds();
        for v in [b.min.x, b.min.y, b.max.x, b.max.y] {
            assert!(v.abs() <= MAX_WORLD_EXTENT_M + 10.0, "{v}");
        }
        let _ = Scene::new(world);
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn world_numbers_replaced_never_panic(
        lab in any::<bool>(),
        edits in proptest::collection::vec((0usize..400, hostile_value()), 1..4),
    ) {
        let mut text = (if lab { LAB } else { ROOM }).to_string();
        for (k, v) in edits {
            text = replace_number(&text, k, &v);
        }
        check(&text);
    }

    #[test]
    fn world_bytes_mutated_never_panic(
        cuts in proptest::collection::vec((0usize..6000, 0usize..6, any::<u8>()), 1..5),
    ) {
        let mut bytes = ROOM.as_bytes().to_vec();
        for (at, len, b) in cuts {
            let at = at % (bytes.len() + 1);
            let end = (at + len).min(bytes.len());
            bytes.splice(at..end, std::iter::once(b));
        }
        check(&String::from_utf8_lossy(&bytes));
    }
}
