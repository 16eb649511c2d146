//! The joints, one file per type; each implements `Constraint`, `Sample`, `Described` and
//! `FromDescription` (`crate::constraints`) and is listed once in `crate::constraints::kinds`.

pub mod fixed;
pub mod prismatic;
pub mod revolute;
// joints with their own coordinate, a curve parameter
pub mod cam_follower;
pub mod flat_follower;
pub mod point_on_curve;
pub mod roller_follower;

// joints without coordinates of their own: fixed distances (massless rods), slots, gears,
// linear couplings
pub mod belt;
pub mod fixed_distance;
pub mod gear;
pub mod linear_coupling;
pub mod orientation;
pub mod parallel;
pub mod point_line;
pub mod rack_pinion;

// the roles of a joint's description fields (`super::Described` in each joint file)
pub(crate) use crate::constraints::{Described, Form, Role};
