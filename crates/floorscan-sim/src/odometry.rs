//! Wheel odometry with random and systematic errors (paper Fig. 2: maps "bend" with drift).
//!
//! The robot's true wheel travel per control step is (l, r). The odometry measures
//! l' = l (1 + scale - difference / 2) + n_l and r' = r (1 + scale + difference / 2) + n_r,
//! with n ~ N(0, sigma^2 |travel|) per wheel (a random walk: sigma [m / sqrt(m)]), and integrates
//! them with a wheelbase b (1 + wheelbase_error): heading change (r' - l') / b', forward
//! travel (l' + r') / 2, along the mean heading of the step. The truth uses the same formula
//! with the true travel, so zero errors give odometry equal to the truth.

use floorscan_core::pose::normalize_angle;
use floorscan_core::Pose2;
use serde::{Deserialize, Serialize};

use crate::error::{check_range, Result};
use crate::rng::Rng;

/// Odometry error parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OdometryNoise {
    /// Random error of each wheel's travel [m / sqrt(m)], in [0, 1]: after travelling d metres a
    /// wheel's accumulated error has standard deviation sigma sqrt(d). Default 0.01.
    pub wheel_sigma_per_sqrt_m: f64,
    /// Relative error of the wheel radius the odometry assumes (both wheels), in [-0.5, 0.5]:
    /// distances come out scaled by 1 + this. Default 0.01.
    pub radius_scale_error: f64,
    /// Relative difference of the right and left wheel radii, in [-0.5, 0.5]: straight driving
    /// reads as a curve of curvature difference / wheelbase (the map bends). Default 0.004.
    pub radius_difference: f64,
    /// Relative error of the wheelbase the odometry assumes, in [-0.5, 0.5]: turns read as
    /// 1 / (1 + this) of their true angle. Default 0.02.
    pub wheelbase_error: f64,
}

impl Default for OdometryNoise {
    fn default() -> Self {
        Self {
            wheel_sigma_per_sqrt_m: 0.01,
            radius_scale_error: 0.01,
            radius_difference: 0.004,
            wheelbase_error: 0.02,
        }
    }
}

impl OdometryNoise {
    /// No error at all.
    pub fn none() -> Self {
        Self {
            wheel_sigma_per_sqrt_m: 0.0,
            radius_scale_error: 0.0,
            radius_difference: 0.0,
            wheelbase_error: 0.0,
        }
    }

    pub fn validate(&self) -> Result<()> {
        check_range(
            "wheel_sigma_per_sqrt_m",
            self.wheel_sigma_per_sqrt_m,
            0.0,
            1.0,
        )?;
        check_range("radius_scale_error", self.radius_scale_error, -0.5, 0.5)?;
        check_range("radius_difference", self.radius_difference, -0.5, 0.5)?;
        check_range("wheelbase_error", self.wheelbase_error, -0.5, 0.5)
    }
}

/// Advances a pose by wheel travels (left, right) [m] on a wheelbase [m], along a circular arc.
#[inline]
pub fn integrate(pose: Pose2, left_m: f64, right_m: f64, wheelbase_m: f64) -> Pose2 {
    let arc = 0.5 * (left_m + right_m);
    let dyaw = (right_m - left_m) / wheelbase_m;
    // Exact for a constant-velocity step: the chord of the arc, along the mean heading.
    let half = 0.5 * dyaw;
    let d = if half.abs() > 1e-9 {
        arc * half.sin() / half
    } else {
        arc
    };
    let mid = pose.yaw + half;
    Pose2::new(
        pose.x + d * mid.cos(),
        pose.y + d * mid.sin(),
        normalize_angle(pose.yaw + dyaw),
    )
}

/// The odometry of one robot: integrates measured wheel travel.
#[derive(Debug, Clone)]
pub struct Odometry {
    noise: OdometryNoise,
    wheelbase_m: f64,
    rng: Rng,
    /// Current odometry pose (odom frame; starts at the true start pose).
    pub pose: Pose2,
}

impl Odometry {
    pub fn new(noise: OdometryNoise, wheelbase_m: f64, start: Pose2, seed: u64) -> Result<Self> {
        noise.validate()?;
        Ok(Self {
            noise,
            wheelbase_m,
            rng: Rng::new(seed),
            pose: start,
        })
    }

    /// The measured travel of the wheels for a true travel (left, right) [m].
    pub fn measure(&mut self, left_m: f64, right_m: f64) -> (f64, f64) {
        let n = &self.noise;
        let mut l = left_m * (1.0 + n.radius_scale_error - 0.5 * n.radius_difference);
        let mut r = right_m * (1.0 + n.radius_scale_error + 0.5 * n.radius_difference);
        if n.wheel_sigma_per_sqrt_m > 0.0 {
            l += n.wheel_sigma_per_sqrt_m * left_m.abs().sqrt() * self.rng.normal();
            r += n.wheel_sigma_per_sqrt_m * right_m.abs().sqrt() * self.rng.normal();
        }
        (l, r)
    }

