//! The linear-solver seam: linkwork's sparse LU with a fixed pivot sequence replayed
//! every step (`sparse_lu`, the default), its small dense LU (`small_lu`), faer's dense
//! LU (partial pivoting) and faer's sparse LU (COLAMD column order, simplicial
//! left-looking factorization with partial pivoting at every step).
//! The symbolic part lives in the `Model`, the numeric factors and scratch in `Data`;
//! nothing is allocated per step once the first factorization has sized faer's buffers.
//! faer does not report a numerically zero pivot, so the pivots are checked here.
//! A redundant model solved anyway (more rows m than coordinates n) uses a dense QR
//! (faer) and least squares: `solve` takes an m-vector and leaves x in its first n
//! entries; `solve_transpose` takes b in the first n entries and leaves the
//! minimum-norm m-vector.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::householder::{
    apply_block_householder_sequence_on_the_left_in_place_scratch as apply_q_scratch,
    apply_block_householder_sequence_on_the_left_in_place_with_conj as apply_q,
};
use faer::linalg::lu::partial_pivoting::{factor as dense_factor, solve as dense_solve};
use faer::linalg::qr::no_pivoting::{factor as qr_factor, solve as qr_solve};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::perm::PermRef;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, simplicial, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, MatRef, Par};

use crate::math::pivots::{pivots, Pivots};
use crate::math::small_lu;
use crate::math::sparse_lu::SparseLu;

/// Which linear algebra solves Phi_q x = b.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearKind {
    /// the sparse LU with a fixed pivot sequence (`Refactor`) at every size
    Auto,
    /// linkwork's own dense LU (`small_lu`), for small systems
    Small,
    /// faer's dense LU
    Dense,
    /// faer's sparse LU
    Sparse,
    /// linkwork's sparse LU (`sparse_lu`): COLAMD column order, row order chosen by
    /// partial pivoting at the first factorization, then replayed; chosen again when a
    /// pivot fails its threshold
    Refactor,
    /// faer's dense QR, least squares: chosen for a redundant model solved anyway
    LeastSquares,
}

/// The part of a factorization that depends only on the pattern (in the model).
#[derive(Debug)]
pub(crate) enum SymbolicFactor {
    Small {
        n: usize,
    },
    Dense {
        n: usize,
    },
    Sparse {
        n: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        lu: SymbolicLu<usize>,
    },
    /// the pattern (compressed columns) and the column order of each step (COLAMD)
    Refactor {
        n: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        col_order: Vec<usize>,
    },
    LeastSquares {
        m: usize,
        n: usize,
    },
}

impl SymbolicFactor {
    /// The symbolic factor of an m x n Phi_q whose structural non-zeros are `cells`
    /// (row, column; repeats allowed), and each cell's slot: its position in the value
    /// array. For the sparse path the column ordering is computed once here.
    pub(crate) fn new(
        kind: LinearKind,
        m: usize,
        n: usize,
        cells: &[(usize, usize)],
    ) -> (SymbolicFactor, Vec<u32>) {
        match kind {
            LinearKind::LeastSquares => {
                // column-major m x n
                let slots = cells.iter().map(|&(row, col)| (col * m + row) as u32).collect();
                (SymbolicFactor::LeastSquares { m, n }, slots)
            }
            LinearKind::Small | LinearKind::Dense | LinearKind::Auto => {
                // column-major n x n
                let slots = cells.iter().map(|&(row, col)| (col * n + row) as u32).collect();
                if kind == LinearKind::Dense {
                    (SymbolicFactor::Dense { n }, slots)
                } else {
                    (SymbolicFactor::Small { n }, slots)
                }
            }
            LinearKind::Sparse => {
                let (col_ptr, row_idx, slots) = compressed_columns(n, cells);
                let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
                let lu =
                    factorize_symbolic_lu(sym, Default::default()).expect("symbolic LU of a square pattern");
                (SymbolicFactor::Sparse { n, col_ptr, row_idx, lu }, slots)
            }
            LinearKind::Refactor => {
                let (col_ptr, row_idx, slots) = compressed_columns(n, cells);
                let col_order = crate::math::sparse_lu::colamd_order(n, &col_ptr, &row_idx);
                (SymbolicFactor::Refactor { n, col_ptr, row_idx, col_order }, slots)
            }
        }
    }

