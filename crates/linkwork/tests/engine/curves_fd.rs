//! Every curve type against finite differences of itself (c' and c'' from c, c''' from
//! c''), and the properties its construction promises: it passes through the points or
//! the table it was given, repeats every 2 pi, is C2 across its knots, and the searches
//! for a starting parameter land on the exact answer where there is one. The curve
//! joints on a polar expression against finite differences (d/ds and gamma, where c'''
//! enters), and every refusal of a bad expression.

use linkwork::constraints::{Constraint, ConstraintKind, Extra, Frame, Rows, MAX_ROWS};
use linkwork::curves::{Curve, CurveDesc, CurvePoint, PeriodicSpline};
use linkwork::joints::flat_follower::FlatFollower;
use linkwork::joints::point_on_curve::PointOnCurve;
use linkwork::joints::roller_follower::RollerFollower;
use std::f64::consts::{PI, TAU};

/// A smooth periodic profile r(phi), convex, with every function kind the curves use.
const PROFILE: &str = "0.3 + 0.04*cos(2*phi) + 0.02*sin(phi)*exp(0.3*cos(phi)) + 0.01*atan2(sin(3*phi), 2)";

fn profile_r(phi: f64) -> f64 {
    0.3 + 0.04 * (2.0 * phi).cos()
        + 0.02 * phi.sin() * (0.3 * phi.cos()).exp()
        + 0.01 * (3.0 * phi).sin().atan2(2.0)
}

