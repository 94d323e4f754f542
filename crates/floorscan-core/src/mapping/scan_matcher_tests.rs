//! Tests of [`super`] (scan_matcher.rs): the likelihood field against brute force, the field
//! kept up to date against a fresh one, a room found again, and bad arguments.

use super::*;

fn options() -> ScanMatcherOptions {
    ScanMatcherOptions {
        size_m: 8.0,
        ..Default::default()
    }
}

/// Points [m, robot frame] where rays from `pose` over 270 degrees meet the walls of a
/// 4 x 3 m room with corners (0, 0) and (4, 3) and a 0.4 m box at (2.5, 2.0), within 3 m.
fn room_scan(pose: Pose2, n: usize) -> Vec<[f64; 2]> {
    let segs = [
        ((0.0, 0.0), (4.0, 0.0)),
        ((4.0, 0.0), (4.0, 3.0)),
        ((4.0, 3.0), (0.0, 3.0)),
        ((0.0, 3.0), (0.0, 0.0)),
        ((2.3, 1.8), (2.7, 1.8)),
        ((2.7, 1.8), (2.7, 2.2)),
        ((2.7, 2.2), (2.3, 2.2)),
        ((2.3, 2.2), (2.3, 1.8)),
    ];
    let mut out = Vec::new();
    for k in 0..n {
        let a =
            -0.75 * std::f64::consts::PI + 1.5 * std::f64::consts::PI * k as f64 / (n - 1) as f64;
        let (dx, dy) = ((pose.yaw + a).cos(), (pose.yaw + a).sin());
        let mut best = f64::INFINITY;
        for ((ax, ay), (bx, by)) in segs {
            let (ex, ey) = (bx - ax, by - ay);
            let den = dx * ey - dy * ex;
            if den.abs() < 1e-12 {
                continue;
            }
            let t = ((ax - pose.x) * ey - (ay - pose.y) * ex) / den;
            let s = ((ax - pose.x) * dy - (ay - pose.y) * dx) / den;
            if t > 0.0 && (0.0..=1.0).contains(&s) {
                best = best.min(t);
            }
        }
        if best <= 3.0 {
            out.push([best * a.cos(), best * a.sin()]);
        }
    }
    out
}

#[test]
fn a_fresh_field_is_the_gaussian_of_the_distance_to_the_nearest_hit() {
    let o = options();
    let mut m = ScanMatcher::new(o.clone(), (2.0, 1.5)).unwrap();
    let truth = Pose2::new(1.5, 1.2, 0.3);
    m.insert(&room_scan(truth, 180), truth, false).unwrap();
    let f = m.field_around(1.0, 1.0, 1.2).unwrap();
    let n = m.side();
    let hits: Vec<(i64, i64)> = (0..n * n)
        .filter(|&k| m.hits()[k] > 0)
        .map(|k| ((k % n) as i64, (k / n) as i64))
        .filter(|&(i, j)| {
            i >= f.i0 && j >= f.j0 && i < f.i0 + f.width as i64 && j < f.j0 + f.height as i64
        })
        .collect();
    assert!(hits.len() > 20);
    let cell = o.cell_size_m;
    let mut nonzero = 0;
    for jj in 0..f.height {
        for ii in 0..f.width {
            let (i, j) = (f.i0 + ii as i64, f.j0 + jj as i64);
            let d = hits
                .iter()
                .map(|&(a, b)| ((a - i) as f64).hypot((b - j) as f64) * cell)
                .fold(f64::INFINITY, f64::min);
            let want = if d <= STAMP_SIGMAS * o.sigma_m + 1e-12 {
                (-0.5 * (d / o.sigma_m).powi(2)).exp()
            } else {
                0.0
            };
            let got = f.values[jj * f.width + ii] as f64;
            assert!((got - want).abs() < 1e-6, "({i}, {j}): {got} {want}");
            nonzero += (got > 0.0) as usize;
        }
    }
    assert!(nonzero > 100);
}