    pub(crate) fn kind(&self) -> LinearKind {
        match self {
            SymbolicFactor::Small { .. } => LinearKind::Small,
            SymbolicFactor::Dense { .. } => LinearKind::Dense,
            SymbolicFactor::Sparse { .. } => LinearKind::Sparse,
            SymbolicFactor::Refactor { .. } => LinearKind::Refactor,
            SymbolicFactor::LeastSquares { .. } => LinearKind::LeastSquares,
        }
    }

    /// Length of the value array of Phi_q.
    pub(crate) fn n_values(&self) -> usize {
        match self {
            SymbolicFactor::Small { n } | SymbolicFactor::Dense { n } => n * n,
            SymbolicFactor::Sparse { row_idx, .. } | SymbolicFactor::Refactor { row_idx, .. } => {
                row_idx.len()
            }
            SymbolicFactor::LeastSquares { m, n } => m * n,
        }
    }

    /// The compressed-column pattern of the sparse kinds.
    pub(crate) fn pattern(&self) -> Option<(&[usize], &[usize])> {
        match self {
            SymbolicFactor::Sparse { col_ptr, row_idx, .. }
            | SymbolicFactor::Refactor { col_ptr, row_idx, .. } => Some((col_ptr, row_idx)),
            _ => None,
        }
    }

    /// Structural non-zeros of Phi_q.
    pub(crate) fn nnz(&self) -> usize {
        match self {
            SymbolicFactor::Small { n } | SymbolicFactor::Dense { n } => n * n,
            SymbolicFactor::Sparse { row_idx, .. } | SymbolicFactor::Refactor { row_idx, .. } => {
                row_idx.len()
            }
            SymbolicFactor::LeastSquares { m, n } => m * n,
        }
    }
}

/// The pattern of Phi_q in compressed columns (rows sorted, unique), and each cell's
/// position in the value array.
fn compressed_columns(n: usize, cells: &[(usize, usize)]) -> (Vec<usize>, Vec<usize>, Vec<u32>) {
    let mut entries: Vec<(usize, usize)> = cells.iter().map(|&(row, col)| (col, row)).collect();
    entries.sort_unstable();
    entries.dedup();
    let mut col_ptr = vec![0usize; n + 1];
    let row_idx: Vec<usize> = entries.iter().map(|&(_, r)| r).collect();
    for &(c, _) in &entries {
        col_ptr[c + 1] += 1;
    }
    for c in 0..n {
        col_ptr[c + 1] += col_ptr[c];
    }
    let slots = cells
        .iter()
        .map(|&(row, col)| {
            let range = &row_idx[col_ptr[col]..col_ptr[col + 1]];
            (col_ptr[col] + range.binary_search(&row).expect("entry is in the pattern")) as u32
        })
        .collect();
    (col_ptr, row_idx, slots)
}

/// Numeric factors and scratch of one kind.
pub(crate) enum Numeric {
    Small {
        /// n x n column-major: L (unit lower) and U in place
        lu: Vec<f64>,
        pivots: Vec<usize>,
        /// 1 / diagonal of U
        inv_diag: Vec<f64>,
    },
    Dense {
        /// n x n column-major: L (unit lower) and U in place
        lu: Vec<f64>,
        perm: Vec<usize>,
        perm_inv: Vec<usize>,
        stack: MemBuffer,
    },
    Sparse {
        numeric: simplicial::SimplicialLu<usize, f64>,
        row_perm: Vec<usize>,
        row_perm_inv: Vec<usize>,
        stack: MemBuffer,
    },
    Refactor(Box<SparseLu>),
    LeastSquares {
        /// m x n column-major: R above the diagonal, the Householder vectors below
        qr: Vec<f64>,
        /// block x n: the Householder factors
        q_coeff: Vec<f64>,
        block: usize,
        stack: MemBuffer,
    },
}

