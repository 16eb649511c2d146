//! The replayed factorization and the solves of `LANES` matrices of one pattern at once,
//! on one pivot sequence: each of the program's updates and each entry of the solves is
//! one operation on a lane array, so the index loads and the chains of dependent
//! multiply-adds that bound one matrix's replay are shared by the lanes (the output rows
//! of one integration step are independent given its dense output). Each lane's
//! arithmetic is the scalar replay's, operation for operation (no fused multiply-add):
//! its factors and solutions are the same bits.

use super::{SparseLu, PIVOT_THRESHOLD};
use crate::math::pivots::Pivots;

/// Matrices factored side by side.
pub const LANES: usize = 4;

/// One value of each lane.
pub type Lane = [f64; LANES];

/// The factors of `LANES` matrices on one sequence (`SparseLu::factor_lanes`).
#[derive(Debug, Clone, Default)]
pub struct LaneFactors {
    lu: Vec<Lane>,
    inv_diag: Vec<Lane>,
    v: Vec<Lane>,
    work: Vec<Lane>,
}

impl SparseLu {
    /// Replays the program on each lane's values (in the pattern's order) at once. Per
    /// lane: Some(its pivots) where every pivot is non-zero and passes
    /// `PIVOT_THRESHOLD` (the factors the scalar `factor_replayed` gives, to the bit), None
    /// where one does not (that lane's factors are unusable) or no sequence was chosen yet.
    pub fn factor_lanes(&self, values: &[Lane], f: &mut LaneFactors) -> [Option<Pivots>; LANES] {
        assert_eq!(values.len(), self.a_row.len(), "values do not match the pattern");
        if !self.ready {
            return [None; LANES];
        }
        let good = pulp::Arch::new().dispatch(Replay { lu: self, values, f: &mut *f });
        let d0 = self.lu.len() - self.n;
        std::array::from_fn(|k| good[k].then(|| self.lane_pivots(&f.lu[d0..], k)))
    }

    /// The replay of `factor_lanes`: per lane, whether every pivot passed.
    #[inline(always)]
    fn replay_lanes(&self, values: &[Lane], f: &mut LaneFactors) -> [bool; LANES] {
        let n = self.n;
        let size = self.lu.len();
        f.lu.resize(size, [0.0; LANES]);
        f.inv_diag.resize(n, [0.0; LANES]);
        f.v.resize(self.v.len(), [0.0; LANES]);
        f.work.resize(n, [0.0; LANES]);
        let lu = &mut f.lu[..];
        // SAFETY (the loops below): `compile` checked every position against lu.len()
        for &p in &self.fill {
            unsafe { *lu.get_unchecked_mut(p as usize) = [0.0; LANES] };
        }
        for (v, &p) in values.iter().zip(&self.a_to_lu) {
            unsafe { *lu.get_unchecked_mut(p as usize) = *v };
        }
        let mut good = [true; LANES];
        let d0 = size - n;
        for j in 0..n {
            for &[t, l, u] in &self.ops[self.op_ptr[j] as usize..self.op_ptr[j + 1] as usize] {
                unsafe {
                    let (x, a, b) = (
                        *lu.get_unchecked(t as usize),
                        *lu.get_unchecked(l as usize),
                        *lu.get_unchecked(u as usize),
                    );
                    *lu.get_unchecked_mut(t as usize) = std::array::from_fn(|k| x[k] - a[k] * b[k]);
                }
            }
            let pivot = lu[d0 + j];
            let (l0, l1) = (self.l_ptr[j] as usize, self.l_ptr[j + 1] as usize);
            let mut inv = [0.0; LANES];
            for k in 0..LANES {
                // a zero pivot leaves the lane to the scalar factorization (which decides
                // between a new sequence and a singular column)
                good[k] &= pivot[k] != 0.0;
                inv[k] = 1.0 / pivot[k];
            }
            f.inv_diag[j] = inv;
            let mut largest = [0.0f64; LANES];
            for l in &mut lu[l0..l1] {
                for k in 0..LANES {
                    l[k] *= inv[k];
                    largest[k] = largest[k].max(l[k].abs());
                }
            }
            for k in 0..LANES {
                // |L| <= 1 / threshold is |pivot| >= threshold |candidate|
                good[k] &= largest[k] * PIVOT_THRESHOLD <= 1.0;
            }
        }
        let u0 = self.l_row.len();
        for ((v, u), &i) in f.v.iter_mut().zip(&lu[u0..d0]).zip(&self.u_row) {
            let d = f.inv_diag[i as usize];
            for k in 0..LANES {
                v[k] = u[k] * d[k];
            }
        }
        good
    }

    /// `pivots` of one lane's diagonal.
    fn lane_pivots(&self, diag: &[Lane], k: usize) -> Pivots {
        self.pivots_of(diag.iter().map(|d| d[k]))
    }

    /// Solves each lane's A x = b in place with its factors from `factor_lanes` (b: n
    /// lane values), as `solve` does lane by lane.
    pub fn solve_lanes(&self, f: &mut LaneFactors, b: &mut [Lane]) {
        assert!(self.ready && b.len() == self.n && f.work.len() == self.n);
        pulp::Arch::new().dispatch(Solve { lu: self, f, b });
    }

    /// The solves of `solve_lanes`.
    #[inline(always)]
    fn solve_lanes_inline(&self, f: &mut LaneFactors, b: &mut [Lane]) {
        let nl = self.l_row.len();
        let w = &mut f.work[..];
        for (x, &r) in w.iter_mut().zip(&self.row_of_step) {
            *x = b[r as usize];
        }
        for ((&i, &j), l) in self.l_row.iter().zip(&self.l_col).zip(&f.lu[..nl]) {
            // SAFETY: `compile` checked every row and column index against n = w.len()
            unsafe {
                let (x, y) = (*w.get_unchecked(i as usize), *w.get_unchecked(j as usize));
                *w.get_unchecked_mut(i as usize) = std::array::from_fn(|k| x[k] - l[k] * y[k]);
            }
        }
        for (x, d) in w.iter_mut().zip(&f.inv_diag) {
            for k in 0..LANES {
                x[k] *= d[k];
            }
        }
        for ((&i, &j), v) in self.u_row.iter().zip(&self.u_col).zip(&f.v) {
            // SAFETY: as above
            unsafe {
                let (x, y) = (*w.get_unchecked(i as usize), *w.get_unchecked(j as usize));
                *w.get_unchecked_mut(i as usize) = std::array::from_fn(|k| x[k] - v[k] * y[k]);
            }
        }
        for (x, &c) in w.iter().zip(&self.col_of_step) {
            b[c as usize] = *x;
        }
    }
}

/// `replay_lanes` as `pulp`'s operation: compiled, inlined, for the widest registers the
/// machine has (the lanes' arithmetic in one register where it has AVX).
struct Replay<'a> {
    lu: &'a SparseLu,
    values: &'a [Lane],
    f: &'a mut LaneFactors,
}

impl pulp::WithSimd for Replay<'_> {
    type Output = [bool; LANES];

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        self.lu.replay_lanes(self.values, self.f)
    }
}

/// `solve_lanes_inline` as `pulp`'s operation.
struct Solve<'a> {
    lu: &'a SparseLu,
    f: &'a mut LaneFactors,
    b: &'a mut [Lane],
}

impl pulp::WithSimd for Solve<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        self.lu.solve_lanes_inline(self.f, self.b)
    }
}
