//! Following one assembly branch through a sweep, and reporting where it goes singular.
//!
//! The cheap path (the sweep's predictor and Newton) takes a step when its correction is
//! small against the predicted motion, Phi_q stays well conditioned and det Phi_q keeps
//! its sign. Any other step is redone by the careful path: sub-steps from the last
//! certified state, each a Taylor prediction, Newton, the rates, and a two-way check that
//! the new state continues the old one's branch (`hermite::consistent`); failures halve
//! the sub-step. A sub-step that lands next to a singular configuration is not taken:
//! the path steps over it (to 2, 3, 5 or 9 times the sub-step) and fills the times
//! stepped over from the quintic interpolant of the two certified states. Where det
//! Phi_q changed sign between two certified states, the crossing is located on their
//! interpolant by the signed smallest singular value and reported. So at a change point
//! the sweep keeps the branch whose velocity is continuous (the analytic continuation),
//! whichever sign det Phi_q takes there. Where no sub-step gets on, a limit of motion is
//! located by bisection and reported. Every search is bounded (`STEP_BUDGET`) and polls
//! for cancellation. Locks (an output stopping and reversing) are located on the output's
//! rate. All of this allocates only when something happens.

use crate::constraints::kinds::ConstraintKind;
use crate::error::SolveError;
use crate::math::pivots::NEAR_SINGULAR;
use crate::math::roots::illinois;
use crate::model::data::Data;
use crate::model::slider::slide_driver;
use crate::model::Model;
use crate::solve::acceleration::solve_acceleration;
use crate::solve::deflation::deflated_newton;
use crate::solve::events::driver_values;
use crate::solve::position::{solve_position, PositionInfo};
use crate::solve::velocity::solve_velocity;
use crate::sweep::stepping::branch::{consistent, interpolate, State, CONSISTENCY};
use crate::sweep::stepping::singular::{
    classify, constraint_shares, coordinate_shares, smallest_singular, Event, EventKind,
};
use crate::sweep::stepping::travel::Travels;

/// A step whose Newton correction exceeds this fraction of the predicted motion (or of
/// `JUMP_FLOOR` when little motion is predicted) is suspected of leaving its branch. On a
/// smooth branch the ratio is O((omega h)^2) or smaller, so a false alarm only costs a
/// subdivision.
pub const JUMP_RATIO: f64 = 0.5;
/// Scaled motion (L or rad) below which the prediction is not trusted to judge a jump.
pub const JUMP_FLOOR: f64 = 0.02;
/// The same for a prediction from solved rates (third order in the step): a jump onto a
/// branch through a change point moves by the velocity jump times the step, far above it.
pub const JUMP_FLOOR_RATES: f64 = 1e-7;
/// Sub-steps are halved at most this many times (2^-24 of a step) before giving up.
const MAX_HALVINGS: i32 = 24;
/// Two certified states with opposite det Phi_q signs are taken to have crossed a
/// singular configuration only if their interpolant, where it is singular, satisfies the
/// constraints to this scaled residual: on one branch the interpolant is off by O(h^6);
/// between two branches that pass close it is off by their distance there.
pub const CROSSING_RESIDUAL: f64 = 1e-8;
/// Shares of a singular vector below this are not reported.
const SHARE_FLOOR: f64 = 0.05;

/// What the sweep does at a singular configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OnSingular {
    /// Report the event and go on along the same branch where one exists.
    #[default]
    Continue,
    /// Stop with an error at the first limit, bifurcation or branch jump, keeping the
    /// steps before it.
    Stop,
    /// At a bifurcation, go on along the other branch through it (found by deflated
    /// Newton next to the crossing); otherwise as Continue.
    Switch,
}

/// A quantity whose sign change is a lock: a rate made of coordinate rates.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    pub name: String,
    /// (coordinate, coefficient)
    pub terms: Vec<(usize, f64)>,
}

impl Output {
    fn rate(&self, qd: &[f64]) -> f64 {
        self.terms.iter().map(|(i, c)| c * qd[*i]).sum()
    }
}

