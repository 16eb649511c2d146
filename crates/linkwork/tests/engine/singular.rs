//! Singular configurations along sweeps: change points, limits of motion, locks, det
//! signs; the hard cases of the analysis issue, each checked against geometry.

use crate::common;
use common::*;
use linkwork::stepping::singular::EventKind;
use linkwork::stepping::tracking::OnSingular;
use linkwork::{sweep, Data, LinearKind, Model, Options, Request, SolveError, SweepOutput};

fn run(model: &Model, times: &[f64], request: Request) -> (SweepOutput, Result<(), SolveError>) {
    let mut data = Data::new(model);
    let mut out = SweepOutput::with_request(model, times, request);
    let r = sweep(model, &mut data, times, &mut out, 0, &mut |_| true);
    out.truncate();
    (out, r)
}

fn grid(t0: f64, t1: f64, n: usize) -> Vec<f64> {
    (0..n).map(|k| t0 + (t1 - t0) * k as f64 / (n - 1) as f64).collect()
}

fn wrap(a: f64) -> f64 {
    (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI
}

/// A parallelogram (ground = coupler, crank = rocker) drawn as one, crank at 0.5 rad.
fn parallelogram() -> linkwork::Description {
    let (r1, r2) = (0.30, 0.10);
    let th = 0.5f64;
    let a = [r2 * th.cos(), r2 * th.sin()];
    let b = [r1 + a[0], a[1]];
    let mut d = four_bar(&FourBar { r1, r2, r3: r1, r4: r2 }, th, 1.0);
    d.bodies =
        vec![body("crank", 0.0, 0.0, th), body("coupler", a[0], a[1], 0.0), body("rocker", r1, 0.0, th)];
    d.joints = vec![
        pin("O2", "ground", "crank", [0.0, 0.0]),
        pin("A", "crank", "coupler", a),
        pin("B", "coupler", "rocker", b),
        pin("O4", "ground", "rocker", [r1, 0.0]),
    ];
    d
}

#[test]
fn a_parallelogram_stays_a_parallelogram_through_its_change_points() {
    // two revolutions from 0.5 rad: change points at crank angles pi, 2 pi, 3 pi, 4 pi
    for linear in [LinearKind::Refactor, LinearKind::Small, LinearKind::Dense, LinearKind::Sparse] {
        let model = Model::with_options(parallelogram(), Options { linear, ..Options::default() }).unwrap();
        let times = grid(0.0, 4.0 * std::f64::consts::PI, 501);
        let (out, r) = run(&model, &times, Request::default());
        r.unwrap();
        assert_eq!(out.n_steps, times.len());
        for (k, q) in out.q.chunks_exact(9).enumerate() {
            let th2 = 0.5 + times[k];
            assert!(wrap(q[2] - th2).abs() < 1e-9, "{linear:?} step {k}: crank {} vs {th2}", q[2]);
            // the coupler translates (theta3 = 0) and the rocker follows the crank
            assert!(wrap(q[5]).abs() < 1e-9, "{linear:?} step {k}: coupler turned to {}", q[5]);
            assert!(wrap(q[8] - th2).abs() < 1e-9, "{linear:?} step {k}: rocker {}", q[8]);
        }
        let bif: Vec<f64> =
            out.events.iter().filter(|e| e.kind == EventKind::Bifurcation).map(|e| e.time).collect();
        let expected: Vec<f64> = (1..=4).map(|j| j as f64 * std::f64::consts::PI - 0.5).collect();
        assert_eq!(bif.len(), expected.len(), "{linear:?}: events {:?}", out.events);
        for (t, e) in bif.iter().zip(&expected) {
            // located by root-finding on sigma_min, which is linear in t there but known
            // only to about sqrt(eps) (see tracking::illinois)
            assert!((t - e).abs() < 1e-7, "{linear:?}: change point at {t}, expected {e}");
        }
        for e in &out.events {
            // every joint of the loop takes part in the dependency, the driver does not
            assert!(e.constraints.iter().all(|(n, _)| n != "crank_angle"), "{:?}", e.constraints);
            // sqrt(eps) in t is as close as a solved configuration gets (see
            // tracking::illinois); away from it sigma_min is about 0.1
            assert!(e.sigma_min < 1e-5, "sigma_min {} at the change point", e.sigma_min);
        }
    }
}

#[test]
fn stop_at_a_bifurcation_keeps_the_steps_before_it() {
    let model = Model::new(parallelogram()).unwrap();
    let times = grid(0.0, 4.0, 101);
    let req = Request { on_singular: OnSingular::Stop, ..Request::default() };
    let (out, r) = run(&model, &times, req);
    let err = r.unwrap_err();
    let t_star = std::f64::consts::PI - 0.5;
    assert!(matches!(err, SolveError::Event { .. }), "{err}");
    assert!(err.to_string().contains("branches meet"), "{err}");
    assert_eq!(out.n_steps, times.iter().filter(|&&t| t < t_star).count());
    assert_eq!(out.events.len(), 1);
    assert!((out.events[0].time - t_star).abs() < 1e-7);
}

/// A non-Grashof four-bar driven by its input at constant speed: the input can only rock,
/// so a sweep past the limit stops there with the limit located.
#[test]
fn a_crank_driven_past_its_limit_stops_there_with_the_limit_located() {
    let m = FourBar { r1: 0.40, r2: 0.30, r3: 0.25, r4: 0.20 };
    // the diagonal O4-A reaches r3 + r4 at cos th2 = (r1^2 + r2^2 - (r3 + r4)^2) / (2 r1 r2)
    let limit = ((m.r1 * m.r1 + m.r2 * m.r2 - (m.r3 + m.r4).powi(2)) / (2.0 * m.r1 * m.r2)).acos();
    for linear in [LinearKind::Refactor, LinearKind::Small, LinearKind::Sparse] {
        let model =
            Model::with_options(four_bar(&m, 0.0, 1.0), Options { linear, ..Options::default() }).unwrap();
        let times = grid(0.0, 2.0, 201);
        let (out, r) = run(&model, &times, Request::default());
        let err = r.unwrap_err();
        assert!(err.to_string().contains("limit of motion"), "{err}");
        let steps_before = times.iter().filter(|&&t| t < limit).count();
        assert_eq!(out.n_steps, steps_before, "{linear:?}: the good steps are kept");
        assert!(out.q.iter().all(|v| v.is_finite()));
        let ev = out.events.last().expect("a limit event");
        assert_eq!(ev.kind, EventKind::Limit);
        // t* is where Newton stops converging: within a few 1e-12 of the fold
        assert!((ev.time - limit).abs() < 1e-9, "{linear:?}: limit at {}, expected {limit}", ev.time);
        assert!((ev.drivers[0].1 - limit).abs() < 1e-9);
        assert!(ev.constraints.iter().any(|(n, _)| n == "crank_angle"), "{:?}", ev.constraints);
    }
}

/// Crank and coupler collinear is where the rocker of a crank-rocker stops and reverses.
#[test]
fn the_rocker_locks_where_crank_and_coupler_are_collinear() {
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let model = Model::new(four_bar(&m, 0.0, 5.0)).unwrap();
    let times = grid(0.0, 2.0 * std::f64::consts::PI / 5.0, 301);
    let (out, r) = run(&model, &times, Request { locks: true, ..Request::default() });
    r.unwrap();
    let locks: Vec<_> = out.events.iter().filter(|e| e.kind == EventKind::Lock).collect();
    assert_eq!(locks.len(), 2, "{:?}", out.events);
    for e in locks {
        assert_eq!(e.output.as_deref(), Some("rocker.theta"));
        let (th2, th3) = (e.q[2], e.q[5]);
        assert!(wrap(th3 - th2).sin().abs() < 1e-9, "crank {th2} and coupler {th3} not collinear");
    }
}

/// The slider of an in-line slider-crank stops at its dead centres, crank at 0 and pi.
#[test]
fn the_slider_locks_at_its_dead_centres() {
    let m = SliderCrank { r2: 0.1, r3: 0.3, e: 0.0 };
    let model = Model::new(slider_crank(&m, 0.3, 2.0)).unwrap();
    let times = grid(0.0, std::f64::consts::PI, 200);
    let (out, r) = run(&model, &times, Request { locks: true, derivatives: 0, ..Request::default() });
    r.unwrap();
    let t: Vec<f64> = out.events.iter().filter(|e| e.kind == EventKind::Lock).map(|e| e.time).collect();
    let expected = [(std::f64::consts::PI - 0.3) / 2.0, (2.0 * std::f64::consts::PI - 0.3) / 2.0];
    assert_eq!(t.len(), 2, "{:?}", out.events);
    for (a, b) in t.iter().zip(expected) {
        assert!((a - b).abs() < 1e-10, "dead centre at {a}, expected {b}");
    }
}

#[test]
fn det_sign_agrees_between_the_linear_solvers() {
    let desc = six_bar_stephenson(0.3, 2.0);
    let times = grid(0.0, 3.0, 120);
    let signs: Vec<Vec<f64>> = [LinearKind::Small, LinearKind::Dense, LinearKind::Sparse]
        .iter()
        .map(|&linear| {
            let model = Model::with_options(desc.clone(), Options { linear, ..Options::default() }).unwrap();
            let (out, r) = run(&model, &times, Request::default());
            r.unwrap();
            assert!(out.det_sign.iter().all(|s| s.abs() == 1.0));
            out.det_sign.to_vec()
        })
        .collect();
    assert_eq!(signs[0], signs[1]);
    assert_eq!(signs[0], signs[2]);
}

/// Metres and millimetres: same events at the same times.
#[test]
fn events_do_not_depend_on_units() {
    let scaled = |f: f64| {
        let mut d = parallelogram();
        for b in &mut d.bodies {
            b.x *= f;
            b.y *= f;
        }
        for j in &mut d.joints {
            if let linkwork::JointDesc::Revolute { at: Some(at), .. } = j {
                *at = [at[0] * f, at[1] * f];
            }
        }
        d
    };
    let times = grid(0.0, 4.0, 80);
    let ev = |f: f64| {
        let model = Model::new(scaled(f)).unwrap();
        let (out, r) = run(&model, &times, Request::default());
        r.unwrap();
        out.events.iter().map(|e| (e.kind, e.time)).collect::<Vec<_>>()
    };
    let (m, mm) = (ev(1.0), ev(1000.0));
    assert_eq!(m.len(), 1);
    assert_eq!(m.len(), mm.len());
    for (a, b) in m.iter().zip(&mm) {
        assert_eq!(a.0, b.0);
        assert!((a.1 - b.1).abs() < 1e-7);
    }
}

/// Numerical limits of motion against the triangle inequalities.
#[test]
fn motion_limits_of_four_bars_match_their_closed_forms() {
    use linkwork::analysis::limits::motion_limits;
    // non-Grashof: the input rocks between +-acos((r1^2 + r2^2 - (r3 + r4)^2) / (2 r1 r2))
    let m = FourBar { r1: 0.40, r2: 0.30, r3: 0.25, r4: 0.20 };
    let limit = ((m.r1 * m.r1 + m.r2 * m.r2 - (m.r3 + m.r4).powi(2)) / (2.0 * m.r1 * m.r2)).acos();
    let model = Model::new(four_bar(&m, 0.0, 1.0)).unwrap();
    let lim = motion_limits(&model, "crank_angle", 0.0, &model.q_start, None, None).unwrap();
    assert!(!lim.full_rotation);
    assert!((lim.upper.unwrap() - limit).abs() < 1e-9, "{lim:?}");
    assert!((lim.lower.unwrap() + limit).abs() < 1e-9, "{lim:?}");

    // Grashof crank-rocker: the crank turns fully
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let model = Model::new(four_bar(&m, 0.0, 1.0)).unwrap();
    let lim = motion_limits(&model, "crank_angle", 0.0, &model.q_start, None, None).unwrap();
    assert!(lim.full_rotation && lim.lower.is_none() && lim.upper.is_none(), "{lim:?}");

    // the same linkage driven by its rocker: it swings between the angles where crank
    // and coupler are collinear, |O2 B| = r3 + r2 or r3 - r2
    let mut desc = four_bar(&m, 0.0, 1.0);
    let th4 = desc.bodies[2].theta;
    desc.drivers = vec![linkwork::DriverDesc::Angle {
        name: "rocker_angle".into(),
        body: "rocker".into(),
        law: linkwork::MotionLaw::Constant { value: th4 },
    }];
    let model = Model::new(desc).unwrap();
    let lim = motion_limits(&model, "rocker_angle", 0.0, &model.q_start, None, None).unwrap();
    let swing = |d: f64| ((d * d - m.r1 * m.r1 - m.r4 * m.r4) / (2.0 * m.r1 * m.r4)).acos();
    let (a, b) = (swing(m.r3 + m.r2), swing(m.r3 - m.r2));
    let (lo, hi) = (lim.lower.unwrap(), lim.upper.unwrap());
    let sign = th4.signum();
    let (ea, eb) = if sign > 0.0 { (a, b) } else { (-b, -a) };
    assert!((lo - ea).abs() < 1e-9 && (hi - eb).abs() < 1e-9, "swing [{lo}, {hi}], expected [{ea}, {eb}]");
}

/// Regression: `motion_limits` evaluated the laws of the model's description as read,
/// before any preparation, so a spline law panicked (its second derivatives were never
/// computed) and an expression gave NaN. Every kind of law now gives its value at t.
#[test]
fn motion_limits_evaluate_laws_that_need_preparing() {
    use linkwork::analysis::limits::motion_limits;
    use linkwork::MotionLaw;
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let laws = [
        MotionLaw::from_json(r#"{"type": "spline", "times": [0, 1, 2], "values": [0.1, 0.4, 0.2]}"#),
        MotionLaw::from_json(r#"{"type": "expression", "text": "0.1 + 0.3*t"}"#),
        MotionLaw::from_json(
            r#"{"type": "cam", "start": 0.1,
                "segments": [{"type": "rise", "duration": 2, "lift": 0.6, "profile": "cycloidal"}]}"#,
        ),
    ];
    for law in laws {
        let mut desc = four_bar(&m, 0.1, 1.0);
        *desc.drivers[0].law_mut() = law.unwrap();
        let model = Model::new(desc).unwrap();
        let lim = motion_limits(&model, "crank_angle", 1.0, &model.q_start, None, None).unwrap();
        assert!(lim.full_rotation, "{lim:?}");
        assert!((lim.start - 0.4).abs() < 1e-12, "start {}", lim.start);
    }
}

/// The reported silent flip: a parallelogram whose grid (linspace(0, pi, 1001) from a
/// crank at pi/2) lands exactly on its change point at step 500. Every step stays on the
/// parallelogram, rates included, and the change point is reported once.
#[test]
fn a_grid_point_on_a_change_point_keeps_the_parallelogram() {
    let (r1, r2) = (1.0, 0.4);
    let th = std::f64::consts::FRAC_PI_2;
    let mut d = four_bar(&FourBar { r1, r2, r3: r1, r4: r2 }, th, 1.0);
    let a = [0.0, r2];
    d.bodies =
        vec![body("crank", 0.0, 0.0, th), body("coupler", a[0], a[1], 0.0), body("rocker", r1, 0.0, th)];
    d.joints = vec![
        pin("O2", "ground", "crank", [0.0, 0.0]),
        pin("A", "crank", "coupler", a),
        pin("B", "coupler", "rocker", [r1, r2]),
        pin("O4", "ground", "rocker", [r1, 0.0]),
    ];
    let model = Model::new(d).unwrap();
    for n in [1001, 1000, 25, 7] {
        let times = grid(0.0, std::f64::consts::PI, n);
        let (out, r) = run(&model, &times, Request::default());
        r.unwrap();
        assert_eq!(out.n_steps, n);
        for k in 0..n {
            let q = &out.q[9 * k..9 * k + 9];
            // positions to 1e-10 (measured below 1e-12); rates to 1e-8 (interpolated
            // between states where Phi_q is conditioned to 1e-2 next to the change point)
            assert!(wrap(q[8] - q[2]).abs() < 1e-10, "n {n} step {k}: rocker {} crank {}", q[8], q[2]);
            assert!(wrap(q[5]).abs() < 1e-10, "n {n} step {k}: coupler {}", q[5]);
            assert!(
                (out.qd[9 * k + 8] - 1.0).abs() < 1e-8,
                "n {n} step {k}: rocker rate {}",
                out.qd[9 * k + 8]
            );
        }
        let bif: Vec<_> = out.events.iter().filter(|e| e.kind == EventKind::Bifurcation).collect();
        assert_eq!(bif.len(), 1, "n {n}: {:?}", out.events.iter().map(|e| e.time).collect::<Vec<_>>());
        assert!((bif[0].time - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
    }
}

/// The reported hang: the same parallelogram drawn with the crank at (2.4e-17, 0.4),
/// swept over three turns in 24 steps. It returns (bounded work per step) on its branch.
#[test]
fn a_coarse_grid_over_change_points_returns_on_the_branch() {
    let (r1, r2, cx) = (1.0f64, 0.4f64, 2.4e-17f64);
    let th = r2.atan2(cx);
    let mut d = four_bar(&FourBar { r1, r2, r3: r1, r4: r2 }, th, 1.0);
    d.drivers = vec![crank_driver(std::f64::consts::FRAC_PI_2, 1.0)];
    d.bodies = vec![body("crank", 0.0, 0.0, th), body("coupler", cx, r2, 0.0), body("rocker", r1, 0.0, th)];
    d.joints = vec![
        pin("O2", "ground", "crank", [0.0, 0.0]),
        pin("A", "crank", "coupler", [cx, r2]),
        pin("B", "coupler", "rocker", [r1, r2]),
        pin("O4", "ground", "rocker", [r1, 0.0]),
    ];
    let model = Model::new(d).unwrap();
    let times = grid(0.0, 6.0 * std::f64::consts::PI, 25);
    let start = std::time::Instant::now();
    let (out, r) = run(&model, &times, Request::default());
    // a hang would never return; the sweep takes milliseconds
    assert!(start.elapsed().as_secs_f64() < 20.0);
    r.unwrap();
    for q in out.q.chunks_exact(9) {
        assert!(wrap(q[8] - q[2]).abs() < 1e-10);
    }
    assert_eq!(out.events.len(), 6, "a change point every half turn");
}

/// Crank = rod: the grid of the report (linspace(0, pi, 201) from 0) lands on the toggle
/// at step 100; "continue" goes on along x = 2 r cos(theta) and reports the toggle.
#[test]
fn an_isosceles_slider_crank_goes_on_through_a_toggle_on_the_grid() {
    let m = SliderCrank { r2: 0.1, r3: 0.1, e: 0.0 };
    let model = Model::new(slider_crank(&m, 0.3, 1.0)).unwrap();
    let times: Vec<f64> = grid(0.0, std::f64::consts::PI, 201).iter().map(|t| t - 0.3).collect();
    let (out, r) = run(&model, &times, Request::default());
    r.unwrap();
    for (k, q) in out.q.chunks_exact(9).enumerate() {
        let th2 = 0.3 + times[k];
        assert!((q[6] - 0.2 * th2.cos()).abs() < 1e-11, "step {k}: x {} vs {}", q[6], 0.2 * th2.cos());
    }
    let bif: Vec<f64> =
        out.events.iter().filter(|e| e.kind == EventKind::Bifurcation).map(|e| e.time + 0.3).collect();
    assert_eq!(bif.len(), 1);
    assert!((bif[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
}

/// A solve far from the drawing follows the drawing's branch there (the four-bar after
/// 100 s of crank motion equals the sweep's last step) and reports crossings met.
#[test]
fn solve_along_continues_the_drawing_far_away() {
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let model = Model::new(four_bar(&m, 0.0, 5.0)).unwrap();
    let mut data = Data::new(&model);
    let (_, events) = linkwork::solve_along(&model, &mut data, 100.0, &mut || true).unwrap();
    assert!(events.is_empty());
    let times = grid(0.0, 100.0, 200_001);
    let (out, r) = run(&model, &times, Request::default());
    r.unwrap();
    let last = &out.q[9 * (times.len() - 1)..];
    assert!(rel_err(&data.q, last) < 1e-12, "{:?} vs {:?}", data.q, last);
    // the parallelogram crosses a change point every half turn of its crank
    let model = Model::new(parallelogram()).unwrap();
    let mut data = Data::new(&model);
    let (_, events) = linkwork::solve_along(&model, &mut data, 10.0, &mut || true).unwrap();
    assert_eq!(events.len(), 3, "crank from 0.5 to 10.5 rad crosses pi, 2 pi, 3 pi");
    assert!(wrap(data.q[8] - 10.5).abs() < 1e-10);
}

/// Switch: at each change point the parallelogram takes the other branch (the
/// antiparallelogram, where O4 A stays parallel to O2 B), then back.
#[test]
fn on_singular_switch_takes_the_other_branch() {
    let model = Model::new(parallelogram()).unwrap();
    let times = grid(0.0, 2.0 * std::f64::consts::PI, 301);
    let (out, r) = run(&model, &times, Request { on_singular: OnSingular::Switch, ..Request::default() });
    r.unwrap();
    let (r1, r2) = (0.30, 0.10);
    for (k, q) in out.q.chunks_exact(9).enumerate() {
        let th2 = 0.5 + times[k];
        let (th4, pi) = (q[8], std::f64::consts::PI);
        if th2 < pi - 1e-9 {
            assert!(wrap(th4 - th2).abs() < 1e-10, "step {k}: parallelogram");
        } else if th2 > pi + 1e-9 && th2 < 2.0 * pi - 1e-9 {
            let a = [r2 * th2.cos() - r1, r2 * th2.sin()];
            let b = [r1 + r2 * th4.cos(), r2 * th4.sin()];
            assert!((a[0] * b[1] - a[1] * b[0]).abs() < 1e-10, "step {k}: antiparallelogram");
        }
    }
    assert_eq!(out.events.len(), 2);
    assert!(out.events.iter().all(|e| e.message.contains("takes the other branch")));
}

/// The sparse mobility of large models agrees with the dense SVD where both run: a
/// regular four-bar, a six-bar, a chain, and a parallelogram at its change point (one
/// dependency of its joint rows).
#[test]
fn sparse_mobility_agrees_with_the_dense_svd() {
    use linkwork::analysis::mobility::{mobility, sparse_mobility};
    let cases = vec![
        four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.3, 5.0),
        six_bar_stephenson(0.2, 1.0),
        chain(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 20, 0.3, 1.0, 0.0, 1.0),
    ];
    for d in cases {
        let model = Model::new(d).unwrap();
        let mut data = Data::new(&model);
        linkwork::solve(&model, &mut data, 0.0).unwrap();
        let (dense, sparse) =
            (mobility(&model, &data.q, 0.0).unwrap(), sparse_mobility(&model, &data.q, 0.0));
        assert_eq!(
            (dense.rank, dense.rank_joints, dense.dof, dense.dof_driven),
            (sparse.rank, sparse.rank_joints, sparse.dof, sparse.dof_driven)
        );
        assert!(sparse.redundancies.is_empty() && dense.redundancies.is_empty());
    }
    // the parallelogram at its change point (crank along the ground): joint rows dependent
    let model = Model::new(parallelogram()).unwrap();
    let mut data = Data::new(&model);
    let (_, _) = linkwork::solve_along(&model, &mut data, std::f64::consts::PI - 0.5, &mut || true).unwrap();
    let (dense, sparse) = (
        mobility(&model, &data.q, std::f64::consts::PI - 0.5).unwrap(),
        sparse_mobility(&model, &data.q, std::f64::consts::PI - 0.5),
    );
    assert_eq!(dense.redundancies.len(), 1, "{dense:?}");
    assert_eq!((dense.rank, dense.rank_joints, dense.dof), (sparse.rank, sparse.rank_joints, sparse.dof));
    let names = |d: &linkwork::analysis::mobility::Dependency| {
        let mut v: Vec<String> = d.constraints.iter().map(|(n, _)| n.clone()).collect();
        v.sort();
        v
    };
    assert_eq!(names(&dense.redundancies[0]), names(&sparse.redundancies[0]));
}

/// Switch on a sweep run backwards (times decreasing): at each change point met, the
/// crank at 2 pi and then at pi, the parallelogram takes the antiparallelogram and then
/// the parallelogram again, as the forward sweep does. The span of the careful step over
/// a crossing runs backwards here: times past the crossing are those below it.
#[test]
fn a_backward_sweep_switches_branches_at_each_change_point() {
    let model = Model::new(parallelogram()).unwrap();
    let pi = std::f64::consts::PI;
    let times = grid(2.0 * pi, 0.0, 301);
    let (out, r) = run(&model, &times, Request { on_singular: OnSingular::Switch, ..Request::default() });
    r.unwrap();
    assert_eq!(out.n_steps, times.len());
    let (r1, r2) = (0.30, 0.10);
    for (k, q) in out.q.chunks_exact(9).enumerate() {
        let th2 = 0.5 + times[k];
        let th4 = q[8];
        assert!(wrap(q[2] - th2).abs() < 1e-10, "step {k}: crank {} vs {th2}", q[2]);
        // the antiparallelogram: O4 A parallel to O2 B
        let a = [r2 * th2.cos() - r1, r2 * th2.sin()];
        let b = [r1 + r2 * th4.cos(), r2 * th4.sin()];
        if th2 > 2.0 * pi + 1e-9 || th2 < pi - 1e-9 {
            assert!(wrap(th4 - th2).abs() < 1e-10, "step {k} (crank {th2}): not the parallelogram");
        } else if th2 > pi + 1e-9 && th2 < 2.0 * pi - 1e-9 {
            assert!(
                (a[0] * b[1] - a[1] * b[0]).abs() < 1e-10,
                "step {k} (crank {th2}): not the antiparallelogram"
            );
        }
    }
    let found: Vec<f64> = out.events.iter().map(|e| e.time).collect();
    assert_eq!(found.len(), 2, "events at {found:?}");
    for (t, e) in found.iter().zip([2.0 * pi - 0.5, pi - 0.5]) {
        assert!((t - e).abs() < 1e-7, "change point at {t}, expected {e}");
    }
    assert!(out.events.iter().all(|e| e.message.contains("takes the other branch")));
}

/// A sweep run backwards with a grid time 1e-9 rad short of the change point at crank
/// angle pi: Phi_q is singular to round-off there, so the careful path steps over it to
/// the next grid time and fills this one from its interpolant. Every step stays on the
/// parallelogram and the change point is reported once, as on the forward sweep.
#[test]
fn a_backward_sweep_fills_a_grid_time_next_to_a_change_point_from_the_span() {
    let model = Model::new(parallelogram()).unwrap();
    let t_star = std::f64::consts::PI - 0.5;
    let h = 0.02;
    let times: Vec<f64> = (0..61).map(|j| t_star + 1e-9 + (30 - j) as f64 * h).collect();
    let (out, r) = run(&model, &times, Request::default());
    r.unwrap();
    assert_eq!(out.n_steps, times.len());
    for (k, q) in out.q.chunks_exact(9).enumerate() {
        let th2 = 0.5 + times[k];
        assert!(wrap(q[2] - th2).abs() < 1e-10, "step {k}: crank {} vs {th2}", q[2]);
        assert!(wrap(q[5]).abs() < 1e-10, "step {k}: coupler turned to {}", q[5]);
        assert!(wrap(q[8] - th2).abs() < 1e-10, "step {k}: rocker {} vs {th2}", q[8]);
    }
    let found: Vec<f64> = out.events.iter().map(|e| e.time).collect();
    assert_eq!(found.len(), 1, "events at {found:?}");
    assert!((found[0] - t_star).abs() < 1e-7, "change point at {}", found[0]);
}

/// Ctrl-C while the careful path searches one step: the non-Grashof crank of
/// `a_crank_driven_past_its_limit_stops_there_with_the_limit_located` driven past its
/// limit, whose last step takes more than the 16 sub-steps between two of the careful
/// path's polls before the limit is located. A cancellation requested there (the step's
/// progress was asked once already; a second call for the same step comes from inside the
/// careful path) ends the sweep at that step as cancelled, not with the limit found after
/// it.
#[test]
fn a_cancellation_asked_inside_a_careful_step_is_honoured() {
    let m = FourBar { r1: 0.40, r2: 0.30, r3: 0.25, r4: 0.20 };
    let limit = ((m.r1 * m.r1 + m.r2 * m.r2 - (m.r3 + m.r4).powi(2)) / (2.0 * m.r1 * m.r2)).acos();
    let model = Model::new(four_bar(&m, 0.0, 1.0)).unwrap();
    let times = grid(0.0, 2.0, 201);
    let step_past = times.iter().filter(|&&t| t < limit).count();
    let mut data = Data::new(&model);
    let mut out = SweepOutput::with_request(&model, &times, Request::default());
    let mut asked: Vec<usize> = Vec::new();
    let r = sweep(&model, &mut data, &times, &mut out, 1, &mut |k| {
        let again = asked.contains(&k);
        asked.push(k);
        !again
    });
    assert_eq!(r.unwrap_err(), SolveError::Cancelled { step: step_past });
    // asked once for each step before it, then from inside the careful path
    assert!(asked.iter().filter(|&&k| k == step_past).count() >= 2, "{asked:?}");
}

/// Switch at the toggles of an isosceles slider-crank (crank = rod = r), in metres
/// (r = 0.1) and in millimetres (r = 100): the slider's two branches through a toggle
/// are x = 2 r cos(theta) and x = 0 (the rod folded back onto the crank, the slider at
/// the crank's pivot), and the sweep takes the other one at each of the four toggles
/// (theta = pi/2, 3 pi/2, ...) whatever the unit: the other branch is searched for in
/// coordinates scaled by the model's length, so the unit must not change what it finds.
#[test]
fn switching_branches_at_a_toggle_does_not_depend_on_units() {
    let pi = std::f64::consts::PI;
    let th0 = 0.3;
    let times = grid(0.0, 4.0 * pi, 301);
    for r in [0.1, 100.0] {
        let model = Model::new(slider_crank(&SliderCrank { r2: r, r3: r, e: 0.0 }, th0, 1.0)).unwrap();
        let (out, res) =
            run(&model, &times, Request { on_singular: OnSingular::Switch, ..Request::default() });
        res.unwrap();
        assert_eq!(out.n_steps, times.len());
        let toggles: Vec<f64> = (0..4).map(|j| (j as f64 + 0.5) * pi - th0).collect();
        let mut worst = 0.0f64;
        for (k, q) in out.q.chunks_exact(9).enumerate() {
            let th2 = th0 + times[k];
            // the branch: the drawn one before the first toggle, then alternately
            let crossed = toggles.iter().filter(|&&t| times[k] > t).count();
            let x = if crossed % 2 == 0 { 2.0 * r * th2.cos() } else { 0.0 };
            worst = worst.max((q[6] - x).abs() / r);
        }
        // measured 1.1e-14 (metres) and 5.8e-15 (millimetres)
        assert!(worst < 1e-10, "r {r}: slider off its branch by {worst:e} r");
        let found: Vec<f64> = out.events.iter().map(|e| e.time).collect();
        assert_eq!(found.len(), 4, "r {r}: events at {found:?}");
        for (t, e) in found.iter().zip(&toggles) {
            assert!((t - e).abs() < 1e-7, "r {r}: toggle at {t}, expected {e}");
        }
        for e in &out.events {
            assert!(e.message.contains("takes the other branch"), "r {r}: {}", e.message);
        }
    }
}
