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
#[path = "dark_rim_tests.rs"]
mod tests;
