//! Bindings of `floorscan_sim::run`: whole runs of frames, the GIL released.

use super::*;

/// Renders frames at poses (N, 3): (images (N, H, W), labels or None, truth or None,
/// exposures (N,)). The GIL is released for the whole run.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn sim_render_run<'py>(
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
