//! Bindings of `floorscan_sim`: worlds, cameras, rendering with truth, robot trajectories,
//! whole runs and the calibration scene. Options arrive as JSON in the simulator's serde form,
//! built by the Python wrappers in `floorscan.sim`. Heavy calls release the GIL.

use std::sync::Arc;

use floorscan_core::mount::ground_to_pixel;
use floorscan_core::{Point2, Pose2};
use floorscan_sim::builtin::{builtin_names, builtin_world};
use floorscan_sim::calibration::{
    calibration_world, default_pattern, robot_pose, PatternKind, PatternSpec,
};
use floorscan_sim::occupancy::{occupancy_raster, OccupancyOptions};
use floorscan_sim::odometry::OdometryNoise;
use floorscan_sim::render::{render_into, RenderBuffers};
use floorscan_sim::robot::{drive, Motion, RobotOptions};
use floorscan_sim::run::{render_run, RunOutputs};
use floorscan_sim::truth::{
    frame_truth, write_columns_csv, FrameTruth, TruthOptions, COLUMNS_CSV_HEADER,
};
use floorscan_sim::world_file::parse_world;
use floorscan_sim::{Camera, CameraRays, Scene};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{error, to_pyerr};
use crate::ground_table::PyGroundTable;

/// Converts a simulator error into its Python exception.
fn sim_err(e: floorscan_sim::Error) -> PyErr {
    match e {
        floorscan_sim::Error::InvalidWorld { .. } => error("WorldError", e.to_string()),
        floorscan_sim::Error::Core(c) => to_pyerr(c),
    }
}

trait IntoSimResult<T> {
    fn sim(self) -> PyResult<T>;
}

impl<T> IntoSimResult<T> for floorscan_sim::Result<T> {
    fn sim(self) -> PyResult<T> {
        self.map_err(sim_err)
    }
}

type Xy<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);
type Rendered<'py> = (Bound<'py, PyAny>, Bound<'py, PyAny>, Option<PyTruth>, f64);
type RenderedRun<'py> = (
    Bound<'py, PyAny>,
    Option<Bound<'py, PyAny>>,
    Option<PyTruth>,
    Bound<'py, PyAny>,
);

/// A value's JSON text; a failure is an InternalError, never an empty string.
fn to_json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| {
        error(
            "InternalError",
            format!("internal error (a bug; please report it): cannot write JSON: {e}"),
        )
    })
}

fn parse_json<T: serde::de::DeserializeOwned>(what: &str, text: &str) -> PyResult<T> {
    serde_json::from_str(text).map_err(|e| error("OptionError", format!("invalid {what}: {e}")))
}

/// A world prepared for rendering.
#[pyclass(name = "SimWorld", module = "floorscan._native", frozen)]
pub struct PyWorld {
    scene: Arc<Scene>,
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

/// A camera with its per-pixel rays.
#[pyclass(name = "SimCamera", module = "floorscan._native", frozen)]
pub struct PyCamera {
    rays: Arc<CameraRays>,
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

/// Ground truth of rendered frames (kept native; converted to arrays or CSV on demand).
#[pyclass(name = "SimTruth", module = "floorscan._native", frozen)]
pub struct PyTruth {
    frames: Vec<FrameTruth>,
    width: usize,
}

#[pymethods]
impl PyTruth {
    fn __len__(&self) -> PyResult<usize> {
        crate::errors::guard(|| Ok(self.frames.len()))
    }

    /// The truth as a dict of numpy arrays, shapes (N, W) or (N, W, 2) or (N, 3).
    fn arrays<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::errors::guard(|| truth_dict(py, &self.frames, self.width))
    }

