//! Cams and followers against their closed forms over a whole cam revolution, positions,
//! velocities and accelerations to 1e-10 relative (Newton stops at 1e-12 scaled, the
//! Jacobians are well conditioned away from dead points, and the closed forms lose a
//! few digits of their own).
//!
//! An eccentric circular cam: a circle of radius R whose centre is e from the cam's pivot
//! O, at angle theta (the cam's angle). A follower translating along the y axis through O
//! touches it at height
//!   knife edge (its tip on the circle): y = e sin th + sqrt(R^2 - e^2 cos^2 th),
//!   roller of radius rho (its centre on the circle of radius R + rho about the centre):
//!                                        y = e sin th + sqrt((R + rho)^2 - e^2 cos^2 th),
//!   flat face normal to y (tangent to the circle at its top): y = e sin th + R.
//! With D = R^2 - e^2 cos^2 th and S = sqrt(D), the knife's y' = e cos th + e^2 sin 2th / (2 S)
//! and y'' = -e sin th + e^2 cos 2th / S - e^4 sin^2 2th / (4 S^3); the follower's rate and
//! acceleration are y' thd and y'' thd^2 + y' thdd.
//!
//! An oscillating follower on a circular cam is a four-bar: pivot O, cam centre, roller
//! centre (or knife tip), follower pivot; the coupler is R + rho (or R).

use crate::common;
use common::*;
use linkwork::curves::CurveDesc;
use linkwork::{Description, DriverDesc, JointDesc, MotionLaw};
use std::f64::consts::{FRAC_PI_2, TAU};

/// Angles compared modulo 2 pi: `got` brought to the turn of `want`.
fn same_turn(got: &[f64], want: &[f64]) -> Vec<f64> {
    got.iter().zip(want).map(|(g, w)| g - ((g - w) / TAU).round() * TAU).collect()
}

fn check(what: &str, got: &[f64], want: &[f64]) {
    let err = rel_err(got, want);
    assert!(err < 1e-10, "{what}: relative error {err:e}");
}

fn cam_follower(
    kind: &str,
    at: [f64; 2],
    curve: CurveDesc,
    b: &str,
    extra: (Option<f64>, Option<[f64; 2]>),
) -> JointDesc {
    JointDesc::CamFollower {
        name: "F".into(),
        body_a: "cam".into(),
        body_b: b.into(),
        follower: kind.into(),
        at,
        curve,
        radius: extra.0,
        face: extra.1,
    }
}

#[test]
fn eccentric_cam_with_translating_followers_matches_closed_form() {
    let (e, big_r, rho) = (0.02, 0.05, 0.015);
    // theta = th0 + w t + alpha t^2 / 2 over one turn, so thdd enters too
    let (th0, w, alpha) = (0.3, 10.0, 5.0);
    let t_end = (-w + (w * w + 2.0 * alpha * TAU).sqrt()) / alpha;
    let n = 721;
    let times: Vec<f64> = (0..n).map(|k| t_end * k as f64 / (n - 1) as f64).collect();
    let theta: Vec<[f64; 3]> =
        times.iter().map(|t| [th0 + w * t + 0.5 * alpha * t * t, w + alpha * t, alpha]).collect();

    for kind in ["knife", "roller", "flat"] {
        // the height of the contact circle's top at theta: y(th), y', y''
        let r = if kind == "roller" { big_r + rho } else { big_r };
        let y_of = |th: f64| -> [f64; 3] {
            if kind == "flat" {
                return [e * th.sin() + r, e * th.cos(), -e * th.sin()];
            }
            let d = r * r - e * e * th.cos().powi(2);
            let s = d.sqrt();
            let s2 = (2.0 * th).sin();
            [
                e * th.sin() + s,
                e * th.cos() + e * e * s2 / (2.0 * s),
                -e * th.sin() + e * e * (2.0 * th).cos() / s - e.powi(4) * s2 * s2 / (4.0 * s.powi(3)),
            ]
        };
        // drawn at cam angle 0 with the follower a little off the profile: assembly moves it
        let y_drawn = y_of(0.0)[0] + 0.003;
        let circle = CurveDesc::Circle { centre: [e, 0.0], radius: big_r };
        let desc = translating_cam(kind, circle, y_drawn, rho, vec![th0, w, 0.5 * alpha]);
        let (model, out) = sweep_all(desc, &times);
        assert_eq!(model.columns[6], "F.s");
        let label = kind;
        let mut want = [vec![], vec![], vec![]];
        for th in &theta {
            let y = y_of(th[0]);
            want[0].push(y[0]);
            want[1].push(y[1] * th[1]);
            want[2].push(y[2] * th[1] * th[1] + y[1] * th[2]);
        }
        check(&format!("{label} y"), &column_named(&model, &out.q, "follower.y"), &want[0]);
        check(&format!("{label} y'"), &column_named(&model, &out.qd, "follower.y"), &want[1]);
        check(&format!("{label} y''"), &column_named(&model, &out.qdd, "follower.y"), &want[2]);

        // the contact's parameter: its direction from the circle's centre, measured from the
        // cam's starting x axis (the cam turned by theta since)
        let s = column_named(&model, &out.q, "F.s");
        let sd = column_named(&model, &out.qd, "F.s");
        let (mut s_want, mut sd_want) = (vec![], vec![]);
        for (th, y) in theta.iter().zip(&want[0]) {
            if kind == "flat" {
                s_want.push(FRAC_PI_2 - th[0]);
                sd_want.push(-th[1]);
            } else {
                // direction atan2(Y, X), X = -e cos th, Y = y - e sin th, X^2 + Y^2 = r^2
                let (x, yy) = (-e * th[0].cos(), y - e * th[0].sin());
                let (xd, yd) = (e * th[0].sin(), y_of(th[0])[1] - e * th[0].cos());
                s_want.push(yy.atan2(x) - th[0]);
                sd_want.push(((x * yd - yy * xd) / (r * r) - 1.0) * th[1]);
            }
        }
        check(&format!("{label} s"), &same_turn(&s, &s_want), &s_want);
        check(&format!("{label} s'"), &sd, &sd_want);
        if kind == "flat" {
            // s'' = -thdd: the tangency row's gamma (with its c''' term) is exact
            let sdd = column_named(&model, &out.qdd, "F.s");
            assert!(sdd.iter().all(|v| (v + alpha).abs() < 1e-10 * alpha), "flat s''");
        }
        // the follower stays upright and on its line
        assert!(column_named(&model, &out.q, "follower.theta").iter().all(|v| v.abs() < 1e-14));
        assert!(column_named(&model, &out.q, "follower.x").iter().all(|v| v.abs() < 1e-14));
    }
}

