//! A model's variants: the same mechanism with some of its numbers moved along design
//! parameters, as a design study varies it, built and swept on the worker threads.
//!
//! A parameter (`sensitivity::Parameter`) is a direction in the joints' and drivers' own
//! numbers (`Constraint::params_mut`), the named points' local coordinates and the inverse
//! dynamics' numbers (masses, gravity, loads: `Dynamics`); a pin's
//! world place, a link length, a law's field all map onto these exactly (affinely), so a
//! design is the compiled model with those numbers set and its plan re-made from the
//! same structure: no redraw, no recompile, nothing under the GIL. Its sweep starts from
//! the model's drawing and assembles the design there (the first step's Newton), as the
//! redrawn and recompiled design does; the two agree to round-off. Where the model has a
//! plan, that start is first put on the branches the base model takes at the first time
//! (each dyad's assembly mode, each Newton block's det sign), by the design's own closed
//! forms: far from the base, Newton from the base's drawing may converge onto the other
//! assembly, silently. A design that cannot be assembled there is its named error.
//!
//! Each thread keeps one variant model and one sweep output and reuses them for every
//! design it takes; only the kept figures are written, straight into the caller's arrays.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

use crate::constraints::Constraint;
use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::params::{Dynamics, Parameter};
use crate::model::structure::{structure, Structure};
use crate::model::Model;
use crate::solve::closed_form::lanes::{Turns, LANES};
use crate::solve::closed_form::Plan;
use crate::solve::position::PivotsAt;
use crate::sweep::batch::on_threads;
use crate::sweep::branches::{asked_branches, sweep_on, Asked};
use crate::sweep::lanes::{self, sweep_lanes, LaneRows};
use crate::sweep::outputs::{Outputs, Request, SweepOutput};
use crate::sweep::time_loop::check_times;

/// How designs move a model's numbers: the parameters, the base numbers they start from.
/// Each parameter moves its numbers along its direction, which is exact for every number
/// the kinematics reads (and for masses, inertias, gravity); a force's direction, which
/// the engine keeps normalized, moves only to first order (studies vary it by redrawing
/// whenever forces are asked for).
#[derive(Debug, Clone)]
pub struct Variation {
    pub params: Vec<Parameter>,
    /// the constraints some parameter moves, with their base numbers (`params_mut` order)
    base: Vec<(usize, Vec<f64>)>,
    /// the named points some parameter moves, with their base local coordinates
    base_points: Vec<(usize, [f64; 2])>,
    /// the inverse dynamics' numbers (masses, gravity, loads), when a parameter moves one
    dynamics: Option<Dynamics>,
    /// the base model's structure, when it has a plan (numbers do not change it)
    structure: Option<Structure>,
}

impl Variation {
    pub fn new(model: &Model, params: Vec<Parameter>) -> Variation {
        let mut moved: Vec<usize> = params.iter().flat_map(|p| p.seeds.iter().map(|s| s.0)).collect();
        moved.sort_unstable();
        moved.dedup();
        let base = moved
            .into_iter()
            .map(|c| {
                let nums =
                    model.constraints[c].kind.clone().params_mut().into_iter().map(|(_, v)| *v).collect();
                (c, nums)
            })
            .collect();
        let mut points: Vec<usize> = params.iter().flat_map(|p| p.points.iter().map(|s| s.0)).collect();
        points.sort_unstable();
        points.dedup();
        let base_points = points.into_iter().map(|k| (k, model.points[k].local)).collect();
        let structure = model.plan.is_ok().then(|| structure(model));
        let dynamics = params.iter().any(|p| !p.dynamics.is_empty()).then(|| Dynamics::new(model));
        Variation { params, base, base_points, dynamics, structure }
    }

