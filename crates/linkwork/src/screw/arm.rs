//! Serial planar arms of revolute and prismatic joints, analysed with screws.
//!
//! An arm is described in its home configuration (all joint values zero): every joint's
//! home axis (a pivot, or a slide direction through a point) and the home pose of the end
//! frame M. Forward kinematics is the product of exponentials g(q) = e^{$1 q1} ... e^{$n qn} M:
//! joint i turns (or slides) everything after it about its axis, which joints 1..i-1 have
//! carried along. At a configuration, joint i's axis screw $_i gives the screw Jacobian
//! J = [$_1 ... $_n], and every question below is answered geometrically:
//! - forward velocity T = J w; its pole is the barycentre of the joint axes with weights w_i;
//! - inverse velocity w_i = S_jk . T / S_jk . $_i, S_jk the line through the other two
//!   joints, or the barycentre construction (the pole split along the joint triangle);
//! - inverse force tau = J^T W: tau_i is the force times the perpendicular distance p_i;
//! - forward force: the force line passes through the torque centres of joint pairs,
//!   X_jk = tau_k P_j - tau_j P_k on the line through joints j and k.

use crate::input::description::Description;

use super::frames::Pose;
use super::joints::{JointKind, MechanismJoints};
use super::projective::{cross, dot, norm, unit3, Gauge, Line, Point};
use super::screws::{Twist, Wrench};
use super::system::ScrewSystem;
use super::{ScrewError, DEGENERATE};

/// Twists closer than this (relative) to what the unknown joints can produce count as
/// reachable; torques within this of balanced count as balanced.
const REACH: f64 = 1e-9;

/// One joint of an arm in the home configuration: a pivot at `at`, or a slide along the
/// unit direction `axis` through `at`.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmJoint {
    pub name: String,
    pub kind: JointKind,
    pub at: [f64; 2],
    /// unit slide direction (prismatic); (1, 0) for a revolute joint
    pub axis: [f64; 2],
}

impl ArmJoint {
    pub fn revolute(name: impl Into<String>, at: [f64; 2]) -> ArmJoint {
        ArmJoint { name: name.into(), kind: JointKind::Revolute, at, axis: [1.0, 0.0] }
    }

    /// A slide along `axis` (normalised) through `at`.
    pub fn prismatic(name: impl Into<String>, at: [f64; 2], axis: [f64; 2]) -> Result<ArmJoint, ScrewError> {
        let name = name.into();
        let n = axis[0].hypot(axis[1]);
        if !(n > 0.0 && n.is_finite()) {
            return Err(ScrewError::Input(format!(
                "joint {name}: slide direction ({}, {}) must be finite and non-zero",
                axis[0], axis[1]
            )));
        }
        Ok(ArmJoint { name, kind: JointKind::Prismatic, at, axis: [axis[0] / n, axis[1] / n] })
    }
}

/// How an arm read from a description maps onto the model's coordinates.
#[derive(Debug, Clone, PartialEq)]
struct Chain {
    mech: MechanismJoints,
    /// (joint index in the description, +1 if its body_a is the inner body, else -1)
    joints: Vec<(usize, f64)>,
    /// the end body (0 ground, i + 1 description body i) and the end point in its frame
    end_body: usize,
    end_local: [f64; 2],
}

/// A serial planar arm.
#[derive(Debug, Clone, PartialEq)]
pub struct SerialArm {
    joints: Vec<ArmJoint>,
    end: Pose,
    gauge: Gauge,
    chain: Option<Chain>,
}

