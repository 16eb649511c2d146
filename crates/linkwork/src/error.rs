//! Errors of the engine: one enum for a model that cannot be compiled, one for a solve
//! that cannot be completed. Every message names the body, joint, driver or time step.

use thiserror::Error;

/// A model description that cannot be compiled.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// The description text could not be read (syntax, missing field, unknown key).
    #[error("model description: {0}")]
    Description(String),
    /// Something is wrong with one body.
    #[error("body '{name}': {problem}")]
    Body { name: String, problem: String },
    /// Something is wrong with one joint or driver.
    #[error("{kind} '{name}': {problem}")]
    Constraint { kind: &'static str, name: String, problem: String },
    /// Something is wrong with one named point.
    #[error("point '{name}': {problem}")]
    Point { name: String, problem: String },
    /// Two things share one name.
    #[error("duplicate name '{name}': used by {first} and by {second}")]
    DuplicateName { name: String, first: &'static str, second: &'static str },
    /// Kinematic analysis needs as many rows as coordinates.
    #[error(
        "{n_rows} constraint rows for {n_coords} coordinates ({n_bodies} moving bodies x 3{}): \
         {dof} degree(s) of freedom left; {advice}",
        if *n_own > 0 { format!(" + {n_own} curve parameter(s)") } else { String::new() }
    )]
    RowCount { n_rows: usize, n_coords: usize, n_bodies: usize, n_own: usize, dof: i64, advice: &'static str },
    /// More rows than coordinates, analysed: which are redundant, or that none is.
    #[error("{n_rows} constraint rows for {n_coords} coordinates: {explanation}")]
    Redundant { n_rows: usize, n_coords: usize, explanation: String },
    /// A model file (or description text) that cannot be read: where, which field, what.
    #[error("{file}: line {line}, column {column}: {}{message}", field_prefix(.field))]
    File { file: String, line: usize, column: usize, field: String, message: String },
    /// A joint whose pins, placed by the drawing's poses, miss its drawn point (or, closed
    /// keeping the pins, whose joints cannot all hold): `miss` in the model's length unit.
    #[error("joint '{joint}' does not close: {detail}")]
    NotClosed { joint: String, miss: f64, detail: String },
    /// An error of one element of a model file, with the line where the element starts.
    #[error("{file}: line {line}: {error}")]
    Located { file: String, line: usize, error: Box<ModelError> },
}

fn field_prefix(field: &str) -> String {
    if field.is_empty() {
        String::new()
    } else {
        format!("{field}: ")
    }
}

impl ModelError {
    /// The element at fault, as (kind, name): kind is "body", "joint", "driver", "load" or
    /// "point". For a duplicate name, the second element that uses it.
    pub fn element(&self) -> Option<(&'static str, &str)> {
        match self {
            ModelError::Body { name, .. } => Some(("body", name)),
            ModelError::Constraint { kind, name, .. } => Some((kind, name)),
            ModelError::Point { name, .. } => Some(("point", name)),
            ModelError::NotClosed { joint, .. } => Some(("joint", joint)),
            ModelError::DuplicateName { name, second, .. } => {
                Some((second.strip_prefix("a ").unwrap_or(second), name))
            }
            ModelError::Located { error, .. } => error.element(),
            ModelError::Description(_)
            | ModelError::RowCount { .. }
            | ModelError::Redundant { .. }
            | ModelError::File { .. } => None,
        }
    }
}

