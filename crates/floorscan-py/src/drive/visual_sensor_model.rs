//! Bindings of `floorscan_core::visual_sensor_model`: the defaults, check and schema of `VisualModel`.

use floorscan_core::visual_sensor_model::VisualModel;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    VisualModel,
    default_visual_sensor_model,
    check_visual_sensor_model,
    visual_sensor_model_schema
);
