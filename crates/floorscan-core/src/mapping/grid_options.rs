//! Options of an occupancy grid: one documented structure, validated when the grid is built.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};
use crate::log_odds::{log_odds_from_probability, LogOdds, MAX_ABS_NATS};
use crate::pose::Point2;

/// A world-aligned rectangle [m]: `min` is the lower-left corner, `max` the upper-right.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Bounds {
    pub min: Point2,
    pub max: Point2,
}

/// What a cell's evidence says, by the grid's thresholds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum Occupancy {
    Free,
    Unknown,
    Occupied,
}

impl Occupancy {
    /// Every class, in code order.
    pub const ALL: [Occupancy; 3] = [Occupancy::Free, Occupancy::Unknown, Occupancy::Occupied];

    /// The name used in Python (the serde name).
    pub fn as_str(self) -> &'static str {
        match self {
            Occupancy::Free => "free",
            Occupancy::Unknown => "unknown",
            Occupancy::Occupied => "occupied",
        }
    }

    /// Small integer code used in numpy arrays: free 0, unknown 1, occupied 2.
    pub fn code(self) -> u8 {
        match self {
            Occupancy::Free => 0,
            Occupancy::Unknown => 1,
            Occupancy::Occupied => 2,
        }
    }
}

/// Which cells a ray clears (updates as free) on its way to its end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum RayWalk {
    /// Every cell the ray passes through ([`crate::raycast`], as OctoMap's
    /// `computeRayKeys`): all the floor a ray crosses is cleared.
    #[default]
    Exact,
    /// One cell per step along the ray's major axis ([`crate::thin_walk`]: the cells of a
    /// Bresenham line, as costmap_2d's clearing and Bonxai), each a cell the ray crosses:
    /// 25-30 % fewer cells and faster; a cell the ray only clips keeps its value.
    Thin,
}

impl RayWalk {
    /// The name used in Python and the config file (the serde name).
    pub fn as_str(self) -> &'static str {
        match self {
            RayWalk::Exact => "exact",
            RayWalk::Thin => "thin",
        }
    }
}

/// Options of [`crate::grid::Grid`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct GridOptions {
    /// Side of a square cell [m], in [0.001, 10]. Default 0.04 (the paper's 4 cm).
    pub cell_size_m: f64,
    /// World position [m] of the lower-left corner of cell (0, 0): where the cell lattice is
    /// anchored. Default (0, 0); a loaded map_server map puts its `origin` here.
    pub origin_m: Point2,
    /// `None` (default): the map grows as the robot explores, tiles allocated on demand.
    /// `Some(bounds)`: the map covers exactly the cells overlapping `bounds` [m]; rays are
    /// clipped to it and a pose outside it is an error.
    pub bounds_m: Option<Bounds>,
    /// Lowest log-odds a cell can hold [nats], in [-16, 0). Default -2.0 (p = 0.12, OctoMap's
    /// lower clamp): a bound lets a free cell turn occupied after a few observations when the
    /// world changes.
    pub clamp_min_nats: f64,
    /// Highest log-odds a cell can hold [nats], in (0, 16]. Default 3.5 (p = 0.97, OctoMap's
    /// upper clamp).
    pub clamp_max_nats: f64,
    /// A cell is occupied when its probability is >= this, in (0.5, 1). Default 0.65 (ROS
    /// map_server's `occupied_thresh`).
    pub occupied_threshold: f64,
    /// A cell is free when its probability is <= this, in (0, 0.5). Default 0.196 (ROS
    /// map_server's `free_thresh`). Between the two thresholds a cell is unknown.
    pub free_threshold: f64,
    /// Most cells the map may span [cells], in [1, 2^32]: the bounding box of a growing map's
    /// tiles, the cells of fixed bounds, and any rectangle read or written at once (an export).
    /// Default 2^25 (33.5 M cells: 231 m square at 4 cm, 64 MB of cells; an export then stays
    /// well under 1 GB). A pose 1000 km away is an [`crate::Error::OutOfBounds`], not an
    /// allocation; raise this for larger sites.
    pub max_cells: u64,
    /// Which cells a ray clears: `"exact"` (default: every cell it passes through, as
    /// OctoMap) or `"thin"` (one per step along its major axis, as costmap_2d and Bonxai:
    /// fewer cells, faster, the floor crossed diagonally cleared more slowly).
    pub ray_walk: RayWalk,
}

/// Default of [`GridOptions::max_cells`].
pub const DEFAULT_MAX_CELLS: u64 = 1 << 25;
/// Upper end of [`GridOptions::max_cells`].
pub const MAX_MAX_CELLS: u64 = 1 << 32;