#[test]
fn circular_cam_with_oscillating_followers_is_a_four_bar() {
    let (big_r, rho) = (0.05, 0.015);
    let (th_drawn, th0, w) = (0.6, 0.8, 10.0);
    let n = 721;
    let times: Vec<f64> = (0..n).map(|k| TAU / w * k as f64 / (n - 1) as f64).collect();
    for (kind, coupler) in [("knife", big_r), ("roller", big_r + rho)] {
        // O2 = cam pivot, A = cam centre (crank 0.02), B = follower point, O4 = (0.08, 0): a
        // Grashof crank-rocker away from its change point (0.02 + 0.08 < coupler + 0.06)
        let m = FourBar { r1: 0.08, r2: 0.02, r3: coupler, r4: 0.06 };
        let ([_, th4], _, _) = four_bar_closed(&m, th_drawn, w, 0.0);
        let a = [m.r2 * th_drawn.cos(), m.r2 * th_drawn.sin()];
        let b = [m.r1 + m.r4 * th4.cos(), m.r4 * th4.sin()];
        let radius = (kind == "roller").then_some(rho);
        let desc = Description {
            units: Default::default(),
            name: "oscillating follower".into(),
            bodies: vec![body("cam", 0.0, 0.0, th_drawn), body("arm", m.r1, 0.0, th4)],
            joints: vec![
                pin("O2", "ground", "cam", [0.0, 0.0]),
                pin("O4", "ground", "arm", [m.r1, 0.0]),
                cam_follower(kind, b, CurveDesc::Circle { centre: a, radius: big_r }, "arm", (radius, None)),
            ],
            drivers: vec![DriverDesc::Angle {
                name: "turn".into(),
                body: "cam".into(),
                law: MotionLaw::Linear { value: th0, rate: w },
            }],
            points: vec![],
            gravity: [0.0, 0.0],
            loads: vec![],
            outputs: Vec::new(),
            branch: None,
            close: None,
            free: false,
            initial_rates: Default::default(),
        };
        let (model, out) = sweep_all(desc, &times);
        let mut want: [Vec<f64>; 5] = Default::default();
        for t in &times {
            let th2 = th0 + w * t;
            let ([th3, th4], [w3, w4], [_, a4]) = four_bar_closed(&m, th2, w, 0.0);
            want[0].push(th4);
            want[1].push(w4);
            want[2].push(a4);
            // the contact lies along the coupler A -> B from the cam centre
            want[3].push(th3 - (th2 - th_drawn));
            want[4].push(w3 - w);
        }
        let label = kind;
        check(
            &format!("{label} theta4"),
            &same_turn(&column_named(&model, &out.q, "arm.theta"), &want[0]),
            &want[0],
        );
        check(&format!("{label} omega4"), &column_named(&model, &out.qd, "arm.theta"), &want[1]);
        check(&format!("{label} alpha4"), &column_named(&model, &out.qdd, "arm.theta"), &want[2]);
        check(&format!("{label} s"), &same_turn(&column_named(&model, &out.q, "F.s"), &want[3]), &want[3]);
        check(&format!("{label} s'"), &column_named(&model, &out.qd, "F.s"), &want[4]);
    }
}
