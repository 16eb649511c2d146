//! Sparse LU with a fixed pivot sequence, replayed every step (refactorization, as in
//! KLU's `klu_refactor`).
//!
//! Along a sweep Phi_q keeps its sparsity pattern and changes its values slowly, so the
//! row and column orders that suit one step suit the next. The first factorization
//! chooses them: the column order is the model's (COLAMD), the row order comes from a
//! left-looking factorization with partial pivoting (Gilbert-Peierls) on the actual
//! values. From that sequence the fill pattern of L and U and the list of every update
//! are compiled once into an elimination program; each later factorization only replays
//! its arithmetic: no pivot search, no symbolic work, no allocation.
//!
//! Every replayed pivot is checked against the largest candidate of its column (the
//! entries of that column of L before scaling): if |pivot| < `PIVOT_THRESHOLD` times it,
//! the sequence no longer suits the values, and the factorization is redone with a new
//! pivot choice (and a new program; its buffers are reused, so it allocates only if the
//! new program is larger than any before). The threshold bounds every entry of L by
//! 1 / `PIVOT_THRESHOLD`, as threshold partial pivoting does.
//!
//! Written here because faer 0.24 has no numeric refactorization that keeps the pivot
//! order: its sparse LU (`factorize_simplicial_numeric_lu`, the supernodal one) searches
//! for pivots and rebuilds the patterns of L and U at every call, which is most of the
//! work for the small and banded systems of mechanisms.
//!
//! Storage: one array for L and U, by step columns. Column j (the j-th column of P A Q)
//! holds, sorted by step: U(0..j, j), the pivot U(j, j), then L(j+1.., j) (unit diagonal
//! not stored). All indices are steps (positions in P A Q) except where said.

use crate::linear::Pivots;

/// A replayed pivot smaller than this fraction of its column's largest candidate makes
/// the factorization choose its pivots again.
pub const PIVOT_THRESHOLD: f64 = 0.1;

const NONE: u32 = u32::MAX;

/// One update of the program: column j -= L(:, k) * U(k, j).
#[derive(Debug, Clone, Copy)]
struct Update {
    /// position of U(k, j) in `lu`
    u: u32,
    /// the step k whose column of L is subtracted
    k: u32,
}

/// A sparse LU of a square matrix in compressed-column form, its pivot sequence fixed at
/// the first factorization and re-chosen only when a pivot fails its threshold.
#[derive(Debug, Clone)]
pub struct SparseLu {
    n: usize,
    /// n + 1 and nnz(A): the pattern of A (compressed columns, rows sorted)
    a_col_ptr: Vec<usize>,
    a_row: Vec<usize>,
    /// n: Q, column of A at each step
    col_of_step: Vec<u32>,
    /// n: P, row of A pivoted at each step, and its inverse
    row_of_step: Vec<u32>,
    step_of_row: Vec<u32>,
    /// sign of det P * det Q
    perm_sign: f64,
    /// n + 1: start of each step column in `lu`; n: position of its pivot
    lu_ptr: Vec<u32>,
    diag: Vec<u32>,
    /// nnz(L + U): the step (row) of each entry, and its value
    lu_row: Vec<u32>,
    lu: Vec<f64>,
    /// nnz(A): where each value of A goes in `lu`
    a_to_lu: Vec<u32>,
    /// the program: n + 1 starts into `updates`; per update, nnz(L(:, k)) targets
    update_ptr: Vec<u32>,
    updates: Vec<Update>,
    targets: Vec<u32>,
    /// n: 1 / U(j, j) (0 where the pivot is 0)
    inv_diag: Vec<f64>,
    /// n: dense work vector of the solves
    work: Vec<f64>,
    /// whether a pivot sequence and its program exist
    ready: bool,
    /// how many times the pivots were chosen (1 after the first factorization)
    pivot_choices: usize,
}

/// Why a replay stopped.
enum Replay {
    Done,
    /// the pivot of this step failed its threshold
    Repivot,
}