/// A position, velocity or acceleration solve that cannot be completed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolveError {
    /// Newton-Raphson did not reach the starting configuration.
    #[error(
        "could not assemble the mechanism at t = {time}: residual {residual:.3e} after {iterations} \
         Newton iterations, largest in {constraint}"
    )]
    Assembly { time: f64, iterations: usize, residual: f64, constraint: String },
    /// A design (a variant of a model) cannot be assembled on the branch its model is
    /// drawn in: one of its groups has no such configuration at the first time.
    #[error(
        "could not assemble the design at t = {time} on the branch its model is drawn in: the {group} of \
         {joints} {why} there"
    )]
    AssemblyBranch { time: f64, group: &'static str, joints: String, why: &'static str },
    /// Newton-Raphson did not converge at a later step.
    #[error(
        "no convergence at step {step} (t = {time}): residual {residual:.3e} after {iterations} \
         Newton iterations, largest in {constraint}"
    )]
    NoConvergence { step: usize, time: f64, iterations: usize, residual: f64, constraint: String },
    /// Phi_q is singular (a dead point, a lock-up, or a redundant constraint).
    #[error(
        "singular configuration at step {step} (t = {time}): pivot ratio {pivot_ratio:.3e} at \
         coordinate {coordinate}; constraints on that body: {constraints}"
    )]
    Singular { step: usize, time: f64, pivot_ratio: f64, coordinate: String, constraints: String },
    /// A NaN or infinity appeared.
    #[error("non-finite value at step {step} (t = {time}) in {what}")]
    NonFinite { step: usize, time: f64, what: String },
    /// The time grid cannot be swept.
    #[error("time grid, step {step}: {problem}")]
    Times { step: usize, problem: String },
    /// The caller asked the sweep to stop (an interrupt, a cancelled progress bar).
    #[error("sweep cancelled at step {step}")]
    Cancelled { step: usize },
    /// The sweep met a singular configuration (a limit of motion, a bifurcation) or left
    /// its branch, and cannot or was asked not to go on; the event is in the output.
    #[error("step {step} (t = {time}): {message}")]
    Event { step: usize, time: f64, message: String },
    /// A driver's motion law is not defined at a requested time.
    #[error("driver '{driver}': t = {time} is outside its spline table [{start}, {end}]")]
    OutOfRange { driver: String, time: f64, start: f64, end: f64 },
    /// The outputs asked for would not fit in memory: refused before the sweep starts.
    #[error(
        "the sweep's outputs need {:.3} GB ({steps} steps x {n_coords} values{what}) and {}; \
         ask for less: outputs=[...] to keep only some bodies, coordinates or points, \
         derivatives=0 or 1, forces=False, every=k to keep every k-th step, or sweep the times \
         in chunks (writing each to a file)",
        *bytes as f64 / 1e9,
        match available { Some(a) => format!("{:.3} GB are available", *a as f64 / 1e9), None => "could not be allocated".into() }
    )]
    TooLarge { bytes: usize, available: Option<usize>, steps: usize, n_coords: usize, what: String },
    /// The outputs asked for name a coordinate or body the model does not have.
    #[error("outputs: {problem}")]
    Outputs { problem: String },
    /// A setting or starting value of a solve that cannot be used (a simulation's
    /// tolerances, its initial q0 or qd0).
    #[error("{problem}")]
    Settings { problem: String },
    /// A kinematic solve of a model compiled with free coordinates (`Options::free`).
    #[error(
        "this model has {dof} free coordinate(s): simulate it (model.simulate) or add drivers \
         for a kinematic analysis"
    )]
    Free { dof: usize },
    /// Initial conditions too far from the constraints to be made consistent silently.
    #[error(
        "inconsistent initial {what}: projecting them onto the constraints moves them by {moved:.3e} \
         (scaled; tolerance {tol:.3e}), most in {coordinate}"
    )]
    Inconsistent { what: &'static str, moved: f64, tol: f64, coordinate: String },
    /// M is singular on the motions the constraints allow: a free coordinate has no mass.
    #[error(
        "no mass on a free coordinate at t = {time}: the mass matrix is singular on the motions the \
         constraints allow, at {coordinate} (body '{body}'); give it a mass and a moment of inertia, \
         or drive it"
    )]
    Massless { time: f64, body: String, coordinate: String },
    /// The explicit integrator's steps are held by stability, not accuracy (Hairer's
    /// stiffness test of DOP853): a stiff load for the step sizes asked.
    #[error(
        "the problem is stiff at t = {time} (step {step}): for {steps} of the last accepted steps h lambda \
         stayed beyond DOP853's stability boundary (h = {h:.3e}, |lambda| ~ {lambda:.3e} 1/s), most likely \
         from {load}; simulate with method=\"gen-alpha\" (implicit), or soften or damp the load"
    )]
    Stiff { step: usize, time: f64, h: f64, lambda: f64, steps: usize, load: String },
    /// The integrator could not take a step (step size underflow, Newton divergence).
    #[error("integration failed at step {step} (t = {time}, step size {h:.3e}): {why}")]
    Step { step: usize, time: f64, h: f64, why: String },
}

impl SolveError {
    /// The time step the error refers to, if any.
    pub fn step(&self) -> Option<usize> {
        match self {
            SolveError::Assembly { .. } | SolveError::AssemblyBranch { .. } => Some(0),
            SolveError::NoConvergence { step, .. }
            | SolveError::Singular { step, .. }
            | SolveError::Event { step, .. }
            | SolveError::NonFinite { step, .. }
            | SolveError::Times { step, .. }
            | SolveError::Cancelled { step }
            | SolveError::Step { step, .. }
            | SolveError::Stiff { step, .. } => Some(*step),
            SolveError::Inconsistent { .. } | SolveError::Massless { .. } => Some(0),
            SolveError::OutOfRange { .. }
            | SolveError::TooLarge { .. }
            | SolveError::Outputs { .. }
            | SolveError::Settings { .. }
            | SolveError::Free { .. } => None,
        }
    }
}
