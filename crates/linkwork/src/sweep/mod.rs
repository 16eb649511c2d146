//! Sweeps: the time loop (`time_loop`) and how it steps (`stepping`), many sweeps on
//! threads (`batch`), the branch a design is asked for (`branches`), and a study's designs
//! as variants of one compiled model (`variants`).

pub mod batch;
pub mod branches;
pub mod stepping;
pub mod time_loop;
pub mod variants;

pub use time_loop::{
    check_times, drawing_time, solve, solve_along, sweep, Outputs, Request, SweepOutput, ALONG_BUDGET,
};
