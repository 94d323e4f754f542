//! Bindings of `floorscan_core::floor_parallax`: the floor-parallax cue, which ranges a frame
//! with an edge ranger and checks its boundaries against the motion since an earlier frame.

use floorscan_core::{FloorParallax, ParallaxOptions, Pose2, Scan};
use numpy::PyArray2;
use pyo3::prelude::*;

use crate::errors::{error, IntoPyResult};
use crate::ground_table::PyGroundTable;
use crate::image::BorrowedImage;
use crate::options::{from_py, to_py};
use crate::ranger::PyVisualRanger;
use crate::scan::PyScan;

#[pyclass(name = "FloorParallax", module = "floorscan._native.ranging")]
pub struct PyFloorParallax {
    inner: FloorParallax,
}

#[pymethods]
impl PyFloorParallax {
    #[new]
    fn new(table: &PyGroundTable, options: &Bound<'_, PyAny>) -> PyResult<Self> {
        crate::errors::guard(|| {
            let options: ParallaxOptions = from_py(options)?;
            Ok(Self {
                inner: FloorParallax::new(table.inner.clone(), options).py()?,
            })
        })
    }

    /// Ranges a (H, W) uint8 or uint16 image with `ranger` and checks its boundaries against
    /// the earlier frames when `world_from_camera` (x, y, yaw) is given; returns the scan and
    /// the report `(baseline_m, vetoes, noise_grey)`. The GIL is released meanwhile.
    #[pyo3(signature = (ranger, image, timestamp, world_from_camera=None))]
    fn scan(
        &mut self,
        py: Python<'_>,
        mut ranger: PyRefMut<'_, PyVisualRanger>,
        image: &Bound<'_, PyAny>,
        timestamp: f64,
        world_from_camera: Option<(f64, f64, f64)>,
    ) -> PyResult<(PyScan, (f64, usize, f64))> {
        crate::errors::guard(|| {
            let pose = world_from_camera.map(|(x, y, yaw)| Pose2::new(x, y, yaw));
            let mut out = Scan::default();
            let cue = &mut self.inner;
            let ranger = &mut ranger.inner;
            let report = if let Ok(a) = image.cast::<PyArray2<u8>>() {
                let img = BorrowedImage::new(a)?;
                let view = img.view()?;
                py.detach(|| cue.scan_into(ranger, &view, timestamp, pose, &mut out))
                    .py()?
            } else if let Ok(a) = image.cast::<PyArray2<u16>>() {
                let img = BorrowedImage::new(a)?;
                let view = img.view()?;
                py.detach(|| cue.scan_into(ranger, &view, timestamp, pose, &mut out))
                    .py()?
            } else {
                return Err(error(
                    "ImageError",
                    "image must be a 2-D numpy array of uint8 or uint16 (H, W)".into(),
                ));
            };
            Ok((
                PyScan { inner: out },
                (report.baseline_m, report.vetoes, report.noise_grey),
            ))
        })
    }

    /// Forgets the earlier frames.
    fn reset(&mut self) -> PyResult<()> {
        crate::errors::guard(|| {
            self.inner.reset();
            Ok(())
        })
    }

    /// The options (every field, serde form).
    #[getter]
    fn options<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| to_py(py, self.inner.options()))
    }
}
