//! Smale's alpha test on the affine target system: a point x with
//! alpha = beta * gamma < alpha0 is an approximate zero (Newton from it converges
//! quadratically) and its root lies within 2 beta of it. gamma is bounded above by the
//! Shub-Smale bound with the Bombieri-Weyl norm (as in Hauenstein and Sottile's
//! alphaCertified): gamma <= mu D^(3/2) / (2 |x|_1), mu = max(1, |f| |Df^{-1} Delta|).
//! Computed in floating point: f(x) in double-double, beta enlarged by bounds on the
//! rounding of f(x) and of the solve, norms Frobenius (above the spectral norm), and
//! alpha must stay below 0.9 alpha0.

use num_complex::Complex64 as C64;

use crate::linear::Lu;
use crate::polynomial::{bombieri_weyl_norms, Compiled, System};

/// (13 - 3 sqrt 17) / 4: Smale's constant for approximate zeros.
pub const ALPHA0: f64 = 0.157_670_780_786_754_6;

/// An affine, parameter-free square system prepared for polishing and certification.
pub struct Affine {
    pub system: System,
    compiled: Compiled,
    degrees: Vec<u32>,
    norm: f64,
}

/// What the alpha test found at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaTest {
    pub alpha: f64,
    pub beta: f64,
    pub gamma: f64,
    /// |Df| |Df^{-1}| (Frobenius).
    pub condition: f64,
    pub certified: bool,
}

impl AlphaTest {
    fn failed() -> Self {
        AlphaTest {
            alpha: f64::INFINITY,
            beta: f64::INFINITY,
            gamma: f64::INFINITY,
            condition: f64::INFINITY,
            certified: false,
        }
    }
}

impl Affine {
    pub fn new(system: System) -> Self {
        let compiled = Compiled::new(&system.polys, system.n_vars);
        let degrees = system.degrees();
        let norm = bombieri_weyl_norms(&system).iter().map(|v| v * v).sum::<f64>().sqrt();
        Affine { system, compiled, degrees, norm }
    }

    pub fn n(&self) -> usize {
        self.system.n_vars
    }

    fn eval(&self, x: &[C64], f: &mut [C64], df: &mut [C64]) {
        let mut pow = vec![C64::default(); self.compiled.pow_len];
        self.compiled.eval(x, f, Some(df), &mut pow);
    }

    /// Newton from x in place until the step stops shrinking; true if it converged.
    pub fn newton(&self, x: &mut [C64], max_iter: usize) -> bool {
        let n = self.n();
        let mut f = vec![C64::default(); n];
        let mut lu = Lu::new(n);
        let mut scratch = vec![C64::default(); n];
        let mut last = f64::INFINITY;
        for _ in 0..max_iter {
            self.eval(x, &mut f, &mut lu.a);
            if lu.factorize() == 0.0 {
                return false;
            }
            lu.solve(&mut f, &mut scratch);
            let step = f.iter().map(|v| v.norm()).fold(0.0, f64::max);
            if !step.is_finite() {
                return false;
            }
            for (xi, di) in x.iter_mut().zip(&f) {
                *xi -= di;
            }
            let size = x.iter().map(|v| v.norm()).fold(0.0, f64::max);
            if step <= 4.0 * f64::EPSILON * (1.0 + size) {
                return true;
            }
            if step >= last {
                // stalled at the rounding level: converged as far as f64 allows
                return step <= 1e-6 * (1.0 + size);
            }
            last = step;
        }
        true
    }

    /// max_i |f_i(x)| and the normwise backward error
    /// max_i |f_i(x)| / (|c_i|_1 max(1, |x|)^d_i): the relative change of coefficients
    /// that makes x an exact root, scale-free.
    pub fn residual(&self, x: &[C64]) -> (f64, f64) {
        let values = self.values(x);
        let size = x.iter().map(|v| v.norm()).fold(1.0, f64::max);
        let mut abs: f64 = 0.0;
        let mut rel: f64 = 0.0;
        for ((v, poly), d) in values.iter().zip(&self.system.polys).zip(&self.degrees) {
            abs = abs.max(v.norm());
            let c: f64 = poly.terms.iter().map(|t| t.coeff.norm()).sum();
            rel = rel.max(v.norm() / (c * size.powi(*d as i32)));
        }
        (abs, rel)
    }

    /// f(x) in double precision, term by term as written.
    fn values(&self, x: &[C64]) -> Vec<C64> {
        let mut values = Vec::with_capacity(self.n());
        for poly in &self.system.polys {
            let mut v = C64::default();
            for term in &poly.terms {
                let mut m = term.coeff;
                for &(i, e) in &term.powers {
                    m *= x[i].powu(e);
                }
                v += m;
            }
            values.push(v);
        }
        values
    }

