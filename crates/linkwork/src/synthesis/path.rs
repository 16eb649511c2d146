//! Path generation with prescribed timing: a coupler point P passes P_1..P_5 while the
//! input crank has turned by phi_1..phi_5 (phi_1 = 0). Standard form (Sandor and Erdman):
//! W = crank (ground pivot G to crank pin A), Z = A to P, both at position 1; then
//! P_j - P_1 = W (e^{i phi_j} - 1) + Z (e^{i theta_j} - 1) with the coupler rotations
//! theta_j unknown. |Z e^{i theta_j}| = |Z| eliminates them: a dyad system in (W, Z) with
//! at most 4 solutions. The second dyad of a four-bar then guides the coupler through the
//! poses (P_j, theta_j): Burmester's dyads of those poses (one of them is the first
//! dyad itself).

use num_complex::Complex64 as C64;

use super::dyad::{solve_rows, DyadRow};
use super::resultant::solve_by_resultant;
use super::{check_scale, coincide, Dyad, DyadSet, Frame, SynthesisError};

/// The problem's frame, or why its data is refused.
fn check(points: &[[f64; 2]], input: &[f64]) -> Result<Frame, SynthesisError> {
    if points.len() != 5 || input.len() != 5 {
        return Err(SynthesisError::Count {
            problem: "path generation with prescribed timing",
            got: points.len().min(input.len()),
            want: "exactly 5 points and 5 input angles (4 or fewer leave free choices: use motion generation; more: least squares)".into(),
        });
    }
    for (i, (p, a)) in points.iter().zip(input).enumerate() {
        if !(p[0].is_finite() && p[1].is_finite() && a.is_finite()) {
            return Err(SynthesisError::NotFinite { what: format!("point or angle {}", i + 1) });
        }
    }
    let points: Vec<C64> = points.iter().map(|p| C64::new(p[0], p[1])).collect();
    let frame = check_scale("the points", &points)?;
    for i in 0..5 {
        for j in i + 1..5 {
            if coincide(points[i], points[j], &frame) {
                return Err(SynthesisError::Coincident { what: "points", i: i + 1, j: j + 1 });
            }
            let turn = (input[j] - input[i]).rem_euclid(std::f64::consts::TAU);
            if turn.min(std::f64::consts::TAU - turn) <= 1e-9 {
                return Err(SynthesisError::Coincident { what: "input angles", i: i + 1, j: j + 1 });
            }
        }
    }
    Ok(frame)
}

pub fn rows(points: &[[f64; 2]], input: &[f64], frame: &Frame) -> [DyadRow; 4] {
    let p1 = frame.to_local(C64::new(points[0][0], points[0][1]));
    std::array::from_fn(|k| DyadRow {
        alpha: 1.0 - C64::from_polar(1.0, input[k + 1] - input[0]),
        beta: frame.to_local(C64::new(points[k + 1][0], points[k + 1][1])) - p1,
        sigma: C64::new(1.0, 0.0),
    })
}

/// Every input dyad (ground pivot G, crank pin A at position 1).
pub fn timed_dyads(points: &[[f64; 2]], input: &[f64]) -> Result<DyadSet, SynthesisError> {
    let frame = check(points, input)?;
    let rows = rows(points, input, &frame);
    let p1 = frame.to_local(C64::new(points[0][0], points[0][1]));
    // x = W, y = Z: A = P1 - Z, G = A - W
    Ok(DyadSet::from_solutions(&solve_rows(&rows)?, &rows, &frame, |w, z| (p1 - z - w, p1 - z)))
}

/// The same by elimination: the independent cross-check.
pub fn timed_dyads_by_resultant(points: &[[f64; 2]], input: &[f64]) -> Result<DyadSet, SynthesisError> {
    let frame = check(points, input)?;
    let rows = rows(points, input, &frame);
    let p1 = frame.to_local(C64::new(points[0][0], points[0][1]));
    Ok(DyadSet::from_solutions(&solve_by_resultant(&rows)?, &rows, &frame, |w, z| (p1 - z - w, p1 - z)))
}

/// Coupler rotations theta_j (from position 1) that a real input dyad implies.
pub fn coupler_rotations(points: &[[f64; 2]], input: &[f64], dyad: &Dyad) -> Vec<f64> {
    let p1 = C64::new(points[0][0], points[0][1]);
    let g = C64::new(dyad.ground[0], dyad.ground[1]);
    let a1 = C64::new(dyad.moving[0], dyad.moving[1]);
    let z = p1 - a1;
    points
        .iter()
        .zip(input)
        .map(|(p, phi)| {
            let a = g + (a1 - g) * C64::from_polar(1.0, phi - input[0]);
            let zj = C64::new(p[0], p[1]) - a;
            (zj / z).arg()
        })
        .collect()
}
