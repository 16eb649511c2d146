//! The mass matrix M(q) of M qdd + Phi_q^T lambda = Q_A: block diagonal, one 3 x 3 block
//! per body about its frame's origin (the centre of mass's offset u_c couples translation
//! and rotation, through B(theta) u_c); zero on the joints' own coordinates (a curve
//! parameter carries no mass).

use crate::constraints::loads::Inertia;
use crate::constraints::{dot, Frame};
use crate::model::Model;

/// The body's block at frame f: [[m, 0, m b_x], [0, m, m b_y], [m b_x, m b_y, J_c + m |u_c|^2]]
/// with b = B(theta) u_c, so that 1/2 qd^T M qd is the kinetic energy.
#[inline]
pub fn mass_block(body: &Inertia, f: &Frame) -> [[f64; 3]; 3] {
    let m = body.mass;
    let b = f.rot_d(body.com);
    let j = body.inertia + m * dot(body.com, body.com);
    [[m, 0.0, m * b[0]], [0.0, m, m * b[1]], [m * b[0], m * b[1], j]]
}

/// Kinetic energy of a body: 1/2 m |v_c|^2 + 1/2 J_c w^2, from its frame's velocity.
#[inline]
pub fn kinetic_energy(body: &Inertia, f: &Frame) -> f64 {
    let v = f.point_velocity(body.com);
    0.5 * body.mass * dot(v, v) + 0.5 * body.inertia * f.thetad * f.thetad
}

/// Frames of the bodies at q, qd.
pub fn frames_of(q: &[f64], qd: &[f64], frames: &mut [Frame]) {
    for (i, f) in frames.iter_mut().enumerate() {
        let s = 3 * i;
        *f = Frame::new([q[s], q[s + 1], q[s + 2]], [qd[s], qd[s + 1], qd[s + 2]]);
    }
}

/// M x (n) at the frames.
pub fn mass_times(model: &Model, frames: &[Frame], x: &[f64], out: &mut [f64]) {
    out.fill(0.0);
    for (i, body) in model.inertias.iter().enumerate() {
        let m = mass_block(body, &frames[i]);
        for j in 0..3 {
            out[3 * i + j] = (0..3).map(|k| m[j][k] * x[3 * i + k]).sum();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1/2 qd^T M qd is the kinetic energy computed from the centre of mass's velocity, for
    /// an off-centre body in a general motion (the same sum of ~10 terms: 1e-14).
    #[test]
    fn mass_block_gives_the_kinetic_energy() {
        let body = Inertia { mass: 2.3, inertia: 0.07, com: [0.4, -0.15] };
        for (q, qd) in [([0.1, 0.2, 0.7], [0.5, -1.2, 2.0]), ([-1.0, 3.0, -2.5], [0.0, 0.3, -4.0])] {
            let f = Frame::new(q, qd);
            let m = mass_block(&body, &f);
            let quad: f64 = (0..3).map(|i| (0..3).map(|j| qd[i] * m[i][j] * qd[j]).sum::<f64>()).sum();
            let t = kinetic_energy(&body, &f);
            assert!((0.5 * quad - t).abs() < 1e-14 * (1.0 + t), "{} vs {t}", 0.5 * quad);
            assert!(t > 0.0);
        }
    }
}
