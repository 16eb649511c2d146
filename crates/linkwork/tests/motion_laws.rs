//! Motion laws: text expressions, cam profiles and programs, sequences, periodic
//! repetition and external functions. Exact derivatives against finite differences,
//! continuity where promised, the published peak coefficients, errors that say where,
//! engine sweeps against the four-bar's closed form, and no allocation per evaluation.
//!
//! Finite differences: central, h = 1e-5 on laws whose time scale is ~1, so truncation
//! O(h^2 f''') ~ 1e-10 and rounding O(eps / h) ~ 1e-11 relative to the derivative's
//! magnitude: checked at 1e-7 relative.

mod common;

use std::f64::consts::PI;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use common::*;
use linkwork::motion::{CamProgram, CamSegment, ExpressionLaw, Periodic, Profile, Rise, Sequence};
use linkwork::{
    sweep, Data, Description, ExprError, Expression, ExternalLaw, Model, MotionLaw, SolveError, SweepOutput,
};

#[path = "common/counting.rs"]
mod counting;
use counting::allocations;

// --- helpers ----------------------------------------------------------------------------

fn prepared(mut law: MotionLaw) -> MotionLaw {
    law.prepare().unwrap_or_else(|e| panic!("{e}"));
    law
}

fn from_json(text: &str) -> MotionLaw {
    prepared(serde_json::from_str(text).unwrap_or_else(|e| panic!("{e}: {text}")))
}

fn expr(text: &str) -> Expression {
    Expression::parse(text, "t").unwrap_or_else(|e| panic!("{text}: {e}"))
}

fn parse_err(text: &str) -> ExprError {
    match Expression::parse(text, "t") {
        Ok(_) => panic!("{text:?} parsed"),
        Err(e) => e,
    }
}

/// Checks f' and f'' of `eval` against central differences (step h) of f and f' at each
/// time, relative to the largest |f'| and |f''| met.
fn check_derivatives(what: &str, eval: &dyn Fn(f64) -> [f64; 3], times: &[f64], h: f64) {
    let most = |k: usize| times.iter().fold(0.0f64, |m, &t| m.max(eval(t)[k].abs()));
    // rounding in the differences, eps |f| / h, is below 1e-9 for the laws here
    let scale = [most(1) + 0.1, most(2) + 0.1];
    for &t in times {
        let [_, fd, fdd] = eval(t);
        let (p, m) = (eval(t + h), eval(t - h));
        let fd_fd = (p[0] - m[0]) / (2.0 * h);
        let fdd_fd = (p[1] - m[1]) / (2.0 * h);
        assert!((fd - fd_fd).abs() <= 1e-7 * scale[0], "{what}: f'({t}) = {fd}, differences {fd_fd}");
        assert!((fdd - fdd_fd).abs() <= 1e-7 * scale[1], "{what}: f''({t}) = {fdd}, differences {fdd_fd}");
    }
}

fn grid(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n).map(|k| a + (b - a) * k as f64 / (n - 1) as f64).collect()
}

/// max |g| over [0, 1]: a fine grid, then golden-section refinement of the best cell.
fn peak(g: &dyn Fn(f64) -> f64) -> f64 {
    let n = 20_000;
    let best = (0..=n).max_by(|&i, &j| g(i as f64 / n as f64).abs().total_cmp(&g(j as f64 / n as f64).abs()));
    let k = best.unwrap() as f64;
    let (mut a, mut b) = (((k - 1.0) / n as f64).max(0.0), ((k + 1.0) / n as f64).min(1.0));
    let r = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..80 {
        let (c, d) = (b - r * (b - a), a + r * (b - a));
        if g(c).abs() > g(d).abs() {
            b = d;
        } else {
            a = c;
        }
    }
    g(0.5 * (a + b)).abs()
}

// --- cam profiles -------------------------------------------------------------------------

#[test]
#[allow(clippy::approx_constant)] // the table's rounded figures are what is checked
fn profiles_match_the_published_peak_coefficients() {
    // Norton, Design of Machinery, tables 8-2 and 8-3: unit lift over unit time
    let published = [
        (Profile::Cycloidal, 2.0, 6.2832),
        (Profile::ModifiedTrapezoid, 2.0, 4.8881),
        (Profile::ModifiedSine, 1.7596, 5.5280),
        (Profile::Polynomial345, 1.8750, 5.7735),
        (Profile::Polynomial4567, 2.1875, 7.5107),
        (Profile::Harmonic, 1.5708, 4.9348),
    ];
    for (p, cv, ca) in published {
        let v = peak(&|u| p.eval(u)[1]);
        let a = peak(&|u| p.eval(u)[2]);
        // to the digits given: within half a unit of the last one
        assert!((v - cv).abs() <= 0.5e-4, "{p:?}: Cv = {v}, published {cv}");
        if p == Profile::Polynomial4567 {
            // the table's 7.5107 is the largest s'' on the grid u = k / 100 (at u = 0.28);
            // the true peak is at the root u = (5 - sqrt 5) / 10 of s''' = 0
            let on_grid = (0..=100).map(|k| p.eval(k as f64 / 100.0)[2]).fold(0.0, f64::max);
            assert!((on_grid - ca).abs() <= 0.5e-4, "{p:?}: Ca on the 1/100 grid = {on_grid}");
            let u: f64 = (5.0 - 5f64.sqrt()) / 10.0;
            let exact = 420.0 * u.powi(2) - 1680.0 * u.powi(3) + 2100.0 * u.powi(4) - 840.0 * u.powi(5);
            assert!((a - exact).abs() <= 1e-12 && (exact - 7.5132).abs() <= 0.5e-4, "{p:?}: Ca = {a}");
        } else {
            assert!((a - ca).abs() <= 0.5e-4, "{p:?}: Ca = {a}, published {ca}");
        }
    }
}

