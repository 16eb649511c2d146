//! Consistent initial conditions: q projected onto Phi(q, t0) = 0 and qd onto
//! Phi_q qd = nu, each by the smallest change in the mass metric (min 1/2 dq^T M dq
//! subject to the constraints: Gauss-Newton on the augmented matrix for q, one solve for
//! qd), reporting how far each moved; beyond a tolerance, a named error. The augmented
//! matrix at t0 also tells whether M has mass on every motion the constraints allow.

use crate::dynamics::augmented::{Augmented, Equilibration};
use crate::dynamics::system::System;
use crate::error::SolveError;
use crate::model::Model;

/// A pivot ratio of [[M, Phi_q^T], [Phi_q, 0]] at t0 below this: singular (no mass on a
/// free coordinate); round-off alone leaves ratios near 1e-16 there.
pub const MASSLESS_BELOW: f64 = 1e-12;

/// How far the initial conditions moved (scaled: x, y / L; theta in rad; rates alike).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Moved {
    pub q: f64,
    pub qd: f64,
}

/// The largest scaled change and the coordinate where it is.
fn largest(model: &Model, a: &[f64], b: &[f64]) -> (f64, usize) {
    let mut best = (0.0, 0);
    for (k, ((x, y), s)) in a.iter().zip(b).zip(&model.col_scale).enumerate() {
        let d = (x - y).abs() / s;
        if d > best.0 || d.is_nan() {
            best = (d, k);
        }
    }
    best
}

/// The named error for a singular augmented matrix at t0: the coordinate a null
/// direction moves most, and its body.
pub fn massless(model: &Model, aug: &mut Augmented, t: f64) -> SolveError {
    let col = aug.null_coordinate();
    let body = if col < 3 * model.n_bodies {
        model.body_names[col / 3].clone()
    } else {
        format!("the own coordinate of {}", model.describe_coordinate(col).1)
    };
    SolveError::Massless { time: t, body, coordinate: model.columns[col].clone() }
}