impl Numeric {
    pub(crate) fn new(sym: &SymbolicFactor) -> Numeric {
        match sym {
            SymbolicFactor::Small { n } => {
                Numeric::Small { lu: vec![0.0; n * n], pivots: vec![0; *n], inv_diag: vec![0.0; *n] }
            }
            SymbolicFactor::Dense { n } => {
                let n = *n;
                let req = StackReq::any_of(&[
                    dense_factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default()),
                    dense_solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
                    dense_solve::solve_transpose_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
                ]);
                Numeric::Dense {
                    lu: vec![0.0; n * n],
                    perm: vec![0; n],
                    perm_inv: vec![0; n],
                    stack: MemBuffer::new(req),
                }
            }
            SymbolicFactor::LeastSquares { m, n } => {
                let (m, n) = (*m, *n);
                let block = qr_factor::recommended_block_size::<f64>(m, n);
                let req = StackReq::any_of(&[
                    qr_factor::qr_in_place_scratch::<f64>(m, n, block, Par::Seq, Default::default()),
                    qr_solve::solve_lstsq_in_place_scratch::<f64>(m, n, block, 1, Par::Seq),
                    apply_q_scratch::<f64>(m, block, 1),
                ]);
                Numeric::LeastSquares {
                    qr: vec![0.0; m * n],
                    q_coeff: vec![0.0; block * n],
                    block,
                    stack: MemBuffer::new(req),
                }
            }
            SymbolicFactor::Refactor { n, col_ptr, row_idx, col_order } => {
                Numeric::Refactor(Box::new(SparseLu::new(*n, col_ptr, row_idx, col_order)))
            }
            SymbolicFactor::Sparse { n, .. } => {
                let n = *n;
                let req = StackReq::any_of(&[
                    simplicial::factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n),
                    simplicial::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
                    simplicial::solve_transpose_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
                ]);
                Numeric::Sparse {
                    numeric: simplicial::SimplicialLu::new(),
                    row_perm: vec![0; n],
                    row_perm_inv: vec![0; n],
                    stack: MemBuffer::new(req),
                }
            }
        }
    }

    /// Factors Phi_q (its values laid out as the symbolic factor says) and returns its
    /// pivots. A zero or non-finite pivot is reported in `Pivots::ratio`, not as an error.
    pub(crate) fn factor(&mut self, sym: &SymbolicFactor, values: &[f64]) -> Pivots {
        match (self, sym) {
            (Numeric::Small { lu, pivots: piv, inv_diag }, SymbolicFactor::Small { n }) => {
                let n = *n;
                lu.copy_from_slice(values);
                small_lu::factor(lu, n, piv, inv_diag);
                // each pivots[k] != k is one row swap
                let swaps = piv.iter().enumerate().filter(|(k, p)| *k != **p).count();
                let sign = if swaps % 2 == 0 { 1.0 } else { -1.0 };
                pivots((0..n).map(|k| (k, lu[k * n + k])), sign)
            }
            (Numeric::Dense { lu, perm, perm_inv, stack }, SymbolicFactor::Dense { n }) => {
                let n = *n;
                lu.copy_from_slice(values);
                let a = MatMut::from_column_major_slice_mut(lu, n, n);
                dense_factor::lu_in_place(
                    a,
                    perm,
                    perm_inv,
                    Par::Seq,
                    MemStack::new(stack),
                    Default::default(),
                );
                let sign = permutation_sign(perm);
                pivots((0..n).map(|k| (k, lu[k * n + k])), sign)
            }
            (
                Numeric::Sparse { numeric, row_perm, row_perm_inv, stack },
                SymbolicFactor::Sparse { n, col_ptr, row_idx, lu },
            ) => {
                let sym = SymbolicSparseColMatRef::new_checked(*n, *n, col_ptr, None, row_idx);
                let a = SparseColMatRef::new(sym, values);
                let col_perm = lu.col_perm();
                let ok = simplicial::factorize_simplicial_numeric_lu(
                    row_perm,
                    row_perm_inv,
                    numeric,
                    a,
                    col_perm,
                    MemStack::new(stack),
                );
                if ok.is_err() {
                    return Pivots { ratio: 0.0, column: 0, det_sign: 0.0 };
                }
                // the diagonal of U, column k of U being column col_perm[k] of Phi_q
                let u = numeric.u_factor_unsorted();
                let fwd = col_perm.arrays().0;
                // det Phi_q = det P_r^-1 det L det U det P_c^-1; L's diagonal may be stored
                let l = numeric.l_factor_unsorted();
                let mut sign = permutation_sign(row_perm) * col_perm_sign(fwd);
                for k in 0..*n {
                    let rows = l.row_idx_of_col_raw(k);
                    if let Some(p) = rows.iter().position(|&r| r == k) {
                        if l.val_of_col(k)[p] < 0.0 {
                            sign = -sign;
                        }
                    }
                }
                pivots(
                    (0..*n).map(|k| {
                        let rows = u.row_idx_of_col_raw(k);
                        let vals = u.val_of_col(k);
                        let d = rows.iter().zip(vals).find(|(&r, _)| r == k).map_or(0.0, |(_, &v)| v);
                        (fwd[k], d)
                    }),
                    sign,
                )
            }
            (Numeric::Refactor(lu), SymbolicFactor::Refactor { .. }) => lu.factor(values),
            (Numeric::LeastSquares { qr, q_coeff, block, stack }, SymbolicFactor::LeastSquares { m, n }) => {
                let (m, n) = (*m, *n);
                qr.copy_from_slice(values);
                qr_factor::qr_in_place(
                    MatMut::from_column_major_slice_mut(qr, m, n),
                    MatMut::from_column_major_slice_mut(q_coeff, *block, n),
                    Par::Seq,
                    MemStack::new(stack),
                    Default::default(),
                );
                // R's diagonal: how close the columns are to dependent. det Phi_q is not
                // defined for a non-square Phi_q: the sign is reported as +1
                pivots((0..n).map(|k| (k, qr[k * m + k].abs())), 1.0)
            }
            _ => unreachable!("factor and symbolic factor of different kinds"),
        }
    }

    /// Solves Phi_q x = rhs in place with the last factorization.
    pub(crate) fn solve(&mut self, sym: &SymbolicFactor, rhs: &mut [f64]) {
        let n = rhs.len();
        if let Numeric::Refactor(lu) = self {
            return lu.solve(rhs);
        }
        if let Numeric::Small { lu, pivots, inv_diag } = self {
            return small_lu::solve(lu, n, pivots, inv_diag, rhs);
        }
        if let (Numeric::LeastSquares { qr, q_coeff, block, stack }, SymbolicFactor::LeastSquares { m, n }) =
            (&mut *self, sym)
        {
            // x = R^-1 (Q^T rhs)[..n]: the least-squares solution, exact for consistent rows
            let (m, n) = (*m, *n);
            let a = MatRef::from_column_major_slice(qr, m, n);
            let coeff = MatRef::from_column_major_slice(q_coeff, *block, n);
            let x = MatMut::from_column_major_slice_mut(&mut rhs[..m], m, 1);
            return qr_solve::solve_lstsq_in_place(a, coeff, a, x, Par::Seq, MemStack::new(stack));
        }
        let x = MatMut::from_column_major_slice_mut(rhs, n, 1);
        match (self, sym) {
            (Numeric::Dense { lu, perm, perm_inv, stack }, SymbolicFactor::Dense { .. }) => {
                let lu = MatRef::from_column_major_slice(lu, n, n);
                let p = PermRef::new_checked(perm, perm_inv, n);
                dense_solve::solve_in_place(lu, lu, p, x, Par::Seq, MemStack::new(stack));
            }
            (
                Numeric::Sparse { numeric, row_perm, row_perm_inv, stack },
                SymbolicFactor::Sparse { lu, .. },
            ) => {
                let p = PermRef::new_checked(row_perm, row_perm_inv, n);
                numeric.solve_in_place_with_conj(
                    p,
                    lu.col_perm(),
                    Conj::No,
                    x,
                    Par::Seq,
                    MemStack::new(stack),
                );
            }
            _ => unreachable!("factor and symbolic factor of different kinds"),
        }
    }
}

