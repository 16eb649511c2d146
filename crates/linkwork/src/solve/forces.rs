//! Inverse dynamics, the stage after acceleration: with M qdd + Phi_q^T lambda = Q,
//! solve Phi_q^T lambda = Q - M qdd by a transpose solve with the factorization the
//! position stage left, in three parts (inertia, gravity, applied loads) so that driver
//! efforts can be split. From lambda: each constraint's reaction on its side b,
//! Q_b = -(d phi / d q_b)^T lambda, reported as a world force and a torque about the
//! constraint's anchor point; a driver's effort is -lambda (torque or force).

use crate::constraints::{Constraint, Frame, Rows};
use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::assembly;

/// The parts of Q - M qdd, in this order in `Data::lambda_parts`.
pub const PARTS: [&str; 3] = ["inertia", "gravity", "loads"];

#[inline(always)]
fn frame(frames: &[Frame], body: Option<usize>) -> &Frame {
    match body {
        Some(i) => &frames[i],
        None => &Frame::GROUND,
    }
}

/// Writes the three parts of the generalized force (n_coords each) at data.q, qd, qdd.
pub(crate) fn generalized_forces(model: &Model, data: &mut Data, t: f64) {
    assembly::update_frames(data);
    for part in data.gen_force.iter_mut() {
        part.fill(0.0);
    }
    for (i, body) in model.inertias.iter().enumerate() {
        let f = &data.frames[i];
        let qi = body.inertia_force(f, &data.qdd[3 * i..3 * i + 3]);
        let qg = body.gravity_force(f, model.gravity);
        data.gen_force[0][3 * i..3 * i + 3].copy_from_slice(&qi);
        data.gen_force[1][3 * i..3 * i + 3].copy_from_slice(&qg);
    }
    for l in &model.loads {
        l.add_to(&data.frames, t, &mut data.gen_force[2]);
    }
}

/// Solves Phi_q^T lambda = Q - M qdd, part by part; writes data.lambda_parts and data.lambda.
/// Reads data.q, qd, qdd and the factorization of Phi_q.
pub fn solve_forces(model: &Model, data: &mut Data, t: f64, step: usize) -> Result<(), SolveError> {
    generalized_forces(model, data, t);
    // scaled: J_s^T (D_r^-1 lambda) = D_c b, with J_s = D_r Phi_q D_c
    for p in 0..PARTS.len() {
        for ((r, b), s) in data.rhs.iter_mut().zip(&data.gen_force[p]).zip(&model.col_scale) {
            *r = b * s;
        }
        data.factor.solve_transpose(&model.symbolic, &mut data.rhs);
        for c in &model.constraints {
            for i in 0..c.n_rows {
                data.lambda_parts[p][c.row0 + i] = data.rhs[c.row0 + i] * c.row_scale[i];
            }
        }
    }
    for (k, l) in data.lambda.iter_mut().enumerate() {
        *l = data.lambda_parts[0][k] + data.lambda_parts[1][k] + data.lambda_parts[2][k];
    }
    if data.lambda.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SolveError::NonFinite { step, time: t, what: "the joint reactions".into() })
    }
}

/// Columns of `reactions`, per constraint.
pub const REACTION_COLUMNS: usize = 4;

/// Each constraint's reaction on its side b from lambda: Fx, Fy (world), the torque
/// about its anchor, and the power it delivers, -lambda . (Phi_q qd) (zero for a joint;
/// a driver's effort times its rate), written into `out` (n_constraints x 4).
/// Reads data.frames (as left by `solve_forces`).
pub fn reactions(model: &Model, data: &Data, t: f64, out: &mut [f64]) {
    for (k, c) in model.constraints.iter().enumerate() {
        let (a, b) = (frame(&data.frames, c.body_a), frame(&data.frames, c.body_b));
        let mut rows = Rows::default();
        let extra = c.extra(&data.q, &data.qd);
        c.kind.position(a, b, &extra, t, &mut rows);
        let mut q_b = [0.0; 3];
        for (row, l) in rows.jac_b.iter().zip(&data.lambda[c.row0..c.row0 + c.n_rows]) {
            for (q, d) in q_b.iter_mut().zip(row) {
                *q -= d * l;
            }
        }
        // moment about b's origin -> about the anchor p: M_p = M_o - (p - R) x F
        let arm = b.rot(c.kind.anchor_b());
        let torque = q_b[2] - (arm[0] * q_b[1] - arm[1] * q_b[0]);
        // power of the constraint force on the motion, -lambda . (Phi_q qd): a driver's
        // effort times its rate in a sweep (Phi_q qd = nu), zero at rest and for a joint
        let (va, vb) = ([a.rd[0], a.rd[1], a.thetad], [b.rd[0], b.rd[1], b.thetad]);
        let mut power = 0.0;
        for i in 0..c.n_rows {
            let rate: f64 = (0..3).map(|j| rows.jac_a[i][j] * va[j] + rows.jac_b[i][j] * vb[j]).sum::<f64>()
                + rows.jac_s[i] * extra.sd;
            power -= data.lambda[c.row0 + i] * rate;
        }
        out[REACTION_COLUMNS * k..REACTION_COLUMNS * (k + 1)]
            .copy_from_slice(&[q_b[0], q_b[1], torque, power]);
    }
}

/// Power of the applied loads (springs, dampers, forces, torques): Q_loads . qd.
pub fn load_power(data: &Data) -> f64 {
    data.gen_force[2].iter().zip(&data.qd).map(|(f, v)| f * v).sum()
}
