//! Solving at one time: at the drawing's time directly, elsewhere by following the branch
//! from there.

use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::acceleration::solve_acceleration;
use crate::solve::position::solve_position;
use crate::solve::velocity::solve_velocity;
use crate::sweep::stepping::singular::Event;
use crate::sweep::stepping::tracking::{OnSingular, Tracker};
use crate::sweep::time_loop::check_times;

/// Sub-steps allowed to follow the drivers from the drawing to a solve's time.
pub const ALONG_BUDGET: usize = 200_000;

/// The time of the drawing: 0, or the nearest time the drivers are defined at.
pub fn drawing_time(model: &Model) -> f64 {
    let (lo, hi) = model.time_domain;
    0.0f64.max(lo).min(hi)
}

/// Position, velocity and acceleration at t on the drawing's branch: assembled at the
/// drawing's time from the drawing, then followed along the drivers to t by the careful
/// path (certified sub-steps, crossings stepped over and reported), so that a time far
/// from the drawing gets the drawing's configuration continued, not whatever Newton finds
/// from the drawing. Returns the events met on the way. `poll` may return false to cancel.
pub fn solve_along(
    model: &Model,
    data: &mut Data,
    t: f64,
    poll: &mut dyn FnMut() -> bool,
) -> Result<(crate::solve::position::PositionInfo, Vec<Event>), SolveError> {
    check_times(model, &[t])?;
    let t_ref = drawing_time(model);
    data.q.copy_from_slice(&model.q_start);
    let info = solve(model, data, t_ref)?;
    if t == t_ref {
        return Ok((info, Vec::new()));
    }
    let mut tracker = Tracker::new(model, OnSingular::Continue, false);
    tracker.det_prev = info.det_sign;
    let from = crate::sweep::stepping::branch::State::capture(data, t_ref, info);
    let info = tracker.follow(model, data, from, t, ALONG_BUDGET, poll)?;
    Ok((info, std::mem::take(&mut tracker.events)))
}

/// Position, velocity and acceleration at one time, from data.q as the starting guess.
pub fn solve(
    model: &Model,
    data: &mut Data,
    t: f64,
) -> Result<crate::solve::position::PositionInfo, SolveError> {
    check_times(model, &[t])?;
    data.with_velocity = true;
    let info = solve_position(model, data, t, 0, true)?;
    solve_velocity(model, data, t, 0)?;
    solve_acceleration(model, data, t, 0)?;
    Ok(info)
}
