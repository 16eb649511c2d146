//! Planar twists and wrenches in Plücker form, and their reciprocal product.

use std::ops::{Add, Mul, Neg, Sub};

use super::projective::{Line, Point};
use super::ScrewError;

/// A planar twist (vx, vy; w): the velocity of the body point at the world origin and the
/// angular rate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Twist {
    pub vx: f64,
    pub vy: f64,
    pub w: f64,
}

/// A planar wrench (fx, fy; m): a force and its moment about the world origin.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Wrench {
    pub fx: f64,
    pub fy: f64,
    pub m: f64,
}

fn unit(v: [f64; 2], what: &str) -> Result<[f64; 2], ScrewError> {
    let n = v[0].hypot(v[1]);
    if !(n > 0.0 && n.is_finite()) {
        return Err(ScrewError::Input(format!(
            "{what} ({}, {}) must be a finite, non-zero direction",
            v[0], v[1]
        )));
    }
    Ok([v[0] / n, v[1] / n])
}

impl Twist {
    pub const ZERO: Twist = Twist { vx: 0.0, vy: 0.0, w: 0.0 };

    pub fn new(vx: f64, vy: f64, w: f64) -> Twist {
        Twist { vx, vy, w }
    }

    /// The axis screw of a revolute joint at `at`, unit rate: (y, -x; 1).
    pub fn revolute(at: [f64; 2]) -> Twist {
        Twist::new(at[1], -at[0], 1.0)
    }

    /// The screw of a prismatic joint sliding along `direction` (normalised), unit rate:
    /// (ux, uy; 0), an axis at infinity.
    pub fn prismatic(direction: [f64; 2]) -> Result<Twist, ScrewError> {
        let u = unit(direction, "the slide direction")?;
        Ok(Twist::new(u[0], u[1], 0.0))
    }

    /// The twist of a body at pose (x, y, theta) moving at (xd, yd, thetad):
    /// (xd + thetad y, yd - thetad x; thetad).
    pub fn of_body(pose: [f64; 3], rate: [f64; 3]) -> Twist {
        Twist::new(rate[0] + rate[2] * pose[1], rate[1] - rate[2] * pose[0], rate[2])
    }

    /// The velocity of the body point at `p`: (vx - w p_y, vy + w p_x).
    pub fn velocity_at(&self, p: [f64; 2]) -> [f64; 2] {
        [self.vx - self.w * p[1], self.vy + self.w * p[0]]
    }

    /// The pole (the point whose velocity is zero) as the homogeneous point
    /// (-vy, vx, w), weighted by the rate; at infinity for a pure translation.
    pub fn pole(&self) -> Point {
        Point([-self.vy, self.vx, self.w])
    }

    pub fn to_array(self) -> [f64; 3] {
        [self.vx, self.vy, self.w]
    }

    pub fn from_array(a: [f64; 3]) -> Twist {
        Twist::new(a[0], a[1], a[2])
    }
}

impl Wrench {
    pub const ZERO: Wrench = Wrench { fx: 0.0, fy: 0.0, m: 0.0 };

    pub fn new(fx: f64, fy: f64, m: f64) -> Wrench {
        Wrench { fx, fy, m }
    }

    /// The line screw of a unit force at angle `angle` (rad) through `through`:
    /// (cos t, sin t; x sin t - y cos t).
    pub fn line_screw(angle: f64, through: [f64; 2]) -> Wrench {
        let (s, c) = angle.sin_cos();
        Wrench::new(c, s, through[0] * s - through[1] * c)
    }

    /// The force `force` acting at the point `at`: (fx, fy; x fy - y fx).
    pub fn force_at(force: [f64; 2], at: [f64; 2]) -> Wrench {
        Wrench::new(force[0], force[1], at[0] * force[1] - at[1] * force[0])
    }

    /// A pure couple m: the line screw of the line at infinity.
    pub fn couple(m: f64) -> Wrench {
        Wrench::new(0.0, 0.0, m)
    }

    /// The moment about the point `p`: m - (p_x fy - p_y fx).
    pub fn moment_about(&self, p: [f64; 2]) -> f64 {
        self.m - (p[0] * self.fy - p[1] * self.fx)
    }

    /// The line of action (-fy, fx, m): its value at a point is the moment about it; the
    /// line at infinity for a pure couple.
    pub fn line(&self) -> Line {
        Line([-self.fy, self.fx, self.m])
    }

    /// The reciprocal product W . T = fx vx + fy vy + m w (virtual power).
    pub fn power(&self, t: &Twist) -> f64 {
        self.fx * t.vx + self.fy * t.vy + self.m * t.w
    }

    pub fn to_array(self) -> [f64; 3] {
        [self.fx, self.fy, self.m]
    }

    pub fn from_array(a: [f64; 3]) -> Wrench {
        Wrench::new(a[0], a[1], a[2])
    }
}

macro_rules! linear_ops {
    ($t:ident, $a:ident, $b:ident, $c:ident) => {
        impl Add for $t {
            type Output = $t;
            fn add(self, o: $t) -> $t {
                $t::new(self.$a + o.$a, self.$b + o.$b, self.$c + o.$c)
            }
        }
        impl Sub for $t {
            type Output = $t;
            fn sub(self, o: $t) -> $t {
                $t::new(self.$a - o.$a, self.$b - o.$b, self.$c - o.$c)
            }
        }
        impl Neg for $t {
            type Output = $t;
            fn neg(self) -> $t {
                $t::new(-self.$a, -self.$b, -self.$c)
            }
        }
        impl Mul<f64> for $t {
            type Output = $t;
            fn mul(self, s: f64) -> $t {
                $t::new(self.$a * s, self.$b * s, self.$c * s)
            }
        }
    };
}
linear_ops!(Twist, vx, vy, w);
linear_ops!(Wrench, fx, fy, m);

// A point is the pole of a twist and a line the action line of a wrench; the maps live
// here so that points and lines (projective) know nothing of screws.
impl Point {
    /// The twist whose pole this is (rate W about (X/W, Y/W)): (Y, -X; W).
    pub fn twist(&self) -> Twist {
        Twist::new(self.0[1], -self.0[0], self.0[2])
    }
}

impl Line {
    /// The wrench whose line of action this is: (fx, fy; m) = (b, -a; c).
    pub fn wrench(&self) -> Wrench {
        Wrench::new(self.0[1], -self.0[0], self.0[2])
    }
}
