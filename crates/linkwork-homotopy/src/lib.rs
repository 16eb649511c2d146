//! linkwork-homotopy: every isolated root of a small dense square polynomial system.
//!
//! A `System` is given as monomials in unknowns x and parameters p. `solve` tracks the
//! paths of a linear-product start system (total degree, or multi-homogeneous on given
//! variable groups) with the gamma trick; `solve_parameter` tracks only the generic number
//! of paths from stored roots at generic parameters. Paths run on projective patches (an
//! endpoint at infinity is recognised, not lost), in parallel with rayon; every finite
//! endpoint is polished and certified by Smale's alpha test, real ones as real.

// dense kernels index several arrays by the same i, j: index loops read as the maths
#![allow(clippy::needless_range_loop)]

pub mod certify;
pub mod homotopy;
pub mod linear;
pub mod polynomial;
pub mod random;
pub mod solve;
pub mod track;

pub use certify::{Affine, AlphaTest, ALPHA0};
pub use homotopy::Groups;
pub use num_complex::Complex64 as C64;
pub use polynomial::{Polynomial, System, SystemError, Term};
pub use solve::{certify_points, solve, solve_parameter, track_parameter, Options, Root, Solutions};
pub use track::{PathStatus, TrackOptions};