impl Numeric {
    /// Solves Phi_q^T x = rhs in place with the last factorization (inverse dynamics).
    pub(crate) fn solve_transpose(&mut self, sym: &SymbolicFactor, rhs: &mut [f64]) {
        let n = rhs.len();
        if let Numeric::Refactor(lu) = self {
            return lu.solve_transpose(rhs);
        }
        if let Numeric::Small { lu, pivots, inv_diag } = self {
            return small_lu::solve_transpose(lu, n, pivots, inv_diag, rhs);
        }
        if let (Numeric::LeastSquares { qr, q_coeff, block, stack }, SymbolicFactor::LeastSquares { m, n }) =
            (&mut *self, sym)
        {
            // Phi_q^T x = b has many solutions; the minimum-norm one is Q (R^-T b; 0)
            let (m, n) = (*m, *n);
            let a = MatRef::from_column_major_slice(qr, m, n);
            let r_t = a.get(..n, ..).transpose();
            let (head, tail) = rhs[..m].split_at_mut(n);
            let y = MatMut::from_column_major_slice_mut(head, n, 1);
            // R^T is lower triangular; only R's upper triangle is read through it
            solve_lower_triangular_in_place(r_t, y, Par::Seq);
            tail.fill(0.0);
            let coeff = MatRef::from_column_major_slice(q_coeff, *block, n);
            let x = MatMut::from_column_major_slice_mut(&mut rhs[..m], m, 1);
            return apply_q(a, coeff, Conj::No, x, Par::Seq, MemStack::new(stack));
        }
        let x = MatMut::from_column_major_slice_mut(rhs, n, 1);
        match (self, sym) {
            (Numeric::Dense { lu, perm, perm_inv, stack }, SymbolicFactor::Dense { .. }) => {
                let lu = MatRef::from_column_major_slice(lu, n, n);
                let p = PermRef::new_checked(perm, perm_inv, n);
                dense_solve::solve_transpose_in_place(lu, lu, p, x, Par::Seq, MemStack::new(stack));
            }
            (
                Numeric::Sparse { numeric, row_perm, row_perm_inv, stack },
                SymbolicFactor::Sparse { lu, .. },
            ) => {
                let p = PermRef::new_checked(row_perm, row_perm_inv, n);
                numeric.solve_transpose_in_place_with_conj(
                    p,
                    lu.col_perm(),
                    Conj::No,
                    x,
                    Par::Seq,
                    MemStack::new(stack),
                );
            }
            _ => unreachable!("factor and symbolic factor of different kinds"),
        }
    }
}

