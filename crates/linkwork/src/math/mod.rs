pub mod angle;
pub mod jet;
pub mod linear;
pub mod pivots;
pub mod small_lu;
pub mod sparse_lu;
