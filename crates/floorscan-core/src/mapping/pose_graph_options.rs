//! Options of the pose graph (`[slam] mode = "graph"`, `[slam.graph]` in the config file):
//! keyframes matched against a rolling submap of the keyframes before them (the local
//! trajectory), loop closures found by matching a keyframe against the keyframes it passes
//! again, and the graph of both optimised (GTSAM's Levenberg-Marquardt, a Cauchy loss on the
//! loop closures). Made for a laser's scans (a wide view, tens of metres): `floorscan map-log`.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};

/// Options of the pose graph and of the matching that builds it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct PoseGraphOptions {
    /// A new keyframe after this much travel [m] since the last one, in (0, 10]. Default 0.3.
    pub keyframe_distance_m: f64,
    /// ... or this much turn [rad], in (0, 3.2]. Default 0.2.
    pub keyframe_rotation_rad: f64,
    /// Scan points farther than this [m] are ignored, in (0, 100]. Default 20 (a laser's
    /// reliable reach indoors).
    pub range_max_m: f64,
    /// At most this many points of a scan, evenly spaced along it, are matched, in [3,
    /// 100000]. Default 200.
    pub max_points: u32,
    /// Cell of the likelihood fields [m], in [0.01, 0.5]. Default 0.05.
    pub cell_size_m: f64,
    /// Width of the likelihood fields [m], in (0, 1]. Default 0.07.
    pub sigma_m: f64,
    /// Each scan is matched against the points of this many latest keyframes (the rolling
    /// submap), in [1, 1000]. Default 20.
    pub submap_keyframes: u32,
    /// Half-width of the scan-to-submap search in x and y [m], in [0, 2]. Default 0.3.
    pub search_xy_m: f64,
    /// Half-width of the scan-to-submap search in yaw [rad], in [0, 1]. Default 0.25.
    pub search_yaw_rad: f64,
    /// Yaw step of every search [rad], in [0.001, 0.1]. Default 0.01.
    pub yaw_step_rad: f64,
    /// A scan the submap search cannot place is searched again over this half-width in yaw
    /// [rad] (at twice the yaw step), and kept when it scores `loop_min_score`: odometry that
    /// turned wrong by tens of degrees in one step (a wheel slip, a glitch) is caught before
    /// it turns the rest of the run. In [0, 3.2]; 0 turns it off. Default 1.6.
    pub recovery_yaw_rad: f64,
    /// Mean field value a scan-to-submap match needs to be kept, in (0, 1); below it the
    /// odometry's increment is kept. Default 0.3.
    pub min_score: f64,
    /// A keyframe is tried against the keyframes at least this much travel [m] behind it, in
    /// [0, 10000]. Default 8.
    pub loop_min_travel_m: f64,
    /// ... whose estimated position lies within this distance [m] of its own, in (0, 100].
    /// Default 4.
    pub loop_search_radius_m: f64,
    /// Half-width of the loop closure search in x and y [m], in [0, 5]. Default 1.5.
    pub loop_search_xy_m: f64,
    /// Half-width of the loop closure search in yaw [rad], in [0, 1]. Default 0.35.
    pub loop_search_yaw_rad: f64,
    /// Mean field value a loop closure needs, in (0, 1). Default 0.55 (most points within a
    /// field width of the earlier keyframes' points).
    pub loop_min_score: f64,
    /// At most this many earlier keyframes, the nearest, are tried per keyframe, in [1, 20].
    /// Default 2.
    pub loop_candidates: u32,
    /// Loop closures are looked for at every n-th keyframe, in [1, 1000]. Default 2.
    pub loop_every_keyframes: u32,
    /// The earlier keyframe is matched with this many keyframes each side of it, in [0, 100].
    /// Default 6.
    pub loop_neighbours: u32,
    /// Standard deviation of a sequential edge (keyframe to keyframe) in x and y [m], before
    /// travel, in (0, 10]. Default 0.02.
    pub sequential_sigma_xy_m: f64,
    /// ... in yaw [rad], in (0, 3.2]. Default 0.01.
    pub sequential_sigma_yaw_rad: f64,
    /// Growth of a sequential edge's standard deviations with its length: x, y by this times
    /// the metres, yaw by this times (the radians turned + 0.4 x the metres), in [0, 10].
    /// Default 0.05.
    pub sequential_sigma_per_m: f64,
    /// Standard deviation of a loop closure in x and y [m], in (0, 10]. Default 0.05.
    pub loop_sigma_xy_m: f64,
    /// ... in yaw [rad], in (0, 3.2]. Default 0.02.
    pub loop_sigma_yaw_rad: f64,
    /// Scale of the Cauchy loss on loop closures (in standard deviations), in (0, 100]: a
    /// wrong closure weighs little once it disagrees with the rest by more. Default 1.
    pub loop_robust_scale: f64,
    /// A loop closure's standard deviations follow its match's information: the direction
    /// the matched points constrain least (along a corridor passed again) gets `loop_sigma_xy_m`
    /// divided by the square root of its share of the best direction's information (at most
    /// 100 times wider), so a closure that slid along a corridor does not pull the graph along
    /// it. False: `loop_sigma_xy_m` in every direction. Default true.
    pub loop_information: bool,
}

