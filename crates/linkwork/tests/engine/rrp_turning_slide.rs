//! The RRP closed-form group on a turning slide: a rod pinned to a crank at A and at B to
//! a block that slides in the slot of a second, accelerating crank. Every term of the
//! group's rates and accelerations is non-zero there (the slot turns and accelerates,
//! the block slides along it: the Coriolis term 2 omega u), so its positions, rates and
//! accelerations are checked against the general path (Newton on the full constraint
//! set, accelerations from the assembled equations) and against finite differences of
//! the group's own positions and rates. Only cargo runs this mechanism; the Python
//! suite's slider-cranks slide on the ground, where the Coriolis term vanishes.

use crate::common;

use common::*;
use linkwork::blocks::Block;
use linkwork::{
    sweep, Data, Description, DriverDesc, JointDesc, Model, MotionLaw, Options, SolverKind, SweepOutput,
};

const O2: [f64; 2] = [0.5, -0.3];
const CRANK: f64 = 0.15;
const ROD: f64 = 0.9;

/// The slotted bar turns about the origin by theta = 0.4 + 1.5 t + 0.8 t^2; the crank
/// about O2 by 1.0 - 4 t + 0.5 t^2. `slot_side_a`: the prismatic joint names the slotted
/// bar as its side a (the line fixed in the known body) or as side b (the line in the
/// block).
fn turning_slide(slot_side_a: bool) -> Description {
    let (th_bar, th_crank) = (0.4f64, 1.0f64);
    let d = [th_bar.cos(), th_bar.sin()];
    let a = [O2[0] + CRANK * th_crank.cos(), O2[1] + CRANK * th_crank.sin()];
    // B on the slot's line at the rod's length from A (the branch ahead along the slot)
    let along = d[0] * a[0] + d[1] * a[1];
    let off = d[0] * a[1] - d[1] * a[0];
    let s = along + (ROD * ROD - off * off).sqrt();
    let b = [s * d[0], s * d[1]];
    let th_rod = (b[1] - a[1]).atan2(b[0] - a[0]);
    let (side_a, side_b) = if slot_side_a { ("bar", "block") } else { ("block", "bar") };
    let angle = |body: &str, c: Vec<f64>| DriverDesc::Angle {
        name: format!("{body}_angle"),
        body: body.into(),
        law: MotionLaw::Polynomial { coefficients: c },
    };
    Description {
        name: "turning slide".into(),
        units: Default::default(),
        bodies: vec![
            body("bar", 0.0, 0.0, th_bar),
            body("crank", O2[0], O2[1], th_crank),
            body("rod", a[0], a[1], th_rod),
            body("block", b[0], b[1], th_bar),
        ],
        joints: vec![
            pin("O1", "ground", "bar", [0.0, 0.0]),
            pin("O2", "ground", "crank", O2),
            pin("A", "crank", "rod", a),
            pin("B", "rod", "block", b),
            JointDesc::Prismatic {
                name: "slot".into(),
                body_a: side_a.into(),
                body_b: side_b.into(),
                at: Some(b),
                axis: Some(d),
                pin_a: None,
                pin_b: None,
                axis_a: None,
                angle: None,
                travel: None,
            },
        ],
        drivers: vec![angle("bar", vec![0.4, 1.5, 0.8]), angle("crank", vec![1.0, -4.0, 0.5])],
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

fn sweep_with(desc: &Description, solver: SolverKind, times: &[f64]) -> (Model, SweepOutput) {
    let model = Model::with_options(desc.clone(), Options { solver, ..Options::default() }).unwrap();
    let mut data = Data::new(&model);
    let mut out = SweepOutput::new(&model, times);
    sweep(&model, &mut data, times, &mut out, 0, &mut |_| true).unwrap();
    assert_eq!(out.n_done, times.len());
    (model, out)
}

/// Largest difference over the largest magnitude of `b`.
fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

fn times(n: usize, t1: f64) -> Vec<f64> {
    (0..n).map(|k| t1 * k as f64 / (n - 1) as f64).collect()
}

/// The block's slide rate u along the slot and the slot's angular velocity, per step.
fn slide_rates(model: &Model, out: &SweepOutput) -> Vec<(f64, f64)> {
    let (bx, by) = (column_named(model, &out.q, "block.x"), column_named(model, &out.q, "block.y"));
    let (vx, vy) = (column_named(model, &out.qd, "block.x"), column_named(model, &out.qd, "block.y"));
    let (th, w) = (column_named(model, &out.q, "bar.theta"), column_named(model, &out.qd, "bar.theta"));
    (0..out.n_done)
        .map(|k| {
            // v = w x r + u d: u = (v - w perp(r)) . d
            let (c, s) = (th[k].cos(), th[k].sin());
            let u = (vx[k] + w[k] * by[k]) * c + (vy[k] - w[k] * bx[k]) * s;
            (u, w[k])
        })
        .collect()
}

#[test]
fn rrp_on_a_turning_slide_matches_the_general_path_in_positions_rates_and_accelerations() {
    let t = times(401, 1.2);
    for slot_side_a in [true, false] {
        let desc = turning_slide(slot_side_a);
        let (auto, a) = sweep_with(&desc, SolverKind::Auto, &t);
        let blocks = &auto.plan.as_ref().expect("a plan").blocks;
        assert!(blocks.iter().any(|b| matches!(b, Block::Rrp(_))), "no RRP group in {blocks:?}");
        let (_, g) = sweep_with(&desc, SolverKind::General, &t);
        // the Coriolis term is of order one over the sweep
        let peak = slide_rates(&auto, &a).iter().map(|(u, w)| (2.0 * u * w).abs()).fold(0.0, f64::max);
        assert!(peak > 1.0, "side a {slot_side_a}: the Coriolis term peaks at only {peak}");
        let n = a.n_done * auto.n_coords;
        // both at the Newton tolerance (1e-12 scaled) or closer
        for (what, x, y, tol) in
            [("q", &a.q, &g.q, 1e-12), ("qd", &a.qd, &g.qd, 1e-11), ("qdd", &a.qdd, &g.qdd, 1e-10)]
        {
            let e = rel(&x[..n], &y[..n]);
            assert!(e <= tol, "side a {slot_side_a}: {what} differs from the general path by {e:e}");
        }
    }
}

#[test]
fn rrp_on_a_turning_slide_rates_and_accelerations_are_the_derivatives_of_its_positions() {
    // central differences: error ~ h^2 / 6 times the third derivative, ~1e-6 here with
    // h = 1e-3 (measured 1.6e-5 in the rod's angle); a missing or halved Coriolis term
    // is an error of order one
    let h = 1e-3;
    for slot_side_a in [true, false] {
        let desc = turning_slide(slot_side_a);
        let t: Vec<f64> = (0..1201).map(|k| k as f64 * h).collect();
        let (model, out) = sweep_with(&desc, SolverKind::Auto, &t);
        for name in ["rod.x", "rod.y", "rod.theta", "block.x", "block.y"] {
            let q = column_named(&model, &out.q, name);
            let qd = column_named(&model, &out.qd, name);
            let qdd = column_named(&model, &out.qdd, name);
            let fd = |v: &[f64]| -> Vec<f64> {
                (1..v.len() - 1).map(|k| (v[k + 1] - v[k - 1]) / (2.0 * h)).collect()
            };
            let e_rate = rel(&qd[1..qd.len() - 1], &fd(&q));
            let e_acc = rel(&qdd[1..qdd.len() - 1], &fd(&qd));
            assert!(e_rate < 1e-4, "side a {slot_side_a}: {name} rate vs differences {e_rate:e}");
            assert!(e_acc < 1e-4, "side a {slot_side_a}: {name} acceleration vs differences {e_acc:e}");
        }
    }
}
