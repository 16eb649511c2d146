//! linkwork: planar mechanism kinematics in absolute coordinates.
//!
//! Every moving body has q_i = (x_i, y_i, theta_i); every joint and driver is a set of
//! rows of Phi(q, t) = 0. A `Description` (bodies, joints, drivers, motion laws) compiles
//! into an immutable `Model`; a `Data` holds every mutable buffer. One time step is
//! `position` (Newton) -> `velocity` (Phi_q qd = nu) -> `acceleration` (Phi_q qdd = gamma),
//! all from one factorization of Phi_q; `sweep` runs it over a time grid.

pub mod analysis;
pub mod compile;
pub mod constraints;
pub mod dynamics;
pub mod error;
pub mod input;
pub mod math;
pub mod model;
pub mod screw;
pub mod solve;
pub mod sweep;
pub mod synthesis;

// The modules' former top-level paths, kept for callers.
pub use analysis::sensitivity;
pub use constraints::{drivers, joints, loads};
pub use input::{curves, description, expr, files, motion, units};
pub use math::{linear, pivots, small_lu, sparse_lu};
pub use model::{closing, data, memory, structure};
pub use solve::closed_form as blocks;
pub use solve::{acceleration, assembly, forces, position, velocity};
pub use sweep::{batch, branches, stepping, variants};

pub use acceleration::solve_acceleration;
pub use batch::{sweep_batch, sweep_batch_kept, sweep_batch_on, BatchItem};
pub use data::Data;
pub use description::{BodyDesc, Description, DriverDesc, JointDesc, PointDesc, GROUND};
pub use error::{ModelError, SolveError};
pub use expr::{ExprError, Expression};
pub use files::{Format, ModelFile, SourceMap, FORMAT_VERSION};
pub use forces::{load_power, reactions, solve_forces, REACTION_COLUMNS};
pub use linear::LinearKind;
pub use math::pivots::Pivots;
pub use memory::available_memory;
pub use model::{Model, Options, SolverKind};
pub use motion::{ExternalFn, ExternalLaw, MotionLaw};
pub use position::{solve_position, PositionInfo};
pub use sweep::{check_times, drawing_time, solve, solve_along, sweep, Outputs, Request, SweepOutput};
pub use units::Units;
pub use variants::{sweep_variants, VariantFigures, Variation};
pub use velocity::solve_velocity;
