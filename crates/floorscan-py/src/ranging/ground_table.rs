//! Bindings of `floorscan_core::ground_table` and the model-based table of `mount`.

use floorscan_core::mount::ground_table_from_camera;
use floorscan_core::{CameraMount, GroundTable, Lens};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::errors::{error, IntoPyResult};
use crate::options::{from_py, from_py_as_given, to_py};

/// Two numpy arrays (x and y).
type ArrayPair<'py, A> = (Bound<'py, A>, Bound<'py, A>);

#[pyclass(name = "GroundTable", module = "floorscan._native.ranging", frozen)]
#[derive(Clone)]
pub struct PyGroundTable {
    pub inner: GroundTable,
}

/// The pixel coordinates of a lookup, copied out of numpy (equal lengths, or an error).
fn pixel_pairs(
    u: &PyReadonlyArray1<'_, f64>,
    v: &PyReadonlyArray1<'_, f64>,
) -> PyResult<(Vec<f64>, Vec<f64>)> {
    let (u, v) = (u.as_array(), v.as_array());
    if u.len() != v.len() {
        return Err(error(
            "LengthMismatchError",
            format!("u has {} values, v has {}", u.len(), v.len()),
        ));
    }
    Ok((u.to_vec(), v.to_vec()))
}

#[pymethods]
impl PyGroundTable {
    #[staticmethod]
    fn from_arrays(
        image_width: usize,
        image_height: usize,
        spacing_px: usize,
        x_m: PyReadonlyArray1<'_, f64>,
        y_m: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            let x = x_m.as_array().to_vec();
            let y = y_m.as_array().to_vec();
            let inner =
                GroundTable::from_arrays(image_width, image_height, spacing_px, &x, &y).py()?;
            Ok(Self { inner })
        })
    }

    #[staticmethod]
    fn from_camera(
        py: Python<'_>,
        lens: &Bound<'_, PyAny>,
        mount: &Bound<'_, PyAny>,
        image_width: usize,
        image_height: usize,
        spacing_px: usize,
        max_range_m: f64,
    ) -> PyResult<Self> {
        crate::errors::guard(|| {
            let lens: Lens = from_py_as_given(lens)?;
            let mount: CameraMount = from_py_as_given(mount)?;
            let inner = py
                .detach(|| {
                    ground_table_from_camera(
                        &lens,
                        &mount,
                        image_width,
                        image_height,
                        spacing_px,
                        max_range_m,
                    )
                })
                .py()?;
            Ok(Self { inner })
        })
    }

    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        crate::errors::guard(|| {
            Ok(Self {
                inner: GroundTable::from_json(text).py()?,
            })
        })
    }

    fn to_json(&self) -> PyResult<String> {
        crate::errors::guard(|| Ok(self.inner.to_json()))
    }

    /// Ground points at pixels (u, v): two float64 arrays, NaN where there is no ground.
    fn lookup<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray1<'py, f64>,
        v: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<ArrayPair<'py, PyArray1<f64>>> {
        crate::errors::guard(|| {
            let (u, v) = pixel_pairs(&u, &v)?;
            let (xs, ys): (Vec<f64>, Vec<f64>) = py.detach(|| {
                u.iter()
                    .zip(&v)
                    .map(|(&u, &v)| {
                        self.inner
                            .lookup(u, v)
                            .map_or((f64::NAN, f64::NAN), |p| (p.x, p.y))
                    })
                    .unzip()
            });
            Ok((PyArray1::from_vec(py, xs), PyArray1::from_vec(py, ys)))
        })
    }

    /// A copy carrying a predicted floor-position error [m] per node (row-major; NaN unknown).
    fn with_errors(&self, errors_m: PyReadonlyArray1<'_, f64>) -> PyResult<Self> {
        crate::errors::guard(|| {
            let e = errors_m.as_array().to_vec();
            Ok(Self {
                inner: self.inner.clone().with_errors(&e).py()?,
            })
        })
    }

    /// Node errors as a (nodes_v, nodes_u) float64 array [m], NaN unknown; None if the table
    /// carries none.
    fn node_errors<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        crate::errors::guard(|| {
            let (nu, nv) = self.inner.node_shape();
            match self.inner.errors() {
                None => Ok(None),
                Some(e) => {
                    let v: Vec<f64> = e.iter().map(|e| e.unwrap_or(f64::NAN)).collect();
                    Ok(Some(PyArray1::from_vec(py, v).reshape([nv, nu])?))
                }
            }
        })
    }

    /// Predicted errors [m] at pixels (u, v), NaN where unknown or no ground.
    fn lookup_error<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray1<'py, f64>,
        v: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        crate::errors::guard(|| {
            let (u, v) = pixel_pairs(&u, &v)?;
            let out: Vec<f64> = py.detach(|| {
                u.iter()
                    .zip(&v)
                    .map(|(&u, &v)| self.inner.lookup_error(u, v).unwrap_or(f64::NAN))
                    .collect()
            });
            Ok(PyArray1::from_vec(py, out))
        })
    }

    #[getter]
    fn image_width(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.inner.image_width()))
    }
    #[getter]
    fn image_height(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.inner.image_height()))
    }
    #[getter]
    fn spacing_px(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.inner.spacing_px()))
    }

    /// Node values as two (nodes_v, nodes_u) float64 arrays, NaN for no ground.
    fn node_arrays<'py>(&self, py: Python<'py>) -> PyResult<ArrayPair<'py, PyArray2<f64>>> {
        crate::errors::guard(|| {
            let (nu, nv) = self.inner.node_shape();
            let x: Vec<f64> = self
                .inner
                .nodes()
                .iter()
                .map(|p| p.map_or(f64::NAN, |p| p.x))
                .collect();
            let y: Vec<f64> = self
                .inner
                .nodes()
                .iter()
                .map(|p| p.map_or(f64::NAN, |p| p.y))
                .collect();
            Ok((
                PyArray1::from_vec(py, x).reshape([nv, nu])?,
                PyArray1::from_vec(py, y).reshape([nv, nu])?,
            ))
        })
    }

    /// The free-form metadata (a dict).
    fn metadata<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::errors::guard(|| to_py(py, &self.inner.metadata))
    }

    /// A copy of the table with `metadata` (a dict of JSON values) replacing its metadata.
    fn with_metadata(&self, metadata: &Bound<'_, PyAny>) -> PyResult<Self> {
        crate::errors::guard(|| {
            let mut inner = self.inner.clone();
            inner.metadata = from_py(metadata)?;
            Ok(Self { inner })
        })
    }

    fn __eq__(&self, other: &Self) -> PyResult<bool> {
        crate::errors::guard(|| Ok(self.inner == other.inner))
    }
}
