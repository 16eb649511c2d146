//! What a sweep is asked for (`Request`), which figures it keeps (`Outputs`) and their
//! storage (`SweepOutput`): only what is kept is allocated.

use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::memory::{Column, Columns};
use crate::model::Model;
use crate::solve::forces::{load_power, reactions, REACTION_COLUMNS};
use crate::solve::position::PositionInfo;
use crate::sweep::stepping::branch::Row;
use crate::sweep::stepping::singular::Event;
use crate::sweep::stepping::tracking::OnSingular;

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
    pub times: Column<f64>,
    /// what is kept of the coordinates and which body points
    pub outputs: Outputs,
    /// n_steps x n_kept (qd, qdd empty when not solved)
    pub q: Column<f64>,
    pub qd: Column<f64>,
    pub qdd: Column<f64>,
    /// n_steps x outputs.points.len() x 2: the points' world positions, velocities, accelerations
    /// (empty when not solved)
    pub points: Column<f64>,
    pub points_d: Column<f64>,
    pub points_dd: Column<f64>,
    /// n_steps: Newton iterations (factorizations) of each step
    pub iterations: Column<u32>,
    /// n_steps: scaled residual inf-norm at each step's last Newton evaluation
    pub residual: Column<f64>,
    /// n_steps: smallest / largest pivot of the scaled Phi_q (0 at a singular configuration)
    pub pivot_ratio: Column<f64>,
    /// n_steps x n_rows: Lagrange multipliers (empty without forces)
    pub lambda: Column<f64>,
    /// 3 x (n_steps x n_rows): lambda split into inertia, gravity and loads
    pub lambda_parts: [Column<f64>; 3],
    /// n_steps x n_constraints x 4: each constraint's reaction on its side b (Fx, Fy in
    /// world axes, torque about its anchor) and the power it delivers
    pub reactions: Column<f64>,
    /// n_steps: power of the applied loads, Q_loads . qd
    pub load_power: Column<f64>,
    /// n_steps: sign of det Phi_q at each kept step (flips where a singularity is crossed)
    pub det_sign: Column<f64>,
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
        // every column in one allocation (`Columns`), laid out in the order taken below;
        // what is not kept has no length
        let on = |on: bool, len: usize| if on { len } else { 0 };
        let mut c = Columns::default();
        c.add::<f64>(times.len().div_ceil(every));
        for len in [n * m, on(d >= 1, n * m), on(d >= 2, n * m)] {
            c.add::<f64>(len);
        }
        for len in [n * np * 2, on(d >= 1, n * np * 2), on(d >= 2, n * np * 2)] {
            c.add::<f64>(len);
        }
        c.add::<u32>(n);
        for len in [n, n, on(forces, n * r), on(forces, n * r), on(forces, n * r), on(forces, n * r)] {
            c.add::<f64>(len);
        }
        for len in [on(forces, n * nc * REACTION_COLUMNS), on(forces, n), n] {
            c.add::<f64>(len);
        }
        c.finish();
        let mut times_kept = c.take::<f64>();
        for (o, &t) in times_kept.iter_mut().zip(times.iter().step_by(every)) {
            *o = t;
        }
        SweepOutput {
            n_steps: n,
            n_coords: model.n_coords,
            n_kept: m,
            n_rows: r,
            n_constraints: nc,
            n_done: 0,
            request,
            times: times_kept,
            outputs,
            q: c.take(),
            qd: c.take(),
            qdd: c.take(),
            points: c.take(),
            points_d: c.take(),
            points_dd: c.take(),
            iterations: c.take(),
            residual: c.take(),
            pivot_ratio: c.take(),
            lambda: c.take(),
            lambda_parts: std::array::from_fn(|_| c.take()),
            reactions: c.take(),
            load_power: c.take(),
            det_sign: c.take(),
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
    /// Inlined into the sweep's loop, as `keep` is: a call each row cost more than the copy.
    #[inline(always)]
    pub(crate) fn store_coords(&mut self, data: &Data, row: usize) {
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
    pub(crate) fn coord_row(&mut self, row: usize) -> Option<Row<'_>> {
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
    #[inline(never)]
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
    #[inline(always)]
    pub(crate) fn keep(
        &mut self,
        model: &Model,
        data: &Data,
        t: f64,
        row: usize,
        frames_set: bool,
        worst: &mut Worst,
        det_sign: f64,
    ) {
        if !self.outputs.points.is_empty() || self.request.forces {
            self.store_rest(model, data, t, row, frames_set);
        }
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

/// The worst diagnostics of the steps since the last kept row: each kept row reports them.
pub(crate) struct Worst {
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
    pub(crate) fn add(&mut self, info: &PositionInfo) {
        self.iterations = self.iterations.max(info.iterations as u32);
        self.residual = self.residual.max(info.residual);
        self.pivot_ratio = self.pivot_ratio.min(info.pivot_ratio);
    }
}
