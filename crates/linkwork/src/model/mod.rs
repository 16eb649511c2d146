//! Compiling a description into an immutable `Model`: names resolved to indices, local
//! vectors derived from the starting poses, rows counted, scales fixed, the sparsity
//! pattern of Phi_q and its symbolic factorization computed once. A `Model` is
//! `Send + Sync`; every mutable buffer lives in `Data`.

pub mod closing;
pub mod data;
pub mod memory;
pub mod params;
pub mod plan;
pub mod rank;
pub mod slider;
pub mod structure;

use std::sync::Arc;

use crate::constraints::kinds::ConstraintKind;
use crate::constraints::loads::{Inertia, LoadEntry};
use crate::constraints::{Extra, MAX_ROWS};
use crate::input::description::Description;
use crate::math::linear::{LinearKind, SymbolicFactor};
use crate::model::closing::Closing;

/// Solver settings, fixed at compile time.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Newton stops when the scaled residual (length rows / L) is below this ...
    pub tol_residual: f64,
    /// ... and so is the scaled Newton step (x, y / L; theta in rad).
    pub tol_step: f64,
    /// Newton iterations allowed at each step of a sweep.
    pub max_iter: usize,
    /// Newton iterations allowed to assemble from the starting configuration.
    pub max_iter_assembly: usize,
    /// A pivot ratio (smallest / largest |pivot| of the scaled Phi_q) below this is singular.
    pub singular_tol: f64,
    /// Which LU; `Auto` picks the fixed-sequence sparse LU (`Refactor`), the fastest at
    /// every size measured (docs/performance.md).
    pub linear: LinearKind,
    /// No longer read: `Auto` chose the small dense LU up to this many coordinates before
    /// the fixed-sequence LU; kept so that existing option sets stay valid.
    pub dense_max: usize,
    /// Redundant joint rows (dependent at the described configuration): refuse the model,
    /// or solve with all rows in the least-squares sense.
    pub redundant: OnRedundant,
    /// Which solver the sweep's steps take: `Auto` solves the mechanism's groups one after
    /// another (closed-form dyads, small Newton blocks; `blocks`) where its structure
    /// allows, the general sparse Newton otherwise; `General` always the general one.
    pub solver: SolverKind,
    /// Keep degrees of freedom free: a model with fewer rows than coordinates compiles
    /// (its motion follows from forces: `dynamics`); every kinematic solve refuses it.
    pub free: bool,
}

/// See `Options::solver`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SolverKind {
    #[default]
    Auto,
    General,
}

/// What compiling does with redundant joint rows (a third parallel crank, a doubled pin).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OnRedundant {
    /// Refuse the model, naming the dependent joints.
    #[default]
    Error,
    /// Solve anyway: Phi_q (more rows than coordinates, full column rank) is factored by
    /// QR and every solve is a least-squares one, exact while the rows stay consistent.
    /// Which rows are independent changes along the motion, so none is singled out.
    /// Positions, velocities and accelerations are still unique; the reactions of the
    /// joints in the dependency are not (the minimum-norm set is reported). If the
    /// geometry stops being redundant, Newton stops converging and says which joint.
    Solve,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tol_residual: 1e-12,
            tol_step: 1e-12,
            max_iter: 25,
            max_iter_assembly: 100,
            singular_tol: 1e-12,
            linear: LinearKind::Auto,
            dense_max: 48,
            redundant: OnRedundant::Error,
            solver: SolverKind::Auto,
            free: false,
        }
    }
}

/// One joint or driver of a compiled model.
#[derive(Debug, Clone)]
pub struct ConstraintEntry {
    pub name: String,
    /// "joint" or "driver"
    pub role: &'static str,
    pub kind: ConstraintKind,
    /// moving body index of each side (None: the ground)
    pub body_a: Option<usize>,
    pub body_b: Option<usize>,
    /// first row in Phi
    pub row0: usize,
    pub n_rows: usize,
    /// scale of each row: 1/L for length rows, 1 for angle rows
    pub row_scale: [f64; MAX_ROWS],
    /// the column of the joint's extra coordinate, if it has one: its own (a curve
    /// parameter) or borrowed (a gear pair's carrier angle)
    pub extra: Option<usize>,
    /// where entry (i, j) of each side's Jacobian block goes in the value array, and
    /// entry i of the own coordinate's column
    pub(crate) slots_a: [[u32; 3]; MAX_ROWS],
    pub(crate) slots_b: [[u32; 3]; MAX_ROWS],
    pub(crate) slots_s: [u32; MAX_ROWS],
}