/// The outputs of a mechanism: every link pinned to the ground whose angle no driver
/// sets, and every slider on the ground whose slide no driver sets.
pub fn outputs(model: &Model) -> Vec<Output> {
    let driven_angle = |b: usize| {
        model
            .constraints
            .iter()
            .any(|c| matches!(c.kind, ConstraintKind::AngleDriver(_)) && c.body_b == Some(b))
    };
    let mut out = Vec::new();
    for c in &model.constraints {
        let moving = match (c.body_a, c.body_b) {
            (None, Some(b)) | (Some(b), None) => b,
            _ => continue,
        };
        match &c.kind {
            ConstraintKind::Revolute(_) if !driven_angle(moving) => out.push(Output {
                name: model.columns[3 * moving + 2].clone(),
                terms: vec![(3 * moving + 2, 1.0)],
            }),
            ConstraintKind::Prismatic(p) => {
                if slide_driver(model, c.body_a, c.body_b).is_some() {
                    continue;
                }
                // the slide axis in world axes: fixed in a, and a does not turn
                let theta_a = match c.body_a {
                    None => 0.0,
                    Some(a) => model.q_start[3 * a + 2],
                };
                let (s, co) = theta_a.sin_cos();
                let e = [co * p.e_a[0] - s * p.e_a[1], s * p.e_a[0] + co * p.e_a[1]];
                out.push(Output {
                    name: format!("{} (slide)", c.name),
                    terms: vec![(3 * moving, e[0]), (3 * moving + 1, e[1])],
                });
            }
            _ => {}
        }
    }
    out.dedup_by(|a, b| a.name == b.name);
    out
}

/// Whether a converged step left the branch: see `JUMP_RATIO`. `floor` is the predicted
/// motion below which the prediction is not trusted to judge (`JUMP_FLOOR` for positions
/// extrapolated from a few steps, `JUMP_FLOOR_RATES` for a Taylor step from solved rates).
#[inline]
pub fn is_jump(info: &PositionInfo, predicted_motion: f64, floor: f64) -> bool {
    info.correction > JUMP_RATIO * predicted_motion.max(floor)
}

/// Positions, velocities and accelerations at t, from data.q as the start.
fn full_solve(model: &Model, data: &mut Data, t: f64, step: usize) -> Result<PositionInfo, SolveError> {
    let info = solve_position(model, data, t, step, false)?;
    solve_velocity(model, data, t, step)?;
    solve_acceleration(model, data, t, step)?;
    Ok(info)
}

/// data.q set to `from`'s second-order Taylor expansion at t.
fn taylor(data: &mut Data, from: &State, t: f64) {
    let h = t - from.t;
    for i in 0..data.q.len() {
        data.q[i] = from.q[i] + h * (from.qd[i] + 0.5 * h * from.qdd[i]);
    }
}

/// Evaluates and factors Phi_q at data.q without Newton (a configuration at a singular
/// point may not pass Newton's tests), for its singular vectors and the forces. Returns
/// the position diagnostics there (no iterations).
fn factor_without_newton(model: &Model, data: &mut Data, t: f64) -> PositionInfo {
    let residual = crate::solve::assembly::position(model, data, t);
    data.pivots = data.factor.factor(&model.symbolic, &data.jac);
    PositionInfo {
        iterations: 0,
        residual,
        pivot_ratio: data.pivots.ratio,
        det_sign: data.pivots.det_sign,
        correction: 0.0,
    }
}

/// The diagnostics of the factorization in `data` (no solve).
fn here(data: &Data) -> PositionInfo {
    PositionInfo {
        iterations: data.iterations,
        residual: data.residual,
        pivot_ratio: data.pivots.ratio,
        det_sign: data.pivots.det_sign,
        correction: 0.0,
    }
}

/// `data` set to a certified state, with a factorization of Phi_q there (for forces).
fn land(model: &Model, data: &mut Data, s: &State) -> PositionInfo {
    s.restore(data);
    factor_without_newton(model, data, s.t);
    s.info
}

/// From `from` to t within one good step (for locating a lock), in Taylor sub-steps
/// halved on failure; no checks, no events. None if it cannot get there.
fn reach(model: &Model, data: &mut Data, from: &State, t: f64, step: usize) -> Option<PositionInfo> {
    let mut cur = from.clone();
    let mut h = t - cur.t;
    for _ in 0..4 * MAX_HALVINGS {
        let to = if (cur.t + h - t) * h.signum() >= 0.0 { t } else { cur.t + h };
        taylor(data, &cur, to);
        match full_solve(model, data, to, step) {
            Ok(info) if to == t => return Some(info),
            Ok(info) => {
                cur = State::capture(data, to, info);
                h *= 2.0;
            }
            Err(_) => h *= 0.5,
        }
    }
    None
}

/// Why an attempted sub-step was not taken.
enum Failure {
    /// Newton found no solution (or a rate solve failed)
    NoSolution(SolveError),
    /// the solution lies next to a singular configuration: its rates are not trusted
    NearSingular,
    /// the solution is on another branch (`hermite::consistent` fails)
    Inconsistent,
}

