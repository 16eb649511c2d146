//! Following one assembly branch through a sweep, and reporting where it goes singular.
//!
//! Each step is checked against its prediction: a Newton correction much larger than the
//! predicted motion means the solution left the branch the sweep was following. A failed
//! or jumping step is redone from the previous step in halved sub-steps; if that gets
//! through, nothing is lost, and if it does not, the place is located and reported.
//! Between two good steps, a change of sign of det Phi_q means a singular configuration
//! was crossed; it is located by root-finding on the signed smallest singular value.
//! Locks (an output stopping and reversing) are located on the output's rate.
//! All of this allocates only when something happens.

use crate::acceleration::solve_acceleration;
use crate::analysis::singular::{
    classify, constraint_shares, coordinate_shares, smallest_singular, Event, EventKind,
};
use crate::data::Data;
use crate::error::SolveError;
use crate::joints::{Constraint, ConstraintKind};
use crate::model::Model;
use crate::position::{solve_position, PositionInfo};
use crate::velocity::solve_velocity;

/// A step whose Newton correction exceeds this fraction of the predicted motion (or of
/// `JUMP_FLOOR` when little motion is predicted) is suspected of leaving its branch. On a
/// smooth branch the ratio is O((omega h)^2) or smaller, so a false alarm only costs a
/// subdivision.
pub const JUMP_RATIO: f64 = 0.5;
/// Scaled motion (L or rad) below which the prediction is not trusted to judge a jump.
pub const JUMP_FLOOR: f64 = 0.02;
/// Sub-steps are halved at most this many times (2^-24 of a step) before giving up.
const MAX_HALVINGS: i32 = 24;
/// Where det Phi_q changed sign, a located sigma_min above this means no singular
/// configuration was crossed (a jump between branches that pass close). A crossing is
/// located to sigma_min ~ sqrt(eps) (see `illinois`); branches that pass within 1e-4 are
/// reported as meeting.
pub const CROSSING_SIGMA: f64 = 1e-4;
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
                let slide_driven = model.constraints.iter().any(|d| {
                    matches!(d.kind, ConstraintKind::TranslationDriver(_))
                        && d.body_a == c.body_a
                        && d.body_b == c.body_b
                });
                if slide_driven {
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

/// Whether a converged step left the branch: see `JUMP_RATIO`.
#[inline]
pub fn is_jump(info: &PositionInfo, predicted_motion: f64) -> bool {
    info.correction > JUMP_RATIO * predicted_motion.max(JUMP_FLOOR)
}

/// A solved configuration with its rates, to restart from.
#[derive(Debug, Clone)]
struct State {
    t: f64,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    /// the pivot ratio there: next to a singular configuration the rates are not used
    ratio: f64,
}

impl State {
    fn capture(data: &Data, t: f64) -> State {
        State { t, q: data.q.clone(), qd: data.qd.clone(), qdd: data.qdd.clone(), ratio: data.pivots.ratio }
    }
}

/// Why a march stopped short.
enum Stuck {
    /// Newton fails ahead of `last` (or Phi_q is singular there): a limit or a hard spot.
    NoSolution { last: State, ahead: f64, cause: Box<SolveError> },
    /// Newton converges ahead of `last`, but always off the branch.
    Jump { last: State, ahead: f64 },
}

/// Positions, velocities and accelerations at t, from data.q as the start.
fn full_solve(model: &Model, data: &mut Data, t: f64, step: usize) -> Result<PositionInfo, SolveError> {
    let info = solve_position(model, data, t, step, false)?;
    solve_velocity(model, data, t, step)?;
    solve_acceleration(model, data, t, step)?;
    Ok(info)
}

/// From `from`, reaches t in Taylor-predicted sub-steps, halving on failure or jump.
/// Leaves data at t (q, qd, qdd and the factorization of Phi_q).
fn march(model: &Model, data: &mut Data, from: &State, t: f64, step: usize) -> Result<PositionInfo, Stuck> {
    march_keeping(model, data, from, t, step, None)
}

/// `march`, and with `det` given, a sub-step that changes the sign of det Phi_q counts as
/// a jump (used once no singular configuration was found between the two steps).
fn march_keeping(
    model: &Model,
    data: &mut Data,
    from: &State,
    t: f64,
    step: usize,
    det: Option<f64>,
) -> Result<PositionInfo, Stuck> {
    let total = t - from.t;
    let h_min = total.abs() * 2f64.powi(-MAX_HALVINGS);
    let mut cur = from.clone();
    let mut h = total;
    loop {
        let target = if (cur.t + h - t) * total.signum() >= 0.0 { t } else { cur.t + h };
        let hh = target - cur.t;
        let mut motion = 0.0f64;
        // rates solved next to a singular configuration are ill-determined: not followed
        let rates = if cur.ratio < crate::sweep::NEAR_SINGULAR { 0.0 } else { 1.0 };
        for i in 0..data.q.len() {
            let dq = rates * hh * (cur.qd[i] + 0.5 * hh * cur.qdd[i]);
            data.q[i] = cur.q[i] + dq;
            motion = motion.max(dq.abs() / model.col_scale[i]);
        }
        let result = full_solve(model, data, target, step);
        let failed = match result {
            Ok(info)
                if (!is_jump(&info, motion) || hh == 0.0) && det.is_none_or(|d| info.det_sign * d > 0.0) =>
            {
                if target == t {
                    return Ok(info);
                }
                cur.t = target;
                cur.q.copy_from_slice(&data.q);
                cur.qd.copy_from_slice(&data.qd);
                cur.qdd.copy_from_slice(&data.qdd);
                cur.ratio = data.pivots.ratio;
                h = 2.0 * hh;
                continue;
            }
            Ok(_) => None,
            Err(e) => Some(e),
        };
        h = 0.5 * hh;
        if h.abs() < h_min || h == 0.0 {
            return Err(match failed {
                Some(cause) => Stuck::NoSolution { last: cur, ahead: target, cause: Box::new(cause) },
                None => Stuck::Jump { last: cur, ahead: target },
            });
        }
    }
}

/// Factors Phi_q at a state's configuration, without Newton (a solved configuration
/// right at a singularity may not pass Newton's tests again), for its singular vectors.
fn factor_at(model: &Model, data: &mut Data, t: f64) {
    crate::assembly::position(model, data, t);
    data.pivots = data.factor.factor(&model.symbolic, &data.jac);
}

/// Solves at `state.t` again (from its q) so that `data` holds its factorization.
fn resolve(model: &Model, data: &mut Data, state: &State, step: usize) -> Result<PositionInfo, SolveError> {
    data.q.copy_from_slice(&state.q);
    full_solve(model, data, state.t, step)
}

/// Follows the branch through steps and records events.
pub struct Tracker {
    pub on_singular: OnSingular,
    /// watch outputs for locks (needs velocities)
    pub locks: bool,
    outputs: Vec<Output>,
    /// q at the previous step
    pub(crate) q_prev: Vec<f64>,
    rate_prev: Vec<f64>,
    det_prev: f64,
    pub events: Vec<Event>,
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
            events: Vec::new(),
        }
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
        full_solve(model, data, t_prev, step)?;
        Ok(State::capture(data, t_prev))
    }

    fn event(&self, model: &Model, data: &mut Data, kind: EventKind, step: usize, t: f64) -> Event {
        let triple = smallest_singular(model, data, 4);
        let kind = match kind {
            EventKind::Limit | EventKind::Bifurcation => classify(model, &triple),
            k => k,
        };
        let values: Vec<(String, f64)> = model
            .constraints
            .iter()
            .filter(|c| c.role == "driver")
            .filter_map(|c| c.kind.law().map(|l| (c.name.clone(), l.eval(t)[0])))
            .collect();
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
        }
    }

    /// Step k's position solve failed or jumped: redo it from step k-1 in sub-steps.
    /// Ok: data is at times[k]. Err: an event was recorded (limit, jump) or the
    /// original error stands.
    pub fn rescue(
        &mut self,
        model: &Model,
        data: &mut Data,
        t_prev: f64,
        t: f64,
        step: usize,
        original: Option<SolveError>,
    ) -> Result<PositionInfo, SolveError> {
        let from = self.previous(model, data, t_prev, step)?;
        match march(model, data, &from, t, step) {
            Ok(info) => Ok(info),
            Err(Stuck::Jump { last, ahead }) => {
                // accept the off-branch solution only if asked to go on
                data.q.copy_from_slice(&last.q);
                resolve(model, data, &last, step)?;
                let ev = self.event(model, data, EventKind::BranchJump, step, last.t);
                let err = SolveError::Event { step, time: ahead, message: ev.message.clone() };
                self.events.push(ev);
                if self.on_singular == OnSingular::Stop {
                    return Err(err);
                }
                data.q.copy_from_slice(&last.q);
                let mut info = solve_position(model, data, t, step, true)?;
                info.correction = 0.0;
                Ok(info)
            }
            Err(Stuck::NoSolution { last, ahead, cause }) => {
                let (last, _ahead) = self.bisect_fold(model, data, last, ahead, step);
                data.q.copy_from_slice(&last.q);
                factor_at(model, data, last.t);
                let ev = self.event(model, data, EventKind::Limit, step, last.t);
                if ev.kind == EventKind::Limit && ev.sigma_min < 1e-4 {
                    let err = SolveError::Event { step, time: last.t, message: ev.message.clone() };
                    self.events.push(ev);
                    Err(err)
                } else {
                    Err(original.unwrap_or(*cause))
                }
            }
        }
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
                Ok(_) => good = State::capture(data, mid),
                Err(_) => bad = mid,
            }
        }
        (good, bad)
    }

    /// After step k's position solve (data at times[k], factorization of Phi_q there):
    /// where det Phi_q changed sign since step k-1, either a singular configuration was
    /// crossed (located, reported) or the step jumped to another branch without one (no
    /// zero of sigma_min between): then the step is redone in sub-steps that keep the
    /// sign. Returns the step's position info (new if redone).
    pub fn after_position(
        &mut self,
        model: &Model,
        data: &mut Data,
        info: PositionInfo,
        t_prev: f64,
        t: f64,
        step: usize,
    ) -> Result<PositionInfo, SolveError> {
        let det = info.det_sign;
        let det_prev = self.det_prev;
        if det * det_prev >= 0.0 {
            if det != 0.0 {
                self.det_prev = det;
            }
            return Ok(info);
        }
        let q_k = data.q.clone();
        let from = self.previous(model, data, t_prev, step)?;
        let sigma_at = |data: &mut Data, tm: f64| -> Option<f64> {
            march(model, data, &from, tm, step).ok().map(|info| {
                let triple = smallest_singular(model, data, 3);
                triple.sigma * info.det_sign
            })
        };
        let root = illinois(t_prev, t, |tm| sigma_at(data, tm));
        if let Some(t_star) = root {
            // the configuration there is whatever the march reached (its Newton tests may
            // fail right at the crossing)
            let _ = march(model, data, &from, t_star, step);
            factor_at(model, data, t_star);
            let ev = self.event(model, data, EventKind::Bifurcation, step, t_star);
            if ev.sigma_min <= CROSSING_SIGMA {
                self.det_prev = det;
                let stop = self.on_singular == OnSingular::Stop;
                let err = SolveError::Event { step, time: t_star, message: ev.message.clone() };
                self.events.push(ev);
                if stop {
                    return Err(err);
                }
                data.q.copy_from_slice(&q_k);
                return solve_position(model, data, t, step, false);
            }
        }
        // no singular configuration in between: the step left its branch
        match march_keeping(model, data, &from, t, step, Some(det_prev)) {
            Ok(info) => Ok(info),
            Err(_) => {
                let ev = self.event(model, data, EventKind::BranchJump, step, t);
                let err = SolveError::Event { step, time: t, message: ev.message.clone() };
                self.events.push(ev);
                if self.on_singular == OnSingular::Stop {
                    return Err(err);
                }
                self.det_prev = det;
                data.q.copy_from_slice(&q_k);
                solve_position(model, data, t, step, false)
            }
        }
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
        let state_k = State::capture(data, t);
        let from = self.previous(model, data, t_prev, step)?;
        for j in reversed {
            let output = &self.outputs[j];
            let rate_at = |data: &mut Data, tm: f64| -> Option<f64> {
                march(model, data, &from, tm, step).ok().map(|_| output.rate(&data.qd))
            };
            if let Some(t_star) = illinois(t_prev, t, |tm| rate_at(data, tm)) {
                march(model, data, &from, t_star, step).map_err(|_| SolveError::Event {
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
        resolve(model, data, &state_k, step)?;
        Ok(())
    }
}

/// A root of f in [a, b] (f(a), f(b) of opposite signs) by the Illinois variant of
/// regula falsi: superlinear on simple roots, never leaves the bracket. None if f cannot
/// be evaluated at the ends. The caller has seen f change sign between a and b.
///
/// How precise the root is depends on f: a signed sigma_min is known only to about
/// sqrt(eps) near a bifurcation (the residual is quadratic in the distance to the
/// crossing branches, so Newton's solutions wander by sqrt(eps) there), while a rate's
/// zero (a lock) is found to round-off.
fn illinois(mut a: f64, mut b: f64, mut f: impl FnMut(f64) -> Option<f64>) -> Option<f64> {
    let mut fa = f(a)?;
    let mut fb = f(b)?;
    if fa == 0.0 {
        return Some(a);
    }
    if fb == 0.0 {
        return Some(b);
    }
    if fa * fb > 0.0 {
        // the caller saw a sign change between a and b; re-evaluated, one end is so close
        // to the root that its sign is round-off: that end is the root
        return Some(if fa.abs() < fb.abs() { a } else { b });
    }
    let tol = 4.0 * f64::EPSILON * a.abs().max(b.abs()).max((b - a).abs());
    for _ in 0..100 {
        let mut m = (a * fb - b * fa) / (fb - fa);
        if !m.is_finite() || (m - a) * (m - b) > 0.0 {
            m = 0.5 * (a + b);
        }
        let fm = match f(m) {
            Some(v) => v,
            // singular to round-off right at m: that is the root
            None => return Some(m),
        };
        if fm == 0.0 {
            return Some(m);
        }
        if fm * fb < 0.0 {
            a = b;
            fa = fb;
        } else {
            fa *= 0.5;
        }
        b = m;
        fb = fm;
        if (b - a).abs() <= tol {
            break;
        }
    }
    Some(b)
}
