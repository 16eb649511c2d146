//! Forward dynamics in the engine: a damped spring-mass on a slide against its exact
//! solution (both methods, with the energy balance and the work of the damper), and the
//! named errors of a massless free coordinate and of a run out of steps.

use linkwork::dynamics::{simulate, Method, SimOptions, SimOutput};
use linkwork::SolveError;

use crate::oscillator_model::{exact, oscillator, oscillator_on_travel, C, MASS};

/// x(t) of the damped oscillator released at rest 0.3.
fn released(t: f64) -> f64 {
    exact(t, C, 0.3, 0.0)
}

#[test]
fn a_damped_oscillator_follows_its_exact_motion_and_balances_its_energy() {
    let model = oscillator(MASS, C);
    let times: Vec<f64> = (0..=100).map(|k| 0.05 * k as f64).collect();
    // (method, rtol, bound on x): DOP853 measured 2.8e-10; generalized-alpha (second
    // order, numerically damped at rho_inf = 0.9) 2.4e-5
    for (method, rtol, bound) in [(Method::Rk8, 1e-10, 1e-9), (Method::GenAlpha, 1e-8, 1e-4)] {
        let opts = SimOptions { method, rtol, atol: rtol, ..SimOptions::default() };
        let mut out = SimOutput::new(&model, &times);
        simulate(&model, &times, None, None, &opts, &mut out, &mut |_| true).unwrap();
        assert_eq!(out.n_done, times.len());
        let err =
            times.iter().enumerate().map(|(k, &t)| (out.q[3 * k] - released(t)).abs()).fold(0.0, f64::max);
        assert!(err < bound, "{method:?}: x error {err:.3e}");
        // the slide holds: y and theta stay 0
        assert!(out.q.chunks(3).all(|q| q[1].abs() < 1e-12 && q[2].abs() < 1e-12));
        // energy: T + V - W constant, the damper's work negative and most of the start's
        let e0 = out.kinetic[0] + out.potential[0];
        let last = times.len() - 1;
        for k in 0..=last {
            let balance = out.kinetic[k] + out.potential[k] - out.work[k] - e0;
            assert!(balance.abs() < 100.0 * bound * e0, "{method:?} step {k}: balance {balance:.3e}");
        }
        assert!(out.work[last] < -0.5 * e0, "{method:?}: damper's work {}", out.work[last]);
        // the slide's reaction carries the weight: its normal force is m g
        let lambda = out.lambda[model.n_rows * last..model.n_rows * (last + 1)].to_vec();
        assert!(lambda.iter().any(|l| (l.abs() - 2.0 * 9.81).abs() < 1e-6), "{lambda:?}");
    }
}

#[test]
fn a_free_coordinate_without_mass_is_named() {
    let model = oscillator(0.0, C);
    let mut out = SimOutput::new(&model, &[0.0, 1.0]);
    let e = simulate(&model, &[0.0, 1.0], None, None, &SimOptions::default(), &mut out, &mut |_| true)
        .unwrap_err();
    assert!(matches!(&e, SolveError::Massless { body, .. } if body == "block"), "{e}");
}

#[test]
fn a_run_out_of_steps_keeps_the_rows_done() {
    let model = oscillator(MASS, C);
    let times: Vec<f64> = (0..=100).map(|k| 0.05 * k as f64).collect();
    let opts = SimOptions { max_steps: 30, rtol: 1e-10, atol: 1e-10, ..SimOptions::default() };
    let mut out = SimOutput::new(&model, &times);
    let e = simulate(&model, &times, None, None, &opts, &mut out, &mut |_| true).unwrap_err();
    assert!(matches!(e, SolveError::Step { .. }), "{e}");
    assert!(out.n_done > 1 && out.n_done < times.len());
    for (k, &t) in times.iter().enumerate().take(out.n_done) {
        assert!((out.q[3 * k] - released(t)).abs() < 1e-8);
    }
    // cancelled from the progress poll: a named error too
    let mut out = SimOutput::new(&model, &times);
    let e =
        simulate(&model, &times, None, None, &SimOptions::default(), &mut out, &mut |_| false).unwrap_err();
    assert_eq!(e, SolveError::Cancelled { step: 1 });
}

#[test]
fn rows_solved_later_match_the_rows_solved_in_the_run() {
    // accelerations: false leaves qdd, lambda, the reactions and the pivot ratios
    // unallocated; solve_rows fills them from the same stored states, to the bit
    let model = oscillator(MASS, C);
    let times: Vec<f64> = (0..=40).map(|k| 0.05 * k as f64).collect();
    let run = |accelerations: bool| {
        let opts = SimOptions { rtol: 1e-8, atol: 1e-8, accelerations, ..SimOptions::default() };
        let mut out = SimOutput::new(&model, &times);
        simulate(&model, &times, None, None, &opts, &mut out, &mut |_| true).unwrap();
        out
    };
    let (eager, mut lazy) = (run(true), run(false));
    assert!(lazy.qdd.is_empty() && lazy.lambda.is_empty() && lazy.reactions.is_empty());
    assert!(lazy.pivot_ratio.is_empty());
    assert_eq!(eager.pivot_ratio.len(), times.len());
    assert_eq!(eager.q, lazy.q);
    linkwork::dynamics::record::solve_rows(&model, &mut lazy).unwrap();
    assert_eq!(eager.qdd, lazy.qdd);
    assert_eq!(eager.lambda, lazy.lambda);
    assert_eq!(eager.reactions, lazy.reactions);
    assert_eq!(eager.pivot_ratio, lazy.pivot_ratio);
}

/// A run stopped where a slider reaches an end of its travel still reports the work it
/// did: the oscillator's slide given the travel [-0.5, 0.1] from its start (x = 0.3), the
/// block reaches x = -0.2 on its first swing and the run stops there (the default). Each
/// step tried evaluated the accelerations at DOP853's 11 stages after the first and at
/// its end: at least 12 evaluations a step.
#[test]
fn a_run_stopped_at_the_end_of_a_travel_counts_its_evaluations() {
    let model = oscillator_on_travel(MASS, C, Some([-0.5, 0.1]));
    let times: Vec<f64> = (0..=100).map(|k| 0.05 * k as f64).collect();
    let opts = SimOptions { method: Method::Rk8, rtol: 1e-10, atol: 1e-10, ..SimOptions::default() };
    let mut out = SimOutput::new(&model, &times);
    simulate(&model, &times, None, None, &opts, &mut out, &mut |_| true).unwrap();
    // the rows kept are those up to x = -0.2 on the exact motion (bisected on its first
    // swing, which ends near half a period, 0.63 s)
    let (mut lo, mut hi) = (0.0, 0.6);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if released(mid) > -0.2 {
            lo = mid
        } else {
            hi = mid
        }
    }
    assert_eq!(out.n_done, times.iter().filter(|&&t| t <= lo).count());
    assert!(out.events.iter().any(|e| e.message.contains("end of its travel")), "{:?}", out.events);
    assert!(out.n_steps > 0);
    assert!(
        out.n_evaluations >= 12 * out.n_steps,
        "{} evaluations in {} steps",
        out.n_evaluations,
        out.n_steps
    );
}
