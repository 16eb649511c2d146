//! Implicit index-3 generalized-alpha (Arnold and Bruls 2007; Chung and Hulbert's
//! parameters from rho_inf): with the pseudo-acceleration a,
//!   (1 - a_m) a_{n+1} + a_m a_n = (1 - a_f) qdd_{n+1} + a_f qdd_n,
//!   q_{n+1} = q_n + h qd_n + h^2 (1/2 - beta) a_n + h^2 beta a_{n+1},
//!   qd_{n+1} = qd_n + h (1 - gamma) a_n + h gamma a_{n+1},
//! and the equations of motion and Phi(q, t) = 0 at t_{n+1} solved by Newton in the
//! position increment on the iteration matrix
//!   [[M / (beta' h^2) + C gamma' / (beta' h) + K, Phi_q^T], [Phi_q, 0]]
//! (beta' = beta (1 - a_f) / (1 - a_m), gamma' likewise; K, C the exact tangents of
//! M qdd - Q_A; the constraint forces' own stiffness left out: a quasi-Newton), equilibrated
//! at every factorization. The local error is estimated as Zienkiewicz and Xie do for
//! Newmark: (beta - 1/6) h^2 (a_{n+1} - a_n), the leading term of the position's error, and
//! the step adapted to it (order 3 in h). Steps are cut to land on the asked times.
#![allow(clippy::needless_range_loop)] // numeric kernels: one index runs over several arrays

use crate::dynamics::applied::{applied_force, tangents};
use crate::dynamics::augmented::{Equilibration, REGULARISE_BELOW};
use crate::dynamics::energy::{kinetic, load_power, potential};
use crate::dynamics::events::Watch;
use crate::dynamics::mass::mass_times;
use crate::dynamics::options::{relative_sizes, SimOptions};
use crate::dynamics::output::SimOutput;
use crate::dynamics::record::{store_state, StepInfo};
use crate::dynamics::system::{max_abs, System};
use crate::dynamics::travel::stop_at;
use crate::error::SolveError;
use crate::model::Model;
use crate::solve::assembly::nu_into;
use crate::solve::events::EventKind;

/// Newton iterations per step before it is retried smaller.
const MAX_NEWTON: usize = 12;
const SAFETY: f64 = 0.9;
const MIN_FACTOR: f64 = 0.2;
const MAX_FACTOR: f64 = 5.0;
const POLL_EVERY: usize = 64;
/// The most T + V - W may change in one step through a singular configuration (its
/// iterations' pivots regularised), as a part of the energies' size: there, at coarse
/// tolerances, the index-3 iterations can converge to rates off the motion (a
/// parallelogram's crank turned from 111 rad/s forward to 284 back in one step at rtol
/// 5e-3, spun up to 411 rad/s from 70 at 4.4e-2, or stopped), which the positions' error
/// estimate does not see, nor do shorter retries mend. The run stops there with a named
/// error, the rows before kept. Elsewhere the method's own damping of a fast mode may take
/// a large part of a small energy in a step (a stiff spring settling), so it is not judged.
const BALANCE_STEP: f64 = 0.1;
/// The most T + V - W may rise above its lowest value after the first singular
/// configuration, as a part of the largest energies so far. The method's damping only
/// lowers it; after a crossing its iterations can add energy a few per cent a step, and
/// over many crossings multiply it (a parallelogram spun from 51 to 92 rad/s in 1 s at rtol
/// 1.7e-3), which no single step's check sees.
const BALANCE_RISE: f64 = 0.05;
/// The most T + V - W may fall below its highest value after the first singular
/// configuration, as a part of the largest energies so far. The crossings' iterations
/// disturb the rates both ways and the method's damping then takes the disturbance: a
/// parallelogram at rtol 1.2e-3 lost 1 % a crossing, 22 % in 1 s (its crank 118 rad/s
/// down to 105, 7 rad behind the motion), where steps cut to 1 ms hold T + V to 2e-4. The
/// damping of a conservative mechanism's own motion takes far less (0.3 % of the energies
/// between rows of a parallelogram at rtol 1e-4).
const BALANCE_FALL: f64 = 0.05;
/// The most a row's projection onto the constraints may change T + V, as a part of the
/// energies (theirs, or the largest so far where more). The iterations stop with |phi| up
/// to 1e-3 atol; a row that lands within about that of a change point can be projected onto
/// the other branch, its rates onto that branch's tangent (a parallelogram's crank from 78
/// rad/s to 56 and its rocker to 39, T 54 % low, at rtol 5.3e-2). Such a step is taken
/// again with its iterations run to tol_residual, which leaves the positions' projection
/// nothing to move across; a change left after that is the rates' own projection, kept.
const ROW_BALANCE: f64 = 0.01;