impl SparseLu {
    /// For the n x n pattern `col_ptr`, `row_idx` (compressed columns, rows sorted and
    /// unique in each column), eliminated in the column order `col_order` (the column of
    /// A at each step). Nothing is factored yet.
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize], col_order: &[usize]) -> SparseLu {
        assert!(col_ptr.len() == n + 1 && col_order.len() == n && row_idx.len() == col_ptr[n]);
        assert!(row_idx.len() < NONE as usize, "pattern too large for 32-bit positions");
        SparseLu {
            n,
            a_col_ptr: col_ptr.to_vec(),
            a_row: row_idx.to_vec(),
            col_of_step: col_order.iter().map(|&c| c as u32).collect(),
            row_of_step: vec![NONE; n],
            step_of_row: vec![NONE; n],
            perm_sign: 1.0,
            lu_ptr: Vec::new(),
            diag: Vec::new(),
            lu_row: Vec::new(),
            lu: Vec::new(),
            a_to_lu: Vec::new(),
            update_ptr: Vec::new(),
            updates: Vec::new(),
            targets: Vec::new(),
            inv_diag: vec![0.0; n],
            work: vec![0.0; n],
            ready: false,
            pivot_choices: 0,
        }
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// How many times the pivot sequence was chosen: 1 after the first factorization,
    /// one more for every re-pivoting.
    pub fn pivot_choices(&self) -> usize {
        self.pivot_choices
    }

    /// Structural non-zeros of L + U (the unit diagonal of L not counted).
    pub fn nnz_lu(&self) -> usize {
        self.lu.len()
    }

    /// (column of A, U(j, j)) of each step of the last factorization.
    pub fn diagonal(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.diag.iter().zip(&self.col_of_step).map(|(&p, &c)| (c as usize, self.lu[p as usize]))
    }

    /// Multiply-adds of one replayed factorization.
    pub fn n_updates(&self) -> usize {
        self.targets.len()
    }

    /// Factors A (its values in the order of the pattern) and returns its pivots: the
    /// ratio of the smallest to the largest |U(j, j)|, the column of A of the smallest,
    /// the sign of det A. A zero pivot is reported (ratio 0, sign 0), not an error; a
    /// non-finite value gives a NaN ratio.
    pub fn factor(&mut self, values: &[f64]) -> Pivots {
        assert_eq!(values.len(), self.a_row.len(), "values do not match the pattern");
        if !self.ready || matches!(self.replay(values, true), Replay::Repivot) {
            self.choose_pivots(values);
            // the values that chose the pivots pass their own threshold: not checked again
            self.replay(values, false);
        }
        self.pivots()
    }

    /// Solves A x = b in place (b of length n) with the last factorization.
    pub fn solve(&mut self, b: &mut [f64]) {
        let n = self.n;
        assert!(self.ready && b.len() == n);
        let w = &mut self.work;
        for (x, &r) in w.iter_mut().zip(&self.row_of_step) {
            *x = b[r as usize];
        }
        // L y = P b, unit lower, column by column
        for j in 0..n {
            let xj = w[j];
            if xj != 0.0 {
                let (d, end) = (self.diag[j] as usize + 1, self.lu_ptr[j + 1] as usize);
                for (&i, &l) in self.lu_row[d..end].iter().zip(&self.lu[d..end]) {
                    w[i as usize] -= l * xj;
                }
            }
        }
        // U z = y, column by column from the last
        for j in (0..n).rev() {
            let xj = w[j] * self.inv_diag[j];
            w[j] = xj;
            if xj != 0.0 {
                let (s, d) = (self.lu_ptr[j] as usize, self.diag[j] as usize);
                for (&i, &u) in self.lu_row[s..d].iter().zip(&self.lu[s..d]) {
                    w[i as usize] -= u * xj;
                }
            }
        }
        for (&x, &c) in w.iter().zip(&self.col_of_step) {
            b[c as usize] = x;
        }
    }

    /// Solves A^T x = b in place with the last factorization: with P A Q = L U,
    /// U^T L^T (P x) = Q^T b.
    pub fn solve_transpose(&mut self, b: &mut [f64]) {
        let n = self.n;
        assert!(self.ready && b.len() == n);
        let w = &mut self.work;
        for (x, &c) in w.iter_mut().zip(&self.col_of_step) {
            *x = b[c as usize];
        }
        // U^T z = Q^T b: row j of U^T is column j of U
        for j in 0..n {
            let (s, d) = (self.lu_ptr[j] as usize, self.diag[j] as usize);
            let dot: f64 =
                self.lu_row[s..d].iter().zip(&self.lu[s..d]).map(|(&i, &u)| u * w[i as usize]).sum();
            w[j] = (w[j] - dot) * self.inv_diag[j];
        }
        // L^T y = z, unit upper, from the last row
        for j in (0..n).rev() {
            let (d, end) = (self.diag[j] as usize + 1, self.lu_ptr[j + 1] as usize);
            let dot: f64 =
                self.lu_row[d..end].iter().zip(&self.lu[d..end]).map(|(&i, &l)| l * w[i as usize]).sum();
            w[j] -= dot;
        }
        for (&y, &r) in w.iter().zip(&self.row_of_step) {
            b[r as usize] = y;
        }
    }

    /// The diagnostics of the factors in place.
    fn pivots(&self) -> Pivots {
        let (mut lo, mut hi, mut column) = (f64::INFINITY, 0.0f64, 0);
        let mut sign = self.perm_sign;
        for (j, &p) in self.diag.iter().enumerate() {
            let d = self.lu[p as usize];
            let col = self.col_of_step[j] as usize;
            if !d.is_finite() {
                return Pivots { ratio: f64::NAN, column: col, det_sign: 0.0 };
            }
            if d < 0.0 {
                sign = -sign;
            }
            let d = d.abs();
            if d < lo {
                lo = d;
                column = col;
            }
            hi = hi.max(d);
        }
        // a non-finite entry of L that no later pivot met
        if self.lu.iter().any(|v| !v.is_finite()) {
            return Pivots { ratio: f64::NAN, column, det_sign: 0.0 };
        }
        let ratio = if hi > 0.0 { lo / hi } else { 0.0 };
        Pivots { ratio, column, det_sign: if lo > 0.0 { sign } else { 0.0 } }
    }

    /// Replays the program on new values. With `check`, stops at the first pivot that
    /// fails its threshold; a non-finite column goes through (the pivots report it).
    fn replay(&mut self, values: &[f64], check: bool) -> Replay {
        let lu = &mut self.lu;
        lu.fill(0.0);
        for (&v, &p) in values.iter().zip(&self.a_to_lu) {
            lu[p as usize] = v;
        }
        let mut t = 0usize;
        for j in 0..self.n {
            let ops = &self.updates[self.update_ptr[j] as usize..self.update_ptr[j + 1] as usize];
            for op in ops {
                let k = op.k as usize;
                let (l0, l1) = (self.diag[k] as usize + 1, self.lu_ptr[k + 1] as usize);
                let targets = &self.targets[t..t + (l1 - l0)];
                t += l1 - l0;
                let ukj = lu[op.u as usize];
                if ukj != 0.0 {
                    for (p, &target) in (l0..l1).zip(targets) {
                        lu[target as usize] -= lu[p] * ukj;
                    }
                }
            }
            let (d, end) = (self.diag[j] as usize, self.lu_ptr[j + 1] as usize);
            let pivot = lu[d];
            // largest candidate below the pivot; NaN wins, so that it is seen
            let largest =
                lu[d + 1..end]
                    .iter()
                    .fold(0.0f64, |m, v| if v.abs() > m || v.is_nan() { v.abs() } else { m });
            if check && pivot.abs() < PIVOT_THRESHOLD * largest {
                return Replay::Repivot;
            }
            if pivot == 0.0 {
                // all candidates zero: a singular column, left as it is
                self.inv_diag[j] = 0.0;
                continue;
            }
            let inv = 1.0 / pivot;
            self.inv_diag[j] = inv;
            for l in &mut lu[d + 1..end] {
                *l *= inv;
            }
        }
        Replay::Done
    }

    /// Chooses the row order by a left-looking factorization with partial pivoting of
    /// `values` (Gilbert-Peierls: each column is solved against the L computed so far,
    /// over its structural reach), then compiles the program for that order.
    fn choose_pivots(&mut self, values: &[f64]) {
        let n = self.n;
        self.pivot_choices += 1;
        // L by step: (row of A, value), in the order the rows were reached
        let mut l_cols: Vec<Vec<(u32, f64)>> = vec![Vec::new(); n];
        // U by step: the steps k < j (ascending) of each column
        let mut u_cols: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut x = vec![0.0f64; n];
        let mut mark = vec![NONE; n];
        let mut heap: std::collections::BinaryHeap<std::cmp::Reverse<u32>> = Default::default();
        let mut candidates: Vec<u32> = Vec::new();
        self.step_of_row.fill(NONE);
        self.row_of_step.fill(NONE);
        // rows never reached by any column are given to structurally empty steps
        let mut spare_row = 0usize;
        for j in 0..n {
            let c = self.col_of_step[j] as usize;
            candidates.clear();
            let mut reach =
                |r: u32, x: &mut [f64], heap: &mut std::collections::BinaryHeap<_>, step_of_row: &[u32]| {
                    if mark[r as usize] != j as u32 {
                        mark[r as usize] = j as u32;
                        x[r as usize] = 0.0;
                        match step_of_row[r as usize] {
                            NONE => candidates.push(r),
                            k => heap.push(std::cmp::Reverse(k)),
                        }
                    }
                };
            for p in self.a_col_ptr[c]..self.a_col_ptr[c + 1] {
                let r = self.a_row[p] as u32;
                reach(r, &mut x, &mut heap, &self.step_of_row);
                x[r as usize] = values[p];
            }
            // eliminate with the columns of L in ascending step: a topological order
            while let Some(std::cmp::Reverse(k)) = heap.pop() {
                let xk = x[self.row_of_step[k as usize] as usize];
                u_cols[j].push(k);
                for &(r, l) in &l_cols[k as usize] {
                    reach(r, &mut x, &mut heap, &self.step_of_row);
                    x[r as usize] -= l * xk;
                }
            }
            // partial pivoting: the largest candidate (the first of equals; the first if
            // none is finite, and the pivots report it)
            let mut pivot_row = candidates.first().copied().unwrap_or(NONE);
            let mut best = 0.0f64;
            for &r in candidates.iter() {
                let v = x[r as usize].abs();
                if v > best {
                    best = v;
                    pivot_row = r;
                }
            }
            if pivot_row == NONE {
                // no candidate at all: structurally singular; a spare row gives a zero pivot
                while self.step_of_row[spare_row] != NONE || mark[spare_row] == j as u32 {
                    spare_row += 1;
                }
                pivot_row = spare_row as u32;
                mark[spare_row] = j as u32;
                x[spare_row] = 0.0;
            }
            self.row_of_step[j] = pivot_row;
            self.step_of_row[pivot_row as usize] = j as u32;
            let d = x[pivot_row as usize];
            let inv = if d != 0.0 && d.is_finite() { 1.0 / d } else { 0.0 };
            l_cols[j] =
                candidates.iter().filter(|&&r| r != pivot_row).map(|&r| (r, x[r as usize] * inv)).collect();
        }
        self.perm_sign = permutation_sign(&self.row_of_step) * permutation_sign(&self.col_of_step);
        self.compile(&l_cols, &u_cols);
    }

    /// Lays out L and U for the chosen sequence and writes the program.
    fn compile(&mut self, l_cols: &[Vec<(u32, f64)>], u_cols: &[Vec<u32>]) {
        let n = self.n;
        self.lu_ptr.clear();
        self.diag.clear();
        self.lu_row.clear();
        self.lu_ptr.push(0);
        for j in 0..n {
            self.lu_row.extend(&u_cols[j]);
            self.diag.push(self.lu_row.len() as u32);
            self.lu_row.push(j as u32);
            let start = self.lu_row.len();
            self.lu_row.extend(l_cols[j].iter().map(|&(r, _)| self.step_of_row[r as usize]));
            self.lu_row[start..].sort_unstable();
            self.lu_ptr.push(self.lu_row.len() as u32);
        }
        assert!(self.lu_row.len() < NONE as usize, "factors too large for 32-bit positions");
        self.lu.clear();
        self.lu.resize(self.lu_row.len(), 0.0);
        // position of step row i in step column j (present by construction)
        let position = |lu_ptr: &[u32], lu_row: &[u32], i: u32, j: usize| -> u32 {
            let (s, e) = (lu_ptr[j] as usize, lu_ptr[j + 1] as usize);
            let at = lu_row[s..e].binary_search(&i).expect("entry in the fill pattern");
            (s + at) as u32
        };
        let mut step_of_col = vec![0u32; n];
        for (j, &c) in self.col_of_step.iter().enumerate() {
            step_of_col[c as usize] = j as u32;
        }
        self.a_to_lu.clear();
        for c in 0..n {
            let j = step_of_col[c] as usize;
            for p in self.a_col_ptr[c]..self.a_col_ptr[c + 1] {
                let i = self.step_of_row[self.a_row[p]];
                self.a_to_lu.push(position(&self.lu_ptr, &self.lu_row, i, j));
            }
        }
        self.update_ptr.clear();
        self.updates.clear();
        self.targets.clear();
        self.update_ptr.push(0);
        for j in 0..n {
            let (s, d) = (self.lu_ptr[j] as usize, self.diag[j] as usize);
            for u in s..d {
                let k = self.lu_row[u] as usize;
                self.updates.push(Update { u: u as u32, k: k as u32 });
                for p in self.diag[k] as usize + 1..self.lu_ptr[k + 1] as usize {
                    let i = self.lu_row[p];
                    self.targets.push(position(&self.lu_ptr, &self.lu_row, i, j));
                }
            }
            self.update_ptr.push(self.updates.len() as u32);
        }
        self.ready = true;
    }
}

/// The sign of a permutation given as an array (cycles counted with a visited mark).
fn permutation_sign(perm: &[u32]) -> f64 {
    let n = perm.len();
    let mut seen = vec![false; n];
    let mut sign = 1.0;
    for i in 0..n {
        let (mut j, mut len) = (i, 0usize);
        while !seen[j] {
            seen[j] = true;
            j = perm[j] as usize;
            len += 1;
        }
        // a cycle of length len is len - 1 transpositions
        if len > 0 && len % 2 == 0 {
            sign = -sign;
        }
    }
    sign
}
