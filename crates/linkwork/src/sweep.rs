//! The time loop: for each time, predict q from the previous step, solve position,
//! velocity and acceleration, and store them with per-step diagnostics. Outputs are
//! allocated once, before the loop; a failure at step k keeps steps 0..k.

use crate::acceleration::solve_acceleration;
use crate::data::Data;
use crate::error::SolveError;
use crate::forces::{load_power, reactions, solve_forces, REACTION_COLUMNS};
use crate::joints::Constraint;
use crate::model::Model;
use crate::position::solve_position;
use crate::velocity::solve_velocity;

/// Results of a sweep: row-major (n_steps x n_coords) arrays and per-step diagnostics.
/// Only the first `n_done` rows are results; the rest were never reached.
#[derive(Debug, Clone, Default)]
pub struct SweepOutput {
    pub n_steps: usize,
    pub n_coords: usize,
    pub n_rows: usize,
    pub n_constraints: usize,
    /// steps completed
    pub n_done: usize,
    /// n_steps
    pub times: Vec<f64>,
    /// n_steps x n_coords
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    /// n_steps: Newton iterations (factorizations) of each step
    pub iterations: Vec<u32>,
    /// n_steps: scaled residual inf-norm at each step's last Newton evaluation
    pub residual: Vec<f64>,
    /// n_steps: smallest / largest pivot of the scaled Phi_q (0 at a singular configuration)
    pub pivot_ratio: Vec<f64>,
    /// whether the inverse dynamics stage runs (the arrays below are empty otherwise)
    pub forces: bool,
    /// n_steps x n_rows: Lagrange multipliers
    pub lambda: Vec<f64>,
    /// 3 x (n_steps x n_rows): lambda split into inertia, gravity and loads
    pub lambda_parts: [Vec<f64>; 3],
    /// n_steps x n_constraints x 4: each constraint's reaction on its side b (Fx, Fy in
    /// world axes, torque about its anchor) and the power it delivers
    pub reactions: Vec<f64>,
    /// n_steps: power of the applied loads, Q_loads . qd
    pub load_power: Vec<f64>,
}

impl SweepOutput {
    /// Preallocates the outputs of a sweep over `times`.
    pub fn new(model: &Model, times: &[f64]) -> SweepOutput {
        let (n, m) = (times.len(), model.n_coords);
        SweepOutput {
            n_steps: n,
            n_coords: m,
            n_rows: model.n_rows,
            n_constraints: model.constraints.len(),
            n_done: 0,
            times: times.to_vec(),
            q: vec![0.0; n * m],
            qd: vec![0.0; n * m],
            qdd: vec![0.0; n * m],
            iterations: vec![0; n],
            residual: vec![0.0; n],
            pivot_ratio: vec![0.0; n],
            forces: false,
            lambda: Vec::new(),
            lambda_parts: Default::default(),
            reactions: Vec::new(),
            load_power: Vec::new(),
        }
    }

    /// Preallocates the outputs of a sweep with inverse dynamics.
    pub fn with_forces(model: &Model, times: &[f64]) -> SweepOutput {
        let n = times.len();
        SweepOutput {
            forces: true,
            lambda: vec![0.0; n * model.n_rows],
            lambda_parts: std::array::from_fn(|_| vec![0.0; n * model.n_rows]),
            reactions: vec![0.0; n * model.constraints.len() * REACTION_COLUMNS],
            load_power: vec![0.0; n],
            ..SweepOutput::new(model, times)
        }
    }

    /// Drops the rows that were never reached.
    pub fn truncate(&mut self) {
        let (k, m) = (self.n_done, self.n_coords);
        self.n_steps = k;
        self.times.truncate(k);
        self.q.truncate(k * m);
        self.qd.truncate(k * m);
        self.qdd.truncate(k * m);
        self.iterations.truncate(k);
        self.residual.truncate(k);
        self.pivot_ratio.truncate(k);
        self.lambda.truncate(k * self.n_rows);
        for part in self.lambda_parts.iter_mut() {
            part.truncate(k * self.n_rows);
        }
        self.reactions.truncate(k * self.n_constraints * REACTION_COLUMNS);
        self.load_power.truncate(k);
    }
}

