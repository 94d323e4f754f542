//! The floor-parallax cue on frames rendered here by ray casting: a pinhole camera 0.3 m above a
//! textured floor with dark grout lines across it every 0.3 m, and a textured wall standing
//! 1.2 m ahead of the first view. Truth is the scene's geometry.

use super::warp::solve3;
use super::*;
use crate::image::ImageView;
use crate::ranger_options::{ColumnSelection, RangerOptions};
use crate::ColumnReading;

const W: usize = 240;
const H: usize = 180;
const F: f64 = 170.0;
const HEIGHT_M: f64 = 0.3;
const PITCH_DEG: f64 = 25.0;
const WALL_X: f64 = 1.2;
const GROUT_EVERY_M: f64 = 0.3;
const GROUT_M: f64 = 0.012;

/// The ray of pixel (u, v) in the camera ground frame: (dx, dy, dz), camera at height HEIGHT_M.
fn ray(u: f64, v: f64) -> (f64, f64, f64) {
    let (xc, yc, zc) = (
        1.0,
        -(u - (W as f64 - 1.0) / 2.0) / F,
        -(v - (H as f64 - 1.0) / 2.0) / F,
    );
    let (s, c) = PITCH_DEG.to_radians().sin_cos();
    (c * xc + s * zc, yc, -s * xc + c * zc)
}

fn floor_of_pixel(u: f64, v: f64) -> Option<Point2> {
    let (dx, dy, dz) = ray(u, v);
    (dz < -1e-6).then(|| {
        let t = HEIGHT_M / -dz;
        Point2::new(t * dx, t * dy)
    })
}

fn table() -> GroundTable {
    GroundTable::from_fn(W, H, 4, floor_of_pixel).unwrap()
}

fn floor_grey(x: f64, y: f64) -> f64 {
    if x.rem_euclid(GROUT_EVERY_M) < GROUT_M {
        return 55.0;
    }
    150.0 + 22.0 * (x * 41.0).sin() * (y * 37.0).cos() + 12.0 * (x * 97.0 + y * 13.0).sin()
}

fn wall_grey(y: f64, z: f64) -> f64 {
    85.0 + 20.0 * (y * 53.0).sin() * (z * 47.0).cos() + 10.0 * (y * 131.0 - z * 71.0).sin()
}

/// The frame seen from camera foot x = `foot_x` (2 x 2 samples a pixel).
fn render(foot_x: f64) -> Vec<u8> {
    let mut img = vec![0u8; W * H];
    for v in 0..H {
        for u in 0..W {
            let mut acc = 0.0;
            for (a, b) in [(-0.25, -0.25), (0.25, -0.25), (-0.25, 0.25), (0.25, 0.25)] {
                let (dx, dy, dz) = ray(u as f64 + a, v as f64 + b);
                let t_wall = (dx > 1e-9).then(|| (WALL_X - foot_x) / dx).filter(|&t| {
                    let z = HEIGHT_M + t * dz;
                    (0.0..=1.0).contains(&z)
                });
                let t_floor = (dz < -1e-9).then(|| HEIGHT_M / -dz);
                acc += match (t_floor, t_wall) {
                    (Some(tf), Some(tw)) if tf < tw => floor_grey(foot_x + tf * dx, tf * dy),
                    (_, Some(tw)) => wall_grey(tw * dy, HEIGHT_M + tw * dz),
                    (Some(tf), None) => floor_grey(foot_x + tf * dx, tf * dy),
                    (None, None) => 200.0,
                };
            }
            img[v * W + u] = (acc / 4.0).round().clamp(0.0, 255.0) as u8;
        }
    }
    img
}

fn ranger(table: &GroundTable) -> VisualRanger {
    let options = RangerOptions {
        columns: ColumnSelection::Explicit((20..220).step_by(10).map(|u| u as u32).collect()),
        ..RangerOptions::default()
    };
    VisualRanger::new(table.clone(), options).unwrap()
}

fn boundary_x(scan: &Scan) -> Vec<Option<f64>> {
    scan.readings
        .iter()
        .map(|r| match r.outcome {
            ColumnOutcome::Boundary { point, .. } => Some(point.x),
            _ => None,
        })
        .collect()
}

/// Ranges the second view (camera foot at 0.2 m) after the first (at 0), the first's pose
/// given as `first_pose` (odometry, possibly wrong).
fn view(img: &[u8]) -> ImageView<'_, u8> {
    ImageView::new(img, W, H).unwrap()
}

