//! Tests of [`super`] (match_filter.rs): the filter's algebra against the textbook forms it
//! rewrites (the information form inverted directly, the covariance of wheel noise summed by
//! hand, IEEE 754's remainder).

use super::*;

/// The inverse of a square matrix by Gauss-Jordan elimination with partial pivoting.
fn inverse<const N: usize>(a: [[f64; N]; N]) -> [[f64; N]; N] {
    let mut m = a;
    let mut inv = [[0.0; N]; N];
    for (k, row) in inv.iter_mut().enumerate() {
        row[k] = 1.0;
    }
    for c in 0..N {
        let p = (c..N)
            .max_by(|&x, &y| m[x][c].abs().total_cmp(&m[y][c].abs()))
            .unwrap();
        m.swap(c, p);
        inv.swap(c, p);
        let d = m[c][c];
        for k in 0..N {
            m[c][k] /= d;
            inv[c][k] /= d;
        }
        for r in 0..N {
            if r != c {
                let f = m[r][c];
                for k in 0..N {
                    m[r][k] -= f * m[c][k];
                    inv[r][k] -= f * inv[c][k];
                }
            }
        }
    }
    inv
}

fn options(calibrate: bool) -> ScanMatcherOptions {
    ScanMatcherOptions {
        calibrate_odometry: calibrate,
        ..Default::default()
    }
}

/// A random symmetric positive definite 5 x 5 matrix with the filter's scales (a linear
/// congruential generator: no dependency).
fn random_covariance(seed: &mut u64) -> [[f64; 5]; 5] {
    let mut next = || {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let scales = [0.05, 0.05, 0.02, 0.02, 0.01];
    let a: [[f64; 5]; 5] = std::array::from_fn(|r| std::array::from_fn(|_| next() * scales[r]));
    std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            (0..5).map(|k| a[r][k] * a[c][k]).sum::<f64>()
                + if r == c {
                    1e-3 * scales[r] * scales[r]
                } else {
                    0.0
                }
        })
    })
}

#[test]
fn the_remainder_is_ieee_754s() {
    let tau = std::f64::consts::TAU;
    assert_eq!(ieee_remainder(0.25, tau), 0.25);
    assert_eq!(ieee_remainder(-0.25, tau), -0.25);
    assert!((ieee_remainder(tau + 0.5, tau) - 0.5).abs() < 1e-15);
    assert!((ieee_remainder(-3.0 * tau - 0.5, tau) + 0.5).abs() < 1e-14);
    // halfway: to the even multiple (3 pi = 1.5 turns: 2 turns, -pi)
    let r = ieee_remainder(1.5 * tau, tau);
    assert!((r + 0.5 * tau).abs() < 1e-15, "{r}");
    // a quotient that rounds onto a half: still within half a turn
    let x = 2.5 * tau * (1.0 + f64::EPSILON);
    assert!(ieee_remainder(x, tau).abs() <= 0.5 * tau);
    for k in -2000..2000 {
        let x = k as f64 * 0.0137;
        let r = ieee_remainder(x, tau);
        assert!(r.abs() <= 0.5 * tau + 1e-15);
        let n = (x - r) / tau;
        assert!((n - n.round()).abs() < 1e-12, "{x}");
    }
}

#[test]
fn the_fused_covariance_and_pose_are_the_information_forms() {
    // post = (P^-1 + J)^-1 (J in the pose's block); pose = prior + post J z
    let mut seed = 7;
    for k in 0..50 {
        let o = options(true);
        let mut f = MatchFilter::new(&o);
        f.covariance = random_covariance(&mut seed);
        let b = random_covariance(&mut seed);
        let j: [[f64; 3]; 3] =
            std::array::from_fn(|r| std::array::from_fn(|c| b[r][c] * 1e5 * (1.0 + k as f64)));
        let prior = Pose2::new(1.0, -2.0, 0.3);
        let found = MatchResult {
            pose: Pose2::new(1.03, -2.02, 0.31),
            score: 0.8,
            accepted: true,
            points: 90,
        };
        let mut p = f.covariance;
        p[0][0] += 1e-8;
        p[1][1] += 1e-8;
        p[2][2] += 1e-10;
        let got = f.fuse(&o, found, prior, &j);
        let mut info = inverse(p);
        for r in 0..3 {
            for c in 0..3 {
                info[r][c] += j[r][c] / o.match_variance_scale;
            }
        }
        let post = inverse(info);
        let z = [0.03, -0.02, 0.01];
        let jz: [f64; 5] = std::array::from_fn(|r| {
            if r < 3 {
                (0..3)
                    .map(|c| j[r][c] / o.match_variance_scale * z[c])
                    .sum()
            } else {
                0.0
            }
        });
        let step: [f64; 5] = std::array::from_fn(|r| (0..5).map(|c| post[r][c] * jz[c]).sum());
        let scale = post.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for (got, want) in f.covariance.iter().flatten().zip(post.iter().flatten()) {
            assert!((got - want).abs() < 1e-8 * scale, "{k}: {got} {want}");
        }
        assert!(got.accepted);
        assert!((got.pose.x - (1.0 + step[0])).abs() < 1e-9);
        assert!((got.pose.y - (-2.0 + step[1])).abs() < 1e-9);
        assert!((got.pose.yaw - (0.3 + step[2])).abs() < 1e-9);
        assert!((f.calibration[0] - step[3]).abs() < 1e-9);
        assert_eq!(f.last, Some(got.pose));
    }
}

