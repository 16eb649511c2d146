//! The stages of one time step on a compiled model: assembly of Phi, Phi_q, nu and
//! gamma; position (Newton), velocity, acceleration, forces; the plan's closed forms.

pub mod acceleration;
pub mod assembly;
pub mod closed_form;
pub mod deflation;
pub mod events;
pub mod forces;
pub mod position;
pub mod velocity;
