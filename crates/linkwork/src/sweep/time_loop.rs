//! The time loop: for each time, predict q from the previous step, solve position,
//! velocity and acceleration, and store them with per-step diagnostics. Outputs are
//! allocated once, before the loop; a failure at step k keeps steps 0..k.

use crate::constraints::Constraint;
use crate::error::SolveError;
use crate::math::pivots::NEAR_SINGULAR;
use crate::model::data::Data;
use crate::model::memory::zeroed;
use crate::model::Model;
use crate::solve::acceleration::solve_acceleration;
use crate::solve::closed_form::{self, Block};
use crate::solve::forces::{load_power, reactions, solve_forces, REACTION_COLUMNS};
use crate::solve::position::solve_position;
use crate::solve::position::PositionInfo;
use crate::solve::velocity::solve_velocity;
use crate::sweep::stepping::branch::{continues, continues_storing, Row};
use crate::sweep::stepping::predict::{predict, Predictor};
use crate::sweep::stepping::singular::Event;
use crate::sweep::stepping::tracking::JUMP_RATIO;
use crate::sweep::stepping::tracking::{is_jump, OnSingular, Tracker, JUMP_FLOOR, JUMP_FLOOR_RATES};

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

/// Which coordinates and body points a sweep keeps; the default keeps every coordinate
/// and no point. What is not kept is neither stored nor allocated.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Outputs {
    /// the columns of q (and qd, qdd) kept, in this order; None: all of them
    pub coords: Option<Vec<usize>>,
    /// body points (the body, None for the ground; the point in its frame) whose world
    /// position, and velocity and acceleration as the request's derivatives say, are kept
    pub points: Vec<(Option<usize>, [f64; 2])>,
}

impl Outputs {
    /// Every coordinate, no point: what a sweep keeps unless told otherwise.
    pub fn all() -> Outputs {
        Outputs::default()
    }

    /// Columns per row of q: the kept coordinates.
    pub fn n_kept(&self, model: &Model) -> usize {
        self.coords.as_ref().map_or(model.n_coords, Vec::len)
    }

    /// Refuses a coordinate or body that the model does not have.
    pub fn check(&self, model: &Model) -> Result<(), SolveError> {
        let bad = |problem: String| Err(SolveError::Outputs { problem });
        if let Some(c) = self.coords.as_ref().and_then(|c| c.iter().find(|&&c| c >= model.n_coords)) {
            return bad(format!("coordinate {c} does not exist (the model has {})", model.n_coords));
        }
        if let Some((b, _)) = self
            .points
            .iter()
            .find(|(b, u)| b.is_some_and(|b| b >= model.n_bodies) || !u.iter().all(|x| x.is_finite()))
        {
            return bad(format!("point on body {b:?}: no such body, or a coordinate that is not finite"));
        }
        Ok(())
    }
}

/// Results of a sweep: row-major (n_steps x n_kept) arrays and per-step diagnostics,
/// n_steps being the steps kept. Only the first `n_done` rows are results; the rest were
/// never reached.
#[derive(Debug, Clone, Default)]
pub struct SweepOutput {
    /// rows kept: ceil(times / every)
    pub n_steps: usize,
    pub n_coords: usize,
    /// columns of q, qd, qdd: the coordinates `outputs` keeps (n_coords by default)
    pub n_kept: usize,
    pub n_rows: usize,
    pub n_constraints: usize,
    /// rows completed
    pub n_done: usize,
    pub request: Request,
    /// n_steps
    pub times: Vec<f64>,
    /// what is kept of the coordinates and which body points
    pub outputs: Outputs,
    /// n_steps x n_kept (qd, qdd empty when not solved)
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    /// n_steps x outputs.points.len() x 2: the points' world positions, velocities, accelerations
    /// (empty when not solved)
    pub points: Vec<f64>,
    pub points_d: Vec<f64>,
    pub points_dd: Vec<f64>,
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

    /// Preallocates what `request` asks for, every coordinate kept.
    pub fn with_request(model: &Model, times: &[f64], request: Request) -> SweepOutput {
        SweepOutput::with_outputs(model, times, request, Outputs::all())
    }