#[test]
fn straight_driving_grows_the_covariance_by_the_wheels_noise() {
    // 1 m straight in ten steps from a known pose: each wheel travels 0.1 m a step, so x's
    // variance grows by (sigma^2 0.1 + sigma^2 0.1) / 4 and yaw's by 2 sigma^2 0.1 / b^2 a
    // step; y's stays 0 (the heading is known at each step only through yaw, whose
    // covariance with y grows as the path's lever arm); the calibration's states neither
    // estimated nor drifting
    let o = ScanMatcherOptions {
        calibration_drift: 0.0,
        ..options(false)
    };
    let mut f = MatchFilter::new(&o);
    for k in 0..=10 {
        let p = f.predict(&o, Pose2::new(0.1 * k as f64, 0.0, 0.0));
        assert_eq!(p, Pose2::new(0.1 * k as f64, 0.0, 0.0));
    }
    let s2 = o.odometry_wheel_sigma * o.odometry_wheel_sigma;
    let b = o.odometry_wheelbase_m;
    assert!((f.covariance[0][0] - 0.5 * s2 * 1.0).abs() < 1e-15);
    assert!(
        (f.covariance[2][2] - 2.0 * s2 * 1.0 / (b * b)).abs() < 1e-12,
        "{:?}",
        f.covariance
    );
    // y's variance: sum over steps of (distance left)^2 x the yaw variance added there
    let want_yy: f64 = (1..=10)
        .map(|k| {
            let rest = 0.1 * (10 - k) as f64;
            rest * rest * 2.0 * s2 * 0.1 / (b * b)
        })
        .sum();
    assert!(
        (f.covariance[1][1] - want_yy).abs() < 1e-9 * want_yy,
        "{} {want_yy}",
        f.covariance[1][1]
    );
    assert_eq!(f.covariance[3], [0.0; 5]);
    assert_eq!(f.covariance[4], [0.0; 5]);
}

#[test]
fn a_match_beyond_the_gate_is_refused_and_one_within_it_kept() {
    let o = ScanMatcherOptions {
        rejection_threshold: Some(3.0),
        calibrate_odometry: false,
        ..Default::default()
    };
    let sigma = 0.01f64;
    let run = |dx: f64| {
        let mut f = MatchFilter::new(&o);
        f.covariance[0][0] = sigma * sigma;
        f.covariance[1][1] = sigma * sigma;
        f.covariance[2][2] = 1e-6;
        let j = [
            [1.0 / (sigma * sigma), 0.0, 0.0],
            [0.0, 1.0 / (sigma * sigma), 0.0],
            [0.0, 0.0, 1e6],
        ];
        let found = MatchResult {
            pose: Pose2::new(dx, 0.0, 0.0),
            score: 0.9,
            accepted: true,
            points: 50,
        };
        let r = f.fuse(&o, found, Pose2::IDENTITY, &j);
        (r, f.last_mahalanobis.unwrap())
    };
    // the innovation's standard deviation: sqrt(sigma^2 (prediction) + sigma^2 (match))
    let s = (2.0f64).sqrt() * sigma;
    let (r, m) = run(10.0 * s);
    assert!(!r.accepted && r.pose == Pose2::IDENTITY);
    assert!((m - 10.0).abs() < 1e-3, "{m}");
    let (r, m) = run(s);
    assert!(r.accepted && (m - 1.0).abs() < 1e-3);
    assert!((r.pose.x - 0.5 * s).abs() < 1e-6); // halfway: equal weights
}