impl Default for GridOptions {
    fn default() -> Self {
        Self {
            cell_size_m: 0.04,
            origin_m: Point2::new(0.0, 0.0),
            bounds_m: None,
            clamp_min_nats: -2.0,
            clamp_max_nats: 3.5,
            occupied_threshold: 0.65,
            free_threshold: 0.196,
            max_cells: DEFAULT_MAX_CELLS,
            ray_walk: RayWalk::Exact,
        }
    }
}

/// The options in stored units, ready for the update loops.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CellLimits {
    pub clamp_min: i16,
    pub clamp_max: i16,
    /// Occupied when value >= this.
    pub occupied_at: i16,
    /// Free when value <= this.
    pub free_at: i16,
}

impl CellLimits {
    pub fn classify(&self, value: i16) -> Occupancy {
        if value >= self.occupied_at {
            Occupancy::Occupied
        } else if value <= self.free_at {
            Occupancy::Free
        } else {
            Occupancy::Unknown
        }
    }
}

impl GridOptions {
    pub fn validate(&self) -> Result<()> {
        if !(self.cell_size_m.is_finite() && (0.001..=10.0).contains(&self.cell_size_m)) {
            return Err(invalid_option(
                "cell_size_m",
                format!("must be in [0.001, 10] m, got {}", self.cell_size_m),
            ));
        }
        if !(self.origin_m.x.is_finite() && self.origin_m.y.is_finite()) {
            return Err(invalid_option("origin_m", "must be finite"));
        }
        if let Some(b) = self.bounds_m {
            let finite = [b.min.x, b.min.y, b.max.x, b.max.y]
                .iter()
                .all(|v| v.is_finite());
            if !finite || b.max.x <= b.min.x || b.max.y <= b.min.y {
                return Err(invalid_option(
                    "bounds_m",
                    format!(
                        "must be finite with max > min, got min ({}, {}) max ({}, {})",
                        b.min.x, b.min.y, b.max.x, b.max.y
                    ),
                ));
            }
        }
        if !(self.clamp_min_nats < 0.0 && self.clamp_min_nats >= -MAX_ABS_NATS) {
            return Err(invalid_option(
                "clamp_min_nats",
                format!("must be in [-16, 0), got {}", self.clamp_min_nats),
            ));
        }
        if !(self.clamp_max_nats > 0.0 && self.clamp_max_nats <= MAX_ABS_NATS) {
            return Err(invalid_option(
                "clamp_max_nats",
                format!("must be in (0, 16], got {}", self.clamp_max_nats),
            ));
        }
        if !(self.occupied_threshold > 0.5 && self.occupied_threshold < 1.0) {
            return Err(invalid_option(
                "occupied_threshold",
                format!("must be in (0.5, 1), got {}", self.occupied_threshold),
            ));
        }
        if !(self.free_threshold > 0.0 && self.free_threshold < 0.5) {
            return Err(invalid_option(
                "free_threshold",
                format!("must be in (0, 0.5), got {}", self.free_threshold),
            ));
        }
        if !(1..=MAX_MAX_CELLS).contains(&self.max_cells) {
            return Err(invalid_option(
                "max_cells",
                format!("must be in [1, 2^32], got {}", self.max_cells),
            ));
        }
        let limits = self.limits();
        if limits.occupied_at > limits.clamp_max {
            return Err(invalid_option(
                "occupied_threshold",
                format!(
                    "{} is above the upper clamp (p = {:.4}): no cell could ever be occupied",
                    self.occupied_threshold,
                    LogOdds(limits.clamp_max).probability()
                ),
            ));
        }
        if limits.free_at < limits.clamp_min {
            return Err(invalid_option(
                "free_threshold",
                format!(
                    "{} is below the lower clamp (p = {:.4}): no cell could ever be free",
                    self.free_threshold,
                    LogOdds(limits.clamp_min).probability()
                ),
            ));
        }
        Ok(())
    }

    /// The clamp bounds and thresholds in stored units. Thresholds are rounded towards
    /// "unknown" so that a cell classified occupied really has p >= `occupied_threshold`.
    pub fn limits(&self) -> CellLimits {
        let units = |nats: f64| (nats * 1000.0).clamp(-32767.0, 32767.0);
        CellLimits {
            clamp_min: units(self.clamp_min_nats).round() as i16,
            clamp_max: units(self.clamp_max_nats).round() as i16,
            occupied_at: units(log_odds_from_probability(self.occupied_threshold)).ceil() as i16,
            free_at: units(log_odds_from_probability(self.free_threshold)).floor() as i16,
        }
    }
}

#[cfg(test)]
#[path = "grid_options_tests.rs"]
mod tests;
