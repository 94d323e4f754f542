//! Tests of the `dark_rim` module.

use super::*;

#[test]
fn black_below_lit_floor_is_rim_and_dark_floor_is_not() {
    // Rows 9 and 8 black (2), floor 80: the rim.
    assert!(is_dark_rim(9, 80, 255, |_| 2));
    // The same black under a floor hardly brighter (a dim frame): not told apart.
    assert!(!is_dark_rim(9, 6, 255, |_| 2));
    // One lit row among the two: not rim.
    assert!(!is_dark_rim(9, 80, 255, |v| if v == 8 { 40 } else { 2 }));
    // A camera whose black level is 12 of 255: still rim under an 80 floor.
    assert!(is_dark_rim(9, 80, 255, |_| 12));
    // Twice that is not dark.
    assert!(!is_dark_rim(9, 80, 255, |_| 24));
    // 16-bit pixels with 12-bit data: 40 is dark under a floor of 1200 ...
    assert!(is_dark_rim(9, 1200, 65535, |_| 40));
    // ... but under a floor of 1000 (< 65535 / 64) nothing is told.
    assert!(!is_dark_rim(9, 1000, 65535, |_| 40));
    // A black frame (lens cap, lights off): no rim.
    assert!(!is_dark_rim(9, 0, 255, |_| 0));
}
