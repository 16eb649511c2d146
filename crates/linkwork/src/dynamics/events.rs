//! Events of a simulation, the sweep's kinds and fields (`solve::events`), found from the
//! accepted steps and located between them on the quintic Hermite interpolant of
//! (q, qd, qdd) at the steps' ends:
//! - a singular configuration passed (a bifurcation; a limit if a driver row is in the
//!   dependency): looked for where the smallest singular value of Phi_q (mass metric)
//!   at the accepted steps' ends has a local minimum that a V through it could bring to
//!   zero within the steps (whatever their size; a sample off the constraints, an
//!   integrator's dense output, projected onto them first), located at the minimum of
//!   its square on the interpolant (Brent's method), the event's configuration that q
//!   projected onto the constraints;
//! - a lock: the whole motion stops and reverses (every rate zero at once: a swing's end,
//!   a crank that stops short of a dead centre), located where qd turns against itself;
//! - a slider's limits (`travel`): the end of the travel it is given, and its geometric
//!   limit (a lock of that slider), located where its slide, or its rate, crosses them.
#![allow(clippy::needless_range_loop)] // numeric kernels: one index runs over several arrays

use nalgebra::DMatrix;

use crate::dynamics::augmented::Equilibration;
use crate::dynamics::equilibrium::constraints_dense;
use crate::dynamics::mass::mass_times;
use crate::dynamics::system::{max_abs, System};
use crate::dynamics::travel::GEOMETRIC_BELOW;
use crate::math::minimize::brent;
use crate::math::roots::illinois;
use crate::model::slider::{sliders, Slider};
use crate::model::Model;
use crate::solve::events::{
    classify, constraint_shares, coordinate_shares, driver_values, Event, EventKind, SingularTriple,
};

/// A step end whose sigma_min (mass metric) is a local minimum below this is always
/// searched for a singular crossing; above it only if the slopes on either side could
/// bring it to zero within the steps (a crossing stepped over by long steps).
pub const WATCH_BELOW: f64 = 0.1;
/// A reversal is a lock when the rates left where qd turns against itself are below
/// this fraction of the step's: at a genuine stop they vanish together (the interpolant's
/// error is what remains), a motion with several freedoms turning aside keeps rates of
/// its own size.
pub const LOCK_SPEED: f64 = 1e-3;
/// A located minimum is a singular configuration if the scaled Phi_q's smallest singular
/// value there is below this: at a crossing what is left is the interpolant's error
/// (1e-8 to 8e-4 from fine to coarse tolerances on the N-four-bar, rtol 1e-10 to 1e-3),
/// a close pass that is not one leaves its own distance (0.06 and more at the
/// N-four-bar's other minima).
pub const SINGULAR_BELOW: f64 = 1e-2;
/// The scaled |Phi| an event's configuration keeps without a word: the interpolated q
/// projected onto the constraints by Gauss-Newton, which near a crossing converges only
/// linearly and stalls above the projections' tolerance (the residual is quadratic in the
/// distance to the crossing branches): up to 1.1e-7 measured where long steps of rtol
/// 1e-3 leave the interpolant 1e-3 off (a parallelogram spinning at up to 120 rad/s).
/// Coarser tolerances leave it 3e-3 off and the projection stalls at 1e-6 to 1e-5: the
/// crossing is reported all the same, its message saying how far off its configuration is.
const EVENT_RESIDUAL: f64 = 1e-6;
/// A step is sampled at its midpoint too where sigma_min at one of its ends is below
/// this (A01's is 1 throughout, A02's ends 0.1 to 0.4 around its crossings at the
/// coarsest tolerances), or where sigma_min falls steeply enough to cross zero within the
/// step (`Watch::accepted`: a parallelogram turning 0.56 rad a step keeps both ends of the
/// step holding a crossing above 0.5).
pub const MIDPOINT_BELOW: f64 = 0.5;
/// The watch samples a step at interior points too (an integrator's dense output) where
/// the step moves some coordinate (scaled: an angle in radians, a position over the
/// model's length) by more than this: a smooth fast motion (a crank spinning) lets a
/// high-order integrator step over several crossings, farther apart than its step (a
/// parallelogram's are pi apart: every 1.0 rad missed some in a third of 400 runs).
pub const WATCH_MOVE: f64 = 0.5;
/// A sample further than this (scaled |phi|) off the constraints is projected onto them
/// before the watch uses it (`Watch::settle`): rk8's dense output inside a long step lies
/// up to 0.23 off at rtol 3e-3 (its ends are projected), and sigma_min taken there is off
/// by several times that (0.30 for 0.47 on the constraints, 0.77 for 0.43, both 0.1 off),
/// enough to hide a crossing's V or to leave a crossing looking like a close pass.
pub const WATCH_RESIDUAL: f64 = 1e-3;
/// Shares below this are left out of an event's constraints and coordinates.
const SHARE_FLOOR: f64 = 0.05;

/// One accepted step's end: the state, the smallest pivot ratio met on the way,
/// sigma_min of Phi_q there (mass metric) and at the step's midpoint on the interpolant
/// (two crossings a long step apart leave no minimum among the ends alone).
#[derive(Debug, Clone)]
struct Sample {
    t: f64,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    pivot: f64,
    sigma: f64,
    mid: f64,
    /// whether the sample was brought onto the constraints (`Watch::settle`)
    settled: bool,
}

