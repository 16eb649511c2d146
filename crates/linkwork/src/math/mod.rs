//! The numerical kernels; they know nothing of mechanisms: jets, LU (small dense and
//! sparse replayed), the linear-solver seam, pivots, angles, scalar roots and minima.

pub mod angle;
pub mod jet;
pub mod linear;
pub mod minimize;
pub mod pivots;
pub mod roots;
pub mod small_lu;
pub mod sparse_lu;
