//! Every joint and driver against finite differences: the Jacobian blocks against
//! central differences of phi, nu against -phi_t, and gamma against the second
//! derivative of phi along a straight path q + h qd at time t + h (qdd = 0 there, so
//! d2/dh2 phi = (phi_q qd)_q qd + 2 phi_qt qd + phi_tt = -gamma). A joint's own
//! coordinate (a curve parameter) is one more coordinate, perturbed the same way.

use linkwork::constraints::{samples, Constraint, ConstraintKind, Extra, Frame, Rows, MAX_ROWS};

use crate::common;
use common::Rng;

impl Rng {
    fn vec3(&mut self, scale: f64) -> [f64; 3] {
        [scale * self.next(), scale * self.next(), 3.0 * self.next()]
    }
}

fn phi(c: &ConstraintKind, qa: [f64; 3], qb: [f64; 3], s: f64, t: f64) -> [f64; MAX_ROWS] {
    let mut r = Rows::default();
    c.position(&Frame::new(qa, [0.0; 3]), &Frame::new(qb, [0.0; 3]), &Extra { s, sd: 0.0 }, t, &mut r);
    r.phi
}

fn axpy(q: [f64; 3], s: f64, d: [f64; 3]) -> [f64; 3] {
    [q[0] + s * d[0], q[1] + s * d[1], q[2] + s * d[2]]
}

#[test]
fn jacobian_nu_and_gamma_match_finite_differences_for_every_constraint() {
    let mut rng = Rng(0x9E3779B97F4A7C15);
    for c in samples() {
        for _trial in 0..20 {
            let (qa, qb) = (rng.vec3(0.5), rng.vec3(0.5));
            let (qda, qdb) = (rng.vec3(2.0), rng.vec3(2.0));
            let t = rng.next();
            // the extra coordinate (if any) near the joint's own start (a curve parameter)
            let (s, sd) = if c.has_extra() {
                let start = c.own_start(&Frame::new(qa, [0.0; 3]), &Frame::new(qb, [0.0; 3]));
                (start + 0.5 * rng.next(), 2.0 * rng.next())
            } else {
                (0.0, 0.0)
            };
            let extra = Extra { s, sd };
            let n = c.n_rows();
            let mut rows = Rows::default();
            c.position(&Frame::new(qa, qda), &Frame::new(qb, qdb), &extra, t, &mut rows);

            // Jacobian: central differences, h = 1e-6 -> truncation ~1e-12, round-off ~1e-10
            let h = 1e-6;
            for j in 0..3 {
                let mut e = [0.0; 3];
                e[j] = h;
                let (pa, ma) = (phi(&c, axpy(qa, 1.0, e), qb, s, t), phi(&c, axpy(qa, -1.0, e), qb, s, t));
                let (pb, mb) = (phi(&c, qa, axpy(qb, 1.0, e), s, t), phi(&c, qa, axpy(qb, -1.0, e), s, t));
                for i in 0..n {
                    let fd_a = (pa[i] - ma[i]) / (2.0 * h);
                    let fd_b = (pb[i] - mb[i]) / (2.0 * h);
                    assert!(
                        (fd_a - rows.jac_a[i][j]).abs() < 1e-8,
                        "{} d/dq_a[{j}] row {i}: {fd_a} vs {}",
                        c.label(),
                        rows.jac_a[i][j]
                    );
                    assert!(
                        (fd_b - rows.jac_b[i][j]).abs() < 1e-8,
                        "{} d/dq_b[{j}] row {i}: {fd_b} vs {}",
                        c.label(),
                        rows.jac_b[i][j]
                    );
                }
            }

            if c.has_extra() {
                let (p, m) = (phi(&c, qa, qb, s + h, t), phi(&c, qa, qb, s - h, t));
                for i in 0..n {
                    let fd = (p[i] - m[i]) / (2.0 * h);
                    assert!(
                        (fd - rows.jac_s[i]).abs() < 1e-8,
                        "{} d/ds row {i}: {fd} vs {}",
                        c.label(),
                        rows.jac_s[i]
                    );
                }
            } else {
                assert_eq!(rows.jac_s, [0.0; MAX_ROWS], "{} has no extra coordinate", c.label());
            }

            // nu = -phi_t
            let mut nu = [0.0; MAX_ROWS];
            c.nu(t, &mut nu);
            let (p, m) = (phi(&c, qa, qb, s, t + h), phi(&c, qa, qb, s, t - h));
            for i in 0..n {
                let fd = -(p[i] - m[i]) / (2.0 * h);
                assert!((fd - nu[i]).abs() < 1e-8, "{} nu row {i}: {fd} vs {}", c.label(), nu[i]);
            }

            // gamma: second difference along q + s qd, t + s; h = 1e-4 -> error ~1e-8
            let mut gamma = [0.0; MAX_ROWS];
            c.gamma(&Frame::new(qa, qda), &Frame::new(qb, qdb), &extra, t, &mut gamma);
            let h = 1e-4;
            let p = phi(&c, axpy(qa, h, qda), axpy(qb, h, qdb), s + h * sd, t + h);
            let z = phi(&c, qa, qb, s, t);
            let m = phi(&c, axpy(qa, -h, qda), axpy(qb, -h, qdb), s - h * sd, t - h);
            for i in 0..n {
                let fd = -(p[i] - 2.0 * z[i] + m[i]) / (h * h);
                let scale = 1.0 + gamma[i].abs();
                assert!(
                    (fd - gamma[i]).abs() < 1e-5 * scale,
                    "{} gamma row {i}: {fd} vs {}",
                    c.label(),
                    gamma[i]
                );
            }
        }
    }
}

#[test]
fn samples_cover_every_constraint_type() {
    let labels: Vec<&str> = samples().iter().map(|c| c.label()).collect();
    assert_eq!(labels.len(), 19, "{labels:?}");
    for c in samples() {
        assert_eq!(c.row_kinds().len(), c.n_rows());
        assert!(c.n_rows() <= MAX_ROWS);
    }
}
