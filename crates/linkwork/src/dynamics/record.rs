//! Storing one row of a simulation: the state projected onto the constraints (the drift
//! before it kept), qdd and lambda from the index-1 solve there, the energies and the
//! reactions.

use crate::dynamics::energy::{kinetic, potential};
use crate::dynamics::output::{Row, SimOutput};
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
}

/// Projects (q, qd) at t onto the constraints and stores row k: qdd and lambda from the
/// index-1 solve there, the drift before the projection, the energies.
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
) -> Result<(), SolveError> {
    let (iterations, drift, residual) = sys.project_positions(model, q, t, 1e-15);
    if residual.is_nan() || residual > model.options.tol_residual {
        return Err(SolveError::Step {
            step: k,
            time: t,
            h: info.step,
            why: format!("the state cannot be projected onto the constraints (|phi| = {residual:.3e})"),
        });
    }
    let drift_d = sys.project_velocities(model, q, qd, t);
    let (mut qdd, mut lambda) = (vec![0.0; model.n_coords], vec![0.0; model.n_rows]);
    let pivots = sys.accelerations(model, q, qd, t, &mut qdd, &mut lambda);
    if !qdd.iter().chain(&lambda).all(|v| v.is_finite()) {
        return Err(SolveError::NonFinite { step: k, time: t, what: "the accelerations".into() });
    }
    let (tk, vk) = (kinetic(model, sys.frames()), potential(model, sys.frames()));
    // reactions from the multipliers in the rows' units, at the frames of this state
    for c in &model.constraints {
        for i in 0..c.n_rows {
            sys.data.lambda[c.row0 + i] = lambda[c.row0 + i] * c.row_scale[i];
        }
    }
    let per_row = model.constraints.len() * REACTION_COLUMNS;
    reactions(model, &sys.data, t, out.reactions_row(k, per_row));
    let row = Row {
        q,
        qd,
        qdd: &qdd,
        lambda: &lambda,
        drift,
        drift_d,
        work: info.work,
        step: info.step,
        iterations: info.iterations.max(iterations as u32),
        pivot_ratio: pivots.ratio,
    };
    out.store(model, k, row, tk, vk);
    Ok(())
}
