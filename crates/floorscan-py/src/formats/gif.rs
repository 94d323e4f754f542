//! Bindings of `floorscan_codec::GifStream`: an animated GIF written to a file by a Rust thread,
//! frames of palette indices pushed from Python (copied, then queued with the GIL released).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

use floorscan_codec::GifStream;
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::errors::{codec_to_pyerr, error, guard};

type FileStream = GifStream<BufWriter<File>>;

/// An animated GIF being written to `path` (created or truncated) by a background thread: a
/// `width` x `height` animation with one global `palette` (bytes r, g, b, ... of 1 to 256
/// colours), each frame shown for `delay_cs` centiseconds, looping forever. The file is
/// complete (trailer written, synced) when `finish` returns.
#[pyclass(name = "GifStream", module = "floorscan._native.formats")]
pub struct PyGifStream {
    stream: Option<FileStream>,
    path: PathBuf,
}

fn write_error(path: &std::path::Path, e: std::io::Error) -> PyErr {
    error(
        "OutputError",
        format!("cannot write {}: {e}", path.display()),
    )
}

#[pymethods]
impl PyGifStream {
    #[new]
    fn new(
        path: PathBuf,
        width: usize,
        height: usize,
        palette: &[u8],
        delay_cs: u16,
    ) -> PyResult<Self> {
        guard(|| {
            let file = File::create(&path).map_err(|e| write_error(&path, e))?;
            let out = BufWriter::with_capacity(1 << 18, file);
            let stream =
                GifStream::new(out, width, height, palette, delay_cs).map_err(codec_to_pyerr)?;
            Ok(Self {
                stream: Some(stream),
                path,
            })
        })
    }

    /// Queues one (height, width) uint8 frame of palette indices (blocks while the encoder is
    /// 32 frames behind).
    fn push(&mut self, py: Python<'_>, indices: PyReadonlyArray2<'_, u8>) -> PyResult<()> {
        guard(|| {
            let stream = self
                .stream
                .as_mut()
                .ok_or_else(|| error("OutputError", "the GIF stream is closed".into()))?;
            let frame: Vec<u8> = match indices.as_slice() {
                Ok(s) => s.to_vec(),
                Err(_) => indices.as_array().iter().copied().collect(),
            };
            let shape = indices.shape();
            if frame.len() != shape[0] * shape[1] {
                return Err(error("ImageError", "frame is not a 2-D array".into()));
            }
            py.detach(|| stream.push(frame)).map_err(codec_to_pyerr)
        })
    }

    /// Waits for every queued frame, writes the trailer and syncs the file.
    fn finish(&mut self, py: Python<'_>) -> PyResult<()> {
        guard(|| {
            let Some(stream) = self.stream.take() else {
                return Ok(());
            };
            let path = self.path.clone();
            py.detach(move || {
                let writer = stream.finish().map_err(codec_to_pyerr)?;
                let file = writer
                    .into_inner()
                    .map_err(|e| write_error(&path, e.into_error()))?;
                file.sync_all().map_err(|e| write_error(&path, e))
            })
        })
    }

    /// Stops the encoder and closes the file, whatever it holds (the caller removes it).
    fn abort(&mut self, py: Python<'_>) -> PyResult<()> {
        guard(|| {
            if let Some(stream) = self.stream.take() {
                py.detach(move || {
                    let _ = stream.finish().map(|mut w| w.flush());
                });
            }
            Ok(())
        })
    }
}
