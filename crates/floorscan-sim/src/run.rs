//! A whole simulated run: the robot's trajectory rendered frame by frame, with the truth of
//! every frame. Frames are rendered on a rayon pool of the asked number of threads; the result
//! does not depend on it.

use floorscan_core::Pose2;
use rayon::prelude::*;

use crate::camera::CameraRays;
use crate::error::{invalid_option, Result};
use crate::render::{render_into, RenderBuffers};
use crate::scene::Scene;
use crate::truth::{frame_truth, FrameTruth, TruthOptions};

/// Rendered frames of a run, stacked.
#[derive(Debug, Clone, Default)]
pub struct RenderedRun {
    pub width: usize,
    pub height: usize,
    /// Images, frame after frame, row-major (N x H x W).
    pub images: Vec<u8>,
    /// Pixel labels like `images` (empty when not asked for).
    pub labels: Vec<u8>,
    /// Per-frame truth (empty when not asked for).
    pub truth: Vec<FrameTruth>,
    /// Per-frame exposure.
    pub exposures: Vec<f64>,
}

/// What [`render_run`] computes besides the images.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOutputs {
    pub labels: bool,
    pub truth: Option<TruthOptions>,
    /// Worker threads, >= 1.
    pub threads: usize,
}

/// Renders frame k at `poses[k]` with noise stream `k` of `seed`.
pub fn render_run(
    scene: &Scene,
    rays: &CameraRays,
    poses: &[Pose2],
    seed: u64,
    outputs: RunOutputs,
) -> Result<RenderedRun> {
    if outputs.threads == 0 || outputs.threads > 256 {
        return Err(invalid_option(
            "threads",
            format!("must be in 1..=256, got {}", outputs.threads),
        ));
    }
    if let Some(t) = &outputs.truth {
        t.validate()?;
    }
    if let Some(i) = poses.iter().position(|p| !p.is_finite()) {
        return Err(invalid_option("poses", format!("pose {i} is not finite")));
    }
    let (w, h) = (rays.camera.width, rays.camera.height);
    let n = poses.len();
    let px = w * h;
    let mut run = RenderedRun {
        width: w,
        height: h,
        images: vec![0; n * px],
        labels: if outputs.labels {
            vec![0; n * px]
        } else {
            vec![]
        },
        truth: vec![],
        exposures: vec![0.0; n],
    };
    let mut truths: Vec<Option<FrameTruth>> = vec![None; n];
    if n == 0 || px == 0 {
        return Ok(run);
    }
    // One frame per task on a pool of exactly `threads` workers (rayon balances the frames,
    // whose cost varies with the view); each worker reuses its render buffers.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(outputs.threads)
        .build()
        .map_err(|e| invalid_option("threads", format!("cannot start the render threads: {e}")))?;
    let mut labels: Vec<&mut [u8]> = if outputs.labels {
        run.labels.chunks_mut(px).collect()
    } else {
        (0..n).map(|_| Default::default()).collect()
    };
    pool.install(|| {
        run.images
            .par_chunks_mut(px)
            .zip(labels.par_iter_mut())
            .zip(run.exposures.par_iter_mut())
            .zip(truths.par_iter_mut())
            .enumerate()
            .try_for_each_init(
                RenderBuffers::default,
                |buf, (f, (((img, lab), e), tr))| -> Result<()> {
                    render_into(scene, rays, poses[f], seed, f as u64, buf)?;
                    img.copy_from_slice(&buf.image);
                    if !lab.is_empty() {
                        lab.copy_from_slice(&buf.labels);
                    }
                    *e = buf.exposure;
                    if let Some(opts) = &outputs.truth {
                        *tr = Some(frame_truth(scene, rays, poses[f], opts));
                    }
                    Ok(())
                },
            )
    })?;
    run.truth = truths.into_iter().flatten().collect();
    Ok(run)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::builtin_world;
    use crate::camera::Camera;

    #[test]
    fn threads_do_not_change_the_result() {
        let scene = Scene::new(builtin_world("lab").unwrap());
        let rays = CameraRays::new(Camera::wide_angle(64, 48)).unwrap();
        let poses: Vec<Pose2> = (0..7)
            .map(|k| Pose2::new(1.0 + 0.3 * k as f64, 0.1, 0.05 * k as f64))
            .collect();
        let out = |threads| {
            render_run(
                &scene,
                &rays,
                &poses,
                5,
                RunOutputs {
                    labels: true,
                    truth: Some(TruthOptions::default()),
                    threads,
                },
            )
            .unwrap()
        };
        let (a, b) = (out(1), out(3));
        assert_eq!(a.images, b.images);
        assert_eq!(a.labels, b.labels);
        assert_eq!(a.truth.len(), b.truth.len());
        for (k, (x, y)) in a.truth.iter().zip(&b.truth).enumerate() {
            // (Debug text: NaN fields compare unequal with ==.)
            assert_eq!(format!("{x:?}"), format!("{y:?}"), "frame {k}");
        }
        assert_eq!(a.images.len(), 7 * 64 * 48);
        assert!(render_run(
            &scene,
            &rays,
            &poses,
            5,
            RunOutputs {
                labels: false,
                truth: None,
                threads: 0
            }
        )
        .is_err());
    }
}
