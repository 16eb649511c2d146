//! The equations of motion at one state, on one workspace: the index-1 solve of the
//! accelerations and multipliers,
//!   [[M, Phi_q^T], [Phi_q, 0]] [qdd; lambda] = [Q_A; gamma],
//! and the projections of q onto Phi(q, t) = 0 and of qd onto Phi_q qd = nu, each the
//! smallest change in the mass metric (Gauss-Newton on the same augmented matrix).

use crate::constraints::Frame;
use crate::dynamics::applied::{applied_force, LoadJet};
use crate::dynamics::augmented::{Augmented, Equilibration};
use crate::dynamics::mass::mass_times;
use crate::math::pivots::Pivots;
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::assembly::{gamma, nu_into, update_frames};

/// Gauss-Newton iterations allowed to project positions.
pub const MAX_PROJECTION: usize = 50;
/// The scaled residual a projection stops at (round-off of unit-scaled rows).
pub const PROJECTION_TOL: f64 = 1e-15;

/// Where a positions' projection ended: its iterations, scaled |phi| before and after,
/// whether its last correction used factors of the iterate it started from, and whether
/// factors usable by the rates' projection are in place.
struct Settled {
    iterations: usize,
    before: f64,
    residual: f64,
    fresh: bool,
    factored: bool,
}

/// The workspace of the equations of motion of one model.
pub struct System {
    pub aug: Augmented,
    pub loads: Vec<LoadJet>,
    /// q, qd, the frames and gamma (`assembly::gamma`) live here
    pub data: Data,
    pub phi: Vec<f64>,
    /// n + m: right-hand side and solution of the augmented solves
    pub x: Vec<f64>,
    target: Vec<f64>,
    dq: Vec<f64>,
    /// m: Phi_q qd and nu of the rates' projection (kept here: it runs every output row)
    rate: Vec<f64>,
    nu: Vec<f64>,
    /// n: the iterate of the smallest |phi| of a projection (`project_state`)
    best: Vec<f64>,
    pub pivots: Pivots,
}

/// Largest |v|, NaN kept.
pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| if x.abs() > a || x.is_nan() { x.abs() } else { a })
}

impl System {
    pub fn new(model: &Model) -> System {
        let size = model.n_coords + model.n_rows;
        System {
            aug: Augmented::new(model),
            loads: model.loads.iter().map(LoadJet::new).collect(),
            data: Data::new(model),
            phi: vec![0.0; model.n_rows],
            x: vec![0.0; size],
            target: vec![0.0; model.n_coords],
            dq: vec![0.0; model.n_coords],
            rate: vec![0.0; model.n_rows],
            nu: vec![0.0; model.n_rows],
            best: vec![0.0; model.n_coords],
            pivots: Pivots::NONE,
        }
    }

    /// Sets the state the frames describe.
    pub fn set_state(&mut self, q: &[f64], qd: &[f64]) {
        self.data.q.copy_from_slice(q);
        self.data.qd.copy_from_slice(qd);
        update_frames(&mut self.data);
    }

    pub fn frames(&self) -> &[Frame] {
        &self.data.frames
    }

    /// qdd and the scaled multipliers at (q, qd, t), index-1; returns the pivots of the
    /// augmented matrix (regularised and refined where it is singular: `factor_solve`),
    /// equilibrated as `equilibration` says.
    #[allow(clippy::too_many_arguments)]
    pub fn accelerations(
        &mut self,
        model: &Model,
        q: &[f64],
        qd: &[f64],
        t: f64,
        qdd: &mut [f64],
        lambda: &mut [f64],
        equilibration: Equilibration,
    ) -> Pivots {
        let n = model.n_coords;
        self.set_state(q, qd);
        self.aug.fill(model, &self.data.frames, q, t, 1.0, &mut self.phi);
        applied_force(model, &self.data.frames, t, &mut self.x[..n]);
        gamma(model, &mut self.data, t);
        self.x[n..].copy_from_slice(&self.data.rhs);
        self.pivots = self.aug.factor_solve(&mut self.x, equilibration);
        qdd.copy_from_slice(&self.x[..n]);
        lambda.copy_from_slice(&self.x[n..]);
        self.pivots
    }

