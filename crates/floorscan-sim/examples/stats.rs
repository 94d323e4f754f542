use floorscan_sim::builtin::builtin_world;
use floorscan_sim::odometry::OdometryNoise;
use floorscan_sim::render::CameraPlacement;
use floorscan_sim::robot::{drive, Motion, RobotOptions};
use floorscan_sim::grid_index::CellWalk;
use floorscan_sim::{Camera, CameraRays, Scene};
use floorscan_core::Point2;
fn main() {
    let scene = Scene::new(builtin_world("corridor").unwrap());
    let w = &scene.world;
    let motion = Motion::Waypoints { points: w.tour.clone(), repeat: true };
    let tr = drive(w.start, &motion, &RobotOptions::default(), &OdometryNoise::none(), 60.0, 0).unwrap();
    let poses: Vec<_> = tr.truth.iter().step_by(50).copied().collect();
    let rays = CameraRays::new(Camera::wide_angle(320, 240)).unwrap();
    let (mut cells, mut rays_n, mut floor_n) = (0usize, 0usize, 0usize);
    let mut hist = [0usize; 8];
    for p in &poses {
        let place = CameraPlacement::new(&rays, *p);
        for d0 in &rays.dirs {
            let d = place.to_world(*d0);
            let hit = scene.trace(place.origin, d);
            let mut walk = CellWalk::new(&scene.shape, Point2::new(place.origin[0], place.origin[1]), Point2::new(d[0], d[1]));
            let mut c = 0;
            while let Some((_, t_exit)) = walk.next_cell() { c += 1; if t_exit >= hit.t { break; } }
            cells += c; rays_n += 1;
            if d[2] < 0.0 { floor_n += 1; }
            hist[(c.min(64) as f64).log2() as usize] += 1;
        }
    }
    println!("cells/ray {:.2}, floor fraction {:.2}, hist(log2) {:?}", cells as f64 / rays_n as f64, floor_n as f64 / rays_n as f64, hist);
}
