//! A model's variants (a design study's designs as the compiled model with numbers moved):
//! each against the four-bar's closed form with its own link lengths, against its own
//! model swept alone, and the batch on one and two threads against itself.

use crate::common;

use common::{four_bar, four_bar_closed, FourBar};
use linkwork::sensitivity::Parameter;
use linkwork::{sweep, sweep_variants, Data, Model, Outputs, Request, SolveError, SweepOutput, Variation};

// ground 0.38: a crank-rocker clear of the change point (0.4 would fold it at a half turn)
const M: FourBar = FourBar { r1: 0.38, r2: 0.2, r3: 0.35, r4: 0.25 };
const OMEGA: f64 = 5.0;

fn times(n: usize) -> Vec<f64> {
    let turn = std::f64::consts::TAU / OMEGA;
    (0..n).map(|k| turn * k as f64 / (n - 1) as f64).collect()
}

/// The ground pivot O4 (its place in the ground: r1) and the crank's pin A (its place in
/// the crank: r2), as engine parameters.
fn variation(model: &Model) -> Variation {
    let params = ["constraints.O4.u_b.x", "constraints.A.u_a.x"]
        .iter()
        .map(|name| Parameter::resolve(model, name).unwrap())
        .collect();
    Variation::new(model, params)
}

fn kept(model: &Model) -> Outputs {
    let col = |name: &str| model.columns.iter().position(|c| c == name).unwrap();
    Outputs {
        coords: Some(vec![col("coupler.theta"), col("rocker.theta")]),
        points: vec![(Some(2), [0.1, 0.05])],
    }
}

fn deltas() -> Vec<[f64; 2]> {
    // the last (ground 0.41, crank 0.26) is not Grashof: its crank stops at a limit of motion
    vec![[0.0, 0.0], [0.01, 0.0], [-0.02, 0.015], [0.0, -0.03], [0.03, 0.06]]
}

