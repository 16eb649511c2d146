//! The higher-order path: DOP853 (`dop853`) on the index-1 equations of motion,
//! y = (q, qd, W) with y' = (qd, qdd(q, qd, t), P_nc), qdd from the augmented solve at
//! every stage (`System::accelerations`, regularised where the constraints are singular).
//! After every accepted step q and qd are projected onto Phi = 0 and Phi_q qd = nu
//! (coordinate projection, the smallest change in the mass metric), which keeps the drift
//! at round-off and the motion on the manifold it started on. A step whose solves were
//! regularised (a singular crossing) keeps the energy balance it started with
//! (`hold_balance`). Step sizes follow Hairer's
//! error control (the 5th- and 3rd-order estimators combined); results at the asked
//! times come from the dense output of order 7, then projected the same way.
#![allow(clippy::needless_range_loop)] // numeric kernels: one index runs over several arrays

use crate::constraints::loads::Load;
use crate::dynamics::augmented::{Equilibration, REGULARISE_BELOW};
use crate::dynamics::dop853 as tab;
use crate::dynamics::energy::{kinetic, load_power, potential};
use crate::dynamics::events::Watch;
use crate::dynamics::options::{relative_sizes, SimOptions};
use crate::dynamics::output::SimOutput;
use crate::dynamics::record::{store_lanes, store_state, StepInfo};
use crate::dynamics::row_lanes::RowLanes;
use crate::dynamics::system::System;
use crate::dynamics::travel::stop_at;
use crate::error::SolveError;
use crate::math::sparse_lu::LANES;
use crate::model::Model;
use crate::solve::assembly::nu_into;

/// The error scale of component i between two states.
type Scale<'a> = dyn Fn(&[f64], &[f64], usize) -> f64 + 'a;

const SAFETY: f64 = 0.9;
const MIN_FACTOR: f64 = 0.2;
const MAX_FACTOR: f64 = 10.0;
/// Hairer's stiffness test (dop853.f): from every NSTIFF-th accepted step on, h lambda
/// estimated from the last stage and the new point; beyond STIFF_BOUND (DOP853's
/// stability boundary along the negative axis) on STIFF_STEPS tests without six below in
/// a row, the problem is stiff.
const NSTIFF: usize = 1000;
const STIFF_BOUND: f64 = 6.1;
const STIFF_STEPS: usize = 15;
/// `hold_balance` restores the kinetic energy where it is at least this part of the
/// energies (T, V, W_nc, the balance): qd's relative change dT / (2 T) is then well
/// conditioned (near a swing's end, T -> 0, it would amplify the round-off of V).
const HOLD_KINETIC: f64 = 1e-3;
/// `hold_balance` restores at most this part of T: a loss the step's error control
/// allows is far smaller; a larger one is left for the balance to report.
const HOLD_CHANGE: f64 = 1e-6;
/// A step whose end or output rows cannot be projected onto the constraints is taken again
/// this much shorter, at most PROJECTION_RETRIES times in a row (4^-6: its local error,
/// hence its drift, 1e-14 of the first try's).
const RETRY_FACTOR: f64 = 0.25;
const PROJECTION_RETRIES: usize = 6;
/// The most a projected state (a step's end, an output row) may have T + V - W off the
/// balance at its step's start, as a part of the energies' size (`off_balance`). Chosen on
/// 1,000 random runs of the spinning parallelogram at rtol 1e-3 to 1e-2: unchecked, 37 had
/// rows more than 10 % off (their rates on another branch's tangent); with 0.1 one, with
/// 0.03 and 0.01 none more than 5 %, 0.01 leaving the fewest above 2 % (9).
const PROJECTION_BALANCE: f64 = 0.01;
/// Steps between two polls of progress and cancellation.
const POLL_EVERY: usize = 32;

/// The right-hand side and its scratch.
struct Rhs {
    n: usize,
    qdd: Vec<f64>,
    lambda: Vec<f64>,
    nu: Vec<f64>,
    evaluations: usize,
    watch: Watch,
    /// the smallest pivot ratio of the step under way
    step_pivot: f64,
}