/// How the careful path ended a sub-step search that could not go on.
struct Stuck {
    last: State,
    ahead: f64,
    failure: Failure,
}

/// One sub-step of the careful path: Taylor from `from`, Newton at t, rates, checks.
fn attempt(
    model: &Model,
    data: &mut Data,
    from: &State,
    t: f64,
    step: usize,
    base_ratio: f64,
) -> Result<State, Failure> {
    taylor(data, from, t);
    let info = match full_solve(model, data, t, step) {
        Ok(info) => info,
        // singular to round-off: at (or next to) a singular configuration, to step over
        Err(SolveError::Singular { .. }) => return Err(Failure::NearSingular),
        Err(e) => return Err(Failure::NoSolution(e)),
    };
    // next to a singular configuration, relative to how well conditioned the branch was
    // where the careful path started (a model ill-conditioned everywhere is not singular
    // everywhere)
    if info.pivot_ratio < NEAR_SINGULAR && info.pivot_ratio < NEAR_SINGULAR_DROP * base_ratio {
        return Err(Failure::NearSingular);
    }
    let b = State::capture(data, t, info);
    if consistent(model, from, &b) {
        Ok(b)
    } else {
        Err(Failure::Inconsistent)
    }
}

/// A ratio of pivot ratios: a sub-step whose pivot ratio falls below NEAR_SINGULAR and
/// this fraction of its start's is next to a singular configuration.
const NEAR_SINGULAR_DROP: f64 = 1e-2;
/// Multiples of a sub-step tried to step over a singular configuration just ahead: on a
/// uniform grid the first ones land on the next grid times.
const OVERSHOOT: [f64; 4] = [2.0, 3.0, 5.0, 9.0];
/// Where the careful path stops, a smallest singular value below this at the last
/// solvable configuration is a limit of motion (or a crossing that cannot be stepped
/// over); a fold is located to sigma_min ~ sqrt(eps).
const LIMIT_SIGMA: f64 = 1e-4;
/// Pivot ratio at which the rates solved next to a singular configuration are trusted
/// for interpolating across it: measured on a parallelogram's change point, rates solved
/// at pivot ratios of 1e-3 to 1e-2 are off by 4e-11 (velocities) and 2e-8 (accelerations)
/// relative, and the error grows like 1 / ratio^2 closer in.
const CLOSE_RATIO: f64 = 1e-2;
/// Sub-steps (Newton solves) allowed to resolve one sweep step: no input makes a sweep
/// step run unbounded. Crossing a singular configuration takes tens.
pub const STEP_BUDGET: usize = 600;
/// Sub-steps between two polls for cancellation (Ctrl-C) inside the careful path.
const POLL_EVERY: usize = 16;

/// Follows the branch through steps and records events.
pub struct Tracker {
    pub on_singular: OnSingular,
    /// watch outputs for locks (needs velocities)
    pub locks: bool,
    outputs: Vec<Output>,
    /// q at the previous step
    pub(crate) q_prev: Vec<f64>,
    rate_prev: Vec<f64>,
    pub(crate) det_prev: f64,
    /// where the careful path stepped over a singular configuration: the certified states
    /// before and after it; the sweep times between them are filled from its interpolant
    span: Option<(State, State)>,
    /// after a switch of branch at a crossing: its time and the first certified state on
    /// the new branch; span times past the crossing come from this branch
    switched: Option<(f64, State)>,
    pub events: Vec<Event>,
    /// the sliders' travels watched step by step (a sweep of a model that gives some)
    pub(crate) travels: Option<Travels>,
}

impl Tracker {
    pub fn new(model: &Model, on_singular: OnSingular, locks: bool) -> Tracker {
        let outputs = if locks { outputs(model) } else { Vec::new() };
        Tracker {
            on_singular,
            locks,
            rate_prev: vec![0.0; outputs.len()],
            outputs,
            q_prev: vec![0.0; model.n_coords],
            det_prev: 0.0,
            span: None,
            switched: None,
            events: Vec::new(),
            travels: None,
        }
    }

    /// Whether the careful path has stepped past the sweep's next times (they come from
    /// its interpolant or its states).
    pub(crate) fn spanning(&self) -> bool {
        self.span.is_some()
    }

    /// After step 0: remember its det sign and output rates.
    pub fn start(&mut self, info: &PositionInfo, data: &Data) {
        self.det_prev = info.det_sign;
        for (r, o) in self.rate_prev.iter_mut().zip(&self.outputs) {
            *r = o.rate(&data.qd);
        }
    }

