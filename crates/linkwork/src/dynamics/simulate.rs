//! The entry point: a simulation over the asked times from consistent initial conditions,
//! by the method asked, its rows stored with their energy and drift.

use crate::dynamics::augmented::Equilibration;
use crate::dynamics::initial::make_consistent;
use crate::dynamics::options::{Method, SimOptions};
use crate::dynamics::output::SimOutput;
use crate::dynamics::record::{store_state, StepInfo};
use crate::dynamics::system::System;
use crate::dynamics::travel::check_start;
use crate::dynamics::{gen_alpha, rk};
use crate::error::SolveError;
use crate::model::Model;

/// Checks the times: finite, strictly increasing, inside every law's domain.
pub fn check_times(model: &Model, times: &[f64]) -> Result<(), SolveError> {
    if times.is_empty() {
        return Err(SolveError::Times { step: 0, problem: "no times given".into() });
    }
    let (lo, hi) = model.time_domain;
    for (k, &t) in times.iter().enumerate() {
        if !t.is_finite() {
            return Err(SolveError::Times { step: k, problem: format!("time {t} is not finite") });
        }
        if k > 0 && t <= times[k - 1] {
            return Err(SolveError::Times {
                step: k,
                problem: format!("a simulation's times must increase strictly ({} then {t})", times[k - 1]),
            });
        }
        if t < lo || t > hi {
            return Err(SolveError::Times {
                step: k,
                problem: format!("time {t} is outside the interval [{lo}, {hi}] every law is defined on"),
            });
        }
    }
    Ok(())
}

/// Simulates the model over `times` (strictly increasing) from q0, qd0 (default: the
/// drawing at rest), made consistent with the constraints first (those given within
/// `ic_tol`). `poll(rows
/// done)` is called every few steps and may return false to cancel. On error, `out`
/// keeps the rows done (`n_done`).
pub fn simulate(
    model: &Model,
    times: &[f64],
    q0: Option<&[f64]>,
    qd0: Option<&[f64]>,
    opts: &SimOptions,
    out: &mut SimOutput,
    poll: &mut dyn FnMut(usize) -> bool,
) -> Result<(), SolveError> {
    opts.check().map_err(|problem| SolveError::Settings { problem })?;
    check_times(model, times)?;
    let n = model.n_coords;
    for (what, v) in [("q0", q0), ("qd0", qd0)] {
        if let Some(v) = v {
            if v.len() != n || !v.iter().all(|x| x.is_finite()) {
                let bad = v.iter().filter(|x| !x.is_finite()).count();
                let problem = if v.len() != n {
                    format!("{what} must hold {n} values (one per coordinate), not {}", v.len())
                } else {
                    format!("{what} must be finite: {bad} of its {n} values are not")
                };
                return Err(SolveError::Settings { problem });
            }
        }
    }
    let mut q = q0.map_or_else(|| model.q_start.clone(), <[f64]>::to_vec);
    let mut qd = qd0.map_or_else(|| vec![0.0; n], <[f64]>::to_vec);
    let mut sys = System::new(model);
    // what was given is checked against ic_tol; the defaults (the drawing, at rest) are
    // made consistent whatever it takes (drivers' positions and rates at times[0])
    let tol = |given: bool| if given { opts.ic_tol } else { f64::INFINITY };
    out.moved =
        make_consistent(model, &mut sys, &mut q, &mut qd, times[0], tol(q0.is_some()), tol(qd0.is_some()))?;
    check_start(model, &q, &qd)?;
    let start = StepInfo { step: 0.0, iterations: 0, work: 0.0, equilibration: Equilibration::New };
    store_state(model, &mut sys, out, 0, times[0], &mut q, &mut qd, start, opts.accelerations)?;
    match opts.method {
        Method::Rk8 => rk::integrate(model, &mut sys, opts, &q, &qd, out, poll),
        Method::GenAlpha => gen_alpha::integrate(model, &mut sys, opts, &q, &qd, out, poll),
    }
}
