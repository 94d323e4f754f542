//! Bindings of `floorscan_sim::render`: one view with its labels and truth.

use super::*;

/// Renders one view: (image (H, W) uint8, labels (H, W) uint8, truth or None, exposure).
#[pyfunction]
#[pyo3(signature = (world, camera, x, y, yaw, seed, frame, truth, max_range_m))]
#[allow(clippy::too_many_arguments)]
pub fn sim_render<'py>(
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