#[test]
fn profiles_rise_from_rest_to_rest() {
    for p in Profile::ALL {
        let [s0, v0, a0] = p.eval(0.0);
        let [s1, v1, a1] = p.eval(1.0);
        assert_eq!(s0, 0.0, "{p:?}");
        assert!((s1 - 1.0).abs() <= 1e-15, "{p:?}: s(1) = {s1}");
        assert!(v0.abs() <= 1e-15 && v1.abs() <= 1e-14, "{p:?}: s'(0) = {v0}, s'(1) = {v1}");
        if p.continuous_acceleration() {
            assert!(a0.abs() <= 1e-13 && a1.abs() <= 1e-13, "{p:?}: s''(0) = {a0}, s''(1) = {a1}");
        } else {
            assert!((a0 - PI * PI / 2.0).abs() <= 1e-14, "{p:?}: s''(0) = {a0}");
        }
        // monotone rise
        let s: Vec<f64> = grid(0.0, 1.0, 2001).iter().map(|&u| p.eval(u)[0]).collect();
        assert!(s.windows(2).all(|w| w[1] >= w[0]), "{p:?} is not monotone");
    }
}

#[test]
fn profile_derivatives_are_exact() {
    for p in Profile::ALL {
        // away from u = 0 and 1, where the clamp cuts the differences
        check_derivatives(&format!("{p:?}"), &|u| p.eval(u), &grid(1e-3, 1.0 - 1e-3, 997), 1e-5);
    }
}

#[test]
fn piecewise_profiles_are_c2_at_their_inner_joints() {
    // modified trapezoid and modified sine change formula at u = 1/8, 3/8, 1/2, 5/8, 7/8
    for p in [Profile::ModifiedTrapezoid, Profile::ModifiedSine] {
        for u in [0.125, 0.375, 0.5, 0.625, 0.875] {
            let (l, r) = (p.eval(u - 1e-12), p.eval(u + 1e-12));
            for k in 0..3 {
                assert!((l[k] - r[k]).abs() <= 1e-9, "{p:?} jumps in derivative {k} at u = {u}: {l:?} {r:?}");
            }
        }
    }
}

// --- rise and cam program ---------------------------------------------------------------------

#[test]
fn a_rise_holds_before_and_after_and_scales_by_lift_and_duration() {
    for p in Profile::ALL {
        let law =
            prepared(MotionLaw::Rise(Rise { start: 0.2, lift: -0.05, t0: 1.0, duration: 0.4, profile: p }));
        assert_eq!(law.eval(0.5), [0.2, 0.0, 0.0]);
        assert_eq!(law.eval(2.0), [0.2 - 0.05, 0.0, 0.0]);
        let [s, v, a] = p.eval(0.3);
        let [f, fd, fdd] = law.eval(1.0 + 0.3 * 0.4);
        assert!((f - (0.2 - 0.05 * s)).abs() <= 1e-15);
        assert!((fd - (-0.05 * v / 0.4)).abs() <= 1e-14);
        assert!((fdd - (-0.05 * a / 0.16)).abs() <= 1e-13);
        check_derivatives(&format!("rise {p:?}"), &|t| law.eval(t), &grid(1.001, 1.399, 101), 1e-5);
    }
}

fn cam_program(profile: Profile) -> MotionLaw {
    let segments = vec![
        CamSegment::Rise { duration: 0.3, lift: 0.02, profile },
        CamSegment::Dwell { duration: 0.2 },
        CamSegment::Fall { duration: 0.25, lift: 0.02, profile },
        CamSegment::Dwell { duration: 0.25 },
    ];
    MotionLaw::Cam(CamProgram::new(0.1, 0.5, segments).unwrap())
}

#[test]
fn cam_programs_are_continuous_where_their_profiles_promise() {
    for p in Profile::ALL {
        let law = cam_program(p);
        assert_eq!(law.eval(0.0), [0.1, 0.0, 0.0]);
        assert!((law.eval(0.5 + 0.3 + 0.1)[0] - 0.12).abs() <= 1e-15, "top dwell");
        assert!((law.eval(3.0)[0] - 0.1).abs() <= 1e-15, "back at the start");
        let joints = [0.5, 0.8, 1.0, 1.25, 1.5];
        let (d, scale) = (1e-9, [1.0, 0.02 / 0.25, 0.02 * 8.0 / 0.0625]);
        for b in joints {
            let (l, r) = (law.eval(b - d), law.eval(b + d));
            // f and f' continuous: a jump no larger than the slope over 2 d
            assert!((l[0] - r[0]).abs() <= 1e-12, "{p:?} value jumps at t = {b}");
            assert!((l[1] - r[1]).abs() <= 1e-6 * scale[1], "{p:?} velocity jumps at t = {b}: {l:?} {r:?}");
            let jump = (l[2] - r[2]).abs();
            if p.continuous_acceleration() {
                assert!(jump <= 1e-6 * scale[2], "{p:?} acceleration jumps at t = {b}: {l:?} {r:?}");
            } else if b < 1.5 {
                // the simple harmonic's acceleration jumps by lift pi^2 / (2 T^2) at each end
                assert!(jump >= 0.99 * 0.02 * PI * PI / 2.0 / (0.3f64).powi(2), "{p:?} at t = {b}");
            }
        }
        check_derivatives(&format!("cam {p:?}"), &|t| law.eval(t), &grid(0.501, 1.249, 301), 1e-5);
    }
}