    /// The state of the previous step, rebuilt from q_prev (rates solved again).
    fn previous(
        &self,
        model: &Model,
        data: &mut Data,
        t_prev: f64,
        step: usize,
    ) -> Result<State, SolveError> {
        data.q.copy_from_slice(&self.q_prev);
        let info = full_solve(model, data, t_prev, step)?;
        Ok(State::capture(data, t_prev, info))
    }

    fn event(&self, model: &Model, data: &mut Data, kind: EventKind, step: usize, t: f64) -> Event {
        let triple = smallest_singular(model, data, 4);
        let kind = match kind {
            EventKind::Limit | EventKind::Bifurcation => classify(model, &triple),
            k => k,
        };
        let values = driver_values(model, t);
        let drivers: Vec<String> = values.iter().map(|(n, v)| format!("{n} = {v:.12}")).collect();
        let message = match kind {
            EventKind::Limit => format!(
                "a driver reaches a limit of motion at t = {t:.12} ({}): beyond it the mechanism \
                 cannot be assembled unless the driver reverses",
                drivers.join(", ")
            ),
            EventKind::Bifurcation => format!(
                "assembly branches meet at t = {t:.12} ({}): the joints' rows become dependent; \
                 the sweep follows the branch it was on",
                drivers.join(", ")
            ),
            EventKind::Lock => {
                format!("the output stops and reverses at t = {t:.12} ({})", drivers.join(", "))
            }
            EventKind::BranchJump => format!(
                "the solution leaves the branch near t = {t:.12} ({}) and halving the step does not \
                 bring it back",
                drivers.join(", ")
            ),
            // made by `travel::Travels`, which words its own
            EventKind::EndOfTravel => format!("a slider reaches the end of its travel at t = {t:.12}"),
        };
        Event {
            kind,
            step,
            time: t,
            q: data.q.clone(),
            sigma_min: triple.sigma,
            constraints: constraint_shares(model, &triple.w, SHARE_FLOOR),
            coordinates: coordinate_shares(model, &triple.v, SHARE_FLOOR),
            output: None,
            drivers: values,
            message,
            pivot_ratio: data.pivots.ratio,
        }
    }

    /// Step k, when the cheap path's solve failed, jumped, changed the sign of det Phi_q
    /// or came out next to a singular configuration: redone from step k-1 (or from the
    /// state ahead of a crossing) by the careful path. Leaves q, qd, qdd at t in `data`
    /// with a factorization of Phi_q there.
    pub fn careful(
        &mut self,
        model: &Model,
        data: &mut Data,
        t_prev: f64,
        t: f64,
        step: usize,
        poll: &mut dyn FnMut() -> bool,
    ) -> Result<PositionInfo, SolveError> {
        let from = match self.span.take() {
            Some((_, ahead)) => ahead,
            None => self.previous(model, data, t_prev, step)?,
        };
        self.step_from(model, data, from, t, step, poll)
    }

    /// Step k when the careful path has already stepped over (or up to) t: q, qd, qdd
    /// from its interpolant (or its state at t). None when no crossing spans t.
    pub fn spanned(
        &mut self,
        model: &Model,
        data: &mut Data,
        t: f64,
        step: usize,
        poll: &mut dyn FnMut() -> bool,
    ) -> Result<Option<PositionInfo>, SolveError> {
        let Some((behind, ahead)) = &self.span else {
            return Ok(None);
        };
        let direction = (ahead.t - behind.t).signum();
        if let Some((t_star, other)) = self.switched.clone() {
            if (t - t_star) * direction >= 0.0 {
                return self.on_new_branch(model, data, t_star, other, t, step, poll).map(Some);
            }
        }
        if (t - ahead.t) * direction < 0.0 {
            return Ok(Some(self.fill(model, data, t, step)));
        }
        let ahead = self.span.take().map(|(_, b)| b).expect("checked above");
        if t == ahead.t {
            return Ok(Some(land(model, data, &ahead)));
        }
        self.step_from(model, data, ahead, t, step, poll).map(Some)
    }

    /// From a certified state to a time any distance away (a solve far from the drawing),
    /// within `budget` sub-steps. Leaves q, qd, qdd at t in `data`.
    pub fn follow(
        &mut self,
        model: &Model,
        data: &mut Data,
        from: State,
        t: f64,
        budget: usize,
        poll: &mut dyn FnMut() -> bool,
    ) -> Result<PositionInfo, SolveError> {
        let (behind, ahead) = self.advance(model, data, from, t, 0, budget, poll)?;
        self.settle(model, data, behind, ahead, t, 0, poll)
    }

