//! Applied loads: forces and torques following motion laws of time, linear and torsional
//! spring-dampers, and loads at a joint (a torque at a revolute, a force along a
//! prismatic's axis) that are functions of a joint's coordinate or rate (the joint's own,
//! or another's: a gas force of the crank angle): force laws, motors, friction. Each writes its generalized force into Q (n_coords):
//! a force F at the body point u adds (F, (B u) . F) to the body's (x, y, theta) entries.
//! Each is written once more over jets (`*_jet`), from which the sensitivities of the
//! driver efforts take the generalized forces' derivatives exactly.

use crate::constraints::{dot, perp, sub, Frame};
use crate::input::motion::MotionLaw;
use crate::math::jet::{self, pair, Jet, JetFrame, Vec2};

/// One compiled load.
#[derive(Debug, Clone, PartialEq)]
pub enum Load {
    /// magnitude f(t) along the unit world direction `dir`, at the point u of body b
    Force { u: [f64; 2], dir: [f64; 2], law: MotionLaw },
    /// torque f(t) on body b
    Torque { law: MotionLaw },
    /// tension k (L - free_length) + c dL/dt between u_a on a and u_b on b
    Spring { u_a: [f64; 2], u_b: [f64; 2], stiffness: f64, free_length: f64, damping: f64 },
    /// resisting torque k (theta_b - theta_a - free_angle) + c (w_b - w_a) on b
    TorsionSpring { stiffness: f64, free_angle: f64, damping: f64 },
    /// f = law(scale x) (`rate`: of scale x'), acting at the joint (`JointAxis`), x the
    /// coordinate of the joint `reads` (None: the same joint); scale converts x to the
    /// unit the law was written in (per degree)
    JointForce { axis: JointAxis, law: MotionLaw, rate: bool, scale: f64, reads: Option<ReadJoint> },
    /// f = -viscous x' - coulomb tanh(x' / smoothing) at the joint (`JointAxis`)
    Friction { axis: JointAxis, viscous: f64, coulomb: f64, smoothing: f64 },
}

/// The coordinate x of the joint a joint load acts at, and how its generalized force
/// f dx/dq is applied: a torque f on b and -f on a (revolute, x = theta_b - theta_a); a force
/// f along the axis n = A_a e_a at b's point u_b and its reaction on a (prismatic, x = n . d,
/// d = r_b(u_b) - r_a(u_a), the slide from the start).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointAxis {
    Turn,
    Slide { u_a: [f64; 2], u_b: [f64; 2], e_a: [f64; 2] },
}

/// The joint a joint force's law reads when it is not the joint the force acts at: its
/// axis and its sides (None: the ground).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReadJoint {
    pub axis: JointAxis,
    pub body_a: Option<usize>,
    pub body_b: Option<usize>,
}

impl JointAxis {
    /// (x, x') at the sides' poses and velocities.
    pub fn coordinate(&self, a: &Frame, b: &Frame) -> (f64, f64) {
        match self {
            JointAxis::Turn => (b.theta - a.theta, b.thetad - a.thetad),
            JointAxis::Slide { u_a, u_b, e_a } => {
                let n = a.rot(*e_a);
                let d = sub(b.point(*u_b), a.point(*u_a));
                let dd = sub(b.point_velocity(*u_b), a.point_velocity(*u_a));
                // x' = n' . d + n . d', n' = w_a B_a e_a = w_a perp(n)
                (dot(n, d), a.thetad * dot(perp(n), d) + dot(n, dd))
            }
        }
    }

    /// Adds f dx/dq to q.
    fn add_force(
        &self,
        q: &mut [f64],
        body_a: Option<usize>,
        body_b: Option<usize>,
        a: &Frame,
        b: &Frame,
        f: f64,
    ) {
        match self {
            JointAxis::Turn => {
                if let Some(i) = body_b {
                    q[3 * i + 2] += f;
                }
                if let Some(i) = body_a {
                    q[3 * i + 2] -= f;
                }
            }
            JointAxis::Slide { u_a, u_b, e_a } => {
                let n = a.rot(*e_a);
                add_point_force(q, body_b, b, *u_b, [f * n[0], f * n[1]]);
                add_point_force(q, body_a, a, *u_a, [-f * n[0], -f * n[1]]);
                // the axis turns with a: d x / d theta_a has d . (B_a e_a) besides -n . (B_a u_a)
                if let Some(i) = body_a {
                    q[3 * i + 2] += f * dot(perp(n), sub(b.point(*u_b), a.point(*u_a)));
                }
            }
        }
    }

