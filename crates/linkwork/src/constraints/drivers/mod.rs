//! Drivers: one row g(q) - f(t) = 0 each, with a motion law f. They are constraints
//! like the joints (same interface, listed with them in `joints::constraint_list!`);
//! the law adds nu = f'(t) and f''(t) to gamma.

pub mod angle;
pub mod coordinate;
pub mod distance;
pub mod relative_angle;
pub mod translation;

use crate::input::motion::MotionLaw;

// the roles of a driver's description fields, declared beside the joints'
pub(crate) use crate::constraints::{Described, Form, Input, Role};

/// A law for the driver samples: every term non-zero.
pub(crate) fn sample_law() -> MotionLaw {
    MotionLaw::Harmonic { mean: 0.3, amplitude: 0.2, omega: 3.0, phase: 0.4 }
}