fn two_views(first_pose: Pose2, options: ParallaxOptions) -> (Scan, Scan, ParallaxReport) {
    let (_, out, report) = cue_after_two_views(first_pose, options);
    let before = ranger(&table()).scan(&view(&render(0.2)), 0.5).unwrap();
    (before, out, report)
}

/// The cue after ranging both views, the second view's scan and its report.
fn cue_after_two_views(
    first_pose: Pose2,
    options: ParallaxOptions,
) -> (FloorParallax, Scan, ParallaxReport) {
    let table = table();
    let (a, b) = (render(0.0), render(0.2));
    let mut cued = ranger(&table);
    let mut cue = FloorParallax::new(table, options).unwrap();
    let mut out = Scan::default();
    let r0 = cue
        .scan_into(&mut cued, &view(&a), 0.0, Some(first_pose), &mut out)
        .unwrap();
    assert_eq!(r0.vetoes, 0, "no earlier frame yet");
    let report = cue
        .scan_into(
            &mut cued,
            &view(&b),
            0.5,
            Some(Pose2::new(0.2, 0.0, 0.0)),
            &mut out,
        )
        .unwrap();
    (cue, out, report)
}

/// The camera-frame x of the first grout line ahead of the second view and of the wall.
fn truths() -> (f64, f64) {
    let first_grout = (0.2f64 / GROUT_EVERY_M).ceil() * GROUT_EVERY_M;
    (first_grout + GROUT_M - 0.2, WALL_X - 0.2)
}

#[test]
fn grout_lines_are_the_floors_own_and_the_wall_base_is_found_above_them() {
    let (grout_x, wall_x) = truths();
    let (before, after, report) = two_views(Pose2::IDENTITY, ParallaxOptions::default());
    assert!(report.baseline_m > 0.19 && report.vetoes > 0, "{report:?}");
    let (xb, xa) = (boundary_x(&before), boundary_x(&after));
    // the edge ranger alone stops at a grout line in most columns: nearer than the wall
    let at_grout = xb.iter().flatten().filter(|&&x| x < wall_x - 0.1).count();
    assert!(
        at_grout * 2 > xb.len(),
        "{xb:?} (grout from {grout_x:.2} m)"
    );
    assert_wall_base_found(&xa, wall_x, &report);
}

/// The wall's base within 3 cm in at least 80 % of the columns (every column sees the wall),
/// and no boundary past the wall.
fn assert_wall_base_found(xa: &[Option<f64>], wall_x: f64, report: &ParallaxReport) {
    let right = xa
        .iter()
        .flatten()
        .filter(|&&x| (x - wall_x).abs() < 0.03)
        .count();
    assert!(
        right * 10 >= xa.len() * 8,
        "{right} of {}: {xa:?} {report:?}",
        xa.len()
    );
    assert!(xa.iter().flatten().all(|&x| x < wall_x + 0.03), "{xa:?}");
}

#[test]
fn the_refinement_absorbs_odometry_off_by_two_centimetres_and_a_degree() {
    let (_, wall_x) = truths();
    let wrong = Pose2::new(0.02, -0.015, 1f64.to_radians());
    let (_, after, report) = two_views(wrong, ParallaxOptions::default());
    assert_wall_base_found(&boundary_x(&after), wall_x, &report);
}

#[test]
fn without_a_pose_or_a_baseline_the_scan_is_the_edge_rangers() {
    let table = table();
    let img = render(0.2);
    let view = ImageView::new(&img, W, H).unwrap();
    let plain = ranger(&table).scan(&view, 1.0).unwrap();
    let mut cued = ranger(&table);
    let mut cue = FloorParallax::new(table, ParallaxOptions::default()).unwrap();
    let mut out = Scan::default();
    for _ in 0..3 {
        let r = cue
            .scan_into(&mut cued, &view, 1.0, None, &mut out)
            .unwrap();
        assert_eq!(
            (r.vetoes, out.readings.clone()),
            (0, plain.readings.clone())
        );
    }
    // a camera turning about its own centre: no kept frame is even the turn baseline away
    for k in 0..4 {
        let pose = Pose2::new(0.0, 0.0, 0.01 * k as f64);
        let r = cue
            .scan_into(&mut cued, &view, 1.0, Some(pose), &mut out)
            .unwrap();
        assert_eq!(r.vetoes, 0);
        assert_eq!(out.readings, plain.readings);
    }
}

