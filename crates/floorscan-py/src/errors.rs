//! Maps each core error variant to its own Python exception class (defined in
//! `python/floorscan/errors.py`, all subclasses of `floorscan.FloorscanError`).

use floorscan_core::Error;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// The Python class name for a core error variant.
fn class_name(e: &Error) -> &'static str {
    match e {
        Error::InvalidImage(_) => "ImageError",
        Error::InvalidOption { .. } => "OptionError",
        Error::InvalidTable(_) => "TableError",
        Error::UnsupportedVersion { .. } => "UnsupportedVersionError",
        Error::Malformed { .. } => "FileFormatError",
        Error::InvalidGeometry(_) => "GeometryError",
        Error::LengthMismatch(_) => "LengthMismatchError",
        Error::OutOfBounds(_) => "OutOfBoundsError",
    }
}

/// The Python class name for a codec (image file) error variant.
fn codec_class_name(e: &floorscan_codec::Error) -> &'static str {
    use floorscan_codec::Error as E;
    match e {
        E::TooLarge { .. } => "ImageTooLargeError",
        E::Malformed { .. } => "ImageError",
        E::InvalidFrame(_) => "ImageError",
        E::Read { .. } => "DatasetError",
        E::Encode { .. } => "OutputError",
    }
}

/// Converts a codec error into the matching Python exception.
pub fn codec_to_pyerr(e: floorscan_codec::Error) -> PyErr {
    error(codec_class_name(&e), e.to_string())
}

/// Converts a core error into the matching Python exception.
pub fn to_pyerr(e: Error) -> PyErr {
    Python::attach(|py| {
        let message = e.to_string();
        match py
            .import("floorscan.errors")
            .and_then(|m| m.getattr(class_name(&e)))
        {
            Ok(cls) => PyErr::from_type(cls.cast_into().expect("exception class"), message),
            Err(_) => PyRuntimeError::new_err(message),
        }
    })
}

/// `?`-friendly conversion for core results.
pub trait IntoPyResult<T> {
    fn py(self) -> PyResult<T>;
}

impl<T> IntoPyResult<T> for floorscan_core::Result<T> {
    fn py(self) -> PyResult<T> {
        self.map_err(to_pyerr)
    }
}

/// A Python exception of class `name` from `floorscan.errors` (for binding-level checks).
pub fn error(name: &str, message: String) -> PyErr {
    Python::attach(
        |py| match py.import("floorscan.errors").and_then(|m| m.getattr(name)) {
            Ok(cls) => PyErr::from_type(cls.cast_into().expect("exception class"), message),
            Err(_) => PyRuntimeError::new_err(message),
        },
    )
}

/// Runs one FFI entry point with panics caught: a panic (a bug, never expected on any input)
/// becomes `floorscan.errors.InternalError` instead of crossing into Python as
/// `PanicException`. Every `#[pymethods]` / `#[pyfunction]` body that can fail runs in here.
pub fn guard<T>(body: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(body)) {
        Ok(result) => result,
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(error(
                "InternalError",
                format!("internal error (a bug; please report it): {what}"),
            ))
        }
    }
}