    /// The truth columns CSV (header included) with the frames' timestamps [s].
    fn to_csv(&self, py: Python<'_>, timestamps: PyReadonlyArray1<'_, f64>) -> PyResult<String> {
        crate::errors::guard(|| {
            let times = timestamps.as_array().to_vec();
            if times.len() != self.frames.len() {
                return Err(error(
                    "LengthMismatchError",
                    format!(
                        "{} frames but {} timestamps",
                        self.frames.len(),
                        times.len()
                    ),
                ));
            }
            Ok(py.detach(|| {
                let mut out = String::with_capacity(self.frames.len() * self.width * 120 + 200);
                out.push_str(COLUMNS_CSV_HEADER);
                out.push('\n');
                write_columns_csv(&self.frames, &times, &mut out);
                out
            }))
        })
    }
}

fn pose_of(x: f64, y: f64, yaw: f64) -> PyResult<Pose2> {
    Pose2::checked(x, y, yaw).map_err(to_pyerr)
}

fn image_array<'py>(
    py: Python<'py>,
    data: Vec<u8>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, data)
        .reshape(shape.to_vec())?
        .into_any())
}

/// Truth of frames as a dict of arrays, shapes (N, W) or (N, W, 2).
fn truth_dict<'py>(
    py: Python<'py>,
    frames: &[FrameTruth],
    width: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let n = frames.len();
    let cols = || frames.iter().flat_map(|f| f.columns.iter());
    let nan2 = |p: Option<Point2>| p.map_or([f64::NAN, f64::NAN], |p| [p.x, p.y]);
    let d = PyDict::new(py);
    let scalar = |v: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        Ok(PyArray1::from_vec(py, v).reshape([n, width])?.into_any())
    };
    let pairs = |v: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        Ok(PyArray1::from_vec(py, v).reshape([n, width, 2])?.into_any())
    };
    d.set_item(
        "status",
        PyArray1::from_vec(py, cols().map(|c| c.status.code()).collect()).reshape([n, width])?,
    )?;
    d.set_item("row", scalar(cols().map(|c| c.row).collect())?)?;
    d.set_item(
        "point",
        pairs(cols().flat_map(|c| nan2(c.point)).collect())?,
    )?;
    d.set_item(
        "point_world",
        pairs(cols().flat_map(|c| nan2(c.point_world)).collect())?,
    )?;
    d.set_item(
        "obstacle_world",
        pairs(cols().flat_map(|c| nan2(c.obstacle_world)).collect())?,
    )?;
    d.set_item(
        "obstacle_z",
        scalar(cols().map(|c| c.obstacle_z_m).collect())?,
    )?;
    d.set_item(
        "appearance_row",
        scalar(cols().map(|c| c.appearance_row).collect())?,
    )?;
    d.set_item(
        "appearance_point",
        pairs(cols().flat_map(|c| nan2(c.appearance_point)).collect())?,
    )?;
    let poses: Vec<f64> = frames
        .iter()
        .flat_map(|f| [f.pose.x, f.pose.y, f.pose.yaw])
        .collect();
    d.set_item("pose", PyArray1::from_vec(py, poses).reshape([n, 3])?)?;
    let cams: Vec<f64> = frames
        .iter()
        .flat_map(|f| {
            [
                f.world_from_camera.x,
                f.world_from_camera.y,
                f.world_from_camera.yaw,
            ]
        })
        .collect();
    d.set_item(
        "world_from_camera",
        PyArray1::from_vec(py, cams).reshape([n, 3])?,
    )?;
    Ok(d)
}