impl Rhs {
    /// f = (qd, qdd, P_nc) at (t, y), the augmented matrix equilibrated as `equilibration` says;
    /// false if anything is not finite.
    fn eval(
        &mut self,
        model: &Model,
        sys: &mut System,
        t: f64,
        y: &[f64],
        f: &mut [f64],
        equilibration: Equilibration,
    ) -> bool {
        let n = self.n;
        self.evaluations += 1;
        let pivots = sys.accelerations(
            model,
            &y[..n],
            &y[n..2 * n],
            t,
            &mut self.qdd,
            &mut self.lambda,
            equilibration,
        );
        self.watch.pivot(pivots.ratio);
        self.step_pivot = self.step_pivot.min(pivots.ratio);
        f[..n].copy_from_slice(&y[n..2 * n]);
        f[n..2 * n].copy_from_slice(&self.qdd);
        nu_into(model, t, &mut self.nu);
        let constraint_power: f64 = -self.lambda.iter().zip(&self.nu).map(|(l, v)| l * v).sum::<f64>();
        f[2 * n] = load_power(model, sys.frames(), t) + constraint_power;
        f.iter().all(|v| v.is_finite())
    }
}

/// The half-spacing (of a step's unit interval) of the central difference that gives qdd
/// at the watch's interior samples from the dense output.
const INTERIOR_DX: f64 = 1e-4;

