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

/// The pivots of solved configurations, as a sweep reports them at its start (and a
/// study's `pivot_min` reads them): the scaled Phi_q at q, t, factored with its pivots
/// chosen on its own values (`Factor::factor_choosing`). A function of q alone: not of the
/// iterate Newton factored last, nor of the values on which the fixed-sequence LU chose
/// the sequence it replays, nor of the path (Newton or closed forms) that solved q.
/// Its own workspace (a solve's, with its factors, is left as it is), and the last few
/// pivot sequences chosen: a study's designs mostly take one of them again, replayed
/// without the allocations of a new choice.
pub(crate) struct PivotsAt {
    data: Data,
    /// the most recently taken first
    factors: Vec<crate::math::linear::Factor>,
}

/// How many pivot sequences `PivotsAt` keeps.
const SEQUENCES_KEPT: usize = 4;

impl PivotsAt {
    pub(crate) fn new(model: &Model) -> PivotsAt {
        PivotsAt { data: Data::new(model), factors: Vec::new() }
    }

    /// The pivots of `q` at `t` (a configuration of `model`, which has the structure this
    /// was made for).
    pub(crate) fn at(&mut self, model: &Model, q: &[f64], t: f64) -> crate::math::pivots::Pivots {
        let data = &mut self.data;
        data.q.copy_from_slice(q);
        data.qd.fill(0.0);
        // NaN: every body's sin_cos in full, as in a new workspace
        data.frame_base.fill([f64::NAN, 1.0, 0.0]);
        if !assembly::position(model, data, t).is_finite() {
            return crate::math::pivots::Pivots::NONE;
        }
        let sym = &model.symbolic;
        for i in 0..self.factors.len() {
            if let Some(pivots) = self.factors[i].factor_if_chosen(sym, &data.jac) {
                self.factors[..=i].rotate_right(1);
                return pivots;
            }
        }
        let mut factor = match self.factors.len() {
            SEQUENCES_KEPT => self.factors.pop().expect("kept sequences"),
            _ => crate::math::linear::Factor::new(sym),
        };
        let pivots = factor.factor_choosing(sym, &data.jac);
        self.factors.insert(0, factor);
        pivots
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::outputs::SweepOutput;

    /// `PivotsAt` gives each configuration the same bits whatever it measured before (in
    /// any order, with its kept sequences or a new one), and they are a new factorization's
    /// with its pivots chosen there: over a six-bar's turn, whose best pivot rows change.
    #[test]
    fn pivots_at_a_configuration_do_not_depend_on_what_was_measured_before() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
        let mut sequences = 0;
        for name in ["six_bar_stephenson.toml", "four_bar.toml", "slider_crank.toml"] {
            let desc = crate::input::files::read_path(&dir.join(name)).unwrap().description;
            let model = Model::new(desc).unwrap();
            let (lo, hi) = model.time_domain;
            let t0 = 0.0f64.max(lo);
            let times: Vec<f64> = (0..120).map(|k| t0 + (hi.min(t0 + 2.0) - t0) * k as f64 / 120.0).collect();
            let mut data = Data::new(&model);
            let mut out = SweepOutput::new(&model, &times);
            // (a sweep that stops at a limit leaves its steps before it)
            let _ = crate::sweep::time_loop::sweep(&model, &mut data, &times, &mut out, 0, &mut |_| true);
            let times = &times[..out.n_done];
            assert!(times.len() > 20, "{name}: {} steps", times.len());
            let n = model.n_coords;
            let at = |k: usize| &out.q[k * n..(k + 1) * n];
            let mut fresh = Vec::new();
            for (k, &t) in times.iter().enumerate() {
                let mut d = Data::new(&model);
                d.q.copy_from_slice(at(k));
                assembly::position(&model, &mut d, t);
                fresh.push(d.factor.factor(&model.symbolic, &d.jac));
            }
            let mut forward = PivotsAt::new(&model);
            let mut backward = PivotsAt::new(&model);
            for k in 0..times.len() {
                let j = times.len() - 1 - k;
                for (p, want) in [
                    (forward.at(&model, at(k), times[k]), fresh[k]),
                    (backward.at(&model, at(j), times[j]), fresh[j]),
                ] {
                    assert_eq!(p.ratio.to_bits(), want.ratio.to_bits(), "{name}, step {k}");
                    assert_eq!((p.det_sign, p.column), (want.det_sign, want.column), "{name}, step {k}");
                }
            }
            sequences = sequences.max(forward.factors.len());
        }
        assert!(sequences > 1, "no configuration needed a sequence of its own");
    }
}