    /// x as a jet (its rate is its tau^1 part); `p` the slide's six numbers (u_a, u_b, e_a).
    fn coordinate_jet<const W: usize>(&self, a: &JetFrame<W>, b: &JetFrame<W>, p: &[Jet<W>]) -> Jet<W> {
        match self {
            JointAxis::Turn => b.theta - a.theta,
            JointAxis::Slide { .. } => {
                jet::dot(a.rot(pair(p, 4)), jet::sub(b.point(pair(p, 2)), a.point(pair(p, 0))))
            }
        }
    }

    /// `add_force` on jets.
    #[allow(clippy::too_many_arguments)]
    fn add_force_jet<const W: usize>(
        &self,
        q: &mut [Jet<W>],
        body_a: Option<usize>,
        body_b: Option<usize>,
        a: &JetFrame<W>,
        b: &JetFrame<W>,
        p: &[Jet<W>],
        f: Jet<W>,
    ) {
        match self {
            JointAxis::Turn => {
                if let Some(i) = body_b {
                    q[3 * i + 2] = q[3 * i + 2] + f;
                }
                if let Some(i) = body_a {
                    q[3 * i + 2] = q[3 * i + 2] - f;
                }
            }
            JointAxis::Slide { .. } => {
                let (u_a, u_b) = (pair(p, 0), pair(p, 2));
                let n = a.rot(pair(p, 4));
                add_point_force_jet(q, body_b, b, u_b, [f * n[0], f * n[1]]);
                add_point_force_jet(q, body_a, a, u_a, [-(f * n[0]), -(f * n[1])]);
                if let Some(i) = body_a {
                    let d = jet::sub(b.point(u_b), a.point(u_a));
                    q[3 * i + 2] = q[3 * i + 2] + f * jet::dot(jet::perp(n), d);
                }
            }
        }
    }

    /// The slide's numbers (none for a revolute), first among the load's.
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        use crate::constraints::xy;
        match self {
            JointAxis::Turn => Vec::new(),
            JointAxis::Slide { u_a, u_b, e_a } => {
                let mut p: Vec<(String, &mut f64)> = xy("u_a", u_a).into();
                p.extend(xy("u_b", u_b));
                p.extend(xy("e_a", e_a));
                p
            }
        }
    }

    /// How many numbers `params_mut` gives.
    fn n_params(&self) -> usize {
        match self {
            JointAxis::Turn => 0,
            JointAxis::Slide { .. } => 6,
        }
    }
}

impl Load {
    /// A joint load's magnitude f at (x, x') and time-independent: f and df/dx, df/dx' .
    pub fn joint_magnitude(&self, x: f64, xd: f64) -> Option<[f64; 3]> {
        match self {
            Load::JointForce { law, rate, scale, .. } => {
                let arg = if *rate { xd } else { x };
                let [f, fd, _] = law.eval(scale * arg);
                Some(if *rate { [f, 0.0, scale * fd] } else { [f, scale * fd, 0.0] })
            }
            Load::Friction { viscous, coulomb, smoothing, .. } => {
                let th = (xd / smoothing).tanh();
                Some([-viscous * xd - coulomb * th, 0.0, -viscous - coulomb * (1.0 - th * th) / smoothing])
            }
            _ => None,
        }
    }
}

/// A load of a compiled model, with its sides (None: the ground).
#[derive(Debug, Clone)]
pub struct LoadEntry {
    pub name: String,
    pub load: Load,
    pub body_a: Option<usize>,
    pub body_b: Option<usize>,
}

/// Adds (F, moment of F about the body origin) at the body point u to Q.
#[inline]
fn add_point_force(q: &mut [f64], body: Option<usize>, frame: &Frame, u: [f64; 2], f: [f64; 2]) {
    if let Some(i) = body {
        q[3 * i] += f[0];
        q[3 * i + 1] += f[1];
        q[3 * i + 2] += dot(frame.rot_d(u), f);
    }
}

