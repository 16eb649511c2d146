//! Forward dynamics: M(q) qdd + Phi_q^T lambda = Q_A(q, qd, t), Phi(q, t) = 0, for a
//! model with free coordinates (`Options::free`), on the same Model and constraint rows
//! as the kinematic sweeps (beside `sweep`, not woven into it).
//!
//! - `mass`: M, block diagonal per body; the kinetic energy.
//! - `applied`: Q_A (gravity, loads, the quadratic-velocity term) and its exact tangents.
//! - `augmented`: the sparse augmented matrix [[A, Phi_q^T], [Phi_q, 0]], compiled once.
//! - `system`: the index-1 solve of (qdd, lambda) and the projections onto the constraints.
//! - `initial`: consistent initial conditions.
//! - `curvature`: the constraint forces' own stiffness d(Phi_q^T lambda)/dq, exact.
//! - `equilibrium`, `modes`: the rest configuration under the loads, its stability and
//!   its linearized vibration modes.
//! - `energy`: kinetic and potential energy, the power of what is not conservative.
//! - `events`: singular configurations passed and locks, located between the steps;
//!   `travel`: the sliders' limits (the travel given, a stroke's end).
//! - `rk` (with `dop853`): DOP853 on the index-1 form with coordinate projection.
//! - `gen_alpha`: implicit index-3 generalized-alpha with step-size adaptation.
//! - `options`, `output`, `record`, `simulate`: the settings, the rows kept and how one
//!   is stored, the entry point.

pub mod applied;
pub mod augmented;
pub mod curvature;
pub mod dop853;
pub mod energy;
pub mod equilibrium;
pub mod events;
pub mod gen_alpha;
pub mod initial;
pub mod mass;
pub mod modes;
pub mod options;
pub mod output;
pub mod record;
pub mod rk;
pub mod row_lanes;
pub mod simulate;
pub mod system;
pub mod travel;

pub use options::{Method, SimOptions};
pub use output::SimOutput;
pub use simulate::simulate;
