//! Options of the correlative scan matcher and of the filter that fuses its matches with
//! odometry (floorscan's `ScanMatcher`, used by the drive loop and by the pipeline's local scan
//! matching): one documented structure, validated when the matcher is built.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};

/// Options of the scan matcher (the persistent hit map, the search, the odometry filter).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct ScanMatcherOptions {
    /// Side of the persistent map [m], centred on the start, in [4, 400]. Default 80 (a floor
    /// of a building; 10 MB at the default cell). Points outside it are neither matched nor
    /// stored.
    pub size_m: f64,
    /// Cell of the persistent map [m/cell], in [0.01, 0.2]. Default 0.025.
    pub cell_size_m: f64,
    /// Width of the likelihood field [m], in (0, 1]. Default 0.05 (the camera's boundary error
    /// within 2 m).
    pub sigma_m: f64,
    /// Half-width of the search window in x and y [m], in [0, 2]. Default 0.15.
    pub search_xy_m: f64,
    /// Half-width of the search window in yaw [rad], in [0, 0.5]. Default 0.15 (odometry's
    /// heading error over a room's excursion).
    pub search_yaw_rad: f64,
    /// Yaw step of the search [rad], in [0.001, 0.1]. Default 0.01 (2.5 cm at 2.5 m).
    pub yaw_step_rad: f64,
    /// Width of the odometry prior in translation [m], > 0. Default 0.3 (weak: a wall seen
    /// before wins, a featureless view keeps odometry).
    pub prior_xy_m: f64,
    /// Width of the odometry prior in yaw [rad], > 0. Default 0.3.
    pub prior_yaw_rad: f64,
    /// Fewest scan points to match, >= 3. Default 40: a scan with fewer (a view across an open
    /// room, a desk's face) is not matched; odometry carries the pose (EVALUATION.md, "More
    /// seeds on the held-out worlds").
    pub min_points: u32,
    /// The best pose's mean field value needed to accept it, in (0, 1). Default 0.35 (about
    /// half the points within 7 cm of a stored hit).
    pub min_score: f64,
    /// Points farther than this [m] are ignored, in (0, 100]. Default 3.0 (the ranger's range).
    pub range_max_m: f64,
    /// A scan point joins the map only when no stored hit lies within this distance [m], in
    /// [0, 1]; 0 stores every point. Default 0.1 (2 sigma).
    pub novelty_m: f64,
    /// At most this many points, evenly spaced along the scan, are matched, in
    /// [`min_points`, 100000]: a bound on the work of one match. Default 400.
    pub max_points: u32,
    /// Scale of the match's covariance (the inverse of the curvature of the summed field
    /// values over x, y, yaw at the pose found) when it is fused with the odometry prediction
    /// as an extended Kalman filter does, in [0, 1e6]; 0 keeps the match as it is (no
    /// fusion). Default 1 (the field's width as each point's error). A corridor informs only
    /// across itself, so its length stays odometry's.
    pub match_variance_scale: f64,
    /// Estimate odometry's systematic errors online (the turn scale error and the heading
    /// drift per metre, two more states of the filter). Default true (only with
    /// `match_variance_scale` > 0).
    pub calibrate_odometry: bool,
    /// Standard deviation of the turn scale error before any match, in [0, 0.5]. Default 0.05.
    pub turn_error_prior: f64,
    /// Standard deviation of the heading drift before any match [rad/m], in [0, 1]. Default
    /// 0.03.
    pub drift_prior_rad_per_m: f64,
    /// How fast the two calibration states may change, in [0, 0.1]: their variances grow by
    /// its square per radian turned and per metre driven. Default 1e-4.
    pub calibration_drift: f64,
    /// Random error of each wheel's travel [m/sqrt(m)] the prediction's variance grows with,
    /// in [0, 1]. Default 0.01 (the simulator's default odometry noise; a real base's figure
    /// belongs here).
    pub odometry_wheel_sigma: f64,
    /// Wheelbase [m] turning the wheels' error into heading, in (0, 5]. Default 0.3.
    pub odometry_wheelbase_m: f64,
    /// Innovation gate: a match farther from the prediction than this Mahalanobis distance is
    /// refused and odometry kept, > 0. Default unset (no gate; EVALUATION.md, "An innovation
    /// gate").
    pub rejection_threshold: Option<f64>,
}

