//! Complex LU for the tracker's small square systems (n up to a few dozen), factorized
//! in place in a buffer allocated once per path. The matrices are dense in storage but
//! often sparse in fact (Alt's Jacobian has 7 entries in a row of 25): columns are
//! eliminated sparsest first, the pivot is the sparsest row within a factor 10 of the
//! column's largest entry (threshold partial pivoting), and only the pivot row's nonzero
//! entries are eliminated, so fill stays where the structure puts it.

use num_complex::Complex64 as C64;

/// LU factors of an n x n row-major matrix, with its row and column orders.
pub struct Lu {
    pub n: usize,
    pub a: Vec<C64>,
    /// Row pivoted at step k.
    perm: Vec<usize>,
    /// Column eliminated at step k.
    cols: Vec<usize>,
    done: Vec<bool>,
    row_nnz: Vec<usize>,
    col_nnz: Vec<usize>,
    nz: Vec<usize>,
}

/// |re| + |im|: within a factor sqrt 2 of the modulus, without hypot's cost.
fn l1(z: C64) -> f64 {
    z.re.abs() + z.im.abs()
}

/// A pivot must be at least this fraction of its column's largest entry.
const THRESHOLD: f64 = 0.1;

impl Lu {
    pub fn new(n: usize) -> Self {
        Lu {
            n,
            a: vec![C64::default(); n * n],
            perm: (0..n).collect(),
            cols: (0..n).collect(),
            done: vec![false; n],
            row_nnz: vec![0; n],
            col_nnz: vec![0; n],
            nz: Vec::with_capacity(n),
        }
    }

    /// Factorize the matrix now held in `self.a`. Returns min|u_kk| / max|u_kk|, 0 when
    /// a pivot is exactly zero (the caller treats small ratios as singular).
    pub fn factorize(&mut self) -> f64 {
        let n = self.n;
        let zero = C64::default();
        let Lu { a, perm, cols, done, row_nnz, col_nnz, nz, .. } = self;
        row_nnz.fill(0);
        col_nnz.fill(0);
        for r in 0..n {
            for c in 0..n {
                if a[r * n + c] != zero {
                    row_nnz[r] += 1;
                    col_nnz[c] += 1;
                }
            }
        }
        for (k, c) in cols.iter_mut().enumerate() {
            *c = k;
        }
        cols.sort_unstable_by_key(|&c| (col_nnz[c], c));
        done.fill(false);
        let mut min_pivot = f64::INFINITY;
        let mut max_pivot: f64 = 0.0;
        for k in 0..n {
            let c = cols[k];
            let mut big: f64 = 0.0;
            for r in 0..n {
                if !done[r] {
                    big = big.max(l1(a[r * n + c]));
                }
            }
            let mut p = usize::MAX;
            for r in 0..n {
                if done[r] {
                    continue;
                }
                let v = l1(a[r * n + c]);
                let better = p == usize::MAX
                    || (v >= THRESHOLD * big
                        && (l1(a[p * n + c]) < THRESHOLD * big
                            || row_nnz[r] < row_nnz[p]
                            || (row_nnz[r] == row_nnz[p] && v > l1(a[p * n + c]))));
                if better {
                    p = r;
                }
            }
            done[p] = true;
            perm[k] = p;
            let pivot = a[p * n + c];
            let size = pivot.norm_sqr().sqrt();
            min_pivot = min_pivot.min(size);
            max_pivot = max_pivot.max(size);
            if size == 0.0 {
                continue;
            }
            nz.clear();
            nz.extend(cols[k + 1..].iter().copied().filter(|&cc| a[p * n + cc] != zero));
            let inv = pivot.inv();
            for r in 0..n {
                if done[r] || a[r * n + c] == zero {
                    continue;
                }
                let m = a[r * n + c] * inv;
                a[r * n + c] = m;
                for &cc in nz.iter() {
                    let u = a[p * n + cc];
                    a[r * n + cc] -= m * u;
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
        let (a, perm, cols) = (&self.a, &self.perm, &self.cols);
        // L y = P b, y indexed by step
        for k in 0..n {
            let row = &a[perm[k] * n..(perm[k] + 1) * n];
            let mut s = b[perm[k]];
            for j in 0..k {
                s -= row[cols[j]] * scratch[j];
            }
            scratch[k] = s;
        }
        // U x = y, x indexed by column
        for k in (0..n).rev() {
            let row = &a[perm[k] * n..(perm[k] + 1) * n];
            let mut s = scratch[k];
            for &c in &cols[k + 1..] {
                s -= row[c] * b[c];
            }
            b[cols[k]] = s / row[cols[k]];
        }
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

    #[test]
    fn solves_a_sparse_system_with_a_dense_row_and_zero_diagonal() {
        // Alt-like structure: pairs of columns touched by three rows each, a dense core
        // and a dense patch row; diagonal entries zero so every step pivots
        let n = 9;
        let mut rng = crate::random::Rng::new(11);
        let mut lu = Lu::new(n);
        for r in 0..n {
            for c in 0..n {
                let structural = r == n - 1 || c >= 6 || (r / 3 == c / 2 && c < 6);
                if structural && r != c {
                    lu.a[r * n + c] = rng.complex_normal();
                }
            }
        }
        let m = lu.a.clone();
        let x: Vec<C64> = (0..n).map(|_| rng.complex_normal()).collect();
        let mut b: Vec<C64> = (0..n).map(|r| (0..n).map(|c| m[r * n + c] * x[c]).sum()).collect();
        assert!(lu.factorize() > 0.0);
        let mut scratch = vec![C64::default(); n];
        lu.solve(&mut b, &mut scratch);
        for i in 0..n {
            assert!((b[i] - x[i]).norm() < 1e-12, "{i}: {} vs {}", b[i], x[i]);
        }
        // a zero column is singular
        let mut lu = Lu::new(n);
        lu.a.copy_from_slice(&m);
        for r in 0..n {
            lu.a[r * n + 4] = C64::default();
        }
        assert_eq!(lu.factorize(), 0.0);
    }
}
