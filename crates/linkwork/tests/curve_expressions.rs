//! Cam profiles written as expressions r(phi): a closed form, the compile-time refusals
//! naming the joint, and model files.
//!
//! The closed form: an eccentric circular cam (radius R, its centre e from the pivot O
//! along the cam's x axis) is, as a polar profile about O, r(phi) = e cos phi +
//! sqrt(R^2 - e^2 sin^2 phi) (the far root of |r e(phi) - (e, 0)| = R). Written so, it must
//! move a translating knife-edge, roller or flat-faced follower exactly as the `circle`
//! curve does and as the formulas of tests/engine/cams.rs say: q, qd and qdd of the follower to
//! 1e-10 relative (Newton stops at 1e-12 scaled; the closed forms lose a few digits of
//! their own). The contact parameter differs (a polar angle about O, not about the
//! circle's centre), and is checked against its own closed form.
//!
//! A sweep of a cam on an expression allocates nothing per step.

mod common;
use common::*;
use linkwork::curves::CurveDesc;
use linkwork::files::{read, write_description, Format};
use linkwork::units::AngleUnit;
use linkwork::{sweep, Data, Description, Model, SweepOutput, Units};
use std::f64::consts::TAU;

#[path = "common/counting.rs"]
mod counting;
use counting::allocations;

const E: f64 = 0.02;
const R: f64 = 0.05;
const RHO: f64 = 0.015;
/// The eccentric circle as an expression about the pivot.
const ECCENTRIC: &str = "0.02*cos(phi) + sqrt(0.05^2 - 0.02^2*sin(phi)^2)";

fn check(what: &str, got: &[f64], want: &[f64]) {
    let err = rel_err(got, want);
    assert!(err < 1e-10, "{what}: relative error {err:e}");
}

/// A cam turning about the origin (theta = th0 + w t + alpha t^2 / 2, from 0 at the
/// drawing) under a follower translating along the y axis, drawn 3 mm off the profile.
fn eccentric_cam(kind: &str, curve: CurveDesc, coefficients: [f64; 3]) -> Description {
    let reach = if kind == "roller" { R + RHO } else { R };
    let y_drawn = if kind == "flat" { R } else { (reach * reach - E * E).sqrt() } + 0.003;
    translating_cam(kind, curve, y_drawn, RHO, coefficients.to_vec())
}

fn expression(r: &str) -> CurveDesc {
    CurveDesc::PolarExpression { centre: [0.0, 0.0], r: r.into() }
}

#[test]
fn the_eccentric_cam_as_an_expression_moves_its_followers_like_the_circle() {
    // a cam speeding up over one turn, so thdd enters too
    let (th0, w, alpha) = (0.3, 10.0, 5.0);
    let t_end = (-w + (w * w + 2.0 * alpha * TAU).sqrt()) / alpha;
    let n = 721;
    let times: Vec<f64> = (0..n).map(|k| t_end * k as f64 / (n - 1) as f64).collect();
    let coefficients = [th0, w, 0.5 * alpha];
    for kind in ["knife", "roller", "flat"] {
        let reach = if kind == "roller" { R + RHO } else { R };
        // the follower's height at cam angle th and its derivatives in th (tests/engine/cams.rs)
        let y_of = |th: f64| -> [f64; 3] {
            if kind == "flat" {
                return [E * th.sin() + R, E * th.cos(), -E * th.sin()];
            }
            let s = (reach * reach - E * E * th.cos().powi(2)).sqrt();
            let s2 = (2.0 * th).sin();
            [
                E * th.sin() + s,
                E * th.cos() + E * E * s2 / (2.0 * s),
                -E * th.sin() + E * E * (2.0 * th).cos() / s - E.powi(4) * s2 * s2 / (4.0 * s.powi(3)),
            ]
        };
        let (circle, out_c) = sweep_all(
            eccentric_cam(kind, CurveDesc::Circle { centre: [E, 0.0], radius: R }, coefficients),
            &times,
        );
        let (model, out) = sweep_all(eccentric_cam(kind, expression(ECCENTRIC), coefficients), &times);
        let mut want = [vec![], vec![], vec![]];
        for t in &times {
            let (th, thd) = (th0 + w * t + 0.5 * alpha * t * t, w + alpha * t);
            let y = y_of(th);
            want[0].push(y[0]);
            want[1].push(y[1] * thd);
            want[2].push(y[2] * thd * thd + y[1] * alpha);
        }
        for (order, v) in [&out.q, &out.qd, &out.qdd].into_iter().enumerate() {
            let got = column_named(&model, v, "follower.y");
            check(&format!("{kind} y, derivative {order}, closed form"), &got, &want[order]);
            let v_c = [&out_c.q, &out_c.qd, &out_c.qdd][order];
            check(
                &format!("{kind} y, derivative {order}, circle"),
                &got,
                &column_named(&circle, v_c, "follower.y"),
            );
            // the cam's angle is driven, the follower's x and theta stay 0
            for name in ["cam.theta", "follower.x", "follower.theta"] {
                let (a, b) = (column_named(&model, v, name), column_named(&circle, v_c, name));
                assert!(a.iter().zip(&b).all(|(a, b)| (a - b).abs() <= 1e-12), "{kind} {name} {order}");
            }
        }
        // the contact's parameter: the polar angle about O of the contact point (the
        // circle's point towards the follower point, or its top for the flat face), from
        // the cam's x axis
        let s = column_named(&model, &out.q, "F.s");
        for ((t, s), y) in times.iter().zip(&s).zip(&want[0]) {
            let th = th0 + w * t + 0.5 * alpha * t * t;
            let centre = [E * th.cos(), E * th.sin()];
            let contact = if kind == "flat" {
                [centre[0], centre[1] + R]
            } else {
                let d = [-centre[0], y - centre[1]];
                let l = d[0].hypot(d[1]);
                [centre[0] + R * d[0] / l, centre[1] + R * d[1] / l]
            };
            let s_want = contact[1].atan2(contact[0]) - th;
            let err = (s - s_want + TAU / 2.0).rem_euclid(TAU) - TAU / 2.0;
            assert!(err.abs() < 1e-10, "{kind} s at t = {t}: {s} vs {s_want}");
        }
    }
}

