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
//! pivot choice and a new program (allocating: rare, never in a steady state). The
//! threshold bounds every entry of L by 1 / `PIVOT_THRESHOLD`, as threshold partial
//! pivoting does.
//!
//! Written here because faer 0.24 has no numeric refactorization that keeps the pivot
//! order: its sparse LUs (simplicial and supernodal) search for pivots and rebuild the
//! patterns of L and U at every call, which is most of the work for the small and banded
//! systems of mechanisms.
//!
//! Storage: one array for the factors of P A Q = L U: the entries of L (unit diagonal not
//! stored) by ascending columns, the off-diagonal entries of U by descending columns, the
//! n pivots. The program is one multiply-add per update (target -= L entry * U entry);
//! the solves run through the entries in order, one multiply-add each, with U written as
//! D V (V = D^-1 U unit upper). All indices are steps (positions in P A Q) except where
//! said.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::colamd;
use faer::sparse::SymbolicSparseColMatRef;

use crate::math::pivots::Pivots;

mod lanes;
pub use lanes::{Lane, LaneFactors, LANES};

/// A replayed pivot smaller than this fraction of its column's largest candidate makes
/// the factorization choose its pivots again.
pub const PIVOT_THRESHOLD: f64 = 0.1;

/// When the pivots are chosen, a candidate at least this fraction of its column's largest
/// may be preferred for its sparsity: a margin of 5 above `PIVOT_THRESHOLD` before the
/// values drift far enough to need a new choice.
pub const CHOICE_THRESHOLD: f64 = 0.5;

const NONE: u32 = u32::MAX;

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
    /// nnz(L) + nnz(U) + n: the factors' values (see the module doc)
    lu: Vec<f64>,
    /// nnz(L): row and column (steps) of each entry of L, columns ascending
    l_row: Vec<u32>,
    l_col: Vec<u32>,
    /// n + 1: each column's entries of L
    l_ptr: Vec<u32>,
    /// nnz(U): row and column of each off-diagonal entry of U, columns descending
    u_row: Vec<u32>,
    u_col: Vec<u32>,
    /// nnz(U): V = D^-1 U, U's rows divided by their pivots (the solves' unit upper factor)
    v: Vec<f64>,
    /// nnz(A): where each value of A goes in `lu`; the fill positions, zeroed first
    a_to_lu: Vec<u32>,
    fill: Vec<u32>,
    /// the program: (target, L entry, U entry) positions in `lu` of each update
    /// target -= L * U, in order; n + 1 starts of each column's updates
    ops: Vec<[u32; 3]>,
    op_ptr: Vec<u32>,
    /// n: 1 / U(j, j) (0 where the pivot is 0)
    inv_diag: Vec<f64>,
    /// 2 n: dense work vectors of the solves
    work: Vec<f64>,
    /// whether a pivot sequence and its program exist
    ready: bool,
    /// how many times the pivots were chosen (1 after the first factorization)
    pivot_choices: usize,
    /// n: the entries of each row of A (the choice prefers sparse rows)
    row_degree: Vec<u32>,
}

/// What a replay checks of each pivot.
#[derive(Clone, Copy, PartialEq)]
enum Check {
    None,
    /// `PIVOT_THRESHOLD` against its column's largest candidate
    Threshold,
    /// that a new choice on these values would take it (`is_choice`)
    Choice,
}

/// Why a replay stopped.
enum Replay {
    Done,
    /// a pivot failed its threshold
    Repivot,
}

