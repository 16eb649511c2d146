//! A sweep reports where a slider crosses an end of the travel its prismatic joint is
//! given: an offset slider-crank against its closed form x(theta) = r cos(theta) +
//! sqrt(l^2 - (r sin(theta) - e)^2), on every path a sweep takes (the plan's closed forms
//! with rates, positions only under the guard, the general Newton), in a batch, and a
//! slide a translation driver moves past its stops.
use crate::common;

use common::{slider_crank, SliderCrank};
use linkwork::motion::{ExpressionLaw, MotionLaw};
use linkwork::stepping::singular::{Event, EventKind};
use linkwork::{
    sweep_batch, Data, Description, DriverDesc, JointDesc, Model, Options, Request, SolverKind, SweepOutput,
};

const SC: SliderCrank = SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 };
const TH0: f64 = 1.5;
const OMEGA: f64 = 5.0;

/// The slider's x at crank angle theta (closed form).
fn x_of(theta: f64) -> f64 {
    SC.r2 * theta.cos() + (SC.r3.powi(2) - (SC.r2 * theta.sin() - SC.e).powi(2)).sqrt()
}

/// The slide from the start at time t.
fn slide(t: f64) -> f64 {
    x_of(TH0 + OMEGA * t) - x_of(TH0)
}

/// The stroke's ends as slides from the start: (min, max), at theta = pi + asin(e / (l - r))
/// and asin(e / (l + r)).
fn stroke() -> (f64, f64) {
    let x_min = ((SC.r3 - SC.r2).powi(2) - SC.e.powi(2)).sqrt();
    let x_max = ((SC.r3 + SC.r2).powi(2) - SC.e.powi(2)).sqrt();
    (x_min - x_of(TH0), x_max - x_of(TH0))
}

/// Every time in [t0, t1] where the closed-form slide crosses `bound`: sign changes on a
/// fine grid (well below the stroke's period), each bisected to round-off.
fn closed_crossings(bound: f64, t0: f64, t1: f64) -> Vec<f64> {
    crossings_of(slide, bound, t0, t1)
}

/// `closed_crossings` of another slide(t).
fn crossings_of(slide: impl Fn(f64) -> f64, bound: f64, t0: f64, t1: f64) -> Vec<f64> {
    let n = 20_000;
    let f = |t: f64| slide(t) - bound;
    let mut out = Vec::new();
    for i in 0..n {
        let (mut a, mut b) =
            (t0 + (t1 - t0) * i as f64 / n as f64, t0 + (t1 - t0) * (i + 1) as f64 / n as f64);
        if (f(a) > 0.0) == (f(b) > 0.0) {
            continue;
        }
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if (f(m) > 0.0) == (f(a) > 0.0) {
                a = m;
            } else {
                b = m;
            }
        }
        out.push(0.5 * (a + b));
    }
    out
}

fn crank_with_travel(travel: [f64; 2]) -> Description {
    let mut desc = slider_crank(&SC, TH0, OMEGA);
    for j in &mut desc.joints {
        if let JointDesc::Prismatic { travel: t, .. } = j {
            *t = Some(travel);
        }
    }
    desc
}

fn swept(desc: &Description, solver: SolverKind, req: Request, times: &[f64]) -> SweepOutput {
    let model = Model::with_options(desc.clone(), Options { solver, ..Options::default() }).unwrap();
    let mut data = Data::new(&model);
    let mut out = SweepOutput::with_request(&model, times, req);
    linkwork::sweep(&model, &mut data, times, &mut out, 0, &mut |_| true).unwrap();
    assert_eq!(out.n_done, times.len().div_ceil(req.every));
    out
}

fn travel_ends(out: &SweepOutput) -> Vec<&Event> {
    out.events.iter().filter(|e| e.kind == EventKind::EndOfTravel).collect()
}

/// Three turns of the crank on a grid of 150 steps (each 7.2 degrees).
fn three_turns() -> Vec<f64> {
    let t1 = 3.0 * std::f64::consts::TAU / OMEGA;
    (0..=150).map(|k| t1 * k as f64 / 150.0).collect()
}