#[inline(always)]
fn side(frames: &[Frame], body: Option<usize>) -> &Frame {
    body.map_or(&Frame::GROUND, |i| &frames[i])
}

#[inline(always)]
fn side_jet<const W: usize>(frames: &[JetFrame<W>], body: Option<usize>) -> JetFrame<W> {
    body.map_or_else(JetFrame::ground, |i| frames[i])
}

impl LoadEntry {
    /// The moving bodies the load's generalized force depends on: its sides, and the sides
    /// of the joint a joint force reads.
    pub fn bodies(&self) -> impl Iterator<Item = usize> {
        let reads = match &self.load {
            Load::JointForce { reads: Some(r), .. } => [r.body_a, r.body_b],
            _ => [None, None],
        };
        [self.body_a, self.body_b].into_iter().chain(reads).flatten()
    }

    /// A joint load's magnitude f and the rate x' of the joint it acts at (its power is
    /// f x'), at the bodies' `frames`; None for the other loads.
    pub fn joint_load(&self, frames: &[Frame]) -> Option<(f64, f64)> {
        let (a, b) = (side(frames, self.body_a), side(frames, self.body_b));
        let (axis, reads) = match &self.load {
            Load::JointForce { axis, reads, .. } => (axis, *reads),
            Load::Friction { axis, .. } => (axis, None),
            _ => return None,
        };
        let own = axis.coordinate(a, b);
        let (x, xd) = match reads {
            Some(r) => r.axis.coordinate(side(frames, r.body_a), side(frames, r.body_b)),
            None => own,
        };
        Some((self.load.joint_magnitude(x, xd).map_or(0.0, |m| m[0]), own.1))
    }

    /// Adds this load's generalized force at time t to q_out (n_coords), the bodies at
    /// `frames` (indexed as q's bodies).
    pub fn add_to(&self, frames: &[Frame], t: f64, q_out: &mut [f64]) {
        let (a, b) = (side(frames, self.body_a), side(frames, self.body_b));
        match &self.load {
            Load::Force { u, dir, law } => {
                let f = law.eval(t)[0];
                add_point_force(q_out, self.body_b, b, *u, [f * dir[0], f * dir[1]]);
            }
            Load::Torque { law } => {
                if let Some(i) = self.body_b {
                    q_out[3 * i + 2] += law.eval(t)[0];
                }
            }
            Load::Spring { u_a, u_b, stiffness, free_length, damping } => {
                let d = sub(b.point(*u_b), a.point(*u_a));
                let len = dot(d, d).sqrt();
                let e = [d[0] / len, d[1] / len];
                let len_d = dot(e, sub(b.point_velocity(*u_b), a.point_velocity(*u_a)));
                let tension = stiffness * (len - free_length) + damping * len_d;
                add_point_force(q_out, self.body_b, b, *u_b, [-tension * e[0], -tension * e[1]]);
                add_point_force(q_out, self.body_a, a, *u_a, [tension * e[0], tension * e[1]]);
            }
            Load::TorsionSpring { stiffness, free_angle, damping } => {
                let tau = stiffness * (b.theta - a.theta - free_angle) + damping * (b.thetad - a.thetad);
                if let Some(i) = self.body_b {
                    q_out[3 * i + 2] -= tau;
                }
                if let Some(i) = self.body_a {
                    q_out[3 * i + 2] += tau;
                }
            }
            Load::JointForce { axis, .. } | Load::Friction { axis, .. } => {
                let f = self.joint_load(frames).map_or(0.0, |(f, _)| f);
                axis.add_force(q_out, self.body_a, self.body_b, a, b, f);
            }
        }
    }

    /// The motion law of a force or torque.
    pub fn law(&self) -> Option<&MotionLaw> {
        match &self.load {
            Load::Force { law, .. } | Load::Torque { law } => Some(law),
            _ => None,
        }
    }