impl Default for ScanMatcherOptions {
    fn default() -> Self {
        Self {
            size_m: 80.0,
            cell_size_m: 0.025,
            sigma_m: 0.05,
            search_xy_m: 0.15,
            search_yaw_rad: 0.15,
            yaw_step_rad: 0.01,
            prior_xy_m: 0.3,
            prior_yaw_rad: 0.3,
            min_points: 40,
            min_score: 0.35,
            range_max_m: 3.0,
            novelty_m: 0.1,
            max_points: 400,
            match_variance_scale: 1.0,
            calibrate_odometry: true,
            turn_error_prior: 0.05,
            drift_prior_rad_per_m: 0.03,
            calibration_drift: 1e-4,
            odometry_wheel_sigma: 0.01,
            odometry_wheelbase_m: 0.3,
            rejection_threshold: None,
        }
    }
}

/// Most cells the persistent map may hold (64 M: 64 MB of counts).
pub const MAX_MATCHER_CELLS: f64 = 64e6;

impl ScanMatcherOptions {
    pub fn validate(&self) -> Result<()> {
        let ranges: [(&'static str, f64, f64, f64, bool); 17] = [
            ("size_m", self.size_m, 4.0, 400.0, true),
            ("cell_size_m", self.cell_size_m, 0.01, 0.2, true),
            ("sigma_m", self.sigma_m, 0.0, 1.0, false),
            ("search_xy_m", self.search_xy_m, 0.0, 2.0, true),
            ("search_yaw_rad", self.search_yaw_rad, 0.0, 0.5, true),
            ("yaw_step_rad", self.yaw_step_rad, 0.001, 0.1, true),
            ("prior_xy_m", self.prior_xy_m, 0.0, f64::MAX, false),
            ("prior_yaw_rad", self.prior_yaw_rad, 0.0, f64::MAX, false),
            ("range_max_m", self.range_max_m, 0.0, 100.0, false),
            ("novelty_m", self.novelty_m, 0.0, 1.0, true),
            (
                "match_variance_scale",
                self.match_variance_scale,
                0.0,
                1e6,
                true,
            ),
            ("turn_error_prior", self.turn_error_prior, 0.0, 0.5, true),
            (
                "drift_prior_rad_per_m",
                self.drift_prior_rad_per_m,
                0.0,
                1.0,
                true,
            ),
            ("calibration_drift", self.calibration_drift, 0.0, 0.1, true),
            (
                "odometry_wheel_sigma",
                self.odometry_wheel_sigma,
                0.0,
                1.0,
                true,
            ),
            (
                "odometry_wheelbase_m",
                self.odometry_wheelbase_m,
                0.0,
                5.0,
                false,
            ),
            ("min_score", self.min_score, 0.0, 1.0, false),
        ];
        for (name, v, lo, hi, closed_lo) in ranges {
            let above = if closed_lo { v >= lo } else { v > lo };
            // min_score is open at both ends
            let below = if name == "min_score" { v < hi } else { v <= hi };
            if !(v.is_finite() && above && below) {
                let open = if closed_lo { "[" } else { "(" };
                let close = if name == "min_score" { ")" } else { "]" };
                return Err(invalid_option(
                    name,
                    format!("must be in {open}{lo}, {hi}{close}, got {v}"),
                ));
            }
        }
        if self.min_points < 3 {
            return Err(invalid_option(
                "min_points",
                format!("must be >= 3, got {}", self.min_points),
            ));
        }
        if !(self.min_points..=100_000).contains(&self.max_points) {
            return Err(invalid_option(
                "max_points",
                format!(
                    "must be in [min_points = {}, 100000], got {}",
                    self.min_points, self.max_points
                ),
            ));
        }
        if let Some(g) = self.rejection_threshold {
            // inf (no gate) passes, NaN does not
            if g.is_nan() || g <= 0.0 {
                return Err(invalid_option(
                    "rejection_threshold",
                    format!("must be > 0, got {g}"),
                ));
            }
        }
        if (self.size_m / self.cell_size_m).powi(2) > MAX_MATCHER_CELLS {
            return Err(invalid_option(
                "size_m",
                "size_m / cell_size_m gives over 64 M cells",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "scan_matcher_options_tests.rs"]
mod tests;