/// The paths a sweep of the slider-crank takes: the plan's closed forms with rates,
/// positions only (the guard), and the general Newton with and without rates.
fn paths() -> Vec<(SolverKind, Request)> {
    let positions = Request { derivatives: 0, ..Request::default() };
    vec![
        (SolverKind::Auto, Request::default()),
        (SolverKind::Auto, positions),
        (SolverKind::General, Request::default()),
        (SolverKind::General, positions),
        (SolverKind::Auto, Request { every: 7, ..Request::default() }),
    ]
}

/// A travel 5 mm inside the stroke at both ends: out and back in at each end on every
/// turn (12 events over three turns), at the closed form's times to 1e-9 s [the slide is
/// solved to Newton's tolerance (~1e-13 m) and moves at >= 0.1 m/s there], in time order,
/// each between its step's neighbours, naming the joint, the end and its time; every path
/// gives the same times to 1e-11 s.
#[test]
fn a_travel_inside_the_stroke_is_crossed_at_both_ends_every_turn() {
    let (lo, hi) = stroke();
    let travel = [lo + 0.005, hi - 0.005];
    let desc = crank_with_travel(travel);
    let times = three_turns();
    let t1 = *times.last().unwrap();
    let mut expected: Vec<(f64, &str, bool)> = Vec::new();
    for (bound, end) in [(travel[0], "min"), (travel[1], "max")] {
        for t in closed_crossings(bound, 0.0, t1) {
            // leaving the travel where the slide moves away from its inside
            let outward = if end == "max" { slide(t + 1e-6) > bound } else { slide(t + 1e-6) < bound };
            expected.push((t, end, outward));
        }
    }
    expected.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(expected.len(), 12, "the closed form crosses each end twice a turn");
    let mut first: Option<Vec<f64>> = None;
    for (solver, req) in paths() {
        let out = swept(&desc, solver, req, &times);
        let ends = travel_ends(&out);
        let brief: Vec<(f64, &str)> = out.events.iter().map(|e| (e.time, e.message.as_str())).collect();
        assert_eq!(ends.len(), expected.len(), "{solver:?} {req:?}: {brief:#?} {expected:?}");
        for (e, (t, end, outward)) in ends.iter().zip(&expected) {
            assert!((e.time - t).abs() < 1e-9, "{solver:?} {req:?}: {} against {t}", e.time);
            assert_eq!(e.output.as_deref(), Some("S"));
            assert!(
                e.message.contains("slider 'S'") && e.message.contains(&format!("its {end}")),
                "{}",
                e.message
            );
            assert!(e.message.contains(&format!("t = {:.12}", e.time)), "{}", e.message);
            if *outward {
                assert!(e.message.contains("reaches the end of its travel") && e.message.contains("goes on"));
            } else {
                assert!(e.message.contains("comes back inside its travel"), "{}", e.message);
            }
            assert!(times[e.step - 1] < e.time && e.time <= times[e.step], "step {} at {}", e.step, e.time);
            // the configuration there: the slider at the end
            let x_slider = e.q[6];
            let bound = if *end == "max" { travel[1] } else { travel[0] };
            assert!((x_slider - x_of(TH0) - bound).abs() < 1e-12, "{x_slider}");
        }
        let now: Vec<f64> = ends.iter().map(|e| e.time).collect();
        match &first {
            None => first = Some(now),
            Some(f) => {
                for (a, b) in f.iter().zip(&now) {
                    assert!((a - b).abs() < 1e-11, "{solver:?} {req:?}: {a} vs {b}");
                }
            }
        }
        // the sweep goes on through the stops: its rows are those of a sweep without a travel
        let free = swept(&slider_crank(&SC, TH0, OMEGA), solver, req, &times);
        assert_eq!(out.q, free.q, "{solver:?} {req:?}");
        assert!(travel_ends(&free).is_empty());
    }
}

