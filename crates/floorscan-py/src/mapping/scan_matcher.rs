//! Bindings of `floorscan_core::scan_matcher`: the correlative scan matcher with its hit map,
//! its likelihood field and its filter, one call a frame (`floorscan.mapping.ScanMatcher`
//! wraps it).

use floorscan_core::match_filter::MatchResult;
use floorscan_core::scan_matcher::CachedField;
use floorscan_core::{Pose2, ScanMatcher, ScanMatcherOptions};
use numpy::{PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::arrays::{pose, rows};
use crate::errors::{error, guard, IntoPyResult};
use crate::options::from_py;

/// A match as Python sees it: ((x, y, yaw), score, accepted, points).
type Match = ((f64, f64, f64), f64, bool, usize);

fn to_tuple(r: MatchResult) -> Match {
    (
        (r.pose.x, r.pose.y, r.pose.yaw),
        r.score,
        r.accepted,
        r.points,
    )
}

/// `points` (N, 2) float64 as rows (the array's own memory, no copy).
fn points<'a>(a: &'a PyReadonlyArray2<'_, f64>) -> PyResult<&'a [[f64; 2]]> {
    let (flat, _) = rows(a, 2, "points")?;
    Ok(flat.as_chunks::<2>().0)
}

/// One of the matcher's per-frame calls on `points` near `prior`, the GIL released.
fn frame(
    py: Python<'_>,
    inner: &mut ScanMatcher,
    points: &PyReadonlyArray2<'_, f64>,
    prior: [f64; 3],
    step: fn(&mut ScanMatcher, &[[f64; 2]], Pose2) -> floorscan_core::Result<MatchResult>,
) -> PyResult<Match> {
    guard(|| {
        let pts = self::points(points)?;
        py.detach(|| step(inner, pts, pose(prior)))
            .py()
            .map(to_tuple)
    })
}

fn field_tuple<'py>(py: Python<'py>, f: &CachedField) -> PyResult<FieldTuple<'py>> {
    let a = numpy::PyArray1::from_slice(py, &f.values).reshape([f.height, f.width])?;
    Ok((a, f.i0, f.j0))
}

/// A field as Python sees it: ((H, W) float32, i0, j0), its cell (0, 0) the grid's (i0, j0).
type FieldTuple<'py> = (Bound<'py, PyArray2<f32>>, i64, i64);

/// The matcher of `options` (a dict of `ScanMatcherOptions`' fields) whose map is centred on
/// `center` [m, world frame].
#[pyclass(name = "ScanMatcher", module = "floorscan._native.mapping")]
pub struct PyScanMatcher {
    inner: ScanMatcher,
}

#[pymethods]
impl PyScanMatcher {
    #[new]
    fn new(options: &Bound<'_, PyAny>, center: (f64, f64)) -> PyResult<Self> {
        guard(|| {
            let o: ScanMatcherOptions = from_py(options)?;
            Ok(Self {
                inner: ScanMatcher::new(o, center).py()?,
            })
        })
    }

    /// One frame: `points` (N, 2) float64 [m, robot frame] matched near the odometry pose
    /// `prior` (world_from_robot) after the filter's prediction, fused with it, the new points
    /// stored; ((x, y, yaw), score, accepted, points).
    fn correct(
        &mut self,
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        prior: [f64; 3],
    ) -> PyResult<Match> {
        frame(py, &mut self.inner, &points, prior, ScanMatcher::correct)
    }

    /// The best pose for `points` near `prior`, the map unchanged (no filter).
    fn match_scan(
        &mut self,
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        prior: [f64; 3],
    ) -> PyResult<Match> {
        frame(py, &mut self.inner, &points, prior, ScanMatcher::match_scan)
    }

    /// Stores `points` seen from `pose` (only those the map does not explain when
    /// `novel_only`); how many were stored.
    fn insert(
        &mut self,
        points: PyReadonlyArray2<'_, f64>,
        pose: [f64; 3],
        novel_only: bool,
    ) -> PyResult<usize> {
        guard(|| {
            let pts = self::points(&points)?;
            self.inner.insert(pts, self::pose(pose), novel_only).py()
        })
    }

    /// The filter's prediction for odometry's `prior`.
    fn predict(&mut self, prior: [f64; 3]) -> PyResult<(f64, f64, f64)> {
        guard(|| {
            let o = self.inner.options().clone();
            let p = Pose2::checked(prior[0], prior[1], prior[2]).py()?;
            let p = self.inner.filter.predict(&o, p);
            Ok((p.x, p.y, p.yaw))
        })
    }