    /// Sets `variant` (a clone of the base model) to the design `delta` (one value per
    /// parameter: its change from the base) and re-makes its plan. Its description, drawing
    /// and length scale stay the base's: the drawing is where its sweep assembles from.
    pub fn apply(&self, base: &Model, variant: &mut Model, delta: &[f64]) {
        for (c, nums) in &self.base {
            let mut target = nums.clone();
            for (p, d) in self.params.iter().zip(delta) {
                for &(sc, k, w) in &p.seeds {
                    if sc == *c {
                        target[k] += w * d;
                    }
                }
            }
            for ((_, v), t) in variant.constraints[*c].kind.params_mut().into_iter().zip(target) {
                *v = t;
            }
        }
        for &(k, local) in &self.base_points {
            let mut u = local;
            for (p, d) in self.params.iter().zip(delta) {
                for &(pk, dir) in &p.points {
                    if pk == k {
                        u[0] += dir[0] * d;
                        u[1] += dir[1] * d;
                    }
                }
            }
            variant.points[k].local = u;
        }
        if let Some(dynamics) = &self.dynamics {
            let mut values = dynamics.values.clone();
            for (p, d) in self.params.iter().zip(delta) {
                for &(i, w) in &p.dynamics {
                    values[i] += w * d;
                }
            }
            dynamics.set(variant, &values);
        }
        variant.plan = match &self.structure {
            Some(s) => Plan::from_structure(variant, s),
            None => base.plan.clone(),
        };
    }

    /// The design `delta` as a model of its own.
    pub fn model(&self, base: &Model, delta: &[f64]) -> Model {
        let mut variant = base.clone();
        self.apply(base, &mut variant, delta);
        variant
    }
}

/// The kept figures of many designs, stacked: design-major arrays.
#[derive(Debug, Default)]
pub struct VariantFigures {
    pub n_designs: usize,
    pub n_steps: usize,
    /// n_designs x n_steps x n_kept: the kept coordinates (NaN past a design's n_done)
    pub q: Vec<f64>,
    /// n_designs x n_steps x n_points x 2: the kept body points' world positions
    pub points: Vec<f64>,
    /// n_designs: the smallest pivot ratio (closeness to singular) over the done steps
    pub pivot_min: Vec<f64>,
    /// n_designs: the events located (limits, bifurcations, branch jumps)
    pub events: Vec<usize>,
    /// n_designs: steps done
    pub n_done: Vec<usize>,
    /// n_designs: the design's error
    pub errors: Vec<Option<SolveError>>,
}

impl VariantFigures {
    /// Bytes the figures of `n` designs take.
    pub fn bytes(model: &Model, n: usize, n_times: usize, outputs: &Outputs) -> usize {
        let per_step = outputs.n_kept(model) + 2 * outputs.points.len();
        n.saturating_mul(n_times.saturating_mul(per_step).saturating_add(4)).saturating_mul(8)
    }
}

/// Sweeps the `n` designs `deltas` (n x params, row-major: each row a design's changes
/// from the base) of `model` over `times` on `threads` threads (0: one per core), solving
/// what `request` asks and keeping `outputs` (positions); a kept point that is a named
/// point (`named`, per point) moves with the parameters that move it. `watch(done)` as
/// for `sweep_batch`.
#[allow(clippy::too_many_arguments)]
pub fn sweep_variants(
    model: &Model,
    variation: &Variation,
    n: usize,
    deltas: &[f64],
    times: &[f64],
    request: Request,
    outputs: &Outputs,
    named: &[Option<usize>],
    threads: usize,
    watch: &mut dyn FnMut(usize) -> bool,
) -> VariantFigures {
    let m = variation.params.len();
    assert_eq!(deltas.len(), n * m, "one change per design and parameter");
    let request = Request { every: 1, forces: false, ..request };
    let asked = times.first().and_then(|&t| asked_branches(model, t));
    let (n_steps, kept, np) = (times.len(), outputs.n_kept(model), outputs.points.len());
    let mut q = vec![f64::NAN; n * n_steps * kept];
    let mut points = vec![f64::NAN; n * n_steps * np * 2];
    let ctx = Ctx { model, variation, deltas, times, named, asked: asked.as_ref(), kept, np };
    // designs of a plan the lanes step, LANES at a time; the rest one by one
    let lanes = lanes::fit(model, &request) && check_times(model, times).is_ok();
    let width = if lanes { LANES } else { 1 };
    let chunks = n.div_ceil(width);
    let items = {
        // each design's rows, handed to the thread that sweeps it
        let q_rows = Mutex::new(split(&mut q, n, n_steps * kept));
        let point_rows = Mutex::new(split(&mut points, n, n_steps * np * 2));
        let mut watch_designs = |done: usize| watch((done * width).min(n));
        on_threads(
            chunks,
            threads,
            &mut watch_designs,
            || Worker::new(model, times, request, outputs),
            |worker, c, cancel| {
                let ids = c * width..((c + 1) * width).min(n);
                let mut rows: Vec<(&mut [f64], &mut [f64])> = {
                    let (mut qr, mut pr) = (q_rows.lock().expect("rows"), point_rows.lock().expect("rows"));
                    ids.clone()
                        .map(|i| {
                            let q = qr[i].take().expect("a design swept once");
                            (q, pr[i].take().expect("a design swept once"))
                        })
                        .collect()
                };
                let mut done: Vec<Option<Figures>> = vec![None; rows.len()];
                if lanes && rows.len() == LANES && !cancel.load(Ordering::Relaxed) {
                    worker.lanes(&ctx, ids.start, &mut rows, &mut done, cancel);
                }
                for ((i, row), slot) in ids.zip(rows.iter_mut()).zip(done.iter_mut()) {
                    if slot.is_none() {
                        *slot = Some(worker.one(&ctx, i, row, cancel));
                    }
                }
                done
            },
        )
    };
    let mut figures = VariantFigures { n_designs: n, n_steps, ..VariantFigures::default() };
    for item in items.into_iter().flat_map(|c| c.expect("every design was swept")) {
        let (pivot_min, events, done, err) = item.expect("every design was swept");
        figures.pivot_min.push(pivot_min);
        figures.events.push(events);
        figures.n_done.push(done);
        figures.errors.push(err);
    }
    VariantFigures { q, points, ..figures }
}

