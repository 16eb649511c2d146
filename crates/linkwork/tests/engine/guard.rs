//! The positions-only guard (`solve::closed_form::guard`): a sweep of positions only takes
//! each closed-form step the guard shows on its branches, without rates, and the careful
//! path where it cannot. Its positions are those of the sweep with rates (the careful
//! path's two-way check), its events the same; a step across a change point is never the
//! guard's.

use crate::common;
use common::*;
use linkwork::solve::closed_form::{self, guard::Travel};
use linkwork::stepping::singular::EventKind;
use linkwork::{sweep, Data, Model, Request, SolveError, SweepOutput};

fn run(model: &Model, times: &[f64], derivatives: u8) -> (SweepOutput, Result<(), SolveError>) {
    let mut data = Data::new(model);
    let request = Request { derivatives, ..Request::default() };
    let mut out = SweepOutput::with_request(model, times, request);
    let r = sweep(model, &mut data, times, &mut out, 0, &mut |_| true);
    out.truncate();
    (out, r)
}

fn grid(t0: f64, t1: f64, n: usize) -> Vec<f64> {
    (0..n).map(|k| t0 + (t1 - t0) * k as f64 / (n - 1) as f64).collect()
}

/// A parallelogram (ground = coupler, crank = rocker), crank at `th`: change points where
/// the crank lies along the ground.
fn parallelogram(r1: f64, r2: f64, th: f64) -> linkwork::Description {
    let a = [r2 * th.cos(), r2 * th.sin()];
    let mut d = four_bar(&FourBar { r1, r2, r3: r1, r4: r2 }, th, 1.0);
    d.bodies =
        vec![body("crank", 0.0, 0.0, th), body("coupler", a[0], a[1], 0.0), body("rocker", r1, 0.0, th)];
    d.joints = vec![
        pin("O2", "ground", "crank", [0.0, 0.0]),
        pin("A", "crank", "coupler", a),
        pin("B", "coupler", "rocker", [r1 + a[0], a[1]]),
        pin("O4", "ground", "rocker", [r1, 0.0]),
    ];
    d
}

/// The models of the comparison: crank-rockers, a double-crank, four-bars within 1e-4 and
/// 1e-7 of the Grashof limit (passing next to their change points), a parallelogram
/// through its change points, cranks that cannot turn (limits), slider-cranks (one
/// isosceles: a toggle on the way).
fn models() -> Vec<(String, Model)> {
    let mut out = Vec::new();
    let four_bars = [
        (0.38, 0.2, 0.35, 0.25),
        (0.45, 0.12, 0.4, 0.3),
        (0.1, 0.3, 0.35, 0.3),
        (0.38, 0.2, 0.35, 0.2301),
        (0.38, 0.2, 0.35, 0.2300001),
        (0.41, 0.26, 0.35, 0.25),
        (0.5, 0.18, 0.45, 0.35),
    ];
    for (r1, r2, r3, r4) in four_bars {
        let m = FourBar { r1, r2, r3, r4 };
        out.push((format!("four-bar {r1} {r2} {r3} {r4}"), Model::new(four_bar(&m, 0.0, 5.0)).unwrap()));
    }
    out.push(("parallelogram".into(), Model::new(parallelogram(0.3, 0.1, 0.5)).unwrap()));
    for (r2, r3, e) in [(0.1, 0.35, 0.02), (0.1, 0.1, 0.0)] {
        let m = SliderCrank { r2, r3, e };
        out.push((format!("slider-crank {r2} {r3} {e}"), Model::new(slider_crank(&m, 0.3, 5.0)).unwrap()));
    }
    out
}

