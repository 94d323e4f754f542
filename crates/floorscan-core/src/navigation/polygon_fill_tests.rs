//! Tests of the `polygon_fill` module.

use super::*;

fn filled<const N: usize>(w: usize, h: usize, quad: [[i64; 2]; N], shift: u32) -> Vec<u8> {
    let mut cells = vec![0u8; w * h];
    let mut c = Canvas {
        cells: &mut cells,
        width: w,
        height: h,
    };
    PolygonFill::default().fill(&mut c, &[quad], shift, 1);
    cells
}

#[test]
fn an_axis_aligned_square_fills_its_cells() {
    // corners on cell centres 2..=5 (shift 0): the 4 x 4 cells, nothing else
    let cells = filled(8, 8, [[2, 2], [5, 2], [5, 5], [2, 5]], 0);
    for j in 0..8 {
        for i in 0..8 {
            let inside = (2..=5).contains(&i) && (2..=5).contains(&j);
            assert_eq!(cells[j * 8 + i] == 1, inside, "cell {i} {j}");
        }
    }
}

#[test]
fn a_triangle_covers_every_cell_whose_centre_is_inside_and_little_more() {
    // every cell whose centre lies strictly inside is filled; the rest is the outline
    let tri = [[16 * 3, 16 * 2], [16 * 30, 16 * 7], [16 * 9, 16 * 25]];
    let cells = filled(40, 40, tri, 4);
    let p: Vec<[f64; 2]> = tri
        .iter()
        .map(|v| [v[0] as f64 / 16.0, v[1] as f64 / 16.0])
        .collect();
    let side = |a: [f64; 2], b: [f64; 2], q: [f64; 2]| {
        (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0])
    };
    for j in 0..40 {
        for i in 0..40 {
            let q = [i as f64, j as f64];
            let s = [
                side(p[0], p[1], q),
                side(p[1], p[2], q),
                side(p[2], p[0], q),
            ];
            let strictly_inside = s.iter().all(|&v| v > 1e-9) || s.iter().all(|&v| v < -1e-9);
            if strictly_inside {
                assert_eq!(cells[j * 40 + i], 1, "inside cell {i} {j} not filled");
            }
        }
    }
    let count = cells.iter().filter(|&&c| c == 1).count() as f64;
    // area 0.5 |cross| = 0.5 * |27 * 23 - 5 * 6| = 295.5 cells, plus the outline
    assert!(count > 295.5 && count < 295.5 + 2.0 * 70.0, "{count}");
}

#[test]
fn vertices_far_outside_are_clipped_without_overflow_or_long_loops() {
    let big = i64::MAX / 4;
    let cells = filled(
        10,
        10,
        [[-big, -big], [big, -big], [big, big], [-big, big]],
        4,
    );
    assert!(cells.iter().all(|&c| c == 1));
    let cells = filled(
        10,
        10,
        [[-big, -big], [-big + 5, -big], [-big, -big + 5]],
        4,
    );
    assert!(cells.iter().all(|&c| c == 0));
}

#[test]
fn overlapping_polygons_of_one_call_cancel_inside_their_outlines() {
    // two squares overlapping in 4..=6 x 2..=8 (shift 0): even-odd over both edge sets
    // leaves the overlap's inside empty (as OpenCV's fillPoly), outlines drawn
    let mut cells = vec![0u8; 12 * 12];
    let mut c = Canvas {
        cells: &mut cells,
        width: 12,
        height: 12,
    };
    let a = [[1, 2], [6, 2], [6, 8], [1, 8]];
    let b = [[4, 2], [9, 2], [9, 8], [4, 8]];
    PolygonFill::default().fill(&mut c, &[a, b], 0, 1);
    assert_eq!(cells[5 * 12 + 2], 1); // only in a
    assert_eq!(cells[5 * 12 + 8], 1); // only in b
    assert_eq!(cells[5 * 12 + 5], 0); // in both, off the outlines
    assert_eq!(cells[5 * 12 + 4], 1); // b's left edge
}
