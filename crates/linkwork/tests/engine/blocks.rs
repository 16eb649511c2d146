//! The structure-aware path against the general one: every shipped example and random
//! four-bars and slider-cranks swept both ways must agree in positions, velocities,
//! accelerations, reactions, det signs and events; the closed-form groups against the
//! textbook closed forms.

use crate::common;

use common::*;
use linkwork::blocks::Block;
use linkwork::files::read_path;
use linkwork::{sweep, Data, Description, Model, Options, Request, SolverKind, SweepOutput};

fn examples_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn compile(desc: &Description, solver: SolverKind) -> Model {
    Model::with_options(desc.clone(), Options { solver, ..Options::default() }).unwrap()
}

fn run(model: &Model, times: &[f64], req: Request) -> (SweepOutput, Result<(), linkwork::SolveError>) {
    let mut data = Data::new(model);
    let mut out = SweepOutput::with_request(model, times, req);
    let r = sweep(model, &mut data, times, &mut out, 0, &mut |_| true);
    (out, r)
}

/// Largest difference over the largest magnitude of the general path's values.
fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

/// Sweeps both ways and compares; returns how many steps the groups solved (closed form:
/// 0 Newton iterations).
fn both_ways(name: &str, desc: &Description, times: &[f64], req: Request) -> usize {
    let auto = compile(desc, SolverKind::Auto);
    let general = compile(desc, SolverKind::General);
    assert!(general.plan.is_err());
    let (a, ra) = run(&auto, times, req);
    let (g, rg) = run(&general, times, req);
    assert_eq!(ra.is_ok(), rg.is_ok(), "{name}: {ra:?} vs {rg:?}");
    if let (Err(ea), Err(eg)) = (&ra, &rg) {
        assert_eq!(std::mem::discriminant(ea), std::mem::discriminant(eg), "{name}: {ea} vs {eg}");
    }
    assert_eq!(a.n_done, g.n_done, "{name}");
    let n = a.n_done * auto.n_coords;
    // both converge to the Newton tolerance (1e-12 scaled) or closer: their difference is
    // round-off over the conditioning of the step
    let tol = [1e-12, 1e-11, 1e-10];
    for (what, (x, y), tol) in
        [("q", (&a.q, &g.q), tol[0]), ("qd", (&a.qd, &g.qd), tol[1]), ("qdd", (&a.qdd, &g.qdd), tol[2])]
    {
        if !x.is_empty() {
            let e = rel(&x[..n], &y[..n]);
            assert!(e <= tol, "{name}: {what} differs by {e:e} (relative)");
        }
    }
    if req.forces {
        let nl = a.n_done * auto.n_rows;
        let e = rel(&a.lambda[..nl], &g.lambda[..nl]);
        assert!(e <= 1e-9, "{name}: lambda differs by {e:e}");
    }
    assert_eq!(&a.det_sign[..a.n_done], &g.det_sign[..g.n_done], "{name}: det signs");
    assert_eq!(a.events.len(), g.events.len(), "{name}: events {:?} vs {:?}", a.events, g.events);
    for (x, y) in a.events.iter().zip(&g.events) {
        assert_eq!(x.kind, y.kind, "{name}");
        assert!((x.time - y.time).abs() <= 1e-9, "{name}: event at {} vs {}", x.time, y.time);
    }
    if let Ok(plan) = &auto.plan {
        assert!(plan.blocks.iter().all(|b| !b.method().is_empty()));
    }
    a.iterations[..a.n_done].iter().filter(|&&i| i == 0).count()
}

#[test]
fn every_example_agrees_on_both_paths() {
    let mut structured = 0;
    for entry in std::fs::read_dir(examples_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        let desc = read_path(&path).unwrap().description;
        let model = compile(&desc, SolverKind::Auto);
        let (lo, hi) = model.time_domain;
        let t0 = 0.0f64.max(lo);
        let t1 = (t0 + 2.0).min(hi);
        let times: Vec<f64> = (0..=800).map(|k| t0 + (t1 - t0) * k as f64 / 800.0).collect();
        let forces = model.inertias.iter().any(|i| i.mass > 0.0);
        let req = Request { forces, ..Request::default() };
        let closed = both_ways(&name, &desc, &times, req);
        // positions only: the structured steps' jump check on the dyads' middle pins
        both_ways(&name, &desc, &times, Request { derivatives: 0, ..Request::default() });
        if model.plan.is_ok() {
            structured += 1;
        }
        eprintln!(
            "{name}: plan {:?}, {closed} of 801 steps closed form",
            model.plan.as_ref().map(|p| p.blocks.len())
        );
    }
    assert!(structured >= 8, "only {structured} examples have a plan");
}

