//! The branch a design is asked for, where the plan solves a group by Newton (an Assur
//! triad: no closed form): a design drawn on the other assembly of that group (the other
//! sign of det Phi_q) is put on the asked one, not left where its drawing lies. Checked by
//! cargo only (`sweep::branches::on` compares each Newton block's det sign).

use crate::common;
use common::*;
use linkwork::analysis::modes::assembly_modes;
use linkwork::branches::{asked_branches, sweep_on};
use linkwork::{sweep, Data, Description, Model, SweepOutput};

/// A crank driving an Assur triad: a ternary plate T held by three binary links, one from
/// the crank's tip and two from ground pivots. Drawn closed at t = 0.
fn crank_and_triad() -> Description {
    let th2: f64 = 0.4;
    let a = [0.1 * th2.cos(), 0.1 * th2.sin()];
    let (p1, p2, p3) = ([0.30, 0.20], [0.45, 0.25], [0.40, 0.10]);
    let (g2, g3) = ([0.50, 0.45], [0.60, -0.05]);
    let angle = |p: [f64; 2], q: [f64; 2]| (q[1] - p[1]).atan2(q[0] - p[0]);
    let mut d = six_bar_stephenson(th2, 2.0);
    d.name = "crank and triad".into();
    d.bodies = vec![
        body("crank", 0.0, 0.0, th2),
        body("l1", a[0], a[1], angle(a, p1)),
        body("plate", p1[0], p1[1], 0.0),
        body("l2", g2[0], g2[1], angle(g2, p2)),
        body("l3", g3[0], g3[1], angle(g3, p3)),
    ];
    d.joints = vec![
        pin("O2", "ground", "crank", [0.0, 0.0]),
        pin("A", "crank", "l1", a),
        pin("P1", "l1", "plate", p1),
        pin("G2", "ground", "l2", g2),
        pin("P2", "l2", "plate", p2),
        pin("G3", "ground", "l3", g3),
        pin("P3", "l3", "plate", p3),
    ];
    d
}

fn own_sweep(model: &Model, t: &[f64]) -> SweepOutput {
    let mut out = SweepOutput::new(model, t);
    sweep(model, &mut Data::new(model), t, &mut out, 0, &mut |_| true).unwrap();
    out
}

#[test]
fn a_design_drawn_on_the_other_det_sign_of_a_newton_block_is_put_on_the_asked_one() {
    let base = Model::new(crank_and_triad()).unwrap();
    let plan = base.plan.as_ref().expect("a plan");
    let names: Vec<_> = plan.blocks.iter().map(|b| b.name()).collect();
    assert!(names.contains(&"Newton block"), "the triad is a Newton block: {names:?}");
    let t: Vec<f64> = (0..41).map(|k| k as f64 * 0.01).collect();
    let reference = own_sweep(&base, &t);
    let asked = asked_branches(&base, t[0]).expect("the base assembles");

    let modes = assembly_modes(&base, &base.q_start, t[0], 200).unwrap();
    let other = modes
        .modes
        .iter()
        .find(|m| m.det_sign != reference.det_sign[0])
        .expect("an assembly of the triad on the other det sign");
    let mut design = base.clone();
    design.q_start = other.q.clone();
    // alone, the design stays where it is drawn
    let alone = own_sweep(&design, &t);
    assert_eq!(alone.det_sign[0], other.det_sign);

    let mut out = SweepOutput::new(&design, &t);
    sweep_on(&design, &mut Data::new(&design), &t, &mut out, 0, &mut |_| true, Some(&asked)).unwrap();
    assert_eq!(out.n_done, t.len());
    assert!(
        out.det_sign.iter().all(|&s| s == reference.det_sign[0]),
        "the design kept the det sign it was drawn with"
    );
    // and a design drawn on the asked branch is swept as it is, to the bit
    let mut same = SweepOutput::new(&base, &t);
    sweep_on(&base, &mut Data::new(&base), &t, &mut same, 0, &mut |_| true, Some(&asked)).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&same.q), bits(&reference.q));
}