/// Whether b, between a and c ((t, sigma_min) each), is a minimum of sigma_min worth a
/// search: a local minimum, below `WATCH_BELOW` or no higher than the steeper side's
/// slope could take to zero within the longer interval (a V stepped over: sigma = k |t -
/// t*| gives sigma_b <= k h).
fn dips(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> bool {
    if !(b.1 <= a.1 && b.1 < c.1) {
        return false;
    }
    let slope = ((a.1 - b.1) / (b.0 - a.0)).max((c.1 - b.1) / (c.0 - b.0));
    b.1 < WATCH_BELOW || b.1 <= slope * (b.0 - a.0).max(c.0 - b.0)
}

/// Whether a model is watched for singular configurations: it has constraints and freedoms.
fn watched(model: &Model) -> bool {
    model.n_rows > 0 && model.n_rows < model.n_coords
}

/// Watches the accepted steps of a simulation for events.
pub struct Watch {
    samples: Vec<Sample>,
    /// the smallest pivot ratio of the step under way
    step_pivot: f64,
    last_event: f64,
    /// where the last search for a crossing ended
    searched: f64,
    /// the last point of the samples' sequence (ends and midpoints) tested for a dip
    tested: f64,
    q: Vec<f64>,
    qd: Vec<f64>,
    /// the last dependency of the rows found (inverse iteration's start)
    w: Vec<f64>,
    /// the prismatic joints, and whether a travel's end stops the simulation
    sliders: Vec<Slider>,
    stop_at_travel_end: bool,
}

/// The quintic Hermite interpolant on [a.t, b.t] at t: q and qd.
fn hermite(a: &Sample, b: &Sample, t: f64, q: &mut [f64], qd: &mut [f64]) {
    let h = b.t - a.t;
    let s = ((t - a.t) / h).clamp(0.0, 1.0);
    let (s2, s3) = (s * s, s * s * s);
    let (s4, s5) = (s3 * s, s3 * s2);
    let p = [
        1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5,
        s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5,
        0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5,
        10.0 * s3 - 15.0 * s4 + 6.0 * s5,
        -4.0 * s3 + 7.0 * s4 - 3.0 * s5,
        0.5 * s3 - s4 + 0.5 * s5,
    ];
    let d = [
        -30.0 * s2 + 60.0 * s3 - 30.0 * s4,
        1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4,
        s - 4.5 * s2 + 6.0 * s3 - 2.5 * s4,
        30.0 * s2 - 60.0 * s3 + 30.0 * s4,
        -12.0 * s2 + 28.0 * s3 - 15.0 * s4,
        1.5 * s2 - 4.0 * s3 + 2.5 * s4,
    ];
    for i in 0..q.len() {
        let c = [a.q[i], h * a.qd[i], h * h * a.qdd[i], b.q[i], h * b.qd[i], h * h * b.qdd[i]];
        q[i] = (0..6).map(|k| p[k] * c[k]).sum();
        qd[i] = (0..6).map(|k| d[k] * c[k]).sum::<f64>() / h;
    }
}

/// Scaled dot product of two rates (lengths over the model's length scale).
fn dot(model: &Model, a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).zip(&model.col_scale).map(|((x, y), s)| x * y / (s * s)).sum()
}

impl Watch {
    pub fn new(model: &Model, stop_at_travel_end: bool) -> Watch {
        let n = model.n_coords;
        Watch {
            samples: Vec::with_capacity(3),
            step_pivot: f64::INFINITY,
            last_event: f64::NEG_INFINITY,
            searched: f64::NEG_INFINITY,
            tested: f64::NEG_INFINITY,
            q: vec![0.0; n],
            qd: vec![0.0; n],
            w: (0..model.n_rows).map(|i| 1.0 + 0.1 * ((i * 7 + 3) % 11) as f64).collect(),
            sliders: sliders(model),
            stop_at_travel_end,
        }
    }

    /// How many samples a step from q_a to q_b needs inside it (none if the model is not
    /// watched for singular configurations): every `WATCH_MOVE` of its largest move.
    pub fn interior_samples(model: &Model, q_a: &[f64], q_b: &[f64]) -> usize {
        if !watched(model) {
            return 0;
        }
        let moved =
            q_a.iter().zip(q_b).zip(&model.col_scale).fold(0.0f64, |m, ((a, b), s)| m.max((b - a).abs() / s));
        // a non-finite move is the step's own error to report, not the watch's
        if moved.is_finite() {
            (moved / WATCH_MOVE).ceil().max(1.0) as usize - 1
        } else {
            0
        }
    }

    /// A solve of the step under way had this pivot ratio.
    #[inline]
    pub fn pivot(&mut self, ratio: f64) {
        if ratio < self.step_pivot {
            self.step_pivot = ratio;
        }
    }

