//! Singular configurations: how close Phi_q is to singular, in which direction, and what
//! kind of singularity it is.
//!
//! Near a singular configuration Phi_q ~ sigma_min w v^T + ..., with v the motion the
//! constraints allow with every driver held (right singular vector) and w the
//! combination of rows that has become dependent (left singular vector). Where w lies
//! says what happens:
//! - w has a share on a driver row: the driver's value cannot change to first order, so
//!   the driven input has reached a limit of its motion (a rocker at the end of its
//!   swing, a piston driven onto dead centre);
//! - w lies on joint rows only: the joints themselves have become dependent and the
//!   mechanism gains an instantaneous freedom; two assembly branches meet there (a
//!   bifurcation, e.g. a parallelogram's change points).
//!
//! The estimate uses the factorization the position solve left (inverse iteration on
//! Phi_q^T Phi_q), so it costs a few triangular solves.

use crate::model::data::Data;
use crate::model::Model;

pub use crate::solve::events::{
    classify, constraint_shares, coordinate_shares, driver_share, Event, EventKind, SingularTriple,
    DRIVER_SHARE_TOL,
};

fn normalize(x: &mut [f64]) -> f64 {
    let n = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    if n > 0.0 && n.is_finite() {
        x.iter_mut().for_each(|v| *v /= n);
    }
    n
}

/// Estimates the smallest singular triple of the scaled Phi_q from the factorization in
/// `data` (left by the last position solve) by `iterations` steps of inverse iteration.
/// Each step divides the error by (sigma_min / sigma_next)^2, so near a singularity two
/// or three steps are plenty. Returns sigma = 0 if the factorization is singular.
pub fn smallest_singular(model: &Model, data: &mut Data, iterations: usize) -> SingularTriple {
    // w over the rows, v over the coordinates (more rows for a redundant model solved
    // anyway: then sigma_min is that of its QR's R, and the solves are least squares)
    let (n, m) = (model.n_coords, model.n_rows);
    let mut w: Vec<f64> = (0..m).map(|i| 1.0 + 0.1 * ((i * 7 + 3) % 11) as f64).collect();
    normalize(&mut w);
    let mut v = vec![0.0; n];
    let mut buf = vec![0.0; m];
    let mut sigma = 0.0;
    if !(data.pivots.det_sign != 0.0 && data.pivots.ratio > 0.0) {
        return SingularTriple { sigma: 0.0, v, w };
    }
    for _ in 0..iterations.max(1) {
        // v ~ Phi_q^-1 w, then w ~ Phi_q^-T v; |Phi_q^-T v| -> 1 / sigma_min
        buf.copy_from_slice(&w);
        data.factor.solve(&model.symbolic, &mut buf);
        v.copy_from_slice(&buf[..n]);
        if normalize(&mut v) <= 0.0 {
            return SingularTriple { sigma: 0.0, v, w };
        }
        buf[..n].copy_from_slice(&v);
        data.factor.solve_transpose(&model.symbolic, &mut buf);
        w.copy_from_slice(&buf);
        let norm = normalize(&mut w);
        if !(norm > 0.0 && norm.is_finite()) {
            return SingularTriple { sigma: 0.0, v, w };
        }
        sigma = 1.0 / norm;
    }
    SingularTriple { sigma, v, w }
}
