//! Velocity analysis: Phi_q qd = nu, with the factorization left by `solve_position`.

use crate::assembly;
use crate::data::Data;
use crate::error::SolveError;
use crate::model::Model;

/// Reads data.q (through the factors) and writes data.qd.
pub fn solve_velocity(model: &Model, data: &mut Data, t: f64, step: usize) -> Result<(), SolveError> {
    assembly::nu(model, data, t);
    data.factor.solve(&model.symbolic, &mut data.rhs);
    for ((qd, x), s) in data.qd.iter_mut().zip(&data.rhs).zip(&model.col_scale) {
        *qd = x * s;
    }
    if data.qd.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SolveError::NonFinite { step, time: t, what: "the velocities".into() })
    }
}
