//! Natural cubic spline through a table of (time, value).

use serde::{Deserialize, Serialize};

/// A natural cubic spline: piecewise cubic, C2, zero second derivative at both ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CubicSpline {
    pub times: Vec<f64>,
    pub values: Vec<f64>,
    /// Second derivatives at the knots; computed by `prepare`, not part of the description.
    #[serde(skip)]
    pub second: Vec<f64>,
}

impl CubicSpline {
    /// A spline through the table (which `check` must accept).
    pub fn new(times: Vec<f64>, values: Vec<f64>) -> Result<Self, String> {
        let mut s = CubicSpline { times, values, second: Vec::new() };
        s.check()?;
        s.prepare();
        Ok(s)
    }

    pub(crate) fn check(&self) -> Result<(), String> {
        let n = self.times.len();
        if n < 2 || self.values.len() != n {
            return Err(format!(
                "spline needs at least 2 times and as many values ({} times, {} values)",
                n,
                self.values.len()
            ));
        }
        if let Some(v) = self.times.iter().chain(&self.values).find(|v| !v.is_finite()) {
            return Err(format!("spline table holds {v}, not a finite number"));
        }
        if let Some(i) = (1..n).find(|&i| self.times[i] <= self.times[i - 1]) {
            return Err(format!(
                "spline times must increase strictly (times[{}] = {} follows {})",
                i,
                self.times[i],
                self.times[i - 1]
            ));
        }
        Ok(())
    }

    /// Solves the tridiagonal system for the knot second derivatives (natural ends).
    pub fn prepare(&mut self) {
        let (t, y) = (&self.times, &self.values);
        let n = t.len();
        let mut m = vec![0.0; n];
        if n > 2 {
            // Thomas algorithm on the interior knots
            let mut c_prime = vec![0.0; n];
            let mut d_prime = vec![0.0; n];
            for i in 1..n - 1 {
                let h0 = t[i] - t[i - 1];
                let h1 = t[i + 1] - t[i];
                let a = h0 / 6.0;
                let b = (h0 + h1) / 3.0;
                let c = h1 / 6.0;
                let d = (y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0;
                let denom = b - a * c_prime[i - 1];
                c_prime[i] = c / denom;
                d_prime[i] = (d - a * d_prime[i - 1]) / denom;
            }
            for i in (1..n - 1).rev() {
                m[i] = d_prime[i] - c_prime[i] * m[i + 1];
            }
        }
        self.second = m;
    }

    #[inline]
    pub(crate) fn eval(&self, x: f64) -> [f64; 3] {
        let (t, y, m) = (&self.times, &self.values, &self.second);
        let n = t.len();
        // interval k with t[k] <= x < t[k+1], clamped to the end intervals
        let k = match t.partition_point(|&ti| ti <= x) {
            0 => 0,
            p if p >= n => n - 2,
            p => p - 1,
        };
        let h = t[k + 1] - t[k];
        let a = (t[k + 1] - x) / h;
        let b = (x - t[k]) / h;
        let f = a * y[k] + b * y[k + 1] + ((a * a * a - a) * m[k] + (b * b * b - b) * m[k + 1]) * h * h / 6.0;
        let fd = (y[k + 1] - y[k]) / h - (3.0 * a * a - 1.0) / 6.0 * h * m[k]
            + (3.0 * b * b - 1.0) / 6.0 * h * m[k + 1];
        let fdd = a * m[k] + b * m[k + 1];
        [f, fd, fdd]
    }
}
