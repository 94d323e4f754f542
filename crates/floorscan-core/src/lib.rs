//! floorscan-core: a camera as a laser-like range sensor, and the occupancy maps it feeds.
//!
//! An implementation of Howard & Kitchen, *Fast Visual Mapping for Mobile Robot Navigation*:
//! the visual range subsystem ([`edge`], [`ground_table`], [`ranger`], [`scan`]) and the lens
//! models and mounts ([`lens`], [`mount`]) used to build and check calibration tables.
//!
//! Conventions: SI units; REP 103 frames (x forward, y left, z up, angles counter-clockwise in
//! radians); image rows count from the top (v = 0 is the top row); REP 117 ranges.

pub mod branchless;
pub mod edge;
pub mod error;
pub mod ground_table;
pub mod grid;
pub mod grid_options;
pub mod image;
pub mod inserter;
pub mod laser;
pub mod lens;
pub mod log_odds;
pub mod mount;
pub mod pose;
pub mod ranger;
pub mod ray_update;
pub mod raycast;
pub mod ranger_options;
pub mod scan;
pub mod sonar;

pub use edge::Refinement;
pub use error::{Error, Result};
pub use ground_table::GroundTable;
pub use image::{ImageView, Pixel};
pub use lens::Lens;
pub use mount::CameraMount;
pub use pose::{Point2, Pose2};
pub use ranger::VisualRanger;
pub use ranger_options::{ColumnSelection, ColumnStart, RangerOptions};
pub use scan::{ColumnOutcome, ColumnReading, ColumnStatus, Scan};
