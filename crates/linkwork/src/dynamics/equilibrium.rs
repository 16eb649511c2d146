//! Static equilibrium: the configuration at rest under the loads at time t (gravity,
//! springs, applied forces and torques; drivers hold their coordinates),
//!   Q_A(q, 0, t) - Phi_q^T lambda = 0,   Phi(q, t) = 0,
//! by Newton with the exact tangent K_t = K + d(Phi_q^T lambda)/dq (K = -dQ_A/dq from the
//! loads' jets, the constraint forces' curvature from the joints' jets). Each iteration
//! works in the scaled coordinates (x, y / L; theta) on a basis of Phi_q's null space (a
//! dense SVD: the sizes are small, and redundant rows are handled alike): the step puts q
//! back on the constraints by the smallest move and balances the forces along the free
//! motions, lambda comes from the least-squares balance across them. Globalized by a
//! backtracking line search on the residual, and Levenberg-Marquardt damping of the
//! reduced stiffness where it is singular or the step does not reduce the residual.

use nalgebra::{DMatrix, DVector};
use thiserror::Error;

use crate::constraints::{Constraint, Frame, Rows};
use crate::dynamics::applied::{applied_force, tangents, LoadJet};
use crate::dynamics::curvature::{add_constraint_curvature, ConstraintJet};
use crate::dynamics::mass::frames_of;
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::assembly::update_frames;
use crate::solve::forces::{reactions, REACTION_COLUMNS};

/// Settings of the equilibrium solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EqOptions {
    /// Newton iterations allowed
    pub max_iter: usize,
    /// the unbalanced generalized force allowed, relative to the largest applied one
    pub tol_force: f64,
    /// the largest scaled move of one iteration (x, y / L; theta in rad)
    pub max_step: f64,
}

impl Default for EqOptions {
    fn default() -> EqOptions {
        EqOptions { max_iter: 100, tol_force: 1e-12, max_step: 0.5 }
    }
}

impl EqOptions {
    /// Why the settings cannot be used, if they cannot.
    pub fn check(&self) -> Result<(), String> {
        if self.max_iter == 0 {
            return Err("max_iter must be at least 1".into());
        }
        if !(self.tol_force > 0.0 && self.tol_force < 1.0) {
            return Err(format!("tol_force must be in (0, 1), not {}", self.tol_force));
        }
        if !(self.max_step > 0.0 && self.max_step.is_finite()) {
            return Err(format!("max_step must be positive, not {}", self.max_step));
        }
        Ok(())
    }
}

/// No rest configuration found: the last iterate is kept.
#[derive(Debug, Clone, PartialEq, Error)]
#[error(
    "no equilibrium found at t = {time}: {why}; after {iterations} iterations the unbalanced \
     generalized force is {force:.3e} (largest on {coordinate}) and |phi| {phi:.3e}"
)]
pub struct NotConverged {
    pub time: f64,
    pub iterations: usize,
    /// the unbalanced generalized force along the free motions (scaled coordinates:
    /// the model's energy unit)
    pub force: f64,
    /// scaled |Phi|
    pub phi: f64,
    pub coordinate: String,
    pub why: &'static str,
    /// the last iterate
    pub q: Vec<f64>,
}

/// A rest configuration and what stability and modes need at it.
#[derive(Debug, Clone)]
pub struct Equilibrium {
    pub t: f64,
    pub q: Vec<f64>,
    /// the multipliers of the scaled rows (length rows / L)
    pub lambda: Vec<f64>,
    pub iterations: usize,
    /// the unbalanced generalized force along the free motions (scaled coordinates)
    pub force: f64,
    /// scaled |Phi|
    pub phi: f64,
    /// the largest applied generalized force met (scaled coordinates): the force scale
    pub force_scale: f64,
    /// the tangent stiffness S K_t S in the scaled coordinates (n x n)
    pub stiffness: DMatrix<f64>,
    /// an orthonormal basis of Phi_q's null space in the scaled coordinates (n x dof)
    pub null_basis: DMatrix<f64>,
}