/// A design's figures beside its rows: smallest pivot ratio, events, steps done, error.
type Figures = (f64, usize, usize, Option<SolveError>);

/// What every design's sweep reads.
struct Ctx<'a> {
    model: &'a Model,
    variation: &'a Variation,
    deltas: &'a [f64],
    times: &'a [f64],
    named: &'a [Option<usize>],
    asked: Option<&'a Asked>,
    kept: usize,
    np: usize,
}

/// A thread's variant models, workspaces and outputs, reused for every design it takes:
/// one model and workspace per lane, and the one-by-one path's full sweep.
struct Worker {
    variants: Vec<Model>,
    /// each lane's workspace, where its design starts (`lanes::start` puts it back first)
    data: Vec<Data>,
    /// where each lane's start's pivot ratio is factored (`lanes::start`)
    pivots: PivotsAt,
    /// each lane's kept points (body, place in it), moved with its design
    points: Vec<Vec<(Option<usize>, [f64; 2])>>,
    full: SweepOutput,
    /// the crank's cos and sin at each step, as the thread's lanes took them
    turns: Turns,
}

impl Worker {
    fn new(model: &Model, times: &[f64], request: Request, outputs: &Outputs) -> Worker {
        Worker {
            variants: vec![model.clone(); LANES],
            data: (0..LANES).map(|_| Data::new(model)).collect(),
            pivots: PivotsAt::new(model),
            points: vec![outputs.points.clone(); LANES],
            full: SweepOutput::with_outputs(model, times, request, outputs.clone()),
            turns: Turns::default(),
        }
    }

    /// Design `i` on lane `j`'s variant model, its kept points moved with it.
    fn set(&mut self, ctx: &Ctx, j: usize, i: usize, out_full: bool) {
        let m = ctx.variation.params.len();
        ctx.variation.apply(ctx.model, &mut self.variants[j], &ctx.deltas[i * m..(i + 1) * m]);
        let points = if out_full { &mut self.full.outputs.points } else { &mut self.points[j] };
        for (slot, k) in points.iter_mut().zip(ctx.named) {
            if let Some(k) = k {
                slot.1 = self.variants[j].points[*k].local;
            }
        }
    }