/// A travel that covers the stroke (by 1 mm at each end): no event on any path; a travel
/// whose max lies 1e-7 m inside the stroke's: the slide just passes it around each outer
/// dead centre, inside one step of the grid, out and back in on every turn, at the closed
/// form's times to 1e-9 s [the slide moves at ~8e-4 m/s there].
#[test]
fn a_travel_that_covers_the_stroke_reports_none_and_one_that_clips_it_each_turn() {
    let (lo, hi) = stroke();
    let times = three_turns();
    for (solver, req) in paths() {
        let out = swept(&crank_with_travel([lo - 1e-3, hi + 1e-3]), solver, req, &times);
        assert!(travel_ends(&out).is_empty(), "{solver:?} {req:?}: {:#?}", out.events);
    }
    let bound = hi - 1e-7;
    let expected = closed_crossings(bound, 0.0, *times.last().unwrap());
    assert_eq!(expected.len(), 6);
    // each pair inside one step: only the turn of the slide inside the step finds it
    for pair in expected.chunks(2) {
        assert_eq!(times.partition_point(|&t| t < pair[0]), times.partition_point(|&t| t < pair[1]));
    }
    for (solver, req) in paths() {
        let out = swept(&crank_with_travel([lo - 1e-3, bound]), solver, req, &times);
        let ends = travel_ends(&out);
        assert_eq!(ends.len(), 6, "{solver:?} {req:?}: {:#?}", out.events);
        for (e, t) in ends.iter().zip(&expected) {
            assert!((e.time - t).abs() < 1e-9, "{solver:?} {req:?}: {} against {t}", e.time);
            assert!(e.message.contains("its max"));
        }
    }
}

/// A batch's sweeps report them too (the travel of each model its own).
#[test]
fn a_batch_reports_each_models_travel_ends() {
    let (lo, hi) = stroke();
    let times = three_turns();
    let narrow = Model::new(crank_with_travel([lo + 0.005, hi - 0.005])).unwrap();
    let wide = Model::new(crank_with_travel([lo - 1e-3, hi + 1e-3])).unwrap();
    let items = sweep_batch(&[&narrow, &wide, &narrow], &times, Request::default(), 2, &mut |_| true);
    let single =
        swept(&crank_with_travel([lo + 0.005, hi - 0.005]), SolverKind::Auto, Request::default(), &times);
    let counts: Vec<usize> = items.iter().map(|(out, _)| travel_ends(out).len()).collect();
    assert_eq!(counts, [12, 0, 12]);
    for (a, b) in travel_ends(&items[0].0).iter().zip(travel_ends(&single)) {
        assert_eq!(a.time, b.time);
    }
}

/// A slider driven along x at 0.4 m/s on a travel [-0.1, 0.5]: its law moves it past the
/// max at t = 1.25 exactly (to 1e-12 s), the event naming its driver; back and forth as
/// x = 0.6 sin(t) it leaves and re-enters at asin(5/6), pi - asin(5/6), and passes the min
/// at pi + asin(1/6); a start outside the travel, below its min or beyond its max, is an
/// event at the first time.
#[test]
fn a_driven_slide_beyond_its_travel_is_reported() {
    const LINEAR: &str = r#"{"type": "linear", "value": 0.0, "rate": 0.4}"#;
    // the slide along x set by the translation driver "push" (its law as JSON)
    let driven = |law: &str, [lo, hi]: [f64; 2]| {
        let json = format!(
            r#"{{"name": "driven slider",
                "bodies": [{{"name": "slider", "x": 0.0, "y": 0.0}}],
                "joints": [{{"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "slider",
                             "at": [0.0, 0.0], "axis": [1.0, 0.0], "travel": [{lo}, {hi}]}}],
                "drivers": [{{"type": "translation", "name": "push", "joint": "guide", "law": {law}}}]}}"#
        );
        Description::from_json(&json).unwrap()
    };
    let times: Vec<f64> = (0..=40).map(|k| 0.05 * k as f64).collect();
    let desc = driven(LINEAR, [-0.1, 0.5]);
    for solver in [SolverKind::Auto, SolverKind::General] {
        for req in [Request::default(), Request { derivatives: 0, ..Request::default() }] {
            let out = swept(&desc, solver, req, &times);
            let ends = travel_ends(&out);
            assert_eq!(ends.len(), 1, "{:#?}", out.events);
            assert!((ends[0].time - 1.25).abs() < 1e-12, "{}", ends[0].time);
            assert!(
                ends[0].message.contains("its max") && ends[0].message.contains("translation driver 'push'")
            );
        }
    }
    let times: Vec<f64> = (0..=200).map(|k| 0.025 * k as f64).collect();
    let out = swept(
        &driven(r#"{"type": "harmonic", "mean": 0.0, "amplitude": 0.6, "omega": 1.0}"#, [-0.1, 0.5]),
        SolverKind::Auto,
        Request::default(),
        &times,
    );
    let got: Vec<f64> = travel_ends(&out).iter().map(|e| e.time).collect();
    let pi = std::f64::consts::PI;
    let a = (5.0f64 / 6.0).asin();
    let want = [a, pi - a, pi + (1.0f64 / 6.0).asin()];
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 1e-10, "{g} against {w}");
    }
    let out = swept(&driven(LINEAR, [0.1, 0.5]), SolverKind::Auto, Request::default(), &times[..10]);
    let ends = travel_ends(&out);
    assert_eq!(ends.len(), 1);
    assert!(
        ends[0].time == 0.0
            && ends[0].message.contains("starts outside its travel")
            && ends[0].message.contains("its min")
    );
    // and beyond the other end: the start is reported at its max
    let out = swept(&driven(LINEAR, [-0.5, -0.1]), SolverKind::Auto, Request::default(), &times[..10]);
    let ends = travel_ends(&out);
    assert_eq!(ends.len(), 1, "{:#?}", out.events);
    assert!(
        ends[0].time == 0.0
            && ends[0].message.contains("starts outside its travel")
            && ends[0].message.contains("its max")
    );
}

