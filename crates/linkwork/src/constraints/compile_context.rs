//! What a joint or driver asks while it compiles from its description: its bodies by
//! name, their drawn poses, its pins checked against the drawing, the model's size. The
//! compiler answers (`compile/`); each joint's and driver's file holds its own `compile`.

use crate::input::description::{DriverDesc, JointDesc};
use crate::input::motion::MotionLaw;

/// A joint or driver compiled from its description: the constraint and its two sides.
#[derive(Debug, Clone)]
pub(crate) struct Compiled<T> {
    pub joint: T,
    pub a: Option<usize>,
    pub b: Option<usize>,
    /// a coordinate of another body the rows involve (a gear pair's carrier angle)
    pub borrowed: Option<usize>,
}

impl<T> Compiled<T> {
    /// Between bodies a and b, borrowing nothing.
    pub fn new(joint: T, a: Option<usize>, b: Option<usize>) -> Self {
        Compiled { joint, a, b, borrowed: None }
    }

    /// The same sides around `f(joint)` (the kind list wraps each type in its variant).
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> Compiled<U> {
        Compiled { joint: f(self.joint), a: self.a, b: self.b, borrowed: self.borrowed }
    }
}

/// A prismatic joint's slide, as a translation driver that rides on it reads it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Slide {
    pub u_a: [f64; 2],
    pub u_b: [f64; 2],
    pub e_a: [f64; 2],
}

/// A description of a joint, or of a driver with its law (prepared).
pub(crate) enum Desc<'a> {
    Joint(&'a JointDesc),
    Driver(&'a DriverDesc, &'a MotionLaw),
}

/// A joint or driver type compiled from the descriptions that are its own: every type in
/// the kind list implements it, and the list sends each description to the type it names.
pub(crate) trait FromDescription: Sized {
    /// None where `desc` is another type's; else the type with its sides, or what is
    /// wrong with the description.
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>>;
    /// A prismatic joint's slide, for the translation drivers that ride on it.
    fn slide(&self) -> Option<Slide> {
        None
    }
}

/// The questions a joint or driver asks while it compiles. Bodies are `None` for the
/// ground, `Some(i)` for body i.
pub(crate) trait CompileContext {
    /// The body named `name`, or an error naming it.
    fn find(&self, name: &str) -> Result<Option<usize>, String>;
    /// A body's drawn pose (None: the ground).
    fn pose(&self, body: Option<usize>) -> Option<[f64; 3]>;
    /// The model's size L.
    fn length_scale(&self) -> f64;
    /// The pin `key` of `joint` in `body`'s frame: the one given (`pin`), the drawn world
    /// point `at` placed in the body, or, where both are there and disagree, the one the
    /// description's `close` keeps (the miss recorded). `normal`, for a slide, the world
    /// normal of its line (a pin need only be on the line). One of `pin` and `at` is given.
    fn pin(
        &mut self,
        joint: &str,
        body: Option<usize>,
        key: &'static str,
        pin: Option<[f64; 2]>,
        at: Option<[f64; 2]>,
        normal: Option<[f64; 2]>,
    ) -> [f64; 2];
    /// The slide of the prismatic joint named `joint`, compiled before, with its sides.
    fn slide(&self, joint: &str) -> Option<Compiled<Slide>>;

    /// The two sides of a joint by name: two different bodies.
    fn pair(&self, a: &str, b: &str) -> Result<(Option<usize>, Option<usize>), String> {
        let (ia, ib) = (self.find(a)?, self.find(b)?);
        if ia == ib {
            return Err(format!("connects '{a}' to itself; its two sides must be different bodies"));
        }
        Ok((ia, ib))
    }
    /// A body's drawn angle (the ground's: 0).
    fn theta(&self, body: Option<usize>) -> f64 {
        self.pose(body).map_or(0.0, |p| p[2])
    }
    /// A body's origin at the start (the ground's: (0, 0)).
    fn origin(&self, body: Option<usize>) -> [f64; 2] {
        self.pose(body).map_or([0.0, 0.0], |p| [p[0], p[1]])
    }
    /// A world point in a body's drawn frame.
    fn local(&self, body: Option<usize>, p: [f64; 2]) -> [f64; 2] {
        local(self.pose(body), p)
    }
    /// A world direction in a body's drawn frame (turned only).
    fn local_dir(&self, body: Option<usize>, e: [f64; 2]) -> [f64; 2] {
        local(Some([0.0, 0.0, self.theta(body)]), e)
    }
}

pub(crate) fn finite2(p: [f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

/// A world point in the frame of pose `q0` (None: the ground's, the world).
pub(crate) fn local(q0: Option<[f64; 3]>, p: [f64; 2]) -> [f64; 2] {
    match q0 {
        None => p,
        Some([x, y, th]) => {
            let (s, c) = th.sin_cos();
            let d = [p[0] - x, p[1] - y];
            [c * d[0] + s * d[1], -s * d[0] + c * d[1]]
        }
    }
}

/// A body-frame point in world coordinates (pose None: the ground's, the world).
pub(crate) fn world(pose: Option<[f64; 3]>, u: [f64; 2]) -> [f64; 2] {
    match pose {
        None => u,
        Some([x, y, th]) => {
            let (s, c) = th.sin_cos();
            [x + c * u[0] - s * u[1], y + s * u[0] + c * u[1]]
        }
    }
}

/// A given value (finite and > 0, else an error naming `what`), or the default.
pub(crate) fn positive_or(what: &str, given: Option<f64>, default: f64) -> Result<f64, String> {
    match given {
        None => Ok(default),
        Some(v) if v.is_finite() && v > 0.0 => Ok(v),
        Some(v) => Err(format!("{what} {v} must be finite and > 0")),
    }
}

/// The unit vector along a finite, non-zero direction `what`.
pub(crate) fn unit(what: &str, v: [f64; 2]) -> Result<[f64; 2], String> {
    let norm = v[0].hypot(v[1]);
    if !finite2(v) || norm == 0.0 {
        return Err(format!("{what} {v:?} must be a finite, non-zero direction"));
    }
    Ok([v[0] / norm, v[1] / norm])
}
