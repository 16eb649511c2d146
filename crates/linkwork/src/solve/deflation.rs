//! Deflated Newton: a solution of Phi(q, t) = 0 other than a known one, on the same
//! factorization as the plain step.

use crate::model::data::Data;
use crate::model::Model;

/// Newton on Phi(q, t) / (|q - known|^2) + Phi(q, t) from data.q: a solution other than
/// `known` (deflation). With m(q) = 1 / |q - known|^2 + 1 (scaled), the deflated Newton
/// step is the plain one divided by 1 - grad(m).step / m (Sherman-Morrison), so it reuses
/// the factorization of Phi_q. True if it converged (data.q is the solution).
pub(crate) fn deflated_newton(model: &Model, data: &mut Data, t: f64, known: &[f64], tol: f64) -> bool {
    let n = model.n_coords;
    let scale = &model.col_scale;
    for _ in 0..40 {
        let residual = crate::solve::assembly::position(model, data, t);
        data.pivots = data.factor.factor(&model.symbolic, &data.jac);
        if !(residual.is_finite() && data.pivots.ratio > 0.0) {
            return false;
        }
        for (r, p) in data.rhs.iter_mut().zip(&data.phi) {
            *r = -p;
        }
        data.factor.solve(&model.symbolic, &mut data.rhs);
        let d2: f64 = (0..n).map(|i| ((data.q[i] - known[i]) / scale[i]).powi(2)).sum();
        if d2 == 0.0 {
            return false;
        }
        let m = 1.0 / d2 + 1.0;
        let g_dot: f64 =
            (0..n).map(|i| -2.0 * (data.q[i] - known[i]) / scale[i] / (d2 * d2) * data.rhs[i]).sum();
        let factor = 1.0 / (1.0 - g_dot / m);
        let mut step_norm = 0.0f64;
        for ((q, r), s) in data.q.iter_mut().zip(&data.rhs[..n]).zip(scale) {
            let d = factor * r;
            *q += d * s;
            step_norm = step_norm.max(d.abs());
        }
        if !step_norm.is_finite() {
            return false;
        }
        if residual <= tol && step_norm <= 1e-10 {
            return true;
        }
    }
    false
}
