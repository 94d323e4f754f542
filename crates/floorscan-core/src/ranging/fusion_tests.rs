//! Tests of [`super`] (fusion.rs).

use super::*;
use crate::pose::Point2;
use crate::scan::ColumnReading;

fn reading(column: u32, outcome: ColumnOutcome) -> ColumnReading {
    ColumnReading {
        column,
        start_row: 100.0,
        near: Some(Point2::new(0.3, 0.0)),
        outcome,
        confidence: 0.5,
    }
}
fn boundary(column: u32, row: f64) -> ColumnReading {
    reading(
        column,
        ColumnOutcome::Boundary {
            row,
            point: Point2::new(row, 0.0),
            footprint_m: 0.0,
        },
    )
}

#[test]
fn the_edge_refines_a_nearby_appearance_boundary_and_is_ignored_elsewhere() {
    let edge = Scan {
        timestamp_s: 1.0,
        readings: vec![
            boundary(0, 50.2), // 0.8 rows from appearance's: edge wins
            boundary(1, 90.0), // a grout line far below: appearance wins
            boundary(2, 99.0), // too close by appearance, an edge at the start
            reading(
                3,
                ColumnOutcome::NoBoundary {
                    top_row: 0.0,
                    farthest: Point2::new(3.0, 0.0),
                },
            ),
        ],
    };
    let appearance = Scan {
        timestamp_s: 1.0,
        readings: vec![
            boundary(0, 49.4),
            boundary(1, 40.5),
            reading(2, ColumnOutcome::TooClose),
            boundary(3, 20.5),
        ],
    };
    let mut out = Scan::default();
    fuse_scans(&edge, &appearance, 2.0, 1.0, &mut out).unwrap();
    assert_eq!(out.readings[0], edge.readings[0]);
    assert_eq!(out.readings[1], appearance.readings[1]);
    assert_eq!(out.readings[2], edge.readings[2]);
    assert_eq!(out.readings[3], appearance.readings[3]);
    // The appearance ranger saw only floor: the edge ranger's boundary stands.
    let mut app2 = appearance.clone();
    app2.readings[1] = reading(
        1,
        ColumnOutcome::NoBoundary {
            top_row: 0.0,
            farthest: Point2::new(3.0, 0.0),
        },
    );
    fuse_scans(&edge, &app2, 2.0, 1.0, &mut out).unwrap();
    assert_eq!(out.readings[1], edge.readings[1]);
    let short = Scan {
        timestamp_s: 1.0,
        readings: vec![boundary(0, 1.0)],
    };
    assert!(fuse_scans(&edge, &short, 2.0, 1.0, &mut out).is_err());
    assert!(fuse_scans(&edge, &appearance, f64::NAN, 1.0, &mut out).is_err());
    assert!(fuse_scans(&edge, &appearance, 2.0, 1.5, &mut out).is_err());
    assert!(fuse_scans(&edge, &appearance, 2.0, f64::NAN, &mut out).is_err());
}

#[test]
fn a_frame_of_floor_pattern_trusts_the_appearance_rangers_floor() {
    // Four boundary columns by the edge ranger: two far below appearance boundaries (a
    // pattern), one agreeing, one where the appearance ranger saw only floor.
    let nb = || ColumnOutcome::NoBoundary {
        top_row: 0.0,
        farthest: Point2::new(3.0, 0.0),
    };
    let edge = Scan {
        timestamp_s: 1.0,
        readings: vec![
            boundary(0, 90.0),
            boundary(1, 85.0),
            boundary(2, 50.0),
            boundary(3, 70.0),
            reading(4, ColumnOutcome::TooClose),
            reading(5, ColumnOutcome::Invalid { row: Some(95.0) }),
        ],
    };
    let appearance = Scan {
        timestamp_s: 1.0,
        readings: vec![
            boundary(0, 40.0),
            boundary(1, 42.0),
            boundary(2, 49.5),
            reading(3, nb()),
            reading(4, nb()),
            reading(5, nb()),
        ],
    };
    // 2 of 4 edge boundaries lie below the appearance boundary by more than the snap
    assert_eq!(texture_edge_share(&edge, &appearance, 3.0), 0.5);
    let mut out = Scan::default();
    fuse_scans(&edge, &appearance, 3.0, 0.4, &mut out).unwrap();
    // textured: the floor stands; agreement still snaps to the edge
    assert_eq!(out.readings[3], appearance.readings[3]);
    assert_eq!(out.readings[2], edge.readings[2]);
    // a too-close edge and an edge in rows without ground (a corner the table does not
    // cover) under floor the appearance ranger recognises are pattern too
    assert_eq!(out.readings[4], appearance.readings[4]);
    assert_eq!(out.readings[5], appearance.readings[5]);
    fuse_scans(&edge, &appearance, 3.0, 0.5, &mut out).unwrap();
    assert_eq!(out.readings[3], edge.readings[3]); // not above the share: the edge stands
    assert_eq!(out.readings[4], edge.readings[4]); // and a too-close edge stays
    assert_eq!(out.readings[5], edge.readings[5]);
    let none = Scan {
        timestamp_s: 1.0,
        readings: vec![reading(0, nb())],
    };
    assert_eq!(texture_edge_share(&none, &none, 3.0), 0.0);
}

/// The judgement after a frame that follows a (fresh) judgement `previous`.
fn frame_textured(
    edge: &Scan,
    appearance: &Scan,
    snap_rows: f64,
    texture_share: f64,
    previous: bool,
) -> bool {
    let before = TextureState {
        textured: previous,
        frames_inherited: 0,
    };
    before
        .after(edge, appearance, snap_rows, texture_share)
        .textured
}

