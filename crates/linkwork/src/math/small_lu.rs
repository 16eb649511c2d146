//! LU with partial pivoting for small dense systems (up to a few dozen unknowns), in
//! place on a column-major n x n array. For such sizes faer's general kernels spend most
//! of their time dispatching, not computing (see docs/performance.md); this loop is a
//! few lines, allocation-free, and skips the structural zeros of Phi_q.

/// Factors a (column-major, n x n) in place as P a = L U, L unit lower, U upper; `pivots[k]`
/// is the row swapped with row k at step k, `inv_diag[k]` = 1 / U[k][k] (0 where U[k][k]
/// is 0). A zero pivot is left in U (the caller checks the pivots) and its column is not
/// eliminated.
#[inline]
pub fn factor(a: &mut [f64], n: usize, pivots: &mut [usize], inv_diag: &mut [f64]) {
    debug_assert!(a.len() == n * n && pivots.len() == n && inv_diag.len() == n);
    for k in 0..n {
        let (done, rest) = a.split_at_mut(k * n);
        let (col, right) = rest.split_at_mut(n);
        // pivot search in column k
        let mut p = k;
        let mut best = col[k].abs();
        for (i, v) in col.iter().enumerate().skip(k + 1) {
            if v.abs() > best {
                best = v.abs();
                p = i;
            }
        }
        pivots[k] = p;
        if p != k {
            for c in
                done.chunks_exact_mut(n).chain(std::iter::once(&mut *col)).chain(right.chunks_exact_mut(n))
            {
                c.swap(k, p);
            }
        }
        let pivot = col[k];
        if pivot == 0.0 {
            inv_diag[k] = 0.0;
            continue;
        }
        let inv = 1.0 / pivot;
        inv_diag[k] = inv;
        let l = &mut col[k + 1..];
        for x in l.iter_mut() {
            *x *= inv;
        }
        let l = &*l;
        for c in right.chunks_exact_mut(n) {
            let akj = c[k];
            if akj != 0.0 {
                for (x, li) in c[k + 1..].iter_mut().zip(l) {
                    *x -= li * akj;
                }
            }
        }
    }
}

/// Solves a x = b in place with the factors of `factor`.
#[inline]
pub fn solve(lu: &[f64], n: usize, pivots: &[usize], inv_diag: &[f64], b: &mut [f64]) {
    for (k, &p) in pivots.iter().enumerate() {
        b.swap(k, p);
    }
    // L y = P b (unit lower), column by column
    for (k, c) in lu.chunks_exact(n).enumerate() {
        let bk = b[k];
        if bk != 0.0 {
            for (x, l) in b[k + 1..].iter_mut().zip(&c[k + 1..]) {
                *x -= l * bk;
            }
        }
    }
    // U x = y, column by column from the last
    for (k, c) in lu.chunks_exact(n).enumerate().rev() {
        let bk = b[k] * inv_diag[k];
        b[k] = bk;
        if bk != 0.0 {
            for (x, u) in b[..k].iter_mut().zip(&c[..k]) {
                *x -= u * bk;
            }
        }
    }
}

/// Solves a^T x = b in place with the factors of `factor`: U^T L^T P x = b.
#[inline]
pub fn solve_transpose(lu: &[f64], n: usize, pivots: &[usize], inv_diag: &[f64], b: &mut [f64]) {
    // U^T z = b: U^T is lower; row k of U^T is column k of U
    for (k, c) in lu.chunks_exact(n).enumerate() {
        let s: f64 = c[..k].iter().zip(&b[..k]).map(|(u, x)| u * x).sum();
        b[k] = (b[k] - s) * inv_diag[k];
    }
    // L^T w = z: unit upper; row k of L^T is column k of L below the diagonal
    for (k, c) in lu.chunks_exact(n).enumerate().rev() {
        let s: f64 = c[k + 1..].iter().zip(&b[k + 1..]).map(|(l, x)| l * x).sum();
        b[k] -= s;
    }
    // x = P^T w: undo the swaps in reverse order
    for (k, &p) in pivots.iter().enumerate().rev() {
        b.swap(k, p);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn matvec(a: &[f64], n: usize, x: &[f64], transpose: bool) -> Vec<f64> {
        (0..n)
            .map(|i| (0..n).map(|j| if transpose { a[i * n + j] } else { a[j * n + i] } * x[j]).sum())
            .collect()
    }

    #[test]
    fn solves_random_systems_and_their_transposes() {
        let mut seed = 0x2545F4914F6CDD1Du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        };
        for n in [1, 2, 3, 9, 15, 40] {
            for _ in 0..20 {
                // sparse-ish like a Jacobian: zeros must be handled, pivoting needed
                let a: Vec<f64> = (0..n * n).map(|_| if next() > 0.3 { next() } else { 0.0 }).collect();
                let a: Vec<f64> = a
                    .iter()
                    .enumerate()
                    .map(|(k, v)| if k % (n + 1) == 0 { v + 0.1 * next() } else { *v })
                    .collect();
                let x: Vec<f64> = (0..n).map(|_| next()).collect();
                let mut lu = a.clone();
                let (mut piv, mut inv) = (vec![0; n], vec![0.0; n]);
                factor(&mut lu, n, &mut piv, &mut inv);
                let min_pivot = (0..n).map(|k| lu[k * n + k].abs()).fold(f64::INFINITY, f64::min);
                if min_pivot < 1e-6 {
                    continue; // too close to singular for a 1e-10 check
                }
                for transpose in [false, true] {
                    let mut b = matvec(&a, n, &x, transpose);
                    if transpose {
                        solve_transpose(&lu, n, &piv, &inv, &mut b);
                    } else {
                        solve(&lu, n, &piv, &inv, &mut b);
                    }
                    let err = b.iter().zip(&x).fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
                    assert!(err < 1e-9, "n = {n}, transpose = {transpose}: error {err:e}");
                }
            }
        }
    }

    #[test]
    fn a_singular_matrix_leaves_a_zero_pivot() {
        // second column twice the first
        let mut a = vec![1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0];
        let (mut piv, mut inv) = (vec![0; 3], vec![0.0; 3]);
        factor(&mut a, 3, &mut piv, &mut inv);
        let diag: Vec<f64> = (0..3).map(|k| a[k * 3 + k].abs()).collect();
        assert!(diag.iter().any(|&d| d < 1e-15), "{diag:?}");
    }
}
