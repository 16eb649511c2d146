//! Inverse dynamics against hand-worked cases: a driven pendulum (driver torque and pin
//! reaction in closed form) and a slider-crank whose only mass is the slider (crank
//! torque by virtual work). Tolerance 1e-10 relative: the multipliers come from the same
//! well-conditioned factorization as the accelerations, which meet their closed forms
//! near machine precision.

use crate::common;
use common::*;
use linkwork::{
    sweep, Data, Description, DriverDesc, LinearKind, Model, MotionLaw, Options, SweepOutput,
    REACTION_COLUMNS,
};
use std::f64::consts::PI;

fn run(desc: Description, linear: LinearKind, times: &[f64]) -> (Model, SweepOutput) {
    let model = Model::with_options(desc, Options { linear, ..Options::default() }).unwrap();
    let mut data = Data::new(&model);
    let mut out = SweepOutput::with_forces(&model, times);
    sweep(&model, &mut data, times, &mut out, 0, &mut |_| true).unwrap();
    (model, out)
}

#[test]
fn driven_pendulum_torque_and_pin_force_match_the_hand_worked_case() {
    let (l, m, g) = (0.8, 2.5, 9.81);
    let (th0, w0, al) = (-0.3, 2.0, 1.5);
    let mut bob = body("bob", 0.0, 0.0, th0);
    bob.mass = m;
    bob.inertia = m * l * l / 12.0;
    bob.com = Some([0.5 * l * th0.cos(), 0.5 * l * th0.sin()]);
    let desc = Description {
        name: "pendulum".into(),
        units: Default::default(),
        bodies: vec![bob],
        joints: vec![pin("O", "ground", "bob", [0.0, 0.0])],
        drivers: vec![DriverDesc::Angle {
            name: "drive".into(),
            body: "bob".into(),
            law: MotionLaw::Polynomial { coefficients: vec![th0, w0, 0.5 * al] },
        }],
        points: vec![],
        gravity: [0.0, -g],
        loads: vec![],
        outputs: Vec::new(),
        branch: None,
        close: None,
        free: false,
        initial_rates: Default::default(),
    };
    let times: Vec<f64> = (0..201).map(|k| k as f64 * 0.01).collect();
    for linear in [LinearKind::Refactor, LinearKind::Small, LinearKind::Dense, LinearKind::Sparse] {
        let (model, out) = run(desc.clone(), linear, &times);
        let driver_row = model.constraints[1].row0;
        let j_o = m * l * l / 12.0 + m * (0.5 * l) * (0.5 * l);
        for (k, &t) in times.iter().enumerate() {
            let (th, w) = (th0 + w0 * t + 0.5 * al * t * t, w0 + al * t);
            let torque = j_o * al + m * g * 0.5 * l * th.cos();
            let effort = -out.lambda[k * model.n_rows + driver_row];
            assert!(
                (effort - torque).abs() <= 1e-10 * torque.abs().max(1.0),
                "{linear:?} t={t}: {effort} vs {torque}"
            );
            // pin force on the bob: m a_c - m g
            let rc = [0.5 * l * th.cos(), 0.5 * l * th.sin()];
            let ac = [-al * rc[1] - w * w * rc[0], al * rc[0] - w * w * rc[1]];
            let f = [m * ac[0], m * ac[1] + m * g];
            let width = REACTION_COLUMNS * model.constraints.len();
            let r = &out.reactions[k * width..k * width + REACTION_COLUMNS];
            // a joint delivers no power; the driver delivers effort x rate
            assert!(r[3].abs() <= 1e-12);
            let p = out.reactions[k * width + REACTION_COLUMNS + 3];
            assert!((p - effort * w).abs() <= 1e-10 * (torque * w).abs().max(1.0), "driver power {p}");
            assert!(
                (r[0] - f[0]).abs() <= 1e-10 * 30.0 && (r[1] - f[1]).abs() <= 1e-10 * 30.0,
                "{r:?} vs {f:?}"
            );
            // a pin transmits no torque about itself
            assert!(r[2].abs() <= 1e-12 * 30.0, "torque about the pin {}", r[2]);
            // the parts add up, and the gravity part is the static torque
            let parts: f64 = (0..3).map(|p| out.lambda_parts[p][k * model.n_rows + driver_row]).sum();
            assert!((parts + effort).abs() <= 1e-12 * torque.abs().max(1.0));
            let gravity_part = -out.lambda_parts[1][k * model.n_rows + driver_row];
            assert!((gravity_part - m * g * 0.5 * l * th.cos()).abs() <= 1e-10 * m * g * l);
        }
    }
}

#[test]
fn slider_crank_with_a_massive_slider_needs_the_virtual_work_torque() {
    let sc = SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 };
    let (w, m_s) = (5.0, 3.0);
    let mut desc = slider_crank(&sc, 0.0, w);
    desc.bodies[2].mass = m_s; // slider; crank and rod massless
    desc.gravity = [0.0, -9.81]; // carried by the slide, it needs no crank torque
    let n = 361;
    let times: Vec<f64> = (0..n).map(|k| k as f64 * 2.0 * PI / w / (n - 1) as f64).collect();
    let (model, out) = run(desc, LinearKind::Dense, &times);
    let driver_row = model.constraints.iter().find(|c| c.name == "crank_angle").unwrap().row0;
    let mut worst: f64 = 0.0;
    for (k, &t) in times.iter().enumerate() {
        let (_, [_, v], [_, a]) = slider_crank_closed(&sc, w * t, w, 0.0);
        // virtual work: tau w = m_s a v (the slider's kinetic energy rate)
        let torque = m_s * a * v / w;
        let effort = -out.lambda[k * model.n_rows + driver_row];
        worst = worst.max((effort - torque).abs());
    }
    assert!(worst <= 1e-10 * m_s * 5.0 * 0.1, "largest torque error {worst:e}");
}