    /// An accepted step ended at (t, q, qd, qdd) (the first call: the start). Events
    /// found are appended to `events`, `times` are the output times (for their step).
    /// Returns the time the simulation stops at: a travel's end met, if it stops there.
    #[allow(clippy::too_many_arguments)]
    pub fn accepted(
        &mut self,
        model: &Model,
        sys: &mut System,
        times: &[f64],
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        events: &mut Vec<Event>,
    ) -> Option<f64> {
        let pivot = std::mem::replace(&mut self.step_pivot, f64::INFINITY);
        let mut sample = if self.samples.len() == 3 { self.samples.remove(0) } else { self.empty(q.len()) };
        sample.t = t;
        sample.q.copy_from_slice(q);
        sample.qd.copy_from_slice(qd);
        sample.qdd.copy_from_slice(qdd);
        sample.pivot = pivot;
        let watched = watched(model);
        sample.sigma = if watched { sigma_here(model, sys, q, t, &mut self.w) } else { f64::INFINITY };
        sample.settled =
            watched && max_abs(&sys.phi) > WATCH_RESIDUAL && self.settle(model, sys, &mut sample);
        // not sampled: the ends' mean, never a dip of its own
        sample.mid = self.samples.last().map_or(f64::INFINITY, |a| 0.5 * (a.sigma + sample.sigma));
        if let (Some(a), true) = (self.samples.last(), watched) {
            // or where sigma_min falls into the step fast enough to reach zero inside it: a
            // crossing stepped over whole leaves sigma_a + sigma_b = k h at its ends (a V of
            // slope k), k taken as twice the fall seen before a (sigma bends down into a
            // crossing); a long step of a fast motion has both ends far from the crossing
            let falls_through = match self.samples.len() {
                2 => {
                    let p = &self.samples[0];
                    let slope = (p.sigma - a.sigma) / (a.t - p.t);
                    a.sigma + sample.sigma <= 2.0 * slope * (t - a.t)
                }
                _ => true,
            };
            // or where an end was projected: the projection moves it along the constraints,
            // its spacing to its neighbour no longer the watch's (0.67 rad at rtol 0.1)
            if a.sigma.min(sample.sigma) < MIDPOINT_BELOW || falls_through || a.settled || sample.settled {
                let tm = 0.5 * (a.t + t);
                hermite(a, &sample, tm, &mut self.q, &mut self.qd);
                sample.mid = sigma_here(model, sys, &self.q, tm, &mut self.w);
            }
        }
        self.samples.push(sample);
        let k = self.samples.len();
        if k >= 2 {
            self.lock(model, k - 2, times, events);
        }
        if k == 3 {
            // the sequence of ends and midpoints: each point between two others tested once
            let s = &self.samples;
            let fine = [
                (s[0].t, s[0].sigma),
                (0.5 * (s[0].t + s[1].t), s[1].mid),
                (s[1].t, s[1].sigma),
                (0.5 * (s[1].t + s[2].t), s[2].mid),
                (s[2].t, s[2].sigma),
            ];
            for i in 1..4 {
                if fine[i].0 > self.tested && dips(fine[i - 1], fine[i], fine[i + 1]) {
                    self.singular(model, sys, times, events, fine[i - 1].0, fine[i + 1].0, fine[i], false);
                }
            }
            self.tested = fine[3].0;
        }
        if k >= 2 {
            return self.travel(model, sys, k - 2, times, events);
        }
        None
    }

    /// The end of the run: a crossing in the last step, its ratio still falling.
    pub fn finish(&mut self, model: &Model, sys: &mut System, times: &[f64], events: &mut Vec<Event>) {
        let k = self.samples.len();
        if k >= 2 {
            let (b, c) = (&self.samples[k - 2], &self.samples[k - 1]);
            // still falling at the end: the mirror image of the midpoint stands for beyond
            let tm = 0.5 * (b.t + c.t);
            let (mid, end) = ((tm, c.mid), (c.t, c.sigma));
            let beyond = dips(mid, end, (2.0 * c.t - tm, c.mid));
            // or past a crossing already, between the midpoint and the end, the far side of
            // the V lower than the midpoint: sigma_mid + sigma_end = k (t_end - t_mid) for a
            // V of slope k, k taken as twice the fall from b to the midpoint (as in `accepted`)
            let slope = (b.sigma - c.mid) / (tm - b.t);
            let inside = c.mid + c.sigma <= 2.0 * slope * (c.t - tm);
            if c.sigma < c.mid && (beyond || inside) {
                let (lo, hi) = (b.t, c.t);
                self.samples.drain(..k - 2);
                self.samples.push(self.samples[1].clone());
                // [b, c, c]: the search runs over [b, c] only (an empty second interval)
                self.singular(model, sys, times, events, lo, hi, mid, true);
            }
        }
        // a search's window reaches back past the last step's locks and limits
        events.sort_by(|a, b| a.time.total_cmp(&b.time));
    }

