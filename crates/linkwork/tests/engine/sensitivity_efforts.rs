//! Exact sensitivities of the inverse dynamics' multipliers (the driver efforts, the
//! joints' reactions), dlambda/dp, against differences of whole sweeps with forces, the
//! parameter moved: every engine number of the joints and drivers (they move the motion
//! and Phi_q), and the mass properties, gravity and loads' numbers (they move Q alone),
//! on a four-bar with offset centres of mass, gravity and every kind of load, a
//! slider-crank, and a planetary train.
//!
//! The differences are the fourth-order central ones with h = h_rel of the number (of the
//! model's size for lengths): truncation ~h^4 |f^(5)| / 30 and round-off ~|lambda| eps / h.
//! The four-bar's multipliers vary fast (a stiff spring, offset masses): with h_rel = 1e-4
//! its truncation alone reached 1e-9 of the largest derivative, so it takes 3e-5 (worst
//! agreement measured then 3e-10). The slider-crank's and the planetary train's vary
//! slowly and their differences are round-off bound (1e-9 at 3e-5), so they take 1e-3
//! (worst measured 2e-10). Relative agreement 1e-8 against each parameter's largest entry
//! is asked, with an absolute floor of 1e-9 for the ones that vanish; a missing or wrong
//! term (a velocity term, a centre of mass's lever, the (dPhi_q/dp)^T lambda part) is off
//! by 1e-3 or more.

use crate::common;

use common::with_number;
use linkwork::constraints::Constraint;
use linkwork::sensitivity::{sensitivity_sweep, Parameter, SensitivityOutput};
use linkwork::{Data, Model, Options, SolverKind, SweepOutput};
use serde_json::{json, Value};

fn body(name: &str, x: f64, y: f64, theta: f64, mass: f64, inertia: f64, com: [f64; 2]) -> Value {
    json!({"name": name, "x": x, "y": y, "theta": theta, "mass": mass, "inertia": inertia, "com": com})
}

fn pin(name: &str, a: &str, b: &str, at: [f64; 2]) -> Value {
    json!({"type": "revolute", "name": name, "body_a": a, "body_b": b, "at": at})
}

fn linear(value: f64, rate: f64) -> Value {
    json!({"type": "linear", "value": value, "rate": rate})
}

fn steps(t_end: f64, n: usize) -> Vec<f64> {
    (0..n).map(|k| t_end * k as f64 / (n - 1) as f64).collect()
}

/// lambda at every step of a sweep with forces (n_steps x n_rows), by the general solver.
fn multipliers(desc: &Value, engine: Option<(usize, usize, f64)>, times: &[f64]) -> Vec<f64> {
    let options = Options { solver: SolverKind::General, ..Options::default() };
    let mut model = Model::from_json(&desc.to_string(), options).unwrap();
    if let Some((c, i, d)) = engine {
        *model.constraints[c].kind.params_mut()[i].1 += d;
    }
    let mut data = Data::new(&model);
    let mut out = SweepOutput::with_forces(&model, times);
    linkwork::sweep(&model, &mut data, times, &mut out, 0, &mut |_| true).unwrap();
    out.lambda.to_vec()
}