/// Integrates from out's row 0 (stored: q, qd consistent at times[0], work 0) to the last
/// time, storing every asked time. On error the rows done stay in `out`.
pub fn integrate(
    model: &Model,
    sys: &mut System,
    opts: &SimOptions,
    q: &[f64],
    qd: &[f64],
    out: &mut SimOutput,
    poll: &mut dyn FnMut(usize) -> bool,
) -> Result<(), SolveError> {
    let n = model.n_coords;
    let len = 2 * n + 1;
    let times = out.times.clone();
    let t_end = *times.last().expect("times checked non-empty");
    let mut rhs = Rhs {
        n,
        qdd: vec![0.0; n],
        lambda: vec![0.0; model.n_rows],
        nu: vec![0.0; model.n_rows],
        evaluations: 0,
        watch: Watch::new(model, opts.stop_at_travel_end),
        step_pivot: f64::INFINITY,
    };
    let mut y = vec![0.0; len];
    y[..n].copy_from_slice(q);
    y[n..2 * n].copy_from_slice(qd);
    let mut t = times[0];
    let mut k: Vec<Vec<f64>> = vec![vec![0.0; len]; tab::STAGES_EXTENDED];
    let mut f = vec![0.0; len];
    if !rhs.eval(model, sys, t, &y, &mut f, Equilibration::New) {
        return Err(SolveError::NonFinite {
            step: 0,
            time: t,
            what: "the accelerations at the start".into(),
        });
    }
    // the output rows and the event watch factor on a workspace of their own: the sparse
    // LU's pivot order (re-chosen where a pivot fails its threshold) then follows the
    // steps and their dense outputs' stages (computed where a step holds rows or watch
    // samples), and so does the steps' round-off: other times asked change it only there
    let mut aux = System::new(model);
    // a step's rows after its first, projected up to LANES at once on `aux`
    let mut row_lanes = RowLanes::for_model(model, &aux);
    // the accelerations at a step's interior samples for the watch, and the dense output
    // either side of one
    let (mut qdd_j, mut y_dx) = (vec![0.0; n], vec![0.0; len]);
    // T + V - W_nc at the last step's end (W_nc = 0 at the start)
    sys.set_state(q, qd);
    let mut balance = kinetic(model, sys.frames()) + potential(model, sys.frames());
    // the largest T + |V| + |W| so far: the energies' size where they pass through zero
    let mut peak = kinetic(model, sys.frames()) + potential(model, sys.frames()).abs();
    let mut events = Vec::new();
    rhs.watch.accepted(model, &mut aux, &times, t, q, qd, &f[n..2 * n], &mut events);
    // the error's scale per controlled component (q and qd): atol in the model's units
    let abs_scale: Vec<f64> = model.col_scale.iter().chain(&model.col_scale).map(|s| opts.atol * s).collect();
    // and the size the relative part counts (an angle's at most a half-turn; rates' unbounded)
    let sizes: Vec<f64> = relative_sizes(model).into_iter().chain(vec![f64::INFINITY; n]).collect();
    let scale_of =
        |a: &[f64], b: &[f64], i: usize| abs_scale[i] + opts.rtol * a[i].abs().max(b[i].abs()).min(sizes[i]);
    let rms = |v: &[f64], y: &[f64]| {
        (v[..2 * n].iter().enumerate().map(|(i, x)| (x / scale_of(y, y, i)).powi(2)).sum::<f64>()
            / (2 * n) as f64)
            .sqrt()
    };
    let mut h = match opts.h0 {
        Some(h) => h,
        None => {
            // Hairer's starting step: from the sizes of y, f and of f's change
            let (d0, d1) = (rms(&y, &y), rms(&f, &y));
            let h0 = if d0 < 1e-5 || d1 < 1e-5 { 1e-6 } else { 0.01 * d0 / d1 };
            let y1: Vec<f64> = y.iter().zip(&f).map(|(a, b)| a + h0 * b).collect();
            let mut f1 = vec![0.0; len];
            rhs.eval(model, sys, t + h0, &y1, &mut f1, Equilibration::New);
            let df: Vec<f64> = f1.iter().zip(&f).map(|(a, b)| a - b).collect();
            let d2 = rms(&df, &y) / h0;
            let h1 =
                if d1.max(d2) <= 1e-15 { (h0 * 1e-3).max(1e-6) } else { (0.01 / d1.max(d2)).powf(1.0 / 8.0) };
            (100.0 * h0).min(h1)
        }
    }
    .min(opts.h_max);
    let mut next = 1;
    let mut y_new = vec![0.0; len];
    let mut stage = vec![0.0; len];
    let mut dense: Vec<Vec<f64>> = vec![vec![0.0; len]; tab::INTERPOLATOR_POWER];
    let (mut y_out, mut y_end) = (vec![0.0; len], vec![0.0; len]);
    let mut rejected = false;
    // steps taken again in a row because their end or rows could not be projected
    let mut retries = 0;
    let (mut accepted, mut stiff_count, mut nonstiff_count) = (0usize, 0usize, 0usize);
    while next < times.len() {
        if out.n_steps >= opts.max_steps {
            return Err(step_error(
                out,
                t,
                h,
                format!("{} steps taken, the most allowed (max_steps)", out.n_steps),
            ));
        }
        if out.n_steps % POLL_EVERY == 0 && !poll(out.n_done) {
            return Err(SolveError::Cancelled { step: out.n_done });
        }
        // one step from (t, y) with f = y'(t): retried smaller until its error passes
        let min_step = 10.0 * (t.abs() * f64::EPSILON).max(f64::MIN_POSITIVE);
        let (h_step, factor) = loop {
            h = opts.step_toward(h, t_end - t);
            if h < min_step {
                return Err(step_error(out, t, h, "the step size fell below its floor (10 ulp of t)".into()));
            }
            k[0].copy_from_slice(&f);
            rhs.step_pivot = f64::INFINITY;
            let mut finite = true;
            // the stages' matrices equilibrated as the step's first was (its f, at y): within
            // a step the entries' sizes barely change, and the sweeps cost as much as the LU
            for s in 1..tab::STAGES {
                combine(&tab::A[s][..s], &k[..s], h, &y, &mut stage);
                let (head, tail) = k.split_at_mut(s);
                let _ = head;
                finite &= rhs.eval(model, sys, t + tab::C[s] * h, &stage, &mut tail[0], Equilibration::Kept);
                if !finite {
                    break;
                }
            }
            if finite {
                combine(&tab::B, &k[..tab::STAGES], h, &y, &mut y_new);
                let (head, tail) = k.split_at_mut(tab::STAGES);
                let _ = head;
                finite = rhs.eval(model, sys, t + h, &y_new, &mut tail[0], Equilibration::Kept);
            }
            let error = if finite { error_norm(&k, h, &y, &y_new, n, &scale_of) } else { f64::INFINITY };
            out.n_steps += 1;
            if error < 1.0 {
                let mut factor =
                    if error == 0.0 { MAX_FACTOR } else { MAX_FACTOR.min(SAFETY * error.powf(-1.0 / 8.0)) };
                if rejected {
                    factor = factor.min(1.0);
                }
                rejected = false;
                break (h, factor);
            }
            out.n_rejected += 1;
            rejected = true;
            h *= if error.is_finite() { MIN_FACTOR.max(SAFETY * error.powf(-1.0 / 8.0)) } else { 0.25 };
        };
        let t_new = t + h_step;
        // the step's own solves (not the dense output's, which only some steps need)
        let step_pivot = rhs.step_pivot;
        accepted += 1;
        if accepted % NSTIFF == 0 || stiff_count > 0 {
            // h lambda ~ h |f(y_new) - f(stage 12)| / |y_new - stage 12| (both at t + h)
            let (mut num, mut den) = (0.0, 0.0);
            for i in 0..2 * n {
                num += (k[tab::STAGES][i] - k[tab::STAGES - 1][i]).powi(2);
                den += (y_new[i] - stage[i]).powi(2);
            }
            let h_lambda = if den > 0.0 { h_step * (num / den).sqrt() } else { 0.0 };
            if h_lambda > STIFF_BOUND {
                nonstiff_count = 0;
                stiff_count += 1;
                if stiff_count == STIFF_STEPS {
                    return Err(SolveError::Stiff {
                        step: out.n_done,
                        time: t_new,
                        h: h_step,
                        lambda: h_lambda / h_step,
                        steps: STIFF_STEPS,
                        load: stiffest_load(model),
                    });
                }
            } else {
                nonstiff_count += 1;
                if nonstiff_count == 6 {
                    stiff_count = 0;
                }
            }
        }
        // the dense output, where the step holds asked times before its end or the watch
        // samples inside it (a step that moves the mechanism far): its stages on the steps'
        // workspace, before the end's projection there
        let inside = Watch::interior_samples(model, &y[..n], &y_new[..n]);
        if inside > 0 || (next < times.len() && times[next] < t_new) {
            dense_coefficients(
                model, sys, &mut rhs, &mut k, &mut dense, t, h_step, &y, &y_new, &f, &mut stage,
            );
        }
        // the step's end, projected onto the constraints, then the asked times it reached;
        // where either cannot be projected (next to a singular configuration Gauss-Newton
        // stalls on a state as far off the constraints as a coarse tolerance leaves it),
        // the step is taken again shorter, its drift falling as h^8
        y_end.copy_from_slice(&y_new);
        let (qs, rest) = y_end.split_at_mut(n);
        let (_, _, residual, _) = sys.project_state(model, qs, &mut rest[..n], t_new, Equilibration::New);
        let first = next;
        let mut failed = (residual.is_nan() || residual > model.options.tol_residual).then(|| {
            step_error(
                out,
                t_new,
                h_step,
                format!("projection onto the constraints left |phi| = {residual:.3e}"),
            )
        });
        // T and V at the projected end (kept in `sys`'s frames until the balance is taken)
        let (mut t_end, mut v_end) = (f64::NAN, f64::NAN);
        if failed.is_none() {
            (t_end, v_end) = (kinetic(model, sys.frames()), potential(model, sys.frames()));
            failed =
                off_balance(out, t_new, h_step, "the step's end", t_end, v_end, y_end[2 * n], balance, peak);
        }
        while failed.is_none() && next < times.len() && times[next] <= t_new {
            // after the step's first row (its factorization sets the equilibration the
            // others keep), up to LANES rows at once where they are only projected
            let lanes = row_lanes.as_mut().filter(|_| next > first && !opts.accelerations);
            let count = lanes
                .as_ref()
                .map_or(1, |_| times[next..].iter().take(LANES).take_while(|&&tk| tk <= t_new).count());
            if let (true, Some(lanes)) = (count >= 2, lanes) {
                for j in 0..count {
                    let tk = times[next + j];
                    if tk == t_new {
                        y_out.copy_from_slice(&y_new);
                    } else {
                        contd8(&dense, (tk - t) / h_step, &y, &mut y_out);
                    }
                    lanes.load(j, tk, &y_out);
                }
                let info =
                    StepInfo { step: h_step, iterations: 0, work: 0.0, equilibration: Equilibration::Kept };
                let mut check = |out: &SimOutput, k: usize| {
                    let (tr, vr, wr) = (out.kinetic[k], out.potential[k], out.work[k]);
                    off_balance(out, out.times[k], h_step, "an output row", tr, vr, wr, balance, peak)
                };
                let stored;
                (stored, failed) = store_lanes(model, &mut aux, out, lanes, next, count, info, &mut check)?;
                next += stored;
                continue;
            }
            let tk = times[next];
            if tk == t_new {
                y_out.copy_from_slice(&y_new);
            } else {
                contd8(&dense, (tk - t) / h_step, &y, &mut y_out);
            }
            let (qo, rest) = y_out.split_at_mut(n);
            let equilibration = if next > first { Equilibration::Kept } else { Equilibration::New };
            let info = StepInfo { step: h_step, iterations: 0, work: rest[n], equilibration };
            match store_state(model, &mut aux, out, next, tk, qo, &mut rest[..n], info, opts.accelerations) {
                Ok(()) => {
                    let (tr, vr, wr) = (out.kinetic[next], out.potential[next], out.work[next]);
                    failed = off_balance(out, tk, h_step, "an output row", tr, vr, wr, balance, peak);
                    next += 1;
                }
                Err(e @ SolveError::Step { .. }) => failed = Some(e),
                Err(e) => return Err(e),
            }
        }
        if let Some(error) = failed {
            // the rows this step stored are dropped with it
            (next, out.n_done) = (first, first);
            retries += 1;
            if retries > PROJECTION_RETRIES {
                return Err(error);
            }
            out.n_rejected += 1;
            rejected = true;
            h = h_step * RETRY_FACTOR;
            // the step's start evaluated again: its factors' equilibration is the stages'
            if !rhs.eval(model, sys, t, &y, &mut f, Equilibration::New) {
                return Err(step_error(out, t, h_step, "the accelerations are not finite".into()));
            }
            continue;
        }
        retries = 0;
        // the watch at the step's interior samples (accelerations there on the rows'
        // workspace), in order, before its end
        for j in 1..=inside {
            let x = j as f64 / (inside + 1) as f64;
            contd8(&dense, x, &y, &mut y_out);
            let t_j = t + x * h_step;
            // qdd there from the dense output's own rate (a central difference of its qd, a
            // polynomial in x: truncation ~1e-8 relative at this spacing), not a solve
            contd8(&dense, x + INTERIOR_DX, &y, &mut y_dx);
            qdd_j.copy_from_slice(&y_dx[n..2 * n]);
            contd8(&dense, x - INTERIOR_DX, &y, &mut y_dx);
            for (a, v) in qdd_j.iter_mut().zip(&y_dx[n..2 * n]) {
                *a = (*a - v) / (2.0 * INTERIOR_DX * h_step);
            }
            let (q_j, qd_j) = (&y_out[..n], &y_out[n..2 * n]);
            rhs.watch.pivot(step_pivot);
            let stop = rhs.watch.accepted(model, &mut aux, &times, t_j, q_j, qd_j, &qdd_j, &mut events);
            out.events.append(&mut events);
            if let Some(t_stop) = stop {
                out.n_evaluations += rhs.evaluations;
                stop_at(out, t_stop);
                return Ok(());
            }
        }
        y.copy_from_slice(&y_end);
        let (qs, rest) = y.split_at_mut(n);
        if step_pivot < REGULARISE_BELOW {
            let work = rest[n];
            hold_balance(model, sys, &mut rhs.nu, qs, &mut rest[..n], work, t_new, balance);
            // the hold may scale the rates (the positions, hence V, stay)
            t_end = kinetic(model, sys.frames());
        }
        balance = t_end + v_end - y[2 * n];
        peak = peak.max(t_end + v_end.abs() + y[2 * n].abs());
        t = t_new;
        if !rhs.eval(model, sys, t, &y, &mut f, Equilibration::New) {
            return Err(step_error(out, t, h_step, "the accelerations are not finite".into()));
        }
        let stop =
            rhs.watch.accepted(model, &mut aux, &times, t, &y[..n], &y[n..2 * n], &f[n..2 * n], &mut events);
        out.events.append(&mut events);
        if let Some(t_stop) = stop {
            out.n_evaluations += rhs.evaluations;
            stop_at(out, t_stop);
            return Ok(());
        }
        h = h_step * factor;
        h = h.min(opts.h_max);
    }
    rhs.watch.finish(model, &mut aux, &times, &mut out.events);
    out.n_evaluations += rhs.evaluations;
    Ok(())
}