    /// Brings a sample off the constraints (an integrator's dense output inside a long
    /// step) onto them: q and qd projected, qdd solved there, sigma_min taken again; the
    /// sample is kept as it was where the projection does not bring q closer. Returns
    /// whether it was moved.
    fn settle(&mut self, model: &Model, sys: &mut System, s: &mut Sample) -> bool {
        let (q0, qd0) = (s.q.clone(), s.qd.clone());
        let (_, before, residual, _) = sys.project_state(model, &mut s.q, &mut s.qd, s.t, Equilibration::New);
        if !residual.is_finite() || residual >= before {
            s.q.copy_from_slice(&q0);
            s.qd.copy_from_slice(&qd0);
            return false;
        }
        if residual > model.options.tol_residual {
            sys.project_velocities(model, &s.q, &mut s.qd, s.t);
        }
        let mut lambda = vec![0.0; model.n_rows];
        sys.accelerations(model, &s.q, &s.qd, s.t, &mut s.qdd, &mut lambda, Equilibration::New);
        s.sigma = sigma_here(model, sys, &s.q, s.t, &mut self.w);
        true
    }

    fn empty(&self, n: usize) -> Sample {
        Sample {
            t: 0.0,
            q: vec![0.0; n],
            qd: vec![0.0; n],
            qdd: vec![0.0; n],
            pivot: f64::INFINITY,
            sigma: f64::INFINITY,
            mid: f64::INFINITY,
            settled: false,
        }
    }

    /// Each slider between samples i and i + 1: the end of its travel crossed (the first
    /// one met, if it stops the simulation: its time returned), its rate changing sign
    /// where its slide is stationary along every allowed motion (its geometric limit).
    fn travel(
        &mut self,
        model: &Model,
        sys: &mut System,
        i: usize,
        times: &[f64],
        events: &mut Vec<Event>,
    ) -> Option<f64> {
        let (a, b) = (&self.samples[i], &self.samples[i + 1]);
        let (q, qd) = (&mut self.q, &mut self.qd);
        let mut stop: Option<f64> = None;
        for s in &self.sliders {
            let rate = |t: f64, q: &mut [f64], qd: &mut [f64]| {
                hermite(a, b, t, q, qd);
                s.slide(q, qd).1
            };
            let ((_, va), (_, vb)) = (s.slide(&a.q, &a.qd), s.slide(&b.q, &b.qd));
            // where the slide turns back inside the step (its extreme), if it does
            let turn = if va * vb < 0.0 { illinois(a.t, b.t, |t| Some(rate(t, q, qd))) } else { None };
            if let Some([lo, hi]) = s.travel {
                for (bound, side) in [(lo, -1.0), (hi, 1.0)] {
                    // beyond the end: side (x - bound) > 0; first checked at the extreme
                    let beyond = |t: f64, q: &mut [f64], qd: &mut [f64]| {
                        hermite(a, b, t, q, qd);
                        side * (s.slide(q, qd).0 - bound)
                    };
                    if beyond(a.t, q, qd) > 0.0 {
                        continue;
                    }
                    let end = [turn, Some(b.t)].into_iter().flatten().find(|&t| beyond(t, q, qd) > 0.0);
                    let Some(end) = end else { continue };
                    let Some(t) = illinois(a.t, end, |t| Some(beyond(t, q, qd))) else { continue };
                    hermite(a, b, t, q, qd);
                    let _ = sys.project_positions(model, q, t, 1e-15);
                    let what = if side > 0.0 { "max" } else { "min" };
                    let then = if self.stop_at_travel_end {
                        "the simulation stops there, the rows before it kept"
                    } else {
                        "the simulation goes on through it (no stop is modelled)"
                    };
                    let message = format!(
                        "slider '{}' reaches the end of its travel at t = {t:.12} (its {what}, {bound}): {then}",
                        s.name
                    );
                    let pivot = a.pivot.min(b.pivot);
                    events.push(slider_event(
                        model,
                        EventKind::EndOfTravel,
                        &s.name,
                        t,
                        q,
                        times,
                        message,
                        pivot,
                    ));
                    if self.stop_at_travel_end && stop.is_none_or(|x| t < x) {
                        stop = Some(t);
                    }
                }
            }
            // the rate's zero: a stroke's end if the mechanism moves on and the slide is
            // stationary along every motion the joints allow there
            let Some(t) = turn else { continue };
            rate(t, q, qd);
            let speed = dot(model, qd, qd).sqrt();
            let step_speed = dot(model, &a.qd, &a.qd).sqrt().max(dot(model, &b.qd, &b.qd).sqrt());
            if speed <= LOCK_SPEED * step_speed || model.n_rows >= model.n_coords {
                continue;
            }
            let _ = sys.project_positions(model, q, t, 1e-15);
            let Some(basis) = free_motions(model, sys, q, t) else { continue };
            let share = s.free_share(model, q, &basis);
            if share > GEOMETRIC_BELOW {
                continue;
            }
            let (x, _) = s.slide(q, qd);
            let message = format!(
                "slider '{}' stops and reverses at t = {t:.12} (slide {x:.9e}) while the mechanism \
                 moves on: the end of its stroke, where the joints leave it no way further",
                s.name
            );
            let pivot = a.pivot.min(b.pivot);
            events.push(slider_event(model, EventKind::Lock, &s.name, t, q, times, message, pivot));
        }
        // a stop ends the run: what was found after it did not happen
        if let Some(t_stop) = stop {
            events.retain(|e| e.time <= t_stop);
        }
        stop
    }

