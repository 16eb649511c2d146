//! Motion laws of drivers: f(t), f'(t) and f''(t), all exact.

use serde::{Deserialize, Serialize};

/// A time function with exact first and second derivatives.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum MotionLaw {
    /// f = value.
    Constant { value: f64 },
    /// f = value + rate t.
    Linear { value: f64, rate: f64 },
    /// f = c0 + c1 t + c2 t^2 + ...
    Polynomial { coefficients: Vec<f64> },
    /// f = mean + amplitude sin(omega t + phase).
    Harmonic {
        mean: f64,
        amplitude: f64,
        omega: f64,
        #[serde(default)]
        phase: f64,
    },
    /// Natural cubic spline through the table (C2: second derivative continuous).
    Spline(CubicSpline),
    /// f = factor * law(t): a law given in other units (degrees), made internally by
    /// compiling a model; never read from or written to a model file.
    #[serde(skip)]
    Scaled { factor: f64, law: Box<MotionLaw> },
}

impl MotionLaw {
    /// (f, f', f'') at t. Outside a spline's table the end cubic is extended; callers
    /// check `domain` first (a sweep refuses such times).
    #[inline]
    pub fn eval(&self, t: f64) -> [f64; 3] {
        match self {
            MotionLaw::Constant { value } => [*value, 0.0, 0.0],
            MotionLaw::Linear { value, rate } => [value + rate * t, *rate, 0.0],
            MotionLaw::Polynomial { coefficients } => {
                // Horner for the value and both derivatives at once
                let (mut f, mut fd, mut fdd) = (0.0, 0.0, 0.0);
                for &c in coefficients.iter().rev() {
                    fdd = fdd * t + 2.0 * fd;
                    fd = fd * t + f;
                    f = f * t + c;
                }
                [f, fd, fdd]
            }
            MotionLaw::Harmonic { mean, amplitude, omega, phase } => {
                let (s, c) = (omega * t + phase).sin_cos();
                [mean + amplitude * s, amplitude * omega * c, -amplitude * omega * omega * s]
            }
            MotionLaw::Spline(spline) => spline.eval(t),
            MotionLaw::Scaled { factor, law } => law.eval(t).map(|v| factor * v),
        }
    }

    /// The law times `factor` (unit conversion).
    pub fn scaled(self, factor: f64) -> MotionLaw {
        if factor == 1.0 {
            self
        } else {
            MotionLaw::Scaled { factor, law: Box::new(self) }
        }
    }

    /// Checks the law and computes what its evaluation needs (spline coefficients);
    /// a law read from a description must go through this once before `eval`.
    pub fn prepare(&mut self) -> Result<(), String> {
        self.check()?;
        match self {
            MotionLaw::Spline(s) => s.prepare(),
            MotionLaw::Scaled { law, .. } => law.prepare()?,
            _ => {}
        }
        Ok(())
    }

    /// The interval of time on which the law is defined (None: all of it).
    pub fn domain(&self) -> Option<(f64, f64)> {
        match self {
            MotionLaw::Spline(s) => Some((s.times[0], s.times[s.times.len() - 1])),
            MotionLaw::Scaled { law, .. } => law.domain(),
            _ => None,
        }
    }

    /// Why the law cannot be used, if it cannot.
    pub fn check(&self) -> Result<(), String> {
        let finite = |name: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(format!("motion law {name} is {v}, not a finite number"))
            }
        };
        match self {
            MotionLaw::Constant { value } => finite("value", *value),
            MotionLaw::Linear { value, rate } => {
                finite("value", *value)?;
                finite("rate", *rate)
            }
            MotionLaw::Polynomial { coefficients } => {
                if coefficients.is_empty() {
                    return Err("polynomial motion law has no coefficients".into());
                }
                coefficients.iter().try_for_each(|&c| finite("coefficient", c))
            }
            MotionLaw::Harmonic { mean, amplitude, omega, phase } => {
                finite("mean", *mean)?;
                finite("amplitude", *amplitude)?;
                finite("omega", *omega)?;
                finite("phase", *phase)
            }
            MotionLaw::Spline(s) => s.check(),
            MotionLaw::Scaled { factor, law } => {
                finite("factor", *factor)?;
                law.check()
            }
        }
    }
}

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

    fn check(&self) -> Result<(), String> {
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
    fn eval(&self, x: f64) -> [f64; 3] {
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