    /// From a certified state to t: advance, then land on t or fill it from the span.
    fn step_from(
        &mut self,
        model: &Model,
        data: &mut Data,
        from: State,
        t: f64,
        step: usize,
        poll: &mut dyn FnMut() -> bool,
    ) -> Result<PositionInfo, SolveError> {
        let (behind, ahead) = self.advance(model, data, from, t, step, STEP_BUDGET, poll)?;
        self.settle(model, data, behind, ahead, t, step, poll)
    }

    /// After `advance` to t: land on t, or keep the span and fill t from it (from the new
    /// branch if the path switched branches before t).
    #[allow(clippy::too_many_arguments)]
    fn settle(
        &mut self,
        model: &Model,
        data: &mut Data,
        behind: State,
        ahead: State,
        t: f64,
        step: usize,
        poll: &mut dyn FnMut() -> bool,
    ) -> Result<PositionInfo, SolveError> {
        if ahead.t == t && self.switched.is_none() {
            return Ok(land(model, data, &ahead));
        }
        self.span = Some((behind, ahead));
        Ok(self.spanned(model, data, t, step, poll)?.expect("a span was just set"))
    }

    /// A time past a switch of branch: on the new branch, reached from its first state
    /// (backwards for times between the crossing and that state; no events are recorded
    /// there: the crossing has been).
    #[allow(clippy::too_many_arguments)]
    fn on_new_branch(
        &mut self,
        model: &Model,
        data: &mut Data,
        t_star: f64,
        other: State,
        t: f64,
        step: usize,
        poll: &mut dyn FnMut() -> bool,
    ) -> Result<PositionInfo, SolveError> {
        let direction = (other.t - t_star).signum();
        if (t - other.t) * direction >= 0.0 {
            // at or past the new branch's first state: an ordinary careful step from it
            self.span = None;
            self.switched = None;
            if t == other.t {
                return Ok(land(model, data, &other));
            }
            return self.step_from(model, data, other, t, step, poll);
        }
        let (n_events, det_prev) = (self.events.len(), self.det_prev);
        let (span, switched, on_singular) = (self.span.take(), self.switched.take(), self.on_singular);
        self.on_singular = OnSingular::Continue;
        let info = match self.advance(model, data, other, t, step, STEP_BUDGET, poll) {
            Ok((_, ahead)) if ahead.t == t => Ok(land(model, data, &ahead)),
            Ok((behind, ahead)) => {
                self.span = Some((behind, ahead));
                Ok(self.fill(model, data, t, step))
            }
            Err(e) => Err(e),
        };
        self.events.truncate(n_events);
        (self.det_prev, self.span, self.switched, self.on_singular) = (det_prev, span, switched, on_singular);
        info
    }

    /// The other branch through a crossing at (t_star, q_star), at the time of `b` (the
    /// continuation's state just past it): deflated Newton (the continuation's solution
    /// divided out) from starts off `b` along the singular direction `v` (scaled). None
    /// if no other solution there leads back to the crossing.
    fn other_branch(
        &self,
        model: &Model,
        data: &mut Data,
        b: &State,
        (t_star, q_star): (f64, &[f64]),
        v: &[f64],
        step: usize,
    ) -> Option<State> {
        let n = model.n_coords;
        let scale = &model.col_scale;
        let scaled_dist = |q: &[f64], r: &[f64]| -> f64 {
            (0..n).map(|i| ((q[i] - r[i]) / scale[i]).powi(2)).sum::<f64>().sqrt()
        };
        let dist = scaled_dist(&b.q, q_star);
        let tol = model.options.tol_residual;
        for c in [1.0, 2.0, 0.5, 4.0, 0.25] {
            for sign in [1.0, -1.0] {
                for i in 0..n {
                    data.q[i] = b.q[i] + sign * c * dist * v[i] * scale[i];
                }
                if !deflated_newton(model, data, b.t, &b.q, tol) {
                    continue;
                }
                let far = scaled_dist(&data.q, &b.q);
                if far <= 1e-6 * (1.0 + dist) || far > 16.0 * dist + 1e-9 {
                    continue;
                }
                let Ok(info) = full_solve(model, data, b.t, step) else { continue };
                let other = State::capture(data, b.t, info);
                // a branch through the crossing: its own expansion leads back there
                let h = t_star - b.t;
                let (mut back, mut span) = (0.0f64, 0.0f64);
                for i in 0..n {
                    let p = other.q[i] + h * (other.qd[i] + 0.5 * h * other.qdd[i]);
                    back = back.max((p - q_star[i]).abs() / scale[i]);
                    span = span.max((other.q[i] - q_star[i]).abs() / scale[i]);
                }
                if back <= CONSISTENCY * span + 1e-9 {
                    return Some(other);
                }
            }
        }
        None
    }

