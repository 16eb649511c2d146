//! Degenerate and hostile input to every synthesis entry point: huge and tiny scales,
//! near-coincident points and poses, repeated and nearly repeated angles, collinear and
//! cocircular points. Each call returns dyads that satisfy their own equations (checked
//! here in world units, independently of the solver) or a named `SynthesisError`, and
//! within a bounded time; never a panic.

use std::time::{Duration, Instant};

use linkwork::synthesis::alt;
use linkwork::synthesis::function::{four_bar, slider_crank};
use linkwork::synthesis::motion::{
    burmester, burmester_by_resultant, four_pose_curves, three_pose_ground, three_pose_moving,
    two_pose_ground, Pose,
};
use linkwork::synthesis::path::{timed_dyads, timed_dyads_by_resultant};
use linkwork::synthesis::{Dyad, SynthesisError};
use num_complex::Complex64 as C64;
use proptest::prelude::*;

/// Wall time one call of a five-path problem may take (debug build, shared machine).
const CALL_BUDGET: Duration = Duration::from_secs(5);

fn c(p: [f64; 2]) -> C64 {
    C64::new(p[0], p[1])
}

fn timed<T>(f: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = f();
    assert!(start.elapsed() < CALL_BUDGET, "took {:?}", start.elapsed());
    out
}

/// Spread of points: the size the residuals are judged against.
fn spread(points: &[C64]) -> f64 {
    let n = points.len() as f64;
    let centre = points.iter().map(|p| p / n).sum::<C64>();
    points.iter().map(|p| (p - centre).norm()).fold(0.0, f64::max)
}

/// Largest change of a link's length over positions, relative to the data's spread plus
/// the link: the equations a dyad must satisfy, checked in world units.
fn length_change(lengths: impl Iterator<Item = f64>, size: f64) -> f64 {
    let l: Vec<f64> = lengths.collect();
    let (lo, hi) = l.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    (hi - lo) / (size + hi)
}

/// A real certified Burmester dyad keeps its length over the poses: M_j - G with M
/// carried by the body.
fn burmester_error(poses: &[Pose], d: &Dyad) -> f64 {
    let (g, m) = (c(d.ground), c(d.moving));
    let p1 = C64::new(poses[0].x, poses[0].y);
    let pts: Vec<C64> = poses.iter().map(|p| C64::new(p.x, p.y)).collect();
    let lengths = poses
        .iter()
        .map(|p| (C64::new(p.x, p.y) + (m - p1) * C64::from_polar(1.0, p.angle - poses[0].angle) - g).norm());
    length_change(lengths, spread(&pts))
}

/// A real certified timed dyad: the crank pin A_j = G + R(phi_j)(A_1 - G) stays at one
/// distance from P_j.
fn timed_error(points: &[[f64; 2]], input: &[f64], d: &Dyad) -> f64 {
    let (g, a1) = (c(d.ground), c(d.moving));
    let pts: Vec<C64> = points.iter().map(|p| c(*p)).collect();
    let lengths = pts
        .iter()
        .zip(input)
        .map(|(p, phi)| (p - g - (a1 - g) * C64::from_polar(1.0, phi - input[0])).norm());
    length_change(lengths, spread(&pts))
}

/// Every error is one of the named kinds (the match is the test: a new kind must be
/// placed here deliberately).
fn named(e: &SynthesisError) -> bool {
    matches!(
        e,
        SynthesisError::Count { .. }
            | SynthesisError::NotFinite { .. }
            | SynthesisError::Coincident { .. }
            | SynthesisError::Collinear { .. }
            | SynthesisError::Unscalable { .. }
            | SynthesisError::Degenerate(_)
            | SynthesisError::System(_)
    ) && !e.to_string().is_empty()
}

/// Residual allowed a certified root, relative to the data: certification bounds the
/// root's distance, so what is left is rounding in the world units' transform.
const TOL: f64 = 1e-7;

#[derive(Clone, Copy, Debug)]
enum Shape {
    Generic,
    NearCoincident(f64),
    Collinear,
    NearCollinear(f64),
    Cocircular,
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        Just(Shape::Generic),
        (-14.0f64..-2.0).prop_map(|e| Shape::NearCoincident(10f64.powf(e))),
        Just(Shape::Collinear),
        (-14.0f64..-2.0).prop_map(|e| Shape::NearCollinear(10f64.powf(e))),
        Just(Shape::Cocircular),
    ]
}