impl Default for PoseGraphOptions {
    fn default() -> Self {
        Self {
            keyframe_distance_m: 0.3,
            keyframe_rotation_rad: 0.2,
            range_max_m: 20.0,
            max_points: 200,
            cell_size_m: 0.05,
            sigma_m: 0.07,
            submap_keyframes: 20,
            search_xy_m: 0.3,
            search_yaw_rad: 0.25,
            yaw_step_rad: 0.01,
            recovery_yaw_rad: 1.6,
            min_score: 0.3,
            loop_min_travel_m: 8.0,
            loop_search_radius_m: 4.0,
            loop_search_xy_m: 1.5,
            loop_search_yaw_rad: 0.35,
            loop_min_score: 0.55,
            loop_candidates: 2,
            loop_every_keyframes: 2,
            loop_neighbours: 6,
            sequential_sigma_xy_m: 0.02,
            sequential_sigma_yaw_rad: 0.01,
            sequential_sigma_per_m: 0.05,
            loop_sigma_xy_m: 0.05,
            loop_sigma_yaw_rad: 0.02,
            loop_robust_scale: 1.0,
            loop_information: true,
        }
    }
}

/// How far [m] the pose may move from where the rolling submap's field was built before it is
/// built again (it is also built again at each keyframe).
pub const FIELD_REUSE_M: f64 = 1.0;

/// Most cells one likelihood field of a search may hold (16 M: 64 MB of floats).
pub const MAX_FIELD_CELLS: f64 = 16e6;

impl PoseGraphOptions {
    /// Half-side [m] of the square around the pose searched from that a search's field
    /// covers: the scan's reach, the wider search, three field widths, and the
    /// [`FIELD_REUSE_M`] the pose may move before the submap's field is rebuilt.
    pub fn field_half_side_m(&self) -> f64 {
        self.range_max_m
            + self.search_xy_m.max(self.loop_search_xy_m)
            + 3.0 * self.sigma_m
            + FIELD_REUSE_M
    }

