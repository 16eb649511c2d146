//! Limits of motion of a driven input, found numerically for any mechanism: the input
//! is made the sweep parameter (its law replaced by the identity, every other driver
//! held at its value) and swept away from the start both ways until the tracker meets a
//! limit of motion, or a whole turn (angles) or the search range (lengths) is covered.
//! Each limit is located where Newton stops converging, to about round-off in the input.

use crate::error::{ModelError, SolveError};
use crate::input::description::DriverDesc;
use crate::input::motion::MotionLaw;
use crate::model::data::Data;
use crate::model::Model;
use crate::sweep::outputs::{Request, SweepOutput};
use crate::sweep::stepping::singular::{Event, EventKind};
use crate::sweep::stepping::tracking::OnSingular;
use crate::sweep::time_loop::sweep;

/// The range of one driver's input over which the mechanism assembles, on the branch of
/// the given configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionLimits {
    pub driver: String,
    /// whether the input is an angle (rad) or a length
    pub angle: bool,
    /// the input's value at the start
    pub start: f64,
    /// the limits below and above the start; None: none within the search range
    pub lower: Option<f64>,
    pub upper: Option<f64>,
    /// an angle input that turns a whole revolution both ways without a limit
    pub full_rotation: bool,
    /// how far each way was searched
    pub range: f64,
    /// the events met on the way (limits, bifurcations), in the order found
    pub events: Vec<Event>,
}

/// Why limits could not be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LimitsError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Solve(#[from] SolveError),
    #[error("'{0}' is not a driver of the model")]
    NotADriver(String),
}

/// Searches the limits of driver `driver`'s input, from configuration `q` (assembled
/// near it) at time `t`. `range`: how far to search each way (default: a turn for an
/// angle, 4 L for a length); `steps`: sweep steps each way (default 720).
pub fn motion_limits(
    model: &Model,
    driver: &str,
    t: f64,
    q: &[f64],
    range: Option<f64>,
    steps: Option<usize>,
) -> Result<MotionLimits, LimitsError> {
    let mut desc = model.description.clone();
    let index = desc
        .drivers
        .iter()
        .position(|d| d.name() == driver)
        .ok_or_else(|| LimitsError::NotADriver(driver.into()))?;
    let angle = desc.drivers[index].is_angle();
    // the description's laws are as read (spline coefficients, compiled expressions not
    // computed yet): evaluate a prepared copy
    let value_at = |d: &DriverDesc| -> Result<f64, ModelError> {
        let fail =
            |problem: String| ModelError::Constraint { kind: "driver", name: d.name().into(), problem };
        let mut law = d.law().clone();
        law.prepare().map_err(fail)?;
        let value = law.eval(t)[0];
        if !value.is_finite() {
            return Err(fail(format!("its law is not finite at t = {t}")));
        }
        Ok(value)
    };
    let start = value_at(&desc.drivers[index])?;
    for (i, d) in desc.drivers.iter_mut().enumerate() {
        let value = value_at(d)?;
        // the swept input: value = time; the others held where they are at t
        *d.law_mut() = if i == index {
            MotionLaw::Linear { value: 0.0, rate: 1.0 }
        } else {
            MotionLaw::Constant { value }
        };
    }
    desc.loads.clear();
    let swept = Model::with_options(desc, model.options.clone())?;

    // assemble at the start on the given branch
    let mut data = Data::new(&swept);
    data.q.copy_from_slice(q);
    crate::sweep::single_time::solve(&swept, &mut data, start)?;
    let q0 = data.q.clone();

    let range = range.unwrap_or(if angle { 2.0 * std::f64::consts::PI } else { 4.0 * model.length_scale });
    let n = steps.unwrap_or(720).max(2);
    let mut events = Vec::new();
    let mut reach = |sign: f64| -> Result<Option<f64>, LimitsError> {
        let times: Vec<f64> = (0..=n).map(|k| start + sign * range * k as f64 / n as f64).collect();
        let mut data = Data::new(&swept);
        data.q.copy_from_slice(&q0);
        let request = Request { on_singular: OnSingular::Continue, ..Request::default() };
        let mut out = SweepOutput::with_request(&swept, &times, request);
        let result = sweep(&swept, &mut data, &times, &mut out, 0, &mut |_| true);
        let limit = out.events.iter().find(|e| e.kind == EventKind::Limit).map(|e| e.time);
        events.append(&mut out.events);
        match (result, limit) {
            (Ok(()), _) => Ok(None),
            (Err(SolveError::Event { .. }), Some(time)) => Ok(Some(time)),
            (Err(e), _) => Err(e.into()),
        }
    };
    let upper = reach(1.0)?;
    let lower = reach(-1.0)?;
    Ok(MotionLimits {
        driver: driver.to_string(),
        angle,
        start,
        lower,
        upper,
        full_rotation: angle && lower.is_none() && upper.is_none(),
        range,
        events,
    })
}