/// Numeric factors and scratch (in `Data`), with a count of the factorizations made.
pub(crate) struct Factor {
    numeric: Numeric,
    /// one more at every factorization: a solution kept beside the factors (the
    /// velocities solved with Newton's last step) belongs to the factorization it names
    pub(crate) generation: u64,
}

impl Factor {
    pub(crate) fn new(sym: &SymbolicFactor) -> Factor {
        Factor { numeric: Numeric::new(sym), generation: 0 }
    }

    /// Factors Phi_q (its values laid out as the symbolic factor says) and returns its
    /// pivots. A zero or non-finite pivot is reported in `Pivots::ratio`, not as an error.
    pub(crate) fn factor(&mut self, sym: &SymbolicFactor, values: &[f64]) -> Pivots {
        self.generation += 1;
        self.numeric.factor(sym, values)
    }

    /// `factor`, with the pivots chosen on these values: the fixed-sequence LU otherwise
    /// replays the sequence its first factorization chose on other values (the other
    /// kinds choose at every factorization), so its pivots depend on what it factored
    /// before; these are a function of Phi_q alone.
    pub(crate) fn factor_choosing(&mut self, sym: &SymbolicFactor, values: &[f64]) -> Pivots {
        self.generation += 1;
        match &mut self.numeric {
            Numeric::Refactor(lu) => lu.factor_choosing(values),
            numeric => numeric.factor(sym, values),
        }
    }