    /// Fills the augmented matrix and phi at positions q (the frames moved there) and
    /// returns the scaled |phi|: each projection iteration starts so.
    pub(crate) fn fill_at(&mut self, model: &Model, q: &[f64], t: f64) -> f64 {
        self.data.q.copy_from_slice(q);
        update_frames(&mut self.data);
        self.aug.fill(model, &self.data.frames, q, t, 1.0, &mut self.phi);
        max_abs(&self.phi)
    }

    /// Projects q onto Phi(q, t) = 0 by the smallest change in the mass metric; returns
    /// (iterations, scaled |phi| before, after). Stops when |phi| <= tol, when it no
    /// longer halves (round-off), or after `MAX_PROJECTION` iterations (the caller judges
    /// |phi|).
    pub fn project_positions(&mut self, model: &Model, q: &mut [f64], t: f64, tol: f64) -> (usize, f64, f64) {
        let n = model.n_coords;
        self.target.copy_from_slice(q);
        let (mut before, mut residual) = (f64::NAN, f64::NAN);
        let mut last = f64::INFINITY;
        for it in 0..MAX_PROJECTION {
            residual = self.fill_at(model, q, t);
            if it == 0 {
                before = residual;
            }
            // done, or stalled at round-off (no longer halving)
            if !residual.is_finite() || residual <= tol || residual > 0.5 * last {
                return (it, before, residual);
            }
            last = residual;
            for ((d, a), b) in self.dq.iter_mut().zip(&self.target).zip(q.iter()) {
                *d = a - b;
            }
            mass_times(model, &self.data.frames, &self.dq, &mut self.x[..n]);
            for (r, p) in self.x[n..].iter_mut().zip(&self.phi) {
                *r = -p;
            }
            self.pivots = self.aug.factor_solve(&mut self.x, Equilibration::New);
            for (qk, d) in q.iter_mut().zip(&self.x[..n]) {
                *qk += d;
            }
        }
        (MAX_PROJECTION, before, residual)
    }

    /// Projects q onto Phi(q, t) = 0, then qd onto Phi_q qd = nu, as `project_positions`
    /// and `project_velocities` do but on one factorization: a state near the constraints
    /// (a step's end, the dense output between) needs one Newton step, and simplified
    /// Newton with its factors brings both the positions and the rates to round-off; the
    /// matrix is factored again only where an iteration does not halve the residual.
    /// Its factorizations are equilibrated as `equilibration` says (`Kept` for an output row near
    /// the one before it: only round-off differs).
    /// Returns (iterations, scaled |phi| before, after, scaled |Phi_q qd - nu| before).
    pub fn project_state(
        &mut self,
        model: &Model,
        q: &mut [f64],
        qd: &mut [f64],
        t: f64,
        equilibration: Equilibration,
    ) -> (usize, f64, f64, f64) {
        let n = model.n_coords;
        let Settled { iterations, before, residual, mut fresh, mut factored } =
            self.settle_positions(model, q, t, equilibration);
        if !residual.is_finite() || residual > model.options.tol_residual {
            return (iterations, before, residual, f64::NAN);
        }
        // the Jacobian is filled at the projected q: the rates' corrections Phi_q d = nu -
        // Phi_q qd with the same factors (M d + Phi_q^T mu = 0), factored here if none is
        nu_into(model, t, &mut self.nu);
        let (mut before_d, mut last_d) = (f64::NAN, f64::INFINITY);
        for it in 0..6 {
            self.aug.jacobian_times(qd, &mut self.rate);
            let size = self.rate.iter().zip(&self.nu).fold(0.0f64, |a, (r, v)| a.max((r - v).abs()));
            let speed = qd.iter().zip(&model.col_scale).fold(0.0f64, |a, (v, s)| a.max((v / s).abs()));
            if it == 0 {
                before_d = size;
            }
            if !size.is_finite() || size <= PROJECTION_TOL * speed.max(1.0) || (size > 0.5 * last_d && fresh)
            {
                break;
            }
            if !factored || size > 0.5 * last_d {
                self.pivots = self.aug.factor_for_solve(equilibration);
                (factored, fresh) = (true, true);
            } else {
                fresh = false;
            }
            last_d = size;
            self.x[..n].fill(0.0);
            for ((x, r), v) in self.x[n..].iter_mut().zip(&self.rate).zip(&self.nu) {
                *x = v - r;
            }
            self.aug.solve_refined(&mut self.x);
            for (v, d) in qd.iter_mut().zip(&self.x[..n]) {
                *v += d;
            }
        }
        self.data.qd.copy_from_slice(qd);
        update_frames(&mut self.data);
        (iterations, before, residual, before_d)
    }

