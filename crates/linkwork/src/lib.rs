//! linkwork: planar mechanism kinematics in absolute coordinates.
//!
//! Every moving body has q_i = (x_i, y_i, theta_i); every joint and driver is a set of
//! rows of Phi(q, t) = 0. A `Description` (bodies, joints, drivers, motion laws) compiles
//! into an immutable `Model`; a `Data` holds every mutable buffer. One time step is
//! `position` (Newton) -> `velocity` (Phi_q qd = nu) -> `acceleration` (Phi_q qdd = gamma),
//! all from one factorization of Phi_q; `sweep` runs it over a time grid.

pub mod acceleration;
pub mod analysis;
pub mod assembly;
pub mod batch;
pub mod blocks;
pub mod branches;
pub mod closing;
pub mod curves;
pub mod data;
pub mod description;
pub mod drivers;
pub mod error;
pub mod expr;
pub mod files;
pub mod forces;
pub mod joints;
pub mod linear;
pub mod loads;
pub mod memory;
pub mod model;
pub mod motion;
pub mod position;
pub mod screw;
pub mod sensitivity;
pub mod small_lu;
pub mod sparse_lu;
pub mod stepping;
pub mod structure;
pub mod sweep;
pub mod synthesis;
pub mod units;
pub mod variants;
pub mod velocity;

pub use acceleration::solve_acceleration;
pub use batch::{sweep_batch, sweep_batch_on, BatchItem};
pub use data::Data;
pub use description::{BodyDesc, Description, DriverDesc, JointDesc, PointDesc, GROUND};
pub use error::{ModelError, SolveError};
pub use expr::{ExprError, Expression};
pub use files::{Format, ModelFile, SourceMap, FORMAT_VERSION};
pub use forces::{load_power, reactions, solve_forces, REACTION_COLUMNS};
pub use linear::{LinearKind, Pivots};
pub use memory::available_memory;
pub use model::{Model, Options, SolverKind};
pub use motion::{ExternalFn, ExternalLaw, MotionLaw};
pub use position::{solve_position, PositionInfo};
pub use sweep::{check_times, drawing_time, solve, solve_along, sweep, Outputs, Request, SweepOutput};
pub use units::Units;
pub use variants::{sweep_variants, VariantFigures, Variation};
pub use velocity::solve_velocity;
