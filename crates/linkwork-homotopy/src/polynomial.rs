//! Square polynomial systems F(x; p) = 0 in monomial form: n_vars unknowns x, n_params
//! parameters p (coefficients of a problem class), evaluated with their derivatives.

use num_complex::Complex64 as C64;

/// One term: coeff * prod x_v^e_v * prod p_k^e_k, exponents stored sparsely as
/// (index, exponent) over the joined vector z = (x, p).
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    pub coeff: C64,
    pub powers: Vec<(usize, u32)>,
}

impl Term {
    /// A term from dense exponents over z = (x, p).
    pub fn new(coeff: C64, exponents: &[u32]) -> Self {
        let powers = exponents.iter().enumerate().filter(|(_, &e)| e > 0).map(|(i, &e)| (i, e)).collect();
        Term { coeff, powers }
    }

    fn degree_in(&self, vars: &[usize]) -> u32 {
        self.powers.iter().filter(|(i, _)| vars.contains(i)).map(|(_, e)| e).sum()
    }
}

/// A polynomial: a sum of terms.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polynomial {
    pub terms: Vec<Term>,
}

impl Polynomial {
    pub fn new(terms: Vec<Term>) -> Self {
        Polynomial { terms }
    }

    /// The polynomial z_i.
    pub fn var(i: usize) -> Self {
        Polynomial { terms: vec![Term { coeff: C64::new(1.0, 0.0), powers: vec![(i, 1)] }] }
    }

    /// A constant.
    pub fn constant(c: C64) -> Self {
        Polynomial { terms: vec![Term { coeff: c, powers: vec![] }] }
    }

    /// self + other, equal monomials merged.
    pub fn add(&self, other: &Polynomial) -> Polynomial {
        let mut out = self.clone();
        for t in &other.terms {
            out.push(t.clone());
        }
        out
    }

    /// self * k.
    pub fn scale(&self, k: C64) -> Polynomial {
        Polynomial {
            terms: self.terms.iter().map(|t| Term { coeff: t.coeff * k, powers: t.powers.clone() }).collect(),
        }
    }

    /// self * other, equal monomials merged.
    pub fn mul(&self, other: &Polynomial) -> Polynomial {
        let mut out = Polynomial::default();
        for a in &self.terms {
            for b in &other.terms {
                let mut powers = a.powers.clone();
                for &(i, e) in &b.powers {
                    match powers.iter_mut().find(|(j, _)| *j == i) {
                        Some(p) => p.1 += e,
                        None => powers.push((i, e)),
                    }
                }
                powers.sort_unstable();
                out.push(Term { coeff: a.coeff * b.coeff, powers });
            }
        }
        out
    }

    fn push(&mut self, mut term: Term) {
        term.powers.sort_unstable();
        match self.terms.iter_mut().find(|t| t.powers == term.powers) {
            Some(t) => t.coeff += term.coeff,
            None => self.terms.push(term),
        }
    }

    /// Degree in the unknowns listed (indices into z).
    pub fn degree_in(&self, vars: &[usize]) -> u32 {
        self.terms.iter().map(|t| t.degree_in(vars)).max().unwrap_or(0)
    }
}

/// A system of polynomials in n_vars unknowns and n_params parameters. Square when
/// polys.len() == n_vars.
#[derive(Clone, Debug, PartialEq)]
pub struct System {
    pub n_vars: usize,
    pub n_params: usize,
    pub polys: Vec<Polynomial>,
}

/// Why a system was refused.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SystemError {
    #[error("the system has {n_polys} polynomials in {n_vars} unknowns; it must be square")]
    NotSquare { n_polys: usize, n_vars: usize },
    #[error("polynomial {poly} uses index {index}, beyond the {n} unknowns and parameters")]
    IndexOutOfRange { poly: usize, index: usize, n: usize },
    #[error("polynomial {poly} is constant in the unknowns: no start system reaches it")]
    ConstantPolynomial { poly: usize },
    #[error("coefficient of polynomial {poly} is not finite")]
    NotFinite { poly: usize },
    #[error("parameter {index} is not finite")]
    NotFiniteParameter { index: usize },
    #[error("variable groups must partition the {n_vars} unknowns exactly once: {why}")]
    BadGroups { n_vars: usize, why: String },
    #[error("expected {expected} parameter values, got {got}")]
    ParameterCount { expected: usize, got: usize },
}