/// Positions only (the guard) against positions with rates (the two-way check), on fine
/// and coarse grids over two turns: the same steps reached, the same events (kind, step,
/// time to 1e-9), and the positions bit for bit: a step the guard takes is the closed
/// forms' (the same arithmetic as the step the two-way check accepts), and where it
/// cannot show a step, the careful path takes it as it does with rates.
#[test]
fn positions_only_equal_the_careful_sweeps_positions_and_events() {
    for (name, model) in models() {
        for n in [2001, 361, 49, 13] {
            let span =
                if name == "parallelogram" { 4.0 * std::f64::consts::PI } else { 0.8 * std::f64::consts::PI };
            let times = grid(0.0, span, n);
            let (p, rp) = run(&model, &times, 0);
            let (c, rc) = run(&model, &times, 2);
            assert_eq!(rp.is_ok(), rc.is_ok(), "{name} {n}: {rp:?} vs {rc:?}");
            assert_eq!(p.n_done, c.n_done, "{name} {n}");
            let events = |o: &SweepOutput| o.events.iter().map(|e| (e.kind, e.step)).collect::<Vec<_>>();
            assert_eq!(events(&p), events(&c), "{name} {n}");
            for (a, b) in p.events.iter().zip(&c.events) {
                assert!((a.time - b.time).abs() < 1e-9, "{name} {n}: {} vs {}", a.time, b.time);
            }
            let first = p.q.iter().zip(&c.q).position(|(a, b)| a.to_bits() != b.to_bits());
            assert_eq!(first, None, "{name} {n}");
        }
    }
}

