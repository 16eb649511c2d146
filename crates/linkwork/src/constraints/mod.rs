//! The joint library. A joint (or driver) is a set of rows of Phi(q, t) = 0 between at
//! most two bodies. It never sees global indices: it gets the frames of its two sides
//! (the ground is the identity frame) and writes its residual, its Jacobian blocks
//! (n_rows x 3 per side), nu and gamma. `assembly` alone maps blocks into Phi_q.
//!
//! Adding a joint type: one file, one line in `constraint_list!` `kinds`.

pub mod compile_context;
pub mod drivers;
pub mod joints;
pub mod kinds;
pub mod loads;

pub use kinds::{roles, samples, ConstraintKind};

use crate::input::motion::MotionLaw;
use crate::math::jet::{Jet, JetFrame};

/// The most rows one joint or driver writes.
pub const MAX_ROWS: usize = 3;

/// The unit of a row: length rows are scaled by 1/L in the solver, angle rows are not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    Length,
    Angle,
}

/// One side of a joint: a body's pose and velocity, with cos and sin of its angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// world position of the body frame origin, R
    pub r: [f64; 2],
    pub theta: f64,
    pub c: f64,
    pub s: f64,
    /// dR/dt
    pub rd: [f64; 2],
    /// dtheta/dt
    pub thetad: f64,
}

impl Frame {
    /// The ground: identity, at rest.
    pub const GROUND: Frame =
        Frame { r: [0.0, 0.0], theta: 0.0, c: 1.0, s: 0.0, rd: [0.0, 0.0], thetad: 0.0 };

    /// A frame at pose (x, y, theta) with velocity (xd, yd, thetad).
    pub fn new(q: [f64; 3], qd: [f64; 3]) -> Frame {
        let (s, c) = q[2].sin_cos();
        Frame { r: [q[0], q[1]], theta: q[2], c, s, rd: [qd[0], qd[1]], thetad: qd[2] }
    }

    /// A(theta) u: a body-fixed vector in world axes.
    #[inline(always)]
    pub fn rot(&self, u: [f64; 2]) -> [f64; 2] {
        [self.c * u[0] - self.s * u[1], self.s * u[0] + self.c * u[1]]
    }

    /// B(theta) u = dA/dtheta u = A u turned by +90 degrees.
    #[inline(always)]
    pub fn rot_d(&self, u: [f64; 2]) -> [f64; 2] {
        [-self.s * u[0] - self.c * u[1], self.c * u[0] - self.s * u[1]]
    }

    /// World position of the body point u: R + A u.
    #[inline(always)]
    pub fn point(&self, u: [f64; 2]) -> [f64; 2] {
        let p = self.rot(u);
        [self.r[0] + p[0], self.r[1] + p[1]]
    }

    /// World velocity of the body point u: Rd + B u thetad.
    #[inline(always)]
    pub fn point_velocity(&self, u: [f64; 2]) -> [f64; 2] {
        let p = self.rot_d(u);
        [self.rd[0] + p[0] * self.thetad, self.rd[1] + p[1] * self.thetad]
    }

    /// The part of a body point's acceleration that does not involve qdd: -A u thetad^2.
    #[inline(always)]
    pub fn point_centripetal(&self, u: [f64; 2]) -> [f64; 2] {
        let p = self.rot(u);
        let w2 = self.thetad * self.thetad;
        [-p[0] * w2, -p[1] * w2]
    }
}

/// The value s and rate sd of a joint's extra coordinate: its own (a curve parameter:
/// where on its curve a follower is) or one it borrows (the angle of a gear pair's
/// carrier). Joints without one (`has_extra() == false`) get zeros and ignore it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Extra {
    pub s: f64,
    pub sd: f64,
}

/// The rows one joint writes at a configuration: phi (n_rows) and the Jacobian blocks
/// d phi / d q_a and d phi / d q_b (n_rows x 3 each; ignored for a ground side), and
/// d phi / d s for a joint with an extra coordinate.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Rows {
    pub phi: [f64; MAX_ROWS],
    pub jac_a: [[f64; 3]; MAX_ROWS],
    pub jac_b: [[f64; 3]; MAX_ROWS],
    pub jac_s: [f64; MAX_ROWS],
}

