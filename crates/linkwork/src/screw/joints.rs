//! The joints of a linkwork description seen as screws: where each joint is at a
//! configuration q, its unit relative twist, its value (relative angle or slide since the
//! start) and rate. Bodies are numbered 0 for the ground, then 1 + their index in the
//! description (the model's coordinate order).

use crate::input::description::{Description, JointDesc, GROUND};

use super::projective::Point;
use super::screws::Twist;
use super::ScrewError;

/// A revolute (pin) or prismatic (slide) joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    Revolute,
    Prismatic,
}

impl JointKind {
    /// 'R' or 'P'.
    pub fn letter(self) -> char {
        match self {
            JointKind::Revolute => 'R',
            JointKind::Prismatic => 'P',
        }
    }

    pub fn from_letter(c: char) -> Option<JointKind> {
        match c.to_ascii_uppercase() {
            'R' => Some(JointKind::Revolute),
            'P' => Some(JointKind::Prismatic),
            _ => None,
        }
    }
}

/// One joint of a description, with its local geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct MechanismJoint {
    pub name: String,
    /// None for a weld (no relative motion).
    pub kind: Option<JointKind>,
    /// 0: the ground; i + 1: the description's body i.
    pub body_a: usize,
    pub body_b: usize,
    /// the joint point in a's and in b's frame
    local_a: [f64; 2],
    local_b: [f64; 2],
    /// prismatic: the unit slide direction in a's frame
    axis_a: [f64; 2],
    /// theta_b - theta_a at the start
    theta0: f64,
}

/// The joints of a description and its bodies' starting poses.
#[derive(Debug, Clone, PartialEq)]
pub struct MechanismJoints {
    /// "ground", then the description's bodies
    pub body_names: Vec<String>,
    pub joints: Vec<MechanismJoint>,
    /// the starting pose of every body, ground first
    pub start: Vec<[f64; 3]>,
}