/// The hard cases with positions only: the parallelogram through its change points keeps
/// its branch and reports each change point, on a grid landing on one, on a coarse grid
/// over three turns, and the isosceles slider-crank through its toggle.
#[test]
fn positions_only_keep_the_branch_and_report_change_points() {
    let wrap = |a: f64| (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    let model = Model::new(parallelogram(0.3, 0.1, 0.5)).unwrap();
    let times = grid(0.0, 4.0 * std::f64::consts::PI, 501);
    let (out, r) = run(&model, &times, 0);
    r.unwrap();
    for (k, q) in out.q.chunks_exact(9).enumerate() {
        let th2 = 0.5 + times[k];
        assert!(wrap(q[5]).abs() < 1e-9 && wrap(q[8] - th2).abs() < 1e-9, "step {k}: {q:?}");
    }
    let bif: Vec<f64> =
        out.events.iter().filter(|e| e.kind == EventKind::Bifurcation).map(|e| e.time).collect();
    assert_eq!(bif.len(), 4, "{:?}", out.events);
    for (j, t) in bif.iter().enumerate() {
        assert!((t - ((j + 1) as f64 * std::f64::consts::PI - 0.5)).abs() < 1e-7, "{t}");
    }
    // a grid point on the change point, and a coarse grid over three turns
    let on = Model::new(parallelogram(1.0, 0.4, std::f64::consts::FRAC_PI_2)).unwrap();
    for n in [1001, 1000, 25, 7] {
        let (out, r) = run(&on, &grid(0.0, std::f64::consts::PI, n), 0);
        r.unwrap();
        assert!(out.q.chunks_exact(9).all(|q| wrap(q[8] - q[2]).abs() < 1e-10 && wrap(q[5]).abs() < 1e-10));
        assert_eq!(out.events.iter().filter(|e| e.kind == EventKind::Bifurcation).count(), 1, "n {n}");
    }
    let (out, r) = run(&on, &grid(0.0, 6.0 * std::f64::consts::PI, 25), 0);
    r.unwrap();
    assert!(out.q.chunks_exact(9).all(|q| wrap(q[8] - q[2]).abs() < 1e-10));
    assert_eq!(out.events.len(), 6, "a change point every half turn");
    let m = SliderCrank { r2: 0.1, r3: 0.1, e: 0.0 };
    let slider = Model::new(slider_crank(&m, 0.3, 1.0)).unwrap();
    let times: Vec<f64> = grid(0.0, std::f64::consts::PI, 201).iter().map(|t| t - 0.3).collect();
    let (out, r) = run(&slider, &times, 0);
    r.unwrap();
    for (k, q) in out.q.chunks_exact(9).enumerate() {
        assert!((q[6] - 0.2 * (0.3 + times[k]).cos()).abs() < 1e-11, "step {k}");
    }
    assert_eq!(out.events.iter().filter(|e| e.kind == EventKind::Bifurcation).count(), 1);
}

/// A step across a change point is never the guard's, whatever its size and however it
/// straddles the change point: the parallelogram's crank crossing the ground line, steps
/// from 1e-4 to 0.4 rad, 1 % to 99 % of the step before it. Steps of the same sizes a
/// radian past the change point (a margin of 0.036 against the crank pin's 0.1 h) are the
/// guard's: it refuses what it must, not everything.
#[test]
fn a_step_across_a_change_point_is_not_the_guards() {
    let model = Model::new(parallelogram(0.3, 0.1, 0.5)).unwrap();
    let plan = model.plan.as_ref().unwrap();
    assert!(closed_form::guarded(plan));
    // the state at t0 as a sweep of positions leaves it
    let state = |t0: f64| {
        let times = grid(0.0, t0, 400);
        let mut data = Data::new(&model);
        let mut out =
            SweepOutput::with_request(&model, &times, Request { derivatives: 0, ..Request::default() });
        sweep(&model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap();
        data
    };
    let step = |t0: f64, t1: f64| {
        let mut data = state(t0);
        let mut travel = vec![Travel::default(); model.n_bodies];
        let reads = closed_form::guard_reads(plan, model.n_bodies);
        closed_form::step_guarded(&model, plan, &mut data, t1, t1 - t0, &mut travel, &reads).is_ok()
    };
    // the crank along the ground at t = pi - 0.5
    let change = std::f64::consts::PI - 0.5;
    for h in [1e-4, 1e-3, 1e-2, 0.1, 0.4] {
        for before in [0.01, 0.3, 0.5, 0.7, 0.99] {
            let t0 = change - before * h;
            assert!(!step(t0, t0 + h), "h {h}, {before}: the guard took a step across the change point");
        }
        if h <= 0.1 {
            assert!(step(change + 1.0, change + 1.0 + h), "h {h}: a step far from the change point refused");
        }
    }
}

/// The bounds a guarded step forms are those a later group reads (`guard_reads`): on the
/// Stephenson six-bar the crank's (read by the first dyad) and the first dyad's (its
/// coupler carries the second dyad's pin C), not the last dyad's; and a step takes the
/// same verdict with only those formed as with every bound formed, from steps far inside
/// the guard to steps past it.
#[test]
fn a_guarded_step_forms_the_bounds_later_groups_read() {
    let model = Model::new(six_bar_stephenson(0.0, 5.0)).unwrap();
    let plan = model.plan.as_ref().unwrap();
    assert!(closed_form::guarded(plan));
    let reads = closed_form::guard_reads(plan, model.n_bodies);
    assert_eq!(reads, vec![true, true, false]);
    let fb = Model::new(four_bar(&FourBar { r1: 0.38, r2: 0.2, r3: 0.35, r4: 0.25 }, 0.0, 5.0)).unwrap();
    assert_eq!(closed_form::guard_reads(fb.plan.as_ref().unwrap(), fb.n_bodies), vec![true, false]);
    let state = |t0: f64| {
        let times = grid(0.0, t0, 200);
        let mut data = Data::new(&model);
        let mut out =
            SweepOutput::with_request(&model, &times, Request { derivatives: 0, ..Request::default() });
        sweep(&model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap();
        data
    };
    let every = vec![true; reads.len()];
    let (mut taken, mut refused) = (0, 0);
    for k in 1..40 {
        let t0 = 0.03 * k as f64;
        for h in [1e-3, 0.02, 0.1, 0.3, 0.8] {
            let verdict = |reads: &[bool]| {
                let mut data = state(t0);
                let mut travel = vec![Travel::default(); model.n_bodies];
                let ok =
                    closed_form::step_guarded(&model, plan, &mut data, t0 + h, h, &mut travel, reads).is_ok();
                (ok, data.q)
            };
            let (ok, q) = verdict(&reads);
            let (ok_all, q_all) = verdict(&every);
            assert_eq!(ok, ok_all, "t0 {t0}, h {h}");
            if ok {
                assert_eq!(q, q_all, "t0 {t0}, h {h}");
                taken += 1;
            } else {
                refused += 1;
            }
        }
    }
    // both verdicts met
    assert!(taken > 0 && refused > 0, "taken {taken}, refused {refused}");
}
