//! Laws made of other laws: a piecewise sequence, and periodic repetition.

use serde::{Deserialize, Serialize};

use super::cam::{finite, positive};
use super::MotionLaw;

/// Relative size of a jump in value at a breakpoint that still counts as continuous
/// (round-off in laws written with decimal coefficients).
pub const JUMP_TOL: f64 = 1e-9;

/// `laws[0]` before `breakpoints[0]`, `laws[i]` on [breakpoints[i-1], breakpoints[i]),
/// the last law from the last breakpoint on. Every law is evaluated at the absolute time.
/// The value must be continuous at each breakpoint; the velocity and acceleration may
/// jump there (a jump in velocity is an infinite acceleration in the real machine).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sequence {
    pub breakpoints: Vec<f64>,
    pub laws: Vec<MotionLaw>,
}

impl Sequence {
    #[inline]
    pub(crate) fn active(&self, t: f64) -> &MotionLaw {
        &self.laws[self.breakpoints.partition_point(|&b| b <= t)]
    }

    pub(crate) fn domain(&self) -> Option<(f64, f64)> {
        let start = self.laws.first().and_then(|l| l.domain()).map_or(f64::NEG_INFINITY, |d| d.0);
        let end = self.laws.last().and_then(|l| l.domain()).map_or(f64::INFINITY, |d| d.1);
        (start.is_finite() || end.is_finite()).then_some((start, end))
    }

    pub(crate) fn check(&self) -> Result<(), String> {
        let n = self.breakpoints.len();
        if self.laws.len() != n + 1 {
            return Err(format!(
                "sequence needs one law more than breakpoints ({n} breakpoints, {} laws)",
                self.laws.len()
            ));
        }
        for (i, &b) in self.breakpoints.iter().enumerate() {
            finite(&format!("sequence breakpoint {i}"), b)?;
            if i > 0 && b <= self.breakpoints[i - 1] {
                return Err(format!(
                    "sequence breakpoints must increase strictly (breakpoint {i} = {b} follows {})",
                    self.breakpoints[i - 1]
                ));
            }
        }
        for (i, law) in self.laws.iter().enumerate() {
            law.check().map_err(|e| format!("sequence law {i}: {e}"))?;
            // the law must be defined wherever the sequence uses it
            let from = if i == 0 { f64::NEG_INFINITY } else { self.breakpoints[i - 1] };
            let to = if i == n { f64::INFINITY } else { self.breakpoints[i] };
            if let Some((lo, hi)) = law.domain() {
                let lo_ok = i == 0 || lo <= from;
                let hi_ok = i == n || hi >= to;
                if !(lo_ok && hi_ok) || (i == 0 && lo >= to) || (i == n && hi <= from) {
                    return Err(format!(
                        "sequence law {i} is used on [{from}, {to}] but is defined on [{lo}, {hi}] only"
                    ));
                }
            }
        }
        Ok(())
    }

    /// Prepares the laws, then refuses a jump in value at a breakpoint.
    pub(crate) fn prepare(&mut self) -> Result<(), String> {
        for (i, law) in self.laws.iter_mut().enumerate() {
            law.prepare().map_err(|e| format!("sequence law {i}: {e}"))?;
        }
        for (i, &b) in self.breakpoints.iter().enumerate() {
            let left = self.laws[i].eval(b)[0];
            let right = self.laws[i + 1].eval(b)[0];
            let scale = 1f64.max(left.abs()).max(right.abs());
            if !(left - right).is_finite() || (left - right).abs() > JUMP_TOL * scale {
                return Err(format!(
                    "sequence breakpoint {i} (t = {b}): the value jumps from {left} (law {i}) to {right} \
                     (law {}); a driven coordinate cannot jump, make the laws meet there",
                    i + 1
                ));
            }
        }
        Ok(())
    }
}

/// `law` repeated every `period` from `t0` on (and before it): f(t) = law(t0 + tau) +
/// k (law(t0 + period) - law(t0)), with t = t0 + k period + tau, 0 <= tau < period.
/// The net change per period is carried over, so an indexing motion keeps advancing and
/// a rise-dwell-fall repeats exactly. Velocity and acceleration jump at the seams unless
/// the law's own match there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Periodic {
    pub period: f64,
    #[serde(default)]
    pub t0: f64,
    pub law: Box<MotionLaw>,
    /// law(t0 + period) - law(t0); set by `prepare`
    #[serde(skip)]
    advance: f64,
}

impl Periodic {
    /// `law` (which must be prepared) repeated every `period` from `t0`.
    pub fn new(period: f64, t0: f64, law: MotionLaw) -> Result<Self, String> {
        let mut p = Periodic { period, t0, law: Box::new(law), advance: 0.0 };
        p.check()?;
        p.prepare()?;
        Ok(p)
    }

    /// (periods completed k, time within the period t0 + tau).
    #[inline]
    pub(crate) fn fold(&self, t: f64) -> (f64, f64) {
        let x = t - self.t0;
        let mut k = (x / self.period).floor();
        let mut tau = x - k * self.period;
        // round-off can leave tau a hair outside [0, period)
        if tau < 0.0 {
            tau += self.period;
            k -= 1.0;
        } else if tau >= self.period {
            tau -= self.period;
            k += 1.0;
        }
        (k, self.t0 + tau.max(0.0))
    }

    #[inline]
    pub(crate) fn eval(&self, t: f64) -> [f64; 3] {
        let (k, t_in) = self.fold(t);
        let [f, fd, fdd] = self.law.eval(t_in);
        [f + k * self.advance, fd, fdd]
    }

    pub(crate) fn check(&self) -> Result<(), String> {
        positive("periodic period", self.period)?;
        finite("periodic t0", self.t0)?;
        self.law.check().map_err(|e| format!("periodic law: {e}"))?;
        if let Some((lo, hi)) = self.law.domain() {
            if lo > self.t0 || hi < self.t0 + self.period {
                return Err(format!(
                    "periodic law is repeated over [{}, {}] but is defined on [{lo}, {hi}] only",
                    self.t0,
                    self.t0 + self.period
                ));
            }
        }
        Ok(())
    }

    pub(crate) fn prepare(&mut self) -> Result<(), String> {
        self.law.prepare().map_err(|e| format!("periodic law: {e}"))?;
        self.advance = self.law.eval(self.t0 + self.period)[0] - self.law.eval(self.t0)[0];
        if !self.advance.is_finite() {
            return Err(format!(
                "periodic law is not finite at t = {} or t = {}",
                self.t0,
                self.t0 + self.period
            ));
        }
        Ok(())
    }
}
