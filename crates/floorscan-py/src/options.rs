//! Options between Python and Rust. A dict (keyword arguments, a TOML table) is read into the
//! core's options type with serde (pythonize): missing fields take the type's `impl Default`,
//! unknown or ill-typed ones are one `OptionError` naming the key, and the type's `validate`
//! checks the ranges. Options go back to Python as dicts of their serde form, and their field
//! docs as a JSON schema (schemars). Nothing here knows a default or a rule of its own.

use pyo3::prelude::*;
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::errors::error;

/// Reads a Python object (a dict, or a dataclass) into `T`; the error names the key.
pub fn from_py<T: DeserializeOwned>(obj: &Bound<'_, PyAny>) -> PyResult<T> {
    let mut de = pythonize::Depythonizer::from_object(obj);
    serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner().to_string();
        error("OptionError", describe(&path, &inner))
    })
}

/// One line naming the key: `invalid option `a.b`: why`. (The path of an unknown field
/// ends with the field.)
fn describe(path: &str, inner: &str) -> String {
    // serde: "unknown field `foo`, expected one of `a`, `b`"
    if let Some((name, tail)) = inner
        .strip_prefix("unknown field `")
        .and_then(|rest| rest.split_once('`'))
    {
        let key = if path == "." { name } else { path };
        return format!("invalid option `{key}`: unknown option{tail}");
    }
    if path == "." {
        format!("invalid options: {inner}")
    } else {
        format!("invalid option `{path}`: {inner}")
    }
}

/// A value's serde form as Python objects (dicts, lists, numbers, strings).
pub fn to_py<'py, T: Serialize + ?Sized>(
    py: Python<'py>,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, value).map_err(|e| {
        error(
            "InternalError",
            format!("internal error (a bug; please report it): cannot convert to Python: {e}"),
        )
    })
}

/// Three typed functions per options type: its defaults, a check that returns the completed,
/// validated options, and its JSON schema (field docs, types, defaults).
macro_rules! options_functions {
    ($ty:ty, $default:ident, $check:ident, $schema:ident) => {
        #[doc = concat!("The default `", stringify!($ty), "` (its serde form, a dict).")]
        #[pyfunction]
        pub fn $default(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
            crate::errors::guard(|| crate::options::to_py(py, &<$ty>::default()))
        }

        #[doc = concat!(
            "Reads `", stringify!($ty), "` from a dict of any of its fields (the others take ",
            "their defaults), validates it and returns every field."
        )]
        #[pyfunction]
        pub fn $check<'py>(
            py: Python<'py>,
            options: &Bound<'py, PyAny>,
        ) -> PyResult<Bound<'py, PyAny>> {
            crate::errors::guard(|| {
                let o: $ty = crate::options::from_py(options)?;
                crate::errors::IntoPyResult::py(o.validate())?;
                crate::options::to_py(py, &o)
            })
        }

        #[doc = concat!("The JSON schema of `", stringify!($ty), "`: field docs, types, defaults.")]
        #[pyfunction]
        pub fn $schema(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
            crate::errors::guard(|| crate::options::to_py(py, &schemars::schema_for!($ty)))
        }
    };
}

pub(crate) use options_functions;
