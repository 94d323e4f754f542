//! Bindings of `floorscan_codec::ReadAhead`: a dataset's PNG files decoded ahead of the Python
//! frame loop by Rust threads (no GIL, no Python per frame on their side).

use std::path::PathBuf;
use std::sync::Mutex;

use floorscan_codec::ReadAhead;
use pyo3::prelude::*;

use crate::errors::{codec_to_pyerr, error, guard};
use crate::png::to_numpy;

/// Grey images of PNG `paths`, in order, decoded ahead by `threads` Rust threads with at most
/// `depth` decoded frames waiting. Iterating gives each file's (H, W) uint8/uint16 image, or
/// None for a file it did not decode (not a PNG, unreadable, damaged, over `max_pixels`): read
/// that one with the general reader, which reports the error.
#[pyclass(name = "PngReadAhead", module = "floorscan._native.formats")]
pub struct PyPngReadAhead {
    inner: Mutex<Option<ReadAhead>>,
}

#[pymethods]
impl PyPngReadAhead {
    #[new]
    fn new(paths: Vec<PathBuf>, max_pixels: u64, depth: usize, threads: usize) -> PyResult<Self> {
        guard(|| {
            let ahead =
                ReadAhead::new(paths, max_pixels, depth, threads).map_err(codec_to_pyerr)?;
            Ok(Self {
                inner: Mutex::new(Some(ahead)),
            })
        })
    }

    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        guard(|| {
            let next = py.detach(|| {
                let mut inner = self.inner.lock().map_err(|_| "poisoned")?;
                Ok::<_, &str>(inner.as_mut().and_then(ReadAhead::next_frame))
            });
            match next.map_err(|e| error("InternalError", e.into()))? {
                None => Ok(None),
                Some(None) => Ok(Some(py.None().into_bound(py))),
                Some(Some(img)) => to_numpy(py, img).map(Some),
            }
        })
    }

    /// Stops the decoding threads (and waits for them); iterating then ends.
    fn close(&self, py: Python<'_>) -> PyResult<()> {
        guard(|| {
            let ahead = self
                .inner
                .lock()
                .map_err(|_| error("InternalError", "poisoned".into()))?
                .take();
            py.detach(move || drop(ahead));
            Ok(())
        })
    }
}
