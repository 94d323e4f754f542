//! Bindings of the ranging stage (`floorscan._native.ranging`): ground tables, the rangers, their
//! options, scans.

pub mod appearance;
pub mod appearance_options;
pub mod floor_parallax;
pub mod fusion_options;
pub mod ground_table;
pub mod parallax_options;
pub mod ranger;
pub mod ranger_options;
pub mod scan;
