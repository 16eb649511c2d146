//! Acceleration analysis: Phi_q qdd = gamma, with the factorization left by
//! `solve_position` and the velocities from `solve_velocity`.

use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::assembly;

/// Reads data.q, data.qd (and the factors) and writes data.qdd.
pub fn solve_acceleration(model: &Model, data: &mut Data, t: f64, step: usize) -> Result<(), SolveError> {
    assembly::gamma(model, data, t);
    if let Some(e) = crate::solve::velocity::non_finite_row(model, &data.rhs, t, step, "gamma") {
        return Err(e);
    }
    data.factor.solve(&model.symbolic, &mut data.rhs);
    for ((qdd, x), s) in data.qdd.iter_mut().zip(&data.rhs).zip(&model.col_scale) {
        *qdd = x * s;
    }
    if crate::solve::velocity::all_finite(&data.qdd) {
        Ok(())
    } else {
        Err(SolveError::NonFinite { step, time: t, what: "the accelerations".into() })
    }
}
