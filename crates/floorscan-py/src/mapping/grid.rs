//! Bindings of the map builder's global grid (`floorscan_core::{grid, inserter, queries}`):
//! a grid and the inserter that feeds it. Options arrive as dicts of `GridOptions` and
//! `InserterOptions` fields (their serde form), read and validated here. Batch inserts release
//! the GIL.

use floorscan_core::{Evidence, Grid, GridOptions, Inserter, InserterOptions, Point2, Pose2, Ray};
use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::arrays::{laser_layout, pose, rows, slice1, sonar_readings, stats, Stats};
use crate::errors::{error, IntoPyResult};
use crate::grid_views::{distances, extent, limits, occupancy_codes, values};
use crate::options::{from_py, to_py};
use crate::scan::PyScan;

#[pyclass(name = "OccupancyGrid", module = "floorscan._native.mapping")]
pub struct PyOccupancyGrid {
    grid: Grid,
    inserter: Inserter,
}

#[pymethods]
impl PyOccupancyGrid {
    #[new]
    fn new(grid_options: &Bound<'_, PyAny>, inserter_options: &Bound<'_, PyAny>) -> PyResult<Self> {
        crate::errors::guard(|| {
            let go: GridOptions = from_py(grid_options)?;
            let io: InserterOptions = from_py(inserter_options)?;
            Ok(Self {
                grid: Grid::new(go).py()?,
                inserter: Inserter::new(io).py()?,
            })
        })
    }

    fn copy(&self) -> PyResult<Self> {
        crate::errors::guard(|| {
            Ok(Self {
                grid: self.grid.clone(),
                inserter: self.inserter.clone(),
            })
        })
    }

