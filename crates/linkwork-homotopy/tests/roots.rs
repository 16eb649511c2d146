//! Root counts and accuracy on systems whose roots are known independently.

use linkwork_homotopy::{solve, solve_parameter, Groups, Options, Polynomial, System, Term, C64};

fn c(re: f64) -> C64 {
    C64::new(re, 0.0)
}

fn poly(terms: &[(f64, &[u32])]) -> Polynomial {
    Polynomial::new(terms.iter().map(|(k, e)| Term::new(c(*k), e)).collect())
}

#[test]
fn univariate_quintic_all_five_roots() {
    // (x - 1)(x + 2)(x - 3)(x^2 + 1) = x^5 - 2x^4 - 4x^3 + 4x^2 - 5x + 6
    let s = System::new(
        1,
        0,
        vec![poly(&[(1.0, &[5]), (-2.0, &[4]), (-4.0, &[3]), (4.0, &[2]), (-5.0, &[1]), (6.0, &[0])])],
    )
    .unwrap();
    let sol = solve(&s, None, &Options::default()).unwrap();
    assert_eq!(sol.roots.len(), 5, "{sol:?}");
    assert!(sol.distinct);
    let mut real: Vec<f64> = sol.real().map(|r| r.x[0].re).collect();
    real.sort_by(f64::total_cmp);
    assert_eq!(real.len(), 3);
    for (got, want) in real.iter().zip([-2.0, 1.0, 3.0]) {
        assert!((got - want).abs() < 1e-13, "{got} vs {want}");
    }
    for r in sol.roots.iter().filter(|r| !r.real) {
        assert!((r.x[0].re).abs() < 1e-13 && (r.x[0].im.abs() - 1.0).abs() < 1e-13);
        assert!(r.certified);
    }
}

#[test]
fn two_circles_meet_twice_and_twice_at_infinity() {
    // x^2 + y^2 = 4 and (x - 1)^2 + y^2 = 4: x = 1/2, y = +-sqrt(15)/2
    let s = System::new(
        2,
        0,
        vec![
            poly(&[(1.0, &[2, 0]), (1.0, &[0, 2]), (-4.0, &[0, 0])]),
            poly(&[(1.0, &[2, 0]), (-2.0, &[1, 0]), (1.0, &[0, 2]), (-3.0, &[0, 0])]),
        ],
    )
    .unwrap();
    let sol = solve(&s, None, &Options::default()).unwrap();
    assert_eq!(sol.paths, 4);
    assert_eq!(sol.roots.len(), 2, "{sol:?}");
    assert_eq!(sol.at_infinity, 2);
    for r in &sol.roots {
        assert!(r.real && r.certified);
        assert!((r.x[0].re - 0.5).abs() < 1e-14);
        assert!((r.x[1].re.abs() - 15f64.sqrt() / 2.0).abs() < 1e-14);
    }
}

/// Katsura-n: n + 1 unknowns, 2^n regular roots.
fn katsura(n: usize) -> System {
    let m = n + 1;
    let idx = |l: i64| l.unsigned_abs() as usize;
    let mut polys = Vec::new();
    for mm in 0..n as i64 {
        let mut terms: Vec<Term> = Vec::new();
        for l in -(n as i64)..=(n as i64) {
            let k = mm - l;
            if k.unsigned_abs() as usize > n {
                continue;
            }
            let mut e = vec![0u32; m];
            e[idx(l)] += 1;
            e[idx(k)] += 1;
            terms.push(Term::new(c(1.0), &e));
        }
        let mut e = vec![0u32; m];
        e[mm as usize] = 1;
        terms.push(Term::new(c(-1.0), &e));
        polys.push(Polynomial::new(terms));
    }
    let mut terms = Vec::new();
    for l in 0..m {
        let mut e = vec![0u32; m];
        e[l] = 1;
        terms.push(Term::new(c(if l == 0 { 1.0 } else { 2.0 }), &e));
    }
    terms.push(Term::new(c(-1.0), &vec![0u32; m]));
    polys.push(Polynomial::new(terms));
    // merge equal monomials
    let polys = polys
        .into_iter()
        .map(|p| {
            let mut merged: Vec<Term> = Vec::new();
            for t in p.terms {
                match merged.iter_mut().find(|u| u.powers == t.powers) {
                    Some(u) => u.coeff += t.coeff,
                    None => merged.push(t),
                }
            }
            Polynomial::new(merged)
        })
        .collect();
    System::new(m, 0, polys).unwrap()
}

