//! The alpha test and the solve's distinctness against closed forms: on x^2 - c the
//! certificate's beta, gamma bound and alpha are known exactly, so a point just outside
//! the published bound alpha0 = (13 - 3 sqrt 17) / 4 must be refused and one a margin
//! inside accepted. These properties are checked by cargo only (the Python suite sees the
//! certificate through synthesis results, never at a chosen point).

use linkwork_homotopy::{solve, Affine, Options, Polynomial, System, Term, ALPHA0, C64};

fn c(re: f64) -> C64 {
    C64::new(re, 0.0)
}

fn poly(terms: &[(f64, &[u32])]) -> Polynomial {
    Polynomial::new(terms.iter().map(|(k, e)| Term::new(c(*k), e)).collect())
}

/// f = x^2 - k.
fn square_minus(k: f64) -> Affine {
    Affine::new(System::new(1, 0, vec![poly(&[(1.0, &[2]), (-k, &[0])])]).unwrap())
}

/// (beta, gamma bound, alpha) of x^2 - k at real x, by hand: beta = |f / f'|; the
/// Shub-Smale bound gamma <= mu D^(3/2) / (2 |(1, x)|) with D = 2, the Bombieri-Weyl norm
/// |f| = sqrt(1 + k^2) and mu = max(1, |f| |f'^-1| sqrt(D) |(1, x)|^(D - 1)).
fn closed_form(k: f64, x: f64) -> (f64, f64, f64) {
    let x1 = (1.0 + x * x).sqrt();
    let beta = (x * x - k).abs() / (2.0 * x.abs());
    let mu = ((1.0 + k * k).sqrt() * 2f64.sqrt() * x1 / (2.0 * x.abs())).max(1.0);
    let gamma = mu * 2f64.powf(1.5) / (2.0 * x1);
    (beta, gamma, beta * gamma)
}

