//! Solved states and the quintic Hermite interpolant between two of them.
//!
//! Two states on one smooth branch, with their positions, velocities and accelerations,
//! fix the quintic that matches all six; it follows the branch to O(h^6). The careful
//! path uses it to fill times it stepped over (next to a singular configuration, where
//! Newton's solutions and the rates solved there are unreliable) and to locate a crossing
//! without solving next to it. Two solved states are accepted as one branch only if each
//! one's Taylor expansion predicts the other: across a change point, the branch that
//! keeps going (velocity continuous) passes, the other one does not.

use crate::model::data::Data;
use crate::model::Model;
use crate::solve::position::PositionInfo;

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
pub const CONSISTENCY_FLOOR: f64 = 1e-9;

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
    let mut check = TwoWay::default();
    let n = q.len();
    let (s, q_prev, qd) = (&inv_col_scale[..n], &q_prev[..n], &qd[..n]);
    match qdd {
        Some(qdd) => {
            for ((((&s, &q), &p), &v), &a) in s.iter().zip(q).zip(q_prev).zip(qd).zip(&qdd[..n]) {
                check.add(h, s, q, p, v, a);
            }
        }
        None => {
            for ((((&s, &q), &p), &v), &v0) in s.iter().zip(q).zip(q_prev).zip(qd).zip(&qd_prev[..n]) {
                check.add(h, s, q, p, v, (v - v0) / h);
            }
        }
    }
    check.passes()
}

/// The two-way check's largest motion and misfit over the coordinates so far (scaled). A
/// NaN term is passed over (as f64::max does), one comparison each: this runs at every
/// step of a sweep.
#[derive(Default)]
struct TwoWay {
    motion: f64,
    misfit: f64,
}

impl TwoWay {
    /// One coordinate: q now, q_prev at the step before, qd and qdd (acc) now; s its
    /// inverse scale.
    #[inline(always)]
    fn add(&mut self, h: f64, s: f64, q: f64, q_prev: f64, qd: f64, acc: f64) {
        let backward = q - h * (qd - 0.5 * h * acc);
        let (m, f) = ((q - q_prev).abs() * s, (q_prev - backward).abs() * s);
        if m > self.motion {
            self.motion = m;
        }
        if f > self.misfit {
            self.misfit = f;
        }
    }

    /// The largest motion and misfit of both (the terms of `other` added).
    #[inline(always)]
    fn join(&mut self, other: &TwoWay) {
        if other.motion > self.motion {
            self.motion = other.motion;
        }
        if other.misfit > self.misfit {
            self.misfit = other.misfit;
        }
    }

    fn passes(&self) -> bool {
        self.misfit <= CONSISTENCY * self.motion + CONSISTENCY_FLOOR
    }
}

/// Where a step's row is written as the step is checked (`continues_storing`): row `row`
/// of the output's q, and of qd, qdd where they are kept (None where not).
pub struct Row<'a> {
    pub q: &'a mut [f64],
    pub qd: Option<&'a mut [f64]>,
    pub qdd: Option<&'a mut [f64]>,
}

/// `continues` with accelerations, writing q, qd, qdd into `row` as it reads them: one
/// pass over the coordinates where a run of closed-form steps keeps every coordinate,
/// instead of the check's pass and the store's copies. The same comparisons in the same
/// order, so the same answer. The row is written whatever the answer: a step that fails
/// the check is solved again and its row written again, or the sweep ends before it
/// (rows past `n_done` are not results). Inlined into a run's loop (`time_loop`), which
/// is compiled for the machine.
#[inline(always)]
pub fn continues_storing(
    inv_col_scale: &[f64],
    h: f64,
    q_prev: &[f64],
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    row: Row,
) -> bool {
    match (row.qd, row.qdd) {
        (Some(od), Some(odd)) => {
            checked_into::<true, true>(inv_col_scale, h, q_prev, q, qd, qdd, row.q, od, odd)
        }
        (Some(od), None) => {
            checked_into::<true, false>(inv_col_scale, h, q_prev, q, qd, qdd, row.q, od, &mut [])
        }
        (None, _) => {
            checked_into::<false, false>(inv_col_scale, h, q_prev, q, qd, qdd, row.q, &mut [], &mut [])
        }
    }
}