/// Five unit-size points of a shape, then scaled by 10^scale and moved by `offset`
/// (in units of the scaled size).
fn points(shape: Shape, seeds: [f64; 10], scale: f64, offset: [f64; 2]) -> Vec<[f64; 2]> {
    let unit: Vec<C64> = (0..5)
        .map(|k| {
            let (u, v) = (seeds[2 * k], seeds[2 * k + 1]);
            match shape {
                Shape::Generic => C64::new(u, v),
                Shape::NearCoincident(eps) if k == 1 => {
                    C64::new(seeds[0], seeds[1]) + C64::new(eps, 0.3 * eps)
                }
                Shape::NearCoincident(_) => C64::new(u, v),
                Shape::Collinear => C64::new(u, 0.5 * u + 0.2),
                Shape::NearCollinear(eps) => C64::new(u, 0.5 * u + 0.2 + eps * v),
                Shape::Cocircular => C64::from_polar(1.0, 3.0 * u),
            }
        })
        .collect();
    let s = 10f64.powf(scale);
    unit.iter().map(|p| [(p.re + offset[0]) * s, (p.im + offset[1]) * s]).collect()
}

#[derive(Clone, Copy, Debug)]
enum Angles {
    Generic,
    Repeated,
    NearlyRepeated(f64),
}

fn angles_kind() -> impl Strategy<Value = Angles> {
    prop_oneof![
        2 => Just(Angles::Generic),
        1 => Just(Angles::Repeated),
        1 => (-14.0f64..-3.0).prop_map(|e| Angles::NearlyRepeated(10f64.powf(e))),
    ]
}

fn angles(kind: Angles, seeds: [f64; 5]) -> Vec<f64> {
    let mut a: Vec<f64> = seeds.iter().map(|s| 2.0 * s).collect();
    a[0] = 0.0;
    match kind {
        Angles::Generic => {}
        Angles::Repeated => a[3] = a[2],
        Angles::NearlyRepeated(eps) => a[3] = a[2] + eps,
    }
    a
}

fn seeds<const N: usize>() -> impl Strategy<Value = [f64; N]> {
    proptest::array::uniform(-1.0f64..1.0)
}