    /// The whole motion reverses between samples i and i + 1: a lock if every rate
    /// vanishes where qd turns against the first sample's.
    fn lock(&mut self, model: &Model, i: usize, times: &[f64], events: &mut Vec<Event>) {
        let (a, b) = (&self.samples[i], &self.samples[i + 1]);
        let (speed_a, speed_b) = (dot(model, &a.qd, &a.qd).sqrt(), dot(model, &b.qd, &b.qd).sqrt());
        if dot(model, &a.qd, &b.qd) >= 0.0 || speed_a == 0.0 {
            return;
        }
        let (q, qd) = (&mut self.q, &mut self.qd);
        let along = |t: f64, q: &mut [f64], qd: &mut [f64]| {
            hermite(a, b, t, q, qd);
            dot(model, qd, &a.qd)
        };
        let Some(t) = illinois(a.t, b.t, |t| Some(along(t, q, qd))) else { return };
        along(t, q, qd);
        let left = dot(model, qd, qd).sqrt();
        if left > LOCK_SPEED * speed_a.max(speed_b) || t <= self.last_event {
            return;
        }
        // the coordinate that reverses: the largest scaled acceleration there
        let near = if t - a.t < b.t - t { a } else { b };
        let mut dir: Vec<f64> = near.qdd.iter().zip(&model.col_scale).map(|(x, s)| x / s).collect();
        let norm = dir.iter().map(|x| x * x).sum::<f64>().sqrt();
        dir.iter_mut().for_each(|x| *x /= norm.max(f64::MIN_POSITIVE));
        let coordinates = coordinate_shares(model, &dir, SHARE_FLOOR);
        let output = coordinates.first().map(|(c, _)| c.clone());
        let message = format!(
            "the motion stops and reverses at t = {t:.12}{}: every rate is zero there (a swing's end, or a \
             dead centre the mechanism does not pass)",
            output.as_ref().map_or(String::new(), |c| format!(" ({c} turns back)"))
        );
        self.last_event = t;
        events.push(Event {
            kind: EventKind::Lock,
            step: times.partition_point(|&x| x < t),
            time: t,
            q: q.clone(),
            sigma_min: f64::NAN,
            constraints: Vec::new(),
            coordinates,
            output,
            drivers: driver_values(model, t),
            message,
            pivot_ratio: a.pivot.min(b.pivot),
        });
    }

    /// Looks for a singular configuration over [lo0, hi0] (within samples 0..3), from x
    /// where sigma_min = fx dips: the smallest
    /// singular value of Phi_q in the mass metric, sqrt of the smallest eigenvalue of
    /// Phi_q M^-1 Phi_q^T (inverse iteration on the augmented matrix), falls like |t - t*|
    /// into a crossing whatever the rank lost; Brent's method finds the minimum of its
    /// square on the interpolant, an event if the scaled Phi_q is singular there (below
    /// `SINGULAR_BELOW`). `last`: the window ends at the run's end, which no later window
    /// searches.
    #[allow(clippy::too_many_arguments)]
    fn singular(
        &mut self,
        model: &Model,
        sys: &mut System,
        times: &[f64],
        events: &mut Vec<Event>,
        lo0: f64,
        hi0: f64,
        (x, fx): (f64, f64),
        last: bool,
    ) {
        if !watched(model) {
            return;
        }
        // a window that starts before the last minimum found was searched with it
        if lo0 <= self.searched {
            return;
        }
        let pivot = self.samples[1].pivot.min(self.samples[2].pivot);
        let (q, qd, w) = (&mut self.q, &mut self.qd, &mut self.w);
        let samples = &self.samples;
        // sigma_min squared along the interpolant (smooth through a crossing, where
        // sigma = k |t - t*| is a V), at the interpolated q itself: its distance from
        // the constraints is the interpolant's error, and a projection there would stall
        // (near a singular configuration Gauss-Newton converges only linearly)
        let sigma2 = |t: f64| -> f64 {
            let (a, c) =
                if t <= samples[1].t { (&samples[0], &samples[1]) } else { (&samples[1], &samples[2]) };
            hermite(a, c, t, q, qd);
            sigma_here(model, sys, q, t, w).powi(2)
        };
        // Brent's method from the point of the dip, to 1e-9 of the window
        let tol = 1e-9 * (hi0 - lo0);
        let (t, sigma2_t) = brent(lo0, hi0, x, fx * fx, tol, 60, sigma2);
        // a minimum on the window's edge lies beyond it: a later window holds it; unless it
        // is the dip's own point (a step's end next to a crossing, its neighbour within 1e-3
        // of the window: sigma rises towards it, so no later window takes it as a dip)
        // A run's last window has no later one: there only a minimum at its end, within
        // twice Brent's stopping distance (tol + 1e-12 |t|), lies beyond it; crossings 1.4e-5
        // and 8.4e-5 rad of crank inside were dropped as beyond by the wider margin.
        let near = 1e-3 * (hi0 - lo0);
        let near_end = if last { 4.0 * (tol + 1e-12 * hi0.abs()) } else { near };
        if ((t - lo0) < near || hi0 - t < near_end) && (t - x).abs() >= near {
            return;
        }
        self.searched = t;
        // one crossing, found again from a neighbouring window; two crossings may be closer
        // than a window of long steps (A02's pairs at coarse tolerances)
        if t - self.last_event <= 0.1 * (hi0 - lo0) {
            return;
        }
        let (a, c) = if t <= samples[1].t { (&samples[0], &samples[1]) } else { (&samples[1], &samples[2]) };
        let Some((jt, residual)) = jacobian_at(model, sys, a, c, t, q, qd) else { return };
        let Some(basis) = free_motions(model, sys, q, t) else { return };
        let mut event = singular_event(model, &bordered(&jt, &basis), q, t, times, pivot);
        // a configuration left off the constraints has a sigma_min of that distance's
        // size: the interpolant's own minimum there says whether the motion crossed
        let stalled = residual > EVENT_RESIDUAL.max(model.options.tol_residual);
        if stalled {
            event.message.push_str(&format!(
                " (its configuration is left |phi| = {residual:.1e} off the constraints: next to the crossing \
                 the projection of the interpolated state stalls; a smaller rtol brings it closer)"
            ));
        }
        let crossed = if stalled { event.sigma_min.min(sigma2_t.sqrt()) } else { event.sigma_min };
        if crossed < SINGULAR_BELOW {
            self.last_event = t;
            events.push(event);
        }
    }
}