fn rot(theta: f64, v: [f64; 2]) -> [f64; 2] {
    let (s, c) = theta.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

/// The refusal for a joint that is not one relative motion of one screw.
fn unsupported(j: &JointDesc) -> ScrewError {
    let kind = serde_json::to_value(j).ok().and_then(|v| v["type"].as_str().map(str::to_string));
    ScrewError::Mechanism(format!(
        "joint '{}' is a {} joint; screw analysis covers revolute, prismatic and fixed joints",
        j.name(),
        kind.unwrap_or_default()
    ))
}

impl MechanismJoints {
    /// Reads the joints of a description (names resolved, local vectors from the start).
    pub fn from_description(desc: &Description) -> Result<MechanismJoints, ScrewError> {
        let mut body_names = vec![GROUND.to_string()];
        let mut start = vec![[0.0; 3]];
        for b in &desc.bodies {
            body_names.push(b.name.clone());
            start.push([b.x, b.y, b.theta]);
        }
        let index = |joint: &str, body: &str| {
            body_names.iter().position(|n| n == body).ok_or_else(|| {
                ScrewError::Mechanism(format!("joint '{joint}': there is no body named '{body}'"))
            })
        };
        let local = |body: usize, p: [f64; 2]| {
            let [x, y, th] = start[body];
            rot(-th, [p[0] - x, p[1] - y])
        };
        let mut joints = Vec::with_capacity(desc.joints.len());
        for j in &desc.joints {
            let (kind, a, b, at, axis) = match j {
                JointDesc::Revolute { body_a, body_b, at, .. } => {
                    let at = at.ok_or_else(|| {
                        ScrewError::Mechanism(format!(
                            "joint '{}' is given by its pins in the bodies' frames: screw analysis \
                             needs the drawing (Mechanism.assemble gives it)",
                            j.name()
                        ))
                    })?;
                    (Some(JointKind::Revolute), body_a, body_b, at, [1.0, 0.0])
                }
                JointDesc::Prismatic { body_a, body_b, at: Some(at), axis: Some(axis), .. } => {
                    (Some(JointKind::Prismatic), body_a, body_b, *at, *axis)
                }
                JointDesc::Prismatic { .. } => {
                    return Err(ScrewError::Mechanism(format!(
                        "joint '{}' is given by its pins in the bodies' frames: screw analysis \
                         needs the drawing (Mechanism.assemble gives it)",
                        j.name()
                    )))
                }
                JointDesc::Fixed { body_a, body_b, .. } => {
                    let b = index(j.name(), body_b)?;
                    let origin = [start[b][0], start[b][1]];
                    (None, body_a, body_b, origin, [1.0, 0.0])
                }
                JointDesc::Distance { .. }
                | JointDesc::PointOnLine { .. }
                | JointDesc::Gear { .. }
                | JointDesc::RackPinion { .. }
                | JointDesc::Belt { .. }
                | JointDesc::FixedOrientation { .. }
                | JointDesc::Parallel { .. }
                | JointDesc::LinearCoupling { .. } => return Err(unsupported(j)),
                JointDesc::PinInSlot { .. } | JointDesc::CamFollower { .. } => {
                    return Err(ScrewError::Mechanism(format!(
                        "joint '{}': screw analysis covers revolute, prismatic and fixed joints; a pin in \
                         a curved slot or a cam follower has no fixed screw axis",
                        j.name()
                    )));
                }
            };
            let (ia, ib) = (index(j.name(), a)?, index(j.name(), b)?);
            let n = axis[0].hypot(axis[1]);
            if !(n > 0.0 && n.is_finite() && at.iter().all(|v| v.is_finite())) {
                return Err(ScrewError::Mechanism(format!(
                    "joint '{}': position {at:?} or axis {axis:?} is not a finite point and direction",
                    j.name()
                )));
            }
            joints.push(MechanismJoint {
                name: j.name().to_string(),
                kind,
                body_a: ia,
                body_b: ib,
                local_a: local(ia, at),
                local_b: local(ib, at),
                axis_a: rot(-start[ia][2], [axis[0] / n, axis[1] / n]),
                theta0: start[ib][2] - start[ia][2],
            });
        }
        Ok(MechanismJoints { body_names, joints, start })
    }

    /// Bodies, ground included.
    pub fn n_bodies(&self) -> usize {
        self.body_names.len()
    }

    /// Checks that q (and qd) have 3 entries per moving body and are finite.
    pub fn check(&self, what: &str, q: &[f64]) -> Result<(), ScrewError> {
        let n = 3 * (self.n_bodies() - 1);
        if q.len() != n {
            return Err(ScrewError::Input(format!(
                "{what} has {} entries; the mechanism has {n} coordinates",
                q.len()
            )));
        }
        if let Some(i) = q.iter().position(|v| !v.is_finite()) {
            return Err(ScrewError::Input(format!("{what}[{i}] ({}) is not finite", q[i])));
        }
        Ok(())
    }

    pub fn index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// (x, y, theta) of a body (the ground: zeros).
    pub fn pose(&self, q: &[f64], body: usize) -> [f64; 3] {
        if body == 0 {
            return [0.0; 3];
        }
        let k = 3 * (body - 1);
        [q[k], q[k + 1], q[k + 2]]
    }

    /// (xd, yd, thetad) of a body (the ground: zeros).
    pub fn rate(&self, qd: &[f64], body: usize) -> [f64; 3] {
        self.pose(qd, body)
    }

    /// World position of a point with local coordinates u in a body.
    pub fn world(&self, q: &[f64], body: usize, u: [f64; 2]) -> [f64; 2] {
        let [x, y, th] = self.pose(q, body);
        let r = rot(th, u);
        [x + r[0], y + r[1]]
    }

    /// World velocity of a point with local coordinates u in a body.
    pub fn velocity(&self, q: &[f64], qd: &[f64], body: usize, u: [f64; 2]) -> [f64; 2] {
        let th = self.pose(q, body)[2];
        let [xd, yd, w] = self.rate(qd, body);
        let r = rot(th, u);
        [xd - w * r[1], yd + w * r[0]]
    }

    /// The joint's world position at q (for a prismatic joint: its point on a's axis).
    pub fn position(&self, j: usize, q: &[f64]) -> [f64; 2] {
        let jt = &self.joints[j];
        match jt.kind {
            Some(JointKind::Revolute) if jt.body_b != 0 => self.world(q, jt.body_b, jt.local_b),
            _ => self.world(q, jt.body_a, jt.local_a),
        }
    }

    /// A prismatic joint's unit slide direction at q (fixed in body a).
    pub fn axis(&self, j: usize, q: &[f64]) -> [f64; 2] {
        let jt = &self.joints[j];
        rot(self.pose(q, jt.body_a)[2], jt.axis_a)
    }

    /// The twist of b relative to a per unit joint rate ($ of the joint), None for a weld.
    pub fn screw(&self, j: usize, q: &[f64]) -> Option<Twist> {
        match self.joints[j].kind? {
            JointKind::Revolute => Some(Twist::revolute(self.position(j, q))),
            JointKind::Prismatic => {
                let u = self.axis(j, q);
                Some(Twist::new(u[0], u[1], 0.0))
            }
        }
    }

    /// The joint's axis as a homogeneous point: its pivot, or the direction at infinity
    /// across the slide. None for a weld.
    pub fn pole(&self, j: usize, q: &[f64]) -> Option<Point> {
        self.screw(j, q).map(|s| s.pole())
    }

    /// The joint's value at q: theta_b - theta_a minus its starting value (revolute), or
    /// the slide of b on a along the axis since the start (prismatic).
    pub fn value(&self, j: usize, q: &[f64]) -> f64 {
        let jt = &self.joints[j];
        match jt.kind {
            Some(JointKind::Prismatic) => {
                let pa = self.world(q, jt.body_a, jt.local_a);
                let pb = self.world(q, jt.body_b, jt.local_b);
                let u = self.axis(j, q);
                (pb[0] - pa[0]) * u[0] + (pb[1] - pa[1]) * u[1]
            }
            _ => self.pose(q, jt.body_b)[2] - self.pose(q, jt.body_a)[2] - jt.theta0,
        }
    }

    /// The joint's rate at (q, qd): the derivative of `value`.
    pub fn value_rate(&self, j: usize, q: &[f64], qd: &[f64]) -> f64 {
        let jt = &self.joints[j];
        match jt.kind {
            Some(JointKind::Prismatic) => {
                // d/dt (d . u) = d' . u + d . (w_a k x u); the joint keeps d along u
                let pa = self.world(q, jt.body_a, jt.local_a);
                let pb = self.world(q, jt.body_b, jt.local_b);
                let va = self.velocity(q, qd, jt.body_a, jt.local_a);
                let vb = self.velocity(q, qd, jt.body_b, jt.local_b);
                let u = self.axis(j, q);
                let wa = self.rate(qd, jt.body_a)[2];
                let d = [pb[0] - pa[0], pb[1] - pa[1]];
                (vb[0] - va[0]) * u[0] + (vb[1] - va[1]) * u[1] + wa * (d[1] * u[0] - d[0] * u[1])
            }
            _ => self.rate(qd, jt.body_b)[2] - self.rate(qd, jt.body_a)[2],
        }
    }
}
