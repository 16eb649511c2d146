//! Storing one row of a simulation: the state projected onto the constraints (the drift
//! before it kept), qdd and lambda from the index-1 solve there, the energies and the
//! reactions.

use crate::dynamics::augmented::Equilibration;
use crate::dynamics::energy::{kinetic, potential};
use crate::dynamics::output::{Row, SimOutput};
use crate::dynamics::row_lanes::{Projected, RowLanes};
use crate::dynamics::system::System;
use crate::error::SolveError;
use crate::model::Model;
use crate::solve::forces::{reactions, REACTION_COLUMNS};

/// The step that reached a row: its size, Newton iterations and the work done so far.
#[derive(Debug, Clone, Copy)]
pub struct StepInfo {
    pub step: f64,
    pub iterations: u32,
    pub work: f64,
    /// `Kept` for a row not the first of its step: its factorizations keep the
    /// equilibration of the row before (`System::project_state`)
    pub equilibration: Equilibration,
}

/// Projects (q, qd) at t onto the constraints and stores row k: the drift before the
/// projection, the energies, and with `solve` qdd, lambda, the reactions and the pivot
/// ratio from the index-1 solve there (otherwise left for `solve_rows`: those arrays
/// stay empty).
#[allow(clippy::too_many_arguments)]
pub fn store_state(
    model: &Model,
    sys: &mut System,
    out: &mut SimOutput,
    k: usize,
    t: f64,
    q: &mut [f64],
    qd: &mut [f64],
    info: StepInfo,
    solve: bool,
) -> Result<(), SolveError> {
    let projected = sys.project_state(model, q, qd, t, info.equilibration);
    store_projected(model, sys, out, k, t, q, qd, info, projected, solve)
}

/// Stores row k as `store_state` does, from a projection already made (`project_state`'s
/// or a lane's, `RowLanes::project`: iterations, scaled |phi| before and after, scaled
/// |Phi_q qd - nu| before), `sys`'s frames at the projected (q, qd).
#[allow(clippy::too_many_arguments)]
pub fn store_projected(
    model: &Model,
    sys: &mut System,
    out: &mut SimOutput,
    k: usize,
    t: f64,
    q: &[f64],
    qd: &[f64],
    info: StepInfo,
    (iterations, drift, residual, drift_d): Projected,
    solve: bool,
) -> Result<(), SolveError> {
    if residual.is_nan() || residual > model.options.tol_residual {
        return Err(SolveError::Step {
            step: k,
            time: t,
            h: info.step,
            why: format!("the state cannot be projected onto the constraints (|phi| = {residual:.3e})"),
        });
    }
    let (tk, vk) = (kinetic(model, sys.frames()), potential(model, sys.frames()));
    let row = Row {
        q,
        qd,
        drift,
        drift_d,
        work: info.work,
        step: info.step,
        iterations: info.iterations.max(iterations as u32),
    };
    out.store(k, row, tk, vk);
    if solve {
        solve_row(model, sys, out, k)?;
    }
    Ok(())
}

/// Stores rows k..k + count from the states loaded in `lanes` (one step's rows after its
/// first, `info` theirs but for the work done, which each lane holds), in order: projected
/// as lanes where they take that path (`RowLanes::project`), by `store_state` where not,
/// each checked by `check` (row index in; an error stops the rows there) once stored.
/// Returns how many rows were stored and the error that stopped them (a row that cannot
/// be projected, or the check's); other errors are returned as such.
#[allow(clippy::too_many_arguments)]
pub fn store_lanes(
    model: &Model,
    sys: &mut System,
    out: &mut SimOutput,
    lanes: &mut RowLanes,
    k: usize,
    count: usize,
    info: StepInfo,
    check: &mut dyn FnMut(&SimOutput, usize) -> Option<SolveError>,
) -> Result<(usize, Option<SolveError>), SolveError> {
    let projected = lanes.project(model, sys, count);
    for (j, projected) in projected.into_iter().enumerate().take(count) {
        let info = StepInfo { work: lanes.work[j], ..info };
        let (q, qd, t) = (&mut lanes.q[j], &mut lanes.qd[j], lanes.t[j]);
        let stored = match projected {
            Some(p) => {
                sys.set_state(q, qd);
                store_projected(model, sys, out, k + j, t, q, qd, info, p, false)
            }
            None => store_state(model, sys, out, k + j, t, q, qd, info, false),
        };
        let failed = match stored {
            Ok(()) => check(out, k + j).map(|e| (j + 1, e)),
            Err(e @ SolveError::Step { .. }) => Some((j, e)),
            Err(e) => return Err(e),
        };
        if let Some((stored, error)) = failed {
            return Ok((stored, Some(error)));
        }
    }
    Ok((count, None))
}

/// qdd, the multipliers (in the rows' units), the reactions and the pivot ratio of the
/// stored rows, from the index-1 solve at each (what `store_state` leaves when not asked).
pub fn solve_rows(model: &Model, out: &mut SimOutput) -> Result<(), SolveError> {
    let mut sys = System::new(model);
    out.solved_rows(model);
    for k in 0..out.n_done {
        solve_row(model, &mut sys, out, k)?;
    }
    Ok(())
}

/// Row k's index-1 solve at its stored (q, qd).
fn solve_row(model: &Model, sys: &mut System, out: &mut SimOutput, k: usize) -> Result<(), SolveError> {
    let (n, m) = (model.n_coords, model.n_rows);
    out.solved_rows(model);
    let t = out.times[k];
    let (q, qd) = (out.q[k * n..(k + 1) * n].to_vec(), out.qd[k * n..(k + 1) * n].to_vec());
    let (qdd, lambda) = (&mut out.qdd[k * n..(k + 1) * n], &mut out.lambda[k * m..(k + 1) * m]);
    let pivots = sys.accelerations(model, &q, &qd, t, qdd, lambda, Equilibration::New);
    if !qdd.iter().chain(lambda.iter()).all(|v| v.is_finite()) {
        return Err(SolveError::NonFinite { step: k, time: t, what: "the accelerations".into() });
    }
    // the multipliers in the rows' units; the reactions from them at the frames of this state
    for c in &model.constraints {
        for i in 0..c.n_rows {
            lambda[c.row0 + i] *= c.row_scale[i];
        }
    }
    sys.data.lambda.copy_from_slice(lambda);
    let per_row = model.constraints.len() * REACTION_COLUMNS;
    reactions(model, &sys.data, t, out.reactions_row(k, per_row));
    out.pivot_ratio[k] = pivots.ratio;
    Ok(())
}
