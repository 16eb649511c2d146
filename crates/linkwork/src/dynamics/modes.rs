//! Stability and linearized vibration modes about an equilibrium. On the orthonormal basis
//! N of Phi_q's null space (scaled coordinates), the reduced stiffness K_r = N^T K_t N: the
//! equilibrium is stable when all its eigenvalues are positive (a minimum of the potential
//! along every motion the constraints allow), and each eigenvector says which motion is
//! unstable or neutral. The modes solve K_r x = omega^2 M_r x with M_r = N^T M N; the
//! shapes N x are mapped back to q and normalised in the mass metric (x^T M_r x = 1).
//! Loads that are not conservative (a follower force) make K_t unsymmetric: its symmetric
//! part is used here, and `asymmetry` says how much was left out.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::dynamics::equilibrium::{largest_column, rest_frames, Equilibrium};
use crate::dynamics::mass::mass_block;
use crate::error::SolveError;
use crate::model::Model;

/// The reduced stiffness's eigenvalues (ascending; the model's energy unit per unit scaled
/// motion: lengths / L, angles in rad) and their motions.
#[derive(Debug, Clone, PartialEq)]
pub struct Stability {
    pub eigenvalues: Vec<f64>,
    /// the motion of each eigenvalue in q (lengths in the model's unit, angles in rad)
    pub directions: Vec<Vec<f64>>,
    /// the coordinate each motion moves most (scaled)
    pub dominant: Vec<usize>,
    /// eigenvalues within this of zero are neutral
    pub tol: f64,
    /// every eigenvalue above tol (true when nothing is free)
    pub stable: bool,
    /// |K_r - K_r^T| / |K_r| (Frobenius): the loads' part that is not conservative
    pub asymmetry: f64,
}

/// The linearized vibration modes: omega^2 (ascending, rad^2/s^2) and shapes in q.
#[derive(Debug, Clone, PartialEq)]
pub struct Modes {
    pub omega2: Vec<f64>,
    /// mass-normalised (shape^T M shape = 1); the largest scaled component positive
    pub shapes: Vec<Vec<f64>>,
}

fn symmetric_part(k: &DMatrix<f64>) -> DMatrix<f64> {
    (k + k.transpose()) * 0.5
}

/// Eigenpairs of a symmetric matrix, ascending.
fn sorted_eigen(a: DMatrix<f64>) -> (Vec<f64>, Vec<DVector<f64>>) {
    let e = SymmetricEigen::new(a);
    let mut order: Vec<usize> = (0..e.eigenvalues.len()).collect();
    order.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
    let values = order.iter().map(|&k| e.eigenvalues[k]).collect();
    let vectors = order.iter().map(|&k| e.eigenvectors.column(k).into_owned()).collect();
    (values, vectors)
}

/// A motion of the scaled coordinates in q, its largest component made positive.
fn to_q(model: &Model, v: DVector<f64>) -> (Vec<f64>, usize) {
    let k = largest_column(&v);
    let sign = if v[k] < 0.0 { -1.0 } else { 1.0 };
    (v.iter().zip(&model.col_scale).map(|(x, s)| sign * x * s).collect(), k)
}

/// The stability of an equilibrium from its reduced stiffness.
pub fn stability(model: &Model, eq: &Equilibrium) -> Stability {
    let n_mat = &eq.null_basis;
    let k_r = n_mat.transpose() * &eq.stiffness * n_mat;
    let norm = k_r.norm();
    let asymmetry = if norm > 0.0 { (&k_r - k_r.transpose()).norm() / norm } else { 0.0 };
    let (eigenvalues, vectors) = sorted_eigen(symmetric_part(&k_r));
    // neutral: zero to round-off of the stiffness and of the forces that shape it
    let tol = 1e-9 * eq.stiffness.amax().max(eq.force_scale);
    let (mut directions, mut dominant) = (Vec::new(), Vec::new());
    for v in vectors {
        let (d, k) = to_q(model, n_mat * v);
        directions.push(d);
        dominant.push(k);
    }
    let stable = eigenvalues.iter().all(|&l| l > tol);
    Stability { eigenvalues, directions, dominant, tol, stable, asymmetry }
}

/// S M S at q: the mass matrix in the scaled coordinates (n x n).
fn scaled_mass(model: &Model, q: &[f64]) -> DMatrix<f64> {
    let n = model.n_coords;
    let frames = rest_frames(model, q);
    let mut m = DMatrix::zeros(n, n);
    for (i, body) in model.inertias.iter().enumerate() {
        let b = mass_block(body, &frames[i]);
        for j in 0..3 {
            for k in 0..3 {
                m[(3 * i + j, 3 * i + k)] = b[j][k] * model.col_scale[3 * i + j] * model.col_scale[3 * i + k];
            }
        }
    }
    m
}

/// The linearized vibration modes about an equilibrium; `SolveError::Massless` where a
/// motion the constraints allow carries no mass.
pub fn modes(model: &Model, eq: &Equilibrium) -> Result<Modes, SolveError> {
    let n_mat = &eq.null_basis;
    let m_r = n_mat.transpose() * scaled_mass(model, &eq.q) * n_mat;
    if m_r.nrows() == 0 {
        return Ok(Modes { omega2: Vec::new(), shapes: Vec::new() });
    }
    let (masses, motions) = sorted_eigen(m_r.clone());
    let heaviest = masses.last().copied().unwrap_or(0.0);
    if masses[0].is_nan() || masses[0] <= 1e-12 * heaviest {
        let col = largest_column(&(n_mat * &motions[0]));
        let body = if col < 3 * model.n_bodies {
            model.body_names[col / 3].clone()
        } else {
            format!("the own coordinate of {}", model.describe_coordinate(col).1)
        };
        return Err(SolveError::Massless { time: eq.t, body, coordinate: model.columns[col].clone() });
    }
    // K_r x = w^2 M_r x as the symmetric L^-1 K_r L^-T y = w^2 y, x = L^-T y
    let chol = m_r.cholesky().expect("positive definite: its eigenvalues were checked");
    let l = chol.l();
    let k_r = symmetric_part(&(n_mat.transpose() * &eq.stiffness * n_mat));
    let left = l.solve_lower_triangular(&k_r).expect("nonsingular factor");
    let c = l.solve_lower_triangular(&left.transpose()).expect("nonsingular factor");
    let (omega2, ys) = sorted_eigen(symmetric_part(&c));
    let lt = l.transpose();
    let shapes = ys
        .into_iter()
        .map(|y| {
            let x = lt.solve_upper_triangular(&y).expect("nonsingular factor");
            to_q(model, n_mat * x).0
        })
        .collect();
    Ok(Modes { omega2, shapes })
}
