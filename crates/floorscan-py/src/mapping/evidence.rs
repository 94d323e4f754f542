//! Bindings of `floorscan_core::evidence`: the exact merge of evidence maps. The Python
//! wrapper is `floorscan.mapping.evidence`.

use floorscan_core::evidence::{merge, EvidenceRaster, MAX_RASTER_CELLS};
use floorscan_core::Point2;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::errors::{error, IntoPyResult};

/// Refuses rectangles too large to hold (a bound on memory sized by the caller).
pub fn check_size(width: usize, height: usize) -> PyResult<()> {
    if width.saturating_mul(height) > MAX_RASTER_CELLS {
        return Err(error(
            "OutOfBoundsError",
            format!("{width} x {height} cells is more than {MAX_RASTER_CELLS}"),
        ));
    }
    Ok(())
}

/// The merged origin [m] and evidence array.
type Merged<'py> = ((f64, f64), Bound<'py, PyArray2<i32>>);

/// Sums evidence maps on one cell lattice: `cell_sizes_m[k]`, `origins_m[k]` (corner of
/// cell [0, 0]) and `arrays[k]` ((H, W) int32, row 0 the lowest y). Returns the merged
/// origin and array.
#[pyfunction]
pub fn merge_evidence<'py>(
    py: Python<'py>,
    cell_sizes_m: Vec<f64>,
    origins_m: Vec<(f64, f64)>,
    arrays: Vec<PyReadonlyArray2<'py, i32>>,
) -> PyResult<Merged<'py>> {
    if cell_sizes_m.len() != arrays.len() || origins_m.len() != arrays.len() {
        return Err(error(
            "LengthMismatchError",
            format!(
                "{} arrays, {} cell sizes, {} origins",
                arrays.len(),
                cell_sizes_m.len(),
                origins_m.len()
            ),
        ));
    }
    let mut rasters = Vec::with_capacity(arrays.len());
    for (k, a) in arrays.iter().enumerate() {
        let shape = a.shape();
        let values = a
            .as_slice()
            .map_err(|_| {
                error(
                    "LengthMismatchError",
                    format!("evidence map {k} must be a contiguous int32 array"),
                )
            })?
            .to_vec();
        rasters.push(EvidenceRaster {
            cell_size_m: cell_sizes_m[k],
            origin_m: Point2::new(origins_m[k].0, origins_m[k].1),
            width: shape[1],
            height: shape[0],
            values,
        });
    }
    let merged = py.detach(|| merge(&rasters)).py()?;
    let (w, h) = (merged.width, merged.height);
    let origin = (merged.origin_m.x, merged.origin_m.y);
    Ok((
        origin,
        PyArray1::from_vec(py, merged.values).reshape([h, w])?,
    ))
}
