//! Renders the render bench's corridor views (13 poses of the tour, default wide-angle camera)
//! a fixed number of times, for instruction counts that do not depend on the machine's load:
//!
//! ```sh
//! cargo build --release -p floorscan-sim --example render_frames
//! valgrind --tool=callgrind target/release/examples/render_frames 320 240 13
//! ```
//!
//! Arguments: width, height, frames (defaults 320 240 13). Prints a checksum of the images.

use floorscan_core::Pose2;
use floorscan_sim::builtin::builtin_world;
use floorscan_sim::odometry::OdometryNoise;
use floorscan_sim::render::{render_into, RenderBuffers};
use floorscan_sim::robot::{drive, Motion, RobotOptions};
use floorscan_sim::{Camera, CameraRays, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let arg = |i: usize, default: usize| args.get(i).copied().unwrap_or(default);
    let (w, h, frames) = (arg(0, 320), arg(1, 240), arg(2, 13));
    let scene = Scene::new(builtin_world("corridor")?);
    let world = &scene.world;
    let motion = Motion::Waypoints {
        points: world.tour.clone(),
        repeat: true,
    };
    let run = drive(
        world.start,
        &motion,
        &RobotOptions::default(),
        &OdometryNoise::none(),
        60.0,
        0,
    )?;
    let poses: Vec<Pose2> = run.truth.iter().step_by(50).copied().collect();
    let rays = CameraRays::new(Camera::wide_angle(w, h))?;
    let mut buf = RenderBuffers::default();
    let mut checksum = 0u64;
    for k in 0..frames {
        render_into(&scene, &rays, poses[k % poses.len()], 0, k as u64, &mut buf)?;
        checksum = buf
            .image
            .iter()
            .fold(checksum, |s, &b| s.wrapping_mul(31).wrapping_add(b as u64));
    }
    println!("{frames} frames {w}x{h}, checksum {checksum:016x}");
    Ok(())
}
