//! Solved states and the quintic Hermite interpolant between two of them.
//!
//! Two states on one smooth branch, with their positions, velocities and accelerations,
//! fix the quintic that matches all six; it follows the branch to O(h^6). The careful
//! path uses it to fill times it stepped over (next to a singular configuration, where
//! Newton's solutions and the rates solved there are unreliable) and to locate a crossing
//! without solving next to it. Two solved states are accepted as one branch only if each
//! one's Taylor expansion predicts the other: across a change point, the branch that
//! keeps going (velocity continuous) passes, the other one does not.

use crate::data::Data;
use crate::model::Model;
use crate::position::PositionInfo;

/// A solved configuration with its rates, to step from.
#[derive(Debug, Clone)]
pub struct State {
    pub t: f64,
    /// n_coords each
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    /// pivot ratio and det sign of Phi_q there
    pub ratio: f64,
    pub det_sign: f64,
    /// the position solve's diagnostics
    pub info: PositionInfo,
}

impl State {
    /// The state in `data` (q, qd, qdd solved at t, `info` from its position solve).
    pub fn capture(data: &Data, t: f64, info: PositionInfo) -> State {
        State {
            t,
            q: data.q.clone(),
            qd: data.qd.clone(),
            qdd: data.qdd.clone(),
            ratio: info.pivot_ratio,
            det_sign: info.det_sign,
            info,
        }
    }

    /// Writes q, qd, qdd into `data`.
    pub fn restore(&self, data: &mut Data) {
        data.q.copy_from_slice(&self.q);
        data.qd.copy_from_slice(&self.qd);
        data.qdd.copy_from_slice(&self.qdd);
    }
}

/// One state's Taylor expansion predicting the other's positions, both ways, must be off
/// by at most this fraction of the motion between them. On one branch the misfit is
/// O(h^3) against an O(h) motion; onto another branch through a change point it is the
/// jump in velocity times h, a fraction of the motion of order one.
pub const CONSISTENCY: f64 = 0.1;
/// Scaled misfit below which two states always agree (round-off of converged solves).
const CONSISTENCY_FLOOR: f64 = 1e-9;

/// Whether `b` continues `a`'s branch: see `CONSISTENCY`.
pub fn consistent(model: &Model, a: &State, b: &State) -> bool {
    let h = b.t - a.t;
    let (mut motion, mut misfit) = (0.0f64, 0.0f64);
    for i in 0..a.q.len() {
        let s = 1.0 / model.col_scale[i];
        let forward = a.q[i] + h * (a.qd[i] + 0.5 * h * a.qdd[i]);
        let backward = b.q[i] - h * (b.qd[i] - 0.5 * h * b.qdd[i]);
        motion = motion.max((b.q[i] - a.q[i]).abs() * s);
        misfit = misfit.max((b.q[i] - forward).abs() * s).max((a.q[i] - backward).abs() * s);
    }
    misfit <= CONSISTENCY * motion + CONSISTENCY_FLOOR
}

/// The cheap path's check that a step continues its predecessor's branch, the backward
/// half of `consistent` (its forward half is the predictor's correction): q_prev
/// predicted from the new step's rates, q, qd and qdd (or qd_prev, with velocities only:
/// then qdd is their difference quotient), within CONSISTENCY of the motion.
pub fn continues(
    inv_col_scale: &[f64],
    h: f64,
    q_prev: &[f64],
    qd_prev: &[f64],
    q: &[f64],
    qd: &[f64],
    qdd: Option<&[f64]>,
) -> bool {
    // the largest of each over the coordinates; a NaN term is passed over (as f64::max
    // does), one comparison each: this runs at every step of a sweep
    let (mut motion, mut misfit) = (0.0f64, 0.0f64);
    let mut one = |s: f64, q: f64, q_prev: f64, qd: f64, acc: f64| {
        let backward = q - h * (qd - 0.5 * h * acc);
        let (m, f) = ((q - q_prev).abs() * s, (q_prev - backward).abs() * s);
        if m > motion {
            motion = m;
        }
        if f > misfit {
            misfit = f;
        }
    };
    let n = q.len();
    let (s, q_prev, qd) = (&inv_col_scale[..n], &q_prev[..n], &qd[..n]);
    match qdd {
        Some(qdd) => {
            for ((((&s, &q), &p), &v), &a) in s.iter().zip(q).zip(q_prev).zip(qd).zip(&qdd[..n]) {
                one(s, q, p, v, a);
            }
        }
        None => {
            for ((((&s, &q), &p), &v), &v0) in s.iter().zip(q).zip(q_prev).zip(qd).zip(&qd_prev[..n]) {
                one(s, q, p, v, (v - v0) / h);
            }
        }
    }
    misfit <= CONSISTENCY * motion + CONSISTENCY_FLOOR
}