    fn insert_scan(
        &mut self,
        py: Python<'_>,
        scan: &PyScan,
        pose: [f64; 3],
        mount: [f64; 3],
    ) -> PyResult<Stats> {
        crate::errors::guard(|| {
            let (grid, ins, scan) = (&mut self.grid, &mut self.inserter, &scan.inner);
            py.detach(|| ins.insert_scan(grid, scan, &self::pose(pose), &self::pose(mount)))
                .py()
                .map(stats)
        })
    }

    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (ranges, angles, angle_min, angle_increment, range_min, range_max, pose, mount))]
    fn insert_laser(
        &mut self,
        ranges: PyReadonlyArray1<'_, f64>,
        angles: Option<PyReadonlyArray1<'_, f64>>,
        angle_min: f64,
        angle_increment: f64,
        range_min: f64,
        range_max: f64,
        pose: [f64; 3],
        mount: [f64; 3],
    ) -> PyResult<Stats> {
        crate::errors::guard(|| {
            let r = slice1(&ranges, "ranges")?;
            let a = match &angles {
                Some(a) => Some(slice1(a, "angles")?),
                None => None,
            };
            let laser = laser_layout(r, a, angle_min, angle_increment, range_min, range_max);
            self.inserter
                .insert_laser(
                    &mut self.grid,
                    &laser,
                    &self::pose(pose),
                    &self::pose(mount),
                )
                .py()
                .map(stats)
        })
    }

    /// N scans of B beams: ranges (N, B), poses (N, 3). The GIL is released.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (ranges, poses, angles, angle_min, angle_increment, range_min, range_max, mount))]
    fn insert_lasers(
        &mut self,
        py: Python<'_>,
        ranges: PyReadonlyArray2<'_, f64>,
        poses: PyReadonlyArray2<'_, f64>,
        angles: Option<PyReadonlyArray1<'_, f64>>,
        angle_min: f64,
        angle_increment: f64,
        range_min: f64,
        range_max: f64,
        mount: [f64; 3],
    ) -> PyResult<Stats> {
        crate::errors::guard(|| {
            let beams = ranges.shape()[1];
            let (r, n) = rows(&ranges, beams, "ranges")?;
            let (p, np) = rows(&poses, 3, "poses")?;
            if n != np {
                return Err(error(
                    "LengthMismatchError",
                    format!("{n} scans but {np} poses"),
                ));
            }
            let a = match &angles {
                Some(a) => Some(slice1(a, "angles")?),
                None => None,
            };
            let first = &r[..beams.min(r.len())];
            let layout = laser_layout(first, a, angle_min, angle_increment, range_min, range_max);
            let poses: Vec<Pose2> = p.chunks(3).map(|c| Pose2::new(c[0], c[1], c[2])).collect();
            let (grid, ins) = (&mut self.grid, &mut self.inserter);
            py.detach(|| ins.insert_lasers(grid, &layout, r, &poses, &self::pose(mount)))
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
        pose: [f64; 3],
    ) -> PyResult<Stats> {
        crate::errors::guard(|| {
            let (m, _) = rows(&mounts, 3, "mounts")?;
            let (readings, mounts) =
                sonar_readings(slice1(&ranges, "ranges")?, m, beam_width, range_max)?;
            self.inserter
                .insert_sonar(&mut self.grid, &readings, &self::pose(pose), &mounts)
                .py()
                .map(stats)
        })
    }

    /// One batch of world rays: starts (N, 2), ends (N, 2), hits (N,). GIL released.
    fn insert_rays(
        &mut self,
        py: Python<'_>,
        starts: PyReadonlyArray2<'_, f64>,
        ends: PyReadonlyArray2<'_, f64>,
        hits: PyReadonlyArray1<'_, bool>,
        hit_nats: f64,
        miss_nats: f64,
    ) -> PyResult<Stats> {
        crate::errors::guard(|| {
            let (s, n) = rows(&starts, 2, "starts")?;
            let (e, ne) = rows(&ends, 2, "ends")?;
            let h = hits.as_slice().map_err(|_| {
                error(
                    "LengthMismatchError",
                    "`hits` must be a contiguous bool array".into(),
                )
            })?;
            if ne != n || h.len() != n {
                return Err(error(
                    "LengthMismatchError",
                    format!("{n} starts, {ne} ends and {} hit flags", h.len()),
                ));
            }
            let rays: Vec<Ray> = (0..n)
                .map(|i| Ray {
                    from: Point2::new(s[2 * i], s[2 * i + 1]),
                    to: Point2::new(e[2 * i], e[2 * i + 1]),
                    hit: h[i],
                })
                .collect();
            let (grid, ins) = (&mut self.grid, &mut self.inserter);
            py.detach(|| {
                ins.insert_rays(
                    grid,
                    &rays,
                    Evidence {
                        hit_nats,
                        miss_nats,
                    },
                )
            })
            .py()
            .map(stats)
        })
    }

    /// The exported rectangle (min x, min y, width, height) [cells].
    fn extent(&self) -> PyResult<(i32, i32, usize, usize)> {
        crate::errors::guard(|| Ok(extent(&self.grid)))
    }

    fn values<'py>(
        &self,
        py: Python<'py>,
        min_x: i64,
        min_y: i64,
        width: u64,
        height: u64,
    ) -> PyResult<Bound<'py, PyArray2<i16>>> {
        crate::errors::guard(|| values(py, &self.grid, min_x, min_y, width, height))
    }

    /// Writes an (H, W) int16 array of raw values with its first cell at (min_x, min_y).
    fn write_values(
        &mut self,
        min_x: i64,
        min_y: i64,
        array: PyReadonlyArray2<'_, i16>,
    ) -> PyResult<()> {
        crate::errors::guard(|| {
            let shape = array.shape();
            let data = array.as_slice().map_err(|_| {
                error(
                    "LengthMismatchError",
                    "values must be a contiguous int16 array".into(),
                )
            })?;
            let rect = self
                .grid
                .checked_rect(min_x, min_y, shape[1] as u64, shape[0] as u64)
                .py()?;
            self.grid.write_rect(rect, data).py()
        })
    }

    fn occupancy_codes<'py>(
        &self,
        py: Python<'py>,
        xs: PyReadonlyArray1<'_, f64>,
        ys: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Bound<'py, PyArray1<u8>>> {
        crate::errors::guard(|| {
            occupancy_codes(py, &self.grid, slice1(&xs, "x")?, slice1(&ys, "y")?)
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
            distances(py, &self.grid, slice1(&xs, "x")?, slice1(&ys, "y")?, max_m)
        })
    }

    /// Starts keeping the unclamped evidence layer (before the first update).
    fn keep_evidence(&mut self) -> PyResult<()> {
        self.grid.keep_evidence().py()
    }

    #[getter]
    fn keeps_evidence(&self) -> bool {
        self.grid.keeps_evidence()
    }

    /// (min x, min y, width, height) [cells] of the non-zero evidence, None if there is none.
    fn evidence_extent(&self) -> Option<(i32, i32, usize, usize)> {
        self.grid
            .evidence_rect()
            .map(|r| (r.min.x, r.min.y, r.width(), r.height()))
    }

    /// The evidence of a rectangle as an (H, W) int32 array [1/1000 nat], row 0 the lowest y.
    fn evidence_values<'py>(
        &self,
        py: Python<'py>,
        min_x: i32,
        min_y: i32,
        width: usize,
        height: usize,
    ) -> PyResult<Bound<'py, PyArray2<i32>>> {
        crate::evidence::check_size(width, height)?;
        let rect = floorscan_core::CellRect {
            min: floorscan_core::CellIndex::new(min_x, min_y),
            max: floorscan_core::CellIndex::new(
                min_x.saturating_add(width as i32),
                min_y.saturating_add(height as i32),
            ),
        };
        let mut out = Vec::new();
        py.detach(|| self.grid.read_evidence_rect(rect, &mut out));
        PyArray1::from_vec(py, out).reshape([height, width])
    }

    /// (clamp_min, clamp_max, occupied_at, free_at) in stored units (1/1000 nat).
    fn limits(&self) -> PyResult<(i16, i16, i16, i16)> {
        crate::errors::guard(|| Ok(limits(&self.grid)))
    }

    #[getter]
    fn cell_size_m(&self) -> PyResult<f64> {
        crate::errors::guard(|| Ok(self.grid.cell_size_m()))
    }

    #[getter]
    fn origin_m(&self) -> PyResult<(f64, f64)> {
        crate::errors::guard(|| {
            Ok({
                let o = self.grid.origin_m();
                (o.x, o.y)
            })
        })
    }

    /// Fixed bounds (min x, min y, max x, max y) [cells, max excluded], None if growing.
    #[getter]
    fn fixed_cells(&self) -> PyResult<Option<(i32, i32, i32, i32)>> {
        crate::errors::guard(|| {
            Ok(self
                .grid
                .fixed_cells()
                .map(|r| (r.min.x, r.min.y, r.max.x, r.max.y)))
        })
    }

    #[getter]
    fn memory_bytes(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.grid.memory_bytes() + self.inserter.memory_bytes()))
    }

    #[getter]
    fn grid_memory_bytes(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.grid.memory_bytes()))
    }

    #[getter]
    fn allocated_tiles(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.grid.allocated_tiles()))
    }

    /// The grid options (every field, serde form).
    #[getter]
    fn grid_options<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| to_py(py, self.grid.options()))
    }

    /// The inserter options (every field, serde form).
    #[getter]
    fn inserter_options<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| to_py(py, self.inserter.options()))
    }
}