#[test]
fn cam_programs_read_from_json() {
    let law = from_json(
        r#"{"type": "cam", "start": 0.1, "t0": 0.5, "segments": [
            {"type": "rise", "duration": 0.3, "lift": 0.02, "profile": "cycloidal"},
            {"type": "dwell", "duration": 0.2},
            {"type": "fall", "duration": 0.25, "lift": 0.02, "profile": "polynomial_345"}]}"#,
    );
    assert!((law.eval(0.9)[0] - 0.12).abs() <= 1e-15);
    assert!((law.eval(1.25)[0] - 0.1).abs() <= 1e-15);
    let bad: Result<MotionLaw, _> =
        serde_json::from_str(r#"{"type": "cam", "segments": [{"type": "dwell", "duration": 1, "lift": 2}]}"#);
    assert!(bad.unwrap_err().to_string().contains("unknown field `lift`"));
    let mut empty =
        MotionLaw::Cam(CamProgram::new(0.0, 0.0, vec![CamSegment::Dwell { duration: 1.0 }]).unwrap());
    if let MotionLaw::Cam(c) = &mut empty {
        c.segments[0] = CamSegment::Dwell { duration: 0.0 };
    }
    assert_eq!(empty.prepare().unwrap_err(), "cam segment 0 duration is 0; it must be finite and > 0");
}

// --- sequences and periodic laws ---------------------------------------------------------

#[test]
fn a_sequence_joins_laws_and_refuses_a_jump_naming_the_breakpoint() {
    // accelerate at 2 rad/s^2 for 1 s, then constant speed 2 rad/s
    let law = prepared(MotionLaw::Sequence(Sequence {
        breakpoints: vec![1.0],
        laws: vec![
            MotionLaw::Polynomial { coefficients: vec![0.0, 0.0, 1.0] },
            MotionLaw::Linear { value: -1.0, rate: 2.0 },
        ],
    }));
    assert_eq!(law.eval(0.5), [0.25, 1.0, 2.0]);
    assert_eq!(law.eval(1.0), [1.0, 2.0, 0.0]); // the law after the breakpoint
    assert_eq!(law.eval(3.0), [5.0, 2.0, 0.0]);

    let mut jump = MotionLaw::Sequence(Sequence {
        breakpoints: vec![1.0, 2.0],
        laws: vec![
            MotionLaw::Constant { value: 0.0 },
            MotionLaw::Linear { value: -1.0, rate: 1.0 },
            MotionLaw::Constant { value: 1.5 },
        ],
    });
    let e = jump.prepare().unwrap_err();
    assert!(
        e.starts_with("sequence breakpoint 1 (t = 2): the value jumps from 1 (law 1) to 1.5 (law 2)"),
        "{e}"
    );

    let mut count = MotionLaw::Sequence(Sequence { breakpoints: vec![1.0], laws: vec![] });
    assert!(count.prepare().unwrap_err().contains("one law more than breakpoints"));
}

#[test]
fn a_sequence_takes_the_domain_of_its_end_laws() {
    let spline = |a: f64, b: f64| {
        serde_json::from_str::<MotionLaw>(&format!(
            r#"{{"type": "spline", "times": [{a}, {}, {b}], "values": [0, 0.5, 1]}}"#,
            0.5 * (a + b)
        ))
        .unwrap()
    };
    let law = prepared(MotionLaw::Sequence(Sequence {
        breakpoints: vec![1.0],
        laws: vec![spline(0.0, 1.0), MotionLaw::Linear { value: 0.0, rate: 1.0 }],
    }));
    assert_eq!(law.domain(), Some((0.0, f64::INFINITY)));
    let mut short = MotionLaw::Sequence(Sequence {
        breakpoints: vec![1.0, 3.0],
        laws: vec![MotionLaw::Constant { value: 0.0 }, spline(1.0, 2.0), MotionLaw::Constant { value: 1.0 }],
    });
    let e = short.prepare().unwrap_err();
    assert_eq!(e, "sequence law 1 is used on [1, 3] but is defined on [1, 2] only");
}

