//! Predictor-corrector path tracking: RK4 on dy/dt = -H_y^{-1} H_t, Newton back onto the
//! path, step doubled after consecutive easy steps and halved on any doubt.

use std::time::Instant;

use num_complex::Complex64 as C64;

use crate::homotopy::{Homotopy, Workspace};
use crate::linear::Lu;

#[derive(Clone, Copy, Debug)]
pub struct TrackOptions {
    /// Largest step in t.
    pub max_step: f64,
    /// Smallest step before the path is declared failed.
    pub min_step: f64,
    /// Accepted plus rejected steps before the path is declared failed.
    pub max_steps: usize,
    /// Newton on the path converges when |dy| <= tol (1 + |y|) (max norms).
    pub tol: f64,
    /// Newton iterations allowed per step while tracking.
    pub max_newton: usize,
    /// First step in t.
    pub initial_step: f64,
    /// Consecutive easy steps (Newton in at most 2 iterations) before the step doubles.
    pub grow_after: usize,
    /// Largest first Newton correction accepted, relative to 1 + |y|: the prediction
    /// must land this close to the path.
    pub max_correction: f64,
    /// Wall-clock limit: a path still running then stops as failed (over budget), so
    /// that a degenerate instance with many paths, retracks and detours ends in bounded
    /// time. None: no limit.
    pub deadline: Option<Instant>,
}

