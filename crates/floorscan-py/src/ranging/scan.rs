//! Bindings of `floorscan_core::scan`: a frame's readings as numpy columns.

use floorscan_core::scan::ColumnOutcome;
use floorscan_core::{ColumnReading, ColumnStatus, Point2, Scan};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{error, IntoPyResult};

#[pyclass(name = "Scan", module = "floorscan._native.ranging", frozen)]
#[derive(Clone)]
pub struct PyScan {
    pub inner: Scan,
}

impl PyScan {
    fn column_of<'py, T: numpy::Element>(
        &self,
        py: Python<'py>,
        f: impl Fn(&ColumnReading) -> T,
    ) -> Bound<'py, PyArray1<T>> {
        PyArray1::from_vec(py, self.inner.readings.iter().map(f).collect())
    }
}

#[pymethods]
impl PyScan {
    /// Rebuilds a scan from its CSV columns (status codes as in `ColumnStatus.code`). The near
    /// edge of the field of view is not part of the CSV; pass it if known (NaN otherwise).
    #[staticmethod]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        timestamp_s: f64,
        columns: PyReadonlyArray1<'_, u32>,
        rows: PyReadonlyArray1<'_, f64>,
        status: PyReadonlyArray1<'_, u8>,
        x_m: PyReadonlyArray1<'_, f64>,
        y_m: PyReadonlyArray1<'_, f64>,
        near_x_m: PyReadonlyArray1<'_, f64>,
        near_y_m: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            let (c, r, s, x, y, nx, ny) = (
                columns.as_array(),
                rows.as_array(),
                status.as_array(),
                x_m.as_array(),
                y_m.as_array(),
                near_x_m.as_array(),
                near_y_m.as_array(),
            );
            let n = c.len();
            if [r.len(), s.len(), x.len(), y.len(), nx.len(), ny.len()]
                .iter()
                .any(|&l| l != n)
            {
                return Err(error(
                    "LengthMismatchError",
                    "scan arrays must all have the same length".into(),
                ));
            }
            let point =
                |a: f64, b: f64| (a.is_finite() && b.is_finite()).then(|| Point2::new(a, b));
            let mut readings = Vec::with_capacity(n);
            for i in 0..n {
                let status = ColumnStatus::from_code(s[i])
                    .ok_or_else(|| error("OptionError", format!("unknown status code {}", s[i])))?;
                let p = point(x[i], y[i]);
                let near = point(nx[i], ny[i]);
                let missing = || {
                    error(
                        "GeometryError",
                        format!("reading {i} ({}) needs a finite x and y", status.as_str()),
                    )
                };
                let outcome = match status {
                    ColumnStatus::Boundary => ColumnOutcome::Boundary {
                        row: r[i],
                        point: p.ok_or_else(missing)?,
                        footprint_m: 0.0, // not part of the CSV: no free-space margin
                    },
                    ColumnStatus::NoBoundary => ColumnOutcome::NoBoundary {
                        top_row: r[i],
                        farthest: p.ok_or_else(missing)?,
                    },
                    ColumnStatus::TooClose => ColumnOutcome::TooClose,
                    ColumnStatus::Invalid => ColumnOutcome::Invalid {
                        row: r[i].is_finite().then_some(r[i]),
                    },
                };
                let near = if status == ColumnStatus::TooClose {
                    near.or(p)
                } else {
                    near
                };
                let start_row = if status == ColumnStatus::TooClose {
                    r[i]
                } else {
                    f64::NAN
                };
                readings.push(ColumnReading {
                    column: c[i],
                    start_row,
                    near,
                    outcome,
                    confidence: 1.0,
                });
            }
            Ok(Self {
                inner: Scan {
                    timestamp_s,
                    readings,
                },
            })
        })
    }

    #[getter]
    fn timestamp(&self) -> PyResult<f64> {
        crate::errors::guard(|| Ok(self.inner.timestamp_s))
    }
    fn __len__(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.inner.len()))
    }
    #[getter]
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<u32>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.column)))
    }
    #[getter]
    fn rows<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.row())))
    }
    #[getter]
    fn status_codes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<u8>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.status().code())))
    }
    #[getter]
    fn x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.point().map_or(f64::NAN, |p| p.x))))
    }
    #[getter]
    fn y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.point().map_or(f64::NAN, |p| p.y))))
    }
    #[getter]
    fn ranges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.range_m())))
    }
    #[getter]
    fn bearings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.bearing_rad())))
    }
    /// Floor length one pixel row covers at each boundary [m] (0 where not a boundary).
    #[getter]
    fn footprints<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| {
            Ok(self.column_of(py, |r| match r.outcome {
                ColumnOutcome::Boundary { footprint_m, .. } => footprint_m,
                _ => 0.0,
            }))
        })
    }
    /// Each reading's confidence in [0, 1].
    #[getter]
    fn confidence<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        self.column_of(py, |r| r.confidence)
    }
    #[getter]
    fn start_rows<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.start_row)))
    }
    #[getter]
    fn near_x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.near.map_or(f64::NAN, |p| p.x))))
    }
    #[getter]
    fn near_y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| Ok(self.column_of(py, |r| r.near.map_or(f64::NAN, |p| p.y))))
    }

    /// The scan's CSV lines (no header), see `floorscan_core::scan::SCAN_CSV_HEADER`.
    fn csv_lines(&self) -> PyResult<String> {
        crate::errors::guard(|| {
            Ok({
                let mut s = String::new();
                self.inner.write_csv_lines(&mut s);
                s
            })
        })
    }

    /// Fixed angular binning (sensor_msgs/LaserScan fields) as a dict.
    fn to_laser_bins<'py>(
        &self,
        py: Python<'py>,
        angle_min: f64,
        angle_max: f64,
        angle_increment: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| {
            let bins = self
                .inner
                .to_laser_bins(angle_min, angle_max, angle_increment)
                .py()?;
            let d = PyDict::new(py);
            d.set_item("angle_min", bins.angle_min_rad)?;
            d.set_item("angle_max", bins.angle_max_rad)?;
            d.set_item("angle_increment", bins.angle_increment_rad)?;
            d.set_item("range_min", bins.range_min_m)?;
            d.set_item("range_max", bins.range_max_m)?;
            d.set_item("ranges", PyArray1::from_vec(py, bins.ranges_m))?;
            Ok(d)
        })
    }
}

/// Every column status as (name, code), in code order (`floorscan.ColumnStatus` is built
/// from it).
#[pyfunction]
pub fn column_statuses() -> Vec<(&'static str, u8)> {
    ColumnStatus::ALL
        .iter()
        .map(|s| (s.as_str(), s.code()))
        .collect()
}