/// `continues_storing` with `D`, `DD`: whether qd, qdd are kept.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn checked_into<const D: bool, const DD: bool>(
    inv_col_scale: &[f64],
    h: f64,
    q_prev: &[f64],
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    out_q: &mut [f64],
    out_qd: &mut [f64],
    out_qdd: &mut [f64],
) -> bool {
    let n = q.len();
    let (s, q_prev, qd, qdd, out_q) =
        (&inv_col_scale[..n], &q_prev[..n], &qd[..n], &qdd[..n], &mut out_q[..n]);
    let out_qd = if D { &mut out_qd[..n] } else { out_qd };
    let out_qdd = if DD { &mut out_qdd[..n] } else { out_qdd };
    // two coordinates at a time, each of the pair with its own largest motion and misfit
    // (the two lanes of a vector register), the two joined at the end: the largest of
    // terms is the same whatever order they are taken in (a NaN passed over either way)
    let mut lanes = [TwoWay::default(), TwoWay::default()];
    for i in (0..n - n % 2).step_by(2) {
        let j = i + 1;
        lanes[0].add(h, s[i], q[i], q_prev[i], qd[i], qdd[i]);
        lanes[1].add(h, s[j], q[j], q_prev[j], qd[j], qdd[j]);
        (out_q[i], out_q[j]) = (q[i], q[j]);
        if D {
            (out_qd[i], out_qd[j]) = (qd[i], qd[j]);
        }
        if DD {
            (out_qdd[i], out_qdd[j]) = (qdd[i], qdd[j]);
        }
    }
    if n % 2 == 1 {
        let i = n - 1;
        lanes[0].add(h, s[i], q[i], q_prev[i], qd[i], qdd[i]);
        out_q[i] = q[i];
        if D {
            out_qd[i] = qd[i];
        }
        if DD {
            out_qdd[i] = qdd[i];
        }
    }
    let [mut check, other] = lanes;
    check.join(&other);
    check.passes()
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

    /// The check that stores as it reads answers as `continues` does (on a step that
    /// continues, one that jumps, and one with a NaN) and writes the row it read, qd and
    /// qdd where kept.
    #[test]
    fn continues_storing_is_continues_and_a_store() {
        let h = 1e-3;
        let s = [1.0 / 0.35, 1.0 / 0.35, 1.0];
        let q_prev = [0.1, 0.2, 0.3];
        let (qd, qdd) = ([2.0, -1.0, 5.0], [0.5, 0.25, -3.0]);
        let smooth: Vec<f64> = (0..3).map(|i| q_prev[i] + h * (qd[i] + 0.5 * h * qdd[i])).collect();
        let jumped = [smooth[0], smooth[1] + 0.01, smooth[2]];
        let nan = [smooth[0], f64::NAN, smooth[2]];
        for q in [&smooth[..], &jumped[..], &nan[..]] {
            let expected = continues(&s, h, &q_prev, &[0.0; 3], q, &qd, Some(&qdd));
            for kept in 0..3 {
                let (mut oq, mut oqd, mut oqdd) = ([9.0; 3], [9.0; 3], [9.0; 3]);
                let row = Row {
                    q: &mut oq,
                    qd: (kept >= 1).then_some(&mut oqd[..]),
                    qdd: (kept >= 2).then_some(&mut oqdd[..]),
                };
                assert_eq!(continues_storing(&s, h, &q_prev, q, &qd, &qdd, row), expected);
                assert!(oq.iter().zip(q).all(|(a, b)| a.to_bits() == b.to_bits()));
                assert_eq!(oqd, if kept >= 1 { qd } else { [9.0; 3] });
                assert_eq!(oqdd, if kept >= 2 { qdd } else { [9.0; 3] });
            }
        }
        assert!(continues(&s, h, &q_prev, &[0.0; 3], &smooth, &qd, Some(&qdd)));
        assert!(!continues(&s, h, &q_prev, &[0.0; 3], &jumped, &qd, Some(&qdd)));
    }

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
