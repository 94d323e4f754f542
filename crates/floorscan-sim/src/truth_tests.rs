//! Tests of [`super`] (truth.rs).

use super::*;
use crate::camera::{Camera, Imaging};
use crate::render::{render_into, RenderBuffers};
use crate::world_file::parse_world;
use floorscan_core::mount::ground_to_pixel;

/// A floor with one straight wall whose face is at x = `d` in the camera ground frame.
fn wall_scene(d: f64, extra: &str) -> Scene {
    let text = format!(
        "name = \"wall\"\n[start]\nx = 0\ny = 0\n[[walls]]\nfrom = [{x}, -30]\nto = [{x}, 30]\n{extra}",
        x = d + 0.05
    );
    Scene::new(parse_world(&text, "wall").unwrap())
}

fn camera_at_origin() -> (CameraRays, Pose2) {
    let cam = Camera {
        imaging: Imaging::ideal(),
        ..Default::default()
    };
    let pose = crate::calibration::robot_pose(&cam);
    (CameraRays::new(cam).unwrap(), pose)
}

/// The row where the line x = d crosses column u, from the lens model's forward projection
/// only: bisection on y until the projected column is u.
fn predicted_row(cam: &Camera, d: f64, u: f64) -> f64 {
    let project = |y: f64| ground_to_pixel(&cam.lens, &cam.mount, Point2::new(d, y)).unwrap();
    // Column u decreases as y grows (y is left).
    let (mut lo, mut hi) = (-20.0 * d, 20.0 * d);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        match ground_to_pixel(&cam.lens, &cam.mount, Point2::new(d, mid)) {
            Some(p) if p[0] > u => lo = mid,
            Some(_) => hi = mid,
            None => {
                if mid > 0.0 {
                    hi = mid
                } else {
                    lo = mid
                }
            }
        }
    }
    project(0.5 * (lo + hi))[1]
}

#[test]
fn a_wall_at_a_known_distance_gives_the_rows_and_points_the_lens_predicts() {
    let (rays, pose) = camera_at_origin();
    let cam = rays.camera.clone();
    for d in [0.6, 1.5, 3.0] {
        let scene = wall_scene(d, "");
        let truth = frame_truth(&scene, &rays, pose, &TruthOptions::default());
        let mut checked = 0;
        for c in &truth.columns {
            if c.status != ColumnStatus::Boundary {
                continue;
            }
            let p = c.point.unwrap();
            assert!((p.x - d).abs() < 1e-7, "d {d} column {}: {p:?}", c.column);
            let px = ground_to_pixel(&cam.lens, &cam.mount, p).unwrap();
            assert!((px[0] - c.column as f64).abs() < 1e-6 && (px[1] - c.row).abs() < 1e-6);
            let want = predicted_row(&cam, d, c.column as f64);
            assert!(
                (c.row - want).abs() < 1e-6,
                "d {d} column {}: row {} vs {want}",
                c.column,
                c.row
            );
            let o = c.obstacle_world.unwrap();
            let pw = c.point_world.unwrap();
            assert!(
                (o.x - pw.x).abs() < 1e-6 && (o.y - pw.y).abs() < 1e-6 && c.obstacle_z_m < 1e-6
            );
            checked += 1;
        }
        // The wall spans the whole field of view near the robot.
        assert!(checked > 250, "d {d}: only {checked} boundary columns");
        // Labels of an ideal render agree: floor below the boundary row, wall above.
        let mut buf = RenderBuffers::default();
        render_into(&scene, &rays, pose, 0, 0, &mut buf).unwrap();
        for c in truth
            .columns
            .iter()
            .filter(|c| c.status == ColumnStatus::Boundary)
        {
            let above = c.row.floor() as usize;
            assert_eq!(
                buf.labels[above * cam.width + c.column as usize],
                PixelLabel::Obstacle as u8
            );
            for v in 0..cam.height {
                let label = buf.labels[v * cam.width + c.column as usize];
                if (v as f64) > c.row + 1e-6 {
                    assert_eq!(label, PixelLabel::Carpet as u8);
                } else if (v as f64) < c.row - 1e-6 {
                    // The wall, and above its top edge the ceiling.
                    assert!(
                        label == PixelLabel::Obstacle as u8 || label == PixelLabel::Ceiling as u8
                    );
                }
            }
        }
    }
}

#[test]
fn statuses_too_close_and_no_boundary() {
    let (rays, pose) = camera_at_origin();
    let near = frame_truth(&wall_scene(0.01, ""), &rays, pose, &TruthOptions::default());
    let mid = near.columns[160];
    assert_eq!(mid.status, ColumnStatus::TooClose);
    let far = frame_truth(&wall_scene(12.0, ""), &rays, pose, &TruthOptions::default());
    assert_eq!(far.columns[160].status, ColumnStatus::NoBoundary);
    let far_ok = frame_truth(
        &wall_scene(12.0, ""),
        &rays,
        pose,
        &TruthOptions { max_range_m: 20.0 },
    );
    assert_eq!(far_ok.columns[160].status, ColumnStatus::Boundary);
}

#[test]
fn an_overhang_hides_the_floor_under_it_as_the_lens_predicts() {
    // A slab from z = 0.1 to 0.3 m whose front face is at x = 1.0 in front of a camera 0.4 m
    // high: the floor stays visible under it up to x = 1.0 / (1 - 0.1 / 0.4) = 4/3 m.
    let (rays, pose) = camera_at_origin();
    let scene = Scene::new(
        parse_world(
            "name = \"o\"\n[start]\nx = 0\ny = 0\n[[boxes]]\nrect = [1.0, -5, 1.5, 5]\nbase_m = 0.1\nheight_m = 0.3\n",
            "o",
        )
        .unwrap(),
    );
    let truth = frame_truth(&scene, &rays, pose, &TruthOptions::default());
    let c = truth.columns[160];
    assert_eq!(c.status, ColumnStatus::Boundary);
    let (p, o) = (c.point.unwrap(), c.obstacle_world.unwrap());
    let y_scale = 1.0 / p.x;
    assert!((p.x - 4.0 / 3.0).abs() < 1e-6, "{p:?}");
    assert!(
        (o.x - 1.0).abs() < 1e-6 && (o.y - p.y * y_scale).abs() < 1e-6,
        "{o:?}"
    );
    assert!((c.obstacle_z_m - 0.1).abs() < 1e-6);
}

#[test]
fn paper_on_the_carpet_is_an_appearance_boundary_but_not_an_obstacle() {
    let (rays, pose) = camera_at_origin();
    let scene = wall_scene(
        3.0,
        "[[regions]]\ncovering = \"paper\"\nrect = [1.0, -0.2, 1.3, 0.2]\n",
    );
    let truth = frame_truth(&scene, &rays, pose, &TruthOptions::default());
    let c = truth.columns[160];
    assert_eq!(c.status, ColumnStatus::Boundary);
    assert!((c.point.unwrap().x - 3.0).abs() < 1e-7);
    let a = c.appearance_point.unwrap();
    assert!((a.x - 1.0).abs() < 1e-7, "{a:?}");
    assert!(c.appearance_row > c.row);
    // Away from the paper, the appearance boundary is the wall.
    let side = truth.columns[20];
    assert!((side.appearance_row - side.row).abs() < 1e-6);
}
