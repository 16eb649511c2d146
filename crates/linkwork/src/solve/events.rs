//! The events a sweep or a simulation reports (limits of motion, bifurcations, locks,
//! branch jumps) and how a singular configuration is described: the smallest singular
//! triple of the scaled Phi_q, the constraints and coordinates carrying it, and its kind.

use crate::constraints::Constraint;
use crate::model::Model;

/// What kind of event a sweep or a simulation reports.
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
    /// A slider crosses an end of the travel its prismatic joint is given: a simulation's
    /// stops there or goes on; a sweep goes on through it (kinematics models no stop).
    EndOfTravel,
}

impl EventKind {
    pub fn name(self) -> &'static str {
        match self {
            EventKind::Limit => "limit",
            EventKind::Bifurcation => "bifurcation",
            EventKind::Lock => "lock",
            EventKind::BranchJump => "branch_jump",
            EventKind::EndOfTravel => "end_of_travel",
        }
    }
}

/// A located event of a sweep or a simulation.
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
    /// the smallest pivot ratio of the factorizations met near it (a sweep's Phi_q, a
    /// simulation's augmented matrix); NaN where none applies
    pub pivot_ratio: f64,
}

/// Each driver's value at t (its motion law there), as an event reports them.
pub fn driver_values(model: &Model, t: f64) -> Vec<(String, f64)> {
    model
        .constraints
        .iter()
        .filter(|c| c.role == "driver")
        .filter_map(|c| c.kind.law().map(|l| (c.name.clone(), l.eval(t)[0])))
        .collect()
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