#[test]
fn periodic_laws_carry_their_advance_and_repeat_a_cam_exactly() {
    // an indexing table: a quarter turn in 0.4 s, then 0.6 s at rest, every second
    let index = MotionLaw::Rise(Rise {
        start: 0.0,
        lift: PI / 2.0,
        t0: 0.0,
        duration: 0.4,
        profile: Profile::ModifiedSine,
    });
    let law = MotionLaw::Periodic(Periodic::new(1.0, 0.0, prepared(index.clone())).unwrap());
    for k in [-2.0, 0.0, 1.0, 7.0] {
        for tau in [0.0, 0.13, 0.4, 0.77] {
            let (a, b) = (law.eval(k + tau), index.eval(tau));
            assert!((a[0] - (b[0] + k * PI / 2.0)).abs() <= 1e-13, "k = {k}, tau = {tau}");
            assert!((a[1] - b[1]).abs() <= 1e-12 && (a[2] - b[2]).abs() <= 1e-10, "k = {k}, tau = {tau}");
        }
    }
    // a rise-dwell-fall ends where it starts: no advance
    let cam = cam_program(Profile::Cycloidal);
    let law = MotionLaw::Periodic(Periodic::new(1.0, 0.5, cam.clone()).unwrap());
    for t in grid(0.5, 1.5, 41) {
        for k in [1.0, 5.0, -3.0] {
            let (a, b) = (law.eval(t + k), cam.eval(t));
            assert!((a[0] - b[0]).abs() <= 1e-15 && (a[1] - b[1]).abs() <= 1e-11, "t = {t} + {k}");
        }
    }
    check_derivatives("periodic cam", &|t| law.eval(t), &grid(3.51, 4.24, 101), 1e-5);
    // a spline repeated beyond its table is refused
    let spline: MotionLaw =
        serde_json::from_str(r#"{"type": "spline", "times": [0, 0.5], "values": [0, 1]}"#).unwrap();
    let e = Periodic::new(1.0, 0.0, spline).unwrap_err();
    assert_eq!(e, "periodic law is repeated over [0, 1] but is defined on [0, 0.5] only");
}

// --- expressions -----------------------------------------------------------------------------

#[test]
fn expressions_evaluate_every_function_with_exact_derivatives() {
    // (text, closed form f, f', f'') on t in (0.1, 0.9)
    type Closed = fn(f64) -> [f64; 3];
    let cases: [(&str, Closed); 20] = [
        ("0.35 - 0.16*sin(150*t)", |t| {
            [0.35 - 0.16 * (150.0 * t).sin(), -24.0 * (150.0 * t).cos(), 3600.0 * (150.0 * t).sin()]
        }),
        ("cos(2*t)", |t| [(2.0 * t).cos(), -2.0 * (2.0 * t).sin(), -4.0 * (2.0 * t).cos()]),
        ("tan(t)", |t| {
            let c = t.cos();
            [t.tan(), 1.0 / (c * c), 2.0 * t.tan() / (c * c)]
        }),
        ("asin(t)", |t| [t.asin(), 1.0 / (1.0 - t * t).sqrt(), t / (1.0 - t * t).powf(1.5)]),
        ("acos(t)", |t| [t.acos(), -1.0 / (1.0 - t * t).sqrt(), -t / (1.0 - t * t).powf(1.5)]),
        ("atan(t)", |t| [t.atan(), 1.0 / (1.0 + t * t), -2.0 * t / (1.0 + t * t).powi(2)]),
        ("atan2(t, 1 - t)", |t| {
            let r2 = t * t + (1.0 - t) * (1.0 - t);
            [t.atan2(1.0 - t), 1.0 / r2, -2.0 * (2.0 * t - 1.0) / (r2 * r2)]
        }),
        ("sinh(t) + cosh(t)", |t| [t.exp(), t.exp(), t.exp()]),
        ("tanh(t)", |t| {
            let s = 1.0 - t.tanh().powi(2);
            [t.tanh(), s, -2.0 * t.tanh() * s]
        }),
        ("exp(-t^2)", |t| {
            let g = (-t * t).exp();
            [g, -2.0 * t * g, (4.0 * t * t - 2.0) * g]
        }),
        ("ln(t) + log(t)", |t| [2.0 * t.ln(), 2.0 / t, -2.0 / (t * t)]),
        ("log10(t)", |t| [t.log10(), 1.0 / (t * 10f64.ln()), -1.0 / (t * t * 10f64.ln())]),
        ("sqrt(1 + t)", |t| [(1.0 + t).sqrt(), 0.5 / (1.0 + t).sqrt(), -0.25 / (1.0 + t).powf(1.5)]),
        ("abs(t - 2)", |t| [2.0 - t, -1.0, 0.0]),
        ("min(t, 2) + max(t^2, -1)", |t| [t + t * t, 1.0 + 2.0 * t, 2.0]),
        ("pow(t, 3) - t**2 / 2", |t| [t.powi(3) - t * t / 2.0, 3.0 * t * t - t, 6.0 * t - 1.0]),
        ("hypot(3*t, 4*t)", |t| [5.0 * t, 5.0, 0.0]),
        ("2^t", |t| {
            let l = 2f64.ln();
            [2f64.powf(t), l * 2f64.powf(t), l * l * 2f64.powf(t)]
        }),
        ("t^t", |t| {
            let (f, l) = (t.powf(t), t.ln() + 1.0);
            [f, f * l, f * (l * l + 1.0 / t)]
        }),
        ("1/(1 + t) - e*pi", |t| {
            [1.0 / (1.0 + t) - std::f64::consts::E * PI, -1.0 / (1.0 + t).powi(2), 2.0 / (1.0 + t).powi(3)]
        }),
    ];
    for (text, closed) in cases {
        let e = expr(text);
        for t in grid(0.1, 0.9, 33) {
            let (got, want) = (e.eval(t), closed(t));
            for k in 0..3 {
                let tol = 1e-13 * want[k].abs().max(1.0);
                assert!((got[k] - want[k]).abs() <= tol, "{text} at t = {t}: {got:?}, closed form {want:?}");
            }
        }
        check_derivatives(text, &|t| e.eval(t), &grid(0.1, 0.9, 17), 1e-6);
    }
}

#[test]
fn third_derivatives_of_every_function_match_closed_forms_and_differences() {
    // (text, closed form f''') on t in (0.1, 0.9): every function and operator at third order
    type Closed = fn(f64) -> f64;
    let cases: [(&str, Closed); 26] = [
        ("0.35 - 0.16*sin(150*t)", |t| 0.16 * 150f64.powi(3) * (150.0 * t).cos()),
        ("cos(2*t)", |t| 8.0 * (2.0 * t).sin()),
        ("tan(t)", |t| {
            let g = t.tan();
            2.0 * (1.0 + g * g) * (1.0 + 3.0 * g * g)
        }),
        ("asin(t)", |t| (1.0 + 2.0 * t * t) / (1.0 - t * t).powf(2.5)),
        ("acos(t)", |t| -(1.0 + 2.0 * t * t) / (1.0 - t * t).powf(2.5)),
        ("atan(t)", |t| (6.0 * t * t - 2.0) / (1.0 + t * t).powi(3)),
        ("atan2(t, 1 - t)", |t| {
            // f' = 1 / r2 with r2 = 2 t^2 - 2 t + 1, r2' = 4 t - 2, r2'' = 4
            let r2 = t * t + (1.0 - t) * (1.0 - t);
            -4.0 / (r2 * r2) + 2.0 * (4.0 * t - 2.0).powi(2) / r2.powi(3)
        }),
        ("sinh(t) + cosh(t)", |t| t.exp()),
        ("cosh(2*t) - sinh(t)", |t| 8.0 * (2.0 * t).sinh() - t.cosh()),
        ("tanh(t)", |t| {
            let g = t.tanh();
            -2.0 * (1.0 - g * g) * (1.0 - 3.0 * g * g)
        }),
        ("exp(-t^2)", |t| (12.0 * t - 8.0 * t.powi(3)) * (-t * t).exp()),
        ("ln(t) + log(t)", |t| 4.0 / t.powi(3)),
        ("log10(t)", |t| 2.0 / (t.powi(3) * 10f64.ln())),
        ("sqrt(1 + t)", |t| 0.375 / (1.0 + t).powf(2.5)),
        ("abs(t - 2) + abs(t)^3", |_| 6.0),
        ("min(t^3, 2) + max(t^2, -1)", |_| 6.0),
        ("pow(t, 4) - t**2 / 2 + t^-1 + t^2.5", |t| 24.0 * t - 6.0 / t.powi(4) + 2.5 * 1.5 * 0.5 / t.sqrt()),
        ("hypot(t, 1)", |t| -3.0 * t / (1.0 + t * t).powf(2.5)),
        ("2^t", |t| 2f64.ln().powi(3) * 2f64.powf(t)),
        ("t^t", |t| {
            // f' = f l, f'' = f (l^2 + 1/t), f''' = f (l^3 + 3 l / t - 1 / t^2), l = ln t + 1
            let (f, l) = (t.powf(t), t.ln() + 1.0);
            f * (l.powi(3) + 3.0 * l / t - 1.0 / (t * t))
        }),
        ("1/(1 + t) - e*pi", |t| -6.0 / (1.0 + t).powi(4)),
        ("1/(2 + sin(t))", |t| {
            // u = 2 + sin t: (1/u)''' = -6 u'^3 / u^4 + 6 u' u'' / u^3 - u''' / u^2
            let (u, u1, u2, u3) = (2.0 + t.sin(), t.cos(), -t.sin(), -t.cos());
            -6.0 * u1.powi(3) / u.powi(4) + 6.0 * u1 * u2 / u.powi(3) - u3 / (u * u)
        }),
        ("sin(t)*exp(t)", |t| 2.0 * (t.cos() - t.sin()) * t.exp()),
        ("-exp(2*t)", |t| -8.0 * (2.0 * t).exp()),
        // identities whose terms cancel: every slot of both arguments takes part
        ("atan2(3*sin(t), 3*cos(t))", |_| 0.0),
        ("hypot(2*sin(t), 2*cos(t))", |_| 0.0),
    ];
    for (text, closed) in cases {
        let e = expr(text);
        let times = grid(0.1, 0.9, 33);
        // rounding in the differences of f'', eps |f''| / h, and their truncation,
        // h^2 |f^(5)| / 6, are both below 1e-8 of the largest |f'''| here
        let scale = times.iter().fold(0.1f64, |m, &t| m.max(closed(t).abs()));
        for &t in &times {
            let got = e.eval3(t);
            let want = closed(t);
            assert!(
                (got[3] - want).abs() <= 1e-13 * want.abs().max(1.0),
                "{text} at t = {t}: f''' = {}, closed form {want}",
                got[3]
            );
            // the same rules one order further: the first three are eval's, bit for bit
            assert_eq!(got[..3], e.eval(t), "{text} at t = {t}");
            let h = 1e-6;
            let fd = (e.eval3(t + h)[2] - e.eval3(t - h)[2]) / (2.0 * h);
            assert!((fd - got[3]).abs() <= 1e-7 * scale, "{text}: f'''({t}) = {}, differences {fd}", got[3]);
        }
    }
}

#[test]
fn third_order_powers_stay_finite_where_their_derivatives_are() {
    // a factor n (n - 1) (n - 2) that vanishes must not meet a^(n - 3) = inf at a = 0
    assert_eq!(expr("t^2").eval3(0.0), [0.0, 0.0, 2.0, 0.0]);
    assert_eq!(expr("t^1 + 1").eval3(0.0), [1.0, 1.0, 0.0, 0.0]);
    assert_eq!(expr("t^3").eval3(0.0), [0.0, 0.0, 0.0, 6.0]);
    assert_eq!(expr("(t - 1)^2 * 3").eval3(1.0), [0.0, 0.0, 6.0, 0.0]);
    // where only the third derivative is infinite, eval3 says so and eval does not
    let e = expr("abs(t)^2.5");
    assert!(e.eval(0.0).iter().all(|v| v.is_finite()));
    assert_eq!(e.diagnose(0.0), None);
    assert!(!e.eval3(0.0)[3].is_finite());
    let why = e.diagnose3(0.0).unwrap();
    assert!(
        why.starts_with(
            "the power 0^2.5 at column 7 of 'abs(t)^2.5': its derivatives are not finite (0, 0, 0, "
        ),
        "{why}"
    );
}

#[test]
fn precedence_and_associativity_are_the_usual_ones() {
    let at = |text: &str, t: f64| expr(text).eval(t)[0];
    assert_eq!(at("-t^2", 3.0), -9.0);
    assert_eq!(at("2^3^2", 0.0), 512.0);
    assert_eq!(at("2**3**2", 0.0), 512.0);
    assert_eq!(at("2^-1", 0.0), 0.5);
    assert_eq!(at("1 - 2 - 3", 0.0), -4.0);
    assert_eq!(at("12 / 3 / 2", 0.0), 2.0);
    assert_eq!(at("2*t^2 + 1", 3.0), 19.0);
    assert_eq!(at("--t", 2.0), 2.0);
    assert_eq!(at("+t", 2.0), 2.0);
    assert_eq!(at(".5 + 5. + 1e-3 + 2E2", 0.0), 205.501);
    assert_eq!(at("(t - 1) * (t + 1)", 3.0), 8.0);
    // a variable of another name, for polar cam profiles r(phi)
    let r = Expression::parse("0.05 + 0.01*(1 - cos(phi))", "phi").unwrap();
    let [f, fd, fdd] = r.eval(PI);
    assert!((f - 0.07).abs() <= 1e-16 && fd.abs() <= 1e-17 && (fdd + 0.01).abs() <= 1e-17);
    assert_eq!(r.variable(), "phi");
    assert_eq!(serde_json::to_string(&r).unwrap(), "\"0.05 + 0.01*(1 - cos(phi))\"");
}

#[test]
fn parse_errors_say_what_and_where() {
    let cases = [
        ("0.35 - 0.16*sn(150*t)", "unknown name 'sn' at column 13; did you mean 'sin'?"),
        ("0.35 - 0.16*x", "unknown name 'x' at column 13; the variable is 't'"),
        ("sin(t + 1", "expected ')' (for the '(' at column 4), found the end at column 10"),
        ("(t + 1", "expected ')' (for the '(' at column 1), found the end at column 7"),
        ("t / (2 - 2)", "division by zero at column 3"),
        ("t / 0", "division by zero at column 3"),
        ("atan2(t)", "atan2 takes 2 arguments, got 1 at column 1"),
        ("sin(t, 1)", "sin takes 1 argument, got 2 at column 1"),
        ("2t", "malformed number '2t' at column 1; numbers look like 2, 0.5, .5 or 1e-3; multiply with '*'"),
        ("2e", "malformed number '2e' at column 1; numbers look like 2, 0.5, .5 or 1e-3; multiply with '*'"),
        ("t t", "expected an operator (+ - * / ^) before 't' at column 3; write multiplication with '*', e.g. 2*t"),
        ("t +", "unexpected end of the expression at column 4; expected a number, a name or '('"),
        ("", "unexpected end of the expression at column 1; expected a number, a name or '('"),
        ("t)", "unmatched ')' at column 2"),
        ("sin t", "function 'sin' needs its arguments in parentheses at column 1; write sin(...)"),
        ("t(2)", "'t' is not a function at column 1; multiply with '*'"),
        ("t # 2", "unexpected character '#' at column 3; expressions use numbers, names, + - * / ^ ** ( ) and ','"),
        ("sqrt(-1) + t", "sqrt(-1) is not a finite real number at column 1"),
        ("ln(0)*t", "ln(0) is not a finite real number at column 1"),
        ("1e999 * t", "number '1e999' is too large at column 1"),
        ("t *** 2", "unexpected '*' at column 5; expected a number, a name or '('"),
    ];
    for (text, want) in cases {
        assert_eq!(parse_err(text).to_string(), want, "{text:?}");
    }
    assert_eq!(parse_err("0.35 - 0.16*sn(150*t)").column, 13);
}

#[test]
fn hostile_text_is_refused_without_overflowing_the_stack() {
    let deep = "(".repeat(100_000) + "t" + &")".repeat(100_000);
    let e = parse_err(&deep);
    assert_eq!(e.column, linkwork::expr::MAX_LEN + 1, "{e}");
    let nested = "(".repeat(65) + "t" + &")".repeat(65);
    assert_eq!(parse_err(&nested).to_string(), "expression nested deeper than 64 levels at column 65");
    let signs = "-".repeat(200) + "t";
    assert!(parse_err(&signs).message.contains("nested deeper"));
    let powers = "t^".repeat(100) + "t";
    assert!(parse_err(&powers).message.contains("nested deeper"));
    // the longest accepted text evaluates in the fixed stack
    let long = (0..800).map(|_| "t").collect::<Vec<_>>().join("+");
    assert_eq!(expr(&long).eval(1.0), [800.0, 800.0, 0.0]);
    let balanced = "t*(".repeat(63) + "t" + &")".repeat(63);
    assert_eq!(expr(&balanced).eval(1.0)[1], 64.0);
    let name = Expression::parse("t", "sin").unwrap_err();
    assert_eq!(name.to_string(), "variable name 'sin' is taken by a function or constant");
}

#[test]
fn run_time_domain_errors_are_not_finite_and_diagnosed() {
    let e = expr("1/(t - 1)");
    assert!(!e.eval(1.0)[0].is_finite());
    let why = e.diagnose(1.0).unwrap();
    assert!(why.starts_with("division by zero at column 2 of '1/(t - 1)'"), "{why}");
    let e = expr("sqrt(t - 1)");
    assert!(e.eval(0.5)[0].is_nan());
    let why = e.diagnose(0.5).unwrap();
    assert!(why.starts_with("sqrt(-0.5) at column 1"), "{why}");
    assert_eq!(e.diagnose(2.0), None);
}

// --- external functions --------------------------------------------------------------------

#[test]
fn external_laws_are_called_once_per_time_and_report_failures() {
    let calls = Arc::new(AtomicUsize::new(0));
    let counter = Arc::clone(&calls);
    let func = Arc::new(move |t: f64| {
        counter.fetch_add(1, Ordering::Relaxed);
        if t > 0.5 {
            Err("ValueError: too late".to_string())
        } else {
            Ok([0.1 * t, 0.1, 0.0])
        }
    });
    let mut desc = four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0);
    *desc.drivers[0].law_mut() = MotionLaw::Python(ExternalLaw::new("slow", func));
    let model = Model::new(desc.clone()).unwrap();
    let times = grid(0.0, 1.0, 11);
    let mut data = Data::new(&model);
    let mut out = SweepOutput::new(&model, &times);
    let err = sweep(&model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap_err();
    assert_eq!(out.n_done, 6);
    assert_eq!(
        err.to_string(),
        "non-finite value at step 6 (t = 0.6) in the residual of driver 'crank_angle': python law 'slow' \
         failed at t = 0.6: ValueError: too late"
    );
    // one call per step, however many Newton iterations, velocity and acceleration use it
    assert_eq!(calls.load(Ordering::Relaxed), 7);

    // a description read from text has no function: compiling says so
    let text = desc.to_json();
    assert!(text.contains(r#""type": "python""#) && text.contains(r#""name": "slow""#));
    let e = Model::from_json(&text, Default::default()).unwrap_err().to_string();
    assert!(e.starts_with("driver 'crank_angle': python law 'slow' has no function"), "{e}");
}

// --- through the engine --------------------------------------------------------------------

const BAR: FourBar = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };

/// Sweeps the four-bar with `law` on the crank over `times`; checks every step against
/// the closed form with the law's own (f, f', f'').
fn four_bar_follows(law: MotionLaw, times: &[f64]) {
    let mut desc: Description = four_bar(&BAR, 0.0, 5.0);
    *desc.drivers[0].law_mut() = law.clone();
    let model = Model::new(desc).unwrap();
    let mut data = Data::new(&model);
    let mut out = SweepOutput::new(&model, times);
    sweep(&model, &mut data, times, &mut out, 0, &mut |_| true).unwrap();
    let law = prepared(law);
    let n = model.n_coords;
    for (k, &t) in times.iter().enumerate() {
        let [th2, w2, a2] = law.eval(t);
        let (th, w, a) = four_bar_closed(&BAR, th2, w2, a2);
        for (b, body) in [(1, "coupler"), (2, "rocker")] {
            let j = 3 * model.body_index(body).unwrap() + 2;
            let dth = (out.q[k * n + j] - th[b - 1] + PI).rem_euclid(2.0 * PI) - PI;
            assert!(dth.abs() <= 1e-10, "{body} angle at t = {t}");
            assert!(
                (out.qd[k * n + j] - w[b - 1]).abs() <= 1e-10 * w2.abs().max(1.0),
                "{body} rate at t = {t}"
            );
            assert!(
                (out.qdd[k * n + j] - a[b - 1]).abs() <= 1e-10 * (a2.abs() + w2 * w2).max(1.0),
                "{body} acceleration at t = {t}"
            );
        }
    }
}

#[test]
fn the_four_bar_follows_every_new_law() {
    let times = grid(0.0, 2.0, 801);
    four_bar_follows(from_json(r#"{"type": "expression", "text": "0.3 + 2*t + 0.4*sin(3*t)"}"#), &times);
    let cam = r#"{"type": "cam", "start": 0.2, "segments": [
        {"type": "rise", "duration": 0.6, "lift": 1.5, "profile": "modified_trapezoid"},
        {"type": "dwell", "duration": 0.4},
        {"type": "fall", "duration": 0.7, "lift": 1.5, "profile": "polynomial_4567"},
        {"type": "dwell", "duration": 0.3}]}"#;
    four_bar_follows(from_json(cam), &times);
    four_bar_follows(
        from_json(&format!(r#"{{"type": "periodic", "period": 2.0, "law": {cam}}}"#)),
        &grid(0.0, 5.0, 1001),
    );
    four_bar_follows(
        from_json(
            r#"{"type": "rise", "start": 0.5, "lift": 2.0, "t0": 0.2, "duration": 1.5, "profile": "cycloidal"}"#,
        ),
        &times,
    );
    let seq = r#"{"type": "sequence", "breakpoints": [1.0], "laws": [
        {"type": "polynomial", "coefficients": [0, 0, 1.5]},
        {"type": "linear", "value": -1.5, "rate": 3.0}]}"#;
    four_bar_follows(from_json(seq), &times);
}

#[test]
fn non_finite_laws_stop_the_solve_naming_the_driver_and_step() {
    let run = |text: &str, times: &[f64]| -> (SolveError, usize) {
        let mut desc = four_bar(&BAR, 0.0, 5.0);
        *desc.drivers[0].law_mut() = MotionLaw::Expression(ExpressionLaw::new(text).unwrap());
        let model = Model::new(desc).unwrap();
        let mut data = Data::new(&model);
        let mut out = SweepOutput::new(&model, times);
        let e = sweep(&model, &mut data, times, &mut out, 0, &mut |_| true).unwrap_err();
        (e, out.n_done)
    };
    let times = grid(0.0, 2.0, 9);
    // the value: caught by the residual
    let (e, done) = run("0.3 + 0.1/(t - 1)", &times);
    assert_eq!(done, 4);
    assert!(matches!(e, SolveError::NonFinite { step: 4, .. }), "{e:?}");
    assert!(
        e.to_string().starts_with(
            "non-finite value at step 4 (t = 1) in the residual of driver 'crank_angle': division by zero at \
             column 10 of '0.3 + 0.1/(t - 1)'"
        ),
        "{e}"
    );
    // a finite value with an infinite rate: caught by nu before the solve
    let (e, done) = run("0.3 + sqrt(t)", &times);
    assert_eq!(done, 0);
    assert!(
        e.to_string()
            .starts_with("non-finite value at step 0 (t = 0) in nu of driver 'crank_angle': sqrt(0)"),
        "{e}"
    );
    // finite value and rate, infinite acceleration: caught by gamma
    let (e, done) = run("0.3 + t^1.5", &times);
    assert_eq!(done, 0);
    assert!(
        e.to_string()
            .starts_with("non-finite value at step 0 (t = 0) in gamma of driver 'crank_angle': the power"),
        "{e}"
    );
}

#[test]
fn evaluating_any_law_allocates_nothing() {
    let laws = [
        from_json(
            r#"{"type": "expression", "text": "0.35 - 0.16*sin(150*t) + hypot(t, 2)^1.5 / (1 + atan2(t, 3))"}"#,
        ),
        cam_program(Profile::ModifiedSine),
        MotionLaw::Periodic(Periodic::new(1.0, 0.5, cam_program(Profile::Polynomial345)).unwrap()),
        from_json(
            r#"{"type": "sequence", "breakpoints": [1.0, 2.0], "laws": [
                {"type": "constant", "value": 0}, {"type": "linear", "value": -1, "rate": 1},
                {"type": "expression", "text": "1 + (t - 2)^2"}]}"#,
        ),
        MotionLaw::Python(ExternalLaw::new("f", Arc::new(|t: f64| Ok([t, 1.0, 0.0])))),
    ];
    for law in &laws {
        let before = allocations();
        let mut sum = 0.0;
        for k in 0..10_000 {
            sum += law.eval(k as f64 * 3e-4)[2];
        }
        assert!(sum.is_finite());
        assert_eq!(allocations() - before, 0, "{law:?}");
    }
}

