//! The energy balance of a simulation: kinetic energy, the potential of gravity and of the
//! springs, and the power of what is not conservative (dampers, applied forces and
//! torques, joint forces, motors and friction, driven constraints), whose integral over time is the work W_nc, so that
//! T + V - W_nc stays at its initial value.

use crate::constraints::loads::Load;
use crate::constraints::{dot, sub, Frame};
use crate::dynamics::mass::kinetic_energy;
use crate::model::Model;

#[inline(always)]
fn side(frames: &[Frame], body: Option<usize>) -> &Frame {
    match body {
        Some(i) => &frames[i],
        None => &Frame::GROUND,
    }
}

/// T = 1/2 qd^T M qd.
pub fn kinetic(model: &Model, frames: &[Frame]) -> f64 {
    model.inertias.iter().zip(frames).map(|(b, f)| kinetic_energy(b, f)).sum()
}

/// V: gravity's -m g . r_c of every body, springs' 1/2 k (L - L0)^2, torsion springs'
/// 1/2 k (theta_b - theta_a - theta_0)^2.
pub fn potential(model: &Model, frames: &[Frame]) -> f64 {
    let g = model.gravity;
    let mut v: f64 = model.inertias.iter().zip(frames).map(|(b, f)| -b.mass * dot(g, f.point(b.com))).sum();
    for l in &model.loads {
        let (a, b) = (side(frames, l.body_a), side(frames, l.body_b));
        match &l.load {
            Load::Spring { u_a, u_b, stiffness, free_length, .. } => {
                let d = sub(b.point(*u_b), a.point(*u_a));
                let stretch = dot(d, d).sqrt() - free_length;
                v += 0.5 * stiffness * stretch * stretch;
            }
            Load::TorsionSpring { stiffness, free_angle, .. } => {
                let turn = b.theta - a.theta - free_angle;
                v += 0.5 * stiffness * turn * turn;
            }
            Load::Force { .. } | Load::Torque { .. } | Load::JointForce { .. } | Load::Friction { .. } => {}
        }
    }
    v
}

/// The power of the loads that are not conservative at time t: applied forces and
/// torques (F . v), dampers (-c Ldot^2, -c (w_b - w_a)^2), joint loads (f x': a joint
/// force's law of x counts as work, not as a potential; of another joint's x it is not
/// one in general).
pub fn load_power(model: &Model, frames: &[Frame], t: f64) -> f64 {
    let mut p = 0.0;
    for l in &model.loads {
        let (a, b) = (side(frames, l.body_a), side(frames, l.body_b));
        p += match &l.load {
            Load::Force { u, dir, law } => law.eval(t)[0] * dot(*dir, b.point_velocity(*u)),
            Load::Torque { law } => law.eval(t)[0] * b.thetad,
            Load::Spring { u_a, u_b, damping, .. } => {
                let d = sub(b.point(*u_b), a.point(*u_a));
                let len = dot(d, d).sqrt();
                let rate = dot(d, sub(b.point_velocity(*u_b), a.point_velocity(*u_a))) / len;
                -damping * rate * rate
            }
            Load::TorsionSpring { damping, .. } => {
                let w = b.thetad - a.thetad;
                -damping * w * w
            }
            Load::JointForce { .. } | Load::Friction { .. } => {
                l.joint_load(frames).map_or(0.0, |(f, xd)| f * xd)
            }
        };
    }
    p
}