fn curves() -> Vec<(&'static str, Curve)> {
    let angles: Vec<f64> = (0..=12).map(|k| TAU * k as f64 / 12.0 + 0.2).collect();
    let radii: Vec<f64> = angles.iter().map(|a| 0.3 + 0.08 * (2.0 * a).cos() + 0.03 * a.sin()).collect();
    vec![
        ("circle", Curve::circle([0.1, -0.2], 0.35, 0.7).unwrap()),
        (
            "spline",
            Curve::spline(vec![[0.5, 0.0], [0.2, 0.4], [-0.4, 0.3], [-0.5, -0.2], [0.1, -0.45], [0.3, -0.3]])
                .unwrap(),
        ),
        ("clockwise spline", Curve::spline(vec![[0.0, 1.0], [1.0, 0.0], [0.0, -1.0], [-1.0, 0.0]]).unwrap()),
        ("polar", Curve::polar([0.05, 0.02], -0.4, angles, radii).unwrap()),
        ("polar expression", Curve::polar_expression([0.05, 0.02], -0.4, PROFILE).unwrap()),
    ]
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

/// Deterministic parameters spread over three turns (negative ones too), none on a knot
/// (where c''' jumps, so differences of c'' across it are off by h times the jump).
fn params() -> impl Iterator<Item = f64> {
    (0..200).map(|k| -TAU + 3.0 * TAU * (((k as f64 + 0.5) * 0.618_033_988_749_895) % 1.0))
}

#[test]
fn derivatives_match_finite_differences_for_every_curve() {
    for (name, curve) in curves() {
        for s in params() {
            let k = curve.eval(s);
            // central first differences, h = 1e-6: truncation ~1e-12, round-off ~1e-10
            let h = 1e-6;
            let (p, m) = (curve.eval(s + h), curve.eval(s - h));
            for i in 0..2 {
                let d1 = (p.c[i] - m.c[i]) / (2.0 * h);
                assert!((d1 - k.d1[i]).abs() < 1e-8, "{name} c'[{i}] at s = {s}: {d1} vs {}", k.d1[i]);
                let d2 = (p.d1[i] - m.d1[i]) / (2.0 * h);
                assert!((d2 - k.d2[i]).abs() < 1e-7, "{name} c''[{i}] at s = {s}: {d2} vs {}", k.d2[i]);
            }
            // c'' from c itself: second differences, h = 1e-4 -> error ~1e-8 (c is C2, and
            // C-infinity between knots)
            let h = 1e-4;
            let (p, m) = (curve.eval(s + h), curve.eval(s - h));
            for i in 0..2 {
                let d2 = (p.c[i] - 2.0 * k.c[i] + m.c[i]) / (h * h);
                assert!(
                    (d2 - k.d2[i]).abs() < 1e-5,
                    "{name} c''[{i}] from c at s = {s}: {d2} vs {}",
                    k.d2[i]
                );
            }
            // c''' from c'', one-sided within the interval: c''' jumps at a spline's knots
            let h = 1e-7;
            let p = curve.eval(s + h);
            let q = curve.eval(s + 2.0 * h);
            for i in 0..2 {
                let d3 = (-3.0 * k.d2[i] + 4.0 * p.d2[i] - q.d2[i]) / (2.0 * h);
                assert!(
                    (d3 - k.d3[i]).abs() < 1e-5 * (1.0 + k.d3[i].abs()),
                    "{name} c'''[{i}] at s = {s}: {d3} vs {}",
                    k.d3[i]
                );
            }
        }
    }
}

#[test]
fn curves_repeat_every_turn_and_are_c2_at_their_knots() {
    for (name, curve) in curves() {
        for s in params() {
            let (k, next) = (curve.eval(s), curve.eval(s + TAU));
            for (a, b) in [(k.c, next.c), (k.d1, next.d1), (k.d2, next.d2)] {
                assert!(dist(a, b) < 1e-13, "{name} at s = {s} and s + 2 pi: {a:?} vs {b:?}");
            }
        }
    }
    // a periodic spline on uneven knots: value, slope and curvature continuous at every
    // knot, the seam (knot 0 = knot n - 2 pi) included
    let knots = vec![0.3, 0.9, 1.1, 2.5, 4.0, 5.2, 0.3 + TAU];
    let values = vec![1.0, 0.4, -0.2, 0.8, 1.5, -0.6, 1.0];
    let spline = PeriodicSpline::new(knots.clone(), values.clone()).unwrap();
    for (k, (t, v)) in knots.iter().zip(&values).enumerate() {
        let (left, mid, right) = (spline.eval(t - 1e-9), spline.eval(*t), spline.eval(t + 1e-9));
        assert!((mid[0] - v).abs() < 1e-14, "knot {k}: {} vs {v}", mid[0]);
        // over 1e-9 the value moves by f' 1e-9 and the slope by f'' 1e-9 (both < 1e-7 here)
        assert!((left[0] - right[0]).abs() < 1e-7, "knot {k}: value jumps");
        assert!((left[1] - right[1]).abs() < 1e-7, "knot {k}: slope jumps {} vs {}", left[1], right[1]);
        assert!((left[2] - right[2]).abs() < 1e-6, "knot {k}: curvature jumps {} vs {}", left[2], right[2]);
    }
}

#[test]
fn splines_pass_through_their_points_and_tables() {
    // a body at (0.3, -0.1) turned by 0.5 rad: the curve is given in world points at the start
    let pose: [f64; 3] = [0.3, -0.1, 0.5];
    let world = |c: [f64; 2]| {
        let (s, co) = pose[2].sin_cos();
        [pose[0] + co * c[0] - s * c[1], pose[1] + s * c[0] + co * c[1]]
    };
    let points = vec![[0.5, 0.0], [0.2, 0.4], [-0.4, 0.3], [-0.5, -0.2]];
    let curve = CurveDesc::Spline { points: points.clone() }.to_body(Some(pose)).unwrap();
    // chordal knots: s_k = 2 pi (length of the polygon up to point k) / perimeter
    let chords: Vec<f64> = (0..4).map(|k| dist(points[k], points[(k + 1) % 4])).collect();
    let perimeter: f64 = chords.iter().sum();
    let mut run = 0.0;
    for k in 0..4 {
        let c = world(curve.eval(TAU * run / perimeter).c);
        assert!(dist(c, points[k]) < 1e-14, "spline point {k}: {c:?} vs {:?}", points[k]);
        run += chords[k];
    }
    assert_eq!(curve.orientation(), 1.0);

    // polar: phi from the world x axis at the start, about the world centre
    let angles = vec![0.0, 1.5, 3.0, 4.5, TAU];
    let radii = vec![1.0, 1.3, 0.9, 1.1, 1.0];
    let desc = CurveDesc::Polar { centre: [0.2, 0.1], angles: angles.clone(), radii: radii.clone() };
    let curve = desc.to_body(Some(pose)).unwrap();
    for (phi, r) in angles.iter().zip(&radii) {
        let c = world(curve.eval(*phi).c);
        let want = [0.2 + r * phi.cos(), 0.1 + r * phi.sin()];
        assert!(dist(c, want) < 1e-14, "polar row ({phi}, {r}): {c:?} vs {want:?}");
    }

    // a polar expression: the same phi, r read on [0, 2 pi) and repeated beyond it
    let desc = CurveDesc::PolarExpression { centre: [0.2, 0.1], r: PROFILE.into() };
    let curve = desc.to_body(Some(pose)).unwrap();
    for phi in [-7.0, -0.3, 0.0, 1.0, 2.5, 4.0, 6.2, 9.9, 40.0] {
        let r = profile_r(phi);
        let c = world(curve.eval(phi).c);
        let want = [0.2 + r * f64::cos(phi), 0.1 + r * f64::sin(phi)];
        assert!(dist(c, want) < 1e-15, "polar expression at {phi}: {c:?} vs {want:?}");
    }
    // its length-scale points: 64 equal steps of phi from the world x axis
    let points = desc.world_points();
    assert_eq!(points.len(), 64);
    let (phi, r) = (TAU * 5.0 / 64.0, profile_r(TAU * 5.0 / 64.0));
    assert!(dist(points[5], [0.2 + r * phi.cos(), 0.1 + r * phi.sin()]) < 1e-15);
}

#[test]
fn a_periodic_spline_converges_to_the_function_it_samples() {
    // r = 1 + 0.2 cos(phi) tabulated every degree: the cubic spline's error is about
    // 5/384 h^4 max|r''''| = 2.4e-10, so 1e-9 proves the periodic end conditions right
    let n = 360;
    let angles: Vec<f64> = (0..=n).map(|k| TAU * k as f64 / n as f64).collect();
    let radii: Vec<f64> = angles.iter().map(|a| 1.0 + 0.2 * a.cos()).collect();
    let curve = Curve::polar([0.0, 0.0], 0.0, angles, radii).unwrap();
    for s in params() {
        let k = curve.eval(s);
        let want = CurvePoint {
            c: [(1.0 + 0.2 * s.cos()) * s.cos(), (1.0 + 0.2 * s.cos()) * s.sin()],
            ..CurvePoint::default()
        };
        assert!(dist(k.c, want.c) < 1e-9, "at s = {s}: {:?} vs {:?}", k.c, want.c);
    }
}

#[test]
fn searches_find_the_nearest_point_and_the_tangent_to_a_line() {
    let curve = Curve::circle([0.1, -0.2], 0.35, 0.7).unwrap();
    for a in [-3.0, -1.0, 0.0, 0.4, 2.0, 3.1] {
        // from outside and from inside: the nearest point is on the ray from the centre
        for r in [2.5, 0.1] {
            let p = [0.1 + r * f64::cos(a), -0.2 + r * f64::sin(a)];
            let s = curve.nearest(p);
            let want = (a - 0.7).rem_euclid(TAU);
            let err = (s - want + PI).rem_euclid(TAU) - PI;
            assert!(err.abs() < 1e-12, "nearest to the point at angle {a}: s = {s}, want {want}");
        }
    }
    // a line above the circle, normal (0, 1): it touches the top, s = pi/2 - 0.7
    let s = curve.tangent_to_line([0.0, 1.0], [0.0, 0.5]);
    assert!((s - (PI / 2.0 - 0.7)).abs() < 1e-12, "top: {s}");
    // below: the bottom
    let s = curve.tangent_to_line([0.0, 1.0], [0.0, -1.0]);
    assert!((s - (1.5 * PI - 0.7)).abs() < 1e-12, "bottom: {s}");
}

#[test]
fn bad_curves_are_refused_with_the_reason() {
    let refuse = |r: Result<Curve, String>, what: &str| {
        let e = r.expect_err(what);
        assert!(e.contains(what), "{e:?} should mention {what:?}");
    };
    refuse(Curve::circle([0.0, 0.0], 0.0, 0.0), "radius 0");
    refuse(Curve::circle([0.0, 0.0], -1.0, 0.0), "radius -1");
    refuse(Curve::spline(vec![[0.0, 0.0], [1.0, 0.0]]), "at least 3 points");
    refuse(Curve::spline(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), "points 1 and 2 coincide");
    refuse(Curve::spline(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]), "closes by itself");
    let polar = |angles: Vec<f64>, radii: Vec<f64>| Curve::polar([0.0, 0.0], 0.0, angles, radii);
    refuse(polar(vec![0.0, 1.0, TAU], vec![1.0, 1.0, 1.0]), "at least 4 rows");
    refuse(polar(vec![0.0, 1.0, 2.0, 3.0], vec![1.0, 1.0, 1.0, 1.0]), "not periodic");
    refuse(polar(vec![0.0, 1.0, 2.0, TAU], vec![1.0, 1.2, 1.1, 1.3]), "not periodic");
    refuse(polar(vec![0.0, 1.0, 2.0, TAU], vec![1.0, 0.0, 1.1, 1.0]), "radius 0");
    refuse(polar(vec![0.0, 2.0, 1.0, TAU], vec![1.0, 1.2, 1.1, 1.0]), "increase strictly");
    refuse(polar(vec![0.0, 1.0, 2.0, TAU], vec![1.0, 1.2, 1.1]), "3 radii");
}