#[test]
fn every_new_law_round_trips_through_json() {
    let texts = [
        r#"{"type":"expression","text":"0.35 - 0.16*sin(150*t)"}"#,
        r#"{"type":"rise","start":0.0,"lift":1.0,"t0":0.0,"duration":1.0,"profile":"modified_trapezoid"}"#,
        r#"{"type":"cam","start":0.0,"t0":0.0,"segments":[{"type":"dwell","duration":0.5},{"type":"rise","duration":1.0,"lift":2.0,"profile":"polynomial_345"}]}"#,
        r#"{"type":"sequence","breakpoints":[1.0],"laws":[{"type":"constant","value":1.0},{"type":"linear","value":0.0,"rate":1.0}]}"#,
        r#"{"type":"periodic","period":2.0,"t0":0.0,"law":{"type":"rise","start":0.0,"lift":1.0,"t0":0.0,"duration":1.0,"profile":"harmonic"}}"#,
        r#"{"type":"python","name":"f"}"#,
    ];
    for text in texts {
        let law: MotionLaw = serde_json::from_str(text).unwrap();
        assert_eq!(serde_json::to_string(&law).unwrap(), text);
    }
    let unknown = serde_json::from_str::<MotionLaw>(r#"{"type":"expression","text":"t","variable":"x"}"#);
    assert!(unknown.unwrap_err().to_string().contains("unknown field `variable`"));
    let profile = serde_json::from_str::<MotionLaw>(
        r#"{"type":"rise","lift":1.0,"duration":1.0,"profile":"trapezoid"}"#,
    );
    assert!(profile.unwrap_err().to_string().contains("unknown variant `trapezoid`"));
}

#[test]
fn an_external_law_returning_nan_is_reported_as_such() {
    // a failure left over from an evaluation outside any solve must not be reported later
    let failing = MotionLaw::Python(ExternalLaw::new("f", Arc::new(|_| Err("stale".to_string()))));
    assert!(failing.eval(0.3)[0].is_nan());
    let func = Arc::new(|t: f64| Ok(if t > 0.5 { [f64::NAN; 3] } else { [t, 1.0, 0.0] }));
    let mut desc = four_bar(&BAR, 0.0, 5.0);
    *desc.drivers[0].law_mut() = MotionLaw::Python(ExternalLaw::new("f", func));
    let model = Model::new(desc).unwrap();
    let times = grid(0.0, 1.0, 11);
    let mut data = Data::new(&model);
    let mut out = SweepOutput::new(&model, &times);
    let err = sweep(&model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap_err();
    assert_eq!(
        err.to_string(),
        "non-finite value at step 6 (t = 0.6) in the residual of driver 'crank_angle': python law 'f' \
         returned [NaN, NaN, NaN] at t = 0.6"
    );
}
