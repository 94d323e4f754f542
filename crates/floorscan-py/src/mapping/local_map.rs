//! Bindings of `floorscan_core::local_map`: the robot-centred scrolling window.

use floorscan_core::{InserterOptions, LocalMap, LocalMapOptions};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::arrays::{laser_layout, pose, rows, slice1, sonar_readings, stats, Stats};
use crate::errors::IntoPyResult;
use crate::grid_views;
use crate::options::{from_py, options_functions, to_py};
use crate::scan::PyScan;

#[pyclass(name = "LocalMap", module = "floorscan._native.mapping")]
pub struct PyLocalMap {
    inner: LocalMap,
}

#[pymethods]
impl PyLocalMap {
    #[new]
    fn new(
        options: &Bound<'_, PyAny>,
        inserter_options: &Bound<'_, PyAny>,
        local_from_robot: [f64; 3],
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            let o: LocalMapOptions = from_py(options)?;
            let io: InserterOptions = from_py(inserter_options)?;
            Ok(Self {
                inner: LocalMap::new(o, io, pose(local_from_robot)).py()?,
            })
        })
    }

    fn move_by(&mut self, delta: [f64; 3]) -> PyResult<()> {
        crate::errors::guard(|| self.inner.move_by(&pose(delta)).py())
    }

    fn move_to(&mut self, local_from_robot: [f64; 3]) -> PyResult<()> {
        crate::errors::guard(|| self.inner.move_to(&pose(local_from_robot)).py())
    }

    #[getter]
    fn pose(&self) -> PyResult<(f64, f64, f64)> {
        crate::errors::guard(|| {
            Ok({
                let p = self.inner.pose();
                (p.x, p.y, p.yaw)
            })
        })
    }

    fn insert_scan(&mut self, scan: &PyScan, mount: [f64; 3]) -> PyResult<Stats> {
        crate::errors::guard(|| {
            self.inner
                .insert_scan(&scan.inner, &pose(mount))
                .py()
                .map(stats)
        })
    }

    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (ranges, angles, angle_min, angle_increment, range_min, range_max, mount))]
    fn insert_laser(
        &mut self,
        ranges: PyReadonlyArray1<'_, f64>,
        angles: Option<PyReadonlyArray1<'_, f64>>,
        angle_min: f64,
        angle_increment: f64,
        range_min: f64,
        range_max: f64,
        mount: [f64; 3],
    ) -> PyResult<Stats> {
        crate::errors::guard(|| {
            let r = slice1(&ranges, "ranges")?;
            let a = match &angles {
                Some(a) => Some(slice1(a, "angles")?),
                None => None,
            };
            let laser = laser_layout(r, a, angle_min, angle_increment, range_min, range_max);
            self.inner
                .insert_laser(&laser, &pose(mount))
                .py()
                .map(stats)
        })
    }

    fn insert_sonar(
        &mut self,
        ranges: PyReadonlyArray1<'_, f64>,
        mounts: PyReadonlyArray2<'_, f64>,
        beam_width: f64,
        range_max: f64,
    ) -> PyResult<Stats> {
        crate::errors::guard(|| {
            let (m, _) = rows(&mounts, 3, "mounts")?;
            let (readings, mounts) =
                sonar_readings(slice1(&ranges, "ranges")?, m, beam_width, range_max)?;
            self.inner.insert_sonar(&readings, &mounts).py().map(stats)
        })
    }

    /// The window (min x, min y, width, height) [cells of the local lattice].
    fn extent(&self) -> PyResult<(i32, i32, usize, usize)> {
        crate::errors::guard(|| {
            Ok({
                let r = self.inner.window();
                (r.min.x, r.min.y, r.width(), r.height())
            })
        })
    }

    fn values<'py>(
        &self,
        py: Python<'py>,
        min_x: i64,
        min_y: i64,
        width: u64,
        height: u64,
    ) -> PyResult<Bound<'py, PyArray2<i16>>> {
        crate::errors::guard(|| {
            grid_views::values(py, self.inner.grid(), min_x, min_y, width, height)
        })
    }

    /// The window resampled in the robot frame: (height, width) int16, row 0 at the robot's
    /// right (most negative y), column 0 behind it (most negative x).
    fn robot_view<'py>(
        &self,
        py: Python<'py>,
        width: usize,
        height: usize,
    ) -> PyResult<Bound<'py, PyArray2<i16>>> {
        crate::errors::guard(|| {
            if width.checked_mul(height).is_none_or(|n| n > 1 << 26) {
                return Err(crate::errors::error(
                    "OptionError",
                    format!("a {width} x {height} robot view is larger than 2^26 cells"),
                ));
            }
            let mut out = Vec::new();
            self.inner.robot_view(width, height, &mut out);
            PyArray1::from_vec(py, out).reshape([height, width])
        })
    }

    fn occupancy_codes<'py>(
        &self,
        py: Python<'py>,
        xs: PyReadonlyArray1<'_, f64>,
        ys: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Bound<'py, PyArray1<u8>>> {
        crate::errors::guard(|| {
            grid_views::occupancy_codes(py, self.inner.grid(), slice1(&xs, "x")?, slice1(&ys, "y")?)
        })
    }

    fn distances<'py>(
        &self,
        py: Python<'py>,
        xs: PyReadonlyArray1<'_, f64>,
        ys: PyReadonlyArray1<'_, f64>,
        max_m: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| {
            grid_views::distances(
                py,
                self.inner.grid(),
                slice1(&xs, "x")?,
                slice1(&ys, "y")?,
                max_m,
            )
        })
    }

    fn limits(&self) -> PyResult<(i16, i16, i16, i16)> {
        crate::errors::guard(|| Ok(grid_views::limits(self.inner.grid())))
    }

    #[getter]
    fn cell_size_m(&self) -> PyResult<f64> {
        crate::errors::guard(|| Ok(self.inner.grid().cell_size_m()))
    }

    #[getter]
    fn origin_m(&self) -> PyResult<(f64, f64)> {
        crate::errors::guard(|| {
            Ok({
                let o = self.inner.grid().origin_m();
                (o.x, o.y)
            })
        })
    }

    /// The options (every field, serde form).
    #[getter]
    fn options<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| to_py(py, self.inner.options()))
    }
}

options_functions!(
    LocalMapOptions,
    default_local_map_options,
    check_local_map_options,
    local_map_options_schema
);