    pub fn validate(&self) -> Result<()> {
        // (name, value, low, high, low closed, high closed)
        let ranges: [(&'static str, f64, f64, f64, bool, bool); 21] = [
            (
                "recovery_yaw_rad",
                self.recovery_yaw_rad,
                0.0,
                3.2,
                true,
                true,
            ),
            (
                "keyframe_distance_m",
                self.keyframe_distance_m,
                0.0,
                10.0,
                false,
                true,
            ),
            (
                "keyframe_rotation_rad",
                self.keyframe_rotation_rad,
                0.0,
                3.2,
                false,
                true,
            ),
            ("range_max_m", self.range_max_m, 0.0, 100.0, false, true),
            ("cell_size_m", self.cell_size_m, 0.01, 0.5, true, true),
            ("sigma_m", self.sigma_m, 0.0, 1.0, false, true),
            ("search_xy_m", self.search_xy_m, 0.0, 2.0, true, true),
            ("search_yaw_rad", self.search_yaw_rad, 0.0, 1.0, true, true),
            ("yaw_step_rad", self.yaw_step_rad, 0.001, 0.1, true, true),
            ("min_score", self.min_score, 0.0, 1.0, false, false),
            (
                "loop_min_travel_m",
                self.loop_min_travel_m,
                0.0,
                1e4,
                true,
                true,
            ),
            (
                "loop_search_radius_m",
                self.loop_search_radius_m,
                0.0,
                100.0,
                false,
                true,
            ),
            (
                "loop_search_xy_m",
                self.loop_search_xy_m,
                0.0,
                5.0,
                true,
                true,
            ),
            (
                "loop_search_yaw_rad",
                self.loop_search_yaw_rad,
                0.0,
                1.0,
                true,
                true,
            ),
            (
                "loop_min_score",
                self.loop_min_score,
                0.0,
                1.0,
                false,
                false,
            ),
            (
                "sequential_sigma_xy_m",
                self.sequential_sigma_xy_m,
                0.0,
                10.0,
                false,
                true,
            ),
            (
                "sequential_sigma_yaw_rad",
                self.sequential_sigma_yaw_rad,
                0.0,
                3.2,
                false,
                true,
            ),
            (
                "sequential_sigma_per_m",
                self.sequential_sigma_per_m,
                0.0,
                10.0,
                true,
                true,
            ),
            (
                "loop_sigma_xy_m",
                self.loop_sigma_xy_m,
                0.0,
                10.0,
                false,
                true,
            ),
            (
                "loop_sigma_yaw_rad",
                self.loop_sigma_yaw_rad,
                0.0,
                3.2,
                false,
                true,
            ),
            (
                "loop_robust_scale",
                self.loop_robust_scale,
                0.0,
                100.0,
                false,
                true,
            ),
        ];
        for (name, v, lo, hi, closed_lo, closed_hi) in ranges {
            let above = if closed_lo { v >= lo } else { v > lo };
            let below = if closed_hi { v <= hi } else { v < hi };
            if !(v.is_finite() && above && below) {
                let open = if closed_lo { "[" } else { "(" };
                let close = if closed_hi { "]" } else { ")" };
                return Err(invalid_option(
                    name,
                    format!("must be in {open}{lo}, {hi}{close}, got {v}"),
                ));
            }
        }
        let counts: [(&'static str, u32, u32, u32); 5] = [
            ("max_points", self.max_points, 3, 100_000),
            ("submap_keyframes", self.submap_keyframes, 1, 1000),
            ("loop_candidates", self.loop_candidates, 1, 20),
            ("loop_every_keyframes", self.loop_every_keyframes, 1, 1000),
            ("loop_neighbours", self.loop_neighbours, 0, 100),
        ];
        for (name, v, lo, hi) in counts {
            if !(lo..=hi).contains(&v) {
                return Err(invalid_option(
                    name,
                    format!("must be in [{lo}, {hi}], got {v}"),
                ));
            }
        }
        // A search's field covers the square around the pose searched from that its scan's
        // points can reach (the points it is built from are cut to it).
        let side = 2.0 * self.field_half_side_m() / self.cell_size_m;
        if side * side > MAX_FIELD_CELLS {
            return Err(invalid_option(
                "cell_size_m",
                format!(
                    "too fine for range_max_m = {} (a field would hold over 16 M cells)",
                    self.range_max_m
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "pose_graph_options_tests.rs"]
mod tests;
