//! Dense complex LU with partial pivoting for the tracker's small square systems
//! (n up to a few dozen), factorized in place in a buffer allocated once per path.

use num_complex::Complex64 as C64;

/// LU factors of an n x n row-major matrix, with the row permutation.
pub struct Lu {
    pub n: usize,
    pub a: Vec<C64>,
    pub perm: Vec<usize>,
}

impl Lu {
    pub fn new(n: usize) -> Self {
        Lu { n, a: vec![C64::default(); n * n], perm: (0..n).collect() }
    }

    /// Factorize the matrix now held in `self.a`. Returns min|u_ii| / max|u_ii|, 0 when
    /// a pivot is exactly zero (the caller treats small ratios as singular).
    pub fn factorize(&mut self) -> f64 {
        let n = self.n;
        let a = &mut self.a;
        for (i, p) in self.perm.iter_mut().enumerate() {
            *p = i;
        }
        let mut min_pivot = f64::INFINITY;
        let mut max_pivot: f64 = 0.0;
        for k in 0..n {
            let mut best = k;
            let mut best_norm = a[k * n + k].norm();
            for r in k + 1..n {
                let v = a[r * n + k].norm();
                if v > best_norm {
                    best = r;
                    best_norm = v;
                }
            }
            if best != k {
                for c in 0..n {
                    a.swap(k * n + c, best * n + c);
                }
                self.perm.swap(k, best);
            }
            min_pivot = min_pivot.min(best_norm);
            max_pivot = max_pivot.max(best_norm);
            if best_norm == 0.0 {
                continue;
            }
            let inv = a[k * n + k].inv();
            for r in k + 1..n {
                let m = a[r * n + k] * inv;
                a[r * n + k] = m;
                if m != C64::default() {
                    for c in k + 1..n {
                        let u = a[k * n + c];
                        a[r * n + c] -= m * u;
                    }
                }
            }
        }
        if max_pivot == 0.0 || !min_pivot.is_finite() || !max_pivot.is_finite() {
            0.0
        } else {
            min_pivot / max_pivot
        }
    }

    /// Solve A x = b in place (b becomes x), with the factors of `factorize`.
    pub fn solve(&self, b: &mut [C64], scratch: &mut [C64]) {
        let n = self.n;
        let a = &self.a;
        for i in 0..n {
            scratch[i] = b[self.perm[i]];
        }
        for i in 0..n {
            let mut s = scratch[i];
            for j in 0..i {
                s -= a[i * n + j] * scratch[j];
            }
            scratch[i] = s;
        }
        for i in (0..n).rev() {
            let mut s = scratch[i];
            for j in i + 1..n {
                s -= a[i * n + j] * scratch[j];
            }
            scratch[i] = s / a[i * n + i];
        }
        b[..n].copy_from_slice(&scratch[..n]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_complex_system() {
        let m = [
            [C64::new(0.0, 1.0), C64::new(2.0, 0.0), C64::new(1.0, -1.0)],
            [C64::new(3.0, 0.5), C64::new(0.0, 0.0), C64::new(-1.0, 0.0)],
            [C64::new(1.0, 1.0), C64::new(1.0, 2.0), C64::new(0.0, 2.0)],
        ];
        let x = [C64::new(1.0, -2.0), C64::new(0.5, 0.5), C64::new(-3.0, 1.0)];
        let mut lu = Lu::new(3);
        let mut b = [C64::default(); 3];
        for i in 0..3 {
            for j in 0..3 {
                lu.a[i * 3 + j] = m[i][j];
                b[i] += m[i][j] * x[j];
            }
        }
        assert!(lu.factorize() > 0.1);
        let mut scratch = [C64::default(); 3];
        lu.solve(&mut b, &mut scratch);
        for i in 0..3 {
            assert!((b[i] - x[i]).norm() < 1e-14);
        }
    }
}
