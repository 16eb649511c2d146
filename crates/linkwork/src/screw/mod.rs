//! Screw theory for planar mechanisms: twists, wrenches, join and meet, serial arms,
//! instant centres and the screw systems of closed loops.
//!
//! Conventions (world frame, lengths in the model's units):
//! - a twist T = (vx, vy; w) is the velocity of the body point at the world origin and
//!   the angular rate, so the point p moves at (vx - w p_y, vy + w p_x);
//! - the axis screw of a revolute joint at (x, y), unit rate: $ = (y, -x; 1); a
//!   prismatic joint along the unit direction (ux, uy): $ = (ux, uy; 0);
//! - a wrench W = (fx, fy; m) is a force and its moment about the world origin; the
//!   line screw of a unit force at angle t through (x, y) is
//!   S = (cos t, sin t; x sin t - y cos t);
//! - the reciprocal product (virtual power) is W . T = fx vx + fy vy + m w;
//! - points and lines are homogeneous 3-vectors: the point (X, Y, W) is (X/W, Y/W), or
//!   the direction (X, Y) at infinity when W = 0; the line (a, b, c) is a x + b y + c = 0.
//!   A twist's pole (where its velocity vanishes) is the point (-vy, vx, w); a wrench's
//!   line of action is the line (-fy, fx, m), whose value at a point is the wrench's
//!   moment about that point. Then W . T = line . pole, join(p, q) = p x q and
//!   meet(l, k) = l x k.
//!
//! Files: `screws` (twists, wrenches), `projective` (points, lines, join, meet),
//! `frames` (poses, transport between frames), `joints` (the joints of a description as
//! screws), `arm` (serial arms), `centres` (instant centres, Kennedy), `system` (screw
//! systems and the singularities of closed loops).

mod arm;
mod centres;
mod error;
mod frames;
mod joints;
mod projective;
mod screws;
mod system;

pub use arm::{ArmJoint, ArmState, Barycentre, PairPoints, SerialArm};
pub use centres::{centres_by_kennedy, centres_from_velocities, InstantCentres};
pub use error::ScrewError;
pub use frames::Pose;
pub use joints::{JointKind, MechanismJoint, MechanismJoints};
pub use projective::{join, meet, Gauge, Line, Point};
pub use screws::{Twist, Wrench};
pub use system::{loop_singularity, LoopSingularity, ScrewSystem};

/// Geometry closer than this to degenerate (relative, after scaling by the problem's
/// length) counts as degenerate: coincident points, parallel lines, collinear joints.
pub const DEGENERATE: f64 = 1e-12;
