//! Velocity analysis: Phi_q qd = nu, with the factorization left by `solve_position`.

use crate::constraints::Constraint;
use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::assembly;

/// Reads data.q (through the factors) and writes data.qd. Where the position solve
/// already solved them with the same factorization at the same time, those are taken.
pub fn solve_velocity(model: &Model, data: &mut Data, t: f64, step: usize) -> Result<(), SolveError> {
    let solved = data.velocity_of == Some((data.factor.generation, t));
    if solved && all_finite(&data.nu_rhs) {
        for ((qd, x), s) in data.qd.iter_mut().zip(&data.nu_rhs).zip(&model.col_scale) {
            *qd = x * s;
        }
        return Ok(());
    }
    // not solved yet, or not finite: solved (again) here, naming a row that is not
    assembly::nu(model, data, t);
    if let Some(e) = non_finite_row(model, &data.rhs, t, step, "nu") {
        return Err(e);
    }
    data.factor.solve(&model.symbolic, &mut data.rhs);
    for ((qd, x), s) in data.qd.iter_mut().zip(&data.rhs).zip(&model.col_scale) {
        *qd = x * s;
    }
    if all_finite(&data.qd) {
        Ok(())
    } else {
        Err(SolveError::NonFinite { step, time: t, what: "the velocities".into() })
    }
}

/// The error for the first non-finite entry of a per-row vector (phi, nu, gamma), naming
/// the joint or driver that owns the row and, for a driver, why its law is not finite.
pub(crate) fn non_finite_row(
    model: &Model,
    rows: &[f64],
    t: f64,
    step: usize,
    what: &str,
) -> Option<SolveError> {
    if all_finite(rows) {
        return None;
    }
    let row = rows.iter().position(|v| !v.is_finite())?;
    let c = model.row_owner(row);
    let why = c.kind.law().and_then(|law| law.why_not_finite(t)).map_or(String::new(), |w| format!(": {w}"));
    Some(SolveError::NonFinite { step, time: t, what: format!("{what} of {} '{}'{why}", c.role, c.name) })
}

/// Whether every entry is finite: x * 0 is 0 for a finite x and NaN otherwise, so the sum
/// is exact and the loop has no branch (it vectorizes; the per-step checks are cheap).
#[inline]
pub(crate) fn all_finite(v: &[f64]) -> bool {
    v.iter().fold(0.0, |a, &x| a + x * 0.0) == 0.0
}
