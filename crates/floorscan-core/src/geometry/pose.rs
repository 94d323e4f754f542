//! Planar rigid transforms (SE(2)) in REP 103 convention: x forward, y left, yaw counter-clockwise
//! in radians. Name transforms by the frames they connect: `world_from_robot` maps robot
//! coordinates into world coordinates.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// A 2-D point or vector [m].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Point2 {
    pub x: f64,
    pub y: f64,
}

impl Point2 {
    pub const fn new(x: f64, y: f64) -> Self {
        Self { x, y }
    }
    /// Euclidean norm [m].
    pub fn norm(self) -> f64 {
        self.x.hypot(self.y)
    }
    /// Bearing of the point seen from the origin [rad], `atan2(y, x)`.
    pub fn bearing(self) -> f64 {
        self.y.atan2(self.x)
    }
}

/// A planar pose: translation [m] and yaw [rad]. As a transform `a_from_b`, it maps points
/// expressed in frame b into frame a.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Pose2 {
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
}

impl Pose2 {
    pub const IDENTITY: Pose2 = Pose2 {
        x: 0.0,
        y: 0.0,
        yaw: 0.0,
    };

    pub const fn new(x: f64, y: f64, yaw: f64) -> Self {
        Self { x, y, yaw }
    }

    /// A pose whose components are all finite, or [`Error::InvalidGeometry`].
    pub fn checked(x: f64, y: f64, yaw: f64) -> Result<Self> {
        if x.is_finite() && y.is_finite() && yaw.is_finite() {
            Ok(Self { x, y, yaw })
        } else {
            Err(Error::InvalidGeometry(format!(
                "pose must be finite, got x={x}, y={y}, yaw={yaw}"
            )))
        }
    }

    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.yaw.is_finite()
    }

    /// Maps a point from frame b into frame a (`self` is `a_from_b`).
    pub fn transform_point(&self, p: Point2) -> Point2 {
        let (s, c) = self.yaw.sin_cos();
        Point2::new(self.x + c * p.x - s * p.y, self.y + s * p.x + c * p.y)
    }

    /// `a_from_c = a_from_b * b_from_c`.
    pub fn compose(&self, b_from_c: &Pose2) -> Pose2 {
        let t = self.transform_point(Point2::new(b_from_c.x, b_from_c.y));
        Pose2::new(t.x, t.y, normalize_angle(self.yaw + b_from_c.yaw))
    }

    /// `b_from_a` from `a_from_b`.
    pub fn inverse(&self) -> Pose2 {
        let (s, c) = self.yaw.sin_cos();
        Pose2::new(
            -c * self.x - s * self.y,
            s * self.x - c * self.y,
            normalize_angle(-self.yaw),
        )
    }

    /// The motion from `self` to `other`, expressed in `self`'s frame: `self.inverse() * other`.
    pub fn between(&self, other: &Pose2) -> Pose2 {
        self.inverse().compose(other)
    }

    pub fn translation(&self) -> Point2 {
        Point2::new(self.x, self.y)
    }
}

/// Wraps an angle into (-pi, pi].
pub fn normalize_angle(a: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut r = a.rem_euclid(two_pi);
    if r > std::f64::consts::PI {
        r -= two_pi;
    }
    r
}

#[cfg(test)]
#[path = "pose_tests.rs"]
mod tests;