    /// f(x) at a double-double point, evaluated in double-double complex arithmetic
    /// (rounded to f64 at the end), and each polynomial's sum of |term|.
    fn values_double_double(&self, x: &[Cdd]) -> (Vec<C64>, Vec<f64>) {
        let mut values = Vec::with_capacity(self.n());
        let mut sizes = Vec::with_capacity(self.n());
        for poly in &self.system.polys {
            let mut v = Cdd::from(C64::default());
            let mut s = 0.0;
            for term in &poly.terms {
                let mut m = Cdd::from(term.coeff);
                for &(i, e) in &term.powers {
                    for _ in 0..e {
                        m = m.mul(&x[i]);
                    }
                }
                s += m.to_c64().norm();
                v = v.add(&m);
            }
            values.push(v.to_c64());
            sizes.push(s);
        }
        (values, sizes)
    }

    /// Newton in double-double from x (f in double-double, Df in double at x), then the
    /// alpha test at the refined point: certifies roots whose condition leaves no room in
    /// double, where beta is stuck at ~eps |x| cond. Returns the test (its beta enlarged
    /// by half the rounding of the refined point to double, so that the root lies within
    /// 2 beta of the returned point) and that point.
    pub fn alpha_refined(&self, x: &[C64]) -> (AlphaTest, Vec<C64>) {
        let n = self.n();
        let mut f = vec![C64::default(); n];
        let mut lu = Lu::new(n);
        self.eval(x, &mut f, &mut lu.a);
        if lu.factorize() == 0.0 {
            return (AlphaTest::failed(), x.to_vec());
        }
        let mut scratch = vec![C64::default(); n];
        let mut xd: Vec<Cdd> = x.iter().map(|&z| Cdd::from(z)).collect();
        for _ in 0..4 {
            let (mut step, _) = self.values_double_double(&xd);
            lu.solve(&mut step, &mut scratch);
            for (xi, si) in xd.iter_mut().zip(&step) {
                *xi = xi.add(&Cdd::from(-si));
            }
        }
        let rounded: Vec<C64> = xd.iter().map(|z| z.to_c64()).collect();
        let mut test = self.test(&rounded, &xd);
        let offset = xd.iter().map(|z| z.sub_c64(z.to_c64()).norm_sqr()).sum::<f64>().sqrt();
        test.beta += offset / 2.0;
        (test, rounded)
    }

    /// The alpha test at x.
    pub fn alpha(&self, x: &[C64]) -> AlphaTest {
        let xd: Vec<Cdd> = x.iter().map(|&z| Cdd::from(z)).collect();
        self.test(x, &xd)
    }

    /// The alpha test at the double-double point xd; x is xd rounded, where Df and the
    /// gamma bound are evaluated (they change by a relative 1e-16 between the two, far
    /// inside the margin alpha < 0.9 alpha0 leaves).
    fn test(&self, x: &[C64], xd: &[Cdd]) -> AlphaTest {
        let n = self.n();
        let failed = AlphaTest::failed();
        let mut f = vec![C64::default(); n];
        let mut lu = Lu::new(n);
        self.eval(x, &mut f, &mut lu.a);
        let jac_norm = lu.a.iter().map(|v| v.norm_sqr()).sum::<f64>().sqrt();
        if lu.factorize() == 0.0 {
            return failed;
        }
        let mut scratch = vec![C64::default(); n];
        // columns of Df^{-1}
        let mut inv = vec![C64::default(); n * n];
        for j in 0..n {
            let mut e = vec![C64::default(); n];
            e[j] = C64::new(1.0, 0.0);
            lu.solve(&mut e, &mut scratch);
            for i in 0..n {
                inv[i * n + j] = e[i];
            }
        }
        let inv_norm = inv.iter().map(|v| v.norm_sqr()).sum::<f64>().sqrt();
        if !inv_norm.is_finite() {
            return failed;
        }
        // beta = |Df^{-1} f|, enlarged by |Df^{-1}| times f's rounding bound
        // f(x) in double-double: its rounding error is ~eps^2 of the terms' sizes, so beta
        // is limited by x's own distance to the root, not by the evaluation
        let (f_dd, sizes) = self.values_double_double(xd);
        let max_terms = self.system.polys.iter().map(|p| p.terms.len()).max().unwrap_or(1);
        let max_degree = *self.degrees.iter().max().unwrap_or(&1);
        let k = 4.0 * (max_terms + 2 * max_degree as usize + 4) as f64;
        let eps = f64::EPSILON;
        let rounding = sizes
            .iter()
            .zip(&f_dd)
            .map(|(s, v)| (k * eps * eps * s + eps * v.norm()).powi(2))
            .sum::<f64>()
            .sqrt();
        let mut step = f_dd.clone();
        lu.solve(&mut step, &mut scratch);
        let solve_error = 1.0 + 4.0 * n as f64 * eps * jac_norm * inv_norm;
        let beta = step.iter().map(|v| v.norm_sqr()).sum::<f64>().sqrt() * solve_error + inv_norm * rounding;
        // gamma bound
        let x1 = (1.0 + x.iter().map(|v| v.norm_sqr()).sum::<f64>()).sqrt();
        let mut m_norm = 0.0;
        for j in 0..n {
            let d = self.degrees[j] as f64;
            let delta = d.sqrt() * x1.powf(d - 1.0);
            for i in 0..n {
                m_norm += (inv[i * n + j] * delta).norm_sqr();
            }
        }
        let m_norm = m_norm.sqrt();
        let mu = (self.norm * m_norm).max(1.0);
        let big_d = max_degree as f64;
        let gamma = mu * big_d.powf(1.5) / (2.0 * x1);
        let alpha = beta * gamma;
        AlphaTest {
            alpha,
            beta,
            gamma,
            condition: jac_norm * inv_norm,
            certified: alpha.is_finite() && alpha < 0.9 * ALPHA0,
        }
    }
}

