//! Fusing the edge and appearance range sensors column by column: the appearance ranger says
//! where the floor's look ends (it is not fooled by grout lines, wood grain or reflections), the
//! edge ranger places an edge to a fraction of a row and sees obstacles that look like the
//! floor (a grey wall over a grey carpet). The fused reading is the edge reading when the edge
//! ranger found its first edge within `snap_rows` of the appearance boundary (both boundary or
//! too-close) or when the appearance ranger saw nothing but floor (no boundary), and the
//! appearance reading otherwise (an edge far below an appearance boundary is floor texture).
//!
//! A frame whose floor breaks the texture assumption (more than `texture_share` of its edge
//! boundaries lie farther than `snap_rows` below an appearance boundary: grout lines, plank
//! joints, a printed pattern) also gives the appearance ranger's "only floor" columns to the
//! appearance reading where the edge ranger found a boundary, an edge in rows the ground table
//! does not cover, or an edge in its first window (too close): in such a frame an edge where
//! the floor's look does not end is the floor's own pattern (a grout line at the image's
//! bottom), not a grey obstacle on a grey floor. Elsewhere a too-close edge reading stays (the
//! robot may be touching an obstacle).

use crate::error::{Error, Result};
use crate::scan::{ColumnOutcome, Scan};

/// The share of `edge`'s boundary columns whose boundary lies more than `snap_rows` below
/// (nearer than) the appearance boundary of the same column: how much of the frame's floor
/// pattern the edge ranger took for obstacles. 0 without edge boundaries.
pub fn texture_edge_share(edge: &Scan, appearance: &Scan, snap_rows: f64) -> f64 {
    let (mut boundaries, mut below) = (0usize, 0usize);
    for (e, a) in edge.readings.iter().zip(&appearance.readings) {
        if let ColumnOutcome::Boundary { row: re, .. } = e.outcome {
            boundaries += 1;
            if let ColumnOutcome::Boundary { row: ra, .. } = a.outcome {
                below += usize::from(re - ra > snap_rows);
            }
        }
    }
    if boundaries == 0 {
        0.0
    } else {
        below as f64 / boundaries as f64
    }
}

/// Fuses two scans of the same frame and columns into `out` (its buffer reused); a frame
/// whose [`texture_edge_share`] exceeds `texture_share` (in [0, 1]; 1: never) takes the
/// appearance reading where the appearance ranger saw only floor.
pub fn fuse_scans(
    edge: &Scan,
    appearance: &Scan,
    snap_rows: f64,
    texture_share: f64,
    out: &mut Scan,
) -> Result<()> {
    if edge.len() != appearance.len()
        || edge
            .readings
            .iter()
            .zip(&appearance.readings)
            .any(|(a, b)| a.column != b.column)
    {
        return Err(Error::LengthMismatch(
            "the edge and appearance scans must sample the same columns".into(),
        ));
    }
    if !(snap_rows.is_finite() && snap_rows >= 0.0) {
        return Err(crate::error::invalid_option(
            "snap_rows",
            format!("must be finite and >= 0, got {snap_rows}"),
        ));
    }
    if !(0.0..=1.0).contains(&texture_share) {
        return Err(crate::error::invalid_option(
            "texture_share",
            format!("must be in [0, 1], got {texture_share}"),
        ));
    }
    let textured = texture_edge_share(edge, appearance, snap_rows) > texture_share;
    out.timestamp_s = appearance.timestamp_s;
    out.readings.clear();
    out.readings.extend(
        edge.readings
            .iter()
            .zip(&appearance.readings)
            .map(|(e, a)| {
                let agree = match (e.outcome, a.outcome) {
                    (ColumnOutcome::TooClose, ColumnOutcome::TooClose) => true,
                    (
                        ColumnOutcome::Boundary { row: re, .. },
                        ColumnOutcome::Boundary { row: ra, .. },
                    ) => (re - ra).abs() <= snap_rows,
                    (ColumnOutcome::Boundary { row, .. }, ColumnOutcome::TooClose) => {
                        (row - a.start_row).abs() <= snap_rows
                    }
                    // an edge boundary where the floor's look does not end: a grey obstacle on a
                    // grey floor, or in a textured frame the floor's pattern
                    (ColumnOutcome::Boundary { .. }, ColumnOutcome::NoBoundary { .. }) => !textured,
                    // an edge in rows the table gives no ground (a bottom corner): as a boundary
                    (ColumnOutcome::Invalid { row: Some(_) }, ColumnOutcome::NoBoundary { .. }) => {
                        !textured
                    }
                    // a too-close edge stays (the robot may be at an obstacle already) unless
                    // the frame is textured (then a line of the pattern at the image's bottom)
                    (ColumnOutcome::TooClose, ColumnOutcome::NoBoundary { .. }) => !textured,
                    (_, ColumnOutcome::NoBoundary { .. }) => true,
                    _ => false,
                };
                if agree {
                    *e
                } else {
                    *a
                }
            }),
    );
    Ok(())
}

#[cfg(test)]
mod tests {
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
        assert_eq!(out.readings[3], appearance.readings[3]); // textured: the floor stands
        assert_eq!(out.readings[2], edge.readings[2]); // agreement still snaps to the edge
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
}