impl System {
    pub fn new(n_vars: usize, n_params: usize, polys: Vec<Polynomial>) -> Result<Self, SystemError> {
        let system = System { n_vars, n_params, polys };
        system.validate()?;
        Ok(system)
    }

    pub(crate) fn validate(&self) -> Result<(), SystemError> {
        if self.polys.len() != self.n_vars {
            return Err(SystemError::NotSquare { n_polys: self.polys.len(), n_vars: self.n_vars });
        }
        let n = self.n_vars + self.n_params;
        let vars: Vec<usize> = (0..self.n_vars).collect();
        for (i, poly) in self.polys.iter().enumerate() {
            for term in &poly.terms {
                if !(term.coeff.re.is_finite() && term.coeff.im.is_finite()) {
                    return Err(SystemError::NotFinite { poly: i });
                }
                if let Some(&(index, _)) = term.powers.iter().find(|(k, _)| *k >= n) {
                    return Err(SystemError::IndexOutOfRange { poly: i, index, n });
                }
            }
            if poly.degree_in(&vars) == 0 {
                return Err(SystemError::ConstantPolynomial { poly: i });
            }
        }
        Ok(())
    }

    /// Total degree of each polynomial in the unknowns.
    pub fn degrees(&self) -> Vec<u32> {
        let vars: Vec<usize> = (0..self.n_vars).collect();
        self.polys.iter().map(|p| p.degree_in(&vars)).collect()
    }

    /// The system at fixed parameter values: parameters folded into the coefficients and
    /// equal monomials merged.
    pub fn specialize(&self, p: &[C64]) -> Result<System, SystemError> {
        if p.len() != self.n_params {
            return Err(SystemError::ParameterCount { expected: self.n_params, got: p.len() });
        }
        if let Some(index) = p.iter().position(|z| !(z.re.is_finite() && z.im.is_finite())) {
            return Err(SystemError::NotFiniteParameter { index });
        }
        let polys: Vec<Polynomial> = self
            .polys
            .iter()
            .map(|poly| {
                let mut terms: Vec<Term> = Vec::with_capacity(poly.terms.len());
                for term in &poly.terms {
                    let mut coeff = term.coeff;
                    let mut powers = Vec::new();
                    for &(i, e) in &term.powers {
                        if i >= self.n_vars {
                            coeff *= p[i - self.n_vars].powu(e);
                        } else {
                            powers.push((i, e));
                        }
                    }
                    match terms.iter_mut().find(|t| t.powers == powers) {
                        Some(t) => t.coeff += coeff,
                        None => terms.push(Term { coeff, powers }),
                    }
                }
                terms.retain(|t| t.coeff != C64::new(0.0, 0.0));
                Polynomial { terms }
            })
            .collect();
        // finite parameters can still overflow a coefficient (a product of large ones)
        let overflow =
            |p: &Polynomial| p.terms.iter().any(|t| !(t.coeff.re.is_finite() && t.coeff.im.is_finite()));
        if let Some(poly) = polys.iter().position(overflow) {
            return Err(SystemError::NotFinite { poly });
        }
        Ok(System { n_vars: self.n_vars, n_params: 0, polys })
    }

    /// Whether every coefficient is real (after specialization): real roots can then be
    /// certified real.
    pub fn is_real(&self) -> bool {
        self.polys.iter().all(|p| p.terms.iter().all(|t| t.coeff.im == 0.0))
    }
}

/// A system compiled for evaluation: flat term tables, power tables sized once.
#[derive(Clone, Debug)]
pub struct Compiled {
    pub n_eqs: usize,
    /// Number of entries of z that are differentiated (unknowns, then parameters).
    pub n_z: usize,
    // per equation: range into terms
    starts: Vec<usize>,
    coeffs: Vec<C64>,
    // per term: range into factors
    factor_starts: Vec<usize>,
    factors: Vec<(usize, u32)>,
    max_exp: Vec<u32>,
    // pow[offsets[v] + k] = z_v^k
    offsets: Vec<usize>,
    pub pow_len: usize,
}

