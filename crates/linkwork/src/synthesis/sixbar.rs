//! The chained Stephenson six-bar: a coupler carrying B, D and P, driven through
//! P_1..P_5 while the input link QA turns about the input pivot Q by phi_n and the
//! coupler by theta_n; the link DC, turned by phi_n through the chain, carries C on a
//! circle about the output pivot O. Both dyads are instances of the standard-form dyad system (dyad.rs):
//!
//! dyad 1 (A on QA, B on the coupler): A_n = Q + R(phi_n)(A_1 - Q),
//! B_n = P_n + R(theta_n)(B_1 - P_1), |A_n - B_n| = |A_1 - B_1|; with x = A_1 - Q and
//! y = B_1 - A_1: alpha = e^{i theta} - e^{i phi}, beta = P_n - Q + e^{i theta}(Q - P_1),
//! sigma = e^{i theta}.
//!
//! dyad 2 (D on the coupler, C on the link DC that the chain turns by phi_n, C on a circle
//! about O): C_n = D_n + R(phi_n)(C_1 - D_1), |C_n - O| = |C_1 - O|; with
//! x = D_1 - P_1, y = C_1 - O: alpha = e^{i theta} - e^{i phi},
//! beta = (P_n - O) - e^{i phi}(P_1 - O), sigma = e^{i phi}.
//!
//! In the returned dyads, `ground` is A_1 (dyad 1) or C_1 (dyad 2) and `moving` is B_1 or
//! D_1: neither A_1 nor C_1 is a ground pivot; the field names are the dyad's (the pivot
//! on the guiding link, the pivot on the guided body).

use num_complex::Complex64 as C64;

use linkwork_homotopy::Solutions;

use super::dyad::{solve_rows, DyadRow};
use super::resultant::solve_by_resultant;
use super::{check_scale, DyadSet, Frame, SynthesisError};

fn check(points: &[[f64; 2]], pivot: [f64; 2], phi: &[f64], theta: &[f64]) -> Result<(), SynthesisError> {
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
    if pivot.iter().any(|v| !v.is_finite()) {
        return Err(SynthesisError::NotFinite { what: "the pivot".into() });
    }
    Ok(())
}

fn c(p: [f64; 2]) -> C64 {
    C64::new(p[0], p[1])
}

/// The data's frame (points and pivot brought to unit size); refuses data no frame can
/// scale (`check_scale`).
fn frame(points: &[[f64; 2]], pivot: [f64; 2]) -> Result<Frame, SynthesisError> {
    let mut all: Vec<C64> = points.iter().map(|p| c(*p)).collect();
    all.push(c(pivot));
    check_scale("the points and the pivot", &all)
}

fn rows_1(points: &[[f64; 2]], q: C64, phi: &[f64], theta: &[f64], f: &Frame) -> [DyadRow; 4] {
    let p1 = f.to_local(c(points[0]));
    std::array::from_fn(|k| {
        let n = k + 1;
        let (ep, et) = (C64::from_polar(1.0, phi[n] - phi[0]), C64::from_polar(1.0, theta[n] - theta[0]));
        DyadRow { alpha: et - ep, beta: f.to_local(c(points[n])) - q + et * (q - p1), sigma: et }
    })
}

fn rows_2(points: &[[f64; 2]], o: C64, phi: &[f64], theta: &[f64], f: &Frame) -> [DyadRow; 4] {
    let p1 = f.to_local(c(points[0])) - o;
    std::array::from_fn(|k| {
        let n = k + 1;
        let (ep, et) = (C64::from_polar(1.0, phi[n] - phi[0]), C64::from_polar(1.0, theta[n] - theta[0]));
        DyadRow { alpha: et - ep, beta: f.to_local(c(points[n])) - o - ep * p1, sigma: ep }
    })
}

/// Every dyad 1 (A_1, B_1) about the input pivot `q`, by parameter homotopy.
pub fn dyad_1(
    points: &[[f64; 2]],
    q: [f64; 2],
    phi: &[f64],
    theta: &[f64],
) -> Result<DyadSet, SynthesisError> {
    dyad_1_with(points, q, phi, theta, solve_rows)
}

/// Every dyad 2 (C_1, D_1) with C on a circle about the output pivot `o`, by parameter
/// homotopy.
pub fn dyad_2(
    points: &[[f64; 2]],
    o: [f64; 2],
    phi: &[f64],
    theta: &[f64],
) -> Result<DyadSet, SynthesisError> {
    dyad_2_with(points, o, phi, theta, solve_rows)
}

/// Dyad 1's real solutions by elimination: the independent cross-check.
pub fn dyad_1_by_resultant(
    points: &[[f64; 2]],
    q: [f64; 2],
    phi: &[f64],
    theta: &[f64],
) -> Result<DyadSet, SynthesisError> {
    dyad_1_with(points, q, phi, theta, solve_by_resultant)
}

/// Dyad 2's real solutions by elimination: the independent cross-check.
pub fn dyad_2_by_resultant(
    points: &[[f64; 2]],
    o: [f64; 2],
    phi: &[f64],
    theta: &[f64],
) -> Result<DyadSet, SynthesisError> {
    dyad_2_with(points, o, phi, theta, solve_by_resultant)
}

/// Both dyads' real solutions by elimination.
pub fn dyads_by_resultant(
    points: &[[f64; 2]],
    q: [f64; 2],
    o: [f64; 2],
    phi: &[f64],
    theta: &[f64],
) -> Result<[DyadSet; 2], SynthesisError> {
    Ok([dyad_1_by_resultant(points, q, phi, theta)?, dyad_2_by_resultant(points, o, phi, theta)?])
}

fn dyad_1_with(
    points: &[[f64; 2]],
    q: [f64; 2],
    phi: &[f64],
    theta: &[f64],
    solve: impl Fn(&[DyadRow; 4]) -> Result<Solutions, SynthesisError>,
) -> Result<DyadSet, SynthesisError> {
    check(points, q, phi, theta)?;
    let f = frame(points, q)?;
    let ql = f.to_local(c(q));
    let rows = rows_1(points, ql, phi, theta, &f);
    Ok(DyadSet::from_solutions(&solve(&rows)?, &rows, &f, |x, y| (ql + x, ql + x + y)))
}

fn dyad_2_with(
    points: &[[f64; 2]],
    o: [f64; 2],
    phi: &[f64],
    theta: &[f64],
    solve: impl Fn(&[DyadRow; 4]) -> Result<Solutions, SynthesisError>,
) -> Result<DyadSet, SynthesisError> {
    check(points, o, phi, theta)?;
    let f = frame(points, o)?;
    let ol = f.to_local(c(o));
    let p1 = f.to_local(c(points[0]));
    let rows = rows_2(points, ol, phi, theta, &f);
    Ok(DyadSet::from_solutions(&solve(&rows)?, &rows, &f, |x, y| (ol + y, p1 + x)))
}
