//! Bindings of `floorscan_core::hit_map`: the scan matcher's persistent hit map, stored into
//! in place (the numpy counts and cached likelihood field `ScanMatcher` keeps).

use floorscan_core::hit_map::{FieldMut, HitMap};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyReadwriteArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::arrays::rows;
use crate::errors::{error, guard, IntoPyResult};

fn offsets(a: &PyReadonlyArray2<'_, i64>, name: &str) -> PyResult<Vec<(i64, i64)>> {
    let bad = || {
        error(
            "LengthMismatchError",
            format!("`{name}` must be a contiguous (N, 2) int64 array"),
        )
    };
    if a.shape()[1] != 2 {
        return Err(bad());
    }
    let s = a.as_slice().map_err(|_| bad())?;
    Ok(s.chunks_exact(2).map(|c| (c[0], c[1])).collect())
}

/// The hit map of `side` x `side` cells of `cell_size_m` [m] from `origin_m`, ignoring points
/// beyond `range_max_m`; `novelty` (N, 2) int64 the novelty disc's cell offsets (di, dj);
/// `stamp` (M, 2) int64 and `stamp_values` (M,) float32 the field's stamp.
#[pyclass(name = "HitMap", module = "floorscan._native.drive")]
pub struct PyHitMap {
    inner: HitMap,
}

#[pymethods]
impl PyHitMap {
    #[new]
    fn new(
        side: usize,
        cell_size_m: f64,
        origin_m: (f64, f64),
        range_max_m: f64,
        novelty: PyReadonlyArray2<'_, i64>,
        stamp: PyReadonlyArray2<'_, i64>,
        stamp_values: PyReadonlyArray1<'_, f32>,
    ) -> PyResult<Self> {
        guard(|| {
            let nov = offsets(&novelty, "novelty")?;
            let st = offsets(&stamp, "stamp")?;
            let vals = stamp_values.as_slice().map_err(|_| {
                error(
                    "LengthMismatchError",
                    "`stamp_values` must be a contiguous float32 array".into(),
                )
            })?;
            if vals.len() != st.len() {
                return Err(error(
                    "LengthMismatchError",
                    format!("{} stamp offsets but {} values", st.len(), vals.len()),
                ));
            }
            let stamp = st.iter().zip(vals).map(|(&(a, b), &v)| (a, b, v)).collect();
            Ok(Self {
                inner: HitMap::new(side, cell_size_m, origin_m, range_max_m, nov, stamp).py()?,
            })
        })
    }

    /// Stores `points` (N, 2) float64 [m, robot frame] seen from `pose` into `hits` ((side,
    /// side) uint8, in place), only those without a stored hit in the novelty disc when
    /// `novel_only`, and raises `field` (float32, in place; its cell (0, 0) the grid's cell
    /// `field_origin`) to the new hits' stamps. Returns how many were stored.
    #[pyo3(signature = (hits, points, pose, novel_only, field=None, field_origin=(0, 0)))]
    #[allow(clippy::too_many_arguments)]
    fn insert(
        &mut self,
        py: Python<'_>,
        mut hits: PyReadwriteArray2<'_, u8>,
        points: PyReadonlyArray2<'_, f64>,
        pose: [f64; 3],
        novel_only: bool,
        field: Option<PyReadwriteArray2<'_, f32>>,
        field_origin: (i64, i64),
    ) -> PyResult<usize> {
        guard(|| {
            let (flat, n) = rows(&points, 2, "points")?;
            let pts: Vec<[f64; 2]> = (0..n).map(|k| [flat[2 * k], flat[2 * k + 1]]).collect();
            let hits = hits.as_slice_mut().map_err(|_| {
                error(
                    "LengthMismatchError",
                    "`hits` must be a C-contiguous uint8 array".into(),
                )
            })?;
            let mut field = field;
            let field = match field.as_mut() {
                Some(f) => {
                    let (height, width) = (f.shape()[0], f.shape()[1]);
                    let values = f.as_slice_mut().map_err(|_| {
                        error(
                            "LengthMismatchError",
                            "`field` must be a C-contiguous float32 array".into(),
                        )
                    })?;
                    Some(FieldMut {
                        values,
                        width,
                        height,
                        i0: field_origin.0,
                        j0: field_origin.1,
                    })
                }
                None => None,
            };
            let inner = &mut self.inner;
            let pose = crate::arrays::pose(pose);
            py.detach(|| inner.insert(hits, &pts, pose, novel_only, field))
                .py()
        })
    }
}
