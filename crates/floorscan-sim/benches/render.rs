//! Render time per frame in the corridor world (one core), and a minute of simulated robot time.
//! Run: `cargo bench -p floorscan-sim --bench render`.

use criterion::{criterion_group, criterion_main, Criterion};
use floorscan_core::Pose2;
use floorscan_sim::builtin::builtin_world;
use floorscan_sim::odometry::OdometryNoise;
use floorscan_sim::render::{render_into, RenderBuffers};
use floorscan_sim::robot::{drive, Motion, RobotOptions};
use floorscan_sim::run::{render_run, RunOutputs};
use floorscan_sim::truth::{frame_truth, TruthOptions};
use floorscan_sim::{Camera, CameraRays, Scene};

fn corridor() -> Scene {
    Scene::new(builtin_world("corridor").unwrap())
}

/// Poses along the corridor tour (every 5 s of a 60 s run), so the timing covers many views.
fn tour_poses(scene: &Scene) -> Vec<Pose2> {
    let w = &scene.world;
    let motion = Motion::Waypoints {
        points: w.tour.clone(),
        repeat: true,
    };
    let tr = drive(
        w.start,
        &motion,
        &RobotOptions::default(),
        &OdometryNoise::none(),
        60.0,
        0,
    )
    .unwrap();
    tr.truth.iter().step_by(50).copied().collect()
}

fn bench_render(c: &mut Criterion) {
    let scene = corridor();
    let poses = tour_poses(&scene);
    let mut group = c.benchmark_group("render_corridor");
    for (w, h) in [(320usize, 240usize), (640, 480)] {
        let rays = CameraRays::new(Camera::wide_angle(w, h)).unwrap();
        let mut buf = RenderBuffers::default();
        let mut k = 0usize;
        group.bench_function(format!("{w}x{h}"), |b| {
            b.iter(|| {
                k += 1;
                render_into(&scene, &rays, poses[k % poses.len()], 0, k as u64, &mut buf).unwrap();
            })
        });
    }
    let rays = CameraRays::new(Camera::wide_angle(320, 240)).unwrap();
    let mut k = 0usize;
    group.bench_function("truth_320x240", |b| {
        b.iter(|| {
            k += 1;
            frame_truth(
                &scene,
                &rays,
                poses[k % poses.len()],
                &TruthOptions::default(),
            )
        })
    });
    group.finish();

    let mut group = c.benchmark_group("run_corridor");
    group.sample_size(10);
    let w = &scene.world;
    let motion = Motion::Waypoints {
        points: w.tour.clone(),
        repeat: true,
    };
    let tr = drive(
        w.start,
        &motion,
        &RobotOptions::default(),
        &OdometryNoise::default(),
        60.0,
        0,
    )
    .unwrap();
    group.bench_function("60s_10hz_320x240_images_labels_truth_1thread", |b| {
        b.iter(|| {
            render_run(
                &scene,
                &rays,
                &tr.truth,
                0,
                RunOutputs {
                    labels: true,
                    truth: Some(TruthOptions::default()),
                    threads: 1,
                },
            )
            .unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench_render);
criterion_main!(benches);