/// What every joint and driver provides.
pub trait Constraint {
    /// Number of rows (at most MAX_ROWS).
    fn n_rows(&self) -> usize;
    /// The unit of each row.
    fn row_kinds(&self) -> &'static [RowKind];
    /// Coordinates the joint adds to q (0 or 1): a parameter along a curve, which the
    /// joint's rows tie to the bodies. They are dimensionless (angle-like).
    fn n_own(&self) -> usize {
        0
    }
    /// Whether the rows involve an extra coordinate: the joint's own, or one borrowed from
    /// another body (a carrier's angle), whose column the model gives it.
    fn has_extra(&self) -> bool {
        self.n_own() > 0
    }
    /// The own coordinate that fits the bodies' poses best (its starting value: e.g. the
    /// curve parameter nearest the follower in the described configuration).
    fn own_start(&self, _a: &Frame, _b: &Frame) -> f64 {
        0.0
    }
    /// phi and its Jacobian blocks at the frames' poses (and extra coordinate), time t.
    fn position(&self, a: &Frame, b: &Frame, x: &Extra, t: f64, out: &mut Rows);
    /// nu = -phi_t (zero for time-independent joints).
    fn nu(&self, _t: f64, _nu: &mut [f64; MAX_ROWS]) {}
    /// gamma = -(phi_q qd)_q qd - 2 phi_qt qd - phi_tt at the frames' poses and velocities.
    fn gamma(&self, a: &Frame, b: &Frame, x: &Extra, t: f64, gamma: &mut [f64; MAX_ROWS]);
    /// The motion law of a driver.
    fn law(&self) -> Option<&MotionLaw> {
        None
    }
    /// The point of body b (body frame) about which its reaction torque is reported.
    fn anchor_b(&self) -> [f64; 2] {
        [0.0, 0.0]
    }
    /// The joint's own numbers, the design parameters it has, named ("u_a.x", "length";
    /// a driver's law's after its own, "law.rate"), in the order `phi_jet` reads them.
    fn params_mut(&mut self) -> Vec<(String, &mut f64)>;
    /// phi on jets (`sensitivity::jet`): the sides' perturbed motions, the extra coordinate
    /// `s`, the parameters `p` (in the order of `params_mut`) at time t. The same rows as
    /// `position`, written once more over jets, from which Phi_p, Phi_q, nu, gamma and the
    /// sensitivities' time derivatives all follow exactly.
    fn phi_jet<const W: usize>(
        &self,
        a: &JetFrame<W>,
        b: &JetFrame<W>,
        s: Jet<W>,
        t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    );
}