    /// `add_to` on jets: the bodies' perturbed motions `frames`, the load's numbers `p` (in
    /// the order of `Load::params_mut`). The generalized force at the step is each entry's
    /// value and its change in each direction (the tau^0 parts); rates come from the
    /// motion's jets.
    pub fn add_jet<const W: usize>(
        &self,
        frames: &[JetFrame<W>],
        t: f64,
        p: &[Jet<W>],
        q_out: &mut [Jet<W>],
    ) {
        let (a, b) = (&side_jet(frames, self.body_a), &side_jet(frames, self.body_b));
        match &self.load {
            Load::Force { law, .. } => {
                // the law is of time alone: its numbers' changes only (`MotionLaw::jet`)
                let f = law.jet(t, &p[4..]);
                let force = [f * p[2], f * p[3]];
                add_point_force_jet(q_out, self.body_b, b, pair(p, 0), force);
            }
            Load::Torque { law } => {
                if let Some(i) = self.body_b {
                    q_out[3 * i + 2] = q_out[3 * i + 2] + law.jet(t, p);
                }
            }
            Load::Spring { .. } => {
                let (u_a, u_b) = (pair(p, 0), pair(p, 2));
                let d = jet::sub(b.point(u_b), a.point(u_a));
                let len = jet::dot(d, d).sqrt();
                let inv = len.recip();
                let e = [d[0] * inv, d[1] * inv];
                // dL/dt along the motion: the rate (tau^1) of the length's jet
                let tension = p[4] * (len - p[5]) + p[6] * len.coefficient(1);
                add_point_force_jet(q_out, self.body_b, b, u_b, [-(tension * e[0]), -(tension * e[1])]);
                add_point_force_jet(q_out, self.body_a, a, u_a, [tension * e[0], tension * e[1]]);
            }
            Load::TorsionSpring { .. } => {
                let turn = b.theta - a.theta;
                let tau = p[0] * (turn - p[1]) + p[2] * turn.coefficient(1);
                if let Some(i) = self.body_b {
                    q_out[3 * i + 2] = q_out[3 * i + 2] - tau;
                }
                if let Some(i) = self.body_a {
                    q_out[3 * i + 2] = q_out[3 * i + 2] + tau;
                }
            }
            Load::JointForce { axis, law, rate, scale, reads } => {
                let own = axis.n_params();
                let (x, from) = match reads {
                    Some(r) => {
                        let (c, d) = (side_jet(frames, r.body_a), side_jet(frames, r.body_b));
                        (r.axis.coordinate_jet(&c, &d, &p[own..]), own + r.axis.n_params())
                    }
                    None => (axis.coordinate_jet(a, b, p), own),
                };
                let arg = if *rate { x.coefficient(1) } else { x };
                // f(scale arg) from its derivatives at the step: its tau^0 parts (the value and
                // its change with the motion) are exact, the tau^2 part lacks the third
                // derivative (not read); the law's own numbers add their changes
                let at = scale * arg.value();
                let [f, fd, fdd] = law.eval(at);
                let mut mag = arg.compose([f, scale * fd, scale * scale * fdd, 0.0]);
                let by_params = law.jet(at, &p[from..]);
                for (m, e) in mag.e.iter_mut().zip(by_params.e) {
                    m[0] += e[0];
                }
                axis.add_force_jet(q_out, self.body_a, self.body_b, a, b, p, mag);
            }
            Load::Friction { axis, .. } => {
                let xd = axis.coordinate_jet(a, b, p).coefficient(1);
                let own = &p[axis.n_params()..];
                let (c, mu, eps) = (own[0], own[1], own[2]);
                let th = (xd * eps.recip()).compose({
                    let t = (xd.value() / eps.value()).tanh();
                    [t, 1.0 - t * t, -2.0 * t * (1.0 - t * t), 0.0]
                });
                let mag = -(c * xd) - mu * th;
                axis.add_force_jet(q_out, self.body_a, self.body_b, a, b, p, mag);
            }
        }
    }
}

/// `add_point_force` on jets.
#[inline]
fn add_point_force_jet<const W: usize>(
    q: &mut [Jet<W>],
    body: Option<usize>,
    frame: &JetFrame<W>,
    u: Vec2<W>,
    f: Vec2<W>,
) {
    if let Some(i) = body {
        q[3 * i] = q[3 * i] + f[0];
        q[3 * i + 1] = q[3 * i + 1] + f[1];
        q[3 * i + 2] = q[3 * i + 2] + jet::dot(jet::perp(frame.rot(u)), f);
    }
}