#[test]
fn katsura_has_two_to_the_n_certified_roots() {
    for n in [3, 5] {
        let s = katsura(n);
        let sol = solve(&s, None, &Options::default()).unwrap();
        assert_eq!(sol.roots.len(), 1 << n, "katsura-{n}: {sol:?}");
        for r in &sol.roots {
            assert!(r.certified && r.backward_error < 1e-14, "katsura-{n}: {r:?}");
        }
        assert!(sol.distinct);
        assert_eq!(sol.failed, 0);
    }
}

/// A random bilinear system in two groups of two unknowns: 2-homogeneous Bezout number 6,
/// all six finite for random coefficients; the total-degree start (16 paths) agrees.
#[test]
fn bilinear_multihomogeneous_six_roots_both_ways() {
    let mut rng = linkwork_homotopy::random::Rng::new(7);
    let mut polys = Vec::new();
    for _ in 0..4 {
        let mut terms = Vec::new();
        for a in 0..3 {
            for b in 0..3 {
                let mut e = [0u32; 4];
                if a > 0 {
                    e[a - 1] = 1;
                }
                if b > 0 {
                    e[1 + b] = 1;
                }
                terms.push(Term::new(rng.complex_normal(), &e));
            }
        }
        polys.push(Polynomial::new(terms));
    }
    let s = System::new(4, 0, polys).unwrap();
    let two = solve(&s, Some(Groups(vec![vec![0, 1], vec![2, 3]])), &Options::default()).unwrap();
    assert_eq!(two.paths, 6);
    assert_eq!(two.roots.len(), 6, "{two:?}");
    let total = solve(&s, None, &Options::default()).unwrap();
    assert_eq!(total.paths, 16);
    assert_eq!(total.roots.len(), 6, "{total:?}");
    for r in &two.roots {
        assert!(r.certified);
        let m =
            total.roots.iter().map(|q| q.x.iter().zip(&r.x).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max));
        assert!(m.fold(f64::INFINITY, f64::min) < 1e-12);
    }
}

#[test]
fn parameter_homotopy_follows_the_family() {
    // circles x^2 + y^2 = p0, (x - p1)^2 + y^2 = p0: x = p1/2, y = +-sqrt(p0 - p1^2/4)
    let family = System::new(
        2,
        2,
        vec![
            poly(&[(1.0, &[2, 0, 0, 0]), (1.0, &[0, 2, 0, 0]), (-1.0, &[0, 0, 1, 0])]),
            poly(&[
                (1.0, &[2, 0, 0, 0]),
                (-2.0, &[1, 0, 0, 1]),
                (1.0, &[0, 0, 0, 2]),
                (1.0, &[0, 2, 0, 0]),
                (-1.0, &[0, 0, 1, 0]),
            ]),
        ],
    )
    .unwrap();
    let p0 = [C64::new(0.3, 0.8), C64::new(-0.7, 0.2)];
    let start = solve(&family.specialize(&p0).unwrap(), None, &Options::default()).unwrap();
    assert_eq!(start.roots.len(), 2);
    let starts: Vec<Vec<C64>> = start.roots.iter().map(|r| r.x.clone()).collect();
    let p1 = [c(4.0), c(1.0)];
    let sol = solve_parameter(&family, &p0, &starts, &p1, &Options::default()).unwrap();
    assert_eq!(sol.paths, 2);
    assert_eq!(sol.roots.len(), 2);
    for r in &sol.roots {
        assert!(r.real && r.certified);
        assert!((r.x[0].re - 0.5).abs() < 1e-14);
        assert!((r.x[1].re.abs() - (4.0f64 - 0.25).sqrt()).abs() < 1e-14);
    }
    // a target with no real roots: the two roots come back complex, certified, not real
    let p2 = [c(0.1), c(2.0)];
    let sol = solve_parameter(&family, &p0, &starts, &p2, &Options::default()).unwrap();
    assert_eq!(sol.roots.len(), 2);
    assert!(sol.roots.iter().all(|r| r.certified && !r.real));
}