/// sigma_min of Phi_q in the mass metric at (q, t): three steps of
/// inverse iteration on Phi_q M^-1 Phi_q^T by solves with the augmented matrix, from the
/// last dependency `w` (left there).
fn sigma_here(model: &Model, sys: &mut System, q: &[f64], t: f64, w: &mut [f64]) -> f64 {
    let n = model.n_coords;
    sys.data.q.copy_from_slice(q);
    crate::solve::assembly::update_frames(&mut sys.data);
    sys.aug.fill(model, &sys.data.frames, q, t, 1.0, &mut sys.phi);
    // equilibrated as the workspace's last factorization (a row or a sample nearby): the
    // sweeps would cost as much as the LU, and sigma does not depend on them
    sys.aug.factor(0.0, Equilibration::Kept);
    // the workspace's own solve buffer (n + m)
    let x = &mut sys.x;
    let mut growth = 0.0;
    for _ in 0..3 {
        x[..n].fill(0.0);
        x[n..].copy_from_slice(w);
        sys.aug.solve(x);
        growth = x[n..].iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(growth > 0.0 && growth.is_finite()) {
            return 0.0;
        }
        for (wi, xi) in w.iter_mut().zip(&x[n..]) {
            *wi = xi / growth;
        }
    }
    (1.0 / growth).sqrt()
}

/// The scaled Phi_q at t on the interpolant over [a, c], q projected onto the constraints
/// (left in `q`), and the scaled |phi| left there. Where the projection stalls above
/// `EVENT_RESIDUAL` its last iterate is kept if it came closer than the interpolated point,
/// otherwise that point. None if |phi| is not finite there.
fn jacobian_at(
    model: &Model,
    sys: &mut System,
    a: &Sample,
    c: &Sample,
    t: f64,
    q: &mut [f64],
    qd: &mut [f64],
) -> Option<(DMatrix<f64>, f64)> {
    hermite(a, c, t, q, qd);
    let start = q.to_vec();
    let (_, before, mut residual) = sys.project_positions(model, q, t, 1e-15);
    if residual.is_nan() || residual > before {
        q.copy_from_slice(&start);
        sys.set_state(q, qd);
        residual = before;
    }
    residual.is_finite().then(|| (constraints_dense(model, sys.frames(), q, t).1, residual))
}

/// D = [Phi_q; B] (n x n): the rows and a basis of the free motions.
fn bordered(jac: &DMatrix<f64>, basis: &DMatrix<f64>) -> DMatrix<f64> {
    let (m, n) = jac.shape();
    let mut d = DMatrix::zeros(n, n);
    d.view_mut((0, 0), (m, n)).copy_from(jac);
    d.view_mut((m, 0), (n - m, n)).copy_from(basis);
    d
}

/// Each driver's value at t.
/// An event of one slider (`name`) at t, in state q: its joint the one constraint.
#[allow(clippy::too_many_arguments)]
fn slider_event(
    model: &Model,
    kind: EventKind,
    name: &str,
    t: f64,
    q: &[f64],
    times: &[f64],
    message: String,
    pivot_ratio: f64,
) -> Event {
    Event {
        kind,
        step: times.partition_point(|&x| x < t),
        time: t,
        q: q.to_vec(),
        sigma_min: f64::NAN,
        constraints: vec![(name.to_string(), 1.0)],
        coordinates: Vec::new(),
        output: Some(name.to_string()),
        drivers: driver_values(model, t),
        message,
        pivot_ratio,
    }
}

/// A basis (rows, scaled coordinates) of the motions the constraints allow at q: the
/// mass-metric projections onto Phi_q x = 0 of fixed vectors (n - m of them).
fn free_motions(model: &Model, sys: &mut System, q: &[f64], t: f64) -> Option<DMatrix<f64>> {
    let (n, m) = (model.n_coords, model.n_rows);
    let d = n - m;
    sys.set_state(q, &vec![0.0; n]);
    let mut phi = vec![0.0; m];
    sys.aug.fill(model, &sys.data.frames, q, t, 1.0, &mut phi);
    let mut basis = DMatrix::zeros(d, n);
    let mut r = vec![0.0; n];
    let mut x = vec![0.0; n + m];
    for k in 0..d {
        for (i, v) in r.iter_mut().enumerate() {
            *v = (1.0 + 0.37 * ((k + 1) * (i + 3)) as f64).sin() * model.col_scale[i];
        }
        mass_times(model, &sys.data.frames, &r, &mut x[..n]);
        x[n..].fill(0.0);
        sys.aug.factor_solve(&mut x, Equilibration::New);
        for i in 0..n {
            basis[(k, i)] = x[i] / model.col_scale[i];
        }
    }
    basis.iter().all(|v| v.is_finite()).then_some(basis)
}