#[test]
fn bad_polar_expressions_are_refused_with_the_reason() {
    let refuse = |text: &str, what: &str| {
        let e = Curve::polar_expression([0.0, 0.0], 0.0, text).expect_err(text);
        assert!(e.contains(what), "{text}: {e:?} should mention {what:?}");
    };
    // parse errors keep the column of the expression
    refuse(
        "0.05 + 0.01*sn(phi)",
        "curve r '0.05 + 0.01*sn(phi)': unknown name 'sn' at column 13; did you mean 'sin'?",
    );
    refuse("0.05 + 0.01*t", "unknown name 't' at column 13; the variable is 'phi'");
    refuse("0.05 + (phi", "expected ')' (for the '(' at column 8)");
    // r <= 0 somewhere (here around phi = pi), not finite somewhere
    refuse("0.01 + 0.02*cos(phi)", "is -0.01 at phi = 3.14159");
    refuse("0.01 + 0.02*cos(phi)", "a polar profile's radius must be > 0 all round");
    refuse("0.05*(1 - cos(phi))", "is 0 at phi = 0 (its least value)");
    refuse("0.05 + sqrt(cos(phi))", "curve r is not finite at phi = ");
    refuse("0.05 + sqrt(cos(phi))", "sqrt(-");
    refuse("0.05 + 0.001/(phi - pi)^2", "division by zero at column 13");
    // not periodic: the value drifts (by 6e-9, above 1e-9 of r), the slope or the
    // curvature jumps at the seam
    refuse("0.05 + 1e-9*phi", "not periodic: r(0) = 0.05 but r(2 pi) = 0.05000000628");
    refuse("0.05 + 0.001*sin(phi/2)", "not periodic: r'(0) = 0.0005 but r'(2 pi) = -0.0005");
    refuse("0.05 + 1e-5*phi^3*(2*pi - phi)^2", "not periodic: r''(0) = 0 but r''(2 pi) = 0.0049");
    // periodic ones pass: high frequencies, and a profile written over one turn with min
    assert!(Curve::polar_expression([0.0, 0.0], 0.0, "0.05 + 0.001*cos(40*phi)").is_ok());
    assert!(Curve::polar_expression([0.0, 0.0], 0.0, "0.05 + 0.01*min(phi*(2*pi - phi), 1)^3").is_ok());
    let e = Curve::polar_expression([0.0, 0.0], f64::NAN, "0.05").expect_err("angle");
    assert!(e.contains("angle NaN is not finite"), "{e}");
}

