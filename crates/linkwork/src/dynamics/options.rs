//! How a simulation integrates: the method and its tolerances.

use crate::model::Model;

/// The integration method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// DOP853 (Dormand-Prince 8(5,3), dense output of order 7) on the index-1 equations,
    /// q and qd projected onto the constraints after every step: for smooth problems
    /// where accuracy is wanted (the fastest to a small error on the benchmarks).
    #[default]
    Rk8,
    /// Implicit index-3 generalized-alpha (Arnold and Bruls 2007, Chung and Hulbert's
    /// parameters from rho_inf), Newton on the augmented iteration matrix, the step size
    /// adapted to a local error estimate: for stiff or non-smooth problems.
    GenAlpha,
}

impl Method {
    pub fn from_name(name: &str) -> Option<Method> {
        match name {
            "rk8" => Some(Method::Rk8),
            "gen-alpha" => Some(Method::GenAlpha),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Method::Rk8 => "rk8",
            Method::GenAlpha => "gen-alpha",
        }
    }
}

/// Settings of one simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    pub method: Method,
    /// local error per step below atol * (L for lengths, 1 for angles) + rtol * |value|
    pub rtol: f64,
    pub atol: f64,
    /// the spectral radius at infinity of generalized-alpha (1: no numerical damping,
    /// 0: the most)
    pub rho_inf: f64,
    /// the first step (None: chosen from the problem), the largest step, and the most
    /// steps allowed
    pub h0: Option<f64>,
    pub h_max: f64,
    pub max_steps: usize,
    /// how far the initial conditions may move onto the constraints (scaled)
    pub ic_tol: f64,
    /// qdd, the multipliers, the reactions and the pivot ratio at every row (an index-1
    /// solve each); false leaves them NaN, for `record::solve_rows` when they are wanted
    pub accelerations: bool,
    /// a slider reaching an end of its `travel` stops the simulation there (the rows
    /// before it kept); false: reported, and the motion goes on (no stop is modelled)
    pub stop_at_travel_end: bool,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            method: Method::Rk8,
            rtol: 1e-8,
            atol: 1e-8,
            rho_inf: 0.9,
            h0: None,
            h_max: f64::INFINITY,
            max_steps: 10_000_000,
            ic_tol: 1e-6,
            accelerations: true,
            stop_at_travel_end: true,
        }
    }
}

impl SimOptions {
    /// Checks the numbers: a message naming the one at fault.
    pub fn check(&self) -> Result<(), String> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(self.rtol) || !positive(self.atol) {
            return Err(format!("rtol and atol must be finite and > 0, not {} and {}", self.rtol, self.atol));
        }
        if !(0.0..=1.0).contains(&self.rho_inf) {
            return Err(format!("rho_inf must be in [0, 1], not {}", self.rho_inf));
        }
        if self.h0.is_some_and(|h| !positive(h)) || self.h_max.is_nan() || self.h_max <= 0.0 {
            return Err(format!("h0 and h_max must be > 0, not {:?} and {}", self.h0, self.h_max));
        }
        if self.ic_tol.is_nan() || self.ic_tol < 0.0 {
            return Err(format!("ic_tol must be >= 0, not {}", self.ic_tol));
        }
        Ok(())
    }

    /// The step to take toward a time `to_next` ahead, the step the error control allows
    /// being `h`: `to_next` itself where it is no longer than `h`, or longer by under 1 %
    /// (as Hairer's codes do: never a sliver of a step left before the time, which rounding
    /// can make smaller than t's own resolution), past `h_max` only by rounding (else half
    /// of it); otherwise `h`.
    pub fn step_toward(&self, h: f64, to_next: f64) -> f64 {
        if to_next <= h {
            to_next
        } else if to_next <= 1.01 * h {
            if to_next <= self.h_max * (1.0 + 1e-12) {
                to_next
            } else {
                0.5 * to_next
            }
        } else {
            h
        }
    }
}

/// The largest |value| of each coordinate that the relative tolerance counts: a body's
/// angle at most a half-turn (the turns a crank has made say nothing of the accuracy
/// wanted: rtol |theta| would loosen the control of a revolving crank turn by turn),
/// lengths and a joint's own coordinate unbounded.
pub fn relative_sizes(model: &Model) -> Vec<f64> {
    (0..model.n_coords)
        .map(|i| if i < 3 * model.n_bodies && i % 3 == 2 { std::f64::consts::PI } else { f64::INFINITY })
        .collect()
}
