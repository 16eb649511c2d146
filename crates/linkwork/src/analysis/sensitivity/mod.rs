//! Exact sensitivities of a sweep to design parameters: dq/dp, dqd/dp, dqdd/dp and the
//! points' (`step`), by the implicit function theorem on the factorization of Phi_q, the
//! right-hand sides written by the joints themselves over jets (`jet`, each joint's
//! `phi_jet`): forward-mode differentiation, no differences. Parameters are named
//! description paths or the engine's own numbers (`params`); `efforts` differentiates the
//! inverse dynamics' Lagrange multipliers (the driver efforts) likewise; `structured`
//! solves dq/dp group by group on the structure-aware path, each group's closed form
//! differentiated;
//! `sweep` runs a sweep and its sensitivities step by step, on the path `structured`
//! chooses.
#![allow(clippy::needless_range_loop)] // jets, rows and steps index several arrays by one index

pub mod efforts;
/// the jets live in `crate::math::jet`; this path is kept for callers
pub use crate::math::jet;
pub mod step;
pub mod structured;
pub mod sweep;

/// the parameters name the compiled model's numbers (`crate::model::params`)
pub use crate::model::params::{Dynamics, Parameter, ParameterError};
pub use step::{PointRequest, Sensitivity};
pub use structured::SensitivityPath;
pub use sweep::{sensitivity_sweep, SensitivityOutput, SensitivityRequest};