impl SparseLu {
    /// For the n x n pattern `col_ptr`, `row_idx` (compressed columns, rows sorted and
    /// unique in each column), eliminated in the column order `col_order` (the column of
    /// A at each step). Nothing is factored yet.
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize], col_order: &[usize]) -> SparseLu {
        assert!(col_ptr.len() == n + 1 && col_order.len() == n && row_idx.len() == col_ptr[n]);
        assert!(row_idx.len() < NONE as usize, "pattern too large for 32-bit positions");
        assert!(row_idx.iter().all(|&r| r < n), "a row index is out of range");
        let mut row_degree = vec![0u32; n];
        for &r in row_idx {
            row_degree[r] += 1;
        }
        let mut seen = vec![false; n];
        for &c in col_order {
            assert!(c < n && !std::mem::replace(&mut seen[c], true), "the column order is not a permutation");
        }
        SparseLu {
            n,
            a_col_ptr: col_ptr.to_vec(),
            a_row: row_idx.to_vec(),
            col_of_step: col_order.iter().map(|&c| c as u32).collect(),
            row_of_step: vec![NONE; n],
            step_of_row: vec![NONE; n],
            perm_sign: 1.0,
            lu: Vec::new(),
            l_row: Vec::new(),
            l_col: Vec::new(),
            l_ptr: Vec::new(),
            u_row: Vec::new(),
            u_col: Vec::new(),
            v: Vec::new(),
            a_to_lu: Vec::new(),
            fill: Vec::new(),
            ops: Vec::new(),
            op_ptr: Vec::new(),
            inv_diag: vec![0.0; n],
            work: vec![0.0; 2 * n],
            ready: false,
            pivot_choices: 0,
            row_degree,
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

    /// Multiply-adds of one replayed factorization.
    pub fn n_updates(&self) -> usize {
        self.ops.len()
    }

    /// (column of A, U(j, j)) of each step of the last factorization.
    pub fn diagonal(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        let d0 = self.lu.len() - self.n;
        self.col_of_step.iter().enumerate().map(move |(j, &c)| (c as usize, self.lu[d0 + j]))
    }

    /// Factors A (its values in the order of the pattern) and returns its pivots: the
    /// ratio of the smallest to the largest |U(j, j)|, the column of A of the smallest,
    /// the sign of det A. A zero pivot is reported (ratio 0, sign 0), not an error; a
    /// non-finite value gives a NaN ratio.
    pub fn factor(&mut self, values: &[f64]) -> Pivots {
        assert_eq!(values.len(), self.a_row.len(), "values do not match the pattern");
        if !self.ready || matches!(self.replay(values, Check::Threshold), Replay::Repivot) {
            self.choose_pivots(values);
            // the values that chose the pivots pass their own threshold: not checked again
            self.replay(values, Check::None);
        }
        self.pivots()
    }

    /// Factors A on the sequence it replays if every pivot passes its threshold; None
    /// where one fails or nothing was chosen yet (the factors are then left unusable
    /// until the next factorization).
    pub fn factor_replayed(&mut self, values: &[f64]) -> Option<Pivots> {
        assert_eq!(values.len(), self.a_row.len(), "values do not match the pattern");
        (self.ready && matches!(self.replay(values, Check::Threshold), Replay::Done)).then(|| self.pivots())
    }

    /// Factors A on the sequence it replays where a new choice on these values would take
    /// that sequence again (the pivots `factor_choosing` gives, to the bit, without its
    /// allocation); None where it would not, or nothing was chosen yet (the factors are
    /// then left unusable until the next factorization).
    pub fn factor_if_chosen(&mut self, values: &[f64]) -> Option<Pivots> {
        assert_eq!(values.len(), self.a_row.len(), "values do not match the pattern");
        (self.ready && matches!(self.replay(values, Check::Choice), Replay::Done)).then(|| self.pivots())
    }

    /// Factors A with its pivot sequence chosen on these values, whatever was chosen
    /// before: the pivots are then a function of A alone, not of the values a replayed
    /// sequence was chosen on (a measure of A itself; allocates, as any new choice does).
    pub fn factor_choosing(&mut self, values: &[f64]) -> Pivots {
        assert_eq!(values.len(), self.a_row.len(), "values do not match the pattern");
        // the sequence replayed, where a new choice would take it again (no allocation)
        if let Some(pivots) = self.factor_if_chosen(values) {
            return pivots;
        }
        self.choose_pivots(values);
        self.replay(values, Check::None);
        self.pivots()
    }

    /// Solves A x = b in place (b of length n) with the last factorization: with
    /// P A Q = L D V, L y = P b, then V z = D^-1 y, x = Q z.
    pub fn solve(&mut self, b: &mut [f64]) {
        assert!(self.ready && b.len() == self.n);

        let nl = self.l_row.len();
        let w = &mut self.work[..self.n];
        for (x, &r) in w.iter_mut().zip(&self.row_of_step) {
            *x = b[r as usize];
        }
        // unit lower L, entry by entry in ascending columns: w[j] is final when used
        for ((&i, &j), &l) in self.l_row.iter().zip(&self.l_col).zip(&self.lu[..nl]) {
            // SAFETY: `compile` checked every row and column index against n = w.len()
            unsafe { *w.get_unchecked_mut(i as usize) -= l * *w.get_unchecked(j as usize) };
        }
        for (x, d) in w.iter_mut().zip(&self.inv_diag) {
            *x *= d;
        }
        // unit upper V in descending columns
        for ((&i, &j), &v) in self.u_row.iter().zip(&self.u_col).zip(&self.v) {
            // SAFETY: as above
            unsafe { *w.get_unchecked_mut(i as usize) -= v * *w.get_unchecked(j as usize) };
        }
        for (&x, &c) in w.iter().zip(&self.col_of_step) {
            b[c as usize] = x;
        }
    }

    /// Solves A x = a and A y = b in place at once: the two solves interleaved, so that
    /// their chains of dependent multiply-adds overlap.
    pub fn solve_pair(&mut self, a: &mut [f64], b: &mut [f64]) {
        let n = self.n;
        assert!(self.ready && a.len() == n && b.len() == n);
        let nl = self.l_row.len();
        let (w, z) = self.work.split_at_mut(n);
        for ((x, y), &r) in w.iter_mut().zip(z.iter_mut()).zip(&self.row_of_step) {
            (*x, *y) = (a[r as usize], b[r as usize]);
        }
        for ((&i, &j), &l) in self.l_row.iter().zip(&self.l_col).zip(&self.lu[..nl]) {
            // SAFETY: `compile` checked every row and column index against n = w.len() = z.len()
            unsafe {
                *w.get_unchecked_mut(i as usize) -= l * *w.get_unchecked(j as usize);
                *z.get_unchecked_mut(i as usize) -= l * *z.get_unchecked(j as usize);
            }
        }
        for ((x, y), d) in w.iter_mut().zip(z.iter_mut()).zip(&self.inv_diag) {
            *x *= d;
            *y *= d;
        }
        for ((&i, &j), &v) in self.u_row.iter().zip(&self.u_col).zip(&self.v) {
            // SAFETY: as above
            unsafe {
                *w.get_unchecked_mut(i as usize) -= v * *w.get_unchecked(j as usize);
                *z.get_unchecked_mut(i as usize) -= v * *z.get_unchecked(j as usize);
            }
        }
        for ((&x, &y), &c) in w.iter().zip(z.iter()).zip(&self.col_of_step) {
            (a[c as usize], b[c as usize]) = (x, y);
        }
    }

    /// Solves A X = B in place for `k` right-hand sides at once, B row-major (n x k: each
    /// row's k values together), with `scratch` (n x k): every operation of the program
    /// applied to a row of k values, so the k solves run side by side (the sensitivities'
    /// many parameters).
    pub fn solve_many(&self, b: &mut [f64], k: usize, scratch: &mut [f64]) {
        let n = self.n;
        assert!(self.ready && b.len() == n * k && scratch.len() >= n * k);
        let w = &mut scratch[..n * k];
        for (step, &r) in self.row_of_step.iter().enumerate() {
            let r = r as usize;
            w[step * k..(step + 1) * k].copy_from_slice(&b[r * k..(r + 1) * k]);
        }
        let nl = self.l_row.len();
        // row i -= l row j, as `solve`, on rows of k
        let axpy = |w: &mut [f64], i: usize, j: usize, l: f64| {
            let (i, j) = (i * k, j * k);
            if i > j {
                let (lo, hi) = w.split_at_mut(i);
                for (x, y) in hi[..k].iter_mut().zip(&lo[j..j + k]) {
                    *x -= l * y;
                }
            } else {
                let (lo, hi) = w.split_at_mut(j);
                for (x, y) in lo[i..i + k].iter_mut().zip(&hi[..k]) {
                    *x -= l * y;
                }
            }
        };
        for ((&i, &j), &l) in self.l_row.iter().zip(&self.l_col).zip(&self.lu[..nl]) {
            axpy(w, i as usize, j as usize, l);
        }
        for (row, d) in w.chunks_exact_mut(k).zip(&self.inv_diag) {
            for x in row {
                *x *= d;
            }
        }
        for ((&i, &j), &v) in self.u_row.iter().zip(&self.u_col).zip(&self.v) {
            axpy(w, i as usize, j as usize, v);
        }
        for (step, &c) in self.col_of_step.iter().enumerate() {
            let c = c as usize;
            b[c * k..(c + 1) * k].copy_from_slice(&w[step * k..(step + 1) * k]);
        }
    }

    /// Solves A^T x = b in place with the last factorization: V^T D L^T (P x) = Q^T b.
    pub fn solve_transpose(&mut self, b: &mut [f64]) {
        assert!(self.ready && b.len() == self.n);

        let nl = self.l_row.len();
        let w = &mut self.work[..self.n];
        for (x, &c) in w.iter_mut().zip(&self.col_of_step) {
            *x = b[c as usize];
        }
        // V^T is unit lower: V's entries in ascending columns
        for ((&i, &j), &v) in self.u_row.iter().zip(&self.u_col).zip(&self.v).rev() {
            // SAFETY: `compile` checked every row and column index against n = w.len()
            unsafe { *w.get_unchecked_mut(j as usize) -= v * *w.get_unchecked(i as usize) };
        }
        for (x, d) in w.iter_mut().zip(&self.inv_diag) {
            *x *= d;
        }
        // L^T is unit upper: L's entries in descending columns
        for ((&i, &j), &l) in self.l_row.iter().zip(&self.l_col).zip(&self.lu[..nl]).rev() {
            // SAFETY: as above
            unsafe { *w.get_unchecked_mut(j as usize) -= l * *w.get_unchecked(i as usize) };
        }
        for (&y, &r) in w.iter().zip(&self.row_of_step) {
            b[r as usize] = y;
        }
    }

    /// The diagnostics of the factors in place.
    fn pivots(&self) -> Pivots {
        self.pivots_of(self.lu[self.lu.len() - self.n..].iter().copied())
    }

    /// The diagnostics of the pivots `diag` (U(j, j) of each step) on this sequence.
    fn pivots_of(&self, mut diag: impl Iterator<Item = f64> + Clone) -> Pivots {
        let (mut lo, mut hi, mut at, mut negative, mut finite) = (f64::INFINITY, 0.0f64, 0, 0usize, true);
        for (j, d) in diag.clone().enumerate() {
            finite &= d.is_finite();
            negative += (d < 0.0) as usize;
            let d = d.abs();
            if d < lo {
                (lo, at) = (d, j);
            }
            hi = hi.max(d);
        }
        if !finite {
            let j = diag.position(|d| !d.is_finite()).unwrap_or(0);
            return Pivots { ratio: f64::NAN, column: self.col_of_step[j] as usize, det_sign: 0.0 };
        }
        let sign = if negative % 2 == 0 { self.perm_sign } else { -self.perm_sign };
        let ratio = if hi > 0.0 { lo / hi } else { 0.0 };
        Pivots { ratio, column: self.col_of_step[at] as usize, det_sign: if lo > 0.0 { sign } else { 0.0 } }
    }

    /// Replays the program on new values. Stops at the first pivot that fails `check`;
    /// unchecked, a non-finite column goes through (the pivots report it).
    fn replay(&mut self, values: &[f64], check: Check) -> Replay {
        let lu = &mut self.lu[..];
        // SAFETY (the three loops): `compile` checked every position against lu.len()
        for &p in &self.fill {
            unsafe { *lu.get_unchecked_mut(p as usize) = 0.0 };
        }
        for (&v, &p) in values.iter().zip(&self.a_to_lu) {
            unsafe { *lu.get_unchecked_mut(p as usize) = v };
        }
        let d0 = lu.len() - self.n;
        for j in 0..self.n {
            for &[t, l, u] in &self.ops[self.op_ptr[j] as usize..self.op_ptr[j + 1] as usize] {
                unsafe {
                    *lu.get_unchecked_mut(t as usize) -=
                        *lu.get_unchecked(l as usize) * *lu.get_unchecked(u as usize)
                };
            }
            let pivot = lu[d0 + j];
            let (l0, l1) = (self.l_ptr[j] as usize, self.l_ptr[j + 1] as usize);
            let col = &mut lu[l0..l1];
            if check == Check::Choice {
                let rows = self.l_row[l0..l1].iter().map(|&i| self.row_of_step[i as usize] as usize);
                let c = self.col_of_step[j] as usize;
                let own = &self.a_row[self.a_col_ptr[c]..self.a_col_ptr[c + 1]];
                if !is_choice(pivot, self.row_of_step[j] as usize, col, rows, own, &self.row_degree) {
                    return Replay::Repivot;
                }
            }
            if pivot == 0.0 {
                if check == Check::Threshold && col.iter().any(|&l| l != 0.0) {
                    return Replay::Repivot;
                }
                // all candidates zero: a singular column, left as it is
                self.inv_diag[j] = 0.0;
                continue;
            }
            let inv = 1.0 / pivot;
            self.inv_diag[j] = inv;
            // |L| <= 1 / threshold is |pivot| >= threshold |candidate|
            let mut largest = 0.0f64;
            for l in col.iter_mut() {
                *l *= inv;
                largest = largest.max(l.abs());
            }
            if check == Check::Threshold && largest * PIVOT_THRESHOLD > 1.0 {
                return Replay::Repivot;
            }
        }
        let u0 = self.l_row.len();
        for ((v, &u), &i) in self.v.iter_mut().zip(&lu[u0..d0]).zip(&self.u_row) {
            *v = u * self.inv_diag[i as usize];
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
        let mut row_degree = vec![0usize; n];
        for &r in &self.a_row {
            row_degree[r] += 1;
        }
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
            let entries = self.a_col_ptr[c]..self.a_col_ptr[c + 1];
            for (&r, &v) in self.a_row[entries.clone()].iter().zip(&values[entries]) {
                reach(r as u32, &mut x, &mut heap, &self.step_of_row);
                x[r] = v;
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
            // threshold partial pivoting with a preference for sparse rows: of the
            // candidates at least `CHOICE_THRESHOLD` times the largest, the one whose row of
            // A has the fewest entries (then the largest; then the first reached). A
            // coordinate fixed by a row of its own (a pin on the ground) is then solved
            // from that row alone, exactly. The first candidate if none is finite (the
            // pivots report it).
            let largest = candidates.iter().fold(0.0f64, |m, &r| m.max(x[r as usize].abs()));
            let mut pivot_row = candidates.first().copied().unwrap_or(NONE);
            let mut best = (usize::MAX, 0.0f64);
            for &r in candidates.iter() {
                let v = x[r as usize].abs();
                if v >= CHOICE_THRESHOLD * largest && v > 0.0 {
                    let degree = row_degree[r as usize];
                    if degree < best.0 || (degree == best.0 && v > best.1) {
                        best = (degree, v);
                        pivot_row = r;
                    }
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
    /// Lays out L and U for the chosen sequence and writes the program.
    fn compile(&mut self, l_cols: &[Vec<(u32, f64)>], u_cols: &[Vec<u32>]) {
        let n = self.n;
        // L by ascending columns, rows ascending
        let (mut l_row, mut l_col, mut l_ptr) = (Vec::new(), Vec::new(), vec![0u32]);
        for (j, col) in l_cols.iter().enumerate() {
            let start = l_row.len();
            l_row.extend(col.iter().map(|&(r, _)| self.step_of_row[r as usize]));
            l_row[start..].sort_unstable();
            l_col.resize(l_row.len(), j as u32);
            l_ptr.push(l_row.len() as u32);
        }
        // U by descending columns
        let (mut u_row, mut u_col) = (Vec::new(), Vec::new());
        for (j, col) in u_cols.iter().enumerate().rev() {
            u_row.extend(col);
            u_col.resize(u_row.len(), j as u32);
        }
        let (nl, nu) = (l_row.len(), u_row.len());
        assert!(nl + nu + n < NONE as usize, "factors too large for 32-bit positions");
        // every entry of step column j as (row, position in lu), sorted by row
        let mut entries: Vec<Vec<(u32, u32)>> =
            (0..n).map(|j| vec![(j as u32, (nl + nu + j) as u32)]).collect();
        for (e, (&i, &j)) in l_row.iter().zip(&l_col).enumerate() {
            entries[j as usize].push((i, e as u32));
        }
        for (e, (&i, &j)) in u_row.iter().zip(&u_col).enumerate() {
            entries[j as usize].push((i, (nl + e) as u32));
        }
        for col in entries.iter_mut() {
            col.sort_unstable();
        }
        let position = |i: u32, j: usize| -> u32 {
            let col = &entries[j];
            col[col.binary_search_by_key(&i, |&(r, _)| r).expect("entry in the fill pattern")].1
        };
        let mut step_of_col = vec![0u32; n];
        for (j, &c) in self.col_of_step.iter().enumerate() {
            step_of_col[c as usize] = j as u32;
        }
        let mut covered = vec![false; nl + nu + n];
        self.a_to_lu.clear();
        for (c, &j) in step_of_col.iter().enumerate() {
            for &r in &self.a_row[self.a_col_ptr[c]..self.a_col_ptr[c + 1]] {
                let at = position(self.step_of_row[r], j as usize);
                covered[at as usize] = true;
                self.a_to_lu.push(at);
            }
        }
        self.fill = (0..covered.len() as u32).filter(|&p| !covered[p as usize]).collect();
        // column j -= L(:, k) U(k, j) for each k in U(:, j), ascending
        let (mut ops, mut op_ptr) = (Vec::new(), vec![0u32]);
        let mut level = vec![0u32; nl + nu + n];
        let mut column: Vec<(u32, [u32; 3])> = Vec::new();
        for (j, col) in u_cols.iter().enumerate() {
            column.clear();
            for &k in col {
                let u = position(k, j);
                for e in l_ptr[k as usize]..l_ptr[k as usize + 1] {
                    let t = position(l_row[e as usize], j);
                    // an update waits for its U entry's last update and follows its
                    // target's previous one: the depth at which it can run
                    let depth = (level[u as usize] + 1).max(level[t as usize]);
                    level[t as usize] = depth;
                    column.push((depth, [t, e, u]));
                }
            }
            // by depth, in order within one: independent updates side by side (the
            // chains through U(k, j) no longer serialise the column), each target's
            // updates in their order and every read after its last write, so the
            // factors are the same bits
            column.sort_by_key(|&(depth, _)| depth);
            ops.extend(column.iter().map(|&(_, op)| op));
            op_ptr.push(ops.len() as u32);
        }
        // the bounds that the unchecked loops of `replay` and the solves rely on
        let len = (nl + nu + n) as u32;
        assert!(self.a_to_lu.iter().chain(&self.fill).all(|&p| p < len));
        assert!(ops.iter().all(|op| op.iter().all(|&p| p < len)));
        assert!(l_row.iter().chain(&l_col).chain(&u_row).chain(&u_col).all(|&i| (i as usize) < n));
        self.lu = vec![0.0; nl + nu + n];
        self.v = vec![0.0; nu];
        (self.l_row, self.l_col, self.l_ptr, self.u_row, self.u_col) = (l_row, l_col, l_ptr, u_row, u_col);
        (self.ops, self.op_ptr) = (ops, op_ptr);
        self.ready = true;
    }
}

/// Whether `choose_pivots`, reaching a column with the same pivots before it, would take
/// the row replayed there: of the candidates (the pivot, then the column's entries of L
/// before scaling, in the rows `rows` of A) at least `CHOICE_THRESHOLD` times the largest,
/// the one whose row of A has the fewest entries, then the largest, then the first
/// reached: the column's own rows of A (`own`, ascending) in their order, before the rows
/// its elimination fills in. False where that order between two filled rows decides, or a
/// value is zero or not finite: a new choice then decides.
fn is_choice(
    pivot: f64,
    pivot_row: usize,
    col: &[f64],
    rows: impl Iterator<Item = usize>,
    own: &[usize],
    row_degree: &[u32],
) -> bool {
    let p = pivot.abs();
    if !(p > 0.0 && p.is_finite() && col.iter().all(|c| c.is_finite())) {
        return false;
    }
    let largest = col.iter().fold(p, |m, c| m.max(c.abs()));
    if p < CHOICE_THRESHOLD * largest {
        return false;
    }
    let degree = row_degree[pivot_row];
    let pivot_own = own.binary_search(&pivot_row).is_ok();
    col.iter().zip(rows).all(|(c, r)| {
        let v = c.abs();
        let eligible = v >= CHOICE_THRESHOLD * largest && v > 0.0;
        // a tie: the pivot must have been reached first
        let first = || pivot_own && own.binary_search(&r).map_or(true, |_| pivot_row < r);
        !eligible || row_degree[r] > degree || (row_degree[r] == degree && (v < p || (v == p && first())))
    })
}

/// A fill-reducing column order for LU with partial pivoting (faer's COLAMD): the column
/// of Phi_q eliminated at each step.
pub fn colamd_order(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Vec<usize> {
    let (mut perm, mut perm_inv) = (vec![0usize; n], vec![0usize; n]);
    let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let mut stack = MemBuffer::new(colamd::order_scratch::<usize>(n, n, row_idx.len()));
    match colamd::order(&mut perm, &mut perm_inv, sym, Default::default(), MemStack::new(&mut stack)) {
        Ok(()) => perm,
        // only on index overflow; the natural order is always valid
        Err(_) => (0..n).collect(),
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