/// Checks that the times can be swept: finite, strictly monotone, inside every
/// driver's table.
pub fn check_times(model: &Model, times: &[f64]) -> Result<(), SolveError> {
    if times.is_empty() {
        return Err(SolveError::Times { step: 0, problem: "no times given".into() });
    }
    let direction = if times.len() > 1 { (times[1] - times[0]).signum() } else { 1.0 };
    for (k, &t) in times.iter().enumerate() {
        if !t.is_finite() {
            return Err(SolveError::Times { step: k, problem: format!("time {t} is not finite") });
        }
        if k > 0 && (t - times[k - 1]) * direction <= 0.0 {
            return Err(SolveError::Times {
                step: k,
                problem: format!("times must be strictly monotone ({} then {})", times[k - 1], t),
            });
        }
        let (lo, hi) = model.time_domain;
        if t < lo || t > hi {
            for c in &model.constraints {
                if let Some((start, end)) = c.kind.law().and_then(|l| l.domain()) {
                    if t < start || t > end {
                        return Err(SolveError::OutOfRange { driver: c.name.clone(), time: t, start, end });
                    }
                }
            }
        }
    }
    Ok(())
}

/// Sweeps `times`, starting from data.q (a configuration near the wanted branch at
/// times[0]). `progress(k)` is called every `progress_every` steps (0: never) and may
/// return false to cancel. On error, `out.n_done` steps are valid.
pub fn sweep(
    model: &Model,
    data: &mut Data,
    times: &[f64],
    out: &mut SweepOutput,
    progress_every: usize,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<(), SolveError> {
    check_times(model, times)?;
    let m = model.n_coords;
    out.n_done = 0;
    for (k, &t) in times.iter().enumerate() {
        if progress_every > 0 && k % progress_every == 0 && k > 0 && !progress(k) {
            return Err(SolveError::Cancelled { step: k });
        }
        if k > 0 {
            // second-order prediction from the previous step
            let h = t - times[k - 1];
            for ((q, qd), qdd) in data.q.iter_mut().zip(&data.qd).zip(&data.qdd) {
                *q += h * qd + 0.5 * h * h * qdd;
            }
        }
        let info = solve_position(model, data, t, k, k == 0)?;
        solve_velocity(model, data, t, k)?;
        solve_acceleration(model, data, t, k)?;
        if out.forces {
            solve_forces(model, data, t, k)?;
            let (r, nc) = (model.n_rows, model.constraints.len());
            out.lambda[k * r..(k + 1) * r].copy_from_slice(&data.lambda);
            for (o, l) in out.lambda_parts.iter_mut().zip(&data.lambda_parts) {
                o[k * r..(k + 1) * r].copy_from_slice(l);
            }
            let w = REACTION_COLUMNS * nc;
            reactions(model, data, t, &mut out.reactions[k * w..(k + 1) * w]);
            out.load_power[k] = load_power(data);
        }
        let row = k * m..(k + 1) * m;
        out.q[row.clone()].copy_from_slice(&data.q);
        out.qd[row.clone()].copy_from_slice(&data.qd);
        out.qdd[row].copy_from_slice(&data.qdd);
        out.iterations[k] = info.iterations as u32;
        out.residual[k] = info.residual;
        out.pivot_ratio[k] = info.pivot_ratio;
        out.n_done = k + 1;
    }
    Ok(())
}

/// Position, velocity and acceleration at one time, from data.q as the starting guess.
pub fn solve(model: &Model, data: &mut Data, t: f64) -> Result<crate::position::PositionInfo, SolveError> {
    check_times(model, &[t])?;
    let info = solve_position(model, data, t, 0, true)?;
    solve_velocity(model, data, t, 0)?;
    solve_acceleration(model, data, t, 0)?;
    Ok(info)
}
