//! Bindings of `floorscan_sim::{world, world_file, builtin, occupancy}`: a world prepared for
//! rendering, its true occupancy raster.

use super::*;

/// A world prepared for rendering.
#[pyclass(name = "SimWorld", module = "floorscan._native.sim", frozen)]
pub struct PyWorld {
    pub(crate) scene: Arc<Scene>,
}

#[pymethods]
impl PyWorld {
    /// Parses a world file's text; `source_name` (a path) prefixes error messages.
    #[staticmethod]
    fn from_toml(py: Python<'_>, text: &str, source_name: &str) -> PyResult<Self> {
        crate::errors::guard(|| {
            let world = parse_world(text, source_name).sim()?;
            Ok(Self {
                scene: Arc::new(py.detach(|| Scene::new(world))),
            })
        })
    }

    #[staticmethod]
    fn builtin(py: Python<'_>, name: &str) -> PyResult<Self> {
        crate::errors::guard(|| {
            let world = builtin_world(name).sim()?;
            Ok(Self {
                scene: Arc::new(py.detach(|| Scene::new(world))),
            })
        })
    }

    #[staticmethod]
    fn builtin_names() -> PyResult<Vec<&'static str>> {
        crate::errors::guard(|| Ok(builtin_names()))
    }

    #[getter]
    fn name(&self) -> PyResult<String> {
        crate::errors::guard(|| Ok(self.scene.world.name.clone()))
    }
    #[getter]
    fn description(&self) -> PyResult<String> {
        crate::errors::guard(|| Ok(self.scene.world.description.clone()))
    }
    #[getter]
    fn source(&self) -> PyResult<Option<String>> {
        crate::errors::guard(|| Ok(self.scene.world.source.clone()))
    }
    #[getter]
    fn ceiling_m(&self) -> PyResult<f64> {
        crate::errors::guard(|| Ok(self.scene.world.ceiling_m))
    }
    /// (x, y, yaw) of the start pose.
    #[getter]
    fn start(&self) -> PyResult<(f64, f64, f64)> {
        crate::errors::guard(|| {
            Ok({
                let s = self.scene.world.start;
                (s.x, s.y, s.yaw)
            })
        })
    }
    #[getter]
    fn tour(&self) -> PyResult<Vec<(f64, f64)>> {
        crate::errors::guard(|| Ok(self.scene.world.tour.iter().map(|p| (p.x, p.y)).collect()))
    }
    /// (xmin, ymin, xmax, ymax) [m].
    #[getter]
    fn bounds(&self) -> PyResult<(f64, f64, f64, f64)> {
        crate::errors::guard(|| {
            Ok({
                let b = self.scene.world.bounds();
                (b.min.x, b.min.y, b.max.x, b.max.y)
            })
        })
    }
    /// The world as JSON (the simulator's serde form; for inspection).
    fn to_json(&self) -> PyResult<String> {
        crate::errors::guard(|| to_json(&self.scene.world))
    }

    /// True occupancy raster: (cells (H, W) int8 with 100/0/-1, row 0 = lowest y; origin x, y).
    fn occupancy<'py>(
        &self,
        py: Python<'py>,
        options_json: &str,
    ) -> PyResult<(Bound<'py, PyAny>, f64, f64)> {
        crate::errors::guard(|| {
            let opts: OccupancyOptions = parse_json("occupancy options", options_json)?;
            let scene = self.scene.clone();
            let r = py.detach(|| occupancy_raster(&scene.world, &opts)).sim()?;
            let cells = PyArray1::from_vec(py, r.cells).reshape([r.height, r.width])?;
            Ok((cells.into_any(), r.origin.x, r.origin.y))
        })
    }
}

/// Validates occupancy raster options (JSON, the simulator's serde form).
#[pyfunction]
pub fn validate_occupancy_options(options_json: &str) -> PyResult<()> {
    crate::errors::guard(|| {
        let o: OccupancyOptions = parse_json("occupancy options", options_json)?;
        // The checks live in the raster builder: run them on an empty world's bounds.
        let w = parse_world("name = \"check\"\n[start]\nx = 0\ny = 0\n", "check").sim()?;
        occupancy_raster(&w, &o).map(|_| ()).sim()
    })
}