/// A point or vector parameter, its two coordinates named "<name>.x" and "<name>.y".
pub(crate) fn xy<'a>(name: &str, v: &'a mut [f64; 2]) -> [(String, &'a mut f64); 2] {
    let [x, y] = v;
    [(format!("{name}.x"), x), (format!("{name}.y"), y)]
}

/// Gives one valid, non-trivial instance of a type, for tests over every joint.
pub trait Sample {
    fn sample() -> Self;
}

/// What a field of a joint's or driver's description is: the tools that read
/// descriptions (drawing, design parameters, the builder's assembly) learn from these
/// which fields are points, directions or curves and of which body, instead of keeping
/// tables of their own. A body is named by the field that names it ("body_a").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// the element's name
    Name,
    /// names a body (or the ground)
    Body,
    /// names a joint
    Joint,
    /// a world point at the start, fixed in each of the bodies these fields name
    Point(&'static [&'static str]),
    /// a point in the named body's own frame
    LocalPoint(&'static str),
    /// a world direction at the start, fixed in the named body
    Direction(&'static str),
    /// the direction of a slide: the guide's line, a world direction at the start fixed
    /// in the named body, along which the other body moves
    Slide(&'static str),
    /// a direction in the named body's own frame
    LocalDirection(&'static str),
    /// a curve, in world coordinates at the start, fixed in the named body
    Curve(&'static str),
    /// the pitch radius of a wheel (gear, pulley, pinion) fixed in the named body
    Pitch(&'static str),
    /// the coefficients of the named body's coordinates
    Coefficients(&'static str),
    Length,
    /// a range of lengths [min, max]
    Interval,
    Angle,
    /// a speed ratio
    Ratio,
    /// a number of mixed units (a linear coupling's value)
    Number,
    Flag,
    /// one of these words
    Choice(&'static [&'static str]),
    /// a driver's motion law, and what it sets
    Law(Input),
}

/// What a driver's law sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// a body's angle
    Angle,
    /// body_b's angle less body_a's
    RelativeAngle,
    /// the distance between two points
    Distance,
    /// a point's x or y
    Coordinate,
    /// a prismatic joint's slide
    Slide,
}

impl Role {
    /// The role's name in the table Python reads.
    pub fn name(&self) -> &'static str {
        match self {
            Role::Name => "name",
            Role::Body => "body",
            Role::Joint => "joint",
            Role::Point(_) => "point",
            Role::LocalPoint(_) => "local_point",
            Role::Direction(_) => "direction",
            Role::Slide(_) => "slide",
            Role::LocalDirection(_) => "local_direction",
            Role::Curve(_) => "curve",
            Role::Pitch(_) => "pitch",
            Role::Coefficients(_) => "coefficients",
            Role::Length => "length",
            Role::Interval => "interval",
            Role::Angle => "angle",
            Role::Ratio => "ratio",
            Role::Number => "number",
            Role::Flag => "flag",
            Role::Choice(_) => "choice",
            Role::Law(_) => "law",
        }
    }

    /// The unit of the value, "length" or "angle" (a law's: of what it sets), or None.
    pub fn unit(&self) -> Option<&'static str> {
        match self {
            Role::Point(_) | Role::LocalPoint(_) | Role::Pitch(_) | Role::Length | Role::Interval => {
                Some("length")
            }
            Role::Angle => Some("angle"),
            Role::Law(i) => Some(if i.is_angle() { "angle" } else { "length" }),
            _ => None,
        }
    }

    /// The fields naming the bodies the value is fixed in (none for a plain number).
    pub fn bodies(&self) -> Vec<&'static str> {
        match *self {
            Role::Point(b) => b.to_vec(),
            Role::LocalPoint(b)
            | Role::Direction(b)
            | Role::Slide(b)
            | Role::LocalDirection(b)
            | Role::Curve(b)
            | Role::Pitch(b)
            | Role::Coefficients(b) => vec![b],
            _ => Vec::new(),
        }
    }
}

impl Input {
    /// Whether the law sets an angle (rad) rather than a length.
    pub fn is_angle(&self) -> bool {
        matches!(self, Input::Angle | Input::RelativeAngle)
    }

    pub fn name(&self) -> &'static str {
        match self {
            Input::Angle => "angle",
            Input::RelativeAngle => "relative_angle",
            Input::Distance => "distance",
            Input::Coordinate => "coordinate",
            Input::Slide => "slide",
        }
    }
}

/// One description form a joint or driver type compiles from: its list ("joints" or
/// "drivers"), its `type` and each of its fields with its role, in the description's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Form {
    pub group: &'static str,
    pub type_: &'static str,
    pub fields: &'static [(&'static str, Role)],
}

/// The description forms a joint or driver type compiles from (most have one; a cam
/// follower's form compiles to one of three types, a point on a curve to two forms).
pub trait Described {
    const FORMS: &'static [Form];
}

#[inline(always)]
pub(crate) fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// a x b, the z of the planar cross product (= perp(a) . b).
#[inline(always)]
pub(crate) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[inline(always)]
pub(crate) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// The vector turned by +90 degrees.
#[inline(always)]
pub(crate) fn perp(a: [f64; 2]) -> [f64; 2] {
    [-a[1], a[0]]
}
