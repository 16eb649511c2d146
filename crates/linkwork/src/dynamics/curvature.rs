//! The constraint forces' own stiffness, d(Phi_q^T lambda)/dq = sum_i lambda_i d2phi_i/dq2,
//! exact: each joint's rows on jets (`phi_jet`) whose lanes are its coordinates and whose
//! time direction is one coordinate at a time, so that a lane's tau coefficient is a
//! second derivative of the row (forward over forward mode, no differences).

use crate::constraints::{Constraint, MAX_ROWS};
use crate::math::jet::{Jet, JetFrame};
use crate::model::{ConstraintEntry, Model};

/// Lanes: body a's (x, y, theta), body b's, the extra coordinate.
const W: usize = 7;

/// A constraint's numbers as constant jets (the order `phi_jet` reads them).
#[derive(Debug, Clone)]
pub struct ConstraintJet {
    params: Vec<Jet<W>>,
}

impl ConstraintJet {
    pub fn new(c: &ConstraintEntry) -> ConstraintJet {
        let mut kind = c.kind.clone();
        let params = kind.params_mut().into_iter().map(|(_, v)| Jet::cst(*v)).collect();
        ConstraintJet { params }
    }

    pub fn all(model: &Model) -> Vec<ConstraintJet> {
        model.constraints.iter().map(ConstraintJet::new).collect()
    }
}

/// The model's columns of a constraint's lanes (None: the ground or no extra coordinate).
fn lane_columns(c: &ConstraintEntry) -> [Option<usize>; W] {
    let mut cols = [None; W];
    for k in 0..3 {
        cols[k] = c.body_a.map(|a| 3 * a + k);
        cols[3 + k] = c.body_b.map(|b| 3 * b + k);
    }
    cols[6] = c.extra;
    cols
}

