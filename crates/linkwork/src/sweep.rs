//! The time loop: for each time, predict q from the previous step, solve position,
//! velocity and acceleration, and store them with per-step diagnostics. Outputs are
//! allocated once, before the loop; a failure at step k keeps steps 0..k.

use crate::acceleration::solve_acceleration;
use crate::analysis::singular::Event;
use crate::analysis::tracking::{is_jump, OnSingular, Tracker};
use crate::data::Data;
use crate::error::SolveError;
use crate::forces::{load_power, reactions, solve_forces, REACTION_COLUMNS};
use crate::joints::Constraint;
use crate::model::Model;
use crate::position::solve_position;
use crate::velocity::solve_velocity;

/// A pivot ratio below this marks a step next to a singular configuration: the next
/// prediction does not use its rates: solved to round-off, q is off by about eps / ratio
/// along the near-singular direction, and the rates solved at that q are off by that over
/// the ratio again.
pub(crate) const NEAR_SINGULAR: f64 = 1e-6;

/// What a sweep computes and keeps: work that was not asked for is not done.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Request {
    /// 0: positions only; 1: and velocities; 2: and accelerations
    pub derivatives: u8,
    /// the inverse dynamics stage (needs derivatives = 2)
    pub forces: bool,
    /// keep every `every`-th step (steps 0, every, 2 every, ...); each kept row's
    /// diagnostics are the worst over the steps since the previous kept row
    pub every: usize,
    /// at a limit, bifurcation or branch jump: report and go on, or stop
    pub on_singular: OnSingular,
    /// also locate the locks of the outputs (links pinned to the ground, sliders), where
    /// an output stops and reverses; needs velocities
    pub locks: bool,
}

impl Default for Request {
    fn default() -> Self {
        Request { derivatives: 2, forces: false, every: 1, on_singular: OnSingular::Continue, locks: false }
    }
}

/// Results of a sweep: row-major (n_steps x n_coords) arrays and per-step diagnostics,
/// n_steps being the steps kept. Only the first `n_done` rows are results; the rest were
/// never reached.
#[derive(Debug, Clone, Default)]
pub struct SweepOutput {
    /// rows kept: ceil(times / every)
    pub n_steps: usize,
    pub n_coords: usize,
    pub n_rows: usize,
    pub n_constraints: usize,
    /// rows completed
    pub n_done: usize,
    pub request: Request,
    /// n_steps
    pub times: Vec<f64>,
    /// n_steps x n_coords (qd, qdd empty when not solved)
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    /// n_steps: Newton iterations (factorizations) of each step
    pub iterations: Vec<u32>,
    /// n_steps: scaled residual inf-norm at each step's last Newton evaluation
    pub residual: Vec<f64>,
    /// n_steps: smallest / largest pivot of the scaled Phi_q (0 at a singular configuration)
    pub pivot_ratio: Vec<f64>,
    /// n_steps x n_rows: Lagrange multipliers (empty without forces)
    pub lambda: Vec<f64>,
    /// 3 x (n_steps x n_rows): lambda split into inertia, gravity and loads
    pub lambda_parts: [Vec<f64>; 3],
    /// n_steps x n_constraints x 4: each constraint's reaction on its side b (Fx, Fy in
    /// world axes, torque about its anchor) and the power it delivers
    pub reactions: Vec<f64>,
    /// n_steps: power of the applied loads, Q_loads . qd
    pub load_power: Vec<f64>,
    /// n_steps: sign of det Phi_q at each kept step (flips where a singularity is crossed)
    pub det_sign: Vec<f64>,
    /// the located events, in time order: limits, bifurcations, locks, branch jumps
    pub events: Vec<Event>,
}

impl SweepOutput {
    /// Preallocates the outputs of a sweep over `times` (positions, velocities, accelerations).
    pub fn new(model: &Model, times: &[f64]) -> SweepOutput {
        SweepOutput::with_request(model, times, Request::default())
    }

    /// Positions only (`derivatives` 0), with velocities (1), or with accelerations (2).
    pub fn with_derivatives(model: &Model, times: &[f64], derivatives: u8) -> SweepOutput {
        SweepOutput::with_request(model, times, Request { derivatives, ..Request::default() })
    }

    /// With inverse dynamics.
    pub fn with_forces(model: &Model, times: &[f64]) -> SweepOutput {
        SweepOutput::with_request(model, times, Request { forces: true, ..Request::default() })
    }