impl ConstraintEntry {
    /// The joint's extra coordinate and its rate read from q and qd (zeros without one;
    /// qd may be empty for positions only).
    #[inline(always)]
    pub fn extra(&self, q: &[f64], qd: &[f64]) -> Extra {
        match self.extra {
            Some(k) => Extra { s: q[k], sd: qd.get(k).copied().unwrap_or(0.0) },
            None => Extra::default(),
        }
    }
}

/// A named point fixed in a body.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedPoint {
    pub name: String,
    pub body: Option<usize>,
    /// position in the body frame
    pub local: [f64; 2],
}

/// A compiled mechanism: immutable, shared between threads.
#[derive(Debug, Clone)]
pub struct Model {
    pub name: String,
    pub description: Description,
    /// n_bodies
    pub body_names: Vec<String>,
    /// n_coords: "<body>.x", "<body>.y", "<body>.theta" for every body, then "<joint>.s"
    /// for every joint with its own coordinate (a curve parameter)
    pub columns: Vec<String>,
    /// n_coords: the starting configuration as described
    pub q_start: Vec<f64>,
    /// joints, then drivers
    pub constraints: Vec<ConstraintEntry>,
    pub points: Vec<NamedPoint>,
    pub n_bodies: usize,
    /// 3 n_bodies + the joints' own coordinates
    pub n_coords: usize,
    /// rows of Phi: n_coords, or more for a redundant model solved anyway
    pub n_rows: usize,
    /// joints whose reactions kinematics does not determine (their rows are dependent)
    pub indeterminate: Vec<String>,
    /// L: the largest distance between the described points; lengths are measured in L
    pub length_scale: f64,
    /// n_coords: L for x and y, 1 for theta (the solver works on q / col_scale)
    pub col_scale: Vec<f64>,
    pub options: Options,
    /// the linear algebra chosen, with its symbolic analysis (shared by a model's
    /// variants, which differ in numbers only: `crate::sweep::variants`)
    pub(crate) symbolic: Arc<SymbolicFactor>,
    /// the time interval every driver and load law is defined on
    pub time_domain: (f64, f64),
    /// n_bodies: mass properties (all zero: massless)
    pub inertias: Vec<Inertia>,
    /// gravitational acceleration (world)
    pub gravity: [f64; 2],
    /// applied loads
    pub loads: Vec<LoadEntry>,
    /// the groups solved one after another by the sweep, or why the general path solves
    /// the whole model (`closed_form::Plan::new`)
    pub plan: crate::model::plan::PlanResult,
    /// how a drawing that did not close was closed, as the description asked (`close`)
    pub closing: Option<Closing>,
}

impl Model {
    /// Which linear algebra the model uses.
    pub fn linear_kind(&self) -> LinearKind {
        self.symbolic.kind()
    }

    /// Degrees of freedom left free (coordinates minus rows; 0 for a kinematic model).
    pub fn dof(&self) -> usize {
        self.n_coords.saturating_sub(self.n_rows)
    }

    /// A kinematic solve needs no free coordinate: the error saying to simulate instead.
    pub fn check_kinematic(&self) -> Result<(), crate::error::SolveError> {
        match self.dof() {
            0 => Ok(()),
            dof => Err(crate::error::SolveError::Free { dof }),
        }
    }

    /// Number of structurally non-zero entries of Phi_q.
    pub fn nnz(&self) -> usize {
        self.symbolic.nnz()
    }

    /// The pattern of Phi_q in compressed columns (column starts, then the row of each
    /// entry), for the sparse LUs; None for the dense ones.
    pub fn sparsity(&self) -> Option<(&[usize], &[usize])> {
        self.symbolic.pattern()
    }

    /// Index of a body by name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.body_names.iter().position(|b| b == name)
    }

    /// The name of the constraint that owns a row.
    pub fn row_owner(&self, row: usize) -> &ConstraintEntry {
        let k = self.constraints.partition_point(|c| c.row0 + c.n_rows <= row);
        &self.constraints[k]
    }

    /// "body.x" etc. for a coordinate, and the constraints touching its body (or owning it).
    pub(crate) fn describe_coordinate(&self, col: usize) -> (String, String) {
        let body = col / 3;
        let touching: Vec<&str> = self
            .constraints
            .iter()
            .filter(|c| {
                // a joint's own coordinate: that joint
                if col >= 3 * self.n_bodies {
                    c.extra == Some(col)
                } else {
                    c.body_a == Some(body) || c.body_b == Some(body)
                }
            })
            .map(|c| c.name.as_str())
            .collect();
        (self.columns[col].clone(), touching.join(", "))
    }
}
