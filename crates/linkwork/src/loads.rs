//! Applied loads for inverse dynamics: forces and torques following motion laws, linear
//! and torsional spring-dampers. Each writes its generalized force into Q (n_coords):
//! a force F at the body point u adds (F, (B u) . F) to the body's (x, y, theta) entries.

use crate::joints::{dot, perp, sub, Frame};
use crate::motion::MotionLaw;

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

impl LoadEntry {
    /// Adds this load's generalized force at time t to q_out (n_coords).
    pub fn add_to(&self, a: &Frame, b: &Frame, t: f64, q_out: &mut [f64]) {
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
        }
    }

    /// The motion law of a force or torque.
    pub fn law(&self) -> Option<&MotionLaw> {
        match &self.load {
            Load::Force { law, .. } | Load::Torque { law } => Some(law),
            _ => None,
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
}