/// dlambda/dp of every parameter (the engine's numbers of every joint and driver, and
/// the description paths `paths`) against differences of whole sweeps; the kinematic
/// sensitivities of the dynamics' parameters are exactly zero.
fn check(label: &str, desc: Value, times: &[f64], paths: &[&str], h_rel: f64) {
    let model = Model::from_json(&desc.to_string(), Options::default()).unwrap();
    let mut params = Parameter::all(&model);
    let n_engine = params.len();
    params.extend(paths.iter().map(|p| Parameter::resolve(&model, p).unwrap()));
    let mut data = Data::new(&model);
    let mut out = SensitivityOutput::with_efforts(&model, times, &params, 0);
    sensitivity_sweep(&model, &mut data, times, &params, &[], &mut out, 0, &mut |_| true).unwrap();
    assert_eq!(out.n_done, times.len());
    let (n, nr) = (params.len(), model.n_rows);
    let size = model.length_scale;
    for (j, p) in params.iter().enumerate() {
        let h = h_rel * if p.nominal.abs() > 0.0 { p.nominal.abs().max(0.1 * size) } else { size };
        let run = |d: f64| {
            if j < n_engine {
                let (c, i, _) = p.seeds[0];
                multipliers(&desc, Some((c, i, d)), times)
            } else {
                multipliers(&with_number(&desc, &p.name, |v| v + d), None, times)
            }
        };
        let f: Vec<Vec<f64>> = [-2.0, -1.0, 1.0, 2.0].iter().map(|k| run(k * h)).collect();
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        for (at, got) in out.dlambda.iter().skip(j).step_by(n).enumerate() {
            let want = (f[0][at] - 8.0 * f[1][at] + 8.0 * f[2][at] - f[3][at]) / (12.0 * h);
            assert!(got.is_finite(), "{label}: dlambda/d{} at {at} is {got}", p.name);
            worst = worst.max((got - want).abs());
            scale = scale.max(want.abs());
        }
        assert_eq!(out.dlambda.len(), times.len() * nr * n);
        assert!(
            worst <= 1e-8 * scale + 1e-9,
            "{label}: dlambda/d{}: worst error {worst:e} against differences as large as {scale:e}",
            p.name
        );
        if p.seeds.is_empty() && p.points.is_empty() {
            // mass properties, gravity, loads: the motion does not depend on them
            for a in [&out.dq, &out.dqd, &out.dqdd] {
                assert!(a.iter().skip(j).step_by(n).all(|&v| v == 0.0), "{label}: dq/d{} not zero", p.name);
            }
        }
    }
}

fn four_bar() -> Value {
    // O2 (0, 0), O4 (0.35, 0); crank 0.2, coupler 0.35, rocker 0.25; centres of mass off
    // the bars (velocity terms in Q), gravity on a tilted y, every kind of load
    let (a, b) = ([0.2 * 0.3f64.cos(), 0.2 * 0.3f64.sin()], [0.517365536421962, 0.1857115430397069]);
    json!({
        "gravity": [0.4, -9.81],
        "bodies": [
            body("crank", 0.0, 0.0, 0.3, 1.2, 0.004, [0.08, 0.05]),
            body("coupler", a[0], a[1], 0.0, 2.0, 0.02, [0.3, 0.16]),
            body("rocker", 0.35, 0.0, 2.2, 1.5, 0.01, [0.3, 0.1]),
        ],
        "joints": [
            pin("O2", "ground", "crank", [0.0, 0.0]),
            pin("A", "crank", "coupler", a),
            pin("B", "coupler", "rocker", b),
            pin("O4", "ground", "rocker", [0.35, 0.0]),
        ],
        "drivers": [{"type": "angle", "name": "input", "body": "crank", "law": linear(0.3, 5.0)}],
        "loads": [
            {"type": "spring", "name": "S", "body_a": "ground", "at_a": [0.1, 0.3], "body_b": "coupler",
             "at_b": [0.3, 0.2], "stiffness": 300.0, "free_length": 0.1, "damping": 4.0},
            {"type": "force", "name": "F", "body": "coupler", "at": [0.35, 0.12], "direction": [0.3, -1.0],
             "law": {"type": "harmonic", "mean": 5.0, "amplitude": 2.0, "omega": 3.0, "phase": 0.1}},
            {"type": "torque", "name": "T", "body": "rocker", "law": linear(1.5, -2.0)},
            {"type": "torsion_spring", "name": "TS", "body_a": "crank", "body_b": "coupler", "stiffness": 2.0,
             "free_angle": 0.4, "damping": 0.3},
        ],
    })
}

#[test]
fn four_bar_with_masses_gravity_and_loads() {
    let paths = [
        "bodies.coupler.mass",
        "bodies.coupler.inertia",
        "bodies.coupler.com.0",
        "bodies.rocker.com.1",
        "bodies.crank.mass",
        "gravity.0",
        "gravity.1",
        "loads.S.stiffness",
        "loads.S.free_length",
        "loads.S.damping",
        "loads.S.at_a.0",
        "loads.S.at_b.1",
        "loads.F.at.1",
        "loads.F.direction.0",
        "loads.F.law.amplitude",
        "loads.F.law.omega",
        "loads.T.law.rate",
        "loads.TS.stiffness",
        "loads.TS.free_angle",
        "loads.TS.damping",
        "joints.B.at.0",
        "drivers.input.law.rate",
    ];
    check("four-bar", four_bar(), &steps(0.6, 13), &paths, 3e-5);
}

