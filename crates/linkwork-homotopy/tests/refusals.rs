//! Systems the solver cannot track are refused by name (SystemError), never a panic:
//! parameters that are not finite, or finite ones whose products overflow a coefficient.

use linkwork_homotopy::{solve, solve_parameter, Options, Polynomial, System, SystemError, Term, C64};

fn c(re: f64) -> C64 {
    C64::new(re, 0.0)
}

/// x^2 - p0 x + p1 = 0, one unknown, two parameters.
fn family() -> System {
    System::new(
        1,
        2,
        vec![Polynomial::new(vec![
            Term::new(c(1.0), &[2, 0, 0]),
            Term::new(c(-1.0), &[1, 1, 0]),
            Term::new(c(1.0), &[0, 0, 1]),
        ])],
    )
    .unwrap()
}

/// The family's two roots at p0 = (3, 2): 1 and 2.
fn starts() -> (Vec<C64>, Vec<Vec<C64>>) {
    (vec![c(3.0), c(2.0)], vec![vec![c(1.0)], vec![c(2.0)]])
}

#[test]
fn parameters_that_are_not_finite_are_refused() {
    let (p0, roots) = starts();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let p1 = vec![c(1.0), c(bad)];
        let got = solve_parameter(&family(), &p0, &roots, &p1, &Options::default());
        assert_eq!(got.unwrap_err(), SystemError::NotFiniteParameter { index: 1 });
        assert_eq!(family().specialize(&p1).unwrap_err(), SystemError::NotFiniteParameter { index: 1 });
        let p0_bad = vec![c(bad), c(2.0)];
        let got = solve_parameter(&family(), &p0_bad, &roots, &[c(3.0), c(2.0)], &Options::default());
        assert_eq!(got.unwrap_err(), SystemError::NotFiniteParameter { index: 0 });
    }
}

#[test]
fn coefficients_that_overflow_are_refused() {
    // x^2 - p0^2 x: a finite parameter of 1e200 squares to infinity
    let squared = System::new(
        1,
        1,
        vec![Polynomial::new(vec![Term::new(c(1.0), &[2, 0]), Term::new(c(-1.0), &[1, 2])])],
    )
    .unwrap();
    let p1 = vec![c(1e200)];
    assert_eq!(squared.specialize(&p1).unwrap_err(), SystemError::NotFinite { poly: 0 });
    let got = solve_parameter(&squared, &[c(2.0)], &[vec![c(4.0)]], &p1, &Options::default());
    assert_eq!(got.unwrap_err(), SystemError::NotFinite { poly: 0 });
}

#[test]
fn a_system_built_by_hand_with_a_bad_coefficient_is_refused_before_tracking() {
    // the fields are public: no constructor check stands between them and `solve`
    let mut s =
        System::new(1, 0, vec![Polynomial::new(vec![Term::new(c(1.0), &[2]), Term::new(c(-4.0), &[0])])])
            .unwrap();
    s.polys[0].terms[1].coeff = c(f64::INFINITY);
    assert_eq!(solve(&s, None, &Options::default()).unwrap_err(), SystemError::NotFinite { poly: 0 });
}

#[test]
fn a_parameter_that_zeroes_a_polynomial_is_refused_after_tracking_not_a_panic() {
    // x p0 - p1 at p = (0, 0) is the zero polynomial: no isolated root, the lifted system
    // is not square in the unknowns
    let lin = System::new(
        1,
        2,
        vec![Polynomial::new(vec![Term::new(c(1.0), &[1, 1, 0]), Term::new(c(-1.0), &[0, 0, 1])])],
    )
    .unwrap();
    let got =
        solve_parameter(&lin, &[c(2.0), c(4.0)], &[vec![c(2.0)]], &[c(0.0), c(0.0)], &Options::default());
    assert!(matches!(got, Err(SystemError::ConstantPolynomial { poly: 0 })), "{got:?}");
}
