//! Limits of a slider's motion in a simulation, found from the accepted steps and located
//! between them on the interpolant of the steps' ends (`events`):
//! - the end of the travel a prismatic joint is given (`travel = [min, max]`, its slide from
//!   the start, as a translation driver's): where the slide crosses min or max, an
//!   "end_of_travel" event; the simulation stops there (`SimOptions::stop_at_travel_end`,
//!   the rows up to it kept) or goes on through it (no stop is modelled), reporting it;
//! - a slider's geometric limit (the end of a slider-crank's stroke): where its rate changes
//!   sign while the mechanism moves on and its slide is stationary along every motion the
//!   joints allow there, a "lock" of that slider (as a sweep reports an output's).

use crate::dynamics::output::SimOutput;
use crate::error::SolveError;
use crate::model::slider::sliders;
use crate::model::Model;

/// A slide reversal is the slider's geometric limit when the part of its gradient along
/// the motions the joints allow is below this fraction of the whole: zero at a stroke's
/// end up to the interpolant's error (1e-6 and less on the tests), of order one where
/// forces turn a slider that could go on.
pub const GEOMETRIC_BELOW: f64 = 1e-2;

/// Refuses a start outside a slider's travel.
pub fn check_start(model: &Model, q: &[f64], qd: &[f64]) -> Result<(), SolveError> {
    for s in sliders(model) {
        let Some([lo, hi]) = s.travel else { continue };
        let (x, _) = s.slide(q, qd);
        if x < lo || x > hi {
            return Err(SolveError::Settings {
                problem: format!(
                    "prismatic joint '{}' starts at slide {x:.6e}, outside its travel [{lo}, {hi}] \
                     (the slide from the drawing)",
                    s.name
                ),
            });
        }
    }
    Ok(())
}

/// A simulation stopped at t by a travel's end: the rows asked after it are dropped.
pub fn stop_at(out: &mut SimOutput, t: f64) {
    out.n_done = out.n_done.min(out.times.partition_point(|&x| x <= t));
    out.events.sort_by(|a, b| a.time.total_cmp(&b.time));
}
