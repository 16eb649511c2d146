//! Four-bar and offset slider-crank over a whole crank revolution against their closed
//! forms: positions, velocities and accelerations to 1e-10 relative (the Newton
//! tolerance is 1e-12 scaled and the Jacobians are well conditioned, so the engine sits
//! near machine precision; 1e-10 leaves room for the closed forms' own rounding).

use crate::common;
use common::*;
use linkwork::{sweep, Data, LinearKind, Model, Options, SweepOutput};
use std::f64::consts::PI;

fn run(desc: linkwork::Description, linear: LinearKind, times: &[f64]) -> (Model, SweepOutput) {
    let model = Model::with_options(desc, Options { linear, ..Options::default() }).unwrap();
    let mut data = Data::new(&model);
    let mut out = SweepOutput::new(&model, times);
    sweep(&model, &mut data, times, &mut out, 0, &mut |_| true).unwrap();
    (model, out)
}

fn column(out: &SweepOutput, v: &[f64], j: usize) -> Vec<f64> {
    (0..out.n_done).map(|k| v[k * out.n_coords + j]).collect()
}

#[test]
fn four_bar_matches_closed_form_over_a_revolution() {
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let (th0, w) = (0.3, 5.0);
    let n = 721;
    let times: Vec<f64> = (0..n).map(|k| k as f64 * 2.0 * PI / w / (n - 1) as f64).collect();
    for linear in [LinearKind::Refactor, LinearKind::Small, LinearKind::Dense, LinearKind::Sparse] {
        let (model, out) = run(four_bar_drawn(&m, th0 - 0.25, th0, w), linear, &times);
        assert_eq!(model.linear_kind(), linear);
        let mut expect = vec![vec![]; 18];
        for &t in &times {
            let th2 = th0 + w * t;
            let ([th3, th4], [w3, w4], [a3, a4]) = four_bar_closed(&m, th2, w, 0.0);
            let (c2, s2) = (th2.cos(), th2.sin());
            // coupler origin is A; its velocity and acceleration are A's
            let vals = [
                th2,
                m.r2 * c2,
                m.r2 * s2,
                th3,
                th4,
                w,
                -m.r2 * w * s2,
                m.r2 * w * c2,
                w3,
                w4,
                0.0,
                -m.r2 * w * w * c2,
                -m.r2 * w * w * s2,
                a3,
                a4,
            ];
            for (k, v) in vals.iter().enumerate() {
                expect[k].push(*v);
            }
        }
        // positions: crank.theta, coupler.x, coupler.y, coupler.theta, rocker.theta
        let got_q = [
            column(&out, &out.q, 2),
            column(&out, &out.q, 3),
            column(&out, &out.q, 4),
            column(&out, &out.q, 5),
            column(&out, &out.q, 8),
        ];
        let got_qd = [
            column(&out, &out.qd, 2),
            column(&out, &out.qd, 3),
            column(&out, &out.qd, 4),
            column(&out, &out.qd, 5),
            column(&out, &out.qd, 8),
        ];
        let got_qdd = [
            column(&out, &out.qdd, 3),
            column(&out, &out.qdd, 4),
            column(&out, &out.qdd, 5),
            column(&out, &out.qdd, 8),
        ];
        for (k, g) in got_q.iter().enumerate() {
            // angles are compared modulo 2 pi
            let e: Vec<f64> = g
                .iter()
                .zip(&expect[k])
                .map(|(a, b)| a - ((a - b) / (2.0 * PI)).round() * 2.0 * PI)
                .collect();
            let err = rel_err(&e, &expect[k]);
            assert!(err < 1e-10, "{linear:?} position {k}: {err:e}");
        }
        for (k, g) in got_qd.iter().enumerate() {
            let err = rel_err(g, &expect[5 + k]);
            assert!(err < 1e-10, "{linear:?} velocity {k}: {err:e}");
        }
        for (k, g) in got_qdd.iter().enumerate() {
            let err = rel_err(g, &expect[11 + k]);
            assert!(err < 1e-10, "{linear:?} acceleration {k}: {err:e}");
        }
        // the prediction makes most steps one or two Newton iterations
        let mean_iter = out.iterations.iter().skip(1).map(|&i| i as f64).sum::<f64>() / (n - 1) as f64;
        assert!(mean_iter <= 2.5, "mean Newton iterations {mean_iter}");
        assert!(out.pivot_ratio.iter().all(|&p| p > 1e-3));
    }
}

#[test]
fn offset_slider_crank_matches_closed_form_over_a_revolution() {
    let m = SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 };
    let (th0, w) = (-0.4, 5.0);
    let n = 721;
    let times: Vec<f64> = (0..n).map(|k| k as f64 * 2.0 * PI / w / (n - 1) as f64).collect();
    for linear in [LinearKind::Refactor, LinearKind::Small, LinearKind::Dense, LinearKind::Sparse] {
        let (_, out) = run(slider_crank(&m, th0, w), linear, &times);
        let (mut th3, mut x, mut w3, mut v, mut a3, mut acc) =
            (vec![], vec![], vec![], vec![], vec![], vec![]);
        for &t in &times {
            let ([p3, px], [pw3, pv], [pa3, pa]) = slider_crank_closed(&m, th0 + w * t, w, 0.0);
            th3.push(p3);
            x.push(px);
            w3.push(pw3);
            v.push(pv);
            a3.push(pa3);
            acc.push(pa);
        }
        // rod.theta = column 5, slider.x = column 6
        let checks = [
            ("rod angle", column(&out, &out.q, 5), th3),
            ("slider x", column(&out, &out.q, 6), x),
            ("rod omega", column(&out, &out.qd, 5), w3),
            ("slider v", column(&out, &out.qd, 6), v),
            ("rod alpha", column(&out, &out.qdd, 5), a3),
            ("slider a", column(&out, &out.qdd, 6), acc),
        ];
        for (what, got, want) in checks {
            let err = rel_err(&got, &want);
            assert!(err < 1e-10, "{linear:?} {what}: {err:e}");
        }
        // the slider neither turns nor leaves its line
        assert!(column(&out, &out.q, 8).iter().all(|t| t.abs() < 1e-14));
        assert!(column(&out, &out.q, 7).iter().all(|y| (y - m.e).abs() < 1e-14));
    }
}
