//! The four-bar's and the slider-crank's transmission angles in the linkage summaries
//! (`analysis::linkages`) against the law of cosines and the slider-crank's closed form,
//! at every step of a revolution including the extremes, on both circuits and several
//! offsets. cargo checks the summaries here; the per-step arrays the Python package
//! computes itself (`Linkage.transmission_angle_of`) only pytest checks
//! (tests/test_transmission_angles.py).

use crate::common;

use common::*;
use linkwork::analysis::linkages::linkages;
use linkwork::{Description, JointDesc};
use std::f64::consts::PI;

/// The four-bar of `common`, drawn on its open circuit or (mirrored B about A-O4) on the
/// crossed one.
fn four_bar_circuit(m: &FourBar, th2: f64, omega: f64, open: bool) -> Description {
    let mut d = four_bar(m, th2, omega);
    if !open {
        let a = [m.r2 * th2.cos(), m.r2 * th2.sin()];
        let ([th3, _], _, _) = four_bar_closed(m, th2, omega, 0.0);
        let b = [a[0] + m.r3 * th3.cos(), a[1] + m.r3 * th3.sin()];
        // reflect B across the line A -> O4
        let o4 = [m.r1, 0.0];
        let e = [o4[0] - a[0], o4[1] - a[1]];
        let l2 = e[0] * e[0] + e[1] * e[1];
        let t = ((b[0] - a[0]) * e[0] + (b[1] - a[1]) * e[1]) / l2;
        let foot = [a[0] + t * e[0], a[1] + t * e[1]];
        let bm = [2.0 * foot[0] - b[0], 2.0 * foot[1] - b[1]];
        d.bodies[1] = body("coupler", a[0], a[1], (bm[1] - a[1]).atan2(bm[0] - a[0]));
        d.bodies[2] = body("rocker", m.r1, 0.0, bm[1].atan2(bm[0] - m.r1));
        d.joints[2] = pin("B", "coupler", "rocker", bm);
    }
    d
}

/// The slider-crank of `common`, the slider ahead of the crank pin along x or behind it.
fn slider_crank_circuit(s: &SliderCrank, th2: f64, omega: f64, ahead: bool) -> Description {
    let mut d = slider_crank(s, th2, omega);
    if !ahead {
        let a = [s.r2 * th2.cos(), s.r2 * th2.sin()];
        let th3 = PI - ((s.e - a[1]) / s.r3).asin();
        let x = a[0] + s.r3 * th3.cos();
        d.bodies[1] = body("rod", a[0], a[1], th3);
        d.bodies[2] = body("slider", x, s.e, 0.0);
        d.joints[2] = pin("B", "rod", "slider", [x, s.e]);
        if let JointDesc::Prismatic { at, .. } = &mut d.joints[3] {
            *at = Some([x, s.e]);
        }
    }
    d
}

/// Crank angles over a revolution, with 0 and pi (and any `extra`) among them.
fn revolution(extra: &[f64]) -> Vec<f64> {
    let mut t: Vec<f64> = (0..=360).map(|k| k as f64 * PI / 180.0).collect();
    t.extend(extra.iter().map(|a| a.rem_euclid(2.0 * PI)));
    t.sort_by(f64::total_cmp);
    t.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    t
}

#[test]
fn four_bar_summary_transmission_angle_is_the_law_of_cosines_on_both_circuits() {
    for m in
        [FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, FourBar { r1: 1.0, r2: 0.3, r3: 0.9, r4: 0.7 }]
    {
        for open in [true, false] {
            // the driver's angle is t itself: a revolution from crank angle 0
            let times = revolution(&[]);
            let (model, out) = sweep_all(four_bar_circuit(&m, 0.0, 1.0, open), &times);
            let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
            for (k, &th2) in times.iter().enumerate() {
                let q = &out.q[k * model.n_coords..(k + 1) * model.n_coords];
                let summary = linkages(&model, q);
                assert_eq!(summary.four_bars[0].circuit, if open { "open" } else { "crossed" });
                let mu = summary.four_bars[0].transmission_angle;
                // |A - O4|^2 by the law of cosines in O2-A-O4, then the angle at B
                let ao4 = m.r1 * m.r1 + m.r2 * m.r2 - 2.0 * m.r1 * m.r2 * th2.cos();
                let want = ((m.r3 * m.r3 + m.r4 * m.r4 - ao4) / (2.0 * m.r3 * m.r4)).acos();
                assert!((mu - want).abs() < 1e-9, "open {open}, crank {th2}: {mu} vs {want}");
                lo = lo.min(mu);
                hi = hi.max(mu);
            }
            // the extremes at crank angles 0 and pi
            let at = |d: f64| ((m.r3 * m.r3 + m.r4 * m.r4 - d * d) / (2.0 * m.r3 * m.r4)).acos();
            assert!((lo - at(m.r1 - m.r2)).abs() < 1e-9, "open {open}: min {lo}");
            assert!((hi - at(m.r1 + m.r2)).abs() < 1e-9, "open {open}: max {hi}");
        }
    }
}

#[test]
fn slider_crank_summary_transmission_angle_is_the_closed_form_at_every_offset_and_circuit() {
    for e in [0.0, 0.02, -0.05, 0.1] {
        let s = SliderCrank { r2: 0.1, r3: 0.35, e };
        for ahead in [true, false] {
            // where the rod is normal to the slide's normal: r2 sin th2 = e
            let flat = (e / s.r2).asin();
            let times = revolution(&[PI / 2.0, 3.0 * PI / 2.0, flat, PI - flat]);
            let (model, out) = sweep_all(slider_crank_circuit(&s, 0.0, 1.0, ahead), &times);
            for (k, &th2) in times.iter().enumerate() {
                let q = &out.q[k * model.n_coords..(k + 1) * model.n_coords];
                let summary = linkages(&model, q);
                assert_eq!(summary.slider_cranks.len(), 1);
                assert_eq!(summary.slider_cranks[0].circuit, if ahead { "open" } else { "crossed" });
                let mu = summary.slider_cranks[0].transmission_angle;
                // the rod's component across the slide is |e - r2 sin th2|: the angle to
                // the slide's normal is acos of it over the rod's length
                let want = ((e - s.r2 * th2.sin()).abs() / s.r3).acos();
                assert!((mu - want).abs() < 1e-9, "e {e}, ahead {ahead}, crank {th2}: {mu} vs {want}");
            }
            let mus: Vec<f64> = (0..times.len())
                .map(|k| {
                    linkages(&model, &out.q[k * model.n_coords..(k + 1) * model.n_coords]).slider_cranks[0]
                        .transmission_angle
                })
                .collect();
            let lo = mus.iter().cloned().fold(f64::INFINITY, f64::min);
            let hi = mus.iter().cloned().fold(0.0, f64::max);
            // worst with the crank normal to the slide on the offset's far side; best
            // (pi/2, the rod along the slide) where r2 sin th2 = e
            assert!((lo - ((e.abs() + s.r2) / s.r3).acos()).abs() < 1e-12, "e {e}: min {lo}");
            assert!((hi - PI / 2.0).abs() < 1e-9, "e {e}: max {hi}");
        }
    }
}
