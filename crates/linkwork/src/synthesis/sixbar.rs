//! The chained Stephenson six-bar of the source document: a coupler carrying B, D and P,
//! driven through P_1..P_5 while the input link QA turns by phi_n and the coupler by
//! theta_n. Both dyads are instances of the standard-form dyad system (dyad.rs):
//!
//! dyad 1 (A on QA, B on the coupler): A_n = Q + R(phi_n)(A_1 - Q),
//! B_n = P_n + R(theta_n)(B_1 - P_1), |A_n - B_n| = |A_1 - B_1|; with x = A_1 - Q and
//! y = B_1 - A_1: alpha = e^{i theta} - e^{i phi}, beta = P_n - Q + e^{i theta}(Q - P_1),
//! sigma = e^{i theta}.
//!
//! dyad 2 (D on the coupler, C on the link DC that the chain turns by phi_n, C on a circle
//! about the origin O): C_n = D_n + R(phi_n)(C_1 - D_1), |C_n - O| = |C_1 - O|; with
//! x = D_1 - P_1, y = C_1 - O: alpha = e^{i theta} - e^{i phi},
//! beta = (P_n - O) - e^{i phi}(P_1 - O), sigma = e^{i phi}.
//!
//! In the returned dyads, `ground` is A_1 (dyad 1) or C_1 (dyad 2) and `moving` is B_1 or
//! D_1.

use num_complex::Complex64 as C64;

use super::dyad::{solve_rows, DyadRow};
use super::resultant::solve_by_resultant;
use super::{DyadSet, Frame, SynthesisError};

fn check(points: &[[f64; 2]], phi: &[f64], theta: &[f64]) -> Result<(), SynthesisError> {
    if points.len() != 5 || phi.len() != 5 || theta.len() != 5 {
        return Err(SynthesisError::Count {
            problem: "the chained six-bar's dyads",
            got: points.len().min(phi.len()).min(theta.len()),
            want: "exactly 5 points, 5 input rotations and 5 coupler rotations".into(),
        });
    }
    if points.iter().flatten().chain(phi).chain(theta).any(|v| !v.is_finite()) {
        return Err(SynthesisError::NotFinite { what: "a point or rotation".into() });
    }
    Ok(())
}

fn c(p: [f64; 2]) -> C64 {
    C64::new(p[0], p[1])
}

fn frame(points: &[[f64; 2]], q: [f64; 2]) -> Frame {
    let mut all: Vec<C64> = points.iter().map(|p| c(*p)).collect();
    all.push(c(q));
    all.push(C64::default());
    Frame::fit(all.into_iter())
}

fn rows_1(points: &[[f64; 2]], q: C64, phi: &[f64], theta: &[f64], f: &Frame) -> [DyadRow; 4] {
    let p1 = f.to_local(c(points[0]));
    std::array::from_fn(|k| {
        let n = k + 1;
        let (ep, et) = (C64::from_polar(1.0, phi[n] - phi[0]), C64::from_polar(1.0, theta[n] - theta[0]));
        DyadRow { alpha: et - ep, beta: f.to_local(c(points[n])) - q + et * (q - p1), sigma: et }
    })
}

fn rows_2(points: &[[f64; 2]], phi: &[f64], theta: &[f64], f: &Frame) -> [DyadRow; 4] {
    let o = f.to_local(C64::default());
    let p1 = f.to_local(c(points[0])) - o;
    std::array::from_fn(|k| {
        let n = k + 1;
        let (ep, et) = (C64::from_polar(1.0, phi[n] - phi[0]), C64::from_polar(1.0, theta[n] - theta[0]));
        DyadRow { alpha: et - ep, beta: f.to_local(c(points[n])) - o - ep * p1, sigma: ep }
    })
}

/// Every dyad 1 (A_1, B_1), by parameter homotopy.
pub fn dyad_1(
    points: &[[f64; 2]],
    q: [f64; 2],
    phi: &[f64],
    theta: &[f64],
) -> Result<DyadSet, SynthesisError> {
    check(points, phi, theta)?;
    let f = frame(points, q);
    let ql = f.to_local(c(q));
    let rows = rows_1(points, ql, phi, theta, &f);
    Ok(DyadSet::from_solutions(&solve_rows(&rows)?, &rows, &f, |x, y| (ql + x, ql + x + y)))
}

/// Every dyad 2 (C_1, D_1), by parameter homotopy.
pub fn dyad_2(points: &[[f64; 2]], phi: &[f64], theta: &[f64]) -> Result<DyadSet, SynthesisError> {
    check(points, phi, theta)?;
    let f = frame(points, [0.0, 0.0]);
    let o = f.to_local(C64::default());
    let p1 = f.to_local(c(points[0]));
    let rows = rows_2(points, phi, theta, &f);
    Ok(DyadSet::from_solutions(&solve_rows(&rows)?, &rows, &f, |x, y| (o + y, p1 + x)))
}

/// Both dyads' real solutions by elimination: the independent cross-check.
pub fn dyads_by_resultant(
    points: &[[f64; 2]],
    q: [f64; 2],
    phi: &[f64],
    theta: &[f64],
) -> Result<[DyadSet; 2], SynthesisError> {
    check(points, phi, theta)?;
    let f = frame(points, q);
    let ql = f.to_local(c(q));
    let o = f.to_local(C64::default());
    let p1 = f.to_local(c(points[0]));
    let r1 = rows_1(points, ql, phi, theta, &f);
    let r2 = rows_2(points, phi, theta, &f);
    let one = DyadSet::from_solutions(&solve_by_resultant(&r1)?, &r1, &f, |x, y| (ql + x, ql + x + y));
    let two = DyadSet::from_solutions(&solve_by_resultant(&r2)?, &r2, &f, |x, y| (o + y, p1 + x));
    Ok([one, two])
}
