//! Singular configurations: how close Phi_q is to singular, in which direction, and what
//! kind of singularity it is.
//!
//! Near a singular configuration Phi_q ~ sigma_min w v^T + ..., with v the motion the
//! constraints allow with every driver held (right singular vector) and w the
//! combination of rows that has become dependent (left singular vector). Where w lies
//! says what happens:
//! - w has a share on a driver row: the driver's value cannot change to first order, so
//!   the driven input has reached a limit of its motion (a rocker at the end of its
//!   swing, a piston driven onto dead centre);
//! - w lies on joint rows only: the joints themselves have become dependent and the
//!   mechanism gains an instantaneous freedom; two assembly branches meet there (a
//!   bifurcation, e.g. a parallelogram's change points).
//!
//! The estimate uses the factorization the position solve left (inverse iteration on
//! Phi_q^T Phi_q), so it costs a few triangular solves.

use crate::model::data::Data;
use crate::model::Model;

/// What kind of event a sweep reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// A driver reaches a limit of motion: Phi_q is singular and a driver row is in the
    /// dependency. Beyond it the mechanism cannot be assembled unless the driver reverses.
    Limit,
    /// Joint rows become dependent: assembly branches meet. The sweep goes on along the
    /// branch it was on (or stops, as asked).
    Bifurcation,
    /// An output (a link pinned to the ground, or a slider) stops and reverses while the
    /// input moves: the output locks for an instant. Driven from that output, this would
    /// be a dead point; for a load on the output the mechanical advantage is unbounded.
    Lock,
    /// The solution left the branch the sweep was following and subdividing the step did
    /// not bring it back.
    BranchJump,
}

impl EventKind {
    pub fn name(self) -> &'static str {
        match self {
            EventKind::Limit => "limit",
            EventKind::Bifurcation => "bifurcation",
            EventKind::Lock => "lock",
            EventKind::BranchJump => "branch_jump",
        }
    }
}

/// A located event of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    pub kind: EventKind,
    /// the sweep step it precedes: it lies between times[step - 1] and times[step]
    pub step: usize,
    /// where it was located
    pub time: f64,
    /// n_coords: the configuration there (the nearest solved one for a limit)
    pub q: Vec<f64>,
    /// scaled smallest singular value of Phi_q there (how singular it was found)
    pub sigma_min: f64,
    /// the constraints in the dependency (left singular vector), with their shares
    pub constraints: Vec<(String, f64)>,
    /// the coordinates of the free motion (right singular vector), with their shares
    pub coordinates: Vec<(String, f64)>,
    /// for a lock: the output (a coordinate name, e.g. "rocker.theta")
    pub output: Option<String>,
    /// each driver's value there (its motion law at `time`)
    pub drivers: Vec<(String, f64)>,
    /// what it means, in a sentence
    pub message: String,
}

/// The smallest singular value of the scaled Phi_q and its singular vectors.
#[derive(Debug, Clone, PartialEq)]
pub struct SingularTriple {
    /// estimate of sigma_min of the scaled Phi_q
    pub sigma: f64,
    /// n_coords, unit: right singular vector (scaled coordinates)
    pub v: Vec<f64>,
    /// n_rows, unit: left singular vector (scaled rows)
    pub w: Vec<f64>,
}

fn normalize(x: &mut [f64]) -> f64 {
    let n = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    if n > 0.0 && n.is_finite() {
        x.iter_mut().for_each(|v| *v /= n);
    }
    n
}

/// Estimates the smallest singular triple of the scaled Phi_q from the factorization in
/// `data` (left by the last position solve) by `iterations` steps of inverse iteration.
/// Each step divides the error by (sigma_min / sigma_next)^2, so near a singularity two
/// or three steps are plenty. Returns sigma = 0 if the factorization is singular.
pub fn smallest_singular(model: &Model, data: &mut Data, iterations: usize) -> SingularTriple {
    // w over the rows, v over the coordinates (more rows for a redundant model solved
    // anyway: then sigma_min is that of its QR's R, and the solves are least squares)
    let (n, m) = (model.n_coords, model.n_rows);
    let mut w: Vec<f64> = (0..m).map(|i| 1.0 + 0.1 * ((i * 7 + 3) % 11) as f64).collect();
    normalize(&mut w);
    let mut v = vec![0.0; n];
    let mut buf = vec![0.0; m];
    let mut sigma = 0.0;
    if !(data.pivots.det_sign != 0.0 && data.pivots.ratio > 0.0) {
        return SingularTriple { sigma: 0.0, v, w };
    }
    for _ in 0..iterations.max(1) {
        // v ~ Phi_q^-1 w, then w ~ Phi_q^-T v; |Phi_q^-T v| -> 1 / sigma_min
        buf.copy_from_slice(&w);
        data.factor.solve(&model.symbolic, &mut buf);
        v.copy_from_slice(&buf[..n]);
        if normalize(&mut v) <= 0.0 {
            return SingularTriple { sigma: 0.0, v, w };
        }
        buf[..n].copy_from_slice(&v);
        data.factor.solve_transpose(&model.symbolic, &mut buf);
        w.copy_from_slice(&buf);
        let norm = normalize(&mut w);
        if !(norm > 0.0 && norm.is_finite()) {
            return SingularTriple { sigma: 0.0, v, w };
        }
        sigma = 1.0 / norm;
    }
    SingularTriple { sigma, v, w }
}

/// The constraints carrying a row vector's weight: the norm of each constraint's share,
/// largest first, shares below `floor` left out.
pub fn constraint_shares(model: &Model, w: &[f64], floor: f64) -> Vec<(String, f64)> {
    let mut share = vec![0.0f64; model.constraints.len()];
    for (row, x) in w.iter().enumerate() {
        let owner = model.row_owner(row);
        if let Some(k) = model.constraints.iter().position(|c| std::ptr::eq(c, owner)) {
            share[k] += x * x;
        }
    }
    let mut out: Vec<(String, f64)> = model
        .constraints
        .iter()
        .zip(share)
        .map(|(c, s)| (c.name.clone(), s.sqrt()))
        .filter(|(_, s)| *s > floor)
        .collect();
    out.sort_by(|a, b| b.1.total_cmp(&a.1));
    out
}

/// The coordinates carrying a scaled coordinate vector's weight, largest first.
pub fn coordinate_shares(model: &Model, v: &[f64], floor: f64) -> Vec<(String, f64)> {
    let mut out: Vec<(String, f64)> =
        model.columns.iter().zip(v).map(|(c, x)| (c.clone(), x.abs())).filter(|(_, s)| *s > floor).collect();
    out.sort_by(|a, b| b.1.total_cmp(&a.1));
    out
}

/// The share of the driver rows in a unit left singular vector.
pub fn driver_share(model: &Model, w: &[f64]) -> f64 {
    w.iter()
        .enumerate()
        .filter(|(row, _)| model.row_owner(*row).role == "driver")
        .map(|(_, x)| x * x)
        .sum::<f64>()
        .sqrt()
}

/// Below this driver share a dependency is the joints' own (a bifurcation). At a located
/// singularity the singular vectors are accurate to about sigma_min / gap, far below it.
pub const DRIVER_SHARE_TOL: f64 = 1e-3;

/// Classifies the singularity whose triple is given.
pub fn classify(model: &Model, triple: &SingularTriple) -> EventKind {
    if driver_share(model, &triple.w) > DRIVER_SHARE_TOL {
        EventKind::Limit
    } else {
        EventKind::Bifurcation
    }
}
