//! Sweeps: the time loop (`time_loop`), what it keeps (`outputs`), solving at one time
//! (`single_time`) and how it steps (`stepping`), many sweeps on
//! threads (`batch`), the branch a design is asked for (`branches`), and a study's designs
//! as variants of one compiled model (`variants`).

pub mod batch;
pub mod branches;
pub mod lanes;
pub mod outputs;
pub mod single_time;
pub mod stepping;
pub mod time_loop;
pub mod variants;

pub use outputs::{Outputs, Request, SweepOutput};
pub use single_time::{drawing_time, solve, solve_along, ALONG_BUDGET};
pub use time_loop::{check_times, sweep};