/// Scales from 1e-300 to 1e300, most within the range the solver accepts.
fn scale() -> impl Strategy<Value = f64> {
    prop_oneof![3 => -20.0f64..20.0, 1 => -300.0f64..300.0]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn burmester_satisfies_its_equations_or_names_the_fault(
        sh in shape(), s in seeds::<10>(), ak in angles_kind(), a in seeds::<5>(),
        e in scale(), off in seeds::<2>(), resultant in any::<bool>(),
    ) {
        let pts = points(sh, s, e, [off[0] * 10.0, off[1] * 10.0]);
        let rot = angles(ak, a);
        let poses: Vec<Pose> = pts.iter().zip(&rot).map(|(p, &angle)| Pose { x: p[0], y: p[1], angle }).collect();
        let got = timed(|| if resultant { burmester_by_resultant(&poses) } else { burmester(&poses) });
        match got {
            Ok(set) => {
                for d in set.real().filter(|d| d.certified) {
                    let err = burmester_error(&poses, d);
                    prop_assert!(err < TOL, "{err:e} {d:?}");
                }
                prop_assert!(set.dyads.iter().all(|d| d.ground.iter().chain(&d.moving).all(|v| v.is_finite())));
            }
            Err(e) => prop_assert!(named(&e), "{e}"),
        }
    }

    #[test]
    fn timed_dyads_satisfy_their_equations_or_name_the_fault(
        sh in shape(), s in seeds::<10>(), ak in angles_kind(), a in seeds::<5>(),
        e in scale(), off in seeds::<2>(), resultant in any::<bool>(),
    ) {
        let pts = points(sh, s, e, [off[0] * 10.0, off[1] * 10.0]);
        let input = angles(ak, a);
        let got = timed(|| if resultant { timed_dyads_by_resultant(&pts, &input) } else { timed_dyads(&pts, &input) });
        match got {
            Ok(set) => {
                for d in set.real().filter(|d| d.certified) {
                    let err = timed_error(&pts, &input, d);
                    prop_assert!(err < TOL, "{err:e} {d:?}");
                }
            }
            Err(e) => prop_assert!(named(&e), "{e}"),
        }
    }

    #[test]
    fn closed_forms_satisfy_their_equations_or_name_the_fault(
        sh in shape(), s in seeds::<10>(), ak in angles_kind(), a in seeds::<5>(),
        e in scale(), off in seeds::<2>(), chosen in seeds::<2>(), along in -2.0f64..2.0,
    ) {
        let pts = points(sh, s, e, [off[0] * 10.0, off[1] * 10.0]);
        let rot = angles(ak, a);
        let poses: Vec<Pose> = pts.iter().zip(&rot).map(|(p, &angle)| Pose { x: p[0], y: p[1], angle }).collect();
        let size = 10f64.powf(e);
        let pick = [chosen[0] * size + pts[0][0], chosen[1] * size + pts[0][1]];
        // the three-pose dyads keep their length over three poses, the two-pose one over two
        for (got, n) in [
            (timed(|| three_pose_ground(&poses[..3], pick)), 3),
            (timed(|| three_pose_moving(&poses[..3], pick)), 3),
            (timed(|| two_pose_ground(&poses[..2], pick, along * size)), 2),
        ] {
            match got {
                Ok(d) => {
                    let err = burmester_error(&poses[..n], &d);
                    prop_assert!(err < TOL, "{err:e} {d:?}");
                }
                Err(e) => prop_assert!(named(&e), "{e}"),
            }
        }
        match timed(|| four_pose_curves(&poses[..4], 36)) {
            Ok(dyads) => {
                for d in &dyads {
                    let err = burmester_error(&poses[..4], d);
                    prop_assert!(err < 1e-5, "{err:e} {d:?}");
                }
            }
            Err(e) => prop_assert!(named(&e), "{e}"),
        }
    }

    #[test]
    fn freudenstein_gives_finite_links_or_names_the_fault(
        ak in angles_kind(), a in seeds::<5>(), b in seeds::<5>(), e in scale(),
    ) {
        let input = angles(ak, a);
        let output: Vec<f64> = b.iter().map(|v| 2.0 * v).collect();
        let d = 10f64.powf(e);
        match timed(|| four_bar(&input[1..4], &output[1..4], d)) {
            Ok(fb) => {
                prop_assert!([fb.a, fb.b, fb.c, fb.d].iter().all(|v| v.is_finite() && *v != 0.0), "{fb:?}");
                // Freudenstein's equation itself at the three pairs, relative to its terms
                for k in 1..4 {
                    let (phi, psi) = (input[k], output[k]);
                    let lhs = fb.d / fb.a * psi.cos() - fb.d / fb.c * phi.cos()
                        + (fb.a * fb.a - fb.b * fb.b + fb.c * fb.c + fb.d * fb.d) / (2.0 * fb.a * fb.c);
                    let size = 1.0 + (fb.d / fb.a).abs() + (fb.d / fb.c).abs()
                        + (fb.a * fb.a + fb.b * fb.b + fb.c * fb.c + fb.d * fb.d) / (2.0 * (fb.a * fb.c).abs());
                    prop_assert!((lhs - (phi - psi).cos()).abs() < 1e-8 * size, "{fb:?}");
                }
            }
            Err(err) => prop_assert!(named(&err), "{err}"),
        }
        let positions: Vec<f64> = b.iter().map(|v| (2.0 + v) * d).collect();
        match timed(|| slider_crank(&input[1..4], &positions[1..4])) {
            Ok(sc) => prop_assert!([sc.a, sc.b, sc.e].iter().all(|v| v.is_finite()), "{sc:?}"),
            Err(err) => prop_assert!(named(&err), "{err}"),
        }
    }
}

