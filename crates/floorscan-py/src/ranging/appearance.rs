//! Bindings of `floorscan_core::appearance`. Options arrive as a dict of `AppearanceOptions`
//! fields (its serde form; the others take their defaults), read and validated here.

use floorscan_core::{
    fuse_scans_driven, AppearanceOptions, AppearanceRanger, ColourView, FusionOptions, Pixel, Scan,
    TextureState,
};
use numpy::{
    Element, PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::errors::{error, IntoPyResult};
use crate::ground_table::PyGroundTable;
use crate::image::BorrowedImage;
use crate::options::{from_py, to_py};
use crate::scan::PyScan;

#[pyclass(name = "AppearanceRanger", module = "floorscan._native.ranging")]
pub struct PyAppearanceRanger {
    inner: AppearanceRanger,
}

fn scan_colour<P: Pixel + Element>(
    py: Python<'_>,
    ranger: &mut AppearanceRanger,
    array: &Bound<'_, PyArray3<P>>,
    timestamp: f64,
    out: &mut Scan,
) -> PyResult<()> {
    let shape = array.shape();
    if shape[2] != 3 || !array.is_c_contiguous() {
        return Err(error(
            "ImageError",
            format!("colour image must be a C-contiguous (H, W, 3) array, got shape {shape:?}"),
        ));
    }
    let ro = array.readonly();
    let data = ro
        .as_slice()
        .map_err(|e| error("ImageError", e.to_string()))?;
    let view = ColourView::interleaved(data, shape[1], shape[0]).py()?;
    py.detach(|| ranger.scan_into(&view, timestamp, out)).py()
}

fn scan_grey<P: Pixel + Element>(
    py: Python<'_>,
    ranger: &mut AppearanceRanger,
    array: &Bound<'_, PyArray2<P>>,
    timestamp: f64,
    out: &mut Scan,
) -> PyResult<()> {
    let img = BorrowedImage::new(array)?;
    let view = ColourView::grey(img.view()?);
    py.detach(|| ranger.scan_into(&view, timestamp, out)).py()
}

#[pymethods]
impl PyAppearanceRanger {
    #[new]
    fn new(table: &PyGroundTable, options: &Bound<'_, PyAny>) -> PyResult<Self> {
        crate::errors::guard(|| {
            let options: AppearanceOptions = from_py(options)?;
            Ok(Self {
                inner: AppearanceRanger::new(table.inner.clone(), options).py()?,
            })
        })
    }

    /// Learns from the frame's reference band and scans it: a (H, W) grey or C-contiguous
    /// (H, W, 3) RGB array of uint8 or uint16; the GIL is released while scanning.
    fn scan(
        &mut self,
        py: Python<'_>,
        image: &Bound<'_, PyAny>,
        timestamp: f64,
    ) -> PyResult<PyScan> {
        let mut out = Scan::default();
        let r = &mut self.inner;
        if let Ok(a) = image.cast::<PyArray3<u8>>() {
            scan_colour(py, r, a, timestamp, &mut out)?;
        } else if let Ok(a) = image.cast::<PyArray3<u16>>() {
            scan_colour(py, r, a, timestamp, &mut out)?;
        } else if let Ok(a) = image.cast::<PyArray2<u8>>() {
            scan_grey(py, r, a, timestamp, &mut out)?;
        } else if let Ok(a) = image.cast::<PyArray2<u16>>() {
            scan_grey(py, r, a, timestamp, &mut out)?;
        } else {
            return Err(error(
                "ImageError",
                "image must be a (H, W) or (H, W, 3) numpy array of uint8 or uint16".into(),
            ));
        }
        Ok(PyScan { inner: out })
    }

    /// Forgets the learned floor.
    fn reset_model(&mut self) {
        self.inner.reset_model();
    }

    /// Per sampled column of the last scan, the packed bins of the pixels of the run that
    /// made its boundary: (columns, BOUNDARY_SAMPLES) uint32, NO_SAMPLE (2**32 - 1) where none.
    fn boundary_samples<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        crate::errors::guard(|| {
            let samples = self.inner.boundary_samples();
            let flat: Vec<u32> = samples.iter().flatten().copied().collect();
            PyArray1::from_vec(py, flat)
                .reshape([samples.len(), floorscan_core::appearance::BOUNDARY_SAMPLES])
                .map_err(|e| error("InternalError", e.to_string()))
        })
    }

    /// Per sampled column of the last scan: whether it crossed floor known only as floor the
    /// robot drove over (bool array).
    #[getter]
    fn driven_floor_columns<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_slice(py, self.inner.driven_floor_columns())
    }

    /// Per sampled column of the last scan: the row [px] of the first border between the
    /// reference's floor and driven-over floor (NaN where none; float64 array).
    #[getter]
    fn driven_floor_borders<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.inner.driven_floor_borders())
    }

    /// Learns packed samples of boundaries driven through as floor (from the next frame);
    /// returns how many were learned (NO_SAMPLE entries are skipped).
    fn learn_driven_floor(&mut self, samples: PyReadonlyArray1<'_, u32>) -> PyResult<usize> {
        crate::errors::guard(|| {
            let s = samples
                .as_slice()
                .map_err(|e| error("OptionError", e.to_string()))?;
            self.inner.learn_driven_floor(s).py()
        })
    }

    /// Frames learned since the last reset.
    #[getter]
    fn frames_learned(&self) -> u64 {
        self.inner.model().frames()
    }

    #[getter]
    fn columns<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u32>> {
        PyArray1::from_vec(py, self.inner.columns())
    }

    /// The options (every field, serde form).
    #[getter]
    fn options<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| to_py(py, self.inner.options()))
    }
}

/// Fuses an edge scan and an appearance scan of the same frame and columns
/// (`floorscan_core::fusion`) of an image `image_height` rows tall, with `options` (a dict
/// of `FusionOptions` fields, the others at their defaults), after frames whose floor was
/// judged textured or not (`previous_textured`, inherited `frames_inherited` frames in a row);
/// returns the fused scan and the judgement after this frame, `(scan, textured,
/// frames_inherited)`. `driven_floor`: the appearance ranger's `driven_floor_borders` (an edge
/// on such a border is the border of floor driven over, not an obstacle).
#[pyfunction]
#[pyo3(signature = (edge, appearance, options, image_height, previous_textured = false, frames_inherited = 0, driven_floor = None))]
#[allow(clippy::too_many_arguments)]
pub fn fuse(
    edge: &PyScan,
    appearance: &PyScan,
    options: &Bound<'_, PyAny>,
    image_height: usize,
    previous_textured: bool,
    frames_inherited: u32,
    driven_floor: Option<PyReadonlyArray1<'_, f64>>,
) -> PyResult<(PyScan, bool, u32)> {
    let options: FusionOptions = from_py(options)?;
    options.validate().py()?;
    let mut out = Scan::default();
    let previous = TextureState {
        textured: previous_textured,
        frames_inherited,
    };
    let driven: &[f64] = match &driven_floor {
        Some(a) => a
            .as_slice()
            .map_err(|e| error("OptionError", e.to_string()))?,
        None => &[],
    };
    let state = fuse_scans_driven(
        &edge.inner,
        &appearance.inner,
        options.snap_distance_rows(image_height),
        options.texture_share,
        previous,
        driven,
        &mut out,
    )
    .py()?;
    Ok((
        PyScan { inner: out },
        state.textured,
        state.frames_inherited,
    ))
}