/// The quintic Hermite interpolant of `a` and `b` at t: q, and qd, qdd where given.
pub fn interpolate(
    a: &State,
    b: &State,
    t: f64,
    q: &mut [f64],
    mut qd: Option<&mut [f64]>,
    mut qdd: Option<&mut [f64]>,
) {
    let h = b.t - a.t;
    let s = (t - a.t) / h;
    for i in 0..a.q.len() {
        // monomial coefficients in s of the quintic matching p, h p', h^2 p'' at both ends
        let (p0, v0, a0) = (a.q[i], h * a.qd[i], h * h * a.qdd[i]);
        let (p1, v1, a1) = (b.q[i], h * b.qd[i], h * h * b.qdd[i]);
        let d = p1 - p0;
        let c2 = 0.5 * a0;
        let c3 = 10.0 * d - 6.0 * v0 - 4.0 * v1 - 0.5 * (3.0 * a0 - a1);
        let c4 = -15.0 * d + 8.0 * v0 + 7.0 * v1 + 0.5 * (3.0 * a0 - 2.0 * a1);
        let c5 = 6.0 * d - 3.0 * (v0 + v1) - 0.5 * (a0 - a1);
        q[i] = p0 + s * (v0 + s * (c2 + s * (c3 + s * (c4 + s * c5))));
        if let Some(qd) = qd.as_deref_mut() {
            qd[i] = (v0 + s * (2.0 * c2 + s * (3.0 * c3 + s * (4.0 * c4 + s * 5.0 * c5)))) / h;
        }
        if let Some(qdd) = qdd.as_deref_mut() {
            qdd[i] = (2.0 * c2 + s * (6.0 * c3 + s * (12.0 * c4 + s * 20.0 * c5))) / (h * h);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(t: f64, q: f64, qd: f64, qdd: f64) -> State {
        let info =
            PositionInfo { iterations: 1, residual: 0.0, pivot_ratio: 1.0, det_sign: 1.0, correction: 0.0 };
        State { t, q: vec![q], qd: vec![qd], qdd: vec![qdd], ratio: 1.0, det_sign: 1.0, info }
    }

    #[test]
    fn the_interpolant_reproduces_a_quintic_and_its_derivatives() {
        // any quintic is its own Hermite interpolant: exact to round-off
        let p = |t: f64| 0.3 - 1.2 * t + 0.7 * t * t + 0.25 * t.powi(3) - 0.4 * t.powi(4) + 0.05 * t.powi(5);
        let dp = |t: f64| -1.2 + 1.4 * t + 0.75 * t * t - 1.6 * t.powi(3) + 0.25 * t.powi(4);
        let ddp = |t: f64| 1.4 + 1.5 * t - 4.8 * t * t + 1.0 * t.powi(3);
        let (ta, tb) = (-0.4, 1.3);
        let (a, b) = (state(ta, p(ta), dp(ta), ddp(ta)), state(tb, p(tb), dp(tb), ddp(tb)));
        for k in 0..=10 {
            let t = ta + (tb - ta) * k as f64 / 10.0;
            let (mut q, mut qd, mut qdd) = ([0.0], [0.0], [0.0]);
            interpolate(&a, &b, t, &mut q, Some(&mut qd), Some(&mut qdd));
            // 1e-14: a few roundings of terms of size ~1
            assert!((q[0] - p(t)).abs() < 1e-14, "{t}: {} vs {}", q[0], p(t));
            assert!((qd[0] - dp(t)).abs() < 1e-13, "{t}: {} vs {}", qd[0], dp(t));
            assert!((qdd[0] - ddp(t)).abs() < 1e-12, "{t}: {} vs {}", qdd[0], ddp(t));
        }
    }
}
