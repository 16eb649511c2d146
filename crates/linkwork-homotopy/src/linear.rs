//! Complex LU for the tracker's small square systems (n up to a few dozen), factorized
//! in place in a buffer allocated once per path. The matrices are dense in storage but
//! often sparse in fact (Alt's Jacobian has 7 entries in a row of 25): columns are
//! eliminated sparsest first, the pivot is the sparsest row within a factor 10 of the
//! column's largest entry (threshold partial pivoting), and only the pivot row's nonzero
//! entries are eliminated, so fill stays where the structure puts it.

use num_complex::Complex64 as C64;

/// LU factors of an n x n row-major matrix, with its row and column orders and, per step,
/// the rows it eliminated and the pivot row's nonzero columns (so the solves are sparse
/// too).
pub struct Lu {
    pub n: usize,
    pub a: Vec<C64>,
    /// Row pivoted at step k.
    perm: Vec<usize>,
    /// Column eliminated at step k.
    cols: Vec<usize>,
    /// Rows not yet pivoted.
    active: Vec<usize>,
    /// Nonzeros of each row of the first matrix factorized (the pivot choice prefers
    /// sparse rows).
    row_nnz: Vec<usize>,
    /// Whether `cols` and `row_nnz` hold the structure's order yet.
    ordered: bool,
    /// Rows eliminated at step k: l_rows[l_start[k]..l_start[k + 1]].
    l_rows: Vec<usize>,
    l_start: Vec<usize>,
    /// Nonzero columns of the pivot row after step k: u_cols[u_start[k]..u_start[k + 1]].
    u_cols: Vec<usize>,
    u_start: Vec<usize>,
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
            active: Vec::with_capacity(n),
            row_nnz: vec![0; n],
            ordered: false,
            l_rows: Vec::with_capacity(n * n),
            l_start: Vec::with_capacity(n + 1),
            u_cols: Vec::with_capacity(n * n),
            u_start: Vec::with_capacity(n + 1),
        }
    }

    /// Count the nonzeros of the matrix now held and order the columns sparsest first.
    /// Done at the first factorization only: a tracker's Jacobians share one structure,
    /// and the counts only steer the order (the elimination reads the values).
    fn order(&mut self) {
        let n = self.n;
        let zero = C64::default();
        let row_nnz = &mut self.row_nnz[..];
        let mut col_nnz = vec![0; n];
        row_nnz.fill(0);
        for (r, row) in self.a.chunks_exact(n).enumerate() {
            for (c, v) in row.iter().enumerate() {
                let nz = (*v != zero) as usize;
                row_nnz[r] += nz;
                col_nnz[c] += nz;
            }
        }
        for (k, c) in self.cols.iter_mut().enumerate() {
            *c = k;
        }
        self.cols.sort_unstable_by_key(|&c| (col_nnz[c], c));
        self.ordered = true;
    }

    /// Factorize the matrix now held in `self.a`. Returns min|u_kk| / max|u_kk|, 0 when
    /// a pivot is exactly zero (the caller treats small ratios as singular).
    pub fn factorize(&mut self) -> f64 {
        let n = self.n;
        let zero = C64::default();
        if !self.ordered {
            self.order();
        }
        let Lu { a, perm, cols, active, row_nnz, l_rows, l_start, u_cols, u_start, .. } = self;
        active.clear();
        active.extend(0..n);
        l_rows.clear();
        u_cols.clear();
        l_start.clear();
        u_start.clear();
        let mut min_pivot = f64::INFINITY;
        let mut max_pivot: f64 = 0.0;
        for k in 0..n {
            let c = cols[k];
            l_start.push(l_rows.len());
            u_start.push(u_cols.len());
            // the column's nonzero active rows (the L entries of this step, pivot aside)
            let first = l_rows.len();
            let mut big: f64 = 0.0;
            for &r in active.iter() {
                let v = l1(a[r * n + c]);
                if v > 0.0 {
                    l_rows.push(r);
                    big = big.max(v);
                }
            }
            // among rows within THRESHOLD of the largest, the sparsest: less fill
            let mut best = usize::MAX;
            for (i, &r) in l_rows[first..].iter().enumerate() {
                let v = l1(a[r * n + c]);
                if v < THRESHOLD * big {
                    continue;
                }
                let better = best == usize::MAX || {
                    let q = l_rows[first + best];
                    row_nnz[r] < row_nnz[q] || (row_nnz[r] == row_nnz[q] && v > l1(a[q * n + c]))
                };
                if better {
                    best = i;
                }
            }
            let p = if best == usize::MAX {
                // an empty column: singular; pivot any active row to keep the orders whole
                active[0]
            } else {
                l_rows.swap_remove(first + best)
            };
            let at = active.iter().position(|&r| r == p).expect("the pivot row is active");
            active.swap_remove(at);
            perm[k] = p;
            let pivot = a[p * n + c];
            let size = pivot.norm_sqr().sqrt();
            min_pivot = min_pivot.min(size);
            max_pivot = max_pivot.max(size);
            if size == 0.0 {
                l_rows.truncate(first);
                continue;
            }
            let u_first = u_cols.len();
            u_cols.extend(cols[k + 1..].iter().copied().filter(|&cc| a[p * n + cc] != zero));
            let inv = pivot.inv();
            for &r in &l_rows[first..] {
                let m = a[r * n + c] * inv;
                a[r * n + c] = m;
                for &cc in &u_cols[u_first..] {
                    let u = a[p * n + cc];
                    a[r * n + cc] -= m * u;
                }
            }
        }
        l_start.push(l_rows.len());
        u_start.push(u_cols.len());
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
        // L y = P b, column by column: y_k = b[perm[k]] once every earlier step has
        // subtracted its multiple from it
        scratch[..n].copy_from_slice(&b[..n]);
        for k in 0..n {
            let (p, c) = (self.perm[k], self.cols[k]);
            let yk = scratch[p];
            for &r in &self.l_rows[self.l_start[k]..self.l_start[k + 1]] {
                scratch[r] -= a[r * n + c] * yk;
            }
        }
        // U x = y, x indexed by column
        for k in (0..n).rev() {
            let p = self.perm[k];
            let row = &a[p * n..(p + 1) * n];
            let mut s = scratch[p];
            for &c in &self.u_cols[self.u_start[k]..self.u_start[k + 1]] {
                s -= row[c] * b[c];
            }
            b[self.cols[k]] = s / row[self.cols[k]];
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
                let structural = r == n - 1 || c >= 6 || r / 3 == c / 2;
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
