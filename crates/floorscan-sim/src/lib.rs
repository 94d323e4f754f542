//! floorscan-sim: a simulated office building with exact ground truth, for measuring floorscan
//! and for demos on any machine.
//!
//! - Worlds ([`world`], [`world_file`], [`builtin`]): floor plans with walls, boxes, tables
//!   that overhang, chairs, floor coverings (carpet, linoleum, tiles, paper scraps), lighting.
//! - Cameras ([`camera`]): floorscan-core's lens models and mounts, any resolution.
//! - Rendering ([`render`]) and ground truth ([`truth`], [`occupancy`]).
//! - Robot ([`robot`], [`odometry`]): differential drive with wheel odometry errors.
//! - Runs ([`run`]) and calibration scenes ([`calibration`]).
//!
//! Conventions: SI units, REP 103 frames, image rows from the top. Deterministic per seed.

pub mod builtin;
pub mod calibration;
pub mod camera;
pub mod cell_memo;
pub mod clearance;
pub mod contact_shadow;
pub mod error;
pub mod geometry;
pub mod grid_index;
pub mod lightmap;
pub mod noise_cell;
pub mod noise_lanes;
pub mod occupancy;
pub mod odometry;
pub mod render;
pub mod rng;
pub mod robot;
pub mod run;
pub mod scene;
mod shade;
pub mod texture;
pub mod truth;
pub mod world;
pub mod world_file;

pub use camera::{Camera, CameraRays, Imaging};
pub use error::{Error, Result};
pub use scene::Scene;
pub use truth::{ColumnTruth, FrameTruth, PixelLabel, TruthOptions};
pub use world::World;
