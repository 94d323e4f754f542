use floorscan_sim::builtin::builtin_world;
use floorscan_sim::odometry::OdometryNoise;
use floorscan_sim::render::{render_into, RenderBuffers, CameraPlacement};
use floorscan_sim::robot::{drive, Motion, RobotOptions};
use floorscan_sim::truth::{frame_truth, TruthOptions};
use floorscan_sim::{Camera, CameraRays, Scene, Imaging};
fn main() {
    let mode = std::env::args().nth(1).unwrap_or("default".into());
    let scene = Scene::new(builtin_world("corridor").unwrap());
    let w = &scene.world;
    let motion = Motion::Waypoints { points: w.tour.clone(), repeat: true };
    let tr = drive(w.start, &motion, &RobotOptions::default(), &OdometryNoise::none(), 60.0, 0).unwrap();
    let poses: Vec<_> = tr.truth.iter().step_by(50).copied().collect();
    let mut cam = Camera::wide_angle(320, 240);
    if mode == "ideal" { cam.imaging = Imaging::ideal(); }
    let rays = CameraRays::new(cam).unwrap();
    let mut buf = RenderBuffers::default();
    let n = 200;
    let mut acc = 0.0;
    for k in 0..n {
        match mode.as_str() {
            "trace" => {
                let place = CameraPlacement::new(&rays, poses[k % poses.len()]);
                for d in &rays.dirs { if d[0].is_nan() {continue;} let h = scene.trace(place.origin, place.to_world(*d)); acc += h.t; }
            }
            "truth" => { acc += frame_truth(&scene, &rays, poses[k % poses.len()], &TruthOptions::default()).columns.len() as f64; }
            "setup" => {}
            _ => render_into(&scene, &rays, poses[k % poses.len()], 0, k as u64, &mut buf).unwrap(),
        }
    }
    println!("{acc}");
}