impl Compiled {
    /// Compile polynomials over z of length n_z.
    pub fn new(polys: &[Polynomial], n_z: usize) -> Self {
        let mut starts = vec![0];
        let mut coeffs = Vec::new();
        let mut factor_starts = vec![0];
        let mut factors = Vec::new();
        let mut max_exp = vec![0; n_z];
        for poly in polys {
            for term in &poly.terms {
                coeffs.push(term.coeff);
                for &(i, e) in &term.powers {
                    factors.push((i, e));
                    max_exp[i] = max_exp[i].max(e);
                }
                factor_starts.push(factors.len());
            }
            starts.push(coeffs.len());
        }
        let mut offsets = Vec::with_capacity(n_z);
        let mut pow_len = 0;
        for &m in &max_exp {
            offsets.push(pow_len);
            pow_len += m as usize + 1;
        }
        Compiled {
            offsets,
            pow_len,
            n_eqs: polys.len(),
            n_z,
            starts,
            coeffs,
            factor_starts,
            factors,
            max_exp,
        }
    }

    /// Values f (n_eqs) and, if given, the full derivative df (n_eqs x n_z, row-major)
    /// at z. `pow` is scratch of length `pow_len`.
    pub fn eval(&self, z: &[C64], f: &mut [C64], df: Option<&mut [C64]>, pow: &mut [C64]) {
        self.eval_with(z, &self.coeffs, None, f, df, pow);
    }

    /// Number of terms (the length of a coefficient vector for `eval_with`).
    pub fn n_terms(&self) -> usize {
        self.coeffs.len()
    }

    /// As `eval`, with the terms' coefficients given (one per term, in compile order) and,
    /// if `rate` = (dcoeffs, fr) is given, fr = sum of dcoeff * monomial per equation: the
    /// derivative of f along a change of the coefficients alone.
    pub fn eval_with(
        &self,
        z: &[C64],
        coeffs: &[C64],
        mut rate: Option<(&[C64], &mut [C64])>,
        f: &mut [C64],
        mut df: Option<&mut [C64]>,
        pow: &mut [C64],
    ) {
        if let (Some((dc, fr)), Some(d)) = (rate.as_mut(), df.as_deref_mut()) {
            self.eval_tracking(z, coeffs, dc, fr, f, d, pow);
            return;
        }
        let offsets = &self.offsets;
        for (v, &m) in self.max_exp.iter().enumerate() {
            let mut acc = C64::new(1.0, 0.0);
            pow[offsets[v]] = acc;
            for k in 1..=m as usize {
                acc *= z[v];
                pow[offsets[v] + k] = acc;
            }
        }
        if let Some(d) = df.as_deref_mut() {
            d.fill(C64::new(0.0, 0.0));
        }
        for eq in 0..self.n_eqs {
            let mut value = C64::new(0.0, 0.0);
            let mut along = C64::new(0.0, 0.0);
            for t in self.starts[eq]..self.starts[eq + 1] {
                let fs = &self.factors[self.factor_starts[t]..self.factor_starts[t + 1]];
                let c = coeffs[t];
                let mut monomial = C64::new(1.0, 0.0);
                for &(v, e) in fs {
                    monomial *= pow[offsets[v] + e as usize];
                }
                value += c * monomial;
                if let Some((dc, _)) = rate.as_ref() {
                    along += dc[t] * monomial;
                }
                if let Some(d) = df.as_deref_mut() {
                    // d/dz_v: replace factor z_v^e by e z_v^(e-1); the other factors kept
                    for (k, &(v, e)) in fs.iter().enumerate() {
                        let mut g = c * e as f64 * pow[offsets[v] + e as usize - 1];
                        for (j, &(w, ew)) in fs.iter().enumerate() {
                            if j != k {
                                g *= pow[offsets[w] + ew as usize];
                            }
                        }
                        d[eq * self.n_z + v] += g;
                    }
                }
            }
            f[eq] = value;
            if let Some((_, fr)) = rate.as_mut() {
                fr[eq] = along;
            }
        }
    }
}

impl Compiled {
    fn powers(&self, z: &[C64], pow: &mut [C64]) {
        for (v, &m) in self.max_exp.iter().enumerate() {
            let o = self.offsets[v];
            let mut acc = C64::new(1.0, 0.0);
            pow[o] = acc;
            for k in 1..=m as usize {
                acc *= z[v];
                pow[o + k] = acc;
            }
        }
    }

