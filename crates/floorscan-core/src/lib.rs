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
//! by [`polygon_fill`]), a planner's [`navigation`] function, and the search and hit map of a
//! correlative [`scan_matcher`] and its match's information matrix ([`match_information`]).
//!
//! Conventions: SI units; REP 103 frames (x forward, y left, z up, angles counter-clockwise in
//! radians); image rows count from the top (v = 0 is the top row); REP 117 ranges.

pub mod appearance;
pub mod appearance_options;
pub mod avoidance_map;
pub mod branchless;
pub mod colour_image;
pub mod column_spacing;
pub mod dark_rim;
pub mod dynamic_window;
pub mod edge;
pub mod error;
pub mod evidence;
pub mod floor_model;
pub mod floor_parallax;
pub mod fusion;
pub mod grid;
pub mod grid_options;
pub mod ground_table;
pub mod ground_table_inverse;
pub mod hit_map;
pub mod image;
pub mod inserter;
pub mod lanes;
pub mod laser;
pub mod lens;
pub mod local_map;
pub mod log_odds;
pub mod match_information;
pub mod mount;
pub mod navigation;
pub mod noise_threshold;
pub mod parallax_options;
pub mod polygon_fill;
pub mod pose;
pub mod queries;
pub mod ranger;
pub mod ranger_options;
pub mod ray_update;
pub mod raycast;
pub mod scan;
pub mod scan_matcher;
pub mod scan_matcher_options;
pub mod slam_options;
pub mod sonar;
#[cfg(test)]
mod test_rng;
pub mod thin_walk;

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
pub use ranger::VisualRanger;
pub use ranger_options::{ColumnSelection, ColumnStart, RangerOptions};
pub use ray_update::{Ray, UpdateStats};
pub use raycast::CellIndex;
pub use scan::{ColumnOutcome, ColumnReading, ColumnStatus, Scan};
pub use scan_matcher_options::ScanMatcherOptions;
pub use slam_options::{SlamMode, SlamOptions};
pub use sonar::SonarReading;
