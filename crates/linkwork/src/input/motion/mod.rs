//! Motion laws of drivers: f(t), f'(t) and f''(t), all exact.
//!
//! A law is plain data in the model description, tagged by `"type"`. `prepare` checks it
//! and readies it once (spline coefficients, compiled expressions, segment tables, nested
//! laws); `eval` is then called in the per-step loop and allocates nothing.

mod cam;
mod compose;
mod external;
mod params;
mod spline;

use serde::{Deserialize, Serialize};

use crate::input::expr::Expression;

pub use cam::{CamProgram, CamSegment, Profile, Rise};
pub use compose::{Periodic, Sequence, JUMP_TOL};
pub use external::{ExternalFn, ExternalLaw};
pub use spline::CubicSpline;

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
    /// f = an expression of t written as text, e.g. "0.35 - 0.16*sin(150*t)".
    Expression(ExpressionLaw),
    /// One rise or fall with a cam profile.
    Rise(Rise),
    /// Dwells, rises and falls in turn.
    Cam(CamProgram),
    /// Other laws one after another, joined at breakpoints.
    Sequence(Sequence),
    /// Another law repeated every period, its net change carried over.
    Periodic(Periodic),
    /// A function of the host program (a Python callable), known by name in a description.
    Python(ExternalLaw),
    /// f = factor * law(t): a law given in other units (degrees), made internally by
    /// compiling a model; never read from or written to a model file.
    #[serde(skip)]
    Scaled { factor: f64, law: Box<MotionLaw> },
}

/// An expression law: its text, and once prepared, the compiled expression.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExpressionLaw {
    pub text: String,
    #[serde(skip)]
    compiled: Option<Expression>,
}

impl ExpressionLaw {
    /// The law for `text` (an expression of `t`), compiled.
    pub fn new(text: &str) -> Result<Self, String> {
        let mut e = ExpressionLaw { text: text.to_string(), compiled: None };
        e.prepare()?;
        Ok(e)
    }

    fn parse(&self) -> Result<Expression, String> {
        Expression::parse(&self.text, "t").map_err(|e| format!("expression '{}': {e}", self.text))
    }

    fn prepare(&mut self) -> Result<(), String> {
        self.compiled = Some(self.parse()?);
        Ok(())
    }
}

impl MotionLaw {
    /// Reads one law from JSON (as it appears in a description), unprepared.
    pub fn from_json(text: &str) -> Result<MotionLaw, String> {
        serde_json::from_str(text).map_err(|e| e.to_string())
    }

    /// (f, f', f'') at t. Outside a spline's table the end cubic is extended; callers
    /// check `domain` first (a sweep refuses such times). A law that cannot be evaluated
    /// there (an expression outside its functions' domains, a failing external function)
    /// gives non-finite values: `why_not_finite` says why.
    #[inline(always)]
    pub fn eval(&self, t: f64) -> [f64; 3] {
        // the drivers of most sweeps, at every step of them: in the caller's code, the
        // rest by a call
        match self {
            MotionLaw::Constant { value } => [*value, 0.0, 0.0],
            MotionLaw::Linear { value, rate } => [value + rate * t, *rate, 0.0],
            _ => self.eval_other(t),
        }
    }

