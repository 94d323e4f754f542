//! Tests of the `floor_model` module.

use super::*;

/// A colour bin's (intensity, chroma 1, chroma 2) indices.
fn coords(b: usize) -> (i64, i64, i64) {
    let (i, r) = (
        b / (CHROMA_BINS * CHROMA_BINS),
        b % (CHROMA_BINS * CHROMA_BINS),
    );
    (i as i64, (r / CHROMA_BINS) as i64, (r % CHROMA_BINS) as i64)
}

#[test]
fn bins_cover_their_ranges() {
    assert_eq!(colour_bin([0, 0, 0]), (6 * CHROMA_BINS) + 6);
    assert!(colour_bin([255, 255, 255]) < COLOUR_BINS);
    assert!(colour_bin([255, 0, 0]) < COLOUR_BINS);
    assert!(colour_bin([0, 0, 255]) < COLOUR_BINS);
    assert_eq!(texture_bin(0), 0);
    assert_eq!(texture_bin(1000), TEXTURE_BINS - 1);
}

#[test]
fn share_counts_neighbours_within_one_bin_by_brute_force() {
    let mut m = FloorModel::default();
    m.begin_frame();
    let pixels = [[10, 10, 10], [40, 10, 200], [200, 100, 50], [30, 20, 10]];
    for p in pixels {
        m.add(colour_bin(p), 0);
    }
    m.finish_frame(1.0, 0.3, 1);
    for b in 0..COLOUR_BINS {
        let (i, a, c) = coords(b);
        let near = pixels
            .iter()
            .filter(|p| {
                let (pi, pa, pc) = coords(colour_bin(**p));
                (pi - i).abs() <= 1 && (pa - a).abs() <= 1 && (pc - c).abs() <= 1
            })
            .count();
        assert!(
            (m.colour_share(b) - near as f32 / 4.0).abs() < 1e-6,
            "bin {b}"
        );
        assert_eq!(m.is_floor(b, None), near as f32 / 4.0 >= 0.3);
    }
}

#[test]
fn the_model_blends_frames_at_the_adaptation_rate() {
    let mut m = FloorModel::default();
    let (a, b) = (colour_bin([50, 50, 50]), colour_bin([200, 200, 200]));
    m.begin_frame();
    m.add(a, 0);
    m.finish_frame(0.25, 0.5, 1);
    m.begin_frame();
    m.add(b, 0);
    m.finish_frame(0.25, 0.5, 1);
    assert!((m.colour_share(a) - 0.75).abs() < 1e-6);
    assert!((m.colour_share(b) - 0.25).abs() < 1e-6);
    assert!(m.is_floor(a, Some(0)) && !m.is_floor(b, Some(0)));
    assert!(!m.is_floor(a, Some(5)), "texture bin never seen");
    m.reset();
    assert!(!m.is_floor(a, None));
}

#[test]
fn driven_samples_mark_their_neighbourhood_as_floor_and_fade() {
    let mut m = FloorModel::default();
    let (floor, rug) = (colour_bin([60, 60, 60]), colour_bin([180, 40, 40]));
    m.begin_frame();
    m.add(floor, 0);
    m.finish_frame(0.5, 0.5, 1);
    assert!(!m.is_floor(rug, Some(0)));
    for _ in 0..3 {
        m.add_driven(rug, 5, 1);
    }
    // by brute force: every bin within one (chroma) / reach (intensity) of the rug holds 3
    let (ri, ra, rb) = coords(rug);
    for b in 0..COLOUR_BINS {
        let (i, a, c) = coords(b);
        let near = (i - ri).abs() <= 1 && (a - ra).abs() <= 1 && (c - rb).abs() <= 1;
        assert_eq!(m.driven_colour(b), if near { 3.0 } else { 0.0 }, "bin {b}");
    }
    m.apply_driven(1.0, 3.0);
    assert!(m.is_floor(rug, Some(5)) && m.is_floor(rug, Some(4)) && m.is_floor(floor, Some(0)));
    assert!(!m.is_floor(rug, Some(7)), "texture bin two away");
    // a new frame recomputes the reference's bins; the driven ones stay while they last
    m.begin_frame();
    m.add(floor, 0);
    m.finish_frame(0.5, 0.5, 1);
    m.apply_driven(0.5, 3.0); // 3 -> 1.5 samples: below the minimum
    assert!(!m.is_floor(rug, Some(5)));
    assert!((m.driven_colour(rug) - 1.5).abs() < 1e-6);
    m.reset();
    assert_eq!(m.driven_colour(rug), 0.0);
}