    /// `eval_with` with everything asked for, as the tracker does at every step:
    /// monomials of up to three factors unrolled, each factor's partial derivative from
    /// the others' product (a factor of exponent 1 differentiates to 1).
    #[allow(clippy::too_many_arguments)]
    fn eval_tracking(
        &self,
        z: &[C64],
        coeffs: &[C64],
        dc: &[C64],
        fr: &mut [C64],
        f: &mut [C64],
        d: &mut [C64],
        pow: &mut [C64],
    ) {
        self.powers(z, pow);
        d.fill(C64::default());
        let n_z = self.n_z;
        // z_v^e and its derivative e z_v^(e-1)
        let factor = |(v, e): (usize, u32)| -> (usize, C64, C64) {
            let o = self.offsets[v] + e as usize;
            let de = if e == 1 { C64::new(1.0, 0.0) } else { pow[o - 1] * e as f64 };
            (v, pow[o], de)
        };
        for eq in 0..self.n_eqs {
            let row = &mut d[eq * n_z..(eq + 1) * n_z];
            let mut value = C64::default();
            let mut along = C64::default();
            for t in self.starts[eq]..self.starts[eq + 1] {
                let fs = &self.factors[self.factor_starts[t]..self.factor_starts[t + 1]];
                let c = coeffs[t];
                let monomial = match *fs {
                    [] => C64::new(1.0, 0.0),
                    [a] => {
                        let (va, ma, da) = factor(a);
                        row[va] += c * da;
                        ma
                    }
                    [a, b] => {
                        let ((va, ma, da), (vb, mb, db)) = (factor(a), factor(b));
                        row[va] += c * da * mb;
                        row[vb] += c * db * ma;
                        ma * mb
                    }
                    [a, b, e] => {
                        let ((va, ma, da), (vb, mb, db), (ve, me, de)) = (factor(a), factor(b), factor(e));
                        let (cab, cme) = (c * ma * mb, c * me);
                        row[va] += cme * da * mb;
                        row[vb] += cme * db * ma;
                        row[ve] += cab * de;
                        ma * mb * me
                    }
                    _ => {
                        let mut m = C64::new(1.0, 0.0);
                        for (k, &(v, e)) in fs.iter().enumerate() {
                            let (_, mv, dv) = factor((v, e));
                            m *= mv;
                            let mut g = c * dv;
                            for (j, &w) in fs.iter().enumerate() {
                                if j != k {
                                    g *= factor(w).1;
                                }
                            }
                            row[v] += g;
                        }
                        m
                    }
                };
                value += c * monomial;
                along += dc[t] * monomial;
            }
            f[eq] = value;
            fr[eq] = along;
        }
    }
}

/// Bombieri-Weyl norm of each polynomial of a parameter-free system, homogenized to its
/// total degree d: ||f||^2 = sum |c_a|^2 a! (d - |a|)! / d!. Used by the alpha test.
pub fn bombieri_weyl_norms(system: &System) -> Vec<f64> {
    let degrees = system.degrees();
    system
        .polys
        .iter()
        .zip(degrees)
        .map(|(poly, d)| {
            let mut sum = 0.0;
            for term in &poly.terms {
                let mut weight = 1.0 / factorial(d);
                let mut total = 0;
                for &(_, e) in &term.powers {
                    weight *= factorial(e);
                    total += e;
                }
                weight *= factorial(d - total);
                sum += term.coeff.norm_sqr() * weight;
            }
            sum.sqrt()
        })
        .collect()
}