/// The travel is closed: a slide exactly at an end is inside it. A slider driven at
/// -0.5 m/s from an end of [-0.25, 0] (the steps 0.25 s apart, binary fractions, so that
/// the slide equals each end exactly at a step): no event at the start, at the max; it
/// reaches the min exactly at t = 0.5 and is beyond it after: one event, there. Started at
/// the min of [0, 0.25] and driven at +0.5 m/s: the same at the max.
#[test]
fn a_slide_exactly_at_an_end_of_its_travel_is_inside_and_leaves_it_once() {
    let driven = |rate: f64, [lo, hi]: [f64; 2]| {
        let json = format!(
            r#"{{"name": "driven slider",
                "bodies": [{{"name": "slider", "x": 0.0, "y": 0.0}}],
                "joints": [{{"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "slider",
                             "at": [0.0, 0.0], "axis": [1.0, 0.0], "travel": [{lo}, {hi}]}}],
                "drivers": [{{"type": "translation", "name": "push", "joint": "guide",
                              "law": {{"type": "linear", "value": 0.0, "rate": {rate}}}}}]}}"#
        );
        Description::from_json(&json).unwrap()
    };
    let times: Vec<f64> = (0..=8).map(|k| 0.25 * k as f64).collect();
    for (rate, travel, end) in [(-0.5, [-0.25, 0.0], "min"), (0.5, [0.0, 0.25], "max")] {
        let desc = driven(rate, travel);
        for solver in [SolverKind::Auto, SolverKind::General] {
            for req in [Request::default(), Request { derivatives: 0, ..Request::default() }] {
                let out = swept(&desc, solver, req, &times);
                let ends = travel_ends(&out);
                assert_eq!(ends.len(), 1, "{rate} {solver:?} {req:?}: {:#?}", out.events);
                let e = ends[0];
                assert_eq!(e.time, 0.5, "{}", e.message);
                assert!(e.message.contains("reaches the end of its travel") && e.message.contains(end));
                assert_eq!(e.q[0], travel[if end == "max" { 1 } else { 0 }], "{:?}", e.q);
            }
        }
    }
}