/// Scales the projected rates qd of a step through a singular crossing so that T + V - W_nc
/// is `balance` again, its value at the step's start. Within the regularised solves'
/// window the stages' accelerations leave the acceleration constraint, and the projection
/// that takes the rates back onto Phi_q qd = 0 takes kinetic energy with them (a loss that
/// varies with where the steps fall, and accumulates into the phase over the crossings).
/// Scaling qd is the smallest change (mass metric) that restores T and keeps
/// Phi_q qd = 0; done only where no driver moves (nu = 0) and the change is a small part
/// of a kinetic energy not near zero (well conditioned), otherwise the loss stays in the
/// balance the results report. Leaves the frames at (q, qd).
#[allow(clippy::too_many_arguments)]
fn hold_balance(
    model: &Model,
    sys: &mut System,
    nu: &mut [f64],
    q: &[f64],
    qd: &mut [f64],
    work: f64,
    t: f64,
    balance: f64,
) {
    nu_into(model, t, nu);
    if nu.iter().any(|v| *v != 0.0) {
        return;
    }
    let (tk, v) = (kinetic(model, sys.frames()), potential(model, sys.frames()));
    let target = balance + work - v;
    let size = tk.abs() + v.abs() + work.abs() + balance.abs();
    if !(tk >= HOLD_KINETIC * size && (target - tk).abs() <= HOLD_CHANGE * tk) {
        return;
    }
    let s = (target / tk).sqrt();
    qd.iter_mut().for_each(|x| *x *= s);
    sys.set_state(q, qd);
}