    /// Feeds one step of true wheel travel.
    pub fn step(&mut self, left_m: f64, right_m: f64) {
        let (l, r) = self.measure(left_m, right_m);
        self.pose = integrate(
            self.pose,
            l,
            r,
            self.wheelbase_m * (1.0 + self.noise.wheelbase_error),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const B: f64 = 0.3;

    /// Drives `steps` steps of (l, r) and returns (truth, odometry).
    fn drive(noise: OdometryNoise, l: f64, r: f64, steps: usize, seed: u64) -> (Pose2, Pose2) {
        let mut odo = Odometry::new(noise, B, Pose2::IDENTITY, seed).unwrap();
        let mut truth = Pose2::IDENTITY;
        for _ in 0..steps {
            truth = integrate(truth, l, r, B);
            odo.step(l, r);
        }
        (truth, odo.pose)
    }

    #[test]
    fn zero_noise_gives_the_truth_exactly() {
        let (t, o) = drive(OdometryNoise::none(), 0.003, 0.0034, 1000, 1);
        assert_eq!(t, o);
    }

    #[test]
    fn scale_error_stretches_straight_travel() {
        let noise = OdometryNoise {
            radius_scale_error: 0.03,
            ..OdometryNoise::none()
        };
        let (t, o) = drive(noise, 0.01, 0.01, 200, 1);
        assert!((t.x - 2.0).abs() < 1e-9);
        assert!((o.x - 2.0 * 1.03).abs() < 1e-9 && o.y.abs() < 1e-12);
    }

    #[test]
    fn wheelbase_error_scales_turns_in_place() {
        let noise = OdometryNoise {
            wheelbase_error: 0.05,
            ..OdometryNoise::none()
        };
        // Turn in place by 1 rad: wheels travel -+ b/2 in total.
        let (t, o) = drive(noise, -B / 2.0 / 100.0, B / 2.0 / 100.0, 100, 1);
        assert!((t.yaw - 1.0).abs() < 1e-12);
        assert!((o.yaw - 1.0 / 1.05).abs() < 1e-12);
    }

    #[test]
    fn radius_difference_bends_a_straight_line() {
        let noise = OdometryNoise {
            radius_difference: 0.01,
            ..OdometryNoise::none()
        };
        let (_, o) = drive(noise, 0.01, 0.01, 300, 1);
        // Heading drift = distance * difference / wheelbase.
        assert!((o.yaw - 3.0 * 0.01 / B).abs() < 1e-9, "{}", o.yaw);
        assert!(o.y > 0.0);
    }

    #[test]
    fn random_error_statistics_match_sigma() {
        // Drive 1 m straight in 100 steps, 4000 times. Each wheel's accumulated error has
        // variance sigma^2 D, so the travelled distance (l + r) / 2 has sigma^2 D / 2 and the
        // heading 2 sigma^2 D / b^2; both are unbiased.
        let sigma = 0.02;
        let noise = OdometryNoise {
            wheel_sigma_per_sqrt_m: sigma,
            ..OdometryNoise::none()
        };
        let n = 4000;
        let (mut dist, mut yaw) = (Vec::new(), Vec::new());
        for seed in 0..n {
            let mut odo = Odometry::new(noise, B, Pose2::IDENTITY, seed as u64).unwrap();
            let mut travelled = 0.0;
            for _ in 0..100 {
                let (l, r) = odo.measure(0.01, 0.01);
                travelled += 0.5 * (l + r);
            }
            dist.push(travelled - 1.0);
            let (_, o) = drive(noise, 0.01, 0.01, 100, seed as u64);
            yaw.push(o.yaw);
        }
        let stats = |v: &[f64]| {
            let m = v.iter().sum::<f64>() / v.len() as f64;
            (
                m,
                v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (v.len() - 1) as f64,
            )
        };
        let ((m_d, var_d), (m_y, var_y)) = (stats(&dist), stats(&yaw));
        let (exp_d, exp_y) = (sigma * sigma / 2.0, 2.0 * sigma * sigma / (B * B));
        // Relative standard error of a variance from 4000 samples: about 2.2 %.
        assert!(
            (var_d / exp_d - 1.0).abs() < 0.1,
            "distance variance {var_d} vs {exp_d}"
        );
        assert!(
            (var_y / exp_y - 1.0).abs() < 0.1,
            "yaw variance {var_y} vs {exp_y}"
        );
        // Means within 4 standard errors of zero.
        assert!(
            m_d.abs() < 4.0 * (exp_d / n as f64).sqrt(),
            "distance biased: {m_d}"
        );
        assert!(
            m_y.abs() < 4.0 * (exp_y / n as f64).sqrt(),
            "heading biased: {m_y}"
        );
    }

    #[test]
    fn invalid_noise_is_rejected() {
        let bad = OdometryNoise {
            radius_scale_error: 0.9,
            ..OdometryNoise::none()
        };
        assert!(Odometry::new(bad, B, Pose2::IDENTITY, 0).is_err());
    }
}