#[test]
fn random_four_bars_and_slider_cranks_agree_on_both_paths() {
    let mut rng = Rng(0x5eed_b10c);
    let times = grid(0.0, 2.0 * std::f64::consts::PI / 3.0, 400);
    for case in 0..40 {
        // Grashof crank-rockers: the crank the shortest, s + l < p + q
        let desc = if case % 2 == 0 {
            let m = loop {
                let r2 = 0.1 + 0.05 * (rng.next() + 1.0);
                let (r1, r3, r4) = (0.4 + 0.1 * rng.next(), 0.4 + 0.1 * rng.next(), 0.35 + 0.1 * rng.next());
                let l = r1.max(r3).max(r4);
                // Grashof with the crank shortest: s + l < p + q, with a margin
                if r2 + l < r1 + r3 + r4 - l - 0.02 {
                    break FourBar { r1, r2, r3, r4 };
                }
            };
            four_bar(&m, 0.3 + rng.next(), 3.0)
        } else {
            let m = SliderCrank {
                r2: 0.1 + 0.05 * (rng.next() + 1.0),
                r3: 0.4 + 0.1 * rng.next(),
                e: 0.05 * rng.next(),
            };
            slider_crank(&m, rng.next(), 3.0)
        };
        let closed = both_ways(&format!("case {case}"), &desc, &times, Request::default());
        assert_eq!(closed, times.len() - 1, "case {case}: every step after the start by the closed forms");
        let positions = Request { derivatives: 0, ..Request::default() };
        let closed = both_ways(&format!("case {case}, positions"), &desc, &times, positions);
        assert_eq!(closed, times.len() - 1, "case {case}: positions only, by the closed forms too");
    }
}

#[test]
fn the_closed_forms_meet_the_textbook_ones() {
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let model = compile(&four_bar(&m, 0.0, 5.0), SolverKind::Auto);
    let plan = model.plan.as_ref().unwrap();
    assert!(matches!(plan.blocks[..], [Block::Crank(_), Block::Rrr(_)]));
    let times = grid(0.0, 2.0 * std::f64::consts::PI / 5.0, 2000);
    let (out, r) = run(&model, &times, Request::default());
    r.unwrap();
    let (mut e_q, mut e_w, mut e_a) = (0.0f64, 0.0f64, 0.0f64);
    for (k, &t) in times.iter().enumerate() {
        let ([th3, th4], [w3, w4], [a3, a4]) = four_bar_closed(&m, 5.0 * t, 5.0, 0.0);
        let row = 9 * k;
        e_q = e_q.max(wrap(out.q[row + 5] - th3).abs()).max(wrap(out.q[row + 8] - th4).abs());
        e_w = e_w.max((out.qd[row + 5] - w3).abs()).max((out.qd[row + 8] - w4).abs());
        e_a = e_a.max((out.qdd[row + 5] - a3).abs()).max((out.qdd[row + 8] - a4).abs());
    }
    // the bar: 1e-12 rad, 1e-11 rad/s, 1e-10 rad/s^2 (alpha peaks near 112 here)
    assert!(e_q <= 1e-12 && e_w <= 1e-11 && e_a <= 1e-10, "{e_q:e} {e_w:e} {e_a:e}");

    let s = SliderCrank { r2: 0.1, r3: 0.35, e: 0.02 };
    let model = compile(&slider_crank(&s, 0.0, 5.0), SolverKind::Auto);
    assert!(matches!(model.plan.as_ref().unwrap().blocks[..], [Block::Crank(_), Block::Rrp(_)]));
    let (out, r) = run(&model, &times, Request::default());
    r.unwrap();
    let (mut e_x, mut e_v, mut e_acc) = (0.0f64, 0.0f64, 0.0f64);
    for (k, &t) in times.iter().enumerate() {
        let ([_, x], [_, v], [_, a]) = slider_crank_closed(&s, 5.0 * t, 5.0, 0.0);
        let row = 9 * k;
        e_x = e_x.max((out.q[row + 6] - x).abs());
        e_v = e_v.max((out.qd[row + 6] - v).abs());
        e_acc = e_acc.max((out.qdd[row + 6] - a).abs());
    }
    assert!(e_x <= 1e-14 && e_v <= 1e-13 && e_acc <= 1e-11, "{e_x:e} {e_v:e} {e_acc:e}");
}

fn wrap(a: f64) -> f64 {
    let tau = 2.0 * std::f64::consts::PI;
    a - tau * (a / tau).round()
}

/// n times from t0 to t1.
fn grid(t0: f64, t1: f64, n: usize) -> Vec<f64> {
    (0..n).map(|k| t0 + (t1 - t0) * k as f64 / (n - 1) as f64).collect()
}
