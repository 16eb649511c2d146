pub mod acceleration;
pub mod assembly;
pub mod blocks;
pub mod forces;
pub mod position;
pub mod velocity;
