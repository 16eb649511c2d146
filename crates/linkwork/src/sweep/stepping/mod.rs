//! Stepping: how a sweep gets from one solved time to the next and keeps its branch.
//!
//! - `predict`: the cheap path's extrapolation of q to the next time;
//! - `tracking`: the checks on each step, the careful path (certified sub-steps that step
//!   over singular configurations), and the events of a sweep (crossings, limits, locks);
//! - `hermite`: solved states, the quintic interpolant between two of them and the test
//!   that two states lie on one branch;
//! - `singular`: how singular Phi_q is, in which direction, and what kind of event;
//! - `travel`: where a slider crosses an end of the travel its prismatic joint is given.
//!
//! `crate::sweep` (the time loop) drives these; `crate::analysis` reads them, never the
//! reverse.

pub mod branch;
pub mod predict;
pub mod singular;
pub mod tracking;
pub mod travel;