impl Default for TrackOptions {
    fn default() -> Self {
        TrackOptions {
            max_step: 0.25,
            min_step: 1e-13,
            max_steps: 20_000,
            tol: 1e-9,
            max_newton: 4,
            initial_step: 0.05,
            grow_after: 2,
            max_correction: 1e-2,
            deadline: None,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathStatus {
    /// Reached t = 1 and Newton there converged.
    Reached,
    /// Reached t = 1 but Newton there did not converge (a singular endpoint).
    Singular,
    /// Stopped before t = 1 (step too small or budget spent).
    Failed,
}

#[derive(Clone, Debug)]
pub struct PathEnd {
    pub y: Vec<C64>,
    pub t: f64,
    pub status: PathStatus,
    pub steps: usize,
    pub rejected: usize,
    /// Pivot ratio of H_y at the end (small: singular endpoint).
    pub pivot_ratio: f64,
    /// Endgame samples: (1 - t, y) at the first accepted step past each 1 - t = 10^-k,
    /// k >= 2. Paths to infinity or to singular roots are judged from them.
    pub samples: Vec<(f64, Vec<C64>)>,
    /// Failed because it spent `max_steps` or reached the deadline (not because the step
    /// fell below `min_step`).
    pub out_of_steps: bool,
}

/// Decides from the endgame samples whether the path may stop early (its endpoint is
/// already known to be at infinity).
pub type Endgame<'a> = &'a (dyn Fn(&[(f64, Vec<C64>)]) -> bool + Sync);

struct Buffers {
    ws: Workspace,
    h: Vec<C64>,
    hy: Lu,
    ht: Vec<C64>,
    scratch: Vec<C64>,
    k: [Vec<C64>; 4],
    tmp: Vec<C64>,
}

/// max_i |v_i|, one square root (the tracker's values are far from overflow).
fn norm_inf(v: &[C64]) -> f64 {
    v.iter().map(|z| z.norm_sqr()).fold(0.0, f64::max).sqrt()
}

impl Buffers {
    fn new(hom: &dyn Homotopy) -> Self {
        let d = hom.dim();
        let z = || vec![C64::default(); d];
        Buffers {
            ws: hom.workspace(),
            h: z(),
            hy: Lu::new(d),
            ht: z(),
            scratch: z(),
            k: [z(), z(), z(), z()],
            tmp: z(),
        }
    }

    /// dy/dt at (y, t) into k[slot]; false if H_y is singular there.
    fn tangent(&mut self, hom: &dyn Homotopy, y: &[C64], t: f64, slot: usize) -> bool {
        hom.eval(y, t, &mut self.h, &mut self.hy.a, &mut self.ht, &mut self.ws);
        // only an exactly singular H_y stops the predictor: a small pivot ratio may be
        // bad scaling, and the corrector judges the step anyway
        if self.hy.factorize() == 0.0 {
            return false;
        }
        let k = &mut self.k[slot];
        for (ki, hti) in k.iter_mut().zip(&self.ht) {
            *ki = -hti;
        }
        self.hy.solve(k, &mut self.scratch);
        k.iter().all(|v| v.re.is_finite() && v.im.is_finite())
    }

    /// dy/dt into k[0] from the factorization and H_t Newton left: they were evaluated
    /// one converged correction (<= tol) away from the new point, far closer than the
    /// predictor's own error, and the next step (or its retries) starts there.
    fn tangent_from_newton(&mut self) -> bool {
        let k = &mut self.k[0];
        for (ki, hti) in k.iter_mut().zip(&self.ht) {
            *ki = -hti;
        }
        self.hy.solve(k, &mut self.scratch);
        k.iter().all(|v| v.re.is_finite() && v.im.is_finite())
    }

    /// Newton on H(., t) = 0 from y, in place. Returns (converged, iterations, first |dy|).
    fn newton(
        &mut self,
        hom: &dyn Homotopy,
        y: &mut [C64],
        t: f64,
        max_iter: usize,
        tol: f64,
    ) -> (bool, usize, f64) {
        let mut first = 0.0;
        let mut last = f64::INFINITY;
        for it in 0..max_iter {
            hom.eval(y, t, &mut self.h, &mut self.hy.a, &mut self.ht, &mut self.ws);
            if self.hy.factorize() == 0.0 {
                return (false, it, first);
            }
            self.hy.solve(&mut self.h, &mut self.scratch);
            let step = norm_inf(&self.h);
            if !step.is_finite() {
                return (false, it, first);
            }
            for (yi, di) in y.iter_mut().zip(&self.h) {
                *yi -= di;
            }
            if it == 0 {
                first = step;
            } else if step > 0.5 * last {
                // not contracting: outside Newton's basin, or already at the rounding level
                let converged = last <= 1e3 * f64::EPSILON * (1.0 + norm_inf(y));
                return (converged, it + 1, first);
            }
            last = step;
            if step <= tol * (1.0 + norm_inf(y)) {
                return (true, it + 1, first);
            }
        }
        (false, max_iter, first)
    }
}

/// Track one path from y0 at t = 0 to t = 1.
pub fn track(hom: &dyn Homotopy, y0: &[C64], opts: &TrackOptions, endgame: Endgame) -> PathEnd {
    let d = hom.dim();
    let mut b = Buffers::new(hom);
    let mut y = y0.to_vec();
    let mut t = 0.0;
    let mut dt = opts.initial_step.min(opts.max_step);
    let mut easy = 0;
    let mut steps = 0;
    let mut rejected = 0;
    let mut trial = vec![C64::default(); d];
    let mut samples: Vec<(f64, Vec<C64>)> = Vec::new();
    let mut next_sample = 1e-2;
    // k[0] already holds dy/dt at (y, t)
    let mut have_tangent = false;
    while t < 1.0 {
        let late = opts.deadline.is_some_and(|d| Instant::now() >= d);
        if steps + rejected >= opts.max_steps || dt < opts.min_step || late {
            let mut end = finish(hom, &mut b, y, t, PathStatus::Failed, steps, rejected, samples);
            end.out_of_steps = steps + rejected >= opts.max_steps || late;
            return end;
        }
        if 1.0 - t <= next_sample {
            samples.push((1.0 - t, y.clone()));
            while next_sample >= 1.0 - t {
                next_sample /= 10.0;
            }
            if endgame(&samples) {
                return finish(hom, &mut b, y, t, PathStatus::Failed, steps, rejected, samples);
            }
        }
        let h = dt.min(1.0 - t);
        // RK4 predictor
        let mut ok = have_tangent || b.tangent(hom, &y, t, 0);
        have_tangent = ok;
        if ok {
            for i in 0..d {
                b.tmp[i] = y[i] + b.k[0][i] * (h / 2.0);
            }
            let tmp = std::mem::take(&mut b.tmp);
            ok = b.tangent(hom, &tmp, t + h / 2.0, 1);
            b.tmp = tmp;
        }
        if ok {
            for i in 0..d {
                b.tmp[i] = y[i] + b.k[1][i] * (h / 2.0);
            }
            let tmp = std::mem::take(&mut b.tmp);
            ok = b.tangent(hom, &tmp, t + h / 2.0, 2);
            b.tmp = tmp;
        }
        if ok {
            for i in 0..d {
                b.tmp[i] = y[i] + b.k[2][i] * h;
            }
            let tmp = std::mem::take(&mut b.tmp);
            ok = b.tangent(hom, &tmp, t + h, 3);
            b.tmp = tmp;
        }
        let mut accepted = false;
        if ok {
            for i in 0..d {
                trial[i] = y[i] + (b.k[0][i] + 2.0 * b.k[1][i] + 2.0 * b.k[2][i] + b.k[3][i]) * (h / 6.0);
            }
            let scale = 1.0 + norm_inf(&y);
            let (conv, iters, first) = b.newton(hom, &mut trial, t + h, opts.max_newton, opts.tol);
            // the predictor must land close to the path, not merely in some basin
            if conv && first <= opts.max_correction * scale {
                accepted = true;
                t = if h >= 1.0 - t { 1.0 } else { t + h };
                y.copy_from_slice(&trial);
                steps += 1;
                have_tangent = b.tangent_from_newton();
                // RK4's error ~ h^5: aim the next first correction at 1e-3 of the path's size
                easy = if iters <= 2 { easy + 1 } else { 0 };
                let aim = 1e-3 * scale;
                let ratio = (aim / first.max(1e-300)).powf(0.2).clamp(0.5, 2.5);
                if easy >= opts.grow_after || ratio <= 1.5 {
                    dt = (h * ratio).min(opts.max_step);
                } else {
                    dt = (h * 1.5).min(opts.max_step);
                }
            }
        }
        if !accepted {
            rejected += 1;
            easy = 0;
            dt /= 2.0;
        }
    }
    finish(hom, &mut b, y, 1.0, PathStatus::Reached, steps, rejected, samples)
}

#[allow(clippy::too_many_arguments)]
fn finish(
    hom: &dyn Homotopy,
    b: &mut Buffers,
    mut y: Vec<C64>,
    t: f64,
    status: PathStatus,
    steps: usize,
    rejected: usize,
    samples: Vec<(f64, Vec<C64>)>,
) -> PathEnd {
    let mut status = status;
    if status == PathStatus::Reached {
        // refine to working precision at t = 1
        let (conv, _, _) = b.newton(hom, &mut y, 1.0, 8, 4.0 * f64::EPSILON);
        if !conv {
            // Newton stalls at rounding level on a regular root too: judge by H_y
            status = PathStatus::Singular;
        }
    }
    hom.eval(&y, t, &mut b.h, &mut b.hy.a, &mut b.ht, &mut b.ws);
    let pivot_ratio = b.hy.factorize();
    if status == PathStatus::Singular && pivot_ratio > 1e-8 {
        status = PathStatus::Reached;
    }
    PathEnd { y, t, status, steps, rejected, pivot_ratio, samples, out_of_steps: false }
}