/// Adds sum_i lambda_i d2phi_i/dq2 (n x n, row-major) at q, time t, to `out`; lambda are
/// the multipliers of the scaled rows (length rows / L), as the augmented solves give them.
pub fn add_constraint_curvature(
    model: &Model,
    jets: &[ConstraintJet],
    q: &[f64],
    lambda: &[f64],
    t: f64,
    out: &mut [f64],
) {
    let n = model.n_coords;
    for (c, cj) in model.constraints.iter().zip(jets) {
        let weights: [f64; MAX_ROWS] =
            std::array::from_fn(|i| if i < c.n_rows { lambda[c.row0 + i] * c.row_scale[i] } else { 0.0 });
        if weights.iter().all(|w| *w == 0.0) {
            continue;
        }
        let cols = lane_columns(c);
        let unit = |k: usize| -> [f64; W] { std::array::from_fn(|d| if d == k { 1.0 } else { 0.0 }) };
        let coordinate = |lane: usize, along: usize| -> Jet<W> {
            let x = cols[lane].map_or(0.0, |col| q[col]);
            Jet::motion(x, if lane == along { 1.0 } else { 0.0 }, 0.0, unit(lane), [0.0; W])
        };
        for (along, col_j) in cols.iter().enumerate() {
            let Some(col_j) = *col_j else { continue };
            let side = |body: Option<usize>, l0: usize| match body {
                Some(_) => JetFrame::new([
                    coordinate(l0, along),
                    coordinate(l0 + 1, along),
                    coordinate(l0 + 2, along),
                ]),
                None => JetFrame::ground(),
            };
            let (a, b) = (side(c.body_a, 0), side(c.body_b, 3));
            let s = if c.extra.is_some() { coordinate(6, along) } else { Jet::ZERO };
            let mut rows = [Jet::ZERO; MAX_ROWS];
            c.kind.phi_jet(&a, &b, s, t, &cj.params, &mut rows);
            for (lane, col_k) in cols.iter().enumerate() {
                let Some(col_k) = *col_k else { continue };
                let h: f64 = (0..c.n_rows).map(|i| weights[i] * rows[i].e[lane][1]).sum();
                out[col_k * n + col_j] += h;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::augmented::Augmented;
    use crate::dynamics::mass::frames_of;
    use crate::input::description::Description;
    use crate::model::Options;

    /// A free four-bar with a slider hung on its coupler by a pin and a prismatic guide to
    /// the ground, and an angle driver: revolutes, a prismatic, a driver in one model.
    fn mixed() -> Model {
        let json = r#"{
          "name": "mixed",
          "bodies": [
            {"name": "crank", "x": 0.0, "y": 0.0, "theta": 0.9},
            {"name": "coupler", "x": 0.62, "y": 0.78, "theta": -0.2},
            {"name": "rocker", "x": 2.0, "y": 0.0, "theta": 1.7},
            {"name": "slide", "x": 1.3, "y": 0.64, "theta": 0.0}
          ],
          "joints": [
            {"type": "revolute", "name": "O", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
            {"type": "revolute", "name": "A", "body_a": "crank", "body_b": "coupler", "pin_a": [1.0, 0.0], "pin_b": [0.0, 0.0]},
            {"type": "revolute", "name": "B", "body_a": "coupler", "body_b": "rocker", "pin_a": [1.8, 0.0], "pin_b": [0.9, 0.0]},
            {"type": "revolute", "name": "C", "body_a": "ground", "body_b": "rocker", "at": [2.0, 0.0]},
            {"type": "prismatic", "name": "P", "body_a": "coupler", "body_b": "slide", "at": [1.3, 0.64], "axis": [1.0, 0.2]}
          ],
          "drivers": [
            {"type": "angle", "name": "turn", "body": "slide", "law": {"type": "linear", "value": 0.0, "rate": 0.3}}
          ]
        }"#;
        let options = Options { free: true, ..Options::default() };
        Model::with_options(Description::from_json(json).unwrap(), options).unwrap()
    }

    /// Phi_q^T lambda at q (n), from the engine's own Jacobian (scaled rows).
    fn generalized(model: &Model, aug: &mut Augmented, q: &[f64], lambda: &[f64], t: f64) -> Vec<f64> {
        let mut frames = vec![crate::constraints::Frame::GROUND; model.n_bodies];
        frames_of(q, &vec![0.0; q.len()], &mut frames);
        let mut phi = vec![0.0; model.n_rows];
        aug.fill(model, &frames, q, t, 1.0, &mut phi);
        let mut out = vec![0.0; model.n_coords];
        aug.jacobian_transpose_times(lambda, &mut out);
        out
    }

    /// The jets' d(Phi_q^T lambda)/dq against central differences of Phi_q^T lambda from the
    /// engine's Jacobian (step 1e-6 on O(1) entries: agreement to ~1e-9), at a configuration
    /// off the constraints (the curvature is a property of the rows, not of the assembly).
    #[test]
    fn curvature_matches_differences_of_the_jacobian() {
        for model in [mixed(), crate::dynamics::applied::tests::loaded_pair()] {
            let n = model.n_coords;
            let mut aug = Augmented::new(&model);
            let q: Vec<f64> =
                model.q_start.iter().enumerate().map(|(i, v)| v + 0.05 * (i as f64).sin()).collect();
            let lambda: Vec<f64> = (0..model.n_rows).map(|i| 1.0 + 0.7 * (1.3 * i as f64).cos()).collect();
            let t = 0.4;
            let mut k = vec![0.0; n * n];
            add_constraint_curvature(&model, &ConstraintJet::all(&model), &q, &lambda, t, &mut k);
            let h = 1e-6;
            for j in 0..n {
                let (mut up, mut down) = (q.clone(), q.clone());
                up[j] += h;
                down[j] -= h;
                let (gu, gd) = (
                    generalized(&model, &mut aug, &up, &lambda, t),
                    generalized(&model, &mut aug, &down, &lambda, t),
                );
                for i in 0..n {
                    let fd = (gu[i] - gd[i]) / (2.0 * h);
                    let got = k[i * n + j];
                    assert!(
                        (got - fd).abs() < 1e-8 * (1.0 + fd.abs()),
                        "({i}, {j}): jets {got} vs differences {fd}"
                    );
                }
            }
            // symmetric (a sum of Hessians) and not all zero: the test can fail
            for i in 0..n {
                for j in 0..n {
                    assert!((k[i * n + j] - k[j * n + i]).abs() < 1e-13 * (1.0 + k[i * n + j].abs()));
                }
            }
            assert!(k.iter().any(|v| v.abs() > 0.1), "{k:?}");
        }
    }
}
