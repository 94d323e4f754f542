//! Bindings of `floorscan_sim::calibration`: the calibration scene and its pattern.

use super::*;

/// The default pattern of a kind ("checkerboard" or "lines") in front of a camera, as JSON.
#[pyfunction]
pub fn sim_default_pattern(camera: &PyCamera, kind: &str) -> PyResult<String> {
    crate::errors::guard(|| {
        let kind: PatternKind = parse_json("pattern kind", &format!("\"{kind}\""))?;
        let spec = default_pattern(kind, &camera.rays.camera).sim()?;
        to_json(&spec)
    })
}

/// Renders the calibration scene of a pattern (JSON): (image, labels).
#[pyfunction]
pub fn sim_render_calibration<'py>(
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
pub fn sim_pattern_points<'py>(py: Python<'py>, pattern_json: &str) -> PyResult<Bound<'py, PyAny>> {
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

/// Validates a pattern (JSON, the simulator's serde form).
#[pyfunction]
pub fn validate_pattern(pattern_json: &str) -> PyResult<()> {
    crate::errors::guard(|| {
        parse_json::<PatternSpec>("pattern", pattern_json)?
            .validate()
            .sim()
    })
}
