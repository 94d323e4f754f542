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
/// Booleans are strict both ways (a field whose default is `true` or `false` takes only
/// `True` or `False`, not the truthiness of `"no"`; a number field refuses `True`), which the
/// conversion alone does not check.
pub fn from_py<T: DeserializeOwned + Serialize + Default>(obj: &Bound<'_, PyAny>) -> PyResult<T> {
    let template = to_py(obj.py(), &T::default())?;
    check_bools(obj, &template, "")?;
    from_py_as_given(obj)
}

/// As [`from_py`], for types without defaults (a lens, a mount: every field is given).
pub fn from_py_as_given<T: DeserializeOwned>(obj: &Bound<'_, PyAny>) -> PyResult<T> {
    let mut de = pythonize::Depythonizer::from_object(obj);
    serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner().to_string();
        let inner = in_users_words(&inner, value_at(obj, &path).as_deref());
        error("OptionError", describe(&path, &inner))
    })
}

/// Walks `given` (a dict, possibly nested) beside `template` (the defaults' serde form): a key
/// whose default is a bool must be given a bool, one whose default is a number must not be.
fn check_bools(
    given: &Bound<'_, PyAny>,
    template: &Bound<'_, PyAny>,
    prefix: &str,
) -> PyResult<()> {
    use pyo3::types::{PyBool, PyDict, PyFloat, PyInt};
    let (Ok(given), Ok(template)) = (given.cast::<PyDict>(), template.cast::<PyDict>()) else {
        return Ok(());
    };
    for (key, value) in given.iter() {
        let Ok(Some(default)) = template.get_item(&key) else {
            continue;
        };
        // Keys read as UTF-8, never through str()/repr(): those check for signals, and a stop
        // signal raised here would be swallowed (written as "Exception ignored in ...").
        let name = || key.extract::<String>().unwrap_or_default();
        let is_bool = value.is_instance_of::<PyBool>();
        let wrong = if default.is_instance_of::<PyBool>() {
            (!is_bool).then_some("true or false")
        } else if default.is_instance_of::<PyInt>() {
            is_bool.then_some("a whole number")
        } else if default.is_instance_of::<PyFloat>() {
            is_bool.then_some("a number")
        } else {
            None
        };
        if let Some(expected) = wrong {
            let shown = value.repr()?.extract::<String>()?;
            return Err(error(
                "OptionError",
                format!(
                    "invalid option `{prefix}{}`: expected {expected}, got {shown}",
                    name()
                ),
            ));
        }
        if value.cast::<PyDict>().is_ok() {
            check_bools(&value, &default, &format!("{prefix}{}.", name()))?;
        }
    }
    Ok(())
}

/// The `repr` of the value at a serde path (`a.b`, `a[0]`) in a dict or list, if there is one.
fn value_at(obj: &Bound<'_, PyAny>, path: &str) -> Option<String> {
    if path == "." {
        return None;
    }
    let mut cur = obj.clone();
    for part in path.split('.') {
        let (key, indices) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if !key.is_empty() {
            cur = cur.get_item(key).ok()?;
        }
        for index in indices.split(['[', ']']).filter(|s| !s.is_empty()) {
            cur = cur.get_item(index.parse::<usize>().ok()?).ok()?;
        }
    }
    Some(cur.repr().ok()?.to_string())
}

/// What the Python-to-Rust conversion says, in a user's words: `expected a number, got 'x'`
/// rather than `TypeError: must be real number, not str`.
fn in_users_words(inner: &str, value: Option<&str>) -> String {
    let got = |expected: &str| match value {
        Some(v) => format!("expected {expected}, got {v}"),
        None => format!("expected {expected}"),
    };
    let msg = inner
        .strip_prefix("TypeError: ")
        .or_else(|| inner.strip_prefix("ValueError: "))
        .unwrap_or(inner);
    if msg.starts_with("must be real number") {
        got("a number")
    } else if msg.contains("cannot be interpreted as an integer") {
        got("a whole number")
    } else if msg.starts_with("OverflowError: can't convert negative int to unsigned") {
        got("a whole number >= 0")
    } else if msg.starts_with("OverflowError") {
        got("a smaller whole number")
    } else if msg.contains("is not an instance of 'Sequence'") {
        got("a list")
    } else if msg.contains("is not an instance of 'Mapping'") {
        got("a table (a dict)")
    } else if msg.contains("cannot be converted to 'PyString'") {
        got("a string")
    } else if msg.contains("cannot be converted to 'PyBool'") {
        got("true or false")
    } else if msg.starts_with("expected either a str or dict for enum") {
        got("one of the option's names (a string)")
    } else if msg.starts_with("data did not match any variant") {
        match value {
            Some(v) => format!("{v} is none of the forms this option takes (`floorscan config --default` shows them)"),
            None => "none of the forms this option takes (`floorscan config --default` shows them)".into(),
        }
    } else {
        msg.to_string()
    }
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
