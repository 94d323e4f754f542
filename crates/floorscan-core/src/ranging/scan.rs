//! One frame's output of the visual range sensor: a reading per sampled image column, and its
//! conversions to a laser-like fixed angular binning (REP 117) and to the public scans CSV.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};
use crate::pose::Point2;

/// What a column saw. Names follow the public CSV (`status` column).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ColumnStatus {
    /// The floor boundary was found and has a ground point.
    Boundary,
    /// No edge up to the column's top limit: free as far as the camera sees.
    NoBoundary,
    /// The edge is already in the first window at the bottom: the robot is too close to see floor.
    TooClose,
    /// The column cannot be used: its start or its boundary row has no ground point.
    Invalid,
}

impl ColumnStatus {
    pub const ALL: [ColumnStatus; 4] = [
        ColumnStatus::Boundary,
        ColumnStatus::NoBoundary,
        ColumnStatus::TooClose,
        ColumnStatus::Invalid,
    ];

    /// The name used in the CSV and in Python.
    pub fn as_str(self) -> &'static str {
        match self {
            ColumnStatus::Boundary => "boundary",
            ColumnStatus::NoBoundary => "no_boundary",
            ColumnStatus::TooClose => "too_close",
            ColumnStatus::Invalid => "invalid",
        }
    }

    /// Small integer code used in numpy arrays (`0..=3`, in the order of [`Self::ALL`]).
    pub fn code(self) -> u8 {
        self as u8
    }

    pub fn from_code(code: u8) -> Option<Self> {
        Self::ALL.get(code as usize).copied()
    }

    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.as_str() == name)
    }
}

/// What one column found, with the data each outcome carries (and nothing it does not).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum ColumnOutcome {
    /// `row`: image row of the boundary [px, float, v = 0 at the top]; `point`: its ground
    /// point in the camera ground frame [m]; `footprint_m`: the length of floor one pixel row
    /// covers there [m] (the range resolution of the reading; 0 if unknown).
    Boundary {
        row: f64,
        point: Point2,
        footprint_m: f64,
    },
    /// Scanned up to `top_row` [px] without an edge; `farthest` is the ground point there [m].
    NoBoundary { top_row: f64, farthest: Point2 },
    /// The first window at the bottom already holds an edge.
    TooClose,
    /// No row from the column's start up has a ground point, or the edge found above the first
    /// window has none (in rows below the column's first row with ground); `row` is the row
    /// found, if any.
    Invalid { row: Option<f64> },
}

/// One sampled column of one frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ColumnReading {
    /// Image column u [px].
    pub column: u32,
    /// Row [px] where the column's scan starts (the nearest floor it looks at).
    pub start_row: f64,
    /// Ground point [m] of the column's lowest row with ground, at or above the start row
    /// (the start row's own where it has one), `None` if there is none: the near edge of the
    /// column's field of view on the floor. The map builder starts free space here.
    pub near: Option<Point2>,
    pub outcome: ColumnOutcome,
    /// How sure the ranger is of the outcome, in [0, 1] (edge ranger: how far the edge response
    /// cleared the threshold; appearance ranger: the floor / not-floor margin; 1 when unknown).
    #[serde(default = "full_confidence")]
    pub confidence: f32,
}

fn full_confidence() -> f32 {
    1.0
}

impl ColumnReading {
    pub fn status(&self) -> ColumnStatus {
        match self.outcome {
            ColumnOutcome::Boundary { .. } => ColumnStatus::Boundary,
            ColumnOutcome::NoBoundary { .. } => ColumnStatus::NoBoundary,
            ColumnOutcome::TooClose => ColumnStatus::TooClose,
            ColumnOutcome::Invalid { .. } => ColumnStatus::Invalid,
        }
    }

    /// Image row reported for the column: the boundary row, the top row scanned, the start row
    /// (too close), or the row found (invalid; NaN if none).
    pub fn row(&self) -> f64 {
        match self.outcome {
            ColumnOutcome::Boundary { row, .. } => row,
            ColumnOutcome::NoBoundary { top_row, .. } => top_row,
            ColumnOutcome::TooClose => self.start_row,
            ColumnOutcome::Invalid { row } => row.unwrap_or(f64::NAN),
        }
    }

    /// The ground point the reading refers to: boundary point, farthest free point, or the near
    /// edge of the field of view (too close).
    pub fn point(&self) -> Option<Point2> {
        match self.outcome {
            ColumnOutcome::Boundary { point, .. } => Some(point),
            ColumnOutcome::NoBoundary { farthest, .. } => Some(farthest),
            ColumnOutcome::TooClose => self.near,
            ColumnOutcome::Invalid { .. } => None,
        }
    }

    /// Range [m] in REP 117 form: finite for a boundary, +inf for no return, -inf for too
    /// close, NaN for invalid.
    pub fn range_m(&self) -> f64 {
        match self.outcome {
            ColumnOutcome::Boundary { point, .. } => point.norm(),
            ColumnOutcome::NoBoundary { .. } => f64::INFINITY,
            ColumnOutcome::TooClose => f64::NEG_INFINITY,
            ColumnOutcome::Invalid { .. } => f64::NAN,
        }
    }