fn finite2(p: [f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

fn check_len(what: &str, v: &[f64], n: usize) -> Result<(), ScrewError> {
    if v.len() != n {
        return Err(ScrewError::Input(format!("{what} has {} entries; the arm has {n} joints", v.len())));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(ScrewError::Input(format!("{what}[{i}] ({}) is not finite", v[i])));
    }
    Ok(())
}

impl SerialArm {
    /// An arm from its joints in the home configuration and the home pose of its end frame
    /// (the end point is the end frame's origin).
    pub fn new(joints: Vec<ArmJoint>, end: Pose) -> Result<SerialArm, ScrewError> {
        if joints.is_empty() {
            return Err(ScrewError::Input("an arm needs at least one joint".into()));
        }
        let mut points = Vec::with_capacity(joints.len() + 1);
        for (i, j) in joints.iter().enumerate() {
            if j.name.is_empty() {
                return Err(ScrewError::Input(format!("joint {} has an empty name", i + 1)));
            }
            if joints[..i].iter().any(|k| k.name == j.name) {
                return Err(ScrewError::Input(format!("two joints are named {}", j.name)));
            }
            if !finite2(j.at) || !finite2(j.axis) || (j.axis[0].hypot(j.axis[1]) - 1.0).abs() > 1e-12 {
                return Err(ScrewError::Input(format!(
                    "joint {}: position {:?} must be finite and axis {:?} a unit vector",
                    j.name, j.at, j.axis
                )));
            }
            points.push(j.at);
        }
        if !(end.x.is_finite() && end.y.is_finite() && end.theta.is_finite()) {
            return Err(ScrewError::Input(format!("end pose {end:?} is not finite")));
        }
        points.push([end.x, end.y]);
        Ok(SerialArm { joints, end, gauge: Gauge::around(&points), chain: None })
    }

    /// A planar arm of revolute joints from its link lengths: joint 1 at the origin, each
    /// link along x in the home configuration, so joint values are the relative angles
    /// (0: straight) and the end point is at the tip of the last link.
    pub fn from_lengths(lengths: &[f64]) -> Result<SerialArm, ScrewError> {
        SerialArm::from_links(&vec![JointKind::Revolute; lengths.len()], lengths)
    }

    /// An arm whose joint i sits at the start of link i (length `lengths[i]`, along x in the
    /// home configuration); a prismatic joint slides along its link, lengthening it.
    /// Joints are named "1", "2", ...
    pub fn from_links(kinds: &[JointKind], lengths: &[f64]) -> Result<SerialArm, ScrewError> {
        if kinds.len() != lengths.len() {
            return Err(ScrewError::Input(format!(
                "{} joint kinds for {} link lengths",
                kinds.len(),
                lengths.len()
            )));
        }
        let mut x = 0.0;
        let mut joints = Vec::with_capacity(kinds.len());
        for (i, (&kind, &l)) in kinds.iter().zip(lengths).enumerate() {
            if !(l.is_finite() && l >= 0.0) {
                return Err(ScrewError::Input(format!(
                    "link {} has length {l}; give a finite length >= 0",
                    i + 1
                )));
            }
            let name = (i + 1).to_string();
            joints.push(match kind {
                JointKind::Revolute => ArmJoint::revolute(name, [x, 0.0]),
                JointKind::Prismatic => ArmJoint::prismatic(name, [x, 0.0], [1.0, 0.0])?,
            });
            x += l;
        }
        SerialArm::new(joints, Pose::new(x, 0.0, 0.0))
    }

    /// The serial chain ground - body - body - ... of a linkwork description, joined by
    /// revolute and prismatic joints (drivers are ignored). The home configuration is the
    /// description's starting configuration; a joint's value is the outer body's angle
    /// relative to the inner one (revolute) or its slide along the axis (prismatic), both
    /// measured from the start. The end point is the named point `end_point` of the last
    /// body, or the last body's frame origin; the end frame turns with the last body.
    pub fn from_description(desc: &Description, end_point: Option<&str>) -> Result<SerialArm, ScrewError> {
        let mech = MechanismJoints::from_description(desc)?;
        if let Some(w) = mech.joints.iter().find(|j| j.kind.is_none()) {
            return Err(ScrewError::Mechanism(format!(
                "joint '{}' is a weld: a serial arm's joints are revolute or prismatic",
                w.name
            )));
        }
        let name_of = |b: usize| {
            if b == 0 {
                "the ground".to_string()
            } else {
                format!("body '{}'", mech.body_names[b])
            }
        };
        let mut visited = vec![false; mech.n_bodies()];
        let mut chain = Vec::new();
        let (mut body, mut came_by) = (0usize, usize::MAX);
        visited[0] = true;
        loop {
            let next: Vec<usize> = (0..mech.joints.len())
                .filter(|&j| j != came_by && (mech.joints[j].body_a == body || mech.joints[j].body_b == body))
                .collect();
            match next.as_slice() {
                [] => break,
                [j] => {
                    let jt = &mech.joints[*j];
                    let (sign, other) = if jt.body_a == body { (1.0, jt.body_b) } else { (-1.0, jt.body_a) };
                    if visited[other] {
                        return Err(ScrewError::Mechanism(format!(
                            "joint '{}' closes a loop: a serial arm is an open chain",
                            jt.name
                        )));
                    }
                    visited[other] = true;
                    chain.push((*j, sign));
                    body = other;
                    came_by = *j;
                }
                many => {
                    let names: Vec<String> =
                        many.iter().map(|&j| format!("'{}'", mech.joints[j].name)).collect();
                    return Err(ScrewError::Mechanism(format!(
                        "{} has joints {} after the chain reaches it: a serial arm joins each body to the next \
                         by one joint",
                        name_of(body),
                        names.join(", ")
                    )));
                }
            }
        }
        if chain.is_empty() {
            return Err(ScrewError::Mechanism("no joint to the ground: there is no arm".into()));
        }
        if let Some(b) = visited.iter().position(|v| !v) {
            return Err(ScrewError::Mechanism(format!("{} is not on the chain from the ground", name_of(b))));
        }
        let q0: Vec<f64> = mech.start[1..].iter().flatten().copied().collect();
        let end_body = body;
        let [bx, by, bth] = mech.start[end_body];
        let end_world = match end_point {
            None => [bx, by],
            Some(name) => {
                let p = desc.points.iter().find(|p| p.name == name).ok_or_else(|| {
                    ScrewError::Mechanism(format!("there is no point named '{name}' for the end point"))
                })?;
                if p.body != mech.body_names[end_body] {
                    return Err(ScrewError::Mechanism(format!(
                        "point '{name}' is on body '{}', not on the last body of the chain, '{}'",
                        p.body, mech.body_names[end_body]
                    )));
                }
                p.at
            }
        };
        let end_local = Pose::new(bx, by, bth).apply_inverse(end_world);
        let mut joints = Vec::with_capacity(chain.len());
        for &(j, _) in &chain {
            let jt = &mech.joints[j];
            let at = mech.position(j, &q0);
            joints.push(match jt.kind {
                Some(JointKind::Prismatic) => ArmJoint::prismatic(jt.name.clone(), at, mech.axis(j, &q0))?,
                _ => ArmJoint::revolute(jt.name.clone(), at),
            });
        }
        let mut arm = SerialArm::new(joints, Pose::new(end_world[0], end_world[1], bth))?;
        arm.chain = Some(Chain { mech, joints: chain, end_body, end_local });
        Ok(arm)
    }

    pub fn joints(&self) -> &[ArmJoint] {
        &self.joints
    }

    pub fn n_joints(&self) -> usize {
        self.joints.len()
    }

    /// The home pose of the end frame.
    pub fn end_home(&self) -> Pose {
        self.end
    }

    /// The length scale and centre used for the degeneracy tests.
    pub fn gauge(&self) -> Gauge {
        self.gauge
    }

    /// For an arm read from a description: the end body's index in the description.
    pub fn end_body(&self) -> Option<usize> {
        self.chain.as_ref().map(|c| c.end_body - 1)
    }

    /// For an arm read from a description: the joint values and rates (q, w) of the arm
    /// at the model's coordinates q and velocities qd.
    pub fn joint_values(
        &self,
        q_model: &[f64],
        qd_model: &[f64],
    ) -> Result<(Vec<f64>, Vec<f64>), ScrewError> {
        let c = self.chain.as_ref().ok_or_else(|| {
            ScrewError::Input("this arm was not read from a mechanism: it has no model coordinates".into())
        })?;
        c.mech.check("q", q_model)?;
        c.mech.check("qd", qd_model)?;
        Ok(c.joints
            .iter()
            .map(|&(j, s)| (s * c.mech.value(j, q_model), s * c.mech.value_rate(j, q_model, qd_model)))
            .unzip())
    }

    /// For an arm read from a description: the end frame's pose and twist computed from the
    /// model's own coordinates and velocities (not from the arm).
    pub fn model_end(&self, q_model: &[f64], qd_model: &[f64]) -> Result<(Pose, Twist), ScrewError> {
        let c = self.chain.as_ref().ok_or_else(|| {
            ScrewError::Input("this arm was not read from a mechanism: it has no model coordinates".into())
        })?;
        c.mech.check("q", q_model)?;
        c.mech.check("qd", qd_model)?;
        let pose = c.mech.pose(q_model, c.end_body);
        let p = c.mech.world(q_model, c.end_body, c.end_local);
        let twist = Twist::of_body(pose, c.mech.rate(qd_model, c.end_body));
        Ok((Pose::new(p[0], p[1], pose[2]), twist))
    }

    /// Forward kinematics at joint values q: every joint's current axis and the end pose.
    pub fn forward(&self, q: &[f64]) -> Result<ArmState, ScrewError> {
        check_len("q", q, self.joints.len())?;
        let n = self.joints.len();
        let mut st = ArmState {
            names: self.joints.iter().map(|j| j.name.clone()).collect(),
            kinds: self.joints.iter().map(|j| j.kind).collect(),
            q: q.to_vec(),
            points: Vec::with_capacity(n),
            positions: Vec::with_capacity(n),
            axes: Vec::with_capacity(n),
            end: Pose::IDENTITY,
            gauge: self.gauge,
        };
        // g: the rigid motion of everything after the joints handled so far
        let mut g = Pose::IDENTITY;
        for (j, &qi) in self.joints.iter().zip(q) {
            let at = g.apply(j.at);
            let u = g.rotate(j.axis);
            st.positions.push(at);
            st.axes.push(u);
            match j.kind {
                JointKind::Revolute => {
                    st.points.push(Point::finite(at));
                    g = g.compose(&Pose::rotation_about(j.at, qi));
                }
                JointKind::Prismatic => {
                    st.points.push(Point::at_infinity([-u[1], u[0]]));
                    g = g.compose(&Pose::translation([j.axis[0] * qi, j.axis[1] * qi]));
                }
            }
        }
        st.end = g.compose(&self.end);
        Ok(st)
    }
}

/// An arm at one configuration: its joint axes, screw Jacobian and end pose.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmState {
    pub names: Vec<String>,
    pub kinds: Vec<JointKind>,
    /// joint values (n)
    pub q: Vec<f64>,
    /// joint axes as homogeneous points (n): (x, y, 1) for a pivot, (-uy, ux, 0) for a
    /// slide along u; the pole of $_i
    pub points: Vec<Point>,
    /// joint positions (n): the pivot, or the slide's reference point
    pub positions: Vec<[f64; 2]>,
    /// current slide directions (n; for a revolute joint, its carried x direction)
    pub axes: Vec<[f64; 2]>,
    /// the end frame's pose; its origin is the end point
    pub end: Pose,
    pub gauge: Gauge,
}

/// A point for every pair of joints (j < k).
pub type PairPoints = Vec<((usize, usize), Point)>;

/// The result of the barycentre construction for an inverse velocity.
#[derive(Debug, Clone, PartialEq)]
pub struct Barycentre {
    /// the joint rates (n), given ones included
    pub rates: Vec<f64>,
    /// the pole of the twist left to the unknown joints
    pub pole: Point,
    /// with three unknown joints: the vertex a whose line through the pole is drawn, and
    /// the foot D where that line crosses the opposite side (the line through the other
    /// two joints). The pole divides a-D, and D divides the side, in the ratios of the rates.
    pub vertex: Option<usize>,
    pub foot: Option<Point>,
}

/// x = beta b + gamma c, for x on the line through b and c (homogeneous 3-vectors).
fn decompose(x: [f64; 3], b: [f64; 3], c: [f64; 3]) -> (f64, f64) {
    let n = cross(b, c);
    let nn = dot(n, n);
    (dot(cross(x, c), n) / nn, dot(cross(b, x), n) / nn)
}

impl ArmState {
    pub fn n_joints(&self) -> usize {
        self.names.len()
    }

    /// The end point (the end frame's origin).
    pub fn end_point(&self) -> [f64; 2] {
        [self.end.x, self.end.y]
    }

    /// The joint screws $_i (unit rate), the columns of J.
    pub fn screws(&self) -> Vec<Twist> {
        self.points.iter().map(|p| p.twist()).collect()
    }

    /// The screw Jacobian J = [$_1 ... $_n] (3 x n), row-major.
    pub fn jacobian(&self) -> Vec<f64> {
        let s = self.screws();
        let mut j = vec![0.0; 3 * s.len()];
        for (c, t) in s.iter().enumerate() {
            for (r, v) in t.to_array().into_iter().enumerate() {
                j[r * s.len() + c] = v;
            }
        }
        j
    }

    /// The screw system of the joint axes.
    pub fn system(&self) -> ScrewSystem {
        ScrewSystem::new(self.names.clone(), self.screws(), self.gauge)
    }

    /// Minimal sets of joints whose screws are dependent (coincident pivots, parallel
    /// slides, three collinear axes): where the arm loses a direction of motion.
    pub fn dependencies(&self) -> Vec<Vec<usize>> {
        self.system().dependencies()
    }

    fn dependent(&self, set: &[usize]) -> ScrewError {
        self.system().error(set)
    }

    /// Forward velocity T = J w.
    pub fn twist(&self, w: &[f64]) -> Result<Twist, ScrewError> {
        check_len("w", w, self.n_joints())?;
        Ok(self.screws().iter().zip(w).fold(Twist::ZERO, |t, (s, &wi)| t + *s * wi))
    }

    /// The velocity pole as the barycentre of the joint axes with weights w_i:
    /// sum w_i P_i, a homogeneous point of weight sum w_i (the end link's angular rate);
    /// at infinity when the rates of the pivots cancel (a pure translation).
    pub fn pole(&self, w: &[f64]) -> Result<Point, ScrewError> {
        check_len("w", w, self.n_joints())?;
        let mut p = [0.0; 3];
        for (pt, &wi) in self.points.iter().zip(w) {
            for (acc, v) in p.iter_mut().zip(pt.0) {
                *acc += wi * v;
            }
        }
        Ok(Point(p))
    }

    /// The velocity of the end point for joint rates w.
    pub fn end_velocity(&self, w: &[f64]) -> Result<[f64; 2], ScrewError> {
        Ok(self.twist(w)?.velocity_at(self.end_point()))
    }

    /// The velocity centre of every pair of joints (j < k): the pole of the motion of
    /// joints j and k alone at rates w_j, w_k, the barycentre w_j P_j + w_k P_k.
    pub fn velocity_centres(&self, w: &[f64]) -> Result<PairPoints, ScrewError> {
        check_len("w", w, self.n_joints())?;
        Ok(self.pairs(|j, k| {
            let (a, b) = (self.points[j].0, self.points[k].0);
            Point([0, 1, 2].map(|i| w[j] * a[i] + w[k] * b[i]))
        }))
    }

    fn pairs(&self, f: impl Fn(usize, usize) -> Point) -> PairPoints {
        let n = self.n_joints();
        let mut out = Vec::with_capacity(n * n.saturating_sub(1) / 2);
        for j in 0..n {
            for k in j + 1..n {
                out.push(((j, k), f(j, k)));
            }
        }
        out
    }

    /// Splits a twist into the part left to the unknown joints: returns the unknown joints,
    /// T - sum_given w_k $_k, and a magnitude to judge "zero" against.
    fn unknowns(&self, t: &Twist, given: &[(usize, f64)]) -> Result<(Vec<usize>, Twist, f64), ScrewError> {
        let n = self.n_joints();
        let mut is_given = vec![false; n];
        let mut rest = *t;
        if !t.to_array().iter().all(|v| v.is_finite()) {
            return Err(ScrewError::Input(format!("twist {:?} is not finite", t.to_array())));
        }
        let mut size = norm(self.gauge.map(&t.pole()));
        for &(k, wk) in given {
            if k >= n || is_given[k] {
                return Err(ScrewError::Input(format!(
                    "given rate for joint index {k}: the arm has joints 0..{} and each may be given once",
                    n - 1
                )));
            }
            if !wk.is_finite() {
                return Err(ScrewError::Input(format!("the given rate of joint {} is {wk}", self.names[k])));
            }
            is_given[k] = true;
            let s = self.points[k].twist();
            rest = rest - s * wk;
            size += wk.abs() * norm(self.gauge.map(&self.points[k]));
        }
        let unknown: Vec<usize> = (0..n).filter(|&i| !is_given[i]).collect();
        if unknown.len() > 3 {
            return Err(ScrewError::Redundant { unknown: unknown.len() });
        }
        // dependent unknown axes cannot be told apart
        let sys = ScrewSystem::new(
            unknown.iter().map(|&i| self.names[i].clone()).collect(),
            unknown.iter().map(|&i| self.points[i].twist()).collect(),
            self.gauge,
        );
        if let Some(set) = sys.dependencies().first() {
            let set: Vec<usize> = set.iter().map(|&i| unknown[i]).collect();
            return Err(self.dependent(&set));
        }
        Ok((unknown, rest, size))
    }

    /// With fewer than three unknown joints: the twist must be one they can produce.
    fn check_reachable(&self, unknown: &[usize], rest: &Twist, size: f64) -> Result<bool, ScrewError> {
        let p = self.gauge.map(&rest.pole());
        if norm(p) <= REACH * size {
            return Ok(false); // nothing left to produce: the unknown rates are zero
        }
        let names = unknown.iter().map(|&i| self.names[i].clone()).collect();
        let pole = rest.pole();
        let (ok, why) = match unknown {
            [] => (false, "the given rates already produce a different twist"),
            [i] => (self.near_same(&pole, &self.points[*i]), "its pole is not at the joint's axis"),
            [i, j] => (
                self.gauge.collinearity(&pole, &self.points[*i], &self.points[*j]) <= REACH,
                "its pole is not on the line through their axes",
            ),
            _ => (true, ""),
        };
        if !ok {
            return Err(ScrewError::Unreachable { joints: names, why: why.into() });
        }
        Ok(true)
    }

    fn near_same(&self, p: &Point, q: &Point) -> bool {
        norm(cross(self.gauge.point(p), self.gauge.point(q))) <= REACH
    }

    /// A unit line screw (unit force; a unit couple for the line at infinity).
    fn unit_line(&self, l: &Line) -> Wrench {
        let g = self.gauge.line(l);
        let w = l.wrench();
        let f = w.fx.hypot(w.fy);
        if g[0].hypot(g[1]) <= DEGENERATE {
            Wrench::couple(w.m.signum())
        } else {
            w * (1.0 / f)
        }
    }

    /// The line screws of the line-screw formula for three unknown joints: for each
    /// unknown i, the unit line screw through the axes of the other two (reciprocal to
    /// both). Errors name coincident pivots, parallel slides or collinear axes.
    pub fn line_screws(&self, unknown: [usize; 3]) -> Result<[Wrench; 3], ScrewError> {
        let n = self.n_joints();
        if unknown.iter().any(|&i| i >= n)
            || unknown[0] == unknown[1]
            || unknown[1] == unknown[2]
            || unknown[0] == unknown[2]
        {
            return Err(ScrewError::Input(format!(
                "joints {unknown:?}: give three different indices below {n}"
            )));
        }
        let mut out = [Wrench::ZERO; 3];
        for (slot, i) in unknown.iter().enumerate() {
            let (j, k) = (unknown[(slot + 1) % 3], unknown[(slot + 2) % 3]);
            let l = self
                .gauge
                .join(&self.points[j], &self.points[k])
                .map_err(|_| self.dependent(&sorted(&[j, k])))?;
            let s = self.unit_line(&l);
            if dot(self.gauge.line(&s.line()), self.gauge.point(&self.points[*i])).abs() <= DEGENERATE {
                return Err(self.dependent(&sorted(&[*i, j, k])));
            }
            out[slot] = s;
        }
        Ok(out)
    }

    /// Inverse velocity by the line-screw formula w_i = S . T / S . $_i: the rates of the
    /// joints not in `given` (joint index, rate) that produce the twist t. At most three
    /// rates are unknown; with three, S is the line through the other two unknown joints;
    /// with two, a line through the other one (t must then have its pole on the line
    /// through their axes); with one, t must be a multiple of its screw.
    pub fn inverse_velocity(&self, t: &Twist, given: &[(usize, f64)]) -> Result<Vec<f64>, ScrewError> {
        let (unknown, rest, size) = self.unknowns(t, given)?;
        let mut w = self.given_rates(given);
        match unknown.as_slice() {
            [a, b, c] => {
                let s = self.line_screws([*a, *b, *c])?;
                for (slot, &i) in [*a, *b, *c].iter().enumerate() {
                    w[i] = s[slot].power(&rest) / s[slot].power(&self.points[i].twist());
                }
            }
            u => {
                if self.check_reachable(u, &rest, size)? {
                    for (slot, &i) in u.iter().enumerate() {
                        // a line through the other unknown axis (if any), not through this one
                        let s = match u.get(1 - slot.min(1)).filter(|_| u.len() == 2) {
                            Some(&j) => self.line_through(&self.points[j], &self.points[i]),
                            None => self.line_avoiding(&self.points[i]),
                        };
                        w[i] = s.power(&rest) / s.power(&self.points[i].twist());
                    }
                }
            }
        }
        Ok(w)
    }

    fn given_rates(&self, given: &[(usize, f64)]) -> Vec<f64> {
        let mut w = vec![0.0; self.n_joints()];
        for &(k, wk) in given {
            w[k] = wk;
        }
        w
    }

    /// Of the lines through p and the gauge's x direction, y direction or centre, the
    /// one that passes farthest from `avoid` (as a unit line screw).
    fn line_through(&self, p: &Point, avoid: &Point) -> Wrench {
        let c = self.gauge.centre;
        let candidates = [Point([1.0, 0.0, 0.0]), Point([0.0, 1.0, 0.0]), Point([c[0], c[1], 1.0])];
        let mut best = (Line::default(), -1.0);
        for e in &candidates {
            let l = Line(cross(p.0, e.0));
            let score = dot(unit3(self.gauge.line(&l)), self.gauge.point(avoid)).abs();
            if norm(l.0) > 0.0 && score > best.1 {
                best = (l, score);
            }
        }
        self.unit_line(&best.0)
    }

    /// A line that does not pass through p: the gauge's best of the lines through the
    /// centre, along x, and the line at infinity.
    fn line_avoiding(&self, p: &Point) -> Wrench {
        let c = self.gauge.centre;
        let candidates = [Line([1.0, 0.0, -c[0]]), Line([0.0, 1.0, -c[1]]), Line([0.0, 0.0, 1.0])];
        let mut best = (candidates[0], -1.0);
        for l in candidates {
            let score = dot(self.gauge.line(&l), self.gauge.point(p)).abs();
            if score > best.1 {
                best = (l, score);
            }
        }
        self.unit_line(&best.0)
    }

    /// Inverse velocity by the barycentre construction: the pole of the twist left to the
    /// unknown joints is split into weights on their axes. With three unknowns (a, b, c),
    /// the line from a through the pole meets the side bc at the foot D; D splits into
    /// b and c, the pole into a and D, each in the inverse ratio of the distances.
    pub fn inverse_velocity_barycentre(
        &self,
        t: &Twist,
        given: &[(usize, f64)],
    ) -> Result<Barycentre, ScrewError> {
        let (unknown, rest, size) = self.unknowns(t, given)?;
        let mut out =
            Barycentre { rates: self.given_rates(given), pole: rest.pole(), vertex: None, foot: None };
        let p = self.gauge.map(&rest.pole());
        let v: Vec<[f64; 3]> = unknown.iter().map(|&i| self.gauge.map(&self.points[i])).collect();
        match unknown.as_slice() {
            [_, _, _] => {
                if norm(p) <= REACH * size {
                    return Ok(out);
                }
                // the vertex seen from the pole most clearly: its line to the pole is well defined
                let spread = |m: usize| norm(cross(unit3(v[m]), unit3(p)));
                let a = (0..3).max_by(|&x, &y| spread(x).total_cmp(&spread(y))).unwrap_or(0);
                let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                let d = cross(cross(v[a], p), cross(v[b], v[c]));
                let (beta, gamma) = decompose(d, v[b], v[c]);
                let (alpha, delta) = decompose(p, v[a], d);
                out.rates[unknown[a]] = alpha;
                out.rates[unknown[b]] = delta * beta;
                out.rates[unknown[c]] = delta * gamma;
                out.vertex = Some(unknown[a]);
                // back from gauge coordinates to world coordinates
                let g = self.gauge;
                out.foot = Some(Point([
                    d[0] * g.scale + g.centre[0] * d[2],
                    d[1] * g.scale + g.centre[1] * d[2],
                    d[2],
                ]));
            }
            u => {
                if self.check_reachable(u, &rest, size)? {
                    match u {
                        [i, j] => {
                            let (bi, bj) = decompose(p, v[0], v[1]);
                            out.rates[*i] = bi;
                            out.rates[*j] = bj;
                        }
                        [i] => out.rates[*i] = dot(p, v[0]) / dot(v[0], v[0]),
                        _ => {}
                    }
                }
            }
        }
        Ok(out)
    }

    /// Inverse force tau = J^T W: tau_i = W . $_i, the moment of W about pivot i (the
    /// force component along slide i).
    pub fn torques(&self, wrench: &Wrench) -> Vec<f64> {
        self.points.iter().map(|p| wrench.power(&p.twist())).collect()
    }

    /// tau_i / |f|: for a pivot, the signed perpendicular distance p_i from the pivot to
    /// the force line (tau_i = |f| p_i); for a slide, the cosine between force and slide.
    /// A pure couple has no line of action: an error.
    pub fn lever_arms(&self, wrench: &Wrench) -> Result<Vec<f64>, ScrewError> {
        let f = wrench.fx.hypot(wrench.fy);
        let g = self.gauge.line(&wrench.line());
        if f == 0.0 || g[0].hypot(g[1]) <= DEGENERATE {
            return Err(ScrewError::Input(
                "the wrench is a pure couple: it has no line of action, so no lever arms".into(),
            ));
        }
        Ok(self.torques(wrench).iter().map(|t| t / f).collect())
    }

    /// The torque centre of every pair of joints (j < k) for joint torques tau:
    /// X_jk = tau_k P_j - tau_j P_k, the point on the line through their axes about which
    /// the end wrench has no moment. It is also the velocity centre of joints j and k at
    /// rates (tau_k, -tau_j): the one motion of the pair that does no work.
    pub fn torque_centres(&self, tau: &[f64]) -> Result<PairPoints, ScrewError> {
        check_len("tau", tau, self.n_joints())?;
        Ok(self.pairs(|j, k| {
            let (a, b) = (self.points[j].0, self.points[k].0);
            Point([0, 1, 2].map(|i| tau[k] * a[i] - tau[j] * b[i]))
        }))
    }

    /// Forward force: the end wrench W with J^T W = tau, found as the line through the
    /// torque centres. With three or more joints the torques fix W (more than three must
    /// agree); a two-joint arm needs the point `through` the force passes (default: the
    /// end point).
    pub fn force(&self, tau: &[f64], through: Option<[f64; 2]>) -> Result<Wrench, ScrewError> {
        check_len("tau", tau, self.n_joints())?;
        let n = self.n_joints();
        let tmax = tau.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        let line = match n {
            1 => {
                return Err(ScrewError::Input(
                    "one joint torque fixes only the force's moment about the joint, not the force".into(),
                ))
            }
            2 => {
                let e = Point::finite(through.unwrap_or(self.end_point()));
                if !finite2([e.0[0], e.0[1]]) {
                    return Err(ScrewError::Input(format!("through {:?} is not finite", [e.0[0], e.0[1]])));
                }
                if let Some(set) = self.dependencies().first() {
                    return Err(self.dependent(set));
                }
                if self.gauge.collinearity(&self.points[0], &self.points[1], &e) <= DEGENERATE {
                    return Err(ScrewError::Dependent {
                        joints: self.names.clone(),
                        detail:
                            "are in line with the point the force passes through: a force along that line \
                                 needs no torque"
                                .into(),
                    });
                }
                if tmax == 0.0 {
                    return Ok(Wrench::ZERO);
                }
                let x = self.torque_centres(tau)?[0].1;
                self.gauge.join(&x, &e).map_err(|_| ScrewError::Unbalanced {
                    why: "the torque centre is the point the force passes through".into(),
                })?
            }
            _ => {
                if through.is_some() {
                    return Err(ScrewError::Input(
                        "`through` is for two-joint arms: three or more torques fix the force line".into(),
                    ));
                }
                // the best-conditioned triangle of axes
                let mut best = (0.0, [0usize; 3]);
                for i in 0..n {
                    for j in i + 1..n {
                        for k in j + 1..n {
                            let c =
                                self.gauge.collinearity(&self.points[i], &self.points[j], &self.points[k]);
                            if c > best.0 {
                                best = (c, [i, j, k]);
                            }
                        }
                    }
                }
                if best.0 <= DEGENERATE {
                    return Err(ScrewError::Dependent {
                        joints: self.names.clone(),
                        detail: "have dependent axes (all pivots collinear or coincident, or only slides): a force \
                                 along their common line needs no torque, so the torques cannot fix the force"
                            .into(),
                    });
                }
                let [i, j, k] = best.1;
                if tau[i] == 0.0 && tau[j] == 0.0 && tau[k] == 0.0 {
                    Line::default()
                } else {
                    let centre = |a: usize, b: usize| {
                        let (pa, pb) = (self.points[a].0, self.points[b].0);
                        Point([0, 1, 2].map(|m| tau[b] * pa[m] - tau[a] * pb[m]))
                    };
                    let x = [centre(i, j), centre(j, k), centre(i, k)];
                    let mut pick = (Line::default(), -1.0);
                    for (a, b) in [(0, 1), (1, 2), (0, 2)] {
                        let l = Line(cross(x[a].0, x[b].0));
                        let score = norm(cross(self.gauge.point(&x[a]), self.gauge.point(&x[b])));
                        if score > pick.1 {
                            pick = (l, score);
                        }
                    }
                    pick.0
                }
            }
        };
        // scale the line so that its moments about the axes are the torques (least squares
        // over the joints that fixed it; exact when they agree)
        let fixed: Vec<usize> = if n == 2 { vec![0, 1] } else { (0..n).collect() };
        let (mut num, mut den) = (0.0, 0.0);
        for &i in &fixed {
            let m = line.dot(&self.points[i]);
            num += m * tau[i];
            den += m * m;
        }
        let wrench = if den > 0.0 { line.scaled(num / den).wrench() } else { Wrench::ZERO };
        for (i, t) in self.torques(&wrench).iter().enumerate() {
            if (t - tau[i]).abs() > REACH * tmax.max(f64::MIN_POSITIVE) {
                return Err(ScrewError::Unbalanced {
                    why: format!(
                        "the torque centres put the force on a line whose moment about joint {} is {t:.6e}, not \
                         {:.6e}; a redundant arm's torques must agree",
                        self.names[i], tau[i]
                    ),
                });
            }
        }
        Ok(wrench)
    }
}

fn sorted(v: &[usize]) -> Vec<usize> {
    let mut v = v.to_vec();
    v.sort_unstable();
    v
}
