//! Tests of the `image` module.

use super::*;

#[test]
fn strided_view_reads_the_right_pixels() {
    let data: Vec<u8> = (0..24).collect();
    // Every other column of a 4 x 6 buffer.
    let view = ImageView::with_strides(&data, 3, 4, 6, 2).unwrap();
    assert_eq!(view.get(0, 0), 0);
    assert_eq!(view.get(2, 3), 22);
    assert_eq!(view.row(1)[2], 8);
}

#[test]
fn too_small_buffer_and_empty_image_are_errors() {
    let data = [0u8; 10];
    assert!(matches!(
        ImageView::new(&data, 4, 3),
        Err(Error::InvalidImage(_))
    ));
    assert!(matches!(
        ImageView::new(&data, 0, 3),
        Err(Error::InvalidImage(_))
    ));
}