/// Renders one view: (image (H, W) uint8, labels (H, W) uint8, truth or None, exposure).
#[pyfunction]
#[pyo3(signature = (world, camera, x, y, yaw, seed, frame, truth, max_range_m))]
#[allow(clippy::too_many_arguments)]
fn sim_render<'py>(
    py: Python<'py>,
    world: &PyWorld,
    camera: &PyCamera,
    x: f64,
    y: f64,
    yaw: f64,
    seed: u64,
    frame: u64,
    truth: bool,
    max_range_m: f64,
) -> PyResult<Rendered<'py>> {
    crate::errors::guard(|| {
        let pose = pose_of(x, y, yaw)?;
        let (scene, rays) = (world.scene.clone(), camera.rays.clone());
        let opts = TruthOptions { max_range_m };
        let (buf, t) = py
            .detach(|| -> floorscan_sim::Result<_> {
                let mut buf = RenderBuffers::default();
                render_into(&scene, &rays, pose, seed, frame, &mut buf)?;
                let t = if truth {
                    opts.validate()?;
                    Some(frame_truth(&scene, &rays, pose, &opts))
                } else {
                    None
                };
                Ok((buf, t))
            })
            .sim()?;
        let (w, h) = (rays.camera.width, rays.camera.height);
        let truth = t.map(|t| PyTruth {
            frames: vec![t],
            width: w,
        });
        Ok((
            image_array(py, buf.image, &[h, w])?,
            image_array(py, buf.labels, &[h, w])?,
            truth,
            buf.exposure,
        ))
    })
}

/// Drives the robot: (times (N,), truth (N, 3), odometry (N, 3)).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn sim_drive<'py>(
    py: Python<'py>,
    x: f64,
    y: f64,
    yaw: f64,
    motion_json: &str,
    robot_json: &str,
    noise_json: &str,
    duration_s: f64,
    seed: u64,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    crate::errors::guard(|| {
        let start = pose_of(x, y, yaw)?;
        let motion: Motion = parse_json("motion", motion_json)?;
        let robot: RobotOptions = parse_json("robot options", robot_json)?;
        let noise: OdometryNoise = parse_json("odometry noise", noise_json)?;
        let tr = py
            .detach(|| drive(start, &motion, &robot, &noise, duration_s, seed))
            .sim()?;
        let n = tr.times_s.len();
        let flat = |p: &[Pose2]| {
            p.iter()
                .flat_map(|p| [p.x, p.y, p.yaw])
                .collect::<Vec<f64>>()
        };
        Ok((
            PyArray1::from_vec(py, tr.times_s).into_any(),
            PyArray1::from_vec(py, flat(&tr.truth))
                .reshape([n, 3])?
                .into_any(),
            PyArray1::from_vec(py, flat(&tr.odometry))
                .reshape([n, 3])?
                .into_any(),
        ))
    })
}

/// Renders frames at poses (N, 3): (images (N, H, W), labels or None, truth or None,
/// exposures (N,)). The GIL is released for the whole run.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn sim_render_run<'py>(
    py: Python<'py>,
    world: &PyWorld,
    camera: &PyCamera,
    poses: PyReadonlyArray2<'py, f64>,
    seed: u64,
    labels: bool,
    truth: bool,
    max_range_m: f64,
    threads: usize,
) -> PyResult<RenderedRun<'py>> {
    crate::errors::guard(|| {
        if poses.shape()[1] != 3 {
            return Err(error(
                "GeometryError",
                format!("poses must have shape (N, 3), got {:?}", poses.shape()),
            ));
        }
        let a = poses.as_array();
        let poses: Vec<Pose2> = a
            .rows()
            .into_iter()
            .map(|r| Pose2::new(r[0], r[1], r[2]))
            .collect();
        let (scene, rays) = (world.scene.clone(), camera.rays.clone());
        let outputs = RunOutputs {
            labels,
            truth: truth.then_some(TruthOptions { max_range_m }),
            threads,
        };
        let run = py
            .detach(|| render_run(&scene, &rays, &poses, seed, outputs))
            .sim()?;
        let (n, h, w) = (poses.len(), run.height, run.width);
        let images = image_array(py, run.images, &[n, h, w])?;
        let labels = if labels {
            Some(image_array(py, run.labels, &[n, h, w])?)
        } else {
            None
        };
        let truth = truth.then_some(PyTruth {
            frames: run.truth,
            width: w,
        });
        Ok((
            images,
            labels,
            truth,
            PyArray1::from_vec(py, run.exposures).into_any(),
        ))
    })
}