/// A step error where a state projected onto the constraints (the step's end, or an output
/// row from the dense output) has T + V - W off the balance at the step's start by more
/// than `PROJECTION_BALANCE` of the energies (theirs, or the largest so far where more):
/// next to a singular configuration, at a coarse tolerance, the projection can take the
/// rates onto another branch's tangent (a parallelogram's crank from 111 rad/s to 9 at
/// rtol 5e-3), which no error estimate sees. The step is then taken again shorter, its
/// dense output and end nearer the motion.
#[allow(clippy::too_many_arguments)]
fn off_balance(
    out: &SimOutput,
    t: f64,
    h: f64,
    what: &str,
    tk: f64,
    v: f64,
    work: f64,
    balance: f64,
    peak: f64,
) -> Option<SolveError> {
    let change = tk + v - work - balance;
    let size = (tk + v.abs() + work.abs()).max(peak);
    (change.abs() > PROJECTION_BALANCE * size).then(|| {
        step_error(
            out,
            t,
            h,
            format!(
                "projecting {what} onto the constraints changed T + V - W by {change:.3e} ({:.0} % of the \
                 energies): its rates were taken off the motion next to a singular configuration",
                100.0 * change.abs() / size
            ),
        )
    })
}

/// The load most likely to make the motion stiff: the largest stiffness (or damping) over
/// the mass (or moment of inertia) of the lightest body it acts on, named with its bodies.
fn stiffest_load(model: &Model) -> String {
    let mut best: Option<(f64, String)> = None;
    for l in &model.loads {
        let mut load = l.load.clone();
        let params = load.params_mut();
        let of = |name: &str| params.iter().find(|(p, _)| p == name).map_or(0.0, |(_, v)| v.abs());
        let (k, c) = (of("stiffness"), of("damping"));
        let torsion = matches!(l.load, Load::TorsionSpring { .. });
        let inertia = [l.body_a, l.body_b]
            .into_iter()
            .flatten()
            .map(|b| if torsion { model.inertias[b].inertia } else { model.inertias[b].mass })
            .fold(f64::INFINITY, f64::min);
        if !(inertia > 0.0 && inertia.is_finite()) || (k == 0.0 && c == 0.0) {
            continue;
        }
        // the load's own rate: sqrt(k / m) or c / m, whichever is faster
        let rate = (k / inertia).sqrt().max(c / inertia);
        let bodies: Vec<&str> =
            [l.body_a, l.body_b].into_iter().flatten().map(|b| model.body_names[b].as_str()).collect();
        let what = format!("load '{}' on {} (rate ~ {rate:.3e} 1/s)", l.name, bodies.join(" and "));
        if best.as_ref().is_none_or(|(r, _)| rate > *r) {
            best = Some((rate, what));
        }
    }
    best.map_or_else(|| "a stiff part of the model (no spring or damper found)".into(), |(_, w)| w)
}