    /// A time the careful path stepped over: q, qd, qdd from the span's interpolant; q
    /// refined by Newton (and the rates solved) where that is well conditioned and stays
    /// on the interpolant; elsewhere (next to the singular configuration) the interpolant
    /// itself, reported with no iterations and its measured residual.
    fn fill(&mut self, model: &Model, data: &mut Data, t: f64, step: usize) -> PositionInfo {
        let (behind, ahead) = self.span.clone().expect("a span to fill from");
        interpolate(&behind, &ahead, t, &mut data.q, Some(&mut data.qd), Some(&mut data.qdd));
        let guess = State::capture(data, t, behind.info);
        if let Ok(info) = full_solve(model, data, t, step) {
            let refined = State::capture(data, t, info);
            if info.pivot_ratio >= NEAR_SINGULAR && consistent(model, &behind, &refined) {
                return info;
            }
        }
        // next to the singular configuration: interpolate between certified states close
        // on either side, near enough for the interpolant's O(d^4) error in qdd, far enough
        // for the O(eps / d^2) error of the rates solved there
        let close = self.close_span(model, data, &behind, &ahead, t, step).unwrap_or((behind, ahead));
        interpolate(&close.0, &close.1, t, &mut data.q, Some(&mut data.qd), Some(&mut data.qdd));
        let here = State::capture(data, t, guess.info);
        here.restore(data);
        factor_without_newton(model, data, t)
    }

    /// Certified states at t - d and t + d, reached from the span's ends, with d doubled
    /// from half the span until Phi_q there is conditioned well enough (`CLOSE_RATIO`)
    /// for their rates; None if none can be reached. Records no event.
    fn close_span(
        &mut self,
        model: &Model,
        data: &mut Data,
        behind: &State,
        ahead: &State,
        t: f64,
        step: usize,
    ) -> Option<(State, State)> {
        let width = ahead.t - behind.t;
        let (n_events, det_prev) = (self.events.len(), self.det_prev);
        let mut none = || true;
        let mut found = None;
        let mut d = 0.5 * width;
        for _ in 0..20 {
            let (lo, hi) = (t - d, t + d);
            let a = self.advance(model, data, behind.clone(), lo, step, STEP_BUDGET, &mut none);
            let b = self.advance(model, data, ahead.clone(), hi, step, STEP_BUDGET, &mut none);
            let (Ok((_, a)), Ok((_, b))) = (a, b) else { break };
            if a.t != lo || b.t != hi || !consistent(model, &a, &b) {
                break;
            }
            let enough = a.ratio.min(b.ratio) >= CLOSE_RATIO;
            found = Some((a, b));
            if enough {
                break;
            }
            d *= 2.0;
        }
        self.events.truncate(n_events);
        self.det_prev = det_prev;
        found
    }