    /// Preallocates what `request` asks for, of the coordinates and points in `outputs`
    /// (checked by `Outputs::check`).
    pub fn with_outputs(model: &Model, times: &[f64], request: Request, outputs: Outputs) -> SweepOutput {
        let every = request.every.max(1);
        let forces = request.forces;
        let d = if forces { 2 } else { request.derivatives.min(2) };
        let d = if request.locks { d.max(1) } else { d };
        let request = Request { derivatives: d, forces, every, ..request };
        let n = times.len().div_ceil(every);
        let (r, nc) = (model.n_rows, model.constraints.len());
        let (m, np) = (outputs.n_kept(model), outputs.points.len());
        let sized = |on: bool, len: usize| if on { zeroed(len) } else { Vec::new() };
        SweepOutput {
            n_steps: n,
            n_coords: model.n_coords,
            n_kept: m,
            n_rows: r,
            n_constraints: nc,
            n_done: 0,
            request,
            times: times.iter().step_by(every).copied().collect(),
            outputs,
            q: zeroed(n * m),
            qd: sized(d >= 1, n * m),
            qdd: sized(d >= 2, n * m),
            points: zeroed(n * np * 2),
            points_d: sized(d >= 1, n * np * 2),
            points_dd: sized(d >= 2, n * np * 2),
            iterations: zeroed(n),
            residual: zeroed(n),
            pivot_ratio: zeroed(n),
            lambda: sized(forces, n * r),
            lambda_parts: std::array::from_fn(|_| sized(forces, n * r)),
            reactions: sized(forces, n * nc * REACTION_COLUMNS),
            load_power: sized(forces, n),
            det_sign: zeroed(n),
            events: Vec::new(),
        }
    }

    /// The bytes the outputs of a sweep of `n_times` times would take (as `with_request`
    /// allocates them), and what they hold, for the refusal message.
    pub fn bytes(model: &Model, n_times: usize, request: Request, outputs: &Outputs) -> (usize, String) {
        let probe = SweepOutput::with_request(model, &[], request);
        let req = probe.request;
        let n = n_times.div_ceil(req.every.max(1));
        let (r, nc) = (model.n_rows, model.constraints.len());
        // per step, each derivative solved: the kept coordinates and the points' x, y
        let m = outputs.n_kept(model) + 2 * outputs.points.len();
        let f = std::mem::size_of::<f64>();
        let mut per_step = (3 * f + std::mem::size_of::<u32>() + f) + m * f; // diagnostics, times, q
        let mut what = vec!["q"];
        if req.derivatives >= 1 {
            per_step += m * f;
            what.push("qd");
        }
        if req.derivatives >= 2 {
            per_step += m * f;
            what.push("qdd");
        }
        if req.forces {
            per_step += (4 * r + nc * REACTION_COLUMNS + 1) * f;
            what.push("forces");
        }
        (n.saturating_mul(per_step), format!(": {}", what.join(", ")))
    }

    /// `with_request`, refusing (instead of aborting the process) outputs that cannot be
    /// allocated or that exceed `available` bytes.
    pub fn try_with_request(
        model: &Model,
        times: &[f64],
        request: Request,
        available: Option<usize>,
    ) -> Result<SweepOutput, SolveError> {
        SweepOutput::try_with_outputs(model, times, request, Outputs::all(), available)
    }

    /// `with_outputs`, checking `outputs` and refusing (instead of aborting the process)
    /// outputs that cannot be allocated or that exceed `available` bytes.
    pub fn try_with_outputs(
        model: &Model,
        times: &[f64],
        request: Request,
        outputs: Outputs,
        available: Option<usize>,
    ) -> Result<SweepOutput, SolveError> {
        outputs.check(model)?;
        let (bytes, what) = SweepOutput::bytes(model, times.len(), request, &outputs);
        let too_large = || SolveError::TooLarge {
            bytes,
            available,
            steps: times.len().div_ceil(request.every.max(1)),
            n_coords: outputs.n_kept(model) + 2 * outputs.points.len(),
            what: what.clone(),
        };
        if available.is_some_and(|a| bytes > a) {
            return Err(too_large());
        }
        // allocate once, fallibly, to find out whether the allocator can give that much
        let mut probe: Vec<u8> = Vec::new();
        probe.try_reserve_exact(bytes).map_err(|_| too_large())?;
        drop(probe);
        Ok(SweepOutput::with_outputs(model, times, request, outputs))
    }

