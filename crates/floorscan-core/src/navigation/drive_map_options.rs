//! The config file's `[drive]` table: the options of the closed loop's avoidance map
//! (`[drive.avoidance_map]`, [`AvoidanceMapOptions`]) and of the inverse sensor model that feeds
//! it visual scans (`[drive.sensor_model]`, [`VisualModel`]). (The loop's own settings, its
//! speed, planner and costmap, are still the Python `floorscan.drive.DriveOptions`.)

use serde::{Deserialize, Serialize};

use crate::avoidance_map_options::AvoidanceMapOptions;
use crate::error::Result;
use crate::visual_sensor_model::VisualModel;

/// The `[drive]` table.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct DriveMapOptions {
    /// The avoidance map (`[drive.avoidance_map]`).
    pub avoidance_map: AvoidanceMapOptions,
    /// The visual inverse sensor model (`[drive.sensor_model]`).
    pub sensor_model: VisualModel,
}

impl DriveMapOptions {
    /// Both tables' rules.
    pub fn validate(&self) -> Result<()> {
        self.avoidance_map.validate()?;
        self.sensor_model.validate()
    }
}