    /// Certified sub-steps from `from` towards `target`, halving on failure and stepping
    /// over singular configurations; every det Phi_q sign change between two certified
    /// states is located on their interpolant and reported. Returns the last state before
    /// `target` and the first at or beyond it (beyond it after stepping over a singular
    /// configuration at or next to `target`). At most `budget` sub-steps.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn advance(
        &mut self,
        model: &Model,
        data: &mut Data,
        from: State,
        target: f64,
        step: usize,
        budget: usize,
        poll: &mut dyn FnMut() -> bool,
    ) -> Result<(State, State), SolveError> {
        let span = target - from.t;
        let h_min = (span.abs() * 0.5f64.powi(MAX_HALVINGS)).max(16.0 * f64::EPSILON * target.abs().max(1.0));
        let base_ratio = from.ratio;
        let mut cur = from;
        let mut h = span;
        let mut tries = 0usize;
        loop {
            let to = if (cur.t + h - target) * span.signum() >= 0.0 { target } else { cur.t + h };
            let hh = to - cur.t;
            let failure =
                match self.try_once(model, data, &cur, to, step, &mut tries, (budget, base_ratio), poll)? {
                    Ok(b) if self.crossed(model, data, &cur, &b, step)? => {
                        if to == target || self.switched.is_some() {
                            return Ok((cur, b));
                        }
                        cur = b;
                        h = 2.0 * hh;
                        continue;
                    }
                    Ok(_) => Failure::Inconsistent,
                    Err(f) => f,
                };
            let small = (0.5 * hh).abs() < h_min;
            if matches!(failure, Failure::NearSingular) || small {
                // a singular configuration at or just before `to`: step over it from cur
                let mut over_it = false;
                for m in OVERSHOOT {
                    let over = cur.t + m * hh;
                    let Ok(b) =
                        self.try_once(model, data, &cur, over, step, &mut tries, (budget, base_ratio), poll)?
                    else {
                        continue;
                    };
                    if self.crossed(model, data, &cur, &b, step)? {
                        if (over - target) * span.signum() >= 0.0 || self.switched.is_some() {
                            return Ok((cur, b));
                        }
                        cur = b;
                        h = hh;
                        over_it = true;
                        break;
                    }
                }
                if over_it {
                    continue;
                }
            }
            if small {
                return self.stuck(model, data, Stuck { last: cur, ahead: to, failure }, target, step);
            }
            h = 0.5 * hh;
        }
    }

    /// One attempt, counted against the budget and polling for cancellation.
    #[allow(clippy::too_many_arguments)]
    fn try_once(
        &mut self,
        model: &Model,
        data: &mut Data,
        from: &State,
        t: f64,
        step: usize,
        tries: &mut usize,
        (budget, base_ratio): (usize, f64),
        poll: &mut dyn FnMut() -> bool,
    ) -> Result<Result<State, Failure>, SolveError> {
        *tries += 1;
        if *tries > budget {
            return Err(SolveError::Event {
                step,
                time: from.t,
                message: format!(
                    "the step to t = {t:.12} was not resolved within {budget} sub-steps (the last \
                     certified configuration is at t = {:.12}): the motion is not smooth enough to \
                     follow there",
                    from.t
                ),
            });
        }
        if *tries % POLL_EVERY == 0 && !poll() {
            return Err(SolveError::Cancelled { step });
        }
        if !t.is_finite() {
            return Ok(Err(Failure::NoSolution(SolveError::NonFinite {
                step,
                time: t,
                what: "the sub-step time".into(),
            })));
        }
        Ok(attempt(model, data, from, t, step, base_ratio))
    }

    /// Between two certified states: where det Phi_q changed sign, a singular
    /// configuration was crossed if their interpolant passes through one while still
    /// satisfying the constraints (to `CROSSING_RESIDUAL`): located by the signed smallest
    /// singular value along it (no Newton solve next to it) and reported. Otherwise `b`
    /// is on another branch that passes close (Ok(false): the sub-step is not taken).
    fn crossed(
        &mut self,
        model: &Model,
        data: &mut Data,
        a: &State,
        b: &State,
        step: usize,
    ) -> Result<bool, SolveError> {
        if a.det_sign * b.det_sign >= 0.0 {
            return Ok(true);
        }
        let signed_sigma = |data: &mut Data, tm: f64| -> Option<f64> {
            interpolate(a, b, tm, &mut data.q, None, None);
            let info = factor_without_newton(model, data, tm);
            let sigma = smallest_singular(model, data, 3).sigma;
            Some(sigma * info.det_sign)
        };
        let t_star = illinois(a.t, b.t, |tm| signed_sigma(data, tm)).unwrap_or(0.5 * (a.t + b.t));
        interpolate(a, b, t_star, &mut data.q, Some(&mut data.qd), Some(&mut data.qdd));
        let at = factor_without_newton(model, data, t_star);
        // a NaN residual is no crossing either
        if at.residual.is_nan() || at.residual > CROSSING_RESIDUAL {
            return Ok(false);
        }
        let mut ev = self.event(model, data, EventKind::Bifurcation, step, t_star);
        self.det_prev = b.det_sign;
        if self.on_singular == OnSingular::Switch && ev.kind == EventKind::Bifurcation {
            let q_star = data.q.clone();
            let v = smallest_singular(model, data, 4).v;
            let kept = "the sweep follows the branch it was on";
            match self.other_branch(model, data, b, (t_star, &q_star), &v, step) {
                Some(other) => {
                    ev.message = ev.message.replace(kept, "the sweep takes the other branch through it");
                    self.det_prev = other.det_sign;
                    self.switched = Some((t_star, other));
                }
                None => {
                    ev.message = ev.message.replace(kept, &format!("no other branch was found there: {kept}"))
                }
            }
        }
        let err = SolveError::Event { step, time: t_star, message: ev.message.clone() };
        self.events.push(ev);
        if self.on_singular == OnSingular::Stop {
            return Err(err);
        }
        Ok(true)
    }

    /// The careful path can go no further: a limit of motion (located by bisection and
    /// reported), a branch that cannot be followed (reported; with Continue, Newton's
    /// solution at the target is taken), or the original failure.
    fn stuck(
        &mut self,
        model: &Model,
        data: &mut Data,
        stuck: Stuck,
        target: f64,
        step: usize,
    ) -> Result<(State, State), SolveError> {
        let Stuck { last, ahead, failure } = stuck;
        // a limit of motion first: Newton converges up to it and not beyond (the target
        // bounds the search where every sub-step was off the branch: none may fail)
        let inconsistent = matches!(failure, Failure::Inconsistent);
        let end = if inconsistent { target } else { ahead };
        let (good, _bad) = self.bisect_fold(model, data, last.clone(), end, step);
        good.restore(data);
        factor_without_newton(model, data, good.t);
        let ev = self.event(model, data, EventKind::Limit, step, good.t);
        if ev.sigma_min < LIMIT_SIGMA {
            let err = SolveError::Event { step, time: good.t, message: ev.message.clone() };
            self.events.push(ev);
            return Err(err);
        }
        if inconsistent {
            let ev = self.event_at(model, data, &last, EventKind::BranchJump, step);
            let err = SolveError::Event { step, time: ahead, message: ev.message.clone() };
            self.events.push(ev);
            if self.on_singular == OnSingular::Stop {
                return Err(err);
            }
            taylor(data, &last, target);
            let info = full_solve(model, data, target, step)?;
            self.det_prev = info.det_sign;
            let b = State::capture(data, target, info);
            return Ok((last, b));
        }
        Err(match failure {
            Failure::NoSolution(e) => e,
            _ => SolveError::Event {
                step,
                time: ahead,
                message: format!(
                    "the solution next to t = {ahead:.12} is nearly singular (pivot ratio below {NEAR_SINGULAR:e}) \
                     and cannot be stepped over"
                ),
            },
        })
    }

    /// The event for a certified state (its factorization refreshed first).
    fn event_at(&self, model: &Model, data: &mut Data, s: &State, kind: EventKind, step: usize) -> Event {
        s.restore(data);
        factor_without_newton(model, data, s.t);
        self.event(model, data, kind, step, s.t)
    }

    /// Narrows [last solved, first unsolved] to round-off by bisection; near a fold in t
    /// the solution moves like sqrt(t* - t), so each probe starts from the last solution
    /// (a Taylor prediction would overshoot).
    fn bisect_fold(
        &self,
        model: &Model,
        data: &mut Data,
        mut good: State,
        mut bad: f64,
        step: usize,
    ) -> (State, f64) {
        for _ in 0..80 {
            let tol = 4.0 * f64::EPSILON * good.t.abs().max(bad.abs()).max(1.0);
            if (bad - good.t).abs() <= tol {
                break;
            }
            let mid = 0.5 * (good.t + bad);
            data.q.copy_from_slice(&good.q);
            match full_solve(model, data, mid, step) {
                Ok(info) => good = State::capture(data, mid, info),
                Err(_) => bad = mid,
            }
        }
        (good, bad)
    }

    /// After step k's velocity solve: locates the locks of the outputs since step k-1.
    pub fn after_velocity(
        &mut self,
        model: &Model,
        data: &mut Data,
        t_prev: f64,
        t: f64,
        step: usize,
    ) -> Result<(), SolveError> {
        if self.outputs.is_empty() {
            return Ok(());
        }
        let mut reversed = Vec::new();
        for (j, o) in self.outputs.iter().enumerate() {
            let r = o.rate(&data.qd);
            if r * self.rate_prev[j] < 0.0 {
                reversed.push(j);
            }
            if r != 0.0 {
                self.rate_prev[j] = r;
            }
        }
        if reversed.is_empty() {
            return Ok(());
        }
        let state_k = State::capture(data, t, here(data));
        let from = self.previous(model, data, t_prev, step)?;
        for j in reversed {
            let output = &self.outputs[j];
            let rate_at = |data: &mut Data, tm: f64| -> Option<f64> {
                reach(model, data, &from, tm, step).map(|_| output.rate(&data.qd))
            };
            if let Some(t_star) = illinois(t_prev, t, |tm| rate_at(data, tm)) {
                reach(model, data, &from, t_star, step).ok_or_else(|| SolveError::Event {
                    step,
                    time: t_star,
                    message: format!("could not solve at the lock of {}", output.name),
                })?;
                let name = output.name.clone();
                let mut ev = self.event(model, data, EventKind::Lock, step, t_star);
                ev.message = ev.message.replacen("the output", &format!("output {name}"), 1);
                ev.output = Some(name);
                self.events.push(ev);
            }
        }
        // back to step k as solved
        state_k.restore(data);
        factor_without_newton(model, data, t);
        Ok(())
    }
}