#[test]
fn polar_expressions_ignore_the_angle_unit() {
    // phi is in radians whatever the model's angle unit: the same cam in degrees (its
    // driver's law in degrees) moves its follower the same
    let times: Vec<f64> = (0..61).map(|k| 0.01 * k as f64).collect();
    let rad = eccentric_cam("roller", expression(ECCENTRIC), [0.3, 10.0, 2.5]);
    let k = 180.0 / std::f64::consts::PI;
    let mut deg = eccentric_cam("roller", expression(ECCENTRIC), [0.3 * k, 10.0 * k, 2.5 * k]);
    deg.units = Units { angle: AngleUnit::Degree, ..Default::default() };
    let (m_rad, out_rad) = sweep_all(rad, &times);
    let (m_deg, out_deg) = sweep_all(deg, &times);
    for (a, b) in [(&out_rad.q, &out_deg.q), (&out_rad.qd, &out_deg.qd), (&out_rad.qdd, &out_deg.qdd)] {
        check("degrees", &column_named(&m_deg, b, "follower.y"), &column_named(&m_rad, a, "follower.y"));
    }
}

#[test]
fn bad_expressions_are_refused_naming_the_joint() {
    let refuse = |r: &str, want: &str| {
        let e = Model::new(eccentric_cam("roller", expression(r), [0.0, 1.0, 0.0])).expect_err(r).to_string();
        assert!(e.starts_with("joint 'F': curve r"), "{e}");
        assert!(e.contains(want), "{r}: {e:?} should mention {want:?}");
    };
    refuse(
        "0.05 + 0.01*(1 - cos(phi)",
        "expected ')' (for the '(' at column 13), found the end at column 26",
    );
    refuse("0.05 + 0.01*(1 - cos(t))", "unknown name 't' at column 22; the variable is 'phi'");
    refuse("0.025 + 0.05*cos(phi)", "is -0.025 at phi = 3.141592653589793 (its least value)");
    refuse("0.05 + 0.001*ln(cos(phi) + 1)", "ln(0) at column 14");
    refuse("0.05 + 0.001*phi", "is not periodic: r(0) = 0.05 but r(2 pi) = 0.0562");
    refuse("0.05 + 0.001*sin(phi/2)", "is not periodic: r'(0) = 0.0005 but r'(2 pi) = -0.0005");
    // the roller's own check still applies to an expression: a hollow of 7 mm radius
    // (r^2 - r r'') / r^3 -> 1 / 146 m at phi = 0, as in tests/test_cams.py, under a
    // 20 mm roller
    let dent = "0.05 - 0.004*exp(-(atan2(sin(phi), cos(phi))/0.15)^2)";
    let e = Model::new(eccentric_cam("roller", expression(dent), [0.0, 1.0, 0.0])).unwrap_err().to_string();
    assert!(e.contains("joint 'F': roller radius 0.015 exceeds the profile's radius of curvature"), "{e}");
}

#[test]
fn model_files_keep_polar_expressions() {
    let desc = eccentric_cam("flat", expression(ECCENTRIC), [0.3, 10.0, 0.0]);
    for format in [Format::Toml, Format::Json] {
        let text = write_description(&desc, format).unwrap();
        assert!(text.contains("polar_expression") && text.contains(ECCENTRIC), "{text}");
        let file = read(&text, format, "cam").unwrap();
        assert_eq!(file.description, desc);
        // and an expression that does not parse is refused on its joint's line
        let bad = text.replace("sqrt(", "sqr(");
        let e = read(&bad, format, "cam.model").unwrap().compile(Default::default()).unwrap_err().to_string();
        assert!(
            e.contains("joint 'F'") && e.contains("unknown name 'sqr' at column 17; did you mean 'sqrt'?"),
            "{e}"
        );
        // the element's first line: the one before its type
        let line = bad.lines().position(|l| l.contains("cam_follower")).unwrap();
        assert!(e.starts_with(&format!("cam.model: line {line}: joint 'F': curve r")), "{e}");
    }
}

#[test]
fn sweeping_a_cam_on_an_expression_allocates_nothing_per_step() {
    // the roller's gamma evaluates r to its third derivative at every step
    let model = Model::new(eccentric_cam("roller", expression(ECCENTRIC), [0.3, 10.0, 0.0])).unwrap();
    let count = |n: usize| {
        let times: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
        let mut data = Data::new(&model);
        let mut out = SweepOutput::new(&model, &times);
        let before = allocations();
        sweep(&model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap();
        assert_eq!(out.n_done, n);
        allocations() - before
    };
    let (few, many) = (count(20), count(2_000));
    assert_eq!(few, many, "{few} allocations for 20 steps, {many} for 2000");
}