/// The cue on the view from 0.2 m after one from `first_x`, both poses exact.
fn after_short_travel(first_x: f64, options: ParallaxOptions) -> (Scan, ParallaxReport) {
    let table = table();
    let (a, b) = (render(first_x), render(0.2));
    let mut cued = ranger(&table);
    let mut cue = FloorParallax::new(table, options).unwrap();
    let mut out = Scan::default();
    let pose = |x: f64| Some(Pose2::new(x, 0.0, 0.0));
    cue.scan_into(&mut cued, &view(&a), 0.0, pose(first_x), &mut out)
        .unwrap();
    let report = cue
        .scan_into(&mut cued, &view(&b), 0.3, pose(0.2), &mut out)
        .unwrap();
    (out, report)
}

#[test]
fn short_of_the_least_baseline_the_farthest_frame_past_the_turn_baseline_is_compared() {
    // 8 cm of travel: short of `min_baseline_m` (0.15), past `min_turn_baseline_m` (0.05)
    let (_, wall_x) = truths();
    let (after, report) = after_short_travel(0.12, ParallaxOptions::default());
    assert!((report.baseline_m - 0.08).abs() < 1e-9, "{report:?}");
    assert_wall_base_found(&boundary_x(&after), wall_x, &report);
    // with the fallback off (the turn baseline at the least baseline) nothing is compared
    let off = ParallaxOptions {
        min_turn_baseline_m: ParallaxOptions::default().min_baseline_m,
        ..ParallaxOptions::default()
    };
    let (after, report) = after_short_travel(0.12, off);
    let plain = ranger(&table()).scan(&view(&render(0.2)), 0.3).unwrap();
    assert_eq!((report.baseline_m, report.vetoes), (0.0, 0), "{report:?}");
    assert_eq!(after.readings, plain.readings);
    // and short of the turn baseline too (3 cm): nothing is compared
    let (_, report) = after_short_travel(0.17, ParallaxOptions::default());
    assert_eq!(report.baseline_m, 0.0, "{report:?}");
}

#[test]
fn turning_on_the_spot_compares_the_kept_frame_whose_camera_moved_farthest() {
    // a camera mounted 0.12 m ahead of the axis the robot turns about: its centre moves along
    // a circle, 2 r sin(angle / 2) from where it was (the chord)
    let (mount, step) = (0.12, 0.15);
    let table = table();
    let img = render(0.2);
    let mut cued = ranger(&table);
    let mut cue = FloorParallax::new(table, ParallaxOptions::default()).unwrap();
    let mut out = Scan::default();
    let camera_at = |yaw: f64| Pose2::new(mount * yaw.cos(), mount * yaw.sin(), yaw);
    let chord = |angle: f64| 2.0 * mount * (angle / 2.0).sin();
    for k in 0..6 {
        let yaw = step * k as f64;
        let r = cue
            .scan_into(
                &mut cued,
                &view(&img),
                0.1 * k as f64,
                Some(camera_at(yaw)),
                &mut out,
            )
            .unwrap();
        // the kept frames' chords: the farthest is the first frame's, compared once >= 0.05
        let farthest = chord(yaw);
        let expected = if k > 0 && farthest >= 0.05 {
            farthest
        } else {
            0.0
        };
        assert!(
            (r.baseline_m - expected).abs() < 1e-9,
            "turn {yaw:.2}: {r:?}"
        );
    }
}

