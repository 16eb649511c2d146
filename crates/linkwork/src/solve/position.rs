//! Position analysis: Newton-Raphson on Phi(q, t) = 0.
//!
//! Each iteration evaluates Phi and Phi_q, factors Phi_q and computes the Newton step.
//! It stops when the scaled residual and the scaled step are both below tolerance, and
//! applies that last (tiny) step: so the factorization left in `Data` is of Phi_q within
//! `tol_step` of the converged q, and serves the velocity and acceleration solves. With
//! `Data::with_velocity`, each iteration also solves the velocities with its
//! factorization, interleaved with the Newton step: the last one's are kept.

use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::assembly;

/// Largest scaled step while assembling from a rough starting guess; keeps Newton on
/// the branch nearest the described configuration.
const ASSEMBLY_MAX_STEP: f64 = 0.5;

/// Diagnostics of one position solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionInfo {
    pub iterations: usize,
    /// scaled residual inf-norm at the last evaluation
    pub residual: f64,
    /// smallest / largest pivot of the scaled Phi_q
    pub pivot_ratio: f64,
    /// sign of det Phi_q at the last factorization
    pub det_sign: f64,
    /// sum of the scaled Newton step norms: how far the solution is from the start guess
    /// (the sweep compares it with the predicted motion to catch branch jumps)
    pub correction: f64,
}

/// Factors the Phi_q in data.jac (kept in data.factor, its pivots in data.pivots); a
/// singular one is an error naming the coordinate of the smallest pivot.
pub(crate) fn factor(
    model: &Model,
    data: &mut Data,
    t: f64,
    step: usize,
) -> Result<crate::math::pivots::Pivots, SolveError> {
    let pivots = data.factor.factor(&model.symbolic, &data.jac);
    data.pivots = pivots;
    // a NaN ratio counts as singular too
    if pivots.ratio.is_nan() || pivots.ratio < model.options.singular_tol {
        let (coordinate, constraints) = model.describe_coordinate(pivots.column);
        return Err(SolveError::Singular {
            step,
            time: t,
            pivot_ratio: pivots.ratio,
            coordinate,
            constraints,
        });
    }
    Ok(pivots)
}

/// The pivots of a solved configuration `q` at `t`, as a sweep reports them at its start
/// (and a study's `pivot_min` reads them): the scaled Phi_q there, factored with its pivots
/// chosen on its own values. A function of q alone: not of the iterate Newton factored last,
/// nor of the values on which the fixed-sequence LU chose the sequence it replays, nor of
/// the path (Newton or closed forms) that solved q. `scratch`: a workspace of `model`'s
/// structure, overwritten (the solve's own, with its factors, is left as it is).
pub(crate) fn pivots_at(model: &Model, scratch: &mut Data, q: &[f64], t: f64) -> crate::math::pivots::Pivots {
    scratch.q.copy_from_slice(q);
    scratch.qd.fill(0.0);
    // NaN: every body's sin_cos in full, as in a new workspace
    scratch.frame_base.fill([f64::NAN, 1.0, 0.0]);
    if !assembly::position(model, scratch, t).is_finite() {
        return crate::math::pivots::Pivots::NONE;
    }
    scratch.factor.factor_choosing(&model.symbolic, &scratch.jac)
}

/// Solves Phi(q, t) = 0 starting from data.q; writes data.q, data.phi, the factors.
///
/// `step` is the sweep step (for error messages); `assembly` allows more iterations and
/// limits the step length, for a start from a rough configuration.
pub fn solve_position(
    model: &Model,
    data: &mut Data,
    t: f64,
    step: usize,
    assembly: bool,
) -> Result<PositionInfo, SolveError> {
    model.check_kinematic()?;
    let opts = &model.options;
    let max_iter = if assembly { opts.max_iter_assembly } else { opts.max_iter };
    let mut residual = f64::NAN;
    let mut correction = 0.0;
    let mut prev_step = f64::INFINITY;
    for it in 1..=max_iter {
        residual = assembly::position(model, data, t);
        if !residual.is_finite() {
            let e = crate::solve::velocity::non_finite_row(model, &data.phi, t, step, "the residual");
            return Err(e.unwrap_or(SolveError::NonFinite { step, time: t, what: "the residual".into() }));
        }
        let pivots = factor(model, data, t, step)?;
        for (r, p) in data.rhs.iter_mut().zip(&data.phi) {
            *r = -p;
        }
        if data.with_velocity {
            // the velocities with this factorization, in case it is the last one
            assembly::nu_into(model, t, &mut data.nu_rhs);
            data.factor.solve_pair(&model.symbolic, &mut data.rhs, &mut data.nu_rhs);
            data.velocity_of = Some((data.factor.generation, t));
        } else {
            data.factor.solve(&model.symbolic, &mut data.rhs);
        }
        let step_norm = data.rhs[..model.n_coords].iter().fold(0.0f64, |m, d| m.max(d.abs()));
        if !step_norm.is_finite() {
            return Err(SolveError::NonFinite { step, time: t, what: "the Newton step".into() });
        }
        // the step cannot be resolved below round-off times the condition number, which
        // 1 / pivot ratio estimates: on ill-conditioned chains tol_step alone is unreachable
        let step_floor = opts.tol_step.max(8.0 * f64::EPSILON / pivots.ratio);
        // near a singular configuration round-off in the residual makes the steps
        // stagnate instead of shrinking: with the residual converged, that is the end, and
        // the step is round-off: q before it is the one whose residual was measured
        let converged = residual <= opts.tol_residual && step_norm <= step_floor;
        let stalled = !converged && residual <= opts.tol_residual && step_norm >= 0.9 * prev_step;
        prev_step = step_norm;
        if !stalled {
            let damping =
                if assembly && step_norm > ASSEMBLY_MAX_STEP { ASSEMBLY_MAX_STEP / step_norm } else { 1.0 };
            for ((q, d), s) in data.q.iter_mut().zip(&data.rhs).zip(&model.col_scale) {
                *q += damping * d * s;
            }
            correction += damping * step_norm;
        }
        if converged || stalled {
            data.iterations = it;
            data.residual = residual;
            return Ok(PositionInfo {
                iterations: it,
                residual,
                pivot_ratio: pivots.ratio,
                det_sign: pivots.det_sign,
                correction,
            });
        }
    }
    data.iterations = max_iter;
    data.residual = residual;
    let worst = data
        .phi
        .iter()
        .enumerate()
        .fold((0, 0.0f64), |w, (i, p)| if p.abs() > w.1 { (i, p.abs()) } else { w });
    let c = model.row_owner(worst.0);
    let constraint = format!("{} '{}'", c.role, c.name);
    Err(if assembly {
        SolveError::Assembly { time: t, iterations: max_iter, residual, constraint }
    } else {
        SolveError::NoConvergence { step, time: t, iterations: max_iter, residual, constraint }
    })
}
