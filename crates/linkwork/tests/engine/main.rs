//! The engine's integration tests, one module per subject, in one test binary: a change to
//! the engine relinks one binary, not one per file. Kept apart, in their own binaries: the
//! tests that count heap allocations with a global allocator (`tests/allocations.rs`,
//! `tests/cams_allocations.rs`, `tests/curve_expressions.rs`, `tests/motion_laws.rs`).
//! Run one module: `cargo test -p linkwork --test engine sweep_travel::`.

#[path = "../common/mod.rs"]
mod common;
#[path = "../common/oscillator.rs"]
mod oscillator_model;

mod asked_newton_block;
mod batch;
mod blocks;
mod cams;
mod closed_form;
mod constraint_roles;
mod curves_fd;
mod dynamics;
mod dynamics_forward;
mod dynamics_properties;
mod equilibrium;
mod free_models;
mod fuzz;
mod guard;
mod joint_library;
mod joints_fd;
mod lanes;
mod layers;
mod memory;
mod model_files;
mod outputs;
mod rrp_turning_slide;
mod screw;
mod sensitivity_efforts;
mod sensitivity_joints;
mod sensitivity_structured;
mod sensitivity_sweeps;
mod singular;
mod sparse_lu;
mod structure;
mod sweep_travel;
mod synthesis;
mod synthesis_hostile;
mod transmission_angles;
mod variants;