#[test]
fn a_corner_offers_both_faces_and_one_facing_the_camera_as_standing_surfaces() {
    // boundaries along a wall facing the camera (x = 1) up to the corner at (1, 0.2), then
    // along a face running away from the camera (y = 0.2); one far boundary and a column
    // without one
    let points = [
        Some(Point2::new(1.0, 0.4)),
        Some(Point2::new(1.0, 0.3)),
        Some(Point2::new(1.0, 0.2)),
        Some(Point2::new(1.1, 0.2)),
        Some(Point2::new(3.0, 0.2)),
        None,
    ];
    let scan = Scan {
        timestamp_s: 0.0,
        readings: points
            .iter()
            .enumerate()
            .map(|(i, p)| ColumnReading {
                column: 10 * i as u32,
                start_row: 0.0,
                near: None,
                outcome: match p {
                    Some(point) => ColumnOutcome::Boundary {
                        row: 0.0,
                        point: *point,
                        footprint_m: 0.0,
                    },
                    None => ColumnOutcome::TooClose,
                },
                confidence: 1.0,
            })
            .collect(),
    };
    let directions = |j: usize| {
        let (d, count) = base_directions(&scan, j, points[j].unwrap(), 0.25);
        d[..count]
            .iter()
            .map(|d| d.map(|p| (p.x.round() as i32, p.y.round() as i32)))
            .collect::<Vec<_>>()
    };
    // on the wall: the line through both neighbours, each alone (the same line), facing
    let along_wall = Some((0, -1));
    assert_eq!(
        directions(1),
        vec![along_wall, along_wall, along_wall, None]
    );
    // at the corner: the chord through the neighbours (diagonal), then each face, then facing
    let corner = directions(2);
    assert_eq!(corner.len(), 4);
    assert_eq!(corner[1..], [along_wall, Some((1, 0)), None]);
    // one neighbour near (the far one is beyond the gap): its line, then facing the camera
    assert_eq!(directions(3), vec![Some((1, 0)), None]);
    // no neighbour near: facing the camera only
    assert_eq!(directions(4), vec![None]);
}

#[test]
fn a_ranger_on_another_table_or_a_pose_not_finite_is_refused() {
    let table = table();
    let img = render(0.0);
    let view = ImageView::new(&img, W, H).unwrap();
    let mut cue = FloorParallax::new(table.clone(), ParallaxOptions::default()).unwrap();
    let mut out = Scan::default();
    let other = GroundTable::from_fn(W, H, 8, floor_of_pixel).unwrap();
    assert!(cue
        .scan_into(&mut ranger(&other), &view, 0.0, None, &mut out)
        .is_err());
    let bad = Some(Pose2::new(f64::NAN, 0.0, 0.0));
    assert!(cue
        .scan_into(&mut ranger(&table), &view, 0.0, bad, &mut out)
        .is_err());
    let options = ParallaxOptions {
        history_frames: 0,
        ..ParallaxOptions::default()
    };
    assert!(FloorParallax::new(table, options).is_err());
}