#[test]
fn the_kept_field_with_new_hits_stamped_equals_a_fresh_one() {
    let mut m = ScanMatcher::new(options(), (2.0, 1.5)).unwrap();
    let a = Pose2::new(1.5, 1.2, 0.3);
    m.insert(&room_scan(a, 180), a, false).unwrap();
    let half = 3.3;
    m.cover(1.5, 1.2, half).unwrap();
    // a shifted copy: new hits, stamped into the kept field
    m.insert(
        &room_scan(Pose2::new(2.5, 1.0, 2.0), 180),
        Pose2::new(2.6, 1.1, 2.05),
        true,
    )
    .unwrap();
    let fresh = m.field_around(1.5, 1.2, half + CACHE_MARGIN_M).unwrap();
    assert_eq!(m.cached_field().unwrap(), &fresh);
}

#[test]
fn a_room_is_found_again_from_a_perturbed_odometry_pose() {
    let mut m = ScanMatcher::new(options(), (2.0, 1.5)).unwrap();
    let first = Pose2::new(1.5, 1.2, 0.3);
    m.insert(&room_scan(first, 180), first, false).unwrap();
    let later = Pose2::new(1.7, 1.1, 0.45);
    let odometry = Pose2::new(later.x + 0.06, later.y - 0.07, later.yaw + 0.05);
    let r = m.match_scan(&room_scan(later, 180), odometry).unwrap();
    assert!(r.accepted);
    let o = m.options();
    assert!((r.pose.x - later.x).hypot(r.pose.y - later.y) <= 1.5 * o.cell_size_m);
    assert!((r.pose.yaw - later.yaw).abs() <= 1.5 * o.yaw_step_rad);
    // correct: the same, fused with odometry; the scan's new points stored
    let before = m.frames();
    let r = m.correct(&room_scan(later, 180), odometry).unwrap();
    assert!(r.accepted && m.frames() == before + 1);
}

#[test]
fn at_most_max_points_are_matched_evenly_spaced() {
    let o = ScanMatcherOptions {
        max_points: 4,
        min_points: 3,
        ..options()
    };
    let mut m = ScanMatcher::new(o, (0.0, 0.0)).unwrap();
    let pts: Vec<[f64; 2]> = (0..10).map(|k| [0.1 * k as f64, 0.0]).collect();
    m.take_matched(&pts);
    // numpy's linspace(0, 9, 4).round(): 0, 3, 6, 9
    assert_eq!(m.matched, vec![pts[0], pts[3], pts[6], pts[9]]);
    let pts: Vec<[f64; 2]> = (0..8).map(|k| [0.1 * k as f64, 0.0]).collect();
    m.take_matched(&pts);
    // linspace(0, 7, 4) = 0, 2.33, 4.67, 7
    assert_eq!(m.matched, vec![pts[0], pts[2], pts[5], pts[7]]);
    m.take_matched(&[[f64::NAN, 0.0], [50.0, 0.0], [0.5, 0.5]]);
    assert_eq!(m.matched, vec![[0.5, 0.5]]);
}

#[test]
fn bad_arguments_are_errors() {
    assert!(ScanMatcher::new(options(), (f64::NAN, 0.0)).is_err());
    let bad = ScanMatcherOptions {
        cell_size_m: 0.0,
        ..options()
    };
    assert!(ScanMatcher::new(bad, (0.0, 0.0)).is_err());
    let mut m = ScanMatcher::new(options(), (0.0, 0.0)).unwrap();
    let pts = [[1.0, 0.0]; 50];
    assert!(m.correct(&pts, Pose2::new(f64::NAN, 0.0, 0.0)).is_err());
    assert!(m
        .match_scan(&pts, Pose2::new(0.0, f64::INFINITY, 0.0))
        .is_err());
    assert!(m.field_around(f64::NAN, 0.0, 1.0).is_err());
    assert!(m.cover(0.0, 0.0, f64::INFINITY).is_err());
    assert!(m.cached_field().is_none());
    // far off the map: nothing stored, nothing matched, no error
    let far = Pose2::new(1e300, -1e300, 0.0);
    assert_eq!(m.insert(&pts, far, false).unwrap(), 0);
    assert!(!m.correct(&pts, far).unwrap().accepted);
}