    /// Bearing [rad] = atan2(y, x) of [`Self::point`], NaN without one.
    pub fn bearing_rad(&self) -> f64 {
        self.point().map_or(f64::NAN, |p| p.bearing())
    }
}

/// The readings of one frame, in the order the columns were sampled.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Scan {
    /// Frame time [s].
    pub timestamp_s: f64,
    pub readings: Vec<ColumnReading>,
}

/// The header of the public scans CSV (one line per column reading).
pub const SCAN_CSV_HEADER: &str = "timestamp,column,row,status,x,y,range,bearing";

/// A laser-scan-like fixed angular binning of a scan (the fields of `sensor_msgs/LaserScan`).
#[derive(Debug, Clone, PartialEq)]
pub struct LaserBins {
    pub angle_min_rad: f64,
    pub angle_max_rad: f64,
    pub angle_increment_rad: f64,
    pub range_min_m: f64,
    pub range_max_m: f64,
    /// One range per bin [m]: the nearest boundary in the bin, +inf for no return (REP 117).
    pub ranges_m: Vec<f64>,
}

impl Scan {
    pub fn len(&self) -> usize {
        self.readings.len()
    }
    pub fn is_empty(&self) -> bool {
        self.readings.is_empty()
    }

    /// Bins the boundary points by bearing into `[angle_min, angle_max]` in steps of
    /// `increment` (all radians). Each bin holds the nearest boundary range inside it; a bin that
    /// a `no_boundary` column falls in, with no boundary, is +inf; a bin that only too-close
    /// columns fall in is -inf; a bin no column covers is +inf (no return).
    pub fn to_laser_bins(
        &self,
        angle_min_rad: f64,
        angle_max_rad: f64,
        increment_rad: f64,
    ) -> Result<LaserBins> {
        if !(angle_min_rad.is_finite()
            && angle_max_rad.is_finite()
            && angle_max_rad > angle_min_rad)
        {
            return Err(invalid_option(
                "angle_max",
                "must be finite and greater than angle_min",
            ));
        }
        if !(increment_rad > 0.0 && increment_rad.is_finite()) {
            return Err(invalid_option("angle_increment", "must be finite and > 0"));
        }
        let n = ((angle_max_rad - angle_min_rad) / increment_rad).round() as usize + 1;
        if n > 1_000_000 {
            return Err(invalid_option(
                "angle_increment",
                "gives more than 10^6 bins",
            ));
        }
        let mut ranges = vec![f64::INFINITY; n];
        let mut has_boundary = vec![false; n];
        let mut range_min = f64::INFINITY;
        let mut range_max: f64 = 0.0;
        for r in &self.readings {
            let bearing = r.bearing_rad();
            if !bearing.is_finite() {
                continue;
            }
            let bin = ((bearing - angle_min_rad) / increment_rad).round();
            if bin < 0.0 || bin >= n as f64 {
                continue;
            }
            let b = bin as usize;
            match r.outcome {
                ColumnOutcome::Boundary { point, .. } => {
                    let range = point.norm();
                    if !has_boundary[b] || range < ranges[b] {
                        ranges[b] = range;
                    }
                    has_boundary[b] = true;
                    range_min = range_min.min(range);
                    range_max = range_max.max(range);
                }
                ColumnOutcome::NoBoundary { farthest, .. } => {
                    range_max = range_max.max(farthest.norm());
                }
                ColumnOutcome::TooClose => {
                    if !has_boundary[b] {
                        ranges[b] = f64::NEG_INFINITY;
                    }
                    if let Some(p) = r.near {
                        range_min = range_min.min(p.norm());
                    }
                }
                ColumnOutcome::Invalid { .. } => {}
            }
        }
        Ok(LaserBins {
            angle_min_rad,
            angle_max_rad: angle_min_rad + (n - 1) as f64 * increment_rad,
            angle_increment_rad: increment_rad,
            range_min_m: if range_min.is_finite() {
                range_min
            } else {
                0.0
            },
            range_max_m: range_max,
            ranges_m: ranges,
        })
    }

    /// Appends this scan's CSV lines (no header) to `out`. Non-finite values are written as
    /// `nan`, `inf` and `-inf`, which Python's `float()` and numpy read back.
    pub fn write_csv_lines(&self, out: &mut String) {
        use std::fmt::Write;
        for r in &self.readings {
            let (x, y) = r.point().map_or((f64::NAN, f64::NAN), |p| (p.x, p.y));
            let _ = writeln!(
                out,
                "{},{},{},{},{},{},{},{}",
                fmt_f64(self.timestamp_s),
                r.column,
                fmt_f64(r.row()),
                r.status().as_str(),
                fmt_f64(x),
                fmt_f64(y),
                fmt_f64(r.range_m()),
                fmt_f64(r.bearing_rad()),
            );
        }
    }
}

fn fmt_f64(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v == f64::INFINITY {
        "inf".into()
    } else if v == f64::NEG_INFINITY {
        "-inf".into()
    } else {
        // Shortest representation that round-trips.
        format!("{v}")
    }
}

#[cfg(test)]
#[path = "scan_tests.rs"]
mod tests;
