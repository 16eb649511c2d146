//! Mechanism analysis on top of the solver stages: degrees of freedom and redundancy,
//! singular configurations and events along a sweep, limits of motion, assembly modes,
//! and the classical outputs of four-bars and slider-cranks (Grashof type, transmission
//! angle). Each module reads a `Model` and configurations; none is woven into the solver.

pub mod limits;
pub mod linkages;
pub mod mobility;
pub mod modes;
pub mod sensitivity;
/// the decomposition lives below the solver (`crate::model::structure`), which plans with it
pub use crate::model::structure;
