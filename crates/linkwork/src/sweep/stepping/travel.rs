//! The ends of the travels a sweep's sliders are given (`travel = [min, max]` on a
//! prismatic joint: its slide from the start), watched step by step. Between two solved
//! steps each slide is followed on the positions solved again at the times searched
//! (Newton from a cubic guess between the steps, apart from the sweep's own data): where
//! its rate changes sign, the turn is found first, and on each monotone piece a crossing
//! of min or max is located by the root of the slide minus the end (Illinois), so to the
//! solve's tolerance over the slide's rate. Each crossing, out of the travel and back in,
//! and a start outside it, is an "end_of_travel" event naming the joint; the sweep goes on
//! through it (kinematics models no stop). A slide a translation driver sets is watched as
//! well: its law is what moves it past the end. Only a model with a travel pays for it.

use crate::constraints::kinds::ConstraintKind;
use crate::math::roots::illinois;
use crate::model::data::Data;
use crate::model::slider::{sliders, Slider};
use crate::model::Model;
use crate::solve::events::{driver_values, Event, EventKind};
use crate::solve::position::solve_position;
use crate::solve::velocity::solve_velocity;

/// A solved step: its time, positions and rates.
#[derive(Debug, Clone)]
struct Mark {
    t: f64,
    q: Vec<f64>,
    qd: Vec<f64>,
}

/// The sliders given a travel, and what watching them keeps.
pub struct Travels {
    sliders: Vec<Slider>,
    /// positions and rates solved at the times searched (the sweep's data untouched)
    scratch: Data,
    prev: Option<Mark>,
    now: Mark,
}

impl Travels {
    /// None where no prismatic joint of the model is given a travel.
    pub fn new(model: &Model) -> Option<Travels> {
        let given = |c: &ConstraintKind| matches!(c, ConstraintKind::Prismatic(p) if p.travel.is_some());
        if !model.constraints.iter().any(|c| given(&c.kind)) {
            return None;
        }
        let sliders: Vec<Slider> = sliders(model).into_iter().filter(|s| s.travel.is_some()).collect();
        let mut scratch = Data::new(model);
        scratch.with_velocity = true;
        let n = model.n_coords;
        Some(Travels {
            sliders,
            scratch,
            prev: None,
            now: Mark { t: 0.0, q: vec![0.0; n], qd: vec![0.0; n] },
        })
    }

    /// After step `step` at t (data.q solved; data.qd too where `rates`): the crossings
    /// since the previous step (or a start outside a travel) added to `events`.
    pub fn after_step(
        &mut self,
        model: &Model,
        data: &Data,
        t: f64,
        step: usize,
        rates: bool,
        events: &mut Vec<Event>,
    ) {
        let Travels { sliders, scratch, prev, now } = self;
        now.t = t;
        now.q.copy_from_slice(&data.q);
        if rates {
            now.qd.copy_from_slice(&data.qd);
        } else {
            scratch.q.copy_from_slice(&data.q);
            if solve_position(model, scratch, t, step, false).is_ok()
                && solve_velocity(model, scratch, t, step).is_ok()
            {
                now.qd.copy_from_slice(&scratch.qd);
            } else if let Some(a) = prev.as_ref() {
                // (no rates there: the chord's, for the cubic guess and the turn test)
                let h = t - a.t;
                now.qd.iter_mut().zip(&now.q).zip(&a.q).for_each(|((v, x), y)| *v = (x - y) / h);
            }
        }
        match prev.as_ref() {
            None => {
                for s in sliders.iter() {
                    start_outside(model, s, now, step, events);
                }
            }
            Some(a) => {
                for s in sliders.iter() {
                    crossings(model, s, scratch, a, now, step, events);
                }
            }
        }
        match prev {
            Some(a) => std::mem::swap(a, now),
            None => *prev = Some(now.clone()),
        }
    }
}

/// Beyond which end of its travel the slide x lies: (+1, max) or (-1, min); None inside.
fn beyond(s: &Slider, x: f64) -> Option<(f64, f64)> {
    let [lo, hi] = s.travel?;
    if x > hi {
        Some((1.0, hi))
    } else if x < lo {
        Some((-1.0, lo))
    } else {
        None
    }
}

fn end_name(side: f64) -> &'static str {
    if side > 0.0 {
        "max"
    } else {
        "min"
    }
}

fn start_outside(model: &Model, s: &Slider, at: &Mark, step: usize, events: &mut Vec<Event>) {
    let (x, _) = s.slide(&at.q, &at.qd);
    let Some((side, bound)) = beyond(s, x) else { return };
    let message = format!(
        "slider '{}' starts outside its travel at t = {:.12} (slide {x:.9e}, beyond its {}, {bound}){}: \
         the sweep goes on (kinematics models no stop)",
        s.name,
        at.t,
        end_name(side),
        driven(model, s)
    );
    events.push(event(model, s, at.t, &at.q, step, message, f64::NAN));
}