fn factorial(n: u32) -> f64 {
    (1..=n).map(f64::from).product()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(re: f64) -> C64 {
        C64::new(re, 0.0)
    }

    #[test]
    fn derivative_matches_finite_difference() {
        // f0 = 2 x0^2 x1 - 3 p0 x1^3 + 1, f1 = x0 x1 p0^2 - x0
        let polys = vec![
            Polynomial::new(vec![
                Term::new(c(2.0), &[2, 1, 0]),
                Term::new(c(-3.0), &[0, 3, 1]),
                Term::new(c(1.0), &[0, 0, 0]),
            ]),
            Polynomial::new(vec![Term::new(c(1.0), &[1, 1, 2]), Term::new(c(-1.0), &[1, 0, 0])]),
        ];
        let compiled = Compiled::new(&polys, 3);
        let z = [C64::new(0.3, -0.7), C64::new(1.1, 0.2), C64::new(-0.4, 0.9)];
        let mut f = [C64::default(); 2];
        let mut df = [C64::default(); 6];
        let mut pow = vec![C64::default(); compiled.pow_len];
        compiled.eval(&z, &mut f, Some(&mut df), &mut pow);
        let h = 1e-6;
        for v in 0..3 {
            let mut zp = z;
            let mut zm = z;
            zp[v] += h;
            zm[v] -= h;
            let mut fp = [C64::default(); 2];
            let mut fm = [C64::default(); 2];
            compiled.eval(&zp, &mut fp, None, &mut pow);
            compiled.eval(&zm, &mut fm, None, &mut pow);
            for eq in 0..2 {
                let fd = (fp[eq] - fm[eq]) / (2.0 * h);
                // central difference: error h^2 * third derivative, here below 1e-9
                assert!((fd - df[eq * 3 + v]).norm() < 1e-8, "eq {eq} var {v}");
            }
        }
    }

    #[test]
    fn the_trackers_unrolled_evaluation_is_the_general_one() {
        // monomials of 0 to 5 factors, exponents 1 to 3, in 5 unknowns
        let mut rng = crate::random::Rng::new(3);
        let mut polys = Vec::new();
        for _ in 0..4 {
            let terms = (0..9)
                .map(|t| {
                    let mut exps = [0u32; 5];
                    for _ in 0..t % 6 {
                        let v = (rng.uniform() * 5.0) as usize % 5;
                        exps[v] = (exps[v] + 1 + (rng.uniform() * 2.0) as u32).min(3);
                    }
                    Term::new(rng.complex_normal(), &exps)
                })
                .collect();
            polys.push(Polynomial::new(terms));
        }
        let compiled = Compiled::new(&polys, 5);
        let n_terms = compiled.n_terms();
        let coeffs: Vec<C64> = (0..n_terms).map(|_| rng.complex_normal()).collect();
        let dc: Vec<C64> = (0..n_terms).map(|_| rng.complex_normal()).collect();
        let z: Vec<C64> = (0..5).map(|_| rng.complex_normal()).collect();
        let mut pow = vec![C64::default(); compiled.pow_len];
        let (mut f1, mut fr, mut d1) =
            (vec![C64::default(); 4], vec![C64::default(); 4], vec![C64::default(); 20]);
        compiled.eval_with(&z, &coeffs, Some((&dc, &mut fr)), &mut f1, Some(&mut d1), &mut pow);
        let (mut f2, mut d2, mut along) =
            (vec![C64::default(); 4], vec![C64::default(); 20], vec![C64::default(); 4]);
        compiled.eval_with(&z, &coeffs, None, &mut f2, Some(&mut d2), &mut pow);
        // the rate is f with the coefficients dc
        compiled.eval_with(&z, &dc, None, &mut along, None, &mut pow);
        let close =
            |a: &[C64], b: &[C64]| a.iter().zip(b).all(|(u, v)| (u - v).norm() <= 1e-12 * (1.0 + v.norm()));
        assert!(close(&f1, &f2) && close(&d1, &d2) && close(&fr, &along));
    }

    #[test]
    fn specialize_folds_parameters() {
        let system = System::new(
            1,
            1,
            vec![Polynomial::new(vec![
                Term::new(c(1.0), &[2, 0]),
                Term::new(c(-1.0), &[0, 2]),
                Term::new(c(2.0), &[2, 1]),
            ])],
        )
        .unwrap();
        let s = system.specialize(&[c(3.0)]).unwrap();
        // x^2 - 9 + 6 x^2 = 7 x^2 - 9
        assert_eq!(s.polys[0].terms.len(), 2);
        assert_eq!(s.polys[0].terms[0].coeff, c(7.0));
        assert_eq!(s.polys[0].terms[1].coeff, c(-9.0));
    }

    #[test]
    fn refuses_non_square_and_constant() {
        let p = Polynomial::new(vec![Term::new(c(1.0), &[1, 0])]);
        assert!(matches!(System::new(2, 0, vec![p.clone()]), Err(SystemError::NotSquare { .. })));
        let k = Polynomial::new(vec![Term::new(c(1.0), &[0, 0])]);
        assert!(matches!(System::new(2, 0, vec![p, k]), Err(SystemError::ConstantPolynomial { poly: 1 })));
    }
}