    /// The positions' part of `project_state`.
    fn settle_positions(
        &mut self,
        model: &Model,
        q: &mut [f64],
        t: f64,
        equilibration: Equilibration,
    ) -> Settled {
        let n = model.n_coords;
        self.target.copy_from_slice(q);
        let (mut before, mut residual) = (f64::NAN, f64::NAN);
        let mut last = f64::INFINITY;
        // whether the last correction was solved with factors of the iterate it started from
        let mut fresh = false;
        let mut factored = false;
        let mut iterations = 0;
        // unregularised Newton, after a regularised one stalled above tol_residual
        let mut exact = false;
        let mut best = f64::INFINITY;
        for it in 0..=MAX_PROJECTION {
            residual = self.fill_at(model, q, t);
            if it == 0 {
                before = residual;
            }
            let slow = residual > 0.5 * last;
            let stalled = slow && fresh;
            // next to a singular configuration the regularised corrections relax the rows
            // that become dependent, and Gauss-Newton stalls (or wanders) where a small
            // residual is left there: from the best iterate on, unregularised Newton steps
            // (their corrections along the weak directions as small as that residual)
            let failing = best > model.options.tol_residual && it < MAX_PROJECTION;
            if stalled && self.aug.regularised && !exact && failing {
                exact = true;
                if best < residual {
                    q.copy_from_slice(&self.best);
                    self.fill_at(model, q, t);
                    residual = best;
                }
            } else if !residual.is_finite()
                || residual <= PROJECTION_TOL
                || (stalled && !exact)
                || it == MAX_PROJECTION
            {
                break;
            }
            if residual < best {
                best = residual;
                self.best.copy_from_slice(q);
            }
            fresh = !factored || slow;
            if fresh {
                self.pivots = if exact {
                    self.aug.factor(0.0, equilibration)
                } else {
                    self.aug.factor_for_solve(equilibration)
                };
                factored = true;
            }
            last = residual;
            for ((d, a), b) in self.dq.iter_mut().zip(&self.target).zip(q.iter()) {
                *d = a - b;
            }
            mass_times(model, &self.data.frames, &self.dq, &mut self.x[..n]);
            for (r, p) in self.x[n..].iter_mut().zip(&self.phi) {
                *r = -p;
            }
            self.aug.solve_refined(&mut self.x);
            for (qk, d) in q.iter_mut().zip(&self.x[..n]) {
                *qk += d;
            }
            iterations = it + 1;
        }
        // after unregularised steps the rates' projection factors again, regularised as
        // before: an exact solve would turn their drift along the weak directions into
        // large rates
        Settled { iterations, before, residual, fresh, factored: factored && !exact }
    }

    /// Projects qd onto Phi_q qd = nu at q (one solve; the augmented matrix is filled at
    /// q here). Returns the scaled |Phi_q qd - nu| before the projection.
    pub fn project_velocities(&mut self, model: &Model, q: &[f64], qd: &mut [f64], t: f64) -> f64 {
        let n = model.n_coords;
        self.set_state(q, qd);
        self.aug.fill(model, &self.data.frames, q, t, 1.0, &mut self.phi);
        let before = self.velocity_drift(model, qd, t);
        mass_times(model, &self.data.frames, qd, &mut self.x[..n]);
        nu_into(model, t, &mut self.x[n..]);
        self.pivots = self.aug.factor_solve(&mut self.x, Equilibration::New);
        qd.copy_from_slice(&self.x[..n]);
        before
    }

    /// Scaled |Phi_q qd - nu| with the Jacobian last filled.
    pub fn velocity_drift(&mut self, model: &Model, qd: &[f64], t: f64) -> f64 {
        self.aug.jacobian_times(qd, &mut self.rate);
        nu_into(model, t, &mut self.nu);
        self.rate.iter().zip(&self.nu).fold(0.0f64, |a, (r, v)| a.max((r - v).abs()))
    }
}
