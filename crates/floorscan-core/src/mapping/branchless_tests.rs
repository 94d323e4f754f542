//! Tests of the `branchless` module.

use super::*;

fn reference(value: i16, stamp: u16, generation: u16, miss: i16, lower: i16) -> i16 {
    if stamp != generation {
        (value + miss).max(lower)
    } else {
        value
    }
}

#[test]
fn matches_the_plain_rule() {
    let values = [
        -16_000i16, -2001, -2000, -1999, -400, -1, 0, 1, 399, 400, 3500, 16_000,
    ];
    let stamps = [0u16, 1, 2, 0x8000, 0xFFFF];
    for &v in &values {
        for &s in &stamps {
            for &g in &stamps {
                for &miss in &[-16_000i16, -400, -1] {
                    for &lo in &[-16_000i16, -2000, -1] {
                        assert_eq!(
                            free_update(v, s, g, miss, lo),
                            reference(v, s, g, miss, lo),
                            "{v} {s} {g} {miss} {lo}"
                        );
                    }
                }
            }
        }
    }
}
