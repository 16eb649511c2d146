//! What the user writes: expressions, motion laws, curves, units, the description and
//! its files.

pub mod curves;
pub mod description;
pub mod expr;
pub mod files;
pub mod motion;
pub mod units;