#[test]
fn solve3_and_the_blur_agree_with_their_definitions() {
    let a = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
    let x = [0.3, -1.2, 2.5];
    let b = [0, 1, 2].map(|r| (0..3).map(|c| a[r][c] * x[c]).sum::<f64>());
    let got = solve3(a, b).unwrap();
    assert!(got.iter().zip(x).all(|(g, e)| (g - e).abs() < 1e-12));
    assert!(solve3(
        [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]],
        [1.0; 3]
    )
    .is_none());
    // a blur keeps a constant image and the sum of a point inside the image
    let k = gaussian_kernel(1.0);
    assert!((k.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    let mut img = vec![7u8; 15 * 11];
    let (mut s, mut out) = (vec![0.0; 15 * 11], vec![0.0; 15 * 11]);
    blur_into(&ImageView::new(&img, 15, 11).unwrap(), &k, &mut s, &mut out);
    assert!(out.iter().all(|&p| (p - 7.0).abs() < 1e-4));
    img.fill(0);
    img[5 * 15 + 7] = 200;
    blur_into(&ImageView::new(&img, 15, 11).unwrap(), &k, &mut s, &mut out);
    assert!((out.iter().sum::<f32>() - 200.0).abs() < 1e-2);
    assert!(out[5 * 15 + 7] > out[5 * 15 + 8] && out[5 * 15 + 8] > out[5 * 15 + 9]);
}

/// A wall along the motion 0.5 m to the left (y = 0.5), a dark baseboard 6 cm high, seen from
/// a camera yawed 40 degrees towards it; the floor plain (no grout) so the only boundary is the
/// wall's base.
fn render_side_wall(foot_x: f64) -> Vec<u8> {
    let yaw = 40f64.to_radians();
    let (sy, cy) = yaw.sin_cos();
    let mut img = vec![0u8; W * H];
    for v in 0..H {
        for u in 0..W {
            let mut acc = 0.0;
            for (a, b) in [(-0.25, -0.25), (0.25, -0.25), (-0.25, 0.25), (0.25, 0.25)] {
                let (dx0, dy0, dz) = ray(u as f64 + a, v as f64 + b);
                let (dx, dy) = (cy * dx0 - sy * dy0, sy * dx0 + cy * dy0);
                let t_wall = (dy > 1e-9)
                    .then(|| 0.5 / dy)
                    .filter(|&t| (0.0..=1.0).contains(&(HEIGHT_M + t * dz)));
                let t_floor = (dz < -1e-9).then(|| HEIGHT_M / -dz);
                acc += match (t_floor, t_wall) {
                    (Some(tf), Some(tw)) if tf < tw => {
                        let (x, y) = (foot_x + tf * dx, tf * dy);
                        140.0 + 10.0 * (x * 61.0).sin() * (y * 53.0).cos()
                    }
                    (_, Some(tw)) => {
                        let (x, z) = (foot_x + tw * dx, HEIGHT_M + tw * dz);
                        if z < 0.06 {
                            40.0
                        } else {
                            120.0 + 18.0 * (x * 43.0).sin() * (z * 57.0).cos()
                        }
                    }
                    (Some(tf), None) => 140.0 + 10.0 * (tf * dx * 61.0).sin(),
                    (None, None) => 200.0,
                };
            }
            img[v * W + u] = (acc / 4.0).round().clamp(0.0, 255.0) as u8;
        }
    }
    img
}

#[test]
fn a_wall_along_the_motion_keeps_its_base() {
    let table = table();
    let yaw = 40f64.to_radians();
    let (a, b) = (render_side_wall(0.0), render_side_wall(0.2));
    let mut plain = ranger(&table);
    let mut cued = ranger(&table);
    let mut cue = FloorParallax::new(table, ParallaxOptions::default()).unwrap();
    let mut out = Scan::default();
    cue.scan_into(
        &mut cued,
        &view(&a),
        0.0,
        Some(Pose2::new(0.0, 0.0, yaw)),
        &mut out,
    )
    .unwrap();
    let report = cue
        .scan_into(
            &mut cued,
            &view(&b),
            0.5,
            Some(Pose2::new(0.2, 0.0, yaw)),
            &mut out,
        )
        .unwrap();
    let before = plain.scan(&view(&b), 0.5).unwrap();
    assert!(report.baseline_m > 0.19);
    let bases = boundary_x(&before).iter().flatten().count();
    assert!(
        bases * 10 >= before.readings.len() * 8,
        "{bases} boundaries"
    );
    // the edge ranger finds the wall's base here; the cue keeps it in all but a column or two
    // (the image's edge, where the wall is seen most obliquely)
    let changed = before
        .readings
        .iter()
        .zip(&out.readings)
        .filter(|(p, q)| p.outcome != q.outcome)
        .count();
    assert!(
        changed * 10 <= before.readings.len(),
        "{changed} of {} columns changed: {report:?}\nbefore {:?}\nafter {:?}",
        before.readings.len(),
        boundary_x(&before),
        boundary_x(&out)
    );
}

const STOP: f64 = 0.4;

/// Frames driven forward 0.2 m apart, back one step and forward again, each compared with the
/// one before (one kept), then one more from where the last stood (nothing far enough back to
/// compare): (scan of that one, its report, the edge ranger's scan of it). The grout line 0.5 m
/// ahead of the stop was found to be the floor's from there twice.
fn drive_then_stand(options: ParallaxOptions) -> (Scan, ParallaxReport, Scan) {
    let options = ParallaxOptions {
        history_frames: 1,
        ..options
    };
    let table = table();
    let mut cued = ranger(&table);
    let plain = ranger(&table).scan(&view(&render(STOP)), 2.0).unwrap();
    let mut cue = FloorParallax::new(table, options).unwrap();
    let mut out = Scan::default();
    for (k, foot) in [0.0, 0.2, STOP, 0.2, STOP].into_iter().enumerate() {
        cue.scan_into(
            &mut cued,
            &view(&render(foot)),
            0.5 * k as f64,
            Some(Pose2::new(foot, 0.0, 0.0)),
            &mut out,
        )
        .unwrap();
    }
    let standing = Pose2::new(STOP, 0.0, 0.0);
    let report = cue
        .scan_into(
            &mut cued,
            &view(&render(STOP)),
            2.0,
            Some(standing),
            &mut out,
        )
        .unwrap();
    (out, report, plain)
}

#[test]
fn the_memory_keeps_the_floors_own_edges_when_there_is_nothing_to_compare() {
    // standing still: no earlier frame far enough back, yet the grout lines seen in two
    // earlier frames are the floor's, and the wall's base is found above them
    let (out, report, plain) = drive_then_stand(ParallaxOptions {
        memory_min_frames: 2,
        ..ParallaxOptions::default()
    });
    assert_eq!(report.baseline_m, 0.0, "{report:?}");
    assert!(
        report.remembered > 0 && report.vetoes == report.remembered,
        "{report:?}"
    );
    let wall_x = WALL_X - STOP;
    let xa = boundary_x(&out);
    assert_wall_base_found(&xa, wall_x, &report);
    // the edge ranger alone stops at grout in most columns
    let at_grout = boundary_x(&plain)
        .iter()
        .flatten()
        .filter(|&&x| x < wall_x - 0.1)
        .count();
    assert!(at_grout * 2 > xa.len(), "{at_grout}");
}

#[test]
fn without_the_memory_or_beyond_its_radius_standing_is_the_edge_rangers_scan() {
    for options in [
        ParallaxOptions::default(),
        // every mark lies farther than 5 cm from the camera
        ParallaxOptions {
            memory_min_frames: 2,
            memory_radius_m: 0.05,
            ..ParallaxOptions::default()
        },
    ] {
        let (out, report, plain) = drive_then_stand(options);
        assert_eq!((report.vetoes, report.remembered), (0, 0));
        assert_eq!(out.readings, plain.readings);
    }
}

/// Ranges the view at camera foot 0.6 m after the one at 0.4 m: the wall stands 0.6 m ahead,
/// its base responding below the frame's threshold (the floor's texture set it).
fn near_wall_views(options: ParallaxOptions) -> (Scan, ParallaxReport) {
    let table = table();
    let mut cued = ranger(&table);
    let mut cue = FloorParallax::new(table, options).unwrap();
    let mut out = Scan::default();
    let mut report = ParallaxReport::default();
    for (k, foot) in [0.4, 0.6].into_iter().enumerate() {
        report = cue
            .scan_into(
                &mut cued,
                &view(&render(foot)),
                k as f64,
                Some(Pose2::new(foot, 0.0, 0.0)),
                &mut out,
            )
            .unwrap();
    }
    (out, report)
}

#[test]
fn above_a_vetoed_boundary_with_no_edge_the_motion_finds_a_faint_wall() {
    let wall_x = WALL_X - 0.6;
    let free = |scan: &Scan| {
        scan.readings
            .iter()
            .filter(|r| !matches!(r.outcome, ColumnOutcome::Boundary { .. }))
            .count()
    };
    // without the search: once the grout before it is vetoed, the faint wall is no edge and
    // columns that see the wall 0.6 m ahead report floor to the end of their range
    let off = ParallaxOptions {
        search_above_vetoed: false,
        ..ParallaxOptions::default()
    };
    let (hazard, report) = near_wall_views(off);
    assert!(report.vetoes > 0 && free(&hazard) > 0, "{report:?}");
    // with it (the default): those columns find the wall's base, none goes past it
    let (out, report) = near_wall_views(ParallaxOptions::default());
    assert_eq!(report.found_above, free(&hazard), "{report:?}");
    assert_eq!(free(&out), 0, "{:?}", boundary_x(&out));
    let xa = boundary_x(&out);
    assert!(xa.iter().flatten().all(|&x| x < wall_x + 0.03), "{xa:?}");
    for (h, o) in hazard.readings.iter().zip(&out.readings) {
        match h.outcome {
            ColumnOutcome::Boundary { .. } => assert_eq!(h, o),
            _ => {
                let ColumnOutcome::Boundary { point, .. } = o.outcome else {
                    unreachable!()
                };
                assert!((point.x - wall_x).abs() < 0.05, "{point:?}, wall {wall_x}");
            }
        }
    }
}

#[test]
fn the_blur_equals_a_pixel_by_pixel_loop_bit_for_bit() {
    // the loop it replaced: each pixel's taps in order, edges clamped
    fn reference(img: &[u8], w: usize, h: usize, kernel: &[f32]) -> Vec<f32> {
        let r = (kernel.len() / 2) as i64;
        let mut s = vec![0.0f32; w * h];
        for v in 0..h {
            for u in 0..w {
                let mut acc = 0.0;
                for (t, &k) in kernel.iter().enumerate() {
                    let uu = (u as i64 + t as i64 - r).clamp(0, w as i64 - 1) as usize;
                    acc += k * img[v * w + uu] as f32;
                }
                s[v * w + u] = acc;
            }
        }
        let mut out = vec![0.0f32; w * h];
        for v in 0..h {
            for u in 0..w {
                let mut acc = 0.0;
                for (t, &k) in kernel.iter().enumerate() {
                    let vv = (v as i64 + t as i64 - r).clamp(0, h as i64 - 1) as usize;
                    acc += k * s[vv * w + u];
                }
                out[v * w + u] = acc;
            }
        }
        out
    }
    let mut stream = crate::test_rng::XorShift::new(12345);
    for (w, h, sigma) in [
        (15, 11, 1.0),
        (3, 40, 2.5),
        (64, 2, 0.7),
        (1, 1, 1.5),
        (33, 17, 4.0),
    ] {
        let img: Vec<u8> = (0..w * h)
            .map(|_| (stream.next_u64() >> 56) as u8)
            .collect();
        let k = gaussian_kernel(sigma);
        let (mut s, mut out) = (vec![0.0; w * h], vec![0.0; w * h]);
        blur_into(&ImageView::new(&img, w, h).unwrap(), &k, &mut s, &mut out);
        let want = reference(&img, w, h, &k);
        assert!(
            out.iter()
                .zip(&want)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{w} x {h}, sigma {sigma}"
        );
    }
}

#[test]
fn a_patchs_column_reads_are_its_bilinear_reads_and_gradients_bit_for_bit() {
    use super::warp::{column_reads, gradient, READ_COLUMNS};
    let (w, h) = (23, 31);
    let mut stream = crate::test_rng::XorShift::new(99);
    let img: Vec<f32> = (0..w * h)
        .map(|_| 255.0 * stream.fraction(1 << 16) as f32)
        .collect();
    let mut out = Vec::new();
    // columns at and next to the image's sides, rows whose patch runs off its top
    for (u, row, rows) in [
        (1.0, 20.37, 8),
        (11.0, 30.0, 30),
        ((w - 2) as f64, 12.875, 4),
        (5.0, 6.3, 9),
    ] {
        column_reads(&img, w, h, u, row, rows, &mut out);
        assert_eq!(out.len(), (rows + 2) * READ_COLUMNS);
        let read = |i: usize, k: usize| out[i * READ_COLUMNS + k];
        for i in 1..=rows {
            for du in [-1i64, 0, 1] {
                let k = (2 + du) as usize;
                let (pu, pv) = (u + du as f64, row - i as f64);
                assert_eq!(read(i, k).to_bits(), bilinear(&img, w, h, pu, pv).to_bits());
                let (gu, gv) = gradient(&img, w, h, pu, pv);
                let from_reads = (
                    (read(i, k + 1) - read(i, k - 1)) / 2.0,
                    (read(i - 1, k) - read(i + 1, k)) / 2.0,
                );
                assert_eq!(
                    (from_reads.0.to_bits(), from_reads.1.to_bits()),
                    (gu.to_bits(), gv.to_bits()),
                    "u {pu}, v {pv}"
                );
            }
        }
    }
}

#[test]
fn a_tested_patch_holds_the_current_frames_reads_and_gradients_at_its_pixels() {
    // the production test's own patch, after the second view: its pixels' readings and
    // central differences are the per-pixel reads of the frame it tested (kept last)
    let (cue, _, report) = cue_after_two_views(Pose2::IDENTITY, ParallaxOptions::default());
    assert!(report.vetoes > 0 && !cue.patch.is_empty(), "{report:?}");
    let n = cue.frames.len();
    let tested = &cue.frames[(cue.next + n - 1) % n].image;
    for px in &cue.patch {
        let want = bilinear(tested, W, H, px.pu, px.pv);
        let (gu, gv) = super::warp::gradient(tested, W, H, px.pu, px.pv);
        assert_eq!(
            px.current.to_bits(),
            want.to_bits(),
            "({}, {})",
            px.pu,
            px.pv
        );
        assert_eq!(
            (px.gradient.0.to_bits(), px.gradient.1.to_bits()),
            (gu.to_bits(), gv.to_bits()),
            "({}, {})",
            px.pu,
            px.pv
        );
        assert_eq!(Some(px.ground), cue.table.lookup(px.pu, px.pv));
    }
}