/// The default pattern of a kind ("checkerboard" or "lines") in front of a camera, as JSON.
#[pyfunction]
fn sim_default_pattern(camera: &PyCamera, kind: &str) -> PyResult<String> {
    crate::errors::guard(|| {
        let kind: PatternKind = parse_json("pattern kind", &format!("\"{kind}\""))?;
        let spec = default_pattern(kind, &camera.rays.camera).sim()?;
        to_json(&spec)
    })
}

/// Renders the calibration scene of a pattern (JSON): (image, labels).
#[pyfunction]
fn sim_render_calibration<'py>(
    py: Python<'py>,
    camera: &PyCamera,
    pattern_json: &str,
    seed: u64,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    crate::errors::guard(|| {
        let spec: PatternSpec = parse_json("pattern", pattern_json)?;
        let rays = camera.rays.clone();
        let buf = py
            .detach(|| -> floorscan_sim::Result<RenderBuffers> {
                let scene = Scene::new(calibration_world(&spec)?);
                let mut buf = RenderBuffers::default();
                render_into(&scene, &rays, robot_pose(&rays.camera), seed, 0, &mut buf)?;
                Ok(buf)
            })
            .sim()?;
        let (w, h) = (rays.camera.width, rays.camera.height);
        Ok((
            image_array(py, buf.image, &[h, w])?,
            image_array(py, buf.labels, &[h, w])?,
        ))
    })
}

/// Pattern points (inner corners or crossings; camera ground frame), (M, 2).
#[pyfunction]
fn sim_pattern_points<'py>(py: Python<'py>, pattern_json: &str) -> PyResult<Bound<'py, PyAny>> {
    crate::errors::guard(|| {
        let spec: PatternSpec = parse_json("pattern", pattern_json)?;
        spec.validate().sim()?;
        let pts = spec.points();
        let n = pts.len();
        Ok(
            PyArray1::from_vec(py, pts.iter().flat_map(|p| [p.x, p.y]).collect())
                .reshape([n, 2])?
                .into_any(),
        )
    })
}

/// Validates options of a simulator component given as JSON: `kind` is "camera", "imaging",
/// "robot", "odometry", "occupancy" or "pattern". Raises the matching error.
#[pyfunction]
fn sim_validate(kind: &str, options_json: &str) -> PyResult<()> {
    crate::errors::guard(|| {
        match kind {
            "camera" => parse_json::<Camera>("camera", options_json)?
                .validate()
                .sim(),
            "imaging" => parse_json::<floorscan_sim::Imaging>("imaging", options_json)?
                .validate()
                .sim(),
            "robot" => parse_json::<RobotOptions>("robot options", options_json)?
                .validate()
                .sim(),
            "odometry" => parse_json::<OdometryNoise>("odometry noise", options_json)?
                .validate()
                .sim(),
            "pattern" => parse_json::<PatternSpec>("pattern", options_json)?
                .validate()
                .sim(),
            "occupancy" => {
                let o: OccupancyOptions = parse_json("occupancy options", options_json)?;
                // The checks live in the raster builder: run them on an empty world's bounds.
                let w = parse_world("name = \"check\"\n[start]\nx = 0\ny = 0\n", "check").sim()?;
                occupancy_raster(&w, &o).map(|_| ()).sim()
            }
            other => Err(error("OptionError", format!("unknown component {other:?}"))),
        }
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(sim_validate, m)?)?;
    m.add_class::<PyWorld>()?;
    m.add_class::<PyCamera>()?;
    m.add_class::<PyTruth>()?;
    m.add_function(wrap_pyfunction!(sim_render, m)?)?;
    m.add_function(wrap_pyfunction!(sim_drive, m)?)?;
    m.add_function(wrap_pyfunction!(sim_render_run, m)?)?;
    m.add_function(wrap_pyfunction!(sim_default_pattern, m)?)?;
    m.add_function(wrap_pyfunction!(sim_render_calibration, m)?)?;
    m.add_function(wrap_pyfunction!(sim_pattern_points, m)?)?;
    Ok(())
}