/// A double-double number hi + lo (|lo| <= ulp(hi) / 2), by error-free transformations.
#[derive(Clone, Copy, Debug)]
struct Dd {
    hi: f64,
    lo: f64,
}

impl Dd {
    fn two_sum(a: f64, b: f64) -> Dd {
        let s = a + b;
        let bb = s - a;
        Dd { hi: s, lo: (a - (s - bb)) + (b - bb) }
    }

    fn add(self, o: Dd) -> Dd {
        let s = Dd::two_sum(self.hi, o.hi);
        let lo = s.lo + self.lo + o.lo;
        Dd::two_sum(s.hi, lo)
    }

    fn mul(self, o: Dd) -> Dd {
        let p = self.hi * o.hi;
        let e = self.hi.mul_add(o.hi, -p);
        let lo = e + (self.hi * o.lo + self.lo * o.hi);
        Dd::two_sum(p, lo)
    }

    fn neg(self) -> Dd {
        Dd { hi: -self.hi, lo: -self.lo }
    }
}

/// A complex double-double.
#[derive(Clone, Copy, Debug)]
struct Cdd {
    re: Dd,
    im: Dd,
}

impl Cdd {
    fn from(z: C64) -> Cdd {
        Cdd { re: Dd { hi: z.re, lo: 0.0 }, im: Dd { hi: z.im, lo: 0.0 } }
    }

    fn add(&self, o: &Cdd) -> Cdd {
        Cdd { re: self.re.add(o.re), im: self.im.add(o.im) }
    }

    fn mul(&self, o: &Cdd) -> Cdd {
        Cdd {
            re: self.re.mul(o.re).add(self.im.mul(o.im).neg()),
            im: self.re.mul(o.im).add(self.im.mul(o.re)),
        }
    }

    fn to_c64(self) -> C64 {
        C64::new(self.re.hi + self.re.lo, self.im.hi + self.im.lo)
    }

    /// self - z, rounded to double: what rounding self to z lost.
    fn sub_c64(&self, z: C64) -> C64 {
        self.add(&Cdd::from(-z)).to_c64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polynomial::{Polynomial, Term};

    #[test]
    fn certifies_a_simple_root_and_refuses_a_far_point() {
        // x^2 - 2 = 0
        let system = System::new(
            1,
            0,
            vec![Polynomial::new(vec![
                Term::new(C64::new(1.0, 0.0), &[2]),
                Term::new(C64::new(-2.0, 0.0), &[0]),
            ])],
        )
        .unwrap();
        let affine = Affine::new(system);
        let near = affine.alpha(&[C64::new(1.414, 0.0)]);
        assert!(near.certified, "{near:?}");
        let root = affine.alpha(&[C64::new(2f64.sqrt(), 0.0)]);
        assert!(root.certified && root.beta < 1e-14);
        let far = affine.alpha(&[C64::new(0.05, 0.0)]);
        assert!(!far.certified, "{far:?}");
    }
}
