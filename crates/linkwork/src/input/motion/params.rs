//! A motion law's numbers as design parameters: named, settable, and the exact
//! derivatives of (f, f', f'') in each, for the sensitivities of the drivers.
//!
//! The closed-form laws have parameters (constant: value; linear: value, rate; polynomial:
//! coefficients.i; harmonic: mean, amplitude, omega, phase), a scaled law (a law in
//! degrees) has its inner law's, scaled. The other laws (tables, expressions, cams,
//! sequences, periodic and Python laws) have none here: a study varies them by
//! differences of whole sweeps.

use super::MotionLaw;
use crate::math::jet::Jet;

impl MotionLaw {
    /// The law's parameters, named as below the law in a description ("rate",
    /// "coefficients.2"), in the order `param_derivative` and `jet` read them.
    pub fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        match self {
            MotionLaw::Constant { value } => vec![("law.value".into(), value)],
            MotionLaw::Linear { value, rate } => vec![("law.value".into(), value), ("law.rate".into(), rate)],
            MotionLaw::Polynomial { coefficients } => coefficients
                .iter_mut()
                .enumerate()
                .map(|(i, c)| (format!("law.coefficients.{i}"), c))
                .collect(),
            MotionLaw::Harmonic { mean, amplitude, omega, phase } => vec![
                ("law.mean".into(), mean),
                ("law.amplitude".into(), amplitude),
                ("law.omega".into(), omega),
                ("law.phase".into(), phase),
            ],
            MotionLaw::Scaled { law, .. } => law.params_mut(),
            _ => Vec::new(),
        }
    }

    /// d (f, f', f'') / d p_i at t, p_i the law's parameter i (`params_mut`).
    pub fn param_derivative(&self, i: usize, t: f64) -> [f64; 3] {
        match self {
            MotionLaw::Constant { .. } => [1.0, 0.0, 0.0],
            MotionLaw::Linear { .. } => [[1.0, 0.0, 0.0], [t, 1.0, 0.0]][i],
            MotionLaw::Polynomial { .. } => {
                let n = i as f64;
                let pow = |k: i32| if k < 0 { 0.0 } else { t.powi(k) };
                let k = i as i32;
                [pow(k), n * pow(k - 1), n * (n - 1.0) * pow(k - 2)]
            }
            MotionLaw::Harmonic { amplitude, omega, phase, .. } => {
                let (a, w) = (*amplitude, *omega);
                let (s, c) = (w * t + phase).sin_cos();
                match i {
                    0 => [1.0, 0.0, 0.0],
                    1 => [s, w * c, -w * w * s],
                    2 => [a * t * c, a * (c - w * t * s), -a * w * (2.0 * s + w * t * c)],
                    _ => [a * c, -a * w * s, -a * w * w * c],
                }
            }
            MotionLaw::Scaled { factor, law } => law.param_derivative(i, t).map(|v| factor * v),
            _ => [0.0; 3],
        }
    }

    /// f at t + tau as a jet (f + f' tau + f'' tau^2 / 2), its parameters' perturbations
    /// read from the jets `p` (their constant parts e[k][0]).
    #[inline]
    pub fn jet<const W: usize>(&self, t: f64, p: &[Jet<W>]) -> Jet<W> {
        let [f, fd, fdd] = self.eval(t);
        let mut out = Jet { v: [f, fd, 0.5 * fdd], e: [[0.0; 3]; W] };
        for (i, pi) in p.iter().enumerate() {
            if pi.e.iter().all(|e| e[0] == 0.0) {
                continue;
            }
            let d = self.param_derivative(i, t);
            for k in 0..W {
                let w = pi.e[k][0];
                out.e[k][0] += w * d[0];
                out.e[k][1] += w * d[1];
                out.e[k][2] += w * 0.5 * d[2];
            }
        }
        out
    }
}