impl Load {
    /// The load's own numbers, the design parameters it has, named ("u.x", "stiffness";
    /// a force's or torque's law's after its own, "law.value"), in the order `add_jet`
    /// reads them. A force's direction is the unit vector the description's normalizes to.
    pub fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        use crate::constraints::xy;
        match self {
            Load::Force { u, dir, law } => {
                let mut p: Vec<(String, &mut f64)> = xy("u", u).into();
                p.extend(xy("dir", dir));
                p.extend(law.params_mut());
                p
            }
            Load::Torque { law } => law.params_mut(),
            Load::Spring { u_a, u_b, stiffness, free_length, damping } => {
                let mut p: Vec<(String, &mut f64)> = xy("u_a", u_a).into();
                p.extend(xy("u_b", u_b));
                p.push(("stiffness".into(), stiffness));
                p.push(("free_length".into(), free_length));
                p.push(("damping".into(), damping));
                p
            }
            Load::TorsionSpring { stiffness, free_angle, damping } => vec![
                ("stiffness".into(), stiffness),
                ("free_angle".into(), free_angle),
                ("damping".into(), damping),
            ],
            Load::JointForce { axis, law, reads, .. } => {
                let mut p = axis.params_mut();
                if let Some(r) = reads {
                    p.extend(r.axis.params_mut().into_iter().map(|(n, v)| (format!("of_joint.{n}"), v)));
                }
                p.extend(law.params_mut());
                p
            }
            Load::Friction { axis, viscous, coulomb, smoothing } => {
                let mut p = axis.params_mut();
                p.push(("viscous".into(), viscous));
                p.push(("coulomb".into(), coulomb));
                p.push(("smoothing".into(), smoothing));
                p
            }
        }
    }
}

/// Mass properties of one body.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Inertia {
    pub mass: f64,
    /// moment of inertia about the centre of mass
    pub inertia: f64,
    /// centre of mass in the body frame
    pub com: [f64; 2],
}

impl Inertia {
    /// Generalized inertia force -M qdd + Q_v of a body: -(m a_c, m (B u_c) . a_c + J_c alpha),
    /// with a_c = Rdd + B u_c alpha - A u_c w^2 the acceleration of the centre of mass.
    #[inline]
    pub fn inertia_force(&self, f: &Frame, qdd: &[f64]) -> [f64; 3] {
        let s = f.rot(self.com);
        let bs = perp(s);
        let w2 = f.thetad * f.thetad;
        let ac = [qdd[0] + bs[0] * qdd[2] - s[0] * w2, qdd[1] + bs[1] * qdd[2] - s[1] * w2];
        let m = self.mass;
        [-m * ac[0], -m * ac[1], -m * dot(bs, ac) - self.inertia * qdd[2]]
    }

    /// Generalized gravity force (m g, (B u_c) . m g).
    #[inline]
    pub fn gravity_force(&self, f: &Frame, g: [f64; 2]) -> [f64; 3] {
        let mg = [self.mass * g[0], self.mass * g[1]];
        [mg[0], mg[1], dot(perp(f.rot(self.com)), mg)]
    }

