//! A sweep of a cam driving three followers (roller, flat face, knife edge) on a polar
//! spline profile makes exactly as many heap allocations over 2,000 steps as over 20:
//! evaluating a curve and the joints that own a coordinate allocates nothing per step.

mod common;
use common::*;
use linkwork::curves::CurveDesc;
use linkwork::{sweep, Data, Description, DriverDesc, JointDesc, Model, MotionLaw, SweepOutput};
use std::f64::consts::TAU;

#[path = "common/counting.rs"]
mod counting;
use counting::allocations;

fn follower(name: &str, b: &str, kind: &str, at: [f64; 2], curve: &CurveDesc) -> JointDesc {
    JointDesc::CamFollower {
        name: name.into(),
        body_a: "cam".into(),
        body_b: b.into(),
        follower: kind.into(),
        at,
        curve: curve.clone(),
        radius: (kind == "roller").then_some(0.008),
        face: (kind == "flat").then_some([1.0, 0.0]),
    }
}

fn slide(name: &str, b: &str, at: [f64; 2], axis: [f64; 2]) -> JointDesc {
    JointDesc::Prismatic {
        name: name.into(),
        body_a: "ground".into(),
        body_b: b.into(),
        at: Some(at),
        axis: Some(axis),
        pin_a: None,
        pin_b: None,
        axis_a: None,
        angle: None,
        travel: None,
    }
}

/// r(phi) = 40 mm + 10 mm of harmonic lift: a roller arm above, a flat-faced slider
/// below, a knife-edge slider on the right.
fn three_followers() -> Description {
    let angles: Vec<f64> = (0..=72).map(|k| TAU * k as f64 / 72.0).collect();
    let radii: Vec<f64> = angles.iter().map(|a| 0.040 + 0.005 * (1.0 - a.cos())).collect();
    let profile = CurveDesc::Polar { centre: [0.0, 0.0], angles, radii };
    Description {
        units: Default::default(),
        name: "three followers".into(),
        bodies: vec![
            body("cam", 0.0, 0.0, 0.0),
            body("arm", -0.060, 0.053, 0.0),
            body("flat", 0.0, -0.045, 0.0),
            body("knife", 0.040, 0.0, 0.0),
        ],
        joints: vec![
            pin("O", "ground", "cam", [0.0, 0.0]),
            pin("O4", "ground", "arm", [-0.060, 0.053]),
            slide("P1", "flat", [0.0, -0.045], [0.0, 1.0]),
            slide("P2", "knife", [0.040, 0.0], [1.0, 0.0]),
            follower("roller", "arm", "roller", [0.0, 0.053], &profile),
            follower("face", "flat", "flat", [0.0, -0.045], &profile),
            follower("tip", "knife", "knife", [0.040, 0.0], &profile),
        ],
        drivers: vec![DriverDesc::Angle {
            name: "turn".into(),
            body: "cam".into(),
            law: MotionLaw::Linear { value: 0.0, rate: TAU },
        }],
        points: vec![],
        gravity: [0.0, 0.0],
        loads: vec![],
        outputs: Vec::new(),
        branch: None,
        close: None,
        free: false,
        initial_rates: Default::default(),
    }
}

fn allocations_of_sweep(model: &Model, n: usize) -> usize {
    let times: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
    let mut data = Data::new(model);
    let mut out = SweepOutput::new(model, &times);
    let before = allocations();
    sweep(model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap();
    assert_eq!(out.n_done, n);
    allocations() - before
}

#[test]
fn cams_allocate_nothing_per_step() {
    let model = Model::new(three_followers()).unwrap();
    assert_eq!(model.n_coords, 15);
    let few = allocations_of_sweep(&model, 20);
    let many = allocations_of_sweep(&model, 2_000);
    assert_eq!(few, many, "{few} allocations for 20 steps, {many} for 2000");
}