// --- the curve joints on a polar expression ------------------------------------------------

fn rows(c: &ConstraintKind, qa: [f64; 3], qb: [f64; 3], s: f64) -> [f64; MAX_ROWS] {
    let mut r = Rows::default();
    c.position(&Frame::new(qa, [0.0; 3]), &Frame::new(qb, [0.0; 3]), &Extra { s, sd: 0.0 }, 0.0, &mut r);
    r.phi
}

fn along(q: [f64; 3], h: f64, qd: [f64; 3]) -> [f64; 3] {
    [q[0] + h * qd[0], q[1] + h * qd[1], q[2] + h * qd[2]]
}

#[test]
fn curve_joints_on_a_polar_expression_match_finite_differences() {
    // the joints' own finite-difference test (joints_fd.rs) on this curve: d/ds of the rows,
    // and gamma as minus the second difference along q + h qd, s + h sd (qdd = 0 there),
    // h = 1e-4 -> error ~1e-8. gamma holds c''' for the roller and the flat face.
    let curve = || Curve::polar_expression([0.05, -0.02], 0.3, PROFILE).unwrap();
    let joints = [
        ConstraintKind::PointOnCurve(PointOnCurve { curve: curve(), u_b: [0.1, 0.25] }),
        ConstraintKind::RollerFollower(RollerFollower { curve: curve(), u_b: [-0.1, 0.2], radius: 0.08 }),
        ConstraintKind::FlatFollower(FlatFollower::new(curve(), [0.05, 0.3], [1.0, -0.3]).unwrap()),
    ];
    type Case = ([f64; 3], [f64; 3], [f64; 3], [f64; 3], f64, f64);
    let cases: [Case; 3] = [
        ([0.1, -0.2, 0.4], [0.3, 0.1, -0.7], [1.5, -0.4, 2.0], [-0.6, 1.1, -1.3], 0.7, 1.9),
        ([-0.3, 0.2, -2.0], [0.0, 0.4, 1.0], [-0.2, 0.9, -3.0], [1.2, 0.3, 0.5], 4.1, -2.2),
        ([0.0, 0.0, 0.0], [0.2, -0.1, 3.0], [0.0, 0.0, 5.0], [0.4, -0.8, 0.0], -1.0, 0.6),
    ];
    for c in &joints {
        for (qa, qb, qda, qdb, s, sd) in cases {
            let mut r = Rows::default();
            let extra = Extra { s, sd };
            c.position(&Frame::new(qa, qda), &Frame::new(qb, qdb), &extra, 0.0, &mut r);
            let h = 1e-6;
            let (p, m) = (rows(c, qa, qb, s + h), rows(c, qa, qb, s - h));
            for i in 0..c.n_rows() {
                let fd = (p[i] - m[i]) / (2.0 * h);
                assert!((fd - r.jac_s[i]).abs() < 1e-8, "{} d/ds row {i}: {fd} vs {}", c.label(), r.jac_s[i]);
            }
            let mut gamma = [0.0; MAX_ROWS];
            c.gamma(&Frame::new(qa, qda), &Frame::new(qb, qdb), &extra, 0.0, &mut gamma);
            let h = 1e-4;
            let p = rows(c, along(qa, h, qda), along(qb, h, qdb), s + h * sd);
            let z = rows(c, qa, qb, s);
            let m = rows(c, along(qa, -h, qda), along(qb, -h, qdb), s - h * sd);
            for i in 0..c.n_rows() {
                let fd = -(p[i] - 2.0 * z[i] + m[i]) / (h * h);
                let tol = 1e-5 * (1.0 + gamma[i].abs());
                assert!((fd - gamma[i]).abs() < tol, "{} gamma row {i}: {fd} vs {}", c.label(), gamma[i]);
            }
        }
    }
}