    /// The numbers of a body's mass properties, in the order `force_jet` reads them.
    pub const NAMES: [&'static str; 4] = ["mass", "inertia", "com.x", "com.y"];

    /// `inertia_force` + `gravity_force` on jets: the body's perturbed motion `f`, its
    /// mass properties `p` (mass, inertia, com.x, com.y; `NAMES`) and gravity `g`. The
    /// centre of mass's acceleration is twice the tau^2 part of its position's jet, so
    /// its change with the motion's (S, S', S'') is exact.
    #[inline]
    pub fn force_jet<const W: usize>(f: &JetFrame<W>, p: &[Jet<W>], g: Vec2<W>) -> [Jet<W>; 3] {
        let (m, j) = (p[0], p[1]);
        let s = f.rot(pair(p, 2));
        let bs = jet::perp(s);
        let r = f.point(pair(p, 2));
        let ac = [r[0].coefficient(2) * 2.0, r[1].coefficient(2) * 2.0];
        let alpha = f.theta.coefficient(2) * 2.0;
        let mg = [m * g[0], m * g[1]];
        [mg[0] - m * ac[0], mg[1] - m * ac[1], jet::dot(bs, mg) - m * jet::dot(bs, ac) - j * alpha]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The jets' values at the step are the generalized forces `add_to`, `inertia_force`
    /// and `gravity_force` give, for every load kind (the same sums in another order: 1e-13
    /// of forces ~10).
    #[test]
    fn jets_value_the_forces_they_differentiate() {
        let (qa, qda, qdda) = ([0.1, -0.2, 0.7], [0.3, 0.1, -1.2], [0.5, -0.4, 2.0]);
        let (qb, qdb, qddb) = ([0.4, 0.3, -0.5], [-0.2, 0.6, 0.9], [1.1, 0.2, -3.0]);
        let motion = |q: [f64; 3], qd: [f64; 3], qdd: [f64; 3]| {
            let x = [0, 1, 2].map(|j| Jet::<1> { v: [q[j], qd[j], 0.5 * qdd[j]], e: [[0.0; 3]] });
            JetFrame::new(x)
        };
        let (qc, qdc, qddc) = ([-0.3, 0.2, 1.1], [0.4, -0.5, 0.8], [0.2, 0.9, -1.5]);
        let jets = [motion(qa, qda, qdda), motion(qb, qdb, qddb), motion(qc, qdc, qddc)];
        let (jb, frames) = (jets[1], [Frame::new(qa, qda), Frame::new(qb, qdb), Frame::new(qc, qdc)]);
        let fb = frames[1];
        let law = MotionLaw::Harmonic { mean: 5.0, amplitude: 2.0, omega: 3.0, phase: 0.1 };
        let slide = JointAxis::Slide { u_a: [0.3, -0.1], u_b: [0.05, 0.2], e_a: [0.6, 0.8] };
        let loads = [
            Load::Force { u: [0.2, 0.1], dir: [0.6, -0.8], law: law.clone() },
            Load::Torque { law },
            Load::Spring {
                u_a: [0.1, 0.3],
                u_b: [-0.2, 0.05],
                stiffness: 300.0,
                free_length: 0.1,
                damping: 4.0,
            },
            Load::TorsionSpring { stiffness: 2.0, free_angle: 0.4, damping: 0.3 },
            Load::JointForce {
                axis: JointAxis::Turn,
                law: MotionLaw::Polynomial { coefficients: vec![1.0, -2.0, 0.5] },
                rate: false,
                scale: 1.3,
                reads: None,
            },
            Load::JointForce {
                axis: slide,
                law: MotionLaw::Linear { value: 3.0, rate: -0.5 },
                rate: true,
                scale: 1.0,
                reads: None,
            },
            // a force along the slide of a law of another joint's slide, and a torque of
            // another's turn rate
            Load::JointForce {
                axis: slide,
                law: MotionLaw::Polynomial { coefficients: vec![2.0, -3.0, 4.0] },
                rate: false,
                scale: 1.0,
                reads: Some(ReadJoint { axis: slide, body_a: Some(2), body_b: Some(0) }),
            },
            Load::JointForce {
                axis: JointAxis::Turn,
                law: MotionLaw::Harmonic { mean: 1.0, amplitude: 2.0, omega: 0.7, phase: 0.3 },
                rate: true,
                scale: 0.9,
                reads: Some(ReadJoint { axis: JointAxis::Turn, body_a: None, body_b: Some(2) }),
            },
            Load::Friction { axis: JointAxis::Turn, viscous: 0.4, coulomb: 1.2, smoothing: 0.5 },
            Load::Friction { axis: slide, viscous: 0.4, coulomb: 1.2, smoothing: 0.5 },
        ];
        let t = 0.37;
        for load in loads {
            let entry = LoadEntry { name: "L".into(), load, body_a: Some(0), body_b: Some(1) };
            let mut want = [0.0; 9];
            entry.add_to(&frames, t, &mut want);
            let p: Vec<Jet<1>> =
                entry.load.clone().params_mut().into_iter().map(|(_, v)| Jet::cst(*v)).collect();
            let mut got = [Jet::<1>::ZERO; 9];
            entry.add_jet(&jets, t, &p, &mut got);
            for (g, w) in got.iter().zip(want) {
                assert!(
                    (g.value() - w).abs() < 1e-13 * (1.0 + w.abs()),
                    "{:?}: {} vs {w}",
                    entry.load,
                    g.value()
                );
            }
        }
        let body = Inertia { mass: 1.3, inertia: 0.02, com: [0.15, -0.04] };
        let g = [0.4, -9.81];
        let p = [body.mass, body.inertia, body.com[0], body.com[1]].map(Jet::<1>::cst);
        let got = Inertia::force_jet(&jb, &p, [Jet::cst(g[0]), Jet::cst(g[1])]);
        let (qi, qg) = (body.inertia_force(&fb, &qddb), body.gravity_force(&fb, g));
        for j in 0..3 {
            let w = qi[j] + qg[j];
            assert!((got[j].value() - w).abs() < 1e-13 * (1.0 + w.abs()), "{j}: {} vs {w}", got[j].value());
        }
    }
}

#[cfg(test)]
mod joint_tests {
    use super::*;

    /// A joint load's generalized force is f dx/dq: its power Q . qd is f x' (the energy
    /// balance counts it so), with x' from `JointAxis::coordinate` at the joint it acts at,
    /// f read at the joint it reads (its own, or another's); and x' is the rate of
    /// x (central differences along the motion, step 1e-6: error ~1e-10).
    #[test]
    fn joint_loads_do_the_work_of_their_magnitude() {
        let (qa, qda) = ([0.1, -0.2, 0.7], [0.3, 0.1, -1.2]);
        let (qb, qdb) = ([0.4, 0.3, -0.5], [-0.2, 0.6, 0.9]);
        let (qc, qdc) = ([-0.3, 0.2, 1.1], [0.4, -0.5, 0.8]);
        let slide = JointAxis::Slide { u_a: [0.3, -0.1], u_b: [0.05, 0.2], e_a: [0.6, 0.8] };
        let other = ReadJoint { axis: JointAxis::Turn, body_a: Some(2), body_b: Some(0) };
        let frames = [Frame::new(qa, qda), Frame::new(qb, qdb), Frame::new(qc, qdc)];
        let law = MotionLaw::Polynomial { coefficients: vec![0.5, 1.5, -2.0] };
        for axis in [JointAxis::Turn, slide] {
            let loads = [
                Load::Friction { axis, viscous: 0.4, coulomb: 1.2, smoothing: 0.5 },
                Load::JointForce { axis, law: law.clone(), rate: false, scale: 1.0, reads: Some(other) },
            ];
            for load in loads {
                let reads = matches!(load, Load::JointForce { .. });
                let entry = LoadEntry { name: "f".into(), load, body_a: Some(0), body_b: Some(1) };
                let mut q = [0.0; 9];
                entry.add_to(&frames, 0.0, &mut q);
                let (x, xd) = axis.coordinate(&frames[0], &frames[1]);
                let f = if reads {
                    law.eval(other.axis.coordinate(&frames[2], &frames[0]).0)[0]
                } else {
                    entry.load.joint_magnitude(x, xd).unwrap()[0]
                };
                assert_eq!(entry.joint_load(&frames), Some((f, xd)));
                let qd: Vec<f64> = qda.iter().chain(&qdb).chain(&qdc).copied().collect();
                let power: f64 = q.iter().zip(&qd).map(|(a, b)| a * b).sum();
                assert!((power - f * xd).abs() < 1e-13, "{axis:?}: {power} vs {}", f * xd);
                assert!(f.abs() > 0.1 && xd.abs() > 0.1, "not a trivial case");
                assert!(q[6..].iter().all(|&v| v == 0.0), "the joint read is not loaded");
            }
            let xd = axis.coordinate(&frames[0], &frames[1]).1;
            let h = 1e-6;
            let at = |s: f64| {
                let step = |q: [f64; 3], qd: [f64; 3]| std::array::from_fn(|j| q[j] + s * qd[j]);
                axis.coordinate(&Frame::new(step(qa, qda), qda), &Frame::new(step(qb, qdb), qdb)).0
            };
            let fd = (at(h) - at(-h)) / (2.0 * h);
            assert!((fd - xd).abs() < 1e-9, "{axis:?}: rate {xd} vs differences {fd}");
        }
    }
}
