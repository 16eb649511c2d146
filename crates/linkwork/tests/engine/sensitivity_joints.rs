//! Every joint and driver's rows over jets (`phi_jet`, from which the sensitivities come)
//! against its own closed forms and against central differences: the jets' values are
//! phi, their first tau coefficients J qd - nu and their second -gamma / 2 (qdd = 0);
//! their eps parts in a coordinate direction are the Jacobian columns; and in a parameter
//! direction, Phi_p and its rates, against central differences of `position`, `nu` and
//! `gamma` with that parameter of the joint moved (`params_mut`).

#![allow(clippy::needless_range_loop)] // rows and coordinates indexed together

use linkwork::constraints::{samples, Constraint, ConstraintKind, Extra, Frame, Rows, MAX_ROWS};
use linkwork::sensitivity::jet::{Jet, JetFrame};

use crate::common;
use common::Rng;

fn vec3(rng: &mut Rng, scale: f64) -> [f64; 3] {
    [scale * rng.next(), scale * rng.next(), 3.0 * rng.next()]
}

struct Case {
    c: ConstraintKind,
    q: [[f64; 3]; 2],
    qd: [[f64; 3]; 2],
    s: f64,
    sd: f64,
    t: f64,
}

impl Case {
    /// (phi, J qd - nu, -gamma / 2) of the joint `c` (qdd = 0).
    fn closed(&self, c: &ConstraintKind) -> [[f64; MAX_ROWS]; 3] {
        let (a, b) = (Frame::new(self.q[0], self.qd[0]), Frame::new(self.q[1], self.qd[1]));
        let x = Extra { s: self.s, sd: self.sd };
        let mut rows = Rows::default();
        c.position(&a, &b, &x, self.t, &mut rows);
        let (mut nu, mut g) = ([0.0; MAX_ROWS], [0.0; MAX_ROWS]);
        c.nu(self.t, &mut nu);
        c.gamma(&a, &b, &x, self.t, &mut g);
        let mut rate = [0.0; MAX_ROWS];
        for i in 0..c.n_rows() {
            rate[i] = (0..3)
                .map(|j| rows.jac_a[i][j] * self.qd[0][j] + rows.jac_b[i][j] * self.qd[1][j])
                .sum::<f64>()
                + if c.has_extra() { rows.jac_s[i] * self.sd } else { 0.0 }
                - nu[i];
        }
        [rows.phi, rate, g.map(|v| -0.5 * v)]
    }

    /// The jets' rows with one eps direction: coordinate `coord` (0..3 side a, 3..6 side b,
    /// 6 the extra coordinate) or parameter `param`.
    fn jets(&self, coord: Option<usize>, param: Option<usize>) -> [Jet<1>; MAX_ROWS] {
        let dir = |k: usize| if coord == Some(k) { 1.0 } else { 0.0 };
        let side = |n: usize| {
            JetFrame::new(std::array::from_fn(|j| {
                Jet::motion(self.q[n][j], self.qd[n][j], 0.0, [dir(3 * n + j)], [0.0])
            }))
        };
        let s = Jet::motion(self.s, self.sd, 0.0, [dir(6)], [0.0]);
        let mut c = self.c.clone();
        let p: Vec<Jet<1>> = c
            .params_mut()
            .into_iter()
            .enumerate()
            .map(|(i, (_, v))| {
                let mut j = Jet::cst(*v);
                if param == Some(i) {
                    j.e[0][0] = 1.0;
                }
                j
            })
            .collect();
        let mut out = [Jet::ZERO; MAX_ROWS];
        self.c.phi_jet(&side(0), &side(1), s, self.t, &p, &mut out);
        out
    }
}

fn cases() -> Vec<Case> {
    let mut rng = Rng(0x005E_ED0F_5E45);
    let mut out = Vec::new();
    for c in samples() {
        for _ in 0..10 {
            let q = [vec3(&mut rng, 0.5), vec3(&mut rng, 0.5)];
            let qd = [vec3(&mut rng, 2.0), vec3(&mut rng, 2.0)];
            let (s, sd) = if c.has_extra() {
                let start = c.own_start(&Frame::new(q[0], [0.0; 3]), &Frame::new(q[1], [0.0; 3]));
                (start + 0.5 * rng.next(), 2.0 * rng.next())
            } else {
                (0.0, 0.0)
            };
            out.push(Case { c: c.clone(), q, qd, s, sd, t: rng.next() });
        }
    }
    out
}

#[test]
fn jets_give_phi_its_rate_gamma_and_jacobian_for_every_constraint() {
    for case in cases() {
        let c = &case.c;
        let want = case.closed(c);
        let got = case.jets(None, None);
        for i in 0..c.n_rows() {
            for (level, what) in ["phi", "J qd - nu", "-gamma / 2"].iter().enumerate() {
                let (g, w) = (got[i].v[level], want[level][i]);
                assert!(
                    (g - w).abs() <= 1e-12 * (1.0 + w.abs()),
                    "{} row {i} {what}: jets {g} vs {w}",
                    c.label()
                );
            }
        }
        let (a, b) = (Frame::new(case.q[0], case.qd[0]), Frame::new(case.q[1], case.qd[1]));
        let mut rows = Rows::default();
        c.position(&a, &b, &Extra { s: case.s, sd: case.sd }, case.t, &mut rows);
        let n_coords = if c.has_extra() { 7 } else { 6 };
        for k in 0..n_coords {
            let got = case.jets(Some(k), None);
            for i in 0..c.n_rows() {
                let w = match k {
                    0..=2 => rows.jac_a[i][k],
                    3..=5 => rows.jac_b[i][k - 3],
                    _ => rows.jac_s[i],
                };
                let g = got[i].e[0][0];
                assert!(
                    (g - w).abs() <= 1e-12 * (1.0 + w.abs()),
                    "{} row {i} d/dq[{k}]: jets {g} vs {w}",
                    c.label()
                );
            }
        }
    }
}

#[test]
fn phi_p_and_its_rates_match_central_differences_for_every_constraint() {
    let mut n_checked = 0;
    for case in cases() {
        let n_params = case.c.clone().params_mut().len();
        for i in 0..n_params {
            let got = case.jets(None, Some(i));
            // central differences with h = 1e-6 in the joint's own number: truncation
            // ~h^2 |phi'''| ~ 1e-12, round-off ~1e-16 / 1e-6 = 1e-10; compared at 1e-7
            let h = 1e-6;
            let moved = |d: f64| {
                let mut c = case.c.clone();
                *c.params_mut()[i].1 += d;
                case.closed(&c)
            };
            let (plus, minus) = (moved(h), moved(-h));
            let name = case.c.clone().params_mut()[i].0.clone();
            for row in 0..case.c.n_rows() {
                for level in 0..3 {
                    let fd = (plus[level][row] - minus[level][row]) / (2.0 * h);
                    let g = got[row].e[0][level];
                    assert!(
                        (g - fd).abs() <= 1e-7 * (1.0 + fd.abs()),
                        "{} d/d{name} row {row}, tau^{level}: jets {g} vs differences {fd}",
                        case.c.label()
                    );
                }
            }
            n_checked += 1;
        }
    }
    // every constraint type has parameters (the drivers their laws')
    assert!(n_checked > 19 * 10 * 2, "{n_checked}");
    for c in samples() {
        assert!(!c.clone().params_mut().is_empty(), "{} has no parameters", c.label());
    }
}