/// The point of x^2 - k between sqrt(k) / 4 and sqrt(k) whose closed-form alpha is
/// `target` (alpha falls as x rises there, so bisection).
fn point_with_alpha(k: f64, target: f64) -> f64 {
    let (mut lo, mut hi) = (k.sqrt() / 4.0, k.sqrt());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if closed_form(k, mid).2 > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

#[test]
fn alpha0_is_the_published_constant() {
    // (13 - 3 sqrt 17) / 4 = 4 / (13 + 3 sqrt 17), the second free of cancellation
    let published = 4.0 / (13.0 + 3.0 * 17f64.sqrt());
    assert!((ALPHA0 - published).abs() <= 2.0 * f64::EPSILON * published, "{ALPHA0} vs {published}");
}

#[test]
fn alpha_test_refuses_a_point_near_a_root_whose_alpha_exceeds_alpha0() {
    // x^2 - 1 at points near its root 1 but not at it: beta, gamma and alpha as the closed
    // form; above alpha0 the point is refused however close it looks (a bound ten times
    // looser would accept every one of these)
    let f = square_minus(1.0);
    for factor in [1.05, 1.5, 2.0, 5.0, 8.5] {
        let x = point_with_alpha(1.0, factor * ALPHA0);
        assert!(x > 0.25 && x < 1.0, "x = {x} is meant to be near the root 1");
        let (beta, gamma, alpha) = closed_form(1.0, x);
        let t = f.alpha(&[c(x)]);
        // beta is enlarged by the rounding bounds, relative ~1e-15 here
        assert!(close(t.beta, beta, 1e-12) && close(t.gamma, gamma, 1e-12), "{t:?} vs {beta} {gamma}");
        assert!(close(t.alpha, alpha, 1e-12), "{t:?} vs alpha {alpha}");
        assert!(!t.certified, "x = {x}: alpha {} = {factor} alpha0 certified", t.alpha);
    }
}

#[test]
fn alpha_test_accepts_a_point_a_margin_inside_alpha0_and_its_root_lies_within_two_beta() {
    let f = square_minus(1.0);
    for factor in [0.1, 0.5, 0.8] {
        let x = point_with_alpha(1.0, factor * ALPHA0);
        let t = f.alpha(&[c(x)]);
        assert!(close(t.alpha, closed_form(1.0, x).2, 1e-12), "{t:?}");
        assert!(t.certified, "x = {x}: alpha {} = {factor} alpha0 refused", t.alpha);
        // the promise a certificate makes: the root 1 within 2 beta of x
        assert!((x - 1.0).abs() <= 2.0 * t.beta, "{x} {t:?}");
    }
}

#[test]
fn alpha_test_refuses_a_point_near_a_near_singular_root_that_it_accepts_near_a_regular_one() {
    // x^2 - eps^2: two roots 2 eps apart, nearly a double root; gamma ~ 1 / eps. A point
    // 0.5 eps from the root eps has alpha above alpha0 and is refused, while the same
    // distance from the regular root of x^2 - 1 certifies easily.
    let eps = 1e-6;
    let f = square_minus(eps * eps);
    let x = eps * 1.5;
    let (beta, gamma, alpha) = closed_form(eps * eps, x);
    assert!(alpha > 1.05 * ALPHA0 && alpha < 9.0 * 0.9 * ALPHA0, "alpha {alpha}: choose another point");
    let t = f.alpha(&[c(x)]);
    assert!(close(t.beta, beta, 1e-9) && close(t.gamma, gamma, 1e-9), "{t:?} vs {beta} {gamma}");
    assert!(!t.certified, "{t:?}");

    let regular = square_minus(1.0).alpha(&[c(1.0 + 0.5 * eps)]);
    assert!(regular.certified && regular.alpha < 1e-5, "{regular:?}");
}

#[test]
fn solve_keeps_two_roots_two_thousandths_apart_as_two_distinct_roots() {
    // (x - 1)(x - 1.002): the roots are well inside each other's reach of a loose
    // merging tolerance, yet certified with radii far below their separation
    let s = System::new(1, 0, vec![poly(&[(1.0, &[2]), (-2.002, &[1]), (1.002, &[0])])]).unwrap();
    let sol = solve(&s, None, &Options::default()).unwrap();
    assert_eq!(sol.roots.len(), 2, "{sol:?}");
    assert!(sol.distinct, "{sol:?}");
    let mut xs: Vec<f64> = sol.roots.iter().map(|r| r.x[0].re).collect();
    xs.sort_by(f64::total_cmp);
    for (got, want) in xs.iter().zip([1.0, 1.002]) {
        assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    }
    for r in &sol.roots {
        assert!(r.certified && r.real && r.radius < 1e-3, "{r:?}");
    }
}

#[test]
fn certify_points_polishes_candidates_near_roots_and_drops_those_newton_cannot_bring_in() {
    // x^2 - 2: candidates a few percent off the roots are polished to +-sqrt 2 and
    // certified; one at the critical point (Df = 0) and one so far out that twelve Newton
    // steps (each halving it) cannot reach a root are counted as failed
    let s = System::new(1, 0, vec![poly(&[(1.0, &[2]), (-2.0, &[0])])]).unwrap();
    let candidates = vec![vec![c(1.4)], vec![c(-1.5)], vec![c(0.0)], vec![c(1e6)]];
    let sol = linkwork_homotopy::certify_points(&s, candidates);
    assert_eq!(sol.failed, 2, "{sol:?}");
    assert_eq!(sol.paths, 4, "every candidate counts as a path: {sol:?}");
    let mut xs: Vec<f64> = sol.roots.iter().map(|r| r.x[0].re).collect();
    xs.sort_by(f64::total_cmp);
    assert_eq!(xs.len(), 2, "{sol:?}");
    for (got, want) in xs.iter().zip([-2f64.sqrt(), 2f64.sqrt()]) {
        assert!((got - want).abs() <= 4.0 * f64::EPSILON, "{got} vs {want}");
    }
    assert!(sol.distinct && sol.roots.iter().all(|r| r.certified && r.real), "{sol:?}");
}

/// f = (x - c)^3 - 2 (x - c) + 2: Newton from x = c cycles between c and c + 1 forever.
fn newton_two_cycle(c: f64) -> Affine {
    // expanded: x^3 - 3c x^2 + (3c^2 - 2) x + (-c^3 + 2c + 2)
    let p =
        poly(&[(1.0, &[3]), (-3.0 * c, &[2]), (3.0 * c * c - 2.0, &[1]), (-c * c * c + 2.0 * c + 2.0, &[0])]);
    Affine::new(System::new(1, 0, vec![p]).unwrap())
}

#[test]
fn newton_runs_until_the_step_reaches_the_rounding_level_not_after_one_step() {
    // x^2 - 4 from 3: the first step lands at 13/6; only the rounding-level stop gives 2
    let f = square_minus(4.0);
    let mut x = vec![c(3.0)];
    assert!(f.newton(&mut x, 12));
    assert!((x[0] - c(2.0)).norm() <= 2.0 * f64::EPSILON, "{:?}", x[0]);
}

#[test]
fn newton_reports_failure_when_its_steps_stop_shrinking_far_from_a_root() {
    // a two-cycle of unit steps: the step stops shrinking at 1, far above the stall bound
    // 1e-6 (1 + |x|), so this is no root however many iterations are allowed
    let f = newton_two_cycle(10.0);
    let mut x = vec![c(10.0)];
    assert!(!f.newton(&mut x, 12), "reported a root at {:?}", x[0]);
}

#[test]
fn residual_is_the_value_and_the_normwise_backward_error_in_closed_form() {
    // x^2 - k at x: |f| = |x^2 - k|, backward error |f| / ((1 + |k|) max(1, |x|)^2)
    for (k, x) in [(4.0, 3.0), (9.0, 0.5), (0.25, -7.0), (1e6, 1001.0)] {
        let (abs, rel) = square_minus(k).residual(&[c(x)]);
        let f = (x * x - k).abs();
        let expected = f / ((1.0 + k) * f64::max(1.0, x.abs()).powi(2));
        assert!(close(abs, f, 4.0 * f64::EPSILON), "k = {k}, x = {x}: |f| {abs} vs {f}");
        assert!(
            close(rel, expected, 8.0 * f64::EPSILON),
            "k = {k}, x = {x}: backward error {rel} vs {expected}"
        );
    }
}

#[test]
fn alpha_refined_returns_the_nearest_double_to_the_root_and_the_rounding_as_beta() {
    // x^2 - 2 from a point 1e-9 off: double-double Newton lands on sqrt 2 to ~1e-32, so the
    // returned point is the double nearest sqrt 2 and beta is half its distance to the root,
    // the rounding the refinement adds (everything else in beta is ~1e-30)
    let f = square_minus(2.0);
    let (test, x) = f.alpha_refined(&[c(2f64.sqrt() + 1e-9)]);
    let r = 2f64.sqrt();
    assert_eq!(x[0], c(r), "refined to {:?}", x[0]);
    // sqrt 2 - r = (2 - r^2) / (sqrt 2 + r); fma gives 2 - r^2 exactly (it is tiny)
    let offset = (f64::mul_add(-r, r, 2.0) / (2.0 * r)).abs();
    assert!(offset > 0.0);
    assert!(close(test.beta, offset / 2.0, 1e-6), "beta {} vs half the rounding {}", test.beta, offset / 2.0);
    assert!(test.certified, "{test:?}");
}

#[test]
fn alpha_refined_refuses_a_point_where_the_jacobian_is_singular() {
    // x^2 - 2 at x = 0: f' = 0, no Newton step exists
    let (test, x) = square_minus(2.0).alpha_refined(&[c(0.0)]);
    assert!(!test.certified && test.alpha.is_infinite(), "{test:?}");
    assert_eq!(x, vec![c(0.0)]);
}
