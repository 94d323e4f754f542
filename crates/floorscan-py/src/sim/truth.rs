//! Bindings of `floorscan_sim::truth`: the ground truth of rendered frames.

use super::*;

/// Ground truth of rendered frames (kept native; converted to arrays or CSV on demand).
#[pyclass(name = "SimTruth", module = "floorscan._native.sim", frozen)]
pub struct PyTruth {
    pub(crate) frames: Vec<FrameTruth>,
    pub(crate) width: usize,
}

#[pymethods]
impl PyTruth {
    fn __len__(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.frames.len()))
    }

    /// The truth as a dict of numpy arrays, shapes (N, W) or (N, W, 2) or (N, 3).
    fn arrays<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| truth_dict(py, &self.frames, self.width))
    }

    /// The truth columns CSV (header included) with the frames' timestamps [s].
    fn to_csv(&self, py: Python<'_>, timestamps: PyReadonlyArray1<'_, f64>) -> PyResult<String> {
        crate::errors::guard(|| {
            let times = timestamps.as_array().to_vec();
            if times.len() != self.frames.len() {
                return Err(error(
                    "LengthMismatchError",
                    format!(
                        "{} frames but {} timestamps",
                        self.frames.len(),
                        times.len()
                    ),
                ));
            }
            Ok(py.detach(|| {
                let mut out = String::with_capacity(self.frames.len() * self.width * 120 + 200);
                out.push_str(COLUMNS_CSV_HEADER);
                out.push('\n');
                write_columns_csv(&self.frames, &times, &mut out);
                out
            }))
        })
    }
}

/// Truth of frames as a dict of arrays, shapes (N, W) or (N, W, 2).
pub fn truth_dict<'py>(
    py: Python<'py>,
    frames: &[FrameTruth],
    width: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let n = frames.len();
    let cols = || frames.iter().flat_map(|f| f.columns.iter());
    let nan2 = |p: Option<Point2>| p.map_or([f64::NAN, f64::NAN], |p| [p.x, p.y]);
    let d = PyDict::new(py);
    let scalar = |v: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        Ok(PyArray1::from_vec(py, v).reshape([n, width])?.into_any())
    };
    let pairs = |v: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        Ok(PyArray1::from_vec(py, v).reshape([n, width, 2])?.into_any())
    };
    d.set_item(
        "status",
        PyArray1::from_vec(py, cols().map(|c| c.status.code()).collect()).reshape([n, width])?,
    )?;
    d.set_item("row", scalar(cols().map(|c| c.row).collect())?)?;
    d.set_item(
        "point",
        pairs(cols().flat_map(|c| nan2(c.point)).collect())?,
    )?;
    d.set_item(
        "point_world",
        pairs(cols().flat_map(|c| nan2(c.point_world)).collect())?,
    )?;
    d.set_item(
        "obstacle_world",
        pairs(cols().flat_map(|c| nan2(c.obstacle_world)).collect())?,
    )?;
    d.set_item(
        "obstacle_z",
        scalar(cols().map(|c| c.obstacle_z_m).collect())?,
    )?;
    d.set_item(
        "appearance_row",
        scalar(cols().map(|c| c.appearance_row).collect())?,
    )?;
    d.set_item(
        "appearance_point",
        pairs(cols().flat_map(|c| nan2(c.appearance_point)).collect())?,
    )?;
    let poses: Vec<f64> = frames
        .iter()
        .flat_map(|f| [f.pose.x, f.pose.y, f.pose.yaw])
        .collect();
    d.set_item("pose", PyArray1::from_vec(py, poses).reshape([n, 3])?)?;
    let cams: Vec<f64> = frames
        .iter()
        .flat_map(|f| {
            [
                f.world_from_camera.x,
                f.world_from_camera.y,
                f.world_from_camera.yaw,
            ]
        })
        .collect();
    d.set_item(
        "world_from_camera",
        PyArray1::from_vec(py, cams).reshape([n, 3])?,
    )?;
    Ok(d)
}
