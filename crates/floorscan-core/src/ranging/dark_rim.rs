//! A lens's dark rim: the corners of an image outside a fisheye's image circle are unlit. A
//! column whose start row the table gives no ground is scanned from that row (the paper's
//! ranger takes the bottom rows for floor); where those rows are the dark rim instead, the
//! step from black to floor at the circle would read as an obstacle touching the robot. Such a
//! column is scanned from its first row with ground instead, decided per frame from the pixels
//! at its start row.

/// Rows from a column's start row up that must be dark for the column to start above them.
pub const DARK_RIM_ROWS: usize = 2;

/// Whether the `DARK_RIM_ROWS` pixels from `start_row` up (`value(v)`, the brightest channel
/// at row v) are the dark rim below floor whose brightness at the first row with ground is
/// `floor_value`: each at most 1/16 of full scale `max` and at most a quarter of the floor's,
/// the floor itself brighter than 1/64 of full scale. (A camera's black level may sit above
/// zero, and a dim frame's floor may be dark; a black frame has no rim to tell; 12-bit data
/// in 16-bit pixels still has one.)
pub fn is_dark_rim(
    start_row: usize,
    floor_value: i32,
    max: i32,
    mut value: impl FnMut(usize) -> i32,
) -> bool {
    floor_value > max / 64
        && (0..DARK_RIM_ROWS.min(start_row + 1)).all(|i| {
            let v = value(start_row - i);
            v <= max / 16 && 4 * v <= floor_value
        })
}

#[cfg(test)]
mod tests {
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
}