/// Projects q and qd (in place) onto the constraints at t0; `tol_q` and `tol_qd` bound
/// how far each may move (scaled). Errors: positions or rates moved beyond their
/// tolerance, no mass on a free coordinate, positions that cannot be projected (no
/// assembly near them).
pub fn make_consistent(
    model: &Model,
    sys: &mut System,
    q: &mut [f64],
    qd: &mut [f64],
    t0: f64,
    tol_q: f64,
    tol_qd: f64,
) -> Result<Moved, SolveError> {
    let (q0, qd0) = (q.to_vec(), qd.to_vec());
    // the augmented matrix at the given positions: singular means no mass on some motion
    // the constraints allow (a kinematically singular start is refused the same way)
    sys.set_state(q, qd);
    let mut phi = vec![0.0; model.n_rows];
    sys.aug.fill(model, &sys.data.frames, q, t0, 1.0, &mut phi);
    let pivots = sys.aug.factor(0.0, Equilibration::New);
    if pivots.ratio.is_nan() || pivots.ratio < MASSLESS_BELOW {
        return Err(massless(model, &mut sys.aug, t0));
    }
    let (_, _, residual) = sys.project_positions(model, q, t0, model.options.tol_residual);
    let (moved_q, at_q) = largest(model, q, &q0);
    if residual.is_nan() || residual > model.options.tol_residual {
        return Err(SolveError::Inconsistent {
            what: "positions (no configuration near them satisfies the constraints)",
            moved: moved_q,
            tol: tol_q,
            coordinate: model.columns[at_q].clone(),
        });
    }
    if moved_q > tol_q {
        return Err(SolveError::Inconsistent {
            what: "positions",
            moved: moved_q,
            tol: tol_q,
            coordinate: model.columns[at_q].clone(),
        });
    }
    sys.project_velocities(model, q, qd, t0);
    let (moved_qd, at_qd) = largest(model, qd, &qd0);
    if moved_qd.is_nan() || moved_qd > tol_qd {
        return Err(SolveError::Inconsistent {
            what: "velocities",
            moved: moved_qd,
            tol: tol_qd,
            coordinate: model.columns[at_qd].clone(),
        });
    }
    Ok(Moved { q: moved_q, qd: moved_qd })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::Frame;
    use crate::dynamics::applied::tests::loaded_pair;
    use crate::dynamics::mass::{frames_of, mass_times};

    /// Positions moved off the constraints by ~1e-4 come back onto them (|phi| at
    /// round-off), the rates onto Phi_q qd = nu, each reporting how far it moved; the
    /// change is the smallest in the mass metric: M dq is a combination of the
    /// constraint rows (its component along the motions they allow vanishes).
    #[test]
    fn projection_lands_on_the_constraints_by_the_smallest_change() {
        let model = loaded_pair();
        let (n, m) = (model.n_coords, model.n_rows);
        let mut sys = System::new(&model);
        let mut q = model.q_start.clone();
        let mut qd = vec![0.3, -0.2, 1.0, 0.1, 0.4, -0.5];
        let bump = [1e-4, -2e-4, 3e-4, 0.0, 1e-4, -1e-4];
        for (x, b) in q.iter_mut().zip(bump) {
            *x += b;
        }
        let (q0, qd0) = (q.clone(), qd.clone());
        let moved = make_consistent(&model, &mut sys, &mut q, &mut qd, 0.0, 1.0, 1.0).unwrap();
        let aug = &mut sys.aug;
        let mut frames = vec![Frame::GROUND; model.n_bodies];
        let mut phi = vec![0.0; m];
        frames_of(&q, &qd, &mut frames);
        aug.fill(&model, &frames, &q, 0.0, 1.0, &mut phi);
        assert!(phi.iter().all(|p| p.abs() < 1e-14), "{phi:?}");
        let mut rate = vec![0.0; m];
        aug.jacobian_times(&qd, &mut rate);
        assert!(rate.iter().all(|r| r.abs() < 1e-14), "{rate:?}");
        assert!(moved.q > 1e-5 && moved.q < 1e-3 && moved.qd > 1e-2 && moved.qd < 1.0, "{moved:?}");
        // optimality: M (q - q0) = Phi_q^T mu for some mu (least squares, then residual)
        let dq: Vec<f64> = q.iter().zip(&q0).map(|(a, b)| a - b).collect();
        let dqd: Vec<f64> = qd.iter().zip(&qd0).map(|(a, b)| a - b).collect();
        // positions: Gauss-Newton stops once on the constraints, optimal to second order
        // in the move; rates: one exact linear solve
        for (d, exact) in [(&dq, false), (&dqd, true)] {
            let mut md = vec![0.0; n];
            mass_times(&model, &frames, d, &mut md);
            // project M d onto the null space of Phi_q^T's complement: solve the
            // augmented system with rhs (M d, 0) -> its q part is the null-space component
            let mut x = vec![0.0; n + m];
            x[..n].copy_from_slice(&md);
            aug.fill(&model, &frames, &q, 0.0, 1.0, &mut phi);
            aug.factor_solve(&mut x, Equilibration::New);
            let size = d.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let bound = if exact { 1e-9 * size } else { 10.0 * size * size };
            assert!(x[..n].iter().all(|v| v.abs() < bound), "{:?} (move {size:.2e})", &x[..n]);
        }
    }

    /// Beyond the tolerance: a named error saying which coordinate moved most.
    #[test]
    fn inconsistent_beyond_tolerance_is_an_error() {
        let model = loaded_pair();
        let mut sys = System::new(&model);
        let mut q = model.q_start.clone();
        q[3] += 0.05;
        let mut qd = vec![0.0; 6];
        let e = make_consistent(&model, &mut sys, &mut q, &mut qd, 0.0, 1e-6, 1e-6).unwrap_err();
        assert!(matches!(e, SolveError::Inconsistent { what: "positions", .. }), "{e}");
    }
}
