//! Poses of frames and the transport of twists and wrenches between frames.
//!
//! A twist or wrench "in frame F" has its vectors in F's axes and is referred to F's
//! origin: a twist's (vx, vy) is the velocity of the body point at F's origin, a wrench's
//! m is the moment about F's origin. The reciprocal product is the same in every frame.

use super::projective::Point;
use super::screws::{Twist, Wrench};

/// The pose of a frame in the world: origin (x, y), rotation theta (rad). Also a rigid
/// motion: p -> R(theta) p + (x, y).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub theta: f64,
}

impl Pose {
    pub const IDENTITY: Pose = Pose { x: 0.0, y: 0.0, theta: 0.0 };

    pub fn new(x: f64, y: f64, theta: f64) -> Pose {
        Pose { x, y, theta }
    }

    /// The rotation by `angle` about the point `centre`.
    pub fn rotation_about(centre: [f64; 2], angle: f64) -> Pose {
        let r = Pose::new(0.0, 0.0, angle).rotate(centre);
        Pose::new(centre[0] - r[0], centre[1] - r[1], angle)
    }

    /// The translation by d.
    pub fn translation(d: [f64; 2]) -> Pose {
        Pose::new(d[0], d[1], 0.0)
    }

    /// The vector v turned by theta.
    pub fn rotate(&self, v: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.theta.sin_cos();
        [c * v[0] - s * v[1], s * v[0] + c * v[1]]
    }

    /// The vector v turned by -theta.
    pub fn unrotate(&self, v: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.theta.sin_cos();
        [c * v[0] + s * v[1], -s * v[0] + c * v[1]]
    }

    /// The world position of the point with frame coordinates p.
    pub fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let r = self.rotate(p);
        [r[0] + self.x, r[1] + self.y]
    }

    /// The frame coordinates of the world point p.
    pub fn apply_inverse(&self, p: [f64; 2]) -> [f64; 2] {
        self.unrotate([p[0] - self.x, p[1] - self.y])
    }

    /// The rigid motion applied to a homogeneous point (directions are only turned).
    pub fn apply_point(&self, p: &Point) -> Point {
        let r = self.rotate([p.0[0], p.0[1]]);
        Point([r[0] + self.x * p.0[2], r[1] + self.y * p.0[2], p.0[2]])
    }

    /// self then other: the pose of a frame whose pose in this frame is `other`.
    pub fn compose(&self, other: &Pose) -> Pose {
        let p = self.apply([other.x, other.y]);
        Pose::new(p[0], p[1], self.theta + other.theta)
    }

    pub fn inverse(&self) -> Pose {
        let p = self.unrotate([-self.x, -self.y]);
        Pose::new(p[0], p[1], -self.theta)
    }

    /// A twist given in this frame, expressed in the world:
    /// v_world(0) = R v - w k x (x, y).
    pub fn twist_to_world(&self, t: &Twist) -> Twist {
        let v = self.rotate([t.vx, t.vy]);
        Twist::new(v[0] + t.w * self.y, v[1] - t.w * self.x, t.w)
    }

    /// A world twist expressed in this frame: v = R^T (v_world(0) + w k x (x, y)).
    pub fn twist_to_local(&self, t: &Twist) -> Twist {
        let v = self.unrotate([t.vx - t.w * self.y, t.vy + t.w * self.x]);
        Twist::new(v[0], v[1], t.w)
    }

    /// A wrench given in this frame, expressed in the world: f = R f_local,
    /// m = m_local + (x, y) x f.
    pub fn wrench_to_world(&self, w: &Wrench) -> Wrench {
        let f = self.rotate([w.fx, w.fy]);
        Wrench::new(f[0], f[1], w.m + self.x * f[1] - self.y * f[0])
    }

    /// A world wrench expressed in this frame.
    pub fn wrench_to_local(&self, w: &Wrench) -> Wrench {
        let f = self.unrotate([w.fx, w.fy]);
        Wrench::new(f[0], f[1], w.m - (self.x * w.fy - self.y * w.fx))
    }
}