/// Everything one configuration gives (scaled coordinates).
struct Eval {
    phi: DVector<f64>,
    /// Q_A in the scaled coordinates: col_scale * Q
    force: DVector<f64>,
    /// U_r, sigma_r, V_r of Phi_q's range and N its null space
    u: DMatrix<f64>,
    sigma: Vec<f64>,
    v: DMatrix<f64>,
    null: DMatrix<f64>,
    lambda: DVector<f64>,
    /// N^T Q_s: the unbalanced force along the free motions
    unbalanced: DVector<f64>,
}

impl Eval {
    fn merit(&self, f_scale: f64) -> f64 {
        (self.unbalanced.norm() / f_scale).powi(2) + self.phi.norm_squared()
    }
}

fn max_abs(v: &DVector<f64>) -> f64 {
    v.iter().fold(0.0f64, |a, x| if x.abs() > a || x.is_nan() { x.abs() } else { a })
}

/// Phi (scaled rows) and the scaled Jacobian Phi_q S (m x n) at q, time t.
pub fn constraints_dense(model: &Model, frames: &[Frame], q: &[f64], t: f64) -> (DVector<f64>, DMatrix<f64>) {
    let (n, m) = (model.n_coords, model.n_rows);
    let mut phi = DVector::zeros(m);
    let mut jac = DMatrix::zeros(m, n);
    let side = |b: Option<usize>| b.map_or(&Frame::GROUND, |i| &frames[i]);
    for c in &model.constraints {
        let mut rows = Rows::default();
        c.kind.position(side(c.body_a), side(c.body_b), &c.extra(q, &[]), t, &mut rows);
        for i in 0..c.n_rows {
            let (r, rs) = (c.row0 + i, c.row_scale[i]);
            phi[r] = rows.phi[i] * rs;
            for j in 0..3 {
                if let Some(a) = c.body_a {
                    jac[(r, 3 * a + j)] += rows.jac_a[i][j] * rs;
                }
                if let Some(b) = c.body_b {
                    jac[(r, 3 * b + j)] += rows.jac_b[i][j] * rs;
                }
            }
            if let Some(k) = c.extra {
                jac[(r, k)] += rows.jac_s[i] * rs;
            }
        }
    }
    for (j, s) in model.col_scale.iter().enumerate() {
        jac.column_mut(j).scale_mut(*s);
    }
    (phi, jac)
}

/// The frames at rest at q.
pub fn rest_frames(model: &Model, q: &[f64]) -> Vec<Frame> {
    let mut frames = vec![Frame::GROUND; model.n_bodies];
    frames_of(q, &vec![0.0; q.len()], &mut frames);
    frames
}

fn evaluate(model: &Model, q: &[f64], t: f64) -> Eval {
    let (n, m) = (model.n_coords, model.n_rows);
    let frames = rest_frames(model, q);
    let (phi, jac) = constraints_dense(model, &frames, q, t);
    let mut qa = vec![0.0; n];
    applied_force(model, &frames, t, &mut qa);
    let force = DVector::from_iterator(n, qa.iter().zip(&model.col_scale).map(|(f, s)| f * s));
    // padded to n x n so that the SVD's V is complete: the zero rows add zero values
    let mut padded = DMatrix::zeros(n, n);
    padded.rows_mut(0, m.min(n)).copy_from(&jac.rows(0, m.min(n)));
    let svd = padded.svd(true, true);
    let (u_all, vt_all) = (svd.u.expect("asked for U"), svd.v_t.expect("asked for V^T"));
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
    let top = order.first().map_or(0.0, |&k| svd.singular_values[k]);
    // rows dependent to round-off count as one (a redundant model's rank)
    let rank = order.iter().filter(|&&k| svd.singular_values[k] > 1e-10 * top && top > 0.0).count();
    let pick = |mat: &DMatrix<f64>, ks: &[usize], rows: usize| {
        DMatrix::from_fn(rows, ks.len(), |i, j| mat[(i, ks[j])])
    };
    let vt_t = vt_all.transpose();
    let (range, free) = order.split_at(rank);
    let u = pick(&u_all, range, m.min(n));
    let v = pick(&vt_t, range, n);
    let null = pick(&vt_t, free, n);
    let sigma: Vec<f64> = range.iter().map(|&k| svd.singular_values[k]).collect();
    // least squares J^T lambda = Q_s: lambda = U_r sigma^-1 V_r^T Q_s
    let mut c = v.transpose() * &force;
    for (x, s) in c.iter_mut().zip(&sigma) {
        *x /= s;
    }
    let mut lambda = DVector::zeros(m);
    if rank > 0 {
        lambda.rows_mut(0, m.min(n)).copy_from(&(&u * c));
    }
    let unbalanced = null.transpose() * &force;
    Eval { phi, force, u, sigma, v, null, lambda, unbalanced }
}