#[test]
fn slider_crank_with_masses() {
    let th: f64 = 0.5;
    let a = [0.1 * th.cos(), 0.1 * th.sin()];
    let bx = a[0] + (0.3f64 * 0.3 - (a[1] - 0.02).powi(2)).sqrt();
    let desc = json!({
        "gravity": [0.0, -9.81],
        "bodies": [
            body("crank", 0.0, 0.0, th, 0.5, 0.001, [0.03, 0.01]),
            body("rod", a[0], a[1], 0.0, 1.1, 0.009, [(a[0] + bx) / 2.0, 0.05]),
            body("slider", bx, 0.02, 0.1, 2.5, 0.002, [bx + 0.01, 0.03]),
        ],
        "joints": [
            pin("O", "ground", "crank", [0.0, 0.0]),
            pin("A", "crank", "rod", a),
            pin("B", "rod", "slider", [bx, 0.02]),
            {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "slider", "at": [bx, 0.02],
             "axis": [1.0, 0.0]},
        ],
        "drivers": [{"type": "angle", "name": "input", "body": "crank",
                     "law": {"type": "polynomial", "coefficients": [th, 3.0, 1.0]}}],
    });
    let paths =
        ["bodies.slider.mass", "bodies.rod.com.1", "bodies.rod.inertia", "gravity.1", "joints.guide.at.1"];
    check("slider-crank", desc, &steps(0.5, 11), &paths, 1e-3);
}

#[test]
fn planetary_train_with_masses_and_its_radii() {
    let (r_s, r_p) = (0.05, 0.03);
    let desc = json!({
        "gravity": [0.0, -9.81],
        "bodies": [
            body("sun", 0.0, 0.0, 0.2, 0.3, 2e-4, [0.0, 0.0]),
            body("carrier", 0.0, 0.0, 0.0, 0.6, 8e-4, [0.03, 0.005]),
            body("planet", r_s + r_p, 0.0, -0.4, 0.2, 5e-5, [r_s + r_p + 0.002, 0.001]),
            body("ring", 0.0, 0.0, 0.7, 0.9, 3e-3, [0.0, 0.0]),
        ],
        "joints": [
            pin("Os", "ground", "sun", [0.0, 0.0]),
            pin("Oc", "ground", "carrier", [0.0, 0.0]),
            pin("Op", "carrier", "planet", [r_s + r_p, 0.0]),
            pin("Or", "ground", "ring", [0.0, 0.0]),
            {"type": "gear", "name": "sun_planet", "body_a": "sun", "body_b": "planet", "radius_a": r_s,
             "radius_b": r_p, "carrier": "carrier"},
            {"type": "gear", "name": "planet_ring", "body_a": "ring", "body_b": "planet",
             "radius_a": r_s + 2.0 * r_p, "radius_b": r_p, "internal": true, "carrier": "carrier"},
        ],
        "drivers": [
            {"type": "angle", "name": "input", "body": "sun", "law": linear(0.2, 6.0)},
            {"type": "angle", "name": "ring_input", "body": "ring", "law": linear(0.7, -2.5)},
        ],
    });
    let paths = [
        "joints.sun_planet.radius_a",
        "joints.sun_planet.radius_b",
        "joints.planet_ring.radius_b",
        "bodies.planet.mass",
        "bodies.carrier.com.0",
    ];
    check("planetary", desc, &steps(0.4, 9), &paths, 1e-3);
}

#[test]
fn numbers_the_dynamics_cannot_differentiate_are_refused_by_name() {
    let mut desc = four_bar();
    desc["loads"][1]["law"] = json!({"type": "spline", "times": [0.0, 0.5, 1.0], "values": [1.0, 3.0, 2.0]});
    let model = Model::from_json(&desc.to_string(), Options::default()).unwrap();
    for (name, says) in [
        ("loads.F.law.values.1", "load 'F' follows a law whose numbers the engine does not differentiate"),
        ("loads.T.law.omega", "the law of load 'T' has law.value, law.rate"),
        ("loads.Z.stiffness", "no load 'Z'"),
        ("loads.S.free_angle", "'free_angle' of load 'S' is not an engine parameter"),
        ("bodies.crank.x", "mass, inertia and com.0, com.1"),
        ("gravity.2", "gravity.0 (x) or gravity.1 (y)"),
    ] {
        let e = Parameter::resolve(&model, name).unwrap_err();
        assert_eq!(e.name, name);
        assert!(e.to_string().contains(says), "{name}: {e}");
    }
}
