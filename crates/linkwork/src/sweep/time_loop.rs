//! The time loop: for each time, predict q from the previous step, solve position,
//! velocity and acceleration, and store them with per-step diagnostics. Outputs are
//! allocated once, before the loop; a failure at step k keeps steps 0..k.

use crate::constraints::Constraint;
use crate::error::SolveError;
use crate::math::pivots::NEAR_SINGULAR;
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::acceleration::solve_acceleration;
use crate::solve::closed_form::guard::Travel;
use crate::solve::closed_form::{self, Block};
use crate::solve::forces::solve_forces;
use crate::solve::position::PositionInfo;
use crate::solve::position::{solve_position, PivotsAt};
use crate::solve::velocity::solve_velocity;
use crate::sweep::outputs::{Request, SweepOutput, Worst};
use crate::sweep::stepping::branch::{continues, continues_storing};
use crate::sweep::stepping::predict::{predict, Predictor};
use crate::sweep::stepping::tracking::JUMP_RATIO;
use crate::sweep::stepping::tracking::{is_jump, Tracker, JUMP_FLOOR, JUMP_FLOOR_RATES};
use crate::sweep::stepping::travel::Travels;

/// Checks that the times can be swept: finite, strictly monotone, inside every
/// driver's table.
pub fn check_times(model: &Model, times: &[f64]) -> Result<(), SolveError> {
    model.check_kinematic()?;
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

/// `sweep`, calling `after(data, t, row)` once row `row` is stored, while data holds its
/// step (q, qd, qdd as solved; with a plan, the frames of q too: the groups set them, or
/// `closed_form::resync` after the general path). An Err from `after` stops the sweep there.
/// `after` is a type parameter, not a `dyn`: the no-op of a sweep without one is compiled away.
pub(crate) fn sweep_observed(
    model: &Model,
    data: &mut Data,
    times: &[f64],
    out: &mut SweepOutput,
    progress_every: usize,
    progress: &mut dyn FnMut(usize) -> bool,
    after: &mut impl FnMut(&Data, f64, usize) -> Result<(), SolveError>,
) -> Result<(), SolveError> {
    check_times(model, times)?;
    let req = out.request;
    out.n_done = 0;
    out.events.clear();
    data.with_velocity = solved_derivatives(model, &req) >= 1;
    let mut tracker = Tracker::new(model, req.on_singular, req.locks);
    tracker.travels = Travels::new(model);
    let result = sweep_steps(model, data, times, out, &mut tracker, progress_every, progress, after, true);
    out.events = std::mem::take(&mut tracker.events);
    if tracker.travels.is_some() {
        // a travel's crossings are found after the step's own events: in time order
        let direction = if times.len() > 1 { (times[1] - times[0]).signum() } else { 1.0 };
        out.events.sort_by(|a, b| (a.time * direction).total_cmp(&(b.time * direction)));
    }
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
    after: &mut impl FnMut(&Data, f64, usize) -> Result<(), SolveError>,
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
    // positions only, a plan whose steps the guard can show on their branches: each
    // closed-form step is accepted by the guard from positions (`closed_form::guard`),
    // the careful path's rates and two-way check only where it cannot
    let guarded = fast_closed
        && req.derivatives == 0
        && !req.forces
        && !req.locks
        && plan.is_some_and(closed_form::guarded);
    let reads = match plan {
        Some(plan) if guarded => closed_form::guard_reads(plan, model.n_bodies),
        _ => Vec::new(),
    };
    let mut guard =
        Guard { on: guarded, travel: vec![Travel::default(); model.n_bodies], reads, stale: false };
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
    // (a model with a travel goes step by step, each step then watched: the same steps)
    let run = plan.filter(|_| runs && fast_closed && !req.forces && !req.locks && tracker.travels.is_none());
    // where the run stopped: the step it handed back
    let mut handoff: Option<Handoff> = None;
    let mut k = 0;
    while k < times.len() {
        if let Some(plan) = run.filter(|_| k > 0 && !tracker.spanning()) {
            let mut ctx =
                Run { model, plan, times, out, progress_every, solved, worst: &mut worst, guard: &mut guard };
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
        // whether the guard took this step (no rates solved, no two-way check)
        let mut by_guard = false;
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
                            let mut info = None;
                            if guard.on {
                                info = guard.step(model, plan, data, times, k, &tracker.q_prev);
                                by_guard = info.is_some();
                            }
                            if info.is_none() {
                                info = closed_step::<false>(
                                    model,
                                    plan,
                                    data,
                                    times,
                                    k,
                                    solved,
                                    &tracker.q_prev,
                                );
                            }
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
        let info = if k > 0 && !rates_set && !by_guard && solved >= 1 {
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
        guard.stale = by_guard;
        if k == 0 {
            tracker.start(&info, data);
        } else if req.locks {
            tracker.after_velocity(model, data, times[k - 1], t, k)?;
        }
        if k == 0 {
            // the start reports its solution's pivots, chosen there (`PivotsAt`): Newton's
            // last factorization is of the iterate before it, on the pivot sequence chosen
            // where Newton began (the drawing); the loop above still steers by that one
            let at = PivotsAt::new(model).at(model, &data.q, t);
            worst.add(&PositionInfo { pivot_ratio: at.ratio, ..info });
        } else {
            worst.add(&info);
        }
        if let Some(travels) = tracker.travels.as_mut() {
            let rates = rates_set || (solved >= 1 && !by_guard);
            travels.after_step(model, data, t, k, rates, &mut tracker.events);
        }
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
    guard: &'w mut Guard,
}

/// The guarded steps of a positions-only sweep (`closed_form::step_guarded`): whether they
/// are taken, the bodies' bounds, and whether data's rates are stale (the last step was
/// the guard's, which solves none).
struct Guard {
    on: bool,
    travel: Vec<Travel>,
    /// per group, whether a later group reads its bodies' bounds (`closed_form::guard_reads`)
    reads: Vec<bool>,
    stale: bool,
}

impl Guard {
    /// Step k by the guard (`closed_step` of positions only, the guard for its check). On
    /// a miss, data is back at step k-1 with its rates and accelerations (solved again if
    /// the guard took that step), and the history's rates theirs, for the careful path.
    #[inline(always)]
    fn step(
        &mut self,
        model: &Model,
        plan: &closed_form::Plan,
        data: &mut Data,
        times: &[f64],
        k: usize,
        q_prev: &[f64],
    ) -> Option<PositionInfo> {
        let (t, h) = (times[k], times[k] - times[k - 1]);
        match closed_form::step_guarded(model, plan, data, t, h, &mut self.travel, &self.reads) {
            Ok(s) => {
                // the caller puts q_prev in hist_q[0]; the rates' history means nothing
                // until a miss sets it
                data.hist_q.rotate_right(1);
                Some(position_info(&s))
            }
            Err(_) => {
                if self.stale {
                    // (a law that cannot be evaluated leaves them; the careful path names it)
                    let _ = closed_form::rates(model, plan, data, times[k - 1]);
                    data.hist_qd.copy_from_slice(&data.qd);
                    data.hist_qdd.copy_from_slice(&data.qdd);
                    self.stale = false;
                }
                data.q.copy_from_slice(q_prev);
                None
            }
        }
    }
}

/// `Run::steps_on` as `pulp`'s operation: its dispatch compiles it, inlined, for the
/// machine's instruction set (AVX2 where there is: three-operand forms, fewer moves;
/// the same operations in the same order, so the same bits).
struct Steps<'r, 'a, 'w, 'd, P: ?Sized, A> {
    run: &'r mut Run<'a, 'w>,
    data: &'d mut Data,
    tracker: &'d mut Tracker,
    k0: usize,
    ratio_prev: &'d mut f64,
    progress: &'d mut P,
    after: &'d mut A,
}

impl<P, A> pulp::WithSimd for Steps<'_, '_, '_, '_, P, A>
where
    P: FnMut(usize) -> bool + ?Sized,
    A: FnMut(&Data, f64, usize) -> Result<(), SolveError>,
{
    type Output = Result<Option<Handoff>, SolveError>;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        self.run.steps_on(self.data, self.tracker, self.k0, self.ratio_prev, self.progress, self.after)
    }
}

impl Run<'_, '_> {
    /// Steps k0, k0 + 1, ... until one is not taken (handed back) or the times end (None):
    /// `steps_on`, compiled for the machine (`Steps`).
    fn steps(
        &mut self,
        data: &mut Data,
        tracker: &mut Tracker,
        k0: usize,
        ratio_prev: &mut f64,
        progress: &mut dyn FnMut(usize) -> bool,
        after: &mut impl FnMut(&Data, f64, usize) -> Result<(), SolveError>,
    ) -> Result<Option<Handoff>, SolveError> {
        pulp::Arch::new().dispatch(Steps { run: self, data, tracker, k0, ratio_prev, progress, after })
    }

    #[inline(always)]
    fn steps_on(
        &mut self,
        data: &mut Data,
        tracker: &mut Tracker,
        k0: usize,
        ratio_prev: &mut f64,
        progress: &mut (impl FnMut(usize) -> bool + ?Sized),
        after: &mut impl FnMut(&Data, f64, usize) -> Result<(), SolveError>,
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
        // every step's q is kept in its row: the guard's steps take their own loop, which
        // keeps the history there (`guarded`)
        let rows_hold_q = self.guard.on && every == 1 && self.out.outputs.coords.is_none();
        let mut k = k0;
        while k < times.len() {
            // whether the guard has been tried at step k and missed it (data at step k-1)
            let mut missed = false;
            if rows_hold_q {
                match self.guarded(data, tracker, k, &mut progress_at, ratio_prev, progress, after)? {
                    None => return Ok(None),
                    Some(m) => (k, row_next, kept_at, missed) = (m, m, m, true),
                }
            }
            if k == progress_at && !missed {
                progress_at += self.progress_every;
                if !progress(k) {
                    return Err(SolveError::Cancelled { step: k });
                }
            }
            let (t, h) = (times[k], times[k] - times[k - 1]);
            if !missed {
                tracker.q_prev.copy_from_slice(&data.q);
            }
            if self.guard.on && !missed {
                if let Some(info) = self.guard.step(model, self.plan, data, times, k, &tracker.q_prev) {
                    std::mem::swap(&mut data.hist_q[0], &mut tracker.q_prev);
                    self.guard.stale = true;
                    tracker.det_prev = info.det_sign;
                    *ratio_prev = info.pivot_ratio;
                    self.worst.add(&info);
                    if k == kept_at {
                        let row = row_next;
                        (row_next, kept_at) = (row + 1, kept_at + every);
                        self.out.store_coords(data, row);
                        self.out.keep(model, data, t, row, true, self.worst, info.det_sign);
                        after(data, t, row)?;
                    }
                    k += 1;
                    continue;
                }
            }
            let solved = self.solved;
            let Some(info) = closed_step::<true>(model, self.plan, data, times, k, solved, &tracker.q_prev)
            else {
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
            self.guard.stale = false;
            self.worst.add(&info);
            if let Some(row) = row {
                (row_next, kept_at) = (row + 1, kept_at + every);
                if stored.is_none() {
                    self.out.store_coords(data, row);
                }
                self.out.keep(model, data, t, row, true, self.worst, info.det_sign);
                after(data, t, row)?;
            }
            k += 1;
        }
        Ok(None)
    }

    /// Steps k0, k0 + 1, ... by the guard (`closed_form::step_guarded`), where every step's
    /// coordinates are kept (`every` 1, every coordinate): each step's row is its q, so no
    /// step sets q aside for a miss nor moves the history; at the step the guard does not
    /// take, both are set from the rows as the step-by-step loop leaves them there (data at
    /// step k-1 with `q_prev`, the history of positions and, where the guard took the last
    /// step, of rates), and it is handed back; None: the times end. Polls `progress` at
    /// its steps, the handed-back one too.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn guarded(
        &mut self,
        data: &mut Data,
        tracker: &mut Tracker,
        k0: usize,
        progress_at: &mut usize,
        ratio_prev: &mut f64,
        progress: &mut (impl FnMut(usize) -> bool + ?Sized),
        after: &mut impl FnMut(&Data, f64, usize) -> Result<(), SolveError>,
    ) -> Result<Option<usize>, SolveError> {
        let (model, plan, times) = (self.model, self.plan, self.times);
        let mut k = k0;
        let missed = loop {
            if k == times.len() {
                break None;
            }
            if k == *progress_at {
                *progress_at += self.progress_every;
                if !progress(k) {
                    return Err(SolveError::Cancelled { step: k });
                }
            }
            let (t, h) = (times[k], times[k] - times[k - 1]);
            let travel = &mut self.guard.travel;
            let Ok(s) = closed_form::step_guarded_inline(model, plan, data, t, h, travel, &self.guard.reads)
            else {
                break Some(k);
            };
            let info = position_info(&s);
            self.guard.stale = true;
            tracker.det_prev = info.det_sign;
            *ratio_prev = info.pivot_ratio;
            self.worst.add(&info);
            self.out.store_coords(data, k);
            self.out.keep(model, data, t, k, true, self.worst, info.det_sign);
            after(data, t, k)?;
            k += 1;
        };
        // the history as the step-by-step loop moves it, one step at a time: q of step k-2
        // newest (the steps before k0 as they were)
        let m = self.out.n_kept;
        let moved = (k - k0).min(data.hist_q.len());
        data.hist_q.rotate_right(moved);
        for (i, hist) in data.hist_q[..moved].iter_mut().enumerate() {
            let row = k - 2 - i;
            hist.copy_from_slice(&self.out.q[row * m..(row + 1) * m]);
        }
        if let Some(k) = missed {
            if self.guard.stale {
                // (a law that cannot be evaluated leaves them; the careful path names it)
                let _ = closed_form::rates(model, plan, data, times[k - 1]);
                data.hist_qd.copy_from_slice(&data.qd);
                data.hist_qdd.copy_from_slice(&data.qdd);
                self.guard.stale = false;
            }
            let prev = &self.out.q[(k - 1) * m..k * m];
            data.q.copy_from_slice(prev);
            tracker.q_prev.copy_from_slice(prev);
        }
        Ok(missed)
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
/// `I`: the plan's step inlined too (a run's loop, compiled for the machine: `Steps`).
#[inline(always)]
fn closed_step<const I: bool>(
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
    let solved = if I {
        closed_form::step_inline(model, plan, data, t, derivatives, h)
    } else {
        closed_form::step(model, plan, data, t, derivatives, h)
    };
    match solved {
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
            Some(position_info(&s))
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

/// A closed-form step's diagnostics as the sweep reports a step's (its closeness as the
/// pivot ratio).
#[inline(always)]
fn position_info(s: &closed_form::StepInfo) -> PositionInfo {
    PositionInfo {
        iterations: s.iterations,
        residual: s.residual,
        pivot_ratio: s.closeness,
        det_sign: s.det_sign,
        correction: s.correction,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::outputs::Outputs;
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
                    // the guard's own loop (every step's q kept), and the guard's steps one by one
                    (Request { derivatives: 0, ..Request::default() }, Outputs::all()),
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