/// The method's constants from rho_inf.
#[derive(Debug, Clone, Copy)]
pub struct Coefficients {
    pub alpha_m: f64,
    pub alpha_f: f64,
    pub beta: f64,
    pub gamma: f64,
}

impl Coefficients {
    pub fn new(rho_inf: f64) -> Coefficients {
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 + alpha_f - alpha_m;
        let beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
        Coefficients { alpha_m, alpha_f, beta, gamma }
    }
}

/// Integrates from out's row 0 (q, qd consistent at times[0]) to the last time.
pub fn integrate(
    model: &Model,
    sys: &mut System,
    opts: &SimOptions,
    q: &[f64],
    qd: &[f64],
    out: &mut SimOutput,
    poll: &mut dyn FnMut(usize) -> bool,
) -> Result<(), SolveError> {
    let (n, m) = (model.n_coords, model.n_rows);
    let co = Coefficients::new(opts.rho_inf);
    let times = out.times.clone();
    let t_end = *times.last().expect("times checked non-empty");
    let (mut q, mut qd) = (q.to_vec(), qd.to_vec());
    let (mut qdd, mut lambda) = (vec![0.0; n], vec![0.0; m]);
    let mut t = times[0];
    let mut watch = Watch::new(model, opts.stop_at_travel_end);
    watch.pivot(sys.accelerations(model, &q, &qd, t, &mut qdd, &mut lambda, Equilibration::New).ratio);
    watch.accepted(model, sys, &times, t, &q, &qd, &qdd, &mut out.events);
    let mut a = qdd.clone();
    let mut nu = vec![0.0; m];
    let power = |sys: &System, lambda: &[f64], nu: &mut [f64], t: f64| {
        nu_into(model, t, nu);
        load_power(model, sys.frames(), t) - lambda.iter().zip(nu.iter()).map(|(l, v)| l * v).sum::<f64>()
    };
    sys.set_state(&q, &qd);
    let mut p_old = power(sys, &lambda, &mut nu, t);
    let mut balance = kinetic(model, sys.frames()) + potential(model, sys.frames());
    let mut work = 0.0;
    let scale: Vec<f64> = model.col_scale.iter().map(|s| opts.atol * s).collect();
    let sizes = relative_sizes(model);
    // the first step: a small fraction of the first interval, then adapted
    let mut h_nat = opts.h0.unwrap_or(((times[1.min(times.len() - 1)] - t).max(t_end - t) * 1e-3).max(1e-9));
    h_nat = h_nat.min(opts.h_max);
    let (mut q1, mut qd1, mut qdd1, mut lambda1, mut a1) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; m], vec![0.0; n]);
    let (mut qa, mut mq, mut pl) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut phi = vec![0.0; m];
    let mut rhs = vec![0.0; n + m];
    let mut next = 1;
    // the smallest pivot ratio of the last step tried (its Newton iterations)
    let mut newton_pivot = f64::INFINITY;
    // the lowest and highest T + V - W since the first singular configuration (a step
    // whose iterations met one, or one the watch reported; NaN before), and the largest
    // energies so far
    let (mut lowest, mut highest) = (f64::NAN, f64::NAN);
    // the smallest pivot ratio of those steps
    let mut met_pivot = f64::INFINITY;
    // the events already looked at for a crossing
    let mut seen = out.events.len();
    let mut peak = kinetic(model, sys.frames()) + potential(model, sys.frames()).abs();
    // the step to the next row is under way with its iterations run to tol_residual
    let mut tight = false;
    while next < times.len() {
        if out.n_steps >= opts.max_steps {
            return Err(step_error(
                out,
                t,
                h_nat,
                format!("{} steps taken, the most allowed (max_steps)", out.n_steps),
            ));
        }
        if out.n_steps % POLL_EVERY == 0 && !poll(out.n_done) {
            return Err(SolveError::Cancelled { step: out.n_done });
        }
        let min_step = 10.0 * (t.abs() * f64::EPSILON).max(f64::MIN_POSITIVE);
        let to_next = times[next] - t;
        let h = opts.step_toward(h_nat, to_next);
        if h < min_step {
            let mut why = String::from("the step size fell below its floor (10 ulp of t)");
            if newton_pivot < REGULARISE_BELOW {
                // the index-3 iterations at a bifurcation: their corrections along the rows'
                // dependency converge too slowly for a tight tolerance
                why += &format!(
                    ", at a singular configuration (pivot ratio {newton_pivot:.1e}) that generalized-alpha \
                     cannot pass at this tolerance: method=\"rk8\" passes it, as may a larger atol"
                );
            }
            return Err(step_error(out, t, h, why));
        }
        let lands = h == to_next;
        let t1 = if lands { times[next] } else { t + h };
        let beta_p = co.beta * (1.0 - co.alpha_f) / (1.0 - co.alpha_m);
        let gamma_p = co.gamma * (1.0 - co.alpha_f) / (1.0 - co.alpha_m);
        // predictor: the acceleration and multipliers kept
        qdd1.copy_from_slice(&qdd);
        lambda1.copy_from_slice(&lambda);
        let pseudo = |qdd1: &[f64], a1: &mut [f64]| {
            for i in 0..n {
                a1[i] = ((1.0 - co.alpha_f) * qdd1[i] + co.alpha_f * qdd[i] - co.alpha_m * a[i])
                    / (1.0 - co.alpha_m);
            }
        };
        pseudo(&qdd1, &mut a1);
        for i in 0..n {
            q1[i] = q[i] + h * qd[i] + h * h * ((0.5 - co.beta) * a[i] + co.beta * a1[i]);
            qd1[i] = qd[i] + h * ((1.0 - co.gamma) * a[i] + co.gamma * a1[i]);
        }
        let (c_m, c_c) = (1.0 / (beta_p * h * h), gamma_p / (beta_p * h));
        let mut converged = false;
        let mut iterations = 0;
        let mut last_pivot = f64::INFINITY;
        newton_pivot = f64::INFINITY;
        for it in 1..=MAX_NEWTON {
            iterations = it;
            sys.set_state(&q1, &qd1);
            sys.aug.fill(model, &sys.data.frames, &q1, t1, c_m, &mut phi);
            applied_force(model, &sys.data.frames, t1, &mut qa);
            mass_times(model, &sys.data.frames, &qdd1, &mut mq);
            sys.aug.jacobian_transpose_times(&lambda1, &mut pl);
            for i in 0..n {
                rhs[i] = qa[i] - mq[i] - pl[i];
            }
            for (r, p) in rhs[n..].iter_mut().zip(&phi) {
                *r = -p;
            }
            let System { aug, loads, .. } = &mut *sys;
            tangents(model, loads, &q1, &qd1, &qdd1, t1, &mut |b| aug.add_tangent(&b, 1.0, c_c));
            // the watch sees the last iteration's (the predictor's states are off the path);
            // the iterations after a step's first keep its equilibration
            let equilibration = if it > 1 { Equilibration::Kept } else { Equilibration::New };
            last_pivot = sys.aug.factor_solve(&mut rhs, equilibration).ratio;
            newton_pivot = newton_pivot.min(last_pivot);
            if !rhs.iter().all(|v| v.is_finite()) {
                break;
            }
            let mut size = 0.0f64;
            for i in 0..n {
                let d = rhs[i];
                q1[i] += d;
                qd1[i] += c_c * d;
                qdd1[i] += c_m * d;
                size = size.max(d.abs() / (scale[i] + opts.rtol * q1[i].abs().min(sizes[i])));
            }
            for (l, d) in lambda1.iter_mut().zip(&rhs[n..]) {
                *l += d;
            }
            let phi_tol = if tight {
                model.options.tol_residual
            } else {
                model.options.tol_residual.max(1e-3 * opts.atol)
            };
            if size <= 1e-3 && max_abs(&phi) <= phi_tol {
                converged = true;
                break;
            }
        }
        out.n_steps += 1;
        if converged {
            watch.pivot(last_pivot);
        }
        if !converged {
            out.n_rejected += 1;
            h_nat = h * 0.25;
            continue;
        }
        pseudo(&qdd1, &mut a1);
        // Zienkiewicz-Xie: the position error's leading term, (beta - 1/6) h^2 (a1 - a)
        let c_err = (co.beta - 1.0 / 6.0).abs() * h * h;
        let err = (0..n).fold(0.0f64, |e, i| {
            let size = q1[i].abs().max(q[i].abs()).min(sizes[i]);
            e.max(c_err * (a1[i] - a[i]).abs() / (scale[i] + opts.rtol * size))
        });
        let factor = if err == 0.0 { MAX_FACTOR } else { MAX_FACTOR.min(SAFETY * err.powf(-1.0 / 3.0)) };
        if err > 1.0 {
            out.n_rejected += 1;
            h_nat = h * factor.max(MIN_FACTOR);
            continue;
        }
        sys.set_state(&q1, &qd1);
        let p_new = power(sys, &lambda1, &mut nu, t1);
        let dw = 0.5 * h * (p_old + p_new);
        let (t1k, v1) = (kinetic(model, sys.frames()), potential(model, sys.frames()));
        if lands {
            // the row, projected; kept only if the step is
            let (mut qs, mut qds) = (q1.clone(), qd1.clone());
            let info = StepInfo {
                step: h,
                iterations: iterations as u32,
                work: work + dw,
                equilibration: Equilibration::New,
            };
            store_state(model, sys, out, next, t1, &mut qs, &mut qds, info, opts.accelerations)?;
            let moved = out.kinetic[next] + out.potential[next] - t1k - v1;
            let size = (t1k + v1.abs() + (work + dw).abs()).max(peak);
            if moved.abs() > ROW_BALANCE * size && !tight {
                out.n_done = next;
                out.n_rejected += 1;
                tight = true;
                h_nat = h;
                continue;
            }
        }
        // accepted
        q.copy_from_slice(&q1);
        qd.copy_from_slice(&qd1);
        qdd.copy_from_slice(&qdd1);
        lambda.copy_from_slice(&lambda1);
        a.copy_from_slice(&a1);
        work += dw;
        let size = balance.abs().max(t1k + v1.abs()) + work.abs() + dw.abs();
        let change = t1k + v1 - work - balance;
        // the rise of T + V - W above its lowest, and its fall below its highest, since the
        // first singular configuration met (a step whose iterations met a small pivot, or a
        // crossing the watch reported)
        if newton_pivot < REGULARISE_BELOW {
            if lowest.is_nan() {
                (lowest, highest) = (balance, balance);
            }
            met_pivot = met_pivot.min(newton_pivot);
        }
        peak = peak.max(t1k + v1.abs()).max(work.abs());
        // the fall from the mean of two steps' ends: the steps after a crossing alternate
        // a few per cent up and down
        let mean = 0.5 * (t1k + v1 - work + balance);
        let (risen, fallen) = (t1k + v1 - work - lowest, highest - mean);
        let left = if risen > BALANCE_RISE * peak {
            Some(("rose", risen))
        } else if fallen > BALANCE_FALL * peak {
            Some(("fell", fallen))
        } else {
            None
        };
        if let Some((how, moved)) = left {
            let which = match out.events.iter().find(|e| e.kind == EventKind::Bifurcation) {
                Some(e) if !met_pivot.is_finite() => format!("passed at t = {:.6}", e.time),
                _ => format!("pivot ratio {met_pivot:.1e}"),
            };
            let why = format!(
                "T + V - W {how} by {moved:.3e} ({:.0} % of the energies) since the first singular \
                 configuration passed: the iterations there converged to rates off the motion, at a \
                 singular configuration ({which}) that generalized-alpha cannot pass at this tolerance: \
                 method=\"rk8\" passes it",
                100.0 * moved / peak
            );
            out.n_done = next;
            return Err(step_error(out, t1, h, why));
        }
        if change.abs() > BALANCE_STEP * size && newton_pivot < REGULARISE_BELOW {
            let why = format!(
                "one step changed T + V - W by {change:.3e} ({:.0} % of the energies): the positions' \
                 iterations converged to rates off the motion, at a singular configuration (pivot ratio \
                 {newton_pivot:.1e}) that generalized-alpha cannot pass at this tolerance: method=\"rk8\" \
                 passes it",
                100.0 * change.abs() / size
            );
            out.n_done = next;
            return Err(step_error(out, t1, h, why));
        }
        let before = balance;
        balance = t1k + v1 - work;
        if !lowest.is_nan() {
            (lowest, highest) = (lowest.min(balance), highest.max(mean));
        }
        p_old = p_new;
        t = t1;
        out.n_evaluations += iterations;
        if !lands || h >= h_nat {
            h_nat = (h * factor).min(opts.h_max);
        }
        if lands {
            next += 1;
            tight = false;
        }
        let stop = watch.accepted(model, sys, &times, t, &q, &qd, &qdd, &mut out.events);
        // a crossing the watch found in this step (its iterations need not have met a small
        // pivot where the step passed it at a distance): the balance from the step's start on
        if lowest.is_nan() && out.events[seen..].iter().any(|e| e.kind == EventKind::Bifurcation) {
            (lowest, highest) = (before.min(balance), before.max(balance));
        }
        seen = out.events.len();
        if let Some(t_stop) = stop {
            stop_at(out, t_stop);
            return Ok(());
        }
    }
    watch.finish(model, sys, &times, &mut out.events);
    Ok(())
}

fn step_error(out: &SimOutput, t: f64, h: f64, why: String) -> SolveError {
    SolveError::Step { step: out.n_done, time: t, h, why: format!("{why}; {} steps taken", out.n_steps) }
}