/// S K_t S: the tangent stiffness of the equilibrium equations in the scaled coordinates.
fn stiffness(
    model: &Model,
    loads: &[LoadJet],
    cj: &[ConstraintJet],
    q: &[f64],
    lambda: &[f64],
    t: f64,
) -> DMatrix<f64> {
    let n = model.n_coords;
    let mut k = vec![0.0; n * n];
    let zeros = vec![0.0; n];
    tangents(model, loads, q, &zeros, &zeros, t, &mut |b| {
        for j in 0..3 {
            for l in 0..3 {
                k[(3 * b.row + j) * n + 3 * b.col + l] += b.k[j][l];
            }
        }
    });
    add_constraint_curvature(model, cj, q, lambda, t, &mut k);
    let s = &model.col_scale;
    DMatrix::from_fn(n, n, |i, j| k[i * n + j] * s[i] * s[j])
}

/// The coordinate where a vector of the scaled coordinates is largest.
pub fn largest_column(v: &DVector<f64>) -> usize {
    v.iamax()
}

/// Solves for the rest configuration from `q_guess` (default: the drawing).
pub fn equilibrium(
    model: &Model,
    t: f64,
    q_guess: Option<&[f64]>,
    opts: &EqOptions,
) -> Result<Equilibrium, NotConverged> {
    let loads: Vec<LoadJet> = model.loads.iter().map(LoadJet::new).collect();
    let cj = ConstraintJet::all(model);
    let s = DVector::from_column_slice(&model.col_scale);
    let mut q = q_guess.map_or_else(|| model.q_start.clone(), |g| g.to_vec());
    let mut ev = evaluate(model, &q, t);
    let mut f_scale = max_abs(&ev.force);
    let tol_phi = model.options.tol_residual;
    let mut mu = 0.0;
    let mut iterations = 0;
    let fail = |ev: &Eval, q: &[f64], iterations: usize, why: &'static str| {
        let along = &ev.null * &ev.unbalanced;
        let col = if along.is_empty() { 0 } else { largest_column(&along) };
        NotConverged {
            time: t,
            iterations,
            force: max_abs(&ev.unbalanced),
            phi: max_abs(&ev.phi),
            coordinate: model.columns.get(col).cloned().unwrap_or_default(),
            why,
            q: q.to_vec(),
        }
    };
    loop {
        if !(ev.phi.iter().chain(ev.force.iter()).all(|v| v.is_finite())) {
            return Err(fail(&ev, &q, iterations, "a non-finite force or residual appeared"));
        }
        let scale = if f_scale > 0.0 { f_scale } else { 1.0 };
        let (force, phi) = (max_abs(&ev.unbalanced), max_abs(&ev.phi));
        if force <= opts.tol_force * scale && phi <= tol_phi {
            break;
        }
        if iterations >= opts.max_iter {
            return Err(fail(&ev, &q, iterations, "the iterations allowed (max_iter) are spent"));
        }
        iterations += 1;
        let lambda: Vec<f64> = ev.lambda.iter().copied().collect();
        let k_s = stiffness(model, &loads, &cj, &q, &lambda, t);
        // back onto the constraints by the smallest move: -V_r sigma^-1 U_r^T phi
        let mut c = ev.u.transpose() * ev.phi.rows(0, ev.u.nrows());
        for (x, sg) in c.iter_mut().zip(&ev.sigma) {
            *x /= -sg;
        }
        let dq_p = &ev.v * c;
        // the forces balanced along the free motions: N^T K N b = N^T (Q_s - K dq_p)
        let k_r = ev.null.transpose() * &k_s * &ev.null;
        let rhs = ev.null.transpose() * (&ev.force - &k_s * &dq_p);
        let k_scale = k_r.amax().max(scale);
        let merit0 = ev.merit(scale);
        let mut accepted = None;
        for _ in 0..16 {
            let mut a = k_r.clone();
            for i in 0..a.nrows() {
                a[(i, i)] += mu;
            }
            let b = if a.nrows() == 0 { Some(DVector::zeros(0)) } else { a.lu().solve(&rhs) };
            let Some(b) = b.filter(|b| b.iter().all(|v| v.is_finite())) else {
                mu = (10.0 * mu).max(1e-6 * k_scale);
                continue;
            };
            let mut dq = &dq_p + &ev.null * b;
            let big = max_abs(&dq);
            if big > opts.max_step {
                dq *= opts.max_step / big;
            }
            let mut alpha = 1.0;
            for _ in 0..12 {
                let trial: Vec<f64> =
                    q.iter().zip(dq.iter().zip(s.iter())).map(|(x, (d, sc))| x + alpha * d * sc).collect();
                let e = evaluate(model, &trial, t);
                let m1 = e.merit(scale);
                // sufficient decrease, or both residuals at the tolerances already
                let done = max_abs(&e.unbalanced) <= opts.tol_force * scale && max_abs(&e.phi) <= tol_phi;
                if m1.is_finite() && (m1 <= (1.0 - 1e-4 * alpha) * merit0 || done) {
                    accepted = Some((trial, e));
                    break;
                }
                alpha *= 0.5;
            }
            if accepted.is_some() {
                break;
            }
            mu = (10.0 * mu).max(1e-6 * k_scale);
        }
        let Some((trial, e)) = accepted else {
            // at the round-off floor of the residuals: as balanced as they can be computed
            if force <= 1e3 * opts.tol_force * scale && phi <= 1e3 * tol_phi {
                break;
            }
            return Err(fail(
                &ev,
                &q,
                iterations,
                "no step reduces the residual from here (no rest position nearby, or the loads cannot balance)",
            ));
        };
        // the damping relaxes as the steps succeed: Newton's quadratic convergence near the root
        mu = if mu > 1e-12 * k_scale { 0.1 * mu } else { 0.0 };
        q = trial;
        ev = e;
        f_scale = f_scale.max(max_abs(&ev.force));
    }
    let lambda: Vec<f64> = ev.lambda.iter().copied().collect();
    let stiffness = stiffness(model, &loads, &cj, &q, &lambda, t);
    Ok(Equilibrium {
        t,
        q,
        lambda,
        iterations,
        force: max_abs(&ev.unbalanced),
        phi: max_abs(&ev.phi),
        force_scale: f_scale,
        stiffness,
        null_basis: ev.null,
    })
}

impl Equilibrium {
    /// The multipliers in the rows' units and each constraint's reaction on its side b
    /// (Fx, Fy, torque about its anchor, power: `forces::reactions`) at rest.
    pub fn reactions(&self, model: &Model) -> (Vec<f64>, Vec<f64>) {
        let mut data = Data::new(model);
        data.q.copy_from_slice(&self.q);
        for c in &model.constraints {
            for i in 0..c.n_rows {
                data.lambda[c.row0 + i] = self.lambda[c.row0 + i] * c.row_scale[i];
            }
        }
        update_frames(&mut data);
        let mut out = vec![0.0; REACTION_COLUMNS * model.constraints.len()];
        reactions(model, &data, self.t, &mut out);
        (data.lambda, out)
    }
}
