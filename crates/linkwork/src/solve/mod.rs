pub mod acceleration;
pub mod assembly;
pub mod closed_form;
pub mod forces;
pub mod position;
pub mod velocity;