/// The reported case: coordinates of 1e300 (the rms by squaring overflowed, nothing was
/// scaled, and the homotopy panicked on an infinite coefficient). Now refused by name,
/// as are tiny spreads; scales well inside the range give the same dyads as unit size.
#[test]
fn timed_dyads_at_extreme_scales_are_refused_by_name_or_scaled() {
    let unit = [[0.0, 0.0], [1.0, 0.2], [1.8, 1.0], [1.5, 2.1], [0.4, 2.4]];
    let input = [0.0, 0.4, 0.9, 1.5, 2.2];
    let at = |s: f64| unit.map(|p| [p[0] * s, p[1] * s]);
    for s in [1e300, 1e200, 1e151] {
        let e = timed_dyads(&at(s), &input).unwrap_err();
        assert!(matches!(e, SynthesisError::Unscalable { .. }), "{e}");
        assert!(e.to_string().contains("overflow"), "{e}");
    }
    for s in [1e-300, 1e-200, 1e-151] {
        let e = timed_dyads(&at(s), &input).unwrap_err();
        assert!(matches!(e, SynthesisError::Unscalable { .. }), "{e}");
        assert!(e.to_string().contains("underflow"), "{e}");
    }
    let reference = timed_dyads(&unit, &input).unwrap();
    assert!(reference.real().count() > 0);
    for s in [1e149, 1e-149, 1e100, 1e-100] {
        let set = timed_dyads(&at(s), &input).unwrap();
        assert_eq!(set.real().count(), reference.real().count(), "scale {s:e}");
        for (d, r) in set.real().zip(reference.real()) {
            for k in 0..2 {
                assert!((d.ground[k] / s - r.ground[k]).abs() < 1e-9, "scale {s:e}: {d:?} vs {r:?}");
                assert!((d.moving[k] / s - r.moving[k]).abs() < 1e-9, "scale {s:e}: {d:?} vs {r:?}");
            }
        }
    }
}

/// Nine collinear points: no four-bar passes through them (its coupler curve meets a line
/// in at most 6 points). Refused at once (it ran for minutes); so are seven on a line.
#[test]
fn alt_refuses_seven_or_more_collinear_points_at_once() {
    let line: [C64; 9] = std::array::from_fn(|k| C64::new(k as f64, 0.5 * k as f64 + 1.0));
    let start = Instant::now();
    let e = alt::four_bars(&line, alt::shipped(), alt::WALL_BUDGET).unwrap_err();
    assert!(start.elapsed() < Duration::from_millis(100), "{:?}", start.elapsed());
    assert!(matches!(&e, SynthesisError::Degenerate(m) if m.contains("1, 2, 3, 4, 5, 6, 7, 8, 9")), "{e}");
    let mut seven = line;
    seven[2] += C64::new(0.0, 0.7);
    seven[6] += C64::new(0.3, -0.4);
    let e = alt::check_points(&seven).unwrap_err();
    assert!(matches!(&e, SynthesisError::Degenerate(m) if m.contains("1, 2, 4, 5, 6, 8, 9")), "{e}");
    // six on a line may still have four-bars: not refused
    let mut six = seven;
    six[8] += C64::new(0.1, 0.9);
    assert!(alt::check_points(&six).is_ok());
    for s in [1e300, 1e-300] {
        let big = line.map(|p| p * s);
        assert!(matches!(
            alt::four_bars(&big, alt::shipped(), alt::WALL_BUDGET),
            Err(SynthesisError::Unscalable { .. })
        ));
    }
    let mut twice = six;
    twice[4] = twice[1];
    assert!(matches!(alt::check_points(&twice), Err(SynthesisError::Coincident { i: 2, j: 5, .. })));
}

/// Nine points off a line by 1e-6 of their size: the paths wander (this ran for minutes);
/// within a budget of one second the instance ends and reports its paths over budget.
#[test]
fn alt_on_nearly_collinear_points_ends_within_its_budget() {
    let mut rng = linkwork_homotopy::random::Rng::new(3);
    let points: [C64; 9] =
        std::array::from_fn(|k| C64::new(k as f64, 0.5 * k as f64 + 1.0 + 1e-6 * rng.complex_normal().re));
    let start = Instant::now();
    let out = alt::four_bars(&points, alt::shipped(), Duration::from_secs(1)).unwrap();
    assert!(start.elapsed() < Duration::from_secs(5), "{:?}", start.elapsed());
    let s = &out.solutions;
    assert_eq!(s.paths, alt::CLASSES);
    assert!(
        s.over_budget > 0 && s.over_budget <= s.failed,
        "{} over budget, {} failed",
        s.over_budget,
        s.failed
    );
}