    /// `factor_choosing` where it needs no new choice of the fixed-sequence LU's pivots
    /// (`SparseLu::factor_if_chosen`); None where it would.
    pub(crate) fn factor_if_chosen(&mut self, sym: &SymbolicFactor, values: &[f64]) -> Option<Pivots> {
        self.generation += 1;
        match &mut self.numeric {
            Numeric::Refactor(lu) => lu.factor_if_chosen(values),
            numeric => Some(numeric.factor(sym, values)),
        }
    }

    /// Solves Phi_q x = rhs in place with the last factorization.
    pub(crate) fn solve(&mut self, sym: &SymbolicFactor, rhs: &mut [f64]) {
        self.numeric.solve(sym, rhs)
    }

    /// Solves Phi_q x = a and Phi_q y = b in place, at once where the kind can: the
    /// fixed-sequence LU interleaves the two, whose triangular solves are chains of
    /// dependent multiply-adds on small systems, so that the second costs little more.
    pub(crate) fn solve_pair(&mut self, sym: &SymbolicFactor, a: &mut [f64], b: &mut [f64]) {
        match &mut self.numeric {
            Numeric::Refactor(lu) => lu.solve_pair(a, b),
            numeric => {
                numeric.solve(sym, a);
                numeric.solve(sym, b);
            }
        }
    }

    /// Solves Phi_q X = B in place for `k` right-hand sides, B row-major (n x k), with
    /// `scratch` (n x k): side by side with the fixed-sequence LU, one column at a time
    /// with the others.
    pub(crate) fn solve_many(&mut self, sym: &SymbolicFactor, b: &mut [f64], k: usize, scratch: &mut [f64]) {
        match &mut self.numeric {
            Numeric::Refactor(lu) => lu.solve_many(b, k, scratch),
            numeric => {
                let n = b.len() / k;
                for col in 0..k {
                    let x = &mut scratch[..n];
                    for (r, x) in x.iter_mut().enumerate() {
                        *x = b[r * k + col];
                    }
                    numeric.solve(sym, x);
                    for (r, x) in x.iter().enumerate() {
                        b[r * k + col] = *x;
                    }
                }
            }
        }
    }

    /// Solves Phi_q^T x = rhs in place with the last factorization (inverse dynamics).
    pub(crate) fn solve_transpose(&mut self, sym: &SymbolicFactor, rhs: &mut [f64]) {
        self.numeric.solve_transpose(sym, rhs)
    }

    /// How many times the pivot sequence of the fixed-sequence LU was chosen (0 for the
    /// other kinds, which choose pivots at every factorization).
    pub(crate) fn pivot_choices(&self) -> usize {
        match &self.numeric {
            Numeric::Refactor(lu) => lu.pivot_choices(),
            _ => 0,
        }
    }
}

/// The sign of a permutation, counting cycles in place: visited entries are marked by
/// bitwise negation (indices are < n) and restored, so nothing is allocated.
fn permutation_sign(perm: &mut [usize]) -> f64 {
    let n = perm.len();
    let mut sign = 1.0;
    for i in 0..n {
        let (mut j, mut len) = (i, 0usize);
        while perm[j] < n {
            let next = perm[j];
            perm[j] = !next;
            j = next;
            len += 1;
        }
        // a cycle of length len is len - 1 transpositions
        if len > 0 && len % 2 == 0 {
            sign = -sign;
        }
    }
    for p in perm.iter_mut() {
        *p = !*p;
    }
    sign
}

/// The sign of the fill-reducing column permutation (fixed by the model; cheap to redo).
fn col_perm_sign(fwd: &[usize]) -> f64 {
    // count inversions by cycles without mutating the model's permutation: O(n) per cycle
    // start test, so only the cycle leaders are walked
    let n = fwd.len();
    let mut sign = 1.0;
    for i in 0..n {
        let mut j = fwd[i];
        let mut len = 1usize;
        let mut leader = true;
        while j != i {
            if j < i {
                leader = false;
                break;
            }
            j = fwd[j];
            len += 1;
        }
        if leader && len % 2 == 0 {
            sign = -sign;
        }
    }
    sign
}
