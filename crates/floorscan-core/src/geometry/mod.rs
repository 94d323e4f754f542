//! Camera and robot geometry: lens models, the camera's mount, planar poses, and the ground lookup
//! table (image pixel to floor point) with its inverse.

pub mod ground_table;
pub mod ground_table_inverse;
pub mod lens;
pub mod mount;
pub mod pose;
