//! floorscan-core: a camera as a laser-like range sensor, and the occupancy maps it feeds.
//!
//! An implementation of Howard & Kitchen, *Fast Visual Mapping for Mobile Robot Navigation*:
//! the visual range subsystem ([`edge`], [`ground_table`], [`ranger`], [`scan`]), the
//! appearance ranger for textured floors ([`floor_model`], [`appearance`], [`colour_image`]) and the lens
//! models and mounts ([`lens`], [`mount`]) used to build and check calibration tables; the map
//! builder: log-odds maths ([`log_odds`]), grids ([`grid_options`], [`grid`], [`queries`],
//! the unclamped, mergeable [`evidence`] layer),
//! the exact ray walk ([`raycast`]), updates from visual scans, lasers and sonars
//! ([`inserter`], [`ray_update`], [`laser`], [`sonar`]) and the robot-centred [`local_map`];
//! for driving on the maps: the [`avoidance_map`]'s updates (its floor quadrilaterals filled
//! by [`polygon_fill`]), a planner's [`navigation`] function, and the correlative
//! [`scan_matcher`] (its [`correlative_search`], [`hit_map`], the match's information matrix
//! [`match_information`] and the [`match_filter`] that fuses matches with odometry).
//!
//! The modules are grouped by stage: [`ranging`] (images to scans), [`geometry`] (lens, mount,
//! pose, ground table), [`mapping`] (scans and poses to maps, scan matching) and [`navigation`]
//! (driving on the maps), as the bindings' submodules and the Python packages are.
//!
//! Conventions: SI units; REP 103 frames (x forward, y left, z up, angles counter-clockwise in
//! radians); image rows count from the top (v = 0 is the top row); REP 117 ranges.

pub mod error;
pub mod geometry;
pub mod image;
pub mod mapping;
pub mod navigation;
pub mod ranging;
#[cfg(test)]
mod test_rng;

// Each stage's modules also at the crate root, the paths the bindings, the simulator and the
// tests have used since before the stages were grouped (`floorscan_core::ranger`).
pub use geometry::{ground_table, ground_table_inverse, lens, mount, pose};
pub use mapping::{
    branchless, correlative_search, evidence, grid, grid_options, hit_map, inserter, laser,
    local_map, log_odds, match_filter, match_information, pose_graph_options, queries, ray_update,
    raycast, scan_matcher, scan_matcher_options, slam_options, sonar, thin_walk,
};
pub use navigation::{
    avoidance_map, avoidance_map_options, costmap_options, drive_map_options, drive_run_options,
    dwa_options, dynamic_window, polygon_fill, visual_sensor_model,
};
pub use ranging::{
    appearance, appearance_options, colour_image, column_spacing, dark_rim, edge, floor_model,
    floor_parallax, fusion, fusion_options, lanes, noise_threshold, parallax_options, ranger,
    ranger_options, scan,
};

pub use appearance::AppearanceRanger;
pub use appearance_options::{AppearanceFeatures, AppearanceOptions};
pub use colour_image::ColourView;
pub use edge::Refinement;
pub use error::{Error, Result};
pub use evidence::EvidenceRaster;
pub use floor_model::FloorModel;
pub use floor_parallax::{FloorParallax, ParallaxReport};
pub use fusion::{
    fuse_scans, fuse_scans_after, fuse_scans_driven, TextureState, MIN_TEXTURE_EVIDENCE,
    TEXTURE_MEMORY_FRAMES,
};
pub use fusion_options::FusionOptions;
pub use grid::{CellRect, Grid};
pub use grid_options::{Bounds, GridOptions, Occupancy};
pub use ground_table::GroundTable;
pub use image::{ImageView, Pixel};
pub use inserter::{Inserter, InserterOptions, TooClosePolicy};
pub use laser::{BeamAngles, LaserScan};
pub use lens::Lens;
pub use local_map::{LocalMap, LocalMapOptions};
pub use log_odds::{Evidence, LogOdds};
pub use mount::CameraMount;
pub use parallax_options::ParallaxOptions;
pub use pose::{Point2, Pose2};
pub use pose_graph_options::PoseGraphOptions;
pub use ranger::VisualRanger;
pub use ranger_options::{ColumnSelection, ColumnStart, RangerOptions};
pub use ray_update::{Ray, UpdateStats};
pub use raycast::CellIndex;
pub use scan::{ColumnOutcome, ColumnReading, ColumnStatus, Scan};
pub use scan_matcher::ScanMatcher;
pub use scan_matcher_options::ScanMatcherOptions;
pub use slam_options::{SlamMode, SlamOptions};
pub use sonar::SonarReading;
