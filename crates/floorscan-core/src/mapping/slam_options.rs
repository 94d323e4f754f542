//! Options of the pipeline's pose correction (`[slam]` in the config file): whether each
//! frame's scan is matched against the map before it is inserted, and the matcher's options.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::pose_graph_options::PoseGraphOptions;
use crate::scan_matcher_options::ScanMatcherOptions;

/// How the pipeline places each scan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum SlamMode {
    /// At the odometry pose, as the paper did (the map bends as odometry drifts).
    Off,
    /// At the odometry pose corrected by local scan matching: each scan matched against the
    /// scans kept so far, fused with odometry by their covariances (the default; only where
    /// odometry is given).
    #[default]
    Local,
    /// Keyframes matched against a rolling submap, loop closures, and a pose graph optimised
    /// over both (`floorscan map-log`, for a laser's scans; `[slam.graph]`).
    Graph,
}

/// Options of the pipeline's pose correction.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct SlamOptions {
    /// `"local"` (default): local scan matching where odometry is given; `"off"`: odometry
    /// poses as they are; `"graph"`: loop closure over a pose graph (`floorscan map-log`
    /// only so far, where it is that command's default).
    pub mode: SlamMode,
    /// The scan matcher and its odometry filter.
    pub matcher: ScanMatcherOptions,
    /// The pose graph (`mode = "graph"`).
    pub graph: PoseGraphOptions,
}

impl SlamOptions {
    /// The matcher's rules; an error names the field as `matcher: field`.
    pub fn validate(&self) -> Result<()> {
        let nest = |table: &'static str| {
            move |e| match e {
                Error::InvalidOption { name, reason } => Error::InvalidOption {
                    name: table,
                    reason: format!("{name}: {reason}"),
                },
                other => other,
            }
        };
        self.matcher.validate().map_err(nest("matcher"))?;
        self.graph.validate().map_err(nest("graph"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_matcher_error_names_the_matcher_and_its_field() {
        let mut o = SlamOptions::default();
        o.validate().unwrap();
        o.matcher.size_m = 1.0;
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains("matcher") && e.contains("size_m"), "{e}");
    }
}