/// The event at a located crossing: the singular vectors of D = [Phi_q; B] by inverse
/// iteration on its LU, the left one's rows on Phi_q naming the dependent joints.
fn singular_event(model: &Model, d: &DMatrix<f64>, q: &[f64], t: f64, times: &[f64], pivot: f64) -> Event {
    let (n, m) = (model.n_coords, model.n_rows);
    let (lu, dt_lu) = (d.clone().lu(), d.transpose().lu());
    let mut u = nalgebra::DVector::from_element(n, 1.0);
    let mut v = nalgebra::DVector::from_element(n, 1.0);
    for _ in 0..3 {
        v = lu.solve(&u).unwrap_or_else(|| v.clone());
        v /= v.norm().max(f64::MIN_POSITIVE);
        u = dt_lu.solve(&v).unwrap_or_else(|| u.clone());
        u /= u.norm().max(f64::MIN_POSITIVE);
    }
    // the rows of Phi_q in the dependency, and sigma_min of Phi_q along them
    let mut w: Vec<f64> = u.as_slice()[..m].to_vec();
    let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
    w.iter_mut().for_each(|x| *x /= norm);
    let jt_w = d.view((0, 0), (m, n)).transpose() * nalgebra::DVector::from_column_slice(&w);
    let triple = SingularTriple { sigma: jt_w.norm(), v: v.as_slice().to_vec(), w };
    let kind = classify(model, &triple);
    let message = match kind {
        EventKind::Limit => format!(
            "a driver reaches a limit of motion at t = {t:.12}: Phi_q is singular with a driver row in the \
             dependency"
        ),
        _ => format!(
            "the motion passes a singular configuration at t = {t:.12}: the joints' rows become dependent \
             (assembly branches meet); the simulation goes on along the branch the motion follows"
        ),
    };
    Event {
        kind,
        step: times.partition_point(|&x| x < t),
        time: t,
        q: q.to_vec(),
        sigma_min: triple.sigma,
        constraints: constraint_shares(model, &triple.w, SHARE_FLOOR),
        coordinates: coordinate_shares(model, &triple.v, SHARE_FLOOR),
        output: None,
        drivers: driver_values(model, t),
        message,
        pivot_ratio: pivot,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The quintic Hermite interpolant of the events is exact on any quintic: q and qd at
    /// interior points of an interval not starting at 0, from the ends' q, qd and qdd.
    #[test]
    fn hermite_reproduces_a_quintic_and_its_rate() {
        let c = [0.7, -1.3, 2.1, 0.4, -0.9, 1.6];
        let f = |t: f64| c.iter().rev().fold(0.0, |a, &k| a * t + k);
        let df = |t: f64| (1..6).rev().fold(0.0, |a, k| a * t + k as f64 * c[k]);
        let d2f = |t: f64| (2..6).rev().fold(0.0, |a, k| a * t + (k * (k - 1)) as f64 * c[k]);
        let sample = |t: f64| Sample {
            t,
            q: vec![f(t)],
            qd: vec![df(t)],
            qdd: vec![d2f(t)],
            pivot: 1.0,
            sigma: 1.0,
            mid: 1.0,
            settled: false,
        };
        let (a, b) = (sample(0.3), sample(1.1));
        let (mut q, mut qd) = ([0.0], [0.0]);
        for k in 0..=8 {
            let t = 0.3 + 0.1 * k as f64;
            hermite(&a, &b, t, &mut q, &mut qd);
            assert!((q[0] - f(t)).abs() < 1e-13, "q at {t}: {} against {}", q[0], f(t));
            assert!((qd[0] - df(t)).abs() < 1e-12, "qd at {t}: {} against {}", qd[0], df(t));
        }
    }

    /// The watch's sigma_min (inverse iteration with the sparse augmented matrix) is the
    /// smallest singular value of Phi_q in the mass metric, sqrt of the least eigenvalue of
    /// Phi_q M^-1 Phi_q^T computed densely here, at a regular configuration of a
    /// parallelogram and next to its change point (bars 0.01 rad from aligned).
    /// A free parallelogram (crank 0.1, coupler and ground 0.3) drawn at crank angle 0.5.
    fn parallelogram() -> Model {
        use crate::{Description, Options};
        let json = r#"{"name": "parallelogram", "gravity": [0.0, -9.81],
            "bodies": [{"name": "crank", "x": 0.0, "y": 0.0, "theta": 0.5, "mass": 0.4, "inertia": 0.002},
                       {"name": "coupler", "x": 0.08775825618903728, "y": 0.04794255386042030, "theta": 0.0,
                        "mass": 1.1, "inertia": 0.01},
                       {"name": "rocker", "x": 0.3, "y": 0.0, "theta": 0.5, "mass": 0.7, "inertia": 0.003}],
            "joints": [{"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
                       {"type": "revolute", "name": "A", "body_a": "crank", "body_b": "coupler",
                        "at": [0.08775825618903728, 0.04794255386042030]},
                       {"type": "revolute", "name": "B", "body_a": "coupler", "body_b": "rocker",
                        "at": [0.38775825618903728, 0.04794255386042030]},
                       {"type": "revolute", "name": "O4", "body_a": "ground", "body_b": "rocker", "at": [0.3, 0.0]}]}"#;
        Model::with_options(
            Description::from_json(json).unwrap(),
            Options { free: true, ..Options::default() },
        )
        .unwrap()
    }

    #[test]
    fn sigma_here_is_the_least_singular_value_of_phi_q_in_the_mass_metric() {
        let (r2, r1) = (0.1, 0.3);
        let model = parallelogram();
        let (n, m) = (model.n_coords, model.n_rows);
        let mut sys = System::new(&model);
        let mut last = 0.0;
        for th in [0.5f64, 0.01] {
            let q = [0.0, 0.0, th, r2 * th.cos(), r2 * th.sin(), 0.0, r1, 0.0, th];
            let mut w = vec![1.0 / (m as f64).sqrt(); m];
            // each call three steps of inverse iteration from the last dependency
            let sigma = (0..6).map(|_| sigma_here(&model, &mut sys, &q, 0.0, &mut w)).last().unwrap();
            // the dense reference from the matrix sigma_here filled: Phi_q by columns, M
            let (mut jac, mut mass) = (DMatrix::zeros(m, n), DMatrix::zeros(n, n));
            let (mut e, mut col) = (vec![0.0; n], vec![0.0; n]);
            for j in 0..n {
                e.fill(0.0);
                e[j] = 1.0;
                sys.aug.jacobian_times(&e, &mut col[..m]);
                jac.column_mut(j).copy_from_slice(&col[..m]);
                mass_times(&model, &sys.data.frames, &e, &mut col);
                mass.column_mut(j).copy_from_slice(&col);
            }
            let schur = &jac * mass.try_inverse().unwrap() * jac.transpose();
            let want = schur.symmetric_eigenvalues().min().sqrt();
            assert!((sigma - want).abs() < 1e-10 * want, "theta {th}: sigma {sigma:e} against {want:e}");
            last = if th < 0.1 { want / last } else { want };
        }
        // next to the change point the mass-metric sigma_min falls with the angle
        assert!(last < 0.05, "sigma_min near the change point over the regular one: {last}");
    }

    /// `jacobian_at` leaves an event's configuration on the constraints where Gauss-Newton
    /// converges, and where its first step lands further off than the interpolated point
    /// (next to the change point, 5.8e-3 off: the step along the near-null direction
    /// overshoots, |phi| 1.09e-2 to 4.5e-2) it keeps that point and its distance. Found by
    /// random offsets of the parallelogram within 0.02 rad of its change point (3 in 20,000).
    #[test]
    fn an_events_configuration_is_projected_and_never_left_further_off_than_interpolated() {
        let model = parallelogram();
        let mut sys = System::new(&model);
        let still = |t: f64, q: &[f64]| Sample {
            t,
            q: q.to_vec(),
            qd: vec![0.0; 9],
            qdd: vec![0.0; 9],
            pivot: 1.0,
            sigma: 1.0,
            mid: 1.0,
            settled: false,
        };
        let th = 0.3f64;
        let near = [0.0, 0.0, th, 0.1 * th.cos() + 2e-4, 0.1 * th.sin(), 0.0, 0.3, 0.0, th + 1e-4];
        let overshooting = [
            0.0023675180196267524,
            0.00018490505924680567,
            -0.004441898225634992,
            0.09876548787027668,
            0.0038850798635967406,
            -0.004404838567532607,
            0.30302786309114343,
            0.0037148591978456774,
            -0.004372604720815481,
        ];
        for (start, converges) in [(near, true), (overshooting, false)] {
            let (a, c) = (still(0.0, &start), still(1.0, &start));
            let (mut interpolated, mut qd) = (vec![0.0; 9], vec![0.0; 9]);
            hermite(&a, &c, 0.5, &mut interpolated, &mut qd);
            let (_, before, _) = sys.project_positions(&model, &mut interpolated.clone(), 0.5, 1e-15);
            let mut q = vec![0.0; 9];
            let (_, residual) = jacobian_at(&model, &mut sys, &a, &c, 0.5, &mut q, &mut qd).unwrap();
            // |phi| where the configuration is left, computed afresh
            let phi = constraints_dense(&model, sys.frames(), &q, 0.5).0.amax();
            assert_eq!(phi, residual, "the stated distance is the configuration's");
            if converges {
                assert!(residual < 1e-14 && before > 1e-5, "{before:e} projected to {residual:e}");
            } else {
                assert!(before > 1e-2, "{before:e}");
                assert_eq!(residual, before);
                assert_eq!(q, interpolated, "the interpolated point kept");
            }
        }
    }
}
