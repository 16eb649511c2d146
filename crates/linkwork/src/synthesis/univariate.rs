//! Univariate polynomials (coefficients lowest degree first) and their roots by the
//! companion matrix's eigenvalues (nalgebra's Schur form), polished by Newton.

use nalgebra::DMatrix;
use num_complex::Complex64 as C64;

pub fn add(a: &[C64], b: &[C64]) -> Vec<C64> {
    let mut out = vec![C64::default(); a.len().max(b.len())];
    for (i, v) in a.iter().enumerate() {
        out[i] += v;
    }
    for (i, v) in b.iter().enumerate() {
        out[i] += v;
    }
    out
}

pub fn sub(a: &[C64], b: &[C64]) -> Vec<C64> {
    let neg: Vec<C64> = b.iter().map(|v| -v).collect();
    add(a, &neg)
}

pub fn mul(a: &[C64], b: &[C64]) -> Vec<C64> {
    if a.is_empty() || b.is_empty() {
        return vec![];
    }
    let mut out = vec![C64::default(); a.len() + b.len() - 1];
    for (i, u) in a.iter().enumerate() {
        for (j, v) in b.iter().enumerate() {
            out[i + j] += u * v;
        }
    }
    out
}

pub fn eval(p: &[C64], x: C64) -> C64 {
    p.iter().rev().fold(C64::default(), |acc, c| acc * x + c)
}

fn derivative(p: &[C64]) -> Vec<C64> {
    p.iter().enumerate().skip(1).map(|(k, c)| c * k as f64).collect()
}

/// All roots of p. Leading coefficients below `rel_tol` times the largest are dropped
/// (their roots are at infinity for the purpose at hand).
pub fn roots(p: &[C64], rel_tol: f64) -> Vec<C64> {
    let scale = p.iter().map(|c| c.norm()).fold(0.0, f64::max);
    if scale == 0.0 {
        return vec![];
    }
    let mut n = p.len();
    while n > 0 && p[n - 1].norm() <= rel_tol * scale {
        n -= 1;
    }
    if n <= 1 {
        return vec![];
    }
    let deg = n - 1;
    let lead = p[deg];
    // companion matrix of the monic polynomial
    let mut m = DMatrix::<C64>::zeros(deg, deg);
    for i in 1..deg {
        m[(i, i - 1)] = C64::new(1.0, 0.0);
    }
    for i in 0..deg {
        m[(i, deg - 1)] = -p[i] / lead;
    }
    let eig = match m.schur().eigenvalues() {
        Some(e) => e,
        None => return vec![],
    };
    let dp = derivative(&p[..n]);
    eig.iter()
        .map(|&z0| {
            // a few Newton steps on p itself recover the accuracy the eigenvalue lost
            let mut z = z0;
            for _ in 0..4 {
                let d = eval(&dp, z);
                if d.norm() == 0.0 {
                    break;
                }
                let step = eval(&p[..n], z) / d;
                if !step.re.is_finite() || !step.im.is_finite() {
                    break;
                }
                z -= step;
            }
            z
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_of_a_cubic() {
        // (x - 1)(x + 2)(x - 0.5) = x^3 + 0.5 x^2 - 2.5 x + 1
        let p: Vec<C64> = [1.0, -2.5, 0.5, 1.0].iter().map(|&v| C64::new(v, 0.0)).collect();
        let mut r: Vec<f64> = roots(&p, 1e-14).iter().map(|z| z.re).collect();
        r.sort_by(f64::total_cmp);
        for (a, b) in r.iter().zip([-2.0, 0.5, 1.0]) {
            assert!((a - b).abs() < 1e-14);
        }
    }
}
