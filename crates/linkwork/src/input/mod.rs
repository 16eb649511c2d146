pub mod curves;
pub mod description;
pub mod expr;
pub mod files;
pub mod motion;
pub mod units;