fn step_error(out: &SimOutput, t: f64, h: f64, why: String) -> SolveError {
    SolveError::Step { step: out.n_done, time: t, h, why: format!("{why}; {} steps taken", out.n_steps) }
}

/// Hairer's error norm of DOP853: the 5th-order estimate, corrected by the 3rd's.
fn error_norm(k: &[Vec<f64>], h: f64, y: &[f64], y_new: &[f64], n: usize, scale_of: &Scale) -> f64 {
    let (mut e5, mut e3) = (0.0, 0.0);
    for i in 0..2 * n {
        let sc = scale_of(y, y_new, i);
        let (mut a, mut b) = (0.0, 0.0);
        for j in 0..13 {
            a += tab::E5[j] * k[j][i];
            b += tab::E3[j] * k[j][i];
        }
        e5 += (a / sc).powi(2);
        e3 += (b / sc).powi(2);
    }
    if e5 == 0.0 && e3 == 0.0 {
        return 0.0;
    }
    h.abs() * e5 / ((e5 + 0.01 * e3) * (2 * n) as f64).sqrt()
}

/// Hairer's contd8 at x in [0, 1] of the step: y + the interpolant, whose powers are
/// summed four components at a time in registers.
fn contd8(dense: &[Vec<f64>], x: f64, y: &[f64], out: &mut [f64]) {
    const LANES: usize = 4;
    let x1 = 1.0 - x;
    let len = out.len();
    let mut i = 0;
    while i < len {
        let w = LANES.min(len - i);
        let mut sum = [0.0f64; LANES];
        for (p, fc) in dense.iter().rev().enumerate() {
            let s = if p % 2 == 0 { x } else { x1 };
            if w == LANES {
                let c: &[f64; LANES] = fc[i..i + LANES].try_into().expect("four components");
                for l in 0..LANES {
                    sum[l] = (sum[l] + c[l]) * s;
                }
            } else {
                for l in 0..w {
                    sum[l] = (sum[l] + fc[i + l]) * s;
                }
            }
        }
        for l in 0..w {
            out[i + l] = sum[l] + y[i + l];
        }
        i += w;
    }
}

