//! The config file's `[drive]` table: the options of the closed loop's avoidance map
//! (`[drive.avoidance_map]`, [`AvoidanceMapOptions`]) and of the inverse sensor model that feeds
//! it visual scans (`[drive.sensor_model]`, [`VisualModel`]), of the costmap
//! (`[drive.costmap]`), of the dynamic-window planner (`[drive.dwa]`), and the drive's own
//! settings (`[drive.run]`, [`DriveRunOptions`]: speed, duration, sensor, ...; the command
//! line's flags override them).

use serde::{Deserialize, Serialize};

use crate::avoidance_map_options::AvoidanceMapOptions;
use crate::costmap_options::CostmapOptions;
use crate::drive_run_options::DriveRunOptions;
use crate::dwa_options::DwaOptions;
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
    /// The costmap and the navigation function (`[drive.costmap]`).
    pub costmap: CostmapOptions,
    /// The dynamic-window planner (`[drive.dwa]`; its top speed is the drive's speed).
    pub dwa: DwaOptions,
    /// The drive's own settings (`[drive.run]`; `floorscan drive`'s flags override them).
    pub run: DriveRunOptions,
}

impl DriveMapOptions {
    /// Both tables' rules.
    pub fn validate(&self) -> Result<()> {
        self.avoidance_map.validate()?;
        self.sensor_model.validate()?;
        self.costmap.validate()?;
        self.dwa.validate()?;
        self.run.validate()
    }
}
