//! Static equilibrium, stability and modes against closed forms: a bar pinned to the
//! ground, held by a torsion spring under gravity, rests where
//! k (theta - theta0) = -m g l cos(theta) (the root of a monotone function, found here by
//! bisection to the last bit), and swings about it at omega^2 = (k - m g l sin theta) / I_O.
//! The bar's frame origin is its centre of mass, away from the pin: the solve works on
//! three coordinates and two pin rows, so the constraint forces' curvature matters.
//! Upright without a spring it is unstable; under a constant torque with no spring and
//! no gravity it has no rest at all.

use linkwork::description::Description;
use linkwork::dynamics::equilibrium::{equilibrium, EqOptions};
use linkwork::dynamics::modes::{modes, stability};
use linkwork::{Model, Options};

const G: f64 = 9.81;
const M: f64 = 1.7;
const L: f64 = 0.6;
const JC: f64 = 0.04;

fn pendulum(gravity: f64, spring: Option<(f64, f64)>, torque: Option<f64>) -> Model {
    let mut loads = Vec::new();
    if let Some((k, theta0)) = spring {
        loads.push(format!(
            r#"{{"type": "torsion_spring", "name": "ts", "body_a": "ground", "body_b": "bar", "stiffness": {k}, "free_angle": {theta0}}}"#
        ));
    }
    if let Some(tau) = torque {
        loads.push(format!(
            r#"{{"type": "torque", "name": "tq", "body": "bar", "law": {{"type": "constant", "value": {tau}}}}}"#
        ));
    }
    let json = format!(
        r#"{{"name": "spring pendulum", "gravity": [0.0, {g}],
          "bodies": [{{"name": "bar", "x": {L}, "y": 0.0, "theta": 0.0, "mass": {M}, "inertia": {JC}}}],
          "joints": [{{"type": "revolute", "name": "O", "body_a": "ground", "body_b": "bar", "at": [0.0, 0.0]}}],
          "loads": [{loads}]}}"#,
        g = -gravity,
        loads = loads.join(", ")
    );
    Model::with_options(Description::from_json(&json).unwrap(), Options { free: true, ..Options::default() })
        .unwrap()
}

/// The root of f on [a, b] (f(a) f(b) < 0) by bisection until the bracket stops shrinking.
fn bisect(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let fa = f(a);
    assert!(fa * f(b) < 0.0);
    loop {
        let c = 0.5 * (a + b);
        if c <= a.min(b) || c >= a.max(b) {
            return c;
        }
        if (f(c) > 0.0) == (fa > 0.0) {
            a = c;
        } else {
            b = c;
        }
    }
}

#[test]
fn spring_pendulum_rests_and_swings_as_the_closed_form_says() {
    // k > m g l: the balance is monotone, one root
    let (k, theta0) = (25.0, 0.9);
    let model = pendulum(G, Some((k, theta0)), None);
    let balance = |th: f64| k * (th - theta0) + M * G * L * th.cos();
    let theta = bisect(balance, -3.0, 3.0);
    let eq = equilibrium(&model, 0.0, None, &EqOptions::default()).unwrap();
    assert!((eq.q[2] - theta).abs() < 1e-12, "theta {} vs {theta}", eq.q[2]);
    // the centre of mass on its circle about the pin
    assert!((eq.q[0] - L * theta.cos()).abs() < 1e-12 && (eq.q[1] - L * theta.sin()).abs() < 1e-12);
    assert!(eq.iterations >= 2 && eq.iterations < 30, "{} iterations", eq.iterations);
    let st = stability(&model, &eq);
    assert!(st.stable && st.eigenvalues.len() == 1 && st.eigenvalues[0] > 0.0, "{st:?}");
    let md = modes(&model, &eq).unwrap();
    let i_o = JC + M * L * L;
    let omega2 = (k - M * G * L * theta.sin()) / i_o;
    assert!((md.omega2[0] - omega2).abs() < 1e-10 * omega2, "{} vs {omega2}", md.omega2[0]);
    // the shape: a unit turn about the pin, mass-normalised: theta' = 1 / sqrt(I_O)
    let s = &md.shapes[0];
    let turn = 1.0 / i_o.sqrt();
    assert!((s[2] - turn).abs() < 1e-10 * turn, "{s:?}");
    assert!((s[0] + L * theta.sin() * turn).abs() < 1e-10 && (s[1] - L * theta.cos() * turn).abs() < 1e-10);
    // the pin holds the weight and the spring's reaction is a pure torque: lambda balances m g
    let lam_y: f64 = eq.lambda[1] * model.constraints[0].row_scale[1];
    assert!((lam_y.abs() - M * G).abs() < 1e-10 * M * G, "{lam_y}");
}

#[test]
fn upright_pendulum_is_found_and_reported_unstable() {
    let model = pendulum(G, None, None);
    let mut guess = model.q_start.clone();
    let th: f64 = 1.3;
    guess.copy_from_slice(&[L * th.cos(), L * th.sin(), th]);
    let eq = equilibrium(&model, 0.0, Some(&guess), &EqOptions::default()).unwrap();
    assert!((eq.q[2] - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{}", eq.q[2]);
    let st = stability(&model, &eq);
    assert!(!st.stable && st.eigenvalues[0] < -st.tol, "{st:?}");
    let md = modes(&model, &eq).unwrap();
    let omega2 = -M * G * L / (JC + M * L * L);
    assert!((md.omega2[0] - omega2).abs() < 1e-10 * omega2.abs(), "{} vs {omega2}", md.omega2[0]);
    // hanging down, the same bar is stable
    let th: f64 = -1.3;
    guess.copy_from_slice(&[L * th.cos(), L * th.sin(), th]);
    let eq = equilibrium(&model, 0.0, Some(&guess), &EqOptions::default()).unwrap();
    assert!((eq.q[2] + std::f64::consts::FRAC_PI_2).abs() < 1e-12 && stability(&model, &eq).stable);
}

#[test]
fn constant_torque_on_a_free_crank_has_no_rest() {
    let model = pendulum(0.0, None, Some(2.0));
    let e = equilibrium(&model, 0.0, None, &EqOptions::default()).unwrap_err();
    assert_eq!(e.q.len(), model.n_coords);
    assert!(e.force > 1.0 && e.coordinate.starts_with("bar."), "{e}");
    assert!(e.to_string().contains("no equilibrium found"), "{e}");
}
