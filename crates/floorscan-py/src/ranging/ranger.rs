//! Bindings of `floorscan_core::ranger`. Options arrive as a dict of `RangerOptions` fields
//! (its serde form; the others take their defaults), read and validated here.

use floorscan_core::{RangerOptions, Scan, VisualRanger};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::errors::{error, IntoPyResult};
use crate::ground_table::PyGroundTable;
use crate::image::BorrowedImage;
use crate::options::{from_py, to_py};
use crate::scan::PyScan;

#[pyclass(name = "VisualRanger", module = "floorscan._native.ranging")]
pub struct PyVisualRanger {
    pub(crate) inner: VisualRanger,
}

#[pymethods]
impl PyVisualRanger {
    #[new]
    fn new(table: &PyGroundTable, options: &Bound<'_, PyAny>) -> PyResult<Self> {
        crate::errors::guard(|| {
            let options: RangerOptions = from_py(options)?;
            Ok(Self {
                inner: VisualRanger::new(table.inner.clone(), options).py()?,
            })
        })
    }

    /// Scans a (H, W) uint8 or uint16 image; the GIL is released while scanning.
    fn scan(
        &mut self,
        py: Python<'_>,
        image: &Bound<'_, PyAny>,
        timestamp: f64,
    ) -> PyResult<PyScan> {
        crate::errors::guard(|| {
            let mut out = Scan::default();
            if let Ok(a) = image.cast::<PyArray2<u8>>() {
                let img = BorrowedImage::new(a)?;
                let view = img.view()?;
                let ranger = &mut self.inner;
                py.detach(|| ranger.scan_into(&view, timestamp, &mut out))
                    .py()?;
            } else if let Ok(a) = image.cast::<PyArray2<u16>>() {
                let img = BorrowedImage::new(a)?;
                let view = img.view()?;
                let ranger = &mut self.inner;
                py.detach(|| ranger.scan_into(&view, timestamp, &mut out))
                    .py()?;
            } else {
                return Err(error(
                    "ImageError",
                    "image must be a 2-D numpy array of uint8 or uint16 (H, W)".into(),
                ));
            }
            Ok(PyScan { inner: out })
        })
    }

    /// The sampled image columns, in output order.
    #[getter]
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<u32>>> {
        crate::errors::guard(|| Ok(PyArray1::from_vec(py, self.inner.columns())))
    }

    /// The options (every field, serde form).
    #[getter]
    fn options<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| to_py(py, self.inner.options()))
    }

    #[getter]
    fn table(&self) -> PyResult<PyGroundTable> {
        crate::errors::guard(|| {
            Ok(PyGroundTable {
                inner: self.inner.table().clone(),
            })
        })
    }
}