/// The crossings of slider s's travel ends between the steps a and b.
fn crossings(
    model: &Model,
    s: &Slider,
    scratch: &mut Data,
    a: &Mark,
    b: &Mark,
    step: usize,
    events: &mut Vec<Event>,
) {
    let ((xa, va), (xb, vb)) = (s.slide(&a.q, &a.qd), s.slide(&b.q, &b.qd));
    let Some([lo, hi]) = s.travel else { return };
    // the slide's turn inside the step, where its rate changes sign: the pieces either
    // side of it are monotone, each crossing an end at most once
    // (on the stack: a step allocates only where it finds a crossing)
    let mut pieces = [(a.t, xa), (b.t, xb), (b.t, xb)];
    let mut n = 2;
    // at the steps themselves, their own solutions: a step whose rates could not be
    // solved (the chord's there) still bounds the searches either side of it
    let mark = |t: f64| [a, b].into_iter().find(|m| m.t == t).map(|m| s.slide(&m.q, &m.qd));
    if va * vb < 0.0 {
        let rate = |t: f64, scratch: &mut Data| match mark(t) {
            Some((_, v)) => Some(v),
            None => solve_at(model, scratch, a, b, t, step).then(|| s.slide(&scratch.q, &scratch.qd).1),
        };
        if let Some(tm) = illinois(a.t, b.t, |t| rate(t, scratch)) {
            if solve_at(model, scratch, a, b, tm, step) {
                pieces[1] = (tm, s.slide(&scratch.q, &scratch.qd).0);
                n = 3;
            }
        }
    }
    for w in pieces[..n].windows(2) {
        let ((t0, x0), (t1, x1)) = (w[0], w[1]);
        for (bound, side) in [(lo, -1.0), (hi, 1.0)] {
            // beyond the end: side (x - bound) > 0
            let (out0, out1) = (side * (x0 - bound) > 0.0, side * (x1 - bound) > 0.0);
            if out0 == out1 {
                continue;
            }
            let past = |t: f64, scratch: &mut Data| match mark(t) {
                Some((x, _)) => Some(side * (x - bound)),
                None => solve_at(model, scratch, a, b, t, step)
                    .then(|| side * (s.slide(&scratch.q, &scratch.qd).0 - bound)),
            };
            let Some(t) = illinois(t0, t1, |t| past(t, scratch)) else { continue };
            if !solve_at(model, scratch, a, b, t, step) {
                continue;
            }
            let what = end_name(side);
            let message = if out1 {
                format!(
                    "slider '{}' reaches the end of its travel at t = {t:.12} (its {what}, {bound}){}: the \
                     sweep goes on through it (kinematics models no stop)",
                    s.name,
                    driven(model, s)
                )
            } else {
                format!(
                    "slider '{}' comes back inside its travel at t = {t:.12} (its {what}, {bound})",
                    s.name
                )
            };
            let ratio = scratch.pivots.ratio;
            events.push(event(model, s, t, &scratch.q, step, message, ratio));
        }
    }
}

/// Positions and rates at t in `scratch`, by Newton from the cubic through the steps a
/// and b (their positions and rates); false if it does not converge.
fn solve_at(model: &Model, scratch: &mut Data, a: &Mark, b: &Mark, t: f64, step: usize) -> bool {
    let h = b.t - a.t;
    let s = (t - a.t) / h;
    let (s2, s3) = (s * s, s * s * s);
    let (h00, h10, h01, h11) = (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, 3.0 * s2 - 2.0 * s3, s3 - s2);
    for i in 0..scratch.q.len() {
        scratch.q[i] = h00 * a.q[i] + h10 * h * a.qd[i] + h01 * b.q[i] + h11 * h * b.qd[i];
    }
    solve_position(model, scratch, t, step, false).is_ok() && solve_velocity(model, scratch, t, step).is_ok()
}

/// ", its translation driver 'd' moving it" where a driver sets the slide.
fn driven(model: &Model, s: &Slider) -> String {
    s.driver(model).map_or(String::new(), |d| format!(", moved there by its translation driver '{d}'"))
}

fn event(
    model: &Model,
    s: &Slider,
    t: f64,
    q: &[f64],
    step: usize,
    message: String,
    pivot_ratio: f64,
) -> Event {
    Event {
        kind: EventKind::EndOfTravel,
        step,
        time: t,
        q: q.to_vec(),
        sigma_min: f64::NAN,
        constraints: vec![(s.name.clone(), 1.0)],
        coordinates: Vec::new(),
        output: Some(s.name.clone()),
        drivers: driver_values(model, t),
        message,
        pivot_ratio,
    }
}
