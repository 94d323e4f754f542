//! The visual range sensor: the paper's column edge filter and its lane kernels, the ranger and its
//! options, the per-frame threshold, the appearance ranger for textured floors and its floor model,
//! their fusion, the floor-parallax cue, and the scans they give.

pub mod appearance;
pub mod appearance_options;
pub mod colour_image;
pub mod column_spacing;
pub mod dark_rim;
pub mod edge;
pub mod floor_model;
pub mod floor_parallax;
pub mod fusion;
pub mod fusion_options;
pub mod lanes;
pub mod noise_threshold;
pub mod parallax_options;
pub mod ranger;
pub mod ranger_options;
pub mod scan;