    /// The information matrix (3, 3) of the match of `points` at `pose` on the kept field.
    fn information<'py>(
        &mut self,
        py: Python<'py>,
        points: PyReadonlyArray2<'_, f64>,
        pose: [f64; 3],
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        guard(|| {
            let pts = self::points(&points)?;
            let m = self.inner.information(pts, self::pose(pose)).py()?;
            matrix(py, &m.map(|r| r.to_vec()))
        })
    }

    /// The match `found` ((x, y, yaw), score, accepted, points) fused with the prediction
    /// `prior` with the match's `information` (3, 3) float64.
    fn fuse(
        &mut self,
        found: Match,
        prior: [f64; 3],
        information: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Match> {
        guard(|| {
            let square = information.shape() == [3, 3];
            let j = information
                .as_slice()
                .ok()
                .filter(|_| square)
                .ok_or_else(|| {
                    error(
                        "LengthMismatchError",
                        "`information` must be a contiguous (3, 3) float64 array".into(),
                    )
                })?;
            let j: [[f64; 3]; 3] = std::array::from_fn(|r| std::array::from_fn(|c| j[3 * r + c]));
            let ((x, y, yaw), score, accepted, points) = found;
            let found = MatchResult {
                pose: Pose2::new(x, y, yaw),
                score,
                accepted,
                points,
            };
            let o = self.inner.options().clone();
            Ok(to_tuple(self.inner.filter.fuse(&o, found, pose(prior), &j)))
        })
    }

    /// The hit counts (side, side) uint8 (row 0 = lowest y), a copy.
    #[getter]
    fn hits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u8>>> {
        let n = self.inner.side();
        numpy::PyArray1::from_slice(py, self.inner.hits()).reshape([n, n])
    }

    /// Cells on a side of the grid.
    #[getter]
    fn side(&self) -> usize {
        self.inner.side()
    }

    /// The grid's cell (0, 0)'s lower-left corner [m].
    #[getter]
    fn origin_m(&self) -> (f64, f64) {
        self.inner.origin_m()
    }

    /// Scans stored so far.
    #[getter]
    fn frames(&self) -> u64 {
        self.inner.frames()
    }

    /// The likelihood field kept (a copy) or None.
    #[getter]
    fn field<'py>(&self, py: Python<'py>) -> PyResult<Option<FieldTuple<'py>>> {
        self.inner
            .cached_field()
            .map(|f| field_tuple(py, f))
            .transpose()
    }

    /// A fresh likelihood field over the square of half-side `half_m` [m] around (x, y).
    fn field_around<'py>(
        &self,
        py: Python<'py>,
        x: f64,
        y: f64,
        half_m: f64,
    ) -> PyResult<FieldTuple<'py>> {
        guard(|| field_tuple(py, &self.inner.field_around(x, y, half_m).py()?))
    }

    /// Makes the kept field cover the square of half-side `half_m` around (x, y); returns it.
    fn cover<'py>(
        &mut self,
        py: Python<'py>,
        x: f64,
        y: f64,
        half_m: f64,
    ) -> PyResult<FieldTuple<'py>> {
        guard(|| {
            let f = self.inner.cover(x, y, half_m).py()?.clone();
            field_tuple(py, &f)
        })
    }

    /// The covariance (5, 5) of the state's error: x [m], y [m], yaw [rad], the turn scale
    /// error, the heading drift [rad/m].
    #[getter]
    fn get_covariance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, &self.inner.filter.covariance.map(|r| r.to_vec()))
    }

    #[setter]
    fn set_covariance(&mut self, value: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
        guard(|| {
            let ok = value.shape() == [5, 5];
            let s = value.as_slice().ok().filter(|_| ok).ok_or_else(|| {
                error(
                    "LengthMismatchError",
                    "the covariance must be a contiguous (5, 5) float64 array".into(),
                )
            })?;
            self.inner.filter.covariance =
                std::array::from_fn(|r| std::array::from_fn(|c| s[5 * r + c]));
            Ok(())
        })
    }

    /// Odometry's estimated errors: (turn scale error, heading drift [rad/m]).
    #[getter]
    fn get_calibration(&self) -> (f64, f64) {
        let [a, b] = self.inner.filter.calibration;
        (a, b)
    }

    #[setter]
    fn set_calibration(&mut self, value: (f64, f64)) {
        self.inner.filter.calibration = [value.0, value.1];
    }

    /// The pose kept last (world_from_robot), None before the first frame.
    #[getter]
    fn get_last_pose(&self) -> Option<(f64, f64, f64)> {
        self.inner.filter.last.map(|p| (p.x, p.y, p.yaw))
    }

    #[setter]
    fn set_last_pose(&mut self, value: Option<[f64; 3]>) -> PyResult<()> {
        guard(|| {
            self.inner.filter.last = match value {
                Some(p) => Some(Pose2::checked(p[0], p[1], p[2]).py()?),
                None => None,
            };
            Ok(())
        })
    }

    /// The last fused match's innovation as a Mahalanobis distance (None before any).
    #[getter]
    fn last_mahalanobis(&self) -> Option<f64> {
        self.inner.filter.last_mahalanobis
    }
}

/// Rows of equal length as a 2-D float64 array.
fn matrix<'py>(py: Python<'py>, rows: &[Vec<f64>]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    Ok(PyArray2::from_vec2(py, rows)?)
}