    /// Drops the rows that were never reached.
    pub fn truncate(&mut self) {
        let (k, m, p) = (self.n_done, self.n_kept, 2 * self.outputs.points.len());
        self.n_steps = k;
        self.times.truncate(k);
        self.q.truncate(k * m);
        self.qd.truncate(k * m);
        self.qdd.truncate(k * m);
        self.points.truncate(k * p);
        self.points_d.truncate(k * p);
        self.points_dd.truncate(k * p);
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

    /// Stores row `row` of the kept coordinates' q, qd, qdd (as the request keeps them).
    fn store_coords(&mut self, data: &Data, row: usize) {
        let d = self.request.derivatives;
        let m = self.n_kept;
        let cells = row * m..(row + 1) * m;
        match &self.outputs.coords {
            None => {
                self.q[cells.clone()].copy_from_slice(&data.q);
                if d >= 1 {
                    self.qd[cells.clone()].copy_from_slice(&data.qd);
                }
                if d >= 2 {
                    self.qdd[cells].copy_from_slice(&data.qdd);
                }
            }
            Some(coords) => {
                let gather = |to: &mut [f64], from: &[f64]| {
                    for (o, &c) in to.iter_mut().zip(coords) {
                        *o = from[c];
                    }
                };
                gather(&mut self.q[cells.clone()], &data.q);
                if d >= 1 {
                    gather(&mut self.qd[cells.clone()], &data.qd);
                }
                if d >= 2 {
                    gather(&mut self.qdd[cells], &data.qdd);
                }
            }
        }
    }

    /// Where a run of closed-form steps writes row `row` as it checks the step, where every
    /// coordinate is kept (`continues_storing`); None where only some are.
    fn coord_row(&mut self, row: usize) -> Option<Row<'_>> {
        if self.outputs.coords.is_some() {
            return None;
        }
        let (d, m) = (self.request.derivatives, self.n_kept);
        let cells = row * m..(row + 1) * m;
        Some(Row {
            q: &mut self.q[cells.clone()],
            qd: (d >= 1).then(|| &mut self.qd[cells.clone()]),
            qdd: (d >= 2).then(|| &mut self.qdd[cells]),
        })
    }

