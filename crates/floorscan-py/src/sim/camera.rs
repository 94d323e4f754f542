//! Bindings of `floorscan_sim::camera`: a camera with its per-pixel rays.

use super::*;

/// A camera with its per-pixel rays.
#[pyclass(name = "SimCamera", module = "floorscan._native.sim", frozen)]
pub struct PyCamera {
    pub(crate) rays: Arc<CameraRays>,
}

#[pymethods]
impl PyCamera {
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<Self> {
        crate::errors::guard(|| {
            let camera: Camera = parse_json("camera", text)?;
            Ok(Self {
                rays: Arc::new(py.detach(|| CameraRays::new(camera)).sim()?),
            })
        })
    }

    /// The default wide-angle camera at a resolution, as JSON.
    #[staticmethod]
    fn default_json(width: usize, height: usize) -> PyResult<String> {
        crate::errors::guard(|| to_json(&Camera::wide_angle(width, height)))
    }

    fn to_json(&self) -> PyResult<String> {
        crate::errors::guard(|| to_json(&self.rays.camera))
    }

    /// Exact ground points (camera ground frame) of pixels: two float64 arrays, NaN where none.
    fn pixel_to_ground<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray1<'py, f64>,
        v: PyReadonlyArray1<'py, f64>,
        max_range_m: f64,
    ) -> PyResult<Xy<'py>> {
        crate::errors::guard(|| {
            let (u, v) = (u.as_array().to_vec(), v.as_array().to_vec());
            if u.len() != v.len() {
                return Err(error(
                    "LengthMismatchError",
                    format!("u has {} values, v has {}", u.len(), v.len()),
                ));
            }
            let cam = &self.rays.camera;
            let (x, y): (Vec<f64>, Vec<f64>) = py.detach(|| {
                u.iter()
                    .zip(&v)
                    .map(|(&u, &v)| {
                        cam.pixel_to_ground(u, v, max_range_m)
                            .map_or((f64::NAN, f64::NAN), |p| (p.x, p.y))
                    })
                    .unzip()
            });
            Ok((PyArray1::from_vec(py, x), PyArray1::from_vec(py, y)))
        })
    }

    /// Pixels (u, v) where ground points (camera ground frame) appear; NaN where not seen.
    fn ground_to_pixel<'py>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArray1<'py, f64>,
        y: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Xy<'py>> {
        crate::errors::guard(|| {
            let (x, y) = (x.as_array().to_vec(), y.as_array().to_vec());
            if x.len() != y.len() {
                return Err(error(
                    "LengthMismatchError",
                    format!("x has {} values, y has {}", x.len(), y.len()),
                ));
            }
            let cam = &self.rays.camera;
            let (u, v): (Vec<f64>, Vec<f64>) = py.detach(|| {
                x.iter()
                    .zip(&y)
                    .map(|(&x, &y)| {
                        ground_to_pixel(&cam.lens, &cam.mount, Point2::new(x, y))
                            .map_or((f64::NAN, f64::NAN), |p| (p[0], p[1]))
                    })
                    .unzip()
            });
            Ok((PyArray1::from_vec(py, u), PyArray1::from_vec(py, v)))
        })
    }

    /// The exact ground table of the camera.
    fn ground_table(
        &self,
        py: Python<'_>,
        spacing_px: usize,
        max_range_m: f64,
    ) -> PyResult<PyGroundTable> {
        crate::errors::guard(|| {
            let cam = self.rays.camera.clone();
            let inner = py
                .detach(|| cam.ground_table(spacing_px, max_range_m))
                .sim()?;
            Ok(PyGroundTable { inner })
        })
    }
}

/// Validates a camera (JSON, the simulator's serde form).
#[pyfunction]
pub fn validate_camera(options_json: &str) -> PyResult<()> {
    crate::errors::guard(|| {
        parse_json::<Camera>("camera", options_json)?
            .validate()
            .sim()
    })
}

/// Validates imaging options (JSON, the simulator's serde form).
#[pyfunction]
pub fn validate_imaging(options_json: &str) -> PyResult<()> {
    crate::errors::guard(|| {
        parse_json::<floorscan_sim::Imaging>("imaging", options_json)?
            .validate()
            .sim()
    })
}