#[test]
fn each_variant_is_the_four_bar_of_its_own_lengths() {
    let model = Model::new(four_bar(&M, 0.0, OMEGA)).unwrap();
    let t = times(361);
    let designs = deltas();
    let flat: Vec<f64> = designs.iter().flatten().copied().collect();
    let figures = sweep_variants(
        &model,
        &variation(&model),
        designs.len(),
        &flat,
        &t,
        Request { derivatives: 0, ..Request::default() },
        &kept(&model),
        &[None],
        2,
        &mut |_| true,
    );
    let n_steps = t.len();
    for (i, d) in designs.iter().enumerate() {
        let m = FourBar { r1: M.r1 + d[0], r2: M.r2 + d[1], ..M };
        if i == designs.len() - 1 {
            assert!(
                figures.errors[i].is_some() && figures.n_done[i] < n_steps,
                "a crank that cannot turn stops"
            );
            assert!(
                figures.q[(i * n_steps + figures.n_done[i]) * 2].is_nan(),
                "no figure past the last step"
            );
        } else {
            assert!(figures.errors[i].is_none(), "design {i}: {:?}", figures.errors[i]);
        }
        for (k, tk) in t.iter().enumerate().take(figures.n_done[i]) {
            let ([th3, th4], _, _) = four_bar_closed(&m, OMEGA * tk, OMEGA, 0.0);
            let q = &figures.q[(i * n_steps + k) * 2..(i * n_steps + k + 1) * 2];
            // the closed form's own round-off (an arccos near its fold) sets the scale; the
            // sweep's angles are continuous, the closed form's principal values
            let turn =
                |a: f64| (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
            assert!(
                turn(q[0] - th3).abs() < 1e-12 && turn(q[1] - th4).abs() < 1e-12,
                "design {i}, step {k}: {q:?} {th3} {th4}"
            );
            let p = &figures.points[(i * n_steps + k) * 2..(i * n_steps + k + 1) * 2];
            let (s, c) = th4.sin_cos();
            let want = [m.r1 + c * 0.1 - s * 0.05, s * 0.1 + c * 0.05];
            assert!((p[0] - want[0]).abs() < 1e-12 && (p[1] - want[1]).abs() < 1e-12, "design {i}, step {k}");
        }
    }
}

#[test]
fn the_batch_equals_each_variant_swept_alone_on_any_number_of_threads() {
    let model = Model::new(four_bar(&M, 0.3, OMEGA)).unwrap();
    let variation = variation(&model);
    let t = times(200);
    let designs = deltas();
    let flat: Vec<f64> = designs.iter().flatten().copied().collect();
    let outputs = kept(&model);
    let request = Request { derivatives: 2, ..Request::default() };
    let run = |threads: usize| {
        sweep_variants(
            &model,
            &variation,
            designs.len(),
            &flat,
            &t,
            request,
            &outputs,
            &[None],
            threads,
            &mut |_| true,
        )
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(
        one.q.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        two.q.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
    assert_eq!(
        one.points.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        two.points.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
    assert_eq!((&one.n_done, &one.events), (&two.n_done, &two.events));
    for (i, d) in designs.iter().enumerate() {
        let alone = variation.model(&model, d);
        let mut data = Data::new(&alone);
        let mut out = SweepOutput::with_outputs(&alone, &t, request, outputs.clone());
        let err = sweep(&alone, &mut data, &t, &mut out, 0, &mut |_| true).err();
        assert_eq!(err.is_some(), one.errors[i].is_some(), "design {i}");
        assert_eq!(out.n_done, one.n_done[i]);
        let k = out.n_done;
        let rows = &one.q[i * t.len() * 2..][..k * 2];
        assert!(rows.iter().zip(&out.q[..k * 2]).all(|(a, b)| a.to_bits() == b.to_bits()), "design {i}");
        let min = out.pivot_ratio[..k].iter().copied().fold(f64::INFINITY, f64::min);
        assert_eq!(min.to_bits(), one.pivot_min[i].to_bits());
        assert_eq!(out.events.len(), one.events[i]);
    }
}

#[test]
fn no_change_is_the_model_itself() {
    let model = Model::new(four_bar(&M, 0.3, OMEGA)).unwrap();
    let variant = variation(&model).model(&model, &[0.0, 0.0]);
    let t = times(100);
    let sweep_of = |m: &Model| {
        let mut data = Data::new(m);
        let mut out = SweepOutput::new(m, &t);
        sweep(m, &mut data, &t, &mut out, 0, &mut |_| true).unwrap();
        out
    };
    let (a, b) = (sweep_of(&model), sweep_of(&variant));
    assert_eq!(a.q, b.q);
    assert_eq!(a.qdd, b.qdd);
    assert_eq!(a.pivot_ratio, b.pivot_ratio);
    assert!(variant.plan.is_ok(), "a variant keeps the model's plan");
}

#[test]
fn a_variant_carries_its_masses_and_gravity() {
    let model = Model::new(four_bar(&M, 0.3, OMEGA)).unwrap();
    let params = ["bodies.coupler.mass", "bodies.rocker.com.1", "gravity.1"]
        .iter()
        .map(|name| Parameter::resolve(&model, name).unwrap())
        .collect();
    let variant = Variation::new(&model, params).model(&model, &[1.5, 0.02, -9.81]);
    let coupler = model.body_index("coupler").unwrap();
    let rocker = model.body_index("rocker").unwrap();
    assert_eq!(variant.inertias[coupler].mass, model.inertias[coupler].mass + 1.5);
    // the description's centre of mass is a drawn (world) point: its y moves the body's
    // own along A(theta_0)^T e_y
    let (s, c) = model.q_start[3 * rocker + 2].sin_cos();
    let (com, moved) = (model.inertias[rocker].com, variant.inertias[rocker].com);
    assert!((moved[0] - (com[0] + s * 0.02)).abs() < 1e-15 && (moved[1] - (com[1] + c * 0.02)).abs() < 1e-15);
    assert_eq!(variant.gravity, [model.gravity[0], model.gravity[1] - 9.81]);
    assert_eq!(variant.inertias[rocker].mass, model.inertias[rocker].mass);
}

/// Designs far from the nominal four-bar, near the Grashof limit: Newton from the nominal
/// drawing converges onto the crossed circuit for the two listed (it did, silently); each
/// variant is swept on the circuit the model is drawn in, the four-bar's closed form with
/// its own lengths at every step. A design with no configuration there (coupler and rocker
/// too short to reach across at the start) is its named error. Python's
/// tests/test_study_branches.py checks thousands of designs the same way.
#[test]
fn every_variant_takes_the_circuit_the_model_is_drawn_in() {
    let nominal = FourBar { r1: 1.0, r2: 0.3, r3: 1.0, r4: 0.8 };
    let model = Model::new(four_bar(&nominal, 0.0, 1.0)).unwrap();
    // the coupler's length (pin B along it in the coupler) and the rocker's (in the rocker)
    let params = ["constraints.B.u_a.x", "constraints.B.u_b.x"]
        .iter()
        .map(|name| Parameter::resolve(&model, name).unwrap())
        .collect();
    let variation = Variation::new(&model, params);
    let lengths =
        [[1.0, 0.8], [0.5670082391355269, 1.22084963147709], [1.0443846667859245, 0.3472422926536495]];
    let mut flat: Vec<f64> = lengths.iter().flat_map(|l| [l[0] - 1.0, l[1] - 0.8]).collect();
    flat.extend([0.3 - 1.0, 0.3 - 0.8]);
    let t: Vec<f64> = (0..181).map(|k| std::f64::consts::TAU * k as f64 / 180.0).collect();
    let kept = Outputs { coords: Some(vec![5, 8]), points: vec![] };
    assert_eq!(
        (&model.columns[5], &model.columns[8]),
        (&"coupler.theta".to_string(), &"rocker.theta".to_string())
    );
    let request = Request { derivatives: 0, ..Request::default() };
    let figures = sweep_variants(&model, &variation, 4, &flat, &t, request, &kept, &[], 1, &mut |_| true);
    let turn = |a: f64| (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    for (i, l) in lengths.iter().enumerate() {
        assert!(
            figures.errors[i].is_none() && figures.n_done[i] == t.len(),
            "design {i}: {:?}",
            figures.errors[i]
        );
        let m = FourBar { r3: l[0], r4: l[1], ..nominal };
        for (k, tk) in t.iter().enumerate() {
            let ([th3, th4], _, _) = four_bar_closed(&m, *tk, 1.0, 0.0);
            let q = &figures.q[(i * t.len() + k) * 2..][..2];
            // an arccos next to its fold sets the closed form's own round-off
            assert!(
                turn(q[0] - th3).abs() < 1e-9 && turn(q[1] - th4).abs() < 1e-9,
                "design {i}, step {k}: {q:?}"
            );
        }
    }
    // one time only: the start itself, checked as it is stored
    let start = sweep_variants(&model, &variation, 4, &flat, &t[..1], request, &kept, &[], 1, &mut |_| true);
    for (i, l) in lengths.iter().enumerate() {
        let ([th3, th4], _, _) = four_bar_closed(&FourBar { r3: l[0], r4: l[1], ..nominal }, 0.0, 1.0, 0.0);
        let q = &start.q[i * 2..][..2];
        assert!(
            turn(q[0] - th3).abs() < 1e-9 && turn(q[1] - th4).abs() < 1e-9,
            "design {i} at the start: {q:?}"
        );
    }
    let err = figures.errors[3].as_ref().expect("0.3 + 0.3 cannot reach across 0.7");
    assert!(matches!(err, SolveError::AssemblyBranch { .. }), "{err}");
    assert!(err.to_string().contains("'B'") && figures.n_done[3] == 0, "{err}");
}