/// The clipped stroke of the test above, wherever the outer dead centre falls inside its
/// step: the grid moved by 0.1 to 0.9 of a step, so that the slide turns in the step's
/// first or second half (its rate larger at the step's start or at its end). Each time,
/// the crossings are the closed form's, to 1e-9 s, on every path.
#[test]
fn a_clipped_stroke_is_found_wherever_the_turn_falls_in_its_step() {
    let (lo, hi) = stroke();
    let bound = hi - 1e-7;
    let desc = crank_with_travel([lo - 1e-3, bound]);
    let t1 = 3.0 * std::f64::consts::TAU / OMEGA;
    for shift in [0.1, 0.3, 0.5, 0.7, 0.9] {
        let times: Vec<f64> = (0..=150).map(|k| t1 * (k as f64 + shift) / 150.0).collect();
        let expected = closed_crossings(bound, times[0], *times.last().unwrap());
        assert_eq!(expected.len(), 6, "{shift}");
        for (solver, req) in paths() {
            let out = swept(&desc, solver, req, &times);
            let ends = travel_ends(&out);
            assert_eq!(ends.len(), expected.len(), "{shift} {solver:?} {req:?}: {:#?}", out.events);
            for (e, t) in ends.iter().zip(&expected) {
                assert!((e.time - t).abs() < 1e-9, "{shift} {solver:?} {req:?}: {} against {t}", e.time);
            }
        }
    }
}

/// A step whose rates cannot be solved still bounds the searches either side of it. The
/// crank's law theta = theta0 + omega t + c (sqrt|t - tb| - sqrt(tb)), c = 1e-4 rad s^-1/2,
/// has no finite rate at the step tb (a cusp: the general path solves the positions
/// there, the rates not; the plan's closed forms refuse the law). tb is the step just
/// after an outer dead centre that falls 0.3 of a step after its start, so that the slide
/// at tb is below the one a step before: the chord between them is the turn test's rate
/// at tb, and the two crossings of the clipped stroke's max inside that step are found
/// only by the turn. All six crossings, at the closed form's times under that law to
/// 1e-9 s, positions only on the general path.
#[test]
fn a_step_without_rates_bounds_the_crossings_either_side_of_it() {
    const C: f64 = 1e-4;
    let (lo, hi) = stroke();
    let bound = hi - 1e-7;
    let t1 = 3.0 * std::f64::consts::TAU / OMEGA;
    let h = t1 / 150.0;
    // the first outer dead centre (crank at asin(e / (l + r)) + 2 pi) without the cusp,
    // at 0.3 of its step
    let dead = ((SC.e / (SC.r3 + SC.r2)).asin() + std::f64::consts::TAU - TH0) / OMEGA;
    let shift = (dead / h - 0.3).rem_euclid(1.0);
    let times: Vec<f64> = (0..=150).map(|k| (k as f64 + shift) * h).collect();
    let kb = times.partition_point(|&t| t < dead);
    let tb = times[kb];
    let theta = |t: f64| TH0 + OMEGA * t + C * ((t - tb).abs().sqrt() - tb.sqrt());
    let slide_c = |t: f64| x_of(theta(t)) - x_of(TH0);
    let expected = crossings_of(slide_c, bound, times[0], *times.last().unwrap());
    assert_eq!(expected.len(), 6);
    // the first pair inside the step before tb, the slide at tb below the one before it
    assert!(times[kb - 1] < expected[0] && expected[1] < tb, "{expected:?} {tb}");
    assert!(slide_c(tb) < slide_c(times[kb - 1]));
    let mut desc = crank_with_travel([lo - 1e-3, bound]);
    let text = format!("{TH0:?} + {OMEGA:?}*t + {C:?}*(sqrt(abs(t - {tb:?})) - sqrt({tb:?}))");
    desc.drivers = vec![DriverDesc::Angle {
        name: "crank_angle".into(),
        body: "crank".into(),
        law: MotionLaw::Expression(ExpressionLaw::new(&text).unwrap()),
    }];
    let out = swept(&desc, SolverKind::General, Request { derivatives: 0, ..Request::default() }, &times);
    let ends = travel_ends(&out);
    let got: Vec<f64> = ends.iter().map(|e| e.time).collect();
    assert_eq!(got.len(), expected.len(), "{got:?} against {expected:?}");
    for (g, t) in got.iter().zip(&expected) {
        assert!((g - t).abs() < 1e-9, "{g} against {t}");
    }
}