#[test]
fn a_frame_without_appearance_boundaries_keeps_the_floors_judgement() {
    // The edge ranger stops at a grout line in every column; the appearance ranger sees
    // floor throughout: no column where both found a boundary, so the frame cannot tell
    // a pattern from obstacles that look like the floor.
    let nb = || ColumnOutcome::NoBoundary {
        top_row: 0.0,
        farthest: Point2::new(3.0, 0.0),
    };
    let edge = Scan {
        timestamp_s: 1.0,
        readings: (0..6).map(|c| boundary(c, 90.0)).collect(),
    };
    let floor = Scan {
        timestamp_s: 1.0,
        readings: (0..6).map(|c| reading(c, nb())).collect(),
    };
    let mut out = Scan::default();
    let textured = TextureState {
        textured: true,
        frames_inherited: 0,
    };
    // After a textured floor: still textured, the appearance ranger's floor stands ...
    let mut s = textured;
    for k in 1..=TEXTURE_MEMORY_FRAMES {
        s = fuse_scans_after(&edge, &floor, 3.0, 0.15, s, &mut out).unwrap();
        assert!(s.textured && s.frames_inherited == k);
        assert_eq!(out.readings, floor.readings);
    }
    // ... for TEXTURE_MEMORY_FRAMES frames in a row, then it lapses to plain.
    s = fuse_scans_after(&edge, &floor, 3.0, 0.15, s, &mut out).unwrap();
    assert_eq!(s, TextureState::default());
    assert_eq!(out.readings, edge.readings);
    // After a plain floor, or on its own: the edge ranger's boundaries stand.
    let plain = TextureState::default();
    let s = fuse_scans_after(&edge, &floor, 3.0, 0.15, plain, &mut out).unwrap();
    assert!(!s.textured);
    assert_eq!(out.readings, edge.readings);
    fuse_scans(&edge, &floor, 3.0, 0.15, &mut out).unwrap();
    assert_eq!(out.readings, edge.readings);
    // With texture_share 1 (off) a textured past counts for nothing.
    let s = fuse_scans_after(&edge, &floor, 3.0, 1.0, textured, &mut out).unwrap();
    assert!(!s.textured);
    // A frame with evidence decides for itself: MIN_TEXTURE_EVIDENCE (3) of the 6 edge
    // boundary columns compared, none far apart: plain, whatever came before.
    let mut app = floor.clone();
    for c in 0..MIN_TEXTURE_EVIDENCE {
        app.readings[c] = boundary(c as u32, 89.5);
    }
    assert!(!frame_textured(&edge, &app, 3.0, 0.15, true));
    // ... and with them far above the edges: textured, whatever came before.
    for c in 0..MIN_TEXTURE_EVIDENCE {
        app.readings[c] = boundary(c as u32, 40.0);
    }
    assert!(frame_textured(&edge, &app, 3.0, 0.15, false));
    // One column fewer is no evidence.
    app.readings[0] = reading(0, nb());
    assert!(frame_textured(&edge, &app, 3.0, 0.15, true));
    assert!(!frame_textured(&edge, &app, 3.0, 0.15, false));
    // Nor are 3 compared columns among 40 edge boundaries (7.5 %): had every one of them
    // lain below its appearance boundary, the share could not pass 0.15.
    let many = Scan {
        timestamp_s: 1.0,
        readings: (0..40).map(|c| boundary(c, 90.0)).collect(),
    };
    let mut few = Scan {
        timestamp_s: 1.0,
        readings: (0..40).map(|c| reading(c, nb())).collect(),
    };
    for c in 0..3 {
        few.readings[c] = boundary(c as u32, 89.5);
    }
    assert!(frame_textured(&many, &few, 3.0, 0.15, true));
    assert!(!frame_textured(&many, &few, 3.0, 0.15, false));
    // 7 of 40 (17.5 %) could: the frame decides (plain here).
    for c in 0..7 {
        few.readings[c] = boundary(c as u32, 89.5);
    }
    assert!(!frame_textured(&many, &few, 3.0, 0.15, true));
}

#[test]
fn an_edge_at_the_border_of_driven_over_floor_is_not_an_obstacle() {
    let no = |c: u32| {
        reading(
            c,
            ColumnOutcome::NoBoundary {
                top_row: 10.0,
                farthest: Point2::new(3.0, 0.0),
            },
        )
    };
    let edge = Scan {
        timestamp_s: 0.0,
        readings: vec![boundary(0, 60.0), boundary(1, 60.0)],
    };
    let appearance = Scan {
        timestamp_s: 0.0,
        readings: vec![no(0), no(1)],
    };
    let mut out = Scan::default();
    let previous = TextureState::default();
    // column 1's edge lies on the border of driven-over floor (row 61.5, within the snap
    // distance): that border, not an obstacle; column 0's border is far from its edge
    let borders = [40.0, 61.5];
    fuse_scans_driven(&edge, &appearance, 3.0, 0.15, previous, &borders, &mut out).unwrap();
    assert_eq!(out.readings[0], edge.readings[0]);
    assert_eq!(out.readings[1], appearance.readings[1]);
    let none = [f64::NAN, f64::NAN];
    fuse_scans_driven(&edge, &appearance, 3.0, 0.15, previous, &none, &mut out).unwrap();
    assert_eq!(out.readings[1], edge.readings[1]);
    // without the flags: the edge in both (an obstacle of the floor's look)
    fuse_scans_after(&edge, &appearance, 3.0, 0.15, previous, &mut out).unwrap();
    assert_eq!(out.readings[1], edge.readings[1]);
    assert!(matches!(
        fuse_scans_driven(&edge, &appearance, 3.0, 0.15, previous, &[60.0], &mut out),
        Err(Error::LengthMismatch(_))
    ));
}