    /// Preallocates what `request` asks for.
    pub fn with_request(model: &Model, times: &[f64], request: Request) -> SweepOutput {
        let every = request.every.max(1);
        let forces = request.forces;
        let d = if forces { 2 } else { request.derivatives.min(2) };
        let d = if request.locks { d.max(1) } else { d };
        let request = Request { derivatives: d, forces, every, ..request };
        let n = times.len().div_ceil(every);
        let (m, r, nc) = (model.n_coords, model.n_rows, model.constraints.len());
        let sized = |on: bool, len: usize| if on { vec![0.0; len] } else { Vec::new() };
        SweepOutput {
            n_steps: n,
            n_coords: m,
            n_rows: r,
            n_constraints: nc,
            n_done: 0,
            request,
            times: times.iter().step_by(every).copied().collect(),
            q: vec![0.0; n * m],
            qd: sized(d >= 1, n * m),
            qdd: sized(d >= 2, n * m),
            iterations: vec![0; n],
            residual: vec![0.0; n],
            pivot_ratio: vec![0.0; n],
            lambda: sized(forces, n * r),
            lambda_parts: std::array::from_fn(|_| sized(forces, n * r)),
            reactions: sized(forces, n * nc * REACTION_COLUMNS),
            load_power: sized(forces, n),
            det_sign: vec![0.0; n],
            events: Vec::new(),
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
        self.det_sign.truncate(k);
    }

    /// Stores the state in `data` as row `row`.
    fn store(&mut self, model: &Model, data: &Data, t: f64, row: usize) {
        let m = self.n_coords;
        let cells = row * m..(row + 1) * m;
        self.q[cells.clone()].copy_from_slice(&data.q);
        if self.request.derivatives >= 1 {
            self.qd[cells.clone()].copy_from_slice(&data.qd);
        }
        if self.request.derivatives >= 2 {
            self.qdd[cells].copy_from_slice(&data.qdd);
        }
        if self.request.forces {
            let r = self.n_rows;
            self.lambda[row * r..(row + 1) * r].copy_from_slice(&data.lambda);
            for (o, l) in self.lambda_parts.iter_mut().zip(&data.lambda_parts) {
                o[row * r..(row + 1) * r].copy_from_slice(l);
            }
            let w = REACTION_COLUMNS * self.n_constraints;
            reactions(model, data, t, &mut self.reactions[row * w..(row + 1) * w]);
            self.load_power[row] = load_power(data);
        }
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
    let req = out.request;
    out.n_done = 0;
    out.events.clear();
    data.with_velocity = req.derivatives >= 1;
    let mut tracker = Tracker::new(model, req.on_singular, req.locks);
    let result = sweep_steps(model, data, times, out, &mut tracker, progress_every, progress);
    out.events = std::mem::take(&mut tracker.events);
    result
}

fn sweep_steps(
    model: &Model,
    data: &mut Data,
    times: &[f64],
    out: &mut SweepOutput,
    tracker: &mut Tracker,
    progress_every: usize,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<(), SolveError> {
    let req = out.request;
    // worst diagnostics since the last kept row
    let (mut iterations, mut residual, mut pivot_ratio) = (0u32, 0.0f64, f64::INFINITY);
    for (k, &t) in times.iter().enumerate() {
        if progress_every > 0 && k % progress_every == 0 && k > 0 && !progress(k) {
            return Err(SolveError::Cancelled { step: k });
        }
        let info = if k == 0 {
            solve_position(model, data, t, k, true)?
        } else {
            tracker.q_prev.copy_from_slice(&data.q);
            // rates next to a singular configuration are unreliable: predict from positions
            let predictor = match req.derivatives {
                _ if data.pivots.ratio < NEAR_SINGULAR => Predictor::Quadratic,
                2 => Predictor::Jerk,
                1 => Predictor::Acceleration,
                _ => Predictor::Cubic,
            };
            predict(data, times, k, predictor);
            let motion = data
                .q
                .iter()
                .zip(&tracker.q_prev)
                .zip(&data.inv_col_scale)
                .fold(0.0f64, |m, ((q, p), s)| m.max((q - p).abs() * s));
            let info = match solve_position(model, data, t, k, false) {
                Ok(info) if !is_jump(&info, motion) => info,
                Ok(_) => tracker.rescue(model, data, times[k - 1], t, k, None)?,
                Err(e @ SolveError::NonFinite { .. }) => return Err(e),
                Err(e) => tracker.rescue(model, data, times[k - 1], t, k, Some(e))?,
            };
            tracker.after_position(model, data, info, times[k - 1], t, k)?
        };
        if req.derivatives >= 1 {
            solve_velocity(model, data, t, k)?;
        }
        if req.derivatives >= 2 {
            solve_acceleration(model, data, t, k)?;
        }
        if k == 0 {
            tracker.start(&info, data);
        } else if req.locks {
            tracker.after_velocity(model, data, times[k - 1], t, k)?;
        }
        iterations = iterations.max(info.iterations as u32);
        residual = residual.max(info.residual);
        pivot_ratio = pivot_ratio.min(info.pivot_ratio);
        if k % req.every == 0 {
            if req.forces {
                solve_forces(model, data, t, k)?;
            }
            let row = k / req.every;
            out.store(model, data, t, row);
            out.iterations[row] = iterations;
            out.residual[row] = residual;
            out.pivot_ratio[row] = pivot_ratio;
            out.det_sign[row] = info.det_sign;
            out.n_done = row + 1;
            (iterations, residual, pivot_ratio) = (0, 0.0, f64::INFINITY);
        }
    }
    Ok(())
}

/// How `predict` extrapolates q to the next time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Predictor {
    /// q + h qd + h^2/2 qdd + h^3/6 jerk, the jerk from the last two accelerations
    Jerk,
    /// q + h qd + h^2/2 qdd, qdd from the last two velocities
    Acceleration,
    /// the quadratic through the last three positions
    Quadratic,
    /// the cubic through the last four positions
    Cubic,
}

/// Predicts q at times[k] from the previous steps, by what the sweep computes: with
/// accelerations `Jerk`, with velocities `Acceleration`, positions only `Cubic`.
/// Their local errors are O(h^3) (`Acceleration`) or O(h^4) (`Jerk`, `Cubic`: with
/// positions only, a quadratic's O(h^3) left 15 % of a fine sweep's steps needing a
/// second Newton iteration), so that most steps take one Newton iteration. After a step close to a singular
/// configuration, whose rates are ill-determined (and may point along the other branch),
/// the sweep asks for `Quadratic`: positions only, and of low order, as the last
/// positions may be packed close there (a higher order amplifies their round-off).
/// Reads data.q, qd, qdd (step k-1) and the history; shifts the history.
pub(crate) fn predict(data: &mut Data, times: &[f64], k: usize, predictor: Predictor) {
    let t = times[k];
    let t1 = times[k - 1];
    let h = t - t1;
    let h1 = if k >= 2 { t1 - times[k - 2] } else { 0.0 };
    // Lagrange weights of the (up to) four previous positions, newest first, the same for
    // every coordinate
    let lagrange = |nodes: &[f64]| -> [f64; 4] {
        let mut w = [0.0; 4];
        for (a, &ta) in nodes.iter().enumerate() {
            w[a] = nodes
                .iter()
                .enumerate()
                .filter(|&(b, _)| b != a)
                .map(|(_, &tb)| (t - tb) / (ta - tb))
                .product();
        }
        w
    };
    let w = match (predictor, k) {
        (Predictor::Jerk | Predictor::Acceleration, _) | (_, 1) => [1.0, 0.0, 0.0, 0.0],
        (_, 2) => lagrange(&[t1, times[0]]),
        (Predictor::Quadratic, _) | (_, 3) => lagrange(&[t1, times[k - 2], times[k - 3]]),
        _ => lagrange(&[t1, times[k - 2], times[k - 3], times[k - 4]]),
    };
    let [q2, q3, q4] = &mut data.hist_q;
    for i in 0..data.q.len() {
        let q1 = data.q[i];
        let p = match predictor {
            Predictor::Jerk => {
                let jerk = if k >= 2 { (data.qdd[i] - data.hist_qdd[i]) / h1 } else { 0.0 };
                q1 + h * (data.qd[i] + h * (0.5 * data.qdd[i] + h * jerk / 6.0))
            }
            Predictor::Acceleration => {
                let acc = if k >= 2 { (data.qd[i] - data.hist_qd[i]) / h1 } else { 0.0 };
                q1 + h * (data.qd[i] + 0.5 * h * acc)
            }
            Predictor::Quadratic | Predictor::Cubic => w[0] * q1 + w[1] * q2[i] + w[2] * q3[i] + w[3] * q4[i],
        };
        data.hist_qdd[i] = data.qdd[i];
        data.hist_qd[i] = data.qd[i];
        q4[i] = q3[i];
        q3[i] = q2[i];
        q2[i] = q1;
        data.q[i] = p;
    }
}

/// Position, velocity and acceleration at one time, from data.q as the starting guess.
pub fn solve(model: &Model, data: &mut Data, t: f64) -> Result<crate::position::PositionInfo, SolveError> {
    check_times(model, &[t])?;
    data.with_velocity = true;
    let info = solve_position(model, data, t, 0, true)?;
    solve_velocity(model, data, t, 0)?;
    solve_acceleration(model, data, t, 0)?;
    Ok(info)
}