    /// Stores the rest of row `row` after its coordinates: the points, the forces.
    /// `frames_set`: data.frames hold the poses (and, as solved, the rates) of data.q, as a
    /// structured step leaves them.
    fn store_rest(&mut self, model: &Model, data: &Data, t: f64, row: usize, frames_set: bool) {
        if !self.outputs.points.is_empty() {
            self.store_points(data, row, frames_set);
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

    /// Keeps row `row` after its coordinates (`store_coords`, or written as the step was
    /// checked: `coord_row`): the rest of the state in `data` and the worst diagnostics
    /// since the last kept row, which start again.
    #[allow(clippy::too_many_arguments)]
    fn keep(
        &mut self,
        model: &Model,
        data: &Data,
        t: f64,
        row: usize,
        frames_set: bool,
        worst: &mut Worst,
        det_sign: f64,
    ) {
        self.store_rest(model, data, t, row, frames_set);
        self.iterations[row] = worst.iterations;
        self.residual[row] = worst.residual;
        self.pivot_ratio[row] = worst.pivot_ratio;
        self.det_sign[row] = det_sign;
        self.n_done = row + 1;
        *worst = Worst::default();
    }

    /// The kept points' world position R + A u, velocity Rd + thetad B u and
    /// acceleration Rdd + thetadd B u - thetad^2 A u, as row `row`.
    fn store_points(&mut self, data: &Data, row: usize, frames_set: bool) {
        let d = self.request.derivatives;
        let cells = row * 2 * self.outputs.points.len();
        for (i, &(body, u)) in self.outputs.points.iter().enumerate() {
            let at = cells + 2 * i;
            let Some(b) = body else {
                self.points[at..at + 2].copy_from_slice(&u);
                for rates in [&mut self.points_d, &mut self.points_dd].into_iter().take(d as usize) {
                    rates[at..at + 2].fill(0.0);
                }
                continue;
            };
            let (q, qd, qdd) = (&data.q[3 * b..3 * b + 3], &data.qd, &data.qdd);
            // a structured step set cos, sin from the pins; else from theta
            let (c, s) = if frames_set {
                (data.frames[b].c, data.frames[b].s)
            } else {
                let (s, c) = q[2].sin_cos();
                (c, s)
            };
            let au = [c * u[0] - s * u[1], s * u[0] + c * u[1]];
            self.points[at] = q[0] + au[0];
            self.points[at + 1] = q[1] + au[1];
            if d >= 1 {
                let w = qd[3 * b + 2];
                self.points_d[at] = qd[3 * b] - w * au[1];
                self.points_d[at + 1] = qd[3 * b + 1] + w * au[0];
                if d >= 2 {
                    let al = qdd[3 * b + 2];
                    self.points_dd[at] = qdd[3 * b] - al * au[1] - w * w * au[0];
                    self.points_dd[at + 1] = qdd[3 * b + 1] + al * au[0] - w * w * au[1];
                }
            }
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
    // every time finite, inside the drivers' common domain and on in one direction: one
    // pass without branches (it vectorises; the loop below, a few times slower, runs only
    // to name the step at fault)
    let (lo, hi) = model.time_domain;
    let inside = times.iter().fold(true, |ok, &t| ok & t.is_finite() & (t >= lo) & (t <= hi));
    let monotone = times.windows(2).fold(true, |ok, w| ok & ((w[1] - w[0]) * direction > 0.0));
    if inside && monotone {
        return Ok(());
    }
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
    sweep_observed(model, data, times, out, progress_every, progress, &mut |_, _, _| Ok(()))
}

/// What `sweep_observed` calls after each kept row: (data at the step, its time, the row).
pub(crate) type Observer<'a> = dyn FnMut(&Data, f64, usize) -> Result<(), SolveError> + 'a;

/// `sweep`, calling `after(data, t, row)` once row `row` is stored, while data holds its
/// step (q, qd, qdd as solved; with a plan, the frames of q too: the groups set them, or
/// `closed_form::resync` after the general path). An Err from `after` stops the sweep there.
pub(crate) fn sweep_observed(
    model: &Model,
    data: &mut Data,
    times: &[f64],
    out: &mut SweepOutput,
    progress_every: usize,
    progress: &mut dyn FnMut(usize) -> bool,
    after: &mut Observer,
) -> Result<(), SolveError> {
    check_times(model, times)?;
    let req = out.request;
    out.n_done = 0;
    out.events.clear();
    data.with_velocity = solved_derivatives(model, &req) >= 1;
    let mut tracker = Tracker::new(model, req.on_singular, req.locks);
    let result = sweep_steps(model, data, times, out, &mut tracker, progress_every, progress, after, true);
    out.events = std::mem::take(&mut tracker.events);
    result
}

#[allow(clippy::too_many_arguments)]
fn sweep_steps(
    model: &Model,
    data: &mut Data,
    times: &[f64],
    out: &mut SweepOutput,
    tracker: &mut Tracker,
    progress_every: usize,
    progress: &mut dyn FnMut(usize) -> bool,
    after: &mut Observer,
    runs: bool,
) -> Result<(), SolveError> {
    let req = out.request;
    // the structure-aware cheap path, where the model has a plan
    let plan = model.plan.as_ref().ok();
    let solved = solved_derivatives(model, &req);
    let has_newton = plan.is_some_and(|p| p.blocks.iter().any(|b| matches!(b, Block::Newton(_))));
    // every group in closed form, with rates (whose two-way check below guards the
    // branch): tried before any prediction, which only a miss needs. Positions only, the
    // prediction is the guard, as on the general path.
    let fast_closed = plan.is_some() && !has_newton && solved >= 1;
    // the largest scaled difference between the structured solution and the prediction
    let deviation = |data: &Data| {
        data.q
            .iter()
            .zip(&data.blocks.q_pred)
            .zip(&data.inv_col_scale)
            .fold(0.0f64, |m, ((q, p), s)| m.max((q - p).abs() * s))
    };
    // the pivot ratio (closeness to singular on the structured path) of the last step
    let mut ratio_prev = f64::INFINITY;
    // worst diagnostics since the last kept row
    let mut worst = Worst::default();
    // the run of steps in one loop (`Run`): every group is a closed form, and nothing else
    // is asked of a step
    let run = plan.filter(|_| runs && fast_closed && !req.forces && !req.locks);
    // where the run stopped: the step it handed back
    let mut handoff: Option<Handoff> = None;
    let mut k = 0;
    while k < times.len() {
        if let Some(plan) = run.filter(|_| k > 0 && !tracker.spanning()) {
            let mut ctx = Run { model, plan, times, out, progress_every, solved, worst: &mut worst };
            match ctx.steps(data, tracker, k, &mut ratio_prev, progress, after)? {
                None => break,
                Some(h) => {
                    k = h.k;
                    handoff = Some(h);
                }
            }
        }
        let t = times[k];
        // a run's hand-back has checked progress at its step already
        if progress_every > 0 && k % progress_every == 0 && k > 0 && handoff.is_none() && !progress(k) {
            return Err(SolveError::Cancelled { step: k });
        }
        // cancellation polled inside the careful path too (a step there can take many solves)
        let mut poll = || progress_every == 0 || progress(k);
        // whether q, qd and qdd at t are all set (by the careful path or its interpolant)
        let mut rates_set = false;
        // whether the plan's groups solved this step (positions and the rates asked for)
        let mut by_blocks = false;
        let info = if k == 0 {
            solve_position(model, data, t, k, true)?
        } else {
            let fast = match handoff.take() {
                // the run tried this step (q_prev set): its groups' solution (data holds
                // it) or their miss (data back at the previous step)
                Some(h) => h.solved,
                None => {
                    tracker.q_prev.copy_from_slice(&data.q);
                    match plan {
                        Some(plan) if fast_closed && !tracker.spanning() => {
                            let info = closed_step(model, plan, data, times, k, solved, &tracker.q_prev);
                            if info.is_some() {
                                data.hist_q[0].copy_from_slice(&tracker.q_prev);
                            }
                            info
                        }
                        _ => None,
                    }
                }
            };
            if let Some(info) = fast {
                by_blocks = true;
                info
            } else {
                // rates next to a singular configuration are unreliable: predict from positions
                let last_ratio = if plan.is_some() { ratio_prev } else { data.pivots.ratio };
                let predictor = match solved {
                    _ if last_ratio < NEAR_SINGULAR => Predictor::Quadratic,
                    2 => Predictor::Jerk,
                    1 => Predictor::Acceleration,
                    _ => Predictor::Cubic,
                };
                predict(data, times, k, predictor);
                if let Some(info) = tracker.spanned(model, data, t, k, &mut poll)? {
                    rates_set = true;
                    info
                } else {
                    let motion = data
                        .q
                        .iter()
                        .zip(&tracker.q_prev)
                        .zip(&data.inv_col_scale)
                        .fold(0.0f64, |m, ((q, p), s)| m.max((q - p).abs() * s));
                    let floor = match predictor {
                        Predictor::Jerk | Predictor::Acceleration => JUMP_FLOOR_RATES,
                        Predictor::Quadratic | Predictor::Cubic => JUMP_FLOOR,
                    };
                    // the structure-aware cheap path: the groups solved in order, on the branch
                    // of each, none near singular; any doubt, and the general cheap path decides
                    let mut structured = None;
                    if let Some(plan) = plan.filter(|_| !fast_closed) {
                        data.blocks.q_pred.copy_from_slice(&data.q);
                        match closed_form::step(model, plan, data, t, solved, t - times[k - 1]) {
                            // as the general path's jump check: the solution against the prediction
                            Ok(s) if deviation(data) <= JUMP_RATIO * motion.max(floor) => {
                                by_blocks = true;
                                structured = Some(PositionInfo {
                                    iterations: s.iterations,
                                    residual: s.residual,
                                    pivot_ratio: s.closeness,
                                    det_sign: s.det_sign,
                                    correction: s.correction,
                                });
                            }
                            _ => data.q.copy_from_slice(&data.blocks.q_pred),
                        }
                    }
                    match structured {
                        Some(info) => info,
                        None => match solve_position(model, data, t, k, false) {
                            // the cheap path: on the predicted branch, well conditioned, no crossing
                            Ok(info)
                                if !is_jump(&info, motion, floor)
                                    && info.pivot_ratio >= NEAR_SINGULAR
                                    && info.det_sign * tracker.det_prev >= 0.0 =>
                            {
                                info
                            }
                            Err(e @ SolveError::NonFinite { .. }) => return Err(e),
                            _ => {
                                rates_set = true;
                                tracker.careful(model, data, times[k - 1], t, k, &mut poll)?
                            }
                        },
                    }
                }
            }
        };
        if solved >= 1 && !rates_set && !by_blocks {
            solve_velocity(model, data, t, k)?;
        }
        if solved >= 2 && !rates_set && !by_blocks {
            solve_acceleration(model, data, t, k)?;
        }
        // the cheap path's step checked backwards from its own rates: next to a change
        // point, Newton from a good prediction may still land on the other branch, which
        // passes close there with other rates
        // (the structured path's too: on a coarse grid a dyad's closeness can pass through
        // zero between two steps without its trend showing it)
        let info = if k > 0 && !rates_set && solved >= 1 {
            let qdd = (solved >= 2).then_some(&data.qdd[..]);
            let h = t - times[k - 1];
            if continues(&data.inv_col_scale, h, &tracker.q_prev, &data.hist_qd, &data.q, &data.qd, qdd) {
                info
            } else {
                rates_set = true;
                by_blocks = false;
                tracker.careful(model, data, times[k - 1], t, k, &mut poll)?
            }
        } else {
            info
        };
        if !rates_set || k == 0 {
            tracker.det_prev = info.det_sign;
        }
        if let Some(plan) = plan {
            if !by_blocks {
                // solved by the general path (the start, the careful path): the branches
                // and det sign the plan continues from
                let rates = rates_set || solved >= 1;
                let h = (k > 0).then(|| t - times[k - 1]);
                closed_form::resync(model, plan, data, t, info.det_sign, rates, h);
            }
        }
        ratio_prev = info.pivot_ratio;
        if k == 0 {
            tracker.start(&info, data);
        } else if req.locks {
            tracker.after_velocity(model, data, times[k - 1], t, k)?;
        }
        worst.add(&info);
        if k % req.every == 0 {
            if req.forces {
                if by_blocks {
                    // the transpose solves need Phi_q factored at q
                    assemble_and_factor(model, data, t, k)?;
                }
                solve_forces(model, data, t, k)?;
            }
            let row = k / req.every;
            out.store_coords(data, row);
            out.keep(model, data, t, row, by_blocks, &mut worst, info.det_sign);
            after(data, t, row)?;
        }
        k += 1;
    }
    Ok(())
}

/// The worst diagnostics of the steps since the last kept row: each kept row reports them.
struct Worst {
    iterations: u32,
    residual: f64,
    pivot_ratio: f64,
}

impl Default for Worst {
    fn default() -> Self {
        Worst { iterations: 0, residual: 0.0, pivot_ratio: f64::INFINITY }
    }
}

impl Worst {
    fn add(&mut self, info: &PositionInfo) {
        self.iterations = self.iterations.max(info.iterations as u32);
        self.residual = self.residual.max(info.residual);
        self.pivot_ratio = self.pivot_ratio.min(info.pivot_ratio);
    }
}

/// The step a run (`Run::steps`) handed back to the step-by-step loop.
struct Handoff {
    k: usize,
    /// Some: the groups solved step k (data holds it, and the history has moved on as
    /// `closed_step` leaves it) but it failed the two-way check; None: the groups missed,
    /// and data is back at step k-1
    solved: Option<PositionInfo>,
}

/// A run of steps that the plan's closed forms take one after another, as the
/// step-by-step loop takes them (`closed_step`, the two-way check, the store), without
/// its per-step dispatch among the paths: the first step they do not take is handed back.
struct Run<'a, 'w> {
    model: &'a Model,
    plan: &'a closed_form::Plan,
    times: &'a [f64],
    out: &'a mut SweepOutput,
    progress_every: usize,
    /// the derivatives each step solves (`solved_derivatives`)
    solved: u8,
    worst: &'w mut Worst,
}

impl Run<'_, '_> {
    /// Steps k0, k0 + 1, ... until one is not taken (handed back) or the times end (None).
    fn steps(
        &mut self,
        data: &mut Data,
        tracker: &mut Tracker,
        k0: usize,
        ratio_prev: &mut f64,
        progress: &mut dyn FnMut(usize) -> bool,
        after: &mut Observer,
    ) -> Result<Option<Handoff>, SolveError> {
        let (model, times) = (self.model, self.times);
        let every = self.out.request.every;
        // the next kept row and the step it is (k % every == 0), and the next step that
        // calls `progress`, counted on rather than found by dividing at every step
        let mut row_next = k0.div_ceil(every);
        let mut kept_at = row_next * every;
        let mut progress_at = match self.progress_every {
            0 => usize::MAX,
            n => k0.next_multiple_of(n),
        };
        for k in k0..times.len() {
            if k == progress_at {
                progress_at += self.progress_every;
                if !progress(k) {
                    return Err(SolveError::Cancelled { step: k });
                }
            }
            let (t, h) = (times[k], times[k] - times[k - 1]);
            tracker.q_prev.copy_from_slice(&data.q);
            let solved = self.solved;
            let Some(info) = closed_step(model, self.plan, data, times, k, solved, &tracker.q_prev) else {
                return Ok(Some(Handoff { k, solved: None }));
            };
            // step k-1's q becomes the history's newest by a swap: q_prev is copied from q
            // again before the next step, and put back where the step is handed back
            std::mem::swap(&mut data.hist_q[0], &mut tracker.q_prev);
            let q_prev = &data.hist_q[0];
            // a kept step's coordinates are written as they are checked, where every one is kept
            let row = (k == kept_at).then_some(row_next);
            let stored = match row.filter(|_| solved >= 2).and_then(|r| self.out.coord_row(r)) {
                Some(out) => {
                    Some(continues_storing(&data.inv_col_scale, h, q_prev, &data.q, &data.qd, &data.qdd, out))
                }
                None => None,
            };
            let ok = stored.unwrap_or_else(|| {
                let qdd = (solved >= 2).then_some(&data.qdd[..]);
                continues(&data.inv_col_scale, h, q_prev, &data.hist_qd, &data.q, &data.qd, qdd)
            });
            if !ok {
                tracker.q_prev.copy_from_slice(&data.hist_q[0]);
                return Ok(Some(Handoff { k, solved: Some(info) }));
            }
            tracker.det_prev = info.det_sign;
            *ratio_prev = info.pivot_ratio;
            self.worst.add(&info);
            if let Some(row) = row {
                (row_next, kept_at) = (row + 1, kept_at + every);
                if stored.is_none() {
                    self.out.store_coords(data, row);
                }
                self.out.keep(model, data, t, row, true, self.worst, info.det_sign);
                after(data, t, row)?;
            }
        }
        Ok(None)
    }
}

/// The derivatives a sweep solves: those asked for, and velocities and accelerations where
/// the model has a plan with a dyad. A dyad keeps the sign of its branch, so a step across
/// its singular configuration lands on the mirror image with the same det sign; on a
/// coarse grid the prediction cannot tell (positions on a grid of three steps over two
/// turns of a parallelogram did flip), nor can the two-way check from velocities alone (at
/// five steps a turn); the two-way check with accelerations does. They cost two 2 x 2
/// solves per dyad and are not stored unless asked for.
fn solved_derivatives(model: &Model, req: &Request) -> u8 {
    let dyads = model
        .plan
        .as_ref()
        .is_ok_and(|p| p.blocks.iter().any(|b| matches!(b, Block::Rrr(_) | Block::Rrp(_) | Block::Rpr(_))));
    if dyads {
        2
    } else {
        req.derivatives
    }
}

/// Step k by a plan whose groups are all closed forms, before any prediction (they need
/// none): on success the predictor's history moves on as `predict` would have moved it,
/// all but its newest q (`hist_q[0]`, the oldest's buffer), which the caller sets to q_prev;
/// on a miss q, qd, qdd of step k-1 are put back for the prediction and the general path.
/// A successful step writes every coordinate's rates it solves (each body is in one group,
/// and a closed form writes its bodies' q, and qd, qdd where asked): step k-1's rates are
/// set aside by swapping buffers with the plan's spares, not copied. Inlined: a run's loop
/// then keeps what it reads from step to step (45 fewer instructions a four-bar step).
#[inline(always)]
fn closed_step(
    model: &Model,
    plan: &closed_form::Plan,
    data: &mut Data,
    times: &[f64],
    k: usize,
    derivatives: u8,
    q_prev: &[f64],
) -> Option<PositionInfo> {
    let (rates, accelerations) = (derivatives >= 1, derivatives >= 2);
    if rates {
        std::mem::swap(&mut data.qd, &mut data.blocks.qd_prev);
    }
    if accelerations {
        std::mem::swap(&mut data.qdd, &mut data.blocks.qdd_prev);
    }
    let (t, h) = (times[k], times[k] - times[k - 1]);
    match closed_form::step(model, plan, data, t, derivatives, h) {
        Ok(s) => {
            // step k-1's rates become the history (the history's old ones the spares)
            if rates {
                std::mem::swap(&mut data.hist_qd, &mut data.blocks.qd_prev);
            } else {
                data.hist_qd.copy_from_slice(&data.qd);
            }
            if accelerations {
                std::mem::swap(&mut data.hist_qdd, &mut data.blocks.qdd_prev);
            } else {
                data.hist_qdd.copy_from_slice(&data.qdd);
            }
            // the caller puts q_prev in hist_q[0] (a run by a swap, not a copy)
            data.hist_q.rotate_right(1);
            Some(PositionInfo {
                iterations: s.iterations,
                residual: s.residual,
                pivot_ratio: s.closeness,
                det_sign: s.det_sign,
                correction: s.correction,
            })
        }
        Err(_) => {
            // step k-1's back; the spares take this step's partial rates
            data.q.copy_from_slice(q_prev);
            if rates {
                std::mem::swap(&mut data.qd, &mut data.blocks.qd_prev);
            }
            if accelerations {
                std::mem::swap(&mut data.qdd, &mut data.blocks.qdd_prev);
            }
            None
        }
    }
}

/// Phi_q assembled and factored at data.q (after a structured step, for the stages that
/// need the whole factorization: inverse dynamics).
fn assemble_and_factor(model: &Model, data: &mut Data, t: f64, step: usize) -> Result<(), SolveError> {
    crate::solve::assembly::position(model, data, t);
    crate::solve::position::factor(model, data, t, step).map(|_| ())
}

/// Sub-steps allowed to follow the drivers from the drawing to a solve's time.
pub const ALONG_BUDGET: usize = 200_000;

/// The time of the drawing: 0, or the nearest time the drivers are defined at.
pub fn drawing_time(model: &Model) -> f64 {
    let (lo, hi) = model.time_domain;
    0.0f64.max(lo).min(hi)
}

/// Position, velocity and acceleration at t on the drawing's branch: assembled at the
/// drawing's time from the drawing, then followed along the drivers to t by the careful
/// path (certified sub-steps, crossings stepped over and reported), so that a time far
/// from the drawing gets the drawing's configuration continued, not whatever Newton finds
/// from the drawing. Returns the events met on the way. `poll` may return false to cancel.
pub fn solve_along(
    model: &Model,
    data: &mut Data,
    t: f64,
    poll: &mut dyn FnMut() -> bool,
) -> Result<(crate::solve::position::PositionInfo, Vec<Event>), SolveError> {
    check_times(model, &[t])?;
    let t_ref = drawing_time(model);
    data.q.copy_from_slice(&model.q_start);
    let info = solve(model, data, t_ref)?;
    if t == t_ref {
        return Ok((info, Vec::new()));
    }
    let mut tracker = Tracker::new(model, OnSingular::Continue, false);
    tracker.det_prev = info.det_sign;
    let from = crate::sweep::stepping::branch::State::capture(data, t_ref, info);
    let info = tracker.follow(model, data, from, t, ALONG_BUDGET, poll)?;
    Ok((info, std::mem::take(&mut tracker.events)))
}

/// Position, velocity and acceleration at one time, from data.q as the starting guess.
pub fn solve(
    model: &Model,
    data: &mut Data,
    t: f64,
) -> Result<crate::solve::position::PositionInfo, SolveError> {
    check_times(model, &[t])?;
    data.with_velocity = true;
    let info = solve_position(model, data, t, 0, true)?;
    solve_velocity(model, data, t, 0)?;
    solve_acceleration(model, data, t, 0)?;
    Ok(info)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::stepping::tracking::OnSingular;

    /// A sweep with the runs of closed-form steps or one step at a time.
    fn swept(
        model: &Model,
        times: &[f64],
        req: Request,
        outputs: Outputs,
        runs: bool,
    ) -> (SweepOutput, bool) {
        let mut data = Data::new(model);
        let mut out = SweepOutput::with_outputs(model, times, req, outputs);
        let mut tracker = Tracker::new(model, req.on_singular, req.locks);
        let mut progress = |_| true;
        let r = sweep_steps(
            model,
            &mut data,
            times,
            &mut out,
            &mut tracker,
            7,
            &mut progress,
            &mut |_, _, _| Ok(()),
            runs,
        );
        out.events = std::mem::take(&mut tracker.events);
        (out, r.is_ok())
    }

    /// The runs take the steps the step-by-step loop takes, as it takes them: every
    /// shipped example whose plan is all closed forms, swept over a fine and a coarse grid (where
    /// steps are handed back: near singular configurations, branch checks), every k-th
    /// row kept, velocities kept without accelerations, or some coordinates and a point,
    /// gives the same bits both ways.
    #[test]
    fn runs_take_the_steps_the_loop_takes() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
        let mut fitted = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|x| x != "toml") {
                continue;
            }
            let model = Model::new(crate::input::files::read_path(&path).unwrap().description).unwrap();
            let closed = |p: &closed_form::Plan| !p.blocks.iter().any(|b| matches!(b, Block::Newton(_)));
            if !model.plan.as_ref().is_ok_and(closed) {
                continue;
            }
            fitted += 1;
            let (lo, hi) = model.time_domain;
            let t0 = 0.0f64.max(lo);
            for (n, span) in [(2000usize, 2.0f64), (60, 40.0)] {
                let t1 = (t0 + span).min(hi);
                let times: Vec<f64> = (0..=n).map(|k| t0 + (t1 - t0) * k as f64 / n as f64).collect();
                let point = Outputs {
                    coords: Some(vec![model.n_coords - 1, 0]),
                    points: vec![(Some(0), [0.1, 0.02])],
                };
                for (req, outputs) in [
                    (Request::default(), Outputs::all()),
                    (Request { derivatives: 0, every: 3, ..Request::default() }, Outputs::all()),
                    (Request { derivatives: 1, ..Request::default() }, Outputs::all()),
                    (Request { on_singular: OnSingular::Stop, ..Request::default() }, point),
                ] {
                    let (mut a, ok_a) = swept(&model, &times, req, outputs.clone(), true);
                    let (mut b, ok_b) = swept(&model, &times, req, outputs, false);
                    let name = path.display();
                    assert_eq!((ok_a, a.n_done), (ok_b, b.n_done), "{name}");
                    // the rows reached (past them a run may have written a row it then handed back)
                    a.truncate();
                    b.truncate();
                    let pairs = [
                        ("q", &a.q, &b.q),
                        ("qd", &a.qd, &b.qd),
                        ("qdd", &a.qdd, &b.qdd),
                        ("points", &a.points, &b.points),
                        ("residual", &a.residual, &b.residual),
                        ("pivot ratio", &a.pivot_ratio, &b.pivot_ratio),
                        ("det sign", &a.det_sign, &b.det_sign),
                    ];
                    for (what, x, y) in pairs {
                        let first = x.iter().zip(y.iter()).position(|(u, v)| u.to_bits() != v.to_bits());
                        assert_eq!(first, None, "{name}, {n} steps, {req:?}: {what} differs");
                    }
                    assert_eq!(a.iterations, b.iterations, "{name}");
                    assert_eq!(format!("{:?}", a.events), format!("{:?}", b.events), "{name}");
                }
            }
        }
        assert!(fitted >= 6, "only {fitted} examples have a plan of closed forms");
    }
}
