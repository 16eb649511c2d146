//! `ScrewError`: degenerate geometry and bad input of the screw toolkit. Messages name
//! the joints at fault.

use thiserror::Error;

/// Why a screw-theory question has no (unique) answer.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ScrewError {
    /// Some joints' screws are linearly dependent (coincident pivots, parallel slides,
    /// three collinear axes): the arm or loop is singular there.
    #[error("{} {detail}", label(joints))]
    Dependent { joints: Vec<String>, detail: String },
    /// Two points given to `join` are the same point.
    #[error("the points coincide: no single line passes through them")]
    SamePoint,
    /// Two lines given to `meet` are the same line.
    #[error("the lines coincide: they have no single meet")]
    SameLine,
    /// A twist that the named joints cannot produce.
    #[error("{} cannot produce this twist: {why}", label(joints))]
    Unreachable { joints: Vec<String>, why: String },
    /// Joint torques that no end wrench balances.
    #[error("no end wrench gives these joint torques: {why}")]
    Unbalanced { why: String },
    /// More unknown joint rates than a planar twist determines.
    #[error(
        "{unknown} unknown joint rates: a planar twist determines at most 3; give the {}",
        more(*unknown - 3)
    )]
    Redundant { unknown: usize },
    /// A description that is not a serial chain, or a joint or driver the analysis
    /// cannot read.
    #[error("{0}")]
    Mechanism(String),
    /// Arguments of the wrong size or value.
    #[error("{0}")]
    Input(String),
}

/// "rate of 1 more joint", "rates of 2 more joints".
fn more(k: usize) -> String {
    if k == 1 {
        "rate of 1 more joint".into()
    } else {
        format!("rates of {k} more joints")
    }
}

/// "joint 1", "joints 1 and 2", "joints 1, 2 and 3".
fn label(names: &[String]) -> String {
    match names {
        [] => "no joints".into(),
        [one] => format!("joint {one}"),
        _ => format!("joints {}", list(names)),
    }
}

/// "1", "1 and 2", "1, 2 and 3".
fn list(names: &[String]) -> String {
    match names {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}