    /// Design `i` swept alone by the general per-design path, into its rows.
    fn one(
        &mut self,
        ctx: &Ctx,
        i: usize,
        (q_dst, p_dst): &mut (&mut [f64], &mut [f64]),
        cancel: &AtomicBool,
    ) -> Figures {
        self.set(ctx, 0, i, true);
        let (variant, out) = (&self.variants[0], &mut self.full);
        let mut data = Data::new(variant);
        let mut keep_going = |_: usize| !cancel.load(Ordering::Relaxed);
        let err = if cancel.load(Ordering::Relaxed) {
            out.n_done = 0; // nothing of this design was swept
            Some(SolveError::Cancelled { step: 0 })
        } else {
            sweep_on(variant, &mut data, ctx.times, out, 4096, &mut keep_going, ctx.asked).err()
        };
        let (done, kept, np) = (out.n_done, ctx.kept, ctx.np);
        q_dst[..done * kept].copy_from_slice(&out.q[..done * kept]);
        p_dst[..done * np * 2].copy_from_slice(&out.points[..done * np * 2]);
        let pivot_min = out.pivot_ratio[..done].iter().copied().fold(f64::INFINITY, f64::min);
        (pivot_min, out.events.len(), done, err)
    }

    /// Designs `first..first + LANES` in lanes (`sweep::lanes`): each started from its own
    /// closed forms on its asked branches (`lanes::start`), then stepped side by side. A
    /// design the lanes take to the end gets its figures in `done`; the others (a start
    /// that is not clear, a missed step; all four where no branches are asked) are left to
    /// the one-by-one path, whose sweep overwrites their rows.
    fn lanes(
        &mut self,
        ctx: &Ctx,
        first: usize,
        rows: &mut [(&mut [f64], &mut [f64])],
        done: &mut [Option<Figures>],
        cancel: &AtomicBool,
    ) {
        let Some(asked) = ctx.asked else { return };
        let t0 = ctx.times[0];
        let mut ratio = [0.0; LANES];
        for (j, start) in ratio.iter_mut().enumerate() {
            self.set(ctx, j, first + j, false);
            let variant = &self.variants[j];
            let Ok(plan) = variant.plan.as_ref() else { return };
            let Some(signs) = asked.signs(plan) else { return };
            let Some(r) = lanes::start(variant, plan, &mut self.data[j], &mut self.pivots, t0, signs) else {
                return;
            };
            *start = r;
        }
        let kept = ctx.kept;
        let coords = self.full.outputs.coords.clone();
        let mut lane_rows: Vec<LaneRows> = rows
            .iter_mut()
            .enumerate()
            .map(|(j, (q, p))| {
                let data = &self.data[j];
                // the start's row, as a sweep stores a row the general path solved
                match &coords {
                    Some(c) => c.iter().zip(q[..kept].iter_mut()).for_each(|(&c, o)| *o = data.q[c]),
                    None => q[..kept].copy_from_slice(&data.q),
                }
                for (i, (body, u)) in self.points[j].iter().enumerate() {
                    p[2 * i..2 * i + 2].copy_from_slice(&match body {
                        Some(b) => {
                            let (x, y, th) = (data.q[3 * b], data.q[3 * b + 1], data.q[3 * b + 2]);
                            let (s, c) = th.sin_cos();
                            [x + (c * u[0] - s * u[1]), y + (s * u[0] + c * u[1])]
                        }
                        None => *u,
                    });
                }
                LaneRows { q, points: p, pivot_min: ratio[j] }
            })
            .collect();
        let points: Vec<_> = (0..ctx.np)
            .map(|p| (self.points[0][p].0, std::array::from_fn(|j| self.points[j][p].1)))
            .collect();
        let models = std::array::from_fn(|j| &self.variants[j]);
        let data = std::array::from_fn(|j| &self.data[j]);
        let Ok(rows) = <&mut [LaneRows; LANES]>::try_from(&mut lane_rows[..]) else { return };
        let outputs = &self.full.outputs;
        let cancelled = || cancel.load(Ordering::Relaxed);
        let turns = &mut self.turns;
        let Some(missed) = sweep_lanes(models, data, ctx.times, outputs, &points, rows, turns, &cancelled)
        else {
            return;
        };
        for (j, row) in lane_rows.iter().enumerate() {
            if missed[j].is_none() {
                done[j] = Some((row.pivot_min, 0, ctx.times.len(), None));
            }
        }
    }
}

/// `buf` cut into `n` consecutive rows of `len` (empty rows when `len` is 0).
fn split(buf: &mut [f64], n: usize, len: usize) -> Vec<Option<&mut [f64]>> {
    let mut rows = Vec::with_capacity(n);
    let mut rest = buf;
    for _ in 0..n {
        let (row, tail) = rest.split_at_mut(len);
        rows.push(Some(row));
        rest = tail;
    }
    rows
}