    /// `eval` of the laws other than constant and linear.
    #[inline(never)]
    fn eval_other(&self, t: f64) -> [f64; 3] {
        match self {
            // `eval` takes these itself
            MotionLaw::Constant { .. } | MotionLaw::Linear { .. } => self.eval(t),
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
            MotionLaw::Expression(e) => match &e.compiled {
                Some(x) => x.eval(t),
                None => [f64::NAN; 3],
            },
            MotionLaw::Rise(r) => r.eval(t),
            MotionLaw::Cam(c) => c.eval(t),
            MotionLaw::Sequence(s) => s.active(t).eval(t),
            MotionLaw::Periodic(p) => p.eval(t),
            MotionLaw::Python(x) => x.eval(t),
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

    /// Checks the law and computes what its evaluation needs (spline coefficients,
    /// compiled expressions, segment tables; nested laws too); a law read from a
    /// description must go through this once before `eval`.
    pub fn prepare(&mut self) -> Result<(), String> {
        self.check()?;
        match self {
            MotionLaw::Spline(s) => s.prepare(),
            MotionLaw::Expression(e) => e.prepare()?,
            MotionLaw::Cam(c) => c.prepare(),
            MotionLaw::Sequence(s) => s.prepare()?,
            MotionLaw::Periodic(p) => p.prepare()?,
            MotionLaw::Scaled { law, .. } => law.prepare()?,
            _ => {}
        }
        Ok(())
    }

    /// The interval of time on which the law is defined (None: all of it).
    pub fn domain(&self) -> Option<(f64, f64)> {
        match self {
            MotionLaw::Spline(s) => Some((s.times[0], s.times[s.times.len() - 1])),
            MotionLaw::Sequence(s) => s.domain(),
            MotionLaw::Scaled { law, .. } => law.domain(),
            _ => None,
        }
    }

    /// Why the law cannot be used, if it cannot.
    pub fn check(&self) -> Result<(), String> {
        let finite = cam::finite;
        match self {
            MotionLaw::Constant { value } => finite("motion law value", *value),
            MotionLaw::Linear { value, rate } => {
                finite("motion law value", *value)?;
                finite("motion law rate", *rate)
            }
            MotionLaw::Polynomial { coefficients } => {
                if coefficients.is_empty() {
                    return Err("polynomial motion law has no coefficients".into());
                }
                coefficients.iter().try_for_each(|&c| finite("motion law coefficient", c))
            }
            MotionLaw::Harmonic { mean, amplitude, omega, phase } => {
                finite("motion law mean", *mean)?;
                finite("motion law amplitude", *amplitude)?;
                finite("motion law omega", *omega)?;
                finite("motion law phase", *phase)
            }
            MotionLaw::Spline(s) => s.check(),
            MotionLaw::Expression(e) => match e.compiled {
                Some(_) => Ok(()),
                None => e.parse().map(|_| ()),
            },
            MotionLaw::Rise(r) => r.check(),
            MotionLaw::Cam(c) => c.check(),
            MotionLaw::Sequence(s) => s.check(),
            MotionLaw::Periodic(p) => p.check(),
            MotionLaw::Python(x) => x.check(),
            MotionLaw::Scaled { factor, law } => {
                finite("motion law factor", *factor)?;
                law.check()
            }
        }
    }

    /// Calls `f` on this law and on every law nested in it (to bind external functions).
    pub fn for_each_mut(&mut self, f: &mut dyn FnMut(&mut MotionLaw)) {
        f(self);
        match self {
            MotionLaw::Sequence(s) => s.laws.iter_mut().for_each(|l| l.for_each_mut(f)),
            MotionLaw::Periodic(p) => p.law.for_each_mut(f),
            MotionLaw::Scaled { law, .. } => law.for_each_mut(f),
            _ => {}
        }
    }

    /// Calls `f` on this law and on every law nested in it.
    pub fn for_each(&self, f: &mut dyn FnMut(&MotionLaw)) {
        f(self);
        match self {
            MotionLaw::Sequence(s) => s.laws.iter().for_each(|l| l.for_each(f)),
            MotionLaw::Periodic(p) => p.law.for_each(f),
            MotionLaw::Scaled { law, .. } => law.for_each(f),
            _ => {}
        }
    }

    /// Why (f, f', f'') at t is not finite, naming the part of the law at fault; None if
    /// it is finite. For the error report of a solve, which has just met the NaN at t on
    /// this thread (an external law's failure is read back, not called again).
    pub fn why_not_finite(&self, t: f64) -> Option<String> {
        match self {
            MotionLaw::Python(x) => {
                if let Some(why) = external::take_failure(&x.name, t) {
                    return Some(why);
                }
                // values are kept, so this calls the function again only if it failed
                let v = x.eval(t);
                external::take_failure(&x.name, t).or_else(|| {
                    (!v.iter().all(|c| c.is_finite()))
                        .then(|| format!("python law '{}' returned {v:?} at t = {t}", x.name))
                })
            }
            MotionLaw::Expression(ExpressionLaw { compiled: Some(e), .. }) => e.diagnose(t),
            MotionLaw::Sequence(s) => {
                let i = s.breakpoints.partition_point(|&b| b <= t);
                s.laws[i].why_not_finite(t).map(|why| format!("sequence law {i}: {why}"))
            }
            MotionLaw::Periodic(p) => {
                let (_, t_in) = p.fold(t);
                p.law.why_not_finite(t_in).map(|why| format!("periodic law at t = {t_in}: {why}"))
            }
            MotionLaw::Scaled { law, .. } => law.why_not_finite(t),
            _ => {
                let v = self.eval(t);
                (!v.iter().all(|c| c.is_finite())).then(|| format!("the law gives {v:?} at t = {t}"))
            }
        }
    }
}