/// out = y + h sum_j a_j k_j, the sum over j in order for each component (the bits of
/// `(0..s).map(..).sum()`), a stage at a time over all components.
fn combine(a: &[f64], k: &[Vec<f64>], h: f64, y: &[f64], out: &mut [f64]) {
    let len = out.len();
    out.fill(-0.0);
    for (&aj, kj) in a.iter().zip(k) {
        for (o, v) in out.iter_mut().zip(&kj[..len]) {
            *o += aj * v;
        }
    }
    for (o, y0) in out.iter_mut().zip(y) {
        *o = y0 + h * *o;
    }
}

/// The dense output's coefficients of the step (t, y) -> (t + h, y_new): three more
/// stages, then F0..F6 (Hairer's contd8).
#[allow(clippy::too_many_arguments)]
fn dense_coefficients(
    model: &Model,
    sys: &mut System,
    rhs: &mut Rhs,
    k: &mut [Vec<f64>],
    dense: &mut [Vec<f64>],
    t: f64,
    h: f64,
    y: &[f64],
    y_new: &[f64],
    f_old: &[f64],
    stage: &mut [f64],
) {
    let len = y.len();
    // equilibrated as the step's stages were
    for s in tab::STAGES + 1..tab::STAGES_EXTENDED {
        combine(&tab::A[s][..s], &k[..s], h, y, stage);
        let (_, tail) = k.split_at_mut(s);
        rhs.eval(model, sys, t + tab::C[s] * h, stage, &mut tail[0], Equilibration::Kept);
    }
    let f_new = &k[tab::STAGES];
    for i in 0..len {
        let dy = y_new[i] - y[i];
        dense[0][i] = dy;
        dense[1][i] = h * f_old[i] - dy;
        dense[2][i] = 2.0 * dy - h * (f_new[i] + f_old[i]);
        for r in 0..4 {
            dense[3 + r][i] = h * (0..tab::STAGES_EXTENDED).map(|j| tab::D[r][j] * k[j][i]).sum::<f64>();
        }
    }
}
