//! The augmented matrix [[A, Phi_q^T], [Phi_q, 0]] of the equations of motion: A is M for
//! the index-1 solve of (qdd, lambda), M c_m + C c_c + K c_k for an implicit step's
//! Newton iteration. One pattern (each body's 3 x 3 block, the blocks that loads couple,
//! the constraints' Jacobian and its transpose, every diagonal entry) is compiled once;
//! each step writes values in place and the fixed-pivot `SparseLu` replays its program.
//! Rows and columns are equilibrated symmetrically (Ruiz) at every factorization, so that
//! masses, lengths and 1/h^2 of any size meet pivots of one size. Constraint rows are
//! the engine's scaled ones (length rows / L): lambda here is the scaled multiplier.
#![allow(clippy::needless_range_loop)] // numeric kernels: one index runs over several arrays

use std::collections::HashMap;

use crate::constraints::{Constraint, Frame, Rows, MAX_ROWS};
use crate::dynamics::applied::TangentBlock;
use crate::dynamics::mass::mass_block;
use crate::math::pivots::Pivots;
use crate::math::sparse_lu::{colamd_order, Lane, LaneFactors, SparseLu, LANES};
use crate::model::Model;

/// A pivot ratio below this makes `factor_solve` regularise: the constraints are near a
/// singular configuration, where an exact solve would amplify the state's small
/// inconsistencies (a stage off the constraints by its truncation error) along the
/// directions the rows stop constraining, and push the motion onto another branch.
pub const REGULARISE_BELOW: f64 = 1e-4;
/// The regularisation, -mu on the multipliers' diagonal of the equilibrated matrix: the
/// rows' components with singular values below sqrt(mu) are relaxed. Chosen on the N-four-bar
/// (A02): 3e-10 and 1e-10 let the amplification through (errors 2e-8 and 2e-6 at rtol
/// 1e-11), as do 20 refinement sweeps; from 1e-9 to 1e-8 with 2 to 10 sweeps the error
/// stops between 2e-9 and 7e-9 alike.
const MU: f64 = 1e-9;
/// Refinement sweeps of a regularised solve: the components well above sqrt(mu) converge
/// (by mu / sigma^2 each sweep), those below stay relaxed.
const REFINE: usize = 5;

/// Pivot sequences kept besides the one in use: a mechanism that turns round (A02's
/// cranks) needs a few in turn, and replaying one kept is far cheaper than a new choice.
const SPARE_SEQUENCES: usize = 3;

/// Slots of one constraint's Jacobian entries (and of their transposes).
#[derive(Debug, Clone, Copy)]
struct JacSlots {
    a: [[u32; 3]; MAX_ROWS],
    b: [[u32; 3]; MAX_ROWS],
    s: [u32; MAX_ROWS],
    at: [[u32; 3]; MAX_ROWS],
    bt: [[u32; 3]; MAX_ROWS],
    st: [u32; MAX_ROWS],
}

/// The equilibration a factorization uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Equilibration {
    /// a new one, from the values being factored
    New,
    /// the last factorization's (nearby states: the output rows of a step after its
    /// first, a step's stages, Newton's later iterations; only round-off differs), a new
    /// one all the same where none was computed yet
    Kept,
}

/// `LANES` sets of the pattern's values (the output rows of one step), equilibrated and
/// factored side by side (`Augmented::factor_lanes`).
#[derive(Debug, Clone)]
pub struct AugLanes {
    /// each lane's values in the pattern's order (unscaled)
    pub values: [Vec<f64>; LANES],
    scaled: Vec<Lane>,
    factors: LaneFactors,
}

/// The compiled pattern, its values and factors (n coordinates, m rows).
#[derive(Debug, Clone)]
pub struct Augmented {
    pub n: usize,
    pub m: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    lu: SparseLu,
    /// pivot sequences chosen before, the most recently used first (`factor_lu`)
    spare: Vec<SparseLu>,
    /// factorizations on a spare sequence so far
    pub spare_uses: usize,
    /// values in the pattern's order (unscaled)
    pub values: Vec<f64>,
    scaled: Vec<f64>,
    /// the symmetric equilibration of the last factorization
    scale: Vec<f64>,
    blocks: HashMap<(usize, usize), [u32; 9]>,
    /// each body's own block (`blocks[(i, i)]`, looked up at every fill)
    body_blocks: Vec<[u32; 9]>,
    jac: Vec<JacSlots>,
    /// the entries of Phi_q in the pattern, column by column: (position in `values`,
    /// constraint row, coordinate), for the products with Phi_q and its transpose
    jac_entries: Vec<[u32; 3]>,
    diag: Vec<u32>,
    /// whether the last factorization was regularised
    pub regularised: bool,
    /// whether `scale` holds an equilibration (`Equilibration::Kept` computes one where not)
    equilibrated: bool,
    work: Vec<f64>,
    /// a regularised solve's refinement: right-hand side, iterate, residual
    refine: Vec<f64>,
}

impl Augmented {
    pub fn new(model: &Model) -> Augmented {
        let (n, m) = (model.n_coords, model.n_rows);
        let mut cells: Vec<(usize, usize)> = Vec::new();
        let block = |cells: &mut Vec<(usize, usize)>, a: usize, b: usize| {
            for j in 0..3 {
                for k in 0..3 {
                    cells.push((3 * a + j, 3 * b + k));
                }
            }
        };
        let mut pairs = Vec::new();
        for i in 0..model.n_bodies {
            pairs.push((i, i));
        }
        for l in &model.loads {
            for a in l.bodies() {
                pairs.extend(l.bodies().map(|b| (a, b)));
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        for &(a, b) in &pairs {
            block(&mut cells, a, b);
        }
        for k in 0..n + m {
            cells.push((k, k));
        }
        for c in &model.constraints {
            for i in 0..c.n_rows {
                let r = n + c.row0 + i;
                for body in [c.body_a, c.body_b].into_iter().flatten() {
                    for j in 0..3 {
                        cells.extend([(r, 3 * body + j), (3 * body + j, r)]);
                    }
                }
                if let Some(s) = c.extra {
                    cells.extend([(r, s), (s, r)]);
                }
            }
        }
        let size = n + m;
        let mut entries: Vec<(usize, usize)> = cells.iter().map(|&(r, c)| (c, r)).collect();
        entries.sort_unstable();
        entries.dedup();
        let mut col_ptr = vec![0usize; size + 1];
        for &(c, _) in &entries {
            col_ptr[c + 1] += 1;
        }
        for c in 0..size {
            col_ptr[c + 1] += col_ptr[c];
        }
        let row_idx: Vec<usize> = entries.iter().map(|&(_, r)| r).collect();
        let slot = |r: usize, c: usize| -> u32 {
            let range = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            (col_ptr[c] + range.binary_search(&r).expect("entry in the pattern")) as u32
        };
        let blocks: HashMap<(usize, usize), [u32; 9]> = pairs
            .iter()
            .map(|&(a, b)| ((a, b), std::array::from_fn(|e| slot(3 * a + e / 3, 3 * b + e % 3))))
            .collect();
        let body_blocks = (0..model.n_bodies).map(|i| blocks[&(i, i)]).collect();
        let none = [[u32::MAX; 3]; MAX_ROWS];
        let jac = model
            .constraints
            .iter()
            .map(|c| {
                let mut s = JacSlots {
                    a: none,
                    b: none,
                    s: [u32::MAX; MAX_ROWS],
                    at: none,
                    bt: none,
                    st: [u32::MAX; MAX_ROWS],
                };
                for i in 0..c.n_rows {
                    let r = n + c.row0 + i;
                    for j in 0..3 {
                        if let Some(a) = c.body_a {
                            s.a[i][j] = slot(r, 3 * a + j);
                            s.at[i][j] = slot(3 * a + j, r);
                        }
                        if let Some(b) = c.body_b {
                            s.b[i][j] = slot(r, 3 * b + j);
                            s.bt[i][j] = slot(3 * b + j, r);
                        }
                    }
                    if let Some(k) = c.extra {
                        s.s[i] = slot(r, k);
                        s.st[i] = slot(k, r);
                    }
                }
                s
            })
            .collect();
        let diag = (0..size).map(|k| slot(k, k)).collect();
        let jac_entries = (0..n)
            .flat_map(|c| (col_ptr[c]..col_ptr[c + 1]).map(move |p| (p, c)))
            .filter(|&(p, _)| row_idx[p] >= n)
            .map(|(p, c)| [p as u32, (row_idx[p] - n) as u32, c as u32])
            .collect();
        let order = colamd_order(size, &col_ptr, &row_idx);
        let lu = SparseLu::new(size, &col_ptr, &row_idx, &order);
        let nnz = row_idx.len();
        Augmented {
            n,
            m,
            col_ptr,
            row_idx,
            lu,
            spare: Vec::with_capacity(SPARE_SEQUENCES + 1),
            spare_uses: 0,
            values: vec![0.0; nnz],
            scaled: vec![0.0; nnz],
            scale: vec![1.0; size],
            blocks,
            body_blocks,
            jac,
            jac_entries,
            diag,
            regularised: false,
            equilibrated: false,
            work: vec![0.0; 2 * size],
            refine: vec![0.0; 3 * size],
        }
    }

    /// Writes c_m M(q) in the top-left block (zeroing the rest of it), Phi_q and Phi_q^T
    /// (scaled rows) at the frames and q (own coordinates), and phi into `phi` (m).
    pub fn fill(&mut self, model: &Model, frames: &[Frame], q: &[f64], t: f64, c_m: f64, phi: &mut [f64]) {
        let values = &mut self.values[..];
        values.fill(0.0);
        for (i, body) in model.inertias.iter().enumerate() {
            let mb = mass_block(body, &frames[i]);
            let slots = self.body_blocks[i];
            for e in 0..9 {
                values[slots[e] as usize] = c_m * mb[e / 3][e % 3];
            }
        }
        for (c, s) in model.constraints.iter().zip(&self.jac) {
            let side = |b: Option<usize>| b.map_or(&Frame::GROUND, |i| &frames[i]);
            let mut rows = Rows::default();
            let extra = c.extra(q, &[]);
            c.kind.position(side(c.body_a), side(c.body_b), &extra, t, &mut rows);
            for i in 0..c.n_rows {
                let rs = c.row_scale[i];
                phi[c.row0 + i] = rows.phi[i] * rs;
                for j in 0..3 {
                    if c.body_a.is_some() {
                        values[s.a[i][j] as usize] = rows.jac_a[i][j] * rs;
                        values[s.at[i][j] as usize] = rows.jac_a[i][j] * rs;
                    }
                    if c.body_b.is_some() {
                        values[s.b[i][j] as usize] = rows.jac_b[i][j] * rs;
                        values[s.bt[i][j] as usize] = rows.jac_b[i][j] * rs;
                    }
                }
                if c.extra.is_some() {
                    values[s.s[i] as usize] += rows.jac_s[i] * rs;
                    values[s.st[i] as usize] += rows.jac_s[i] * rs;
                }
            }
        }
    }

    /// Adds c_k K + c_c C of one tangent block to the top-left block.
    pub fn add_tangent(&mut self, b: &TangentBlock, c_k: f64, c_c: f64) {
        let slots = self.blocks[&(b.row, b.col)];
        for e in 0..9 {
            self.values[slots[e] as usize] += c_k * b.k[e / 3][e % 3] + c_c * b.c[e / 3][e % 3];
        }
    }

    /// Adds v to the diagonal entry k.
    pub fn add_diagonal(&mut self, k: usize, v: f64) {
        self.values[self.diag[k] as usize] += v;
    }

    /// phi_q qd (m): the constraints' rates from the Jacobian in `values`.
    pub fn jacobian_times(&self, x: &[f64], out: &mut [f64]) {
        self.jacobian_times_of(&self.values, x, out);
    }

    /// phi_q qd (m) from the Jacobian in `values` (the pattern's order).
    fn jacobian_times_of(&self, values: &[f64], x: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for &[p, r, c] in &self.jac_entries {
            out[r as usize] += values[p as usize] * x[c as usize];
        }
    }

    /// Phi_q^T y (n): the multipliers' generalized forces.
    pub fn jacobian_transpose_times(&self, y: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for &[p, r, c] in &self.jac_entries {
            out[c as usize] += self.values[p as usize] * y[r as usize];
        }
    }

    /// r = b - A x with the unregularised values.
    fn residual(&self, x: &[f64], b: &[f64], r: &mut [f64]) {
        r.copy_from_slice(b);
        for (c, &xc) in x[..self.n + self.m].iter().enumerate() {
            let (lo, hi) = (self.col_ptr[c], self.col_ptr[c + 1]);
            for (&i, v) in self.row_idx[lo..hi].iter().zip(&self.values[lo..hi]) {
                r[i] -= v * xc;
            }
        }
    }

    /// Equilibrates (Ruiz, symmetric: a few sweeps of 1 / sqrt of each row's largest
    /// entry; none with `Equilibration::Kept` once one was computed) and factors, with -mu on the
    /// multipliers' diagonal of the equilibrated matrix. Returns the pivots.
    pub fn factor(&mut self, mu: f64, equilibration: Equilibration) -> Pivots {
        let size = self.n + self.m;
        let sweeps = if equilibration == Equilibration::Kept && self.equilibrated { 0 } else { 3 };
        self.equilibrated = true;
        if sweeps > 0 {
            self.scale.fill(1.0);
            for (a, v) in self.scaled.iter_mut().zip(&self.values) {
                *a = v.abs();
            }
        }
        // the fields as slices: their data pointers stay in registers through the loops
        let (col_ptr, row_idx, values) = (&self.col_ptr[..], &self.row_idx[..], &self.values[..]);
        let (scaled, scale) = (&mut self.scaled[..], &mut self.scale[..size]);
        let big = &mut self.work[..size];
        for _ in 0..sweeps {
            // a column's largest |a_rc| s_r s_c: the same bits as the largest of the products
            // (rounding is monotonic and the scales positive), one product per entry
            for (c, bc) in big.iter_mut().enumerate() {
                let (lo, hi) = (col_ptr[c], col_ptr[c + 1]);
                let mut b = 0.0f64;
                for (a, &r) in scaled[lo..hi].iter().zip(&row_idx[lo..hi]) {
                    let v = a * scale[r];
                    if v > b {
                        b = v;
                    }
                }
                *bc = b * scale[c];
            }
            for (s, b) in scale.iter_mut().zip(big.iter()) {
                if *b > 0.0 && b.is_finite() {
                    *s /= b.sqrt();
                }
            }
        }
        for (c, &sc) in scale.iter().enumerate() {
            let (lo, hi) = (col_ptr[c], col_ptr[c + 1]);
            for ((a, v), &r) in scaled[lo..hi].iter_mut().zip(&values[lo..hi]).zip(&row_idx[lo..hi]) {
                *a = v * scale[r] * sc;
            }
        }
        if mu > 0.0 {
            for k in self.n..size {
                self.scaled[self.diag[k] as usize] -= mu;
            }
        }
        self.regularised = mu > 0.0;
        self.factor_lu()
    }

    /// Factors the equilibrated values on the pivot sequence in use if its pivots pass
    /// their threshold, else on the most recently used spare sequence that passes (the
    /// same bound on L), else on a new choice (the sequence it replaces kept as a spare).
    fn factor_lu(&mut self) -> Pivots {
        if let Some(pivots) = self.lu.factor_replayed(&self.scaled) {
            return pivots;
        }
        for i in 0..self.spare.len() {
            if let Some(pivots) = self.spare[i].factor_replayed(&self.scaled) {
                std::mem::swap(&mut self.lu, &mut self.spare[i]);
                let used = self.spare.remove(i);
                self.spare.insert(0, used);
                self.spare_uses += 1;
                return pivots;
            }
        }
        if self.lu.pivot_choices() > 0 {
            self.spare.insert(0, self.lu.clone());
            self.spare.truncate(SPARE_SEQUENCES);
        }
        self.lu.factor(&self.scaled)
    }

    /// Solves with the last factors: b in, x out (in place).
    pub fn solve(&mut self, b: &mut [f64]) {
        for (x, s) in b.iter_mut().zip(&self.scale) {
            *x *= s;
        }
        self.lu.solve(b);
        for (x, s) in b.iter_mut().zip(&self.scale) {
            *x *= s;
        }
    }

    /// Factors and solves A x = b (x in `b` on return). Near a singular configuration
    /// (pivot ratio below `REGULARISE_BELOW`: the constraints' rows close to dependent, the
    /// multipliers not unique) the regularised matrix is factored instead and the solution
    /// refined against A a few times (augmented-Lagrangian iterations, as in Bayo and
    /// Ledesma's ALI3-P): what the rows determine converges, the nearly dependent
    /// directions stay relaxed. Returns the pivots of A.
    pub fn factor_solve(&mut self, b: &mut [f64], equilibration: Equilibration) -> Pivots {
        let pivots = self.factor_for_solve(equilibration);
        self.solve_refined(b);
        pivots
    }

    /// The factorization `factor_solve` uses: of A, or of the regularised matrix where A's
    /// pivot ratio is below `REGULARISE_BELOW`. Returns the pivots of A.
    pub fn factor_for_solve(&mut self, equilibration: Equilibration) -> Pivots {
        let pivots = self.factor(0.0, equilibration);
        if pivots.ratio < REGULARISE_BELOW {
            // the same values: the equilibration just computed (the same bits as a new one)
            self.factor(MU, Equilibration::Kept);
        }
        pivots
    }

    /// Solves A x = b with the last factors (`factor_for_solve`), refined against the
    /// values now in A if they were regularised (x in `b` on return). The factors may be
    /// of a nearby matrix: simplified Newton iterations solve with them.
    pub fn solve_refined(&mut self, b: &mut [f64]) {
        if !self.regularised {
            self.solve(b);
            return;
        }
        let size = self.n + self.m;
        // the right-hand side, the iterate and the residual in the workspace kept for them
        let mut buffer = std::mem::take(&mut self.refine);
        buffer.resize(3 * size, 0.0);
        let (rhs, rest) = buffer.split_at_mut(size);
        let (x, r) = rest.split_at_mut(size);
        rhs.copy_from_slice(b);
        r.copy_from_slice(b);
        x.fill(0.0);
        let norm_b = rhs.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(f64::MIN_POSITIVE);
        for _ in 0..REFINE {
            self.solve(r);
            for (xi, d) in x.iter_mut().zip(r.iter()) {
                *xi += d;
            }
            self.residual(x, rhs, r);
            if r.iter().fold(0.0f64, |m, v| m.max(v.abs())) <= 1e-14 * norm_b {
                break;
            }
        }
        b.copy_from_slice(x);
        self.refine = buffer;
    }

    /// A workspace for `LANES` sets of this pattern's values.
    pub fn lanes(&self) -> AugLanes {
        let nnz = self.row_idx.len();
        AugLanes {
            values: std::array::from_fn(|_| vec![0.0; nnz]),
            scaled: vec![[0.0; LANES]; nnz],
            factors: LaneFactors::default(),
        }
    }

    /// Structural entries of the matrix.
    pub fn entries(&self) -> usize {
        self.row_idx.len()
    }

    /// Whether an equilibration is in place for `factor_lanes` to keep.
    pub fn is_equilibrated(&self) -> bool {
        self.equilibrated
    }

    /// Keeps the values last filled as lane k's.
    pub fn keep_lane(&self, lanes: &mut AugLanes, k: usize) {
        lanes.values[k].copy_from_slice(&self.values);
    }

    /// Factors the lanes' values equilibrated as the last factorization was (as `factor`
    /// with `Equilibration::Kept` and no regularisation, lane by lane) on the pivot
    /// sequence in use. Per lane: Some(its pivots) where every pivot passes its threshold
    /// there, else None (that lane is left to `factor`). Nothing of the scalar
    /// factorization changes.
    pub fn factor_lanes(&self, lanes: &mut AugLanes) -> [Option<Pivots>; LANES] {
        if !self.equilibrated {
            return [None; LANES];
        }
        let size = self.n + self.m;
        let (col_ptr, row_idx, scale) = (&self.col_ptr[..], &self.row_idx[..], &self.scale[..size]);
        let [v0, v1, v2, v3] = &lanes.values;
        let nnz = row_idx.len();
        let (v0, v1, v2, v3) = (&v0[..nnz], &v1[..nnz], &v2[..nnz], &v3[..nnz]);
        let scaled = &mut lanes.scaled[..nnz];
        for (c, &sc) in scale.iter().enumerate() {
            for p in col_ptr[c]..col_ptr[c + 1] {
                let sr = scale[row_idx[p]];
                scaled[p] = [v0[p] * sr * sc, v1[p] * sr * sc, v2[p] * sr * sc, v3[p] * sr * sc];
            }
        }
        self.lu.factor_lanes(&lanes.scaled, &mut lanes.factors)
    }

    /// Solves each lane's system with its factors from `factor_lanes` (b in, x out), as
    /// `solve` does lane by lane.
    pub fn solve_lanes(&self, lanes: &mut AugLanes, b: &mut [Lane]) {
        for (x, s) in b.iter_mut().zip(&self.scale) {
            for v in x.iter_mut() {
                *v *= s;
            }
        }
        self.lu.solve_lanes(&mut lanes.factors, b);
        for (x, s) in b.iter_mut().zip(&self.scale) {
            for v in x.iter_mut() {
                *v *= s;
            }
        }
    }

    /// phi_q x (m) with lane k's Jacobian.
    pub fn lane_jacobian_times(&self, lanes: &AugLanes, k: usize, x: &[f64], out: &mut [f64]) {
        self.jacobian_times_of(&lanes.values[k], x, out);
    }

    /// The column of the coordinate most involved in a (near) null direction of A: one
    /// inverse iteration with the equilibrated matrix shifted to quasi-definite (+d on the
    /// coordinates, -d on the multipliers), from a vector of ones on the coordinates. Names
    /// the body a singular M leaves free.
    pub fn null_coordinate(&mut self) -> usize {
        let size = self.n + self.m;
        self.factor(1e-9, Equilibration::New);
        for k in 0..self.n {
            self.scaled[self.diag[k] as usize] += 1e-9;
        }
        self.lu.factor(&self.scaled);
        let mut y = vec![0.0; size];
        for (k, v) in y.iter_mut().enumerate().take(self.n) {
            *v = 1.0 + 0.1 * (k as f64).sin();
        }
        self.lu.solve(&mut y);
        (0..self.n).max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs())).unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::mass::{frames_of, mass_times};
    use crate::input::description::Description;
    use crate::model::Options;
    use nalgebra::{DMatrix, DVector};

    /// Just below the pivot threshold (a parallelogram 3.5e-4 rad from its change point:
    /// pivot ratio 8.8e-5, Phi_q's least singular value 5.7e-5) the regularised factors are
    /// refined to the exact solve: each sweep shrinks the error by about mu / sigma^2, so
    /// five leave round-off (measured: error 2e-12 of |x|, residual 7e-16 of |x|), one
    /// sweep alone 4.5e-3 of |x|. The reference: a dense LU of the same matrix.
    #[test]
    fn the_refined_regularised_solve_is_the_exact_one_just_below_the_pivot_threshold() {
        let (r2, r1, th) = (0.1, 0.3, 3.5e-4f64);
        let json = r#"{"name": "parallelogram",
            "bodies": [{"name": "crank", "x": 0.0, "y": 0.0, "theta": 0.5, "mass": 0.4, "inertia": 0.002},
                       {"name": "coupler", "x": 0.08775825618903728, "y": 0.04794255386042030, "theta": 0.0,
                        "mass": 1.1, "inertia": 0.01},
                       {"name": "rocker", "x": 0.3, "y": 0.0, "theta": 0.5, "mass": 0.7, "inertia": 0.003}],
            "joints": [{"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
                       {"type": "revolute", "name": "A", "body_a": "crank", "body_b": "coupler",
                        "at": [0.08775825618903728, 0.04794255386042030]},
                       {"type": "revolute", "name": "B", "body_a": "coupler", "body_b": "rocker",
                        "at": [0.38775825618903728, 0.04794255386042030]},
                       {"type": "revolute", "name": "O4", "body_a": "ground", "body_b": "rocker", "at": [0.3, 0.0]}]}"#;
        let model = Model::with_options(
            Description::from_json(json).unwrap(),
            Options { free: true, ..Options::default() },
        )
        .unwrap();
        let (n, m) = (model.n_coords, model.n_rows);
        let q = [0.0, 0.0, th, r2 * th.cos(), r2 * th.sin(), 0.0, r1, 0.0, th];
        let mut frames = vec![Frame::GROUND; model.n_bodies];
        frames_of(&q, &[0.0; 9], &mut frames);
        let mut aug = Augmented::new(&model);
        let mut phi = vec![0.0; m];
        aug.fill(&model, &frames, &q, 0.0, 1.0, &mut phi);
        // the dense [[M, Phi_q^T], [Phi_q, 0]] from the values filled, column by column
        let mut a = DMatrix::zeros(n + m, n + m);
        let (mut e, mut col) = (vec![0.0; n], vec![0.0; n]);
        for j in 0..n {
            e.fill(0.0);
            e[j] = 1.0;
            aug.jacobian_times(&e, &mut col[..m]);
            for i in 0..m {
                (a[(n + i, j)], a[(j, n + i)]) = (col[i], col[i]);
            }
            mass_times(&model, &frames, &e, &mut col);
            a.view_mut((0, j), (n, 1)).copy_from_slice(&col);
        }
        let b: Vec<f64> = (0..n + m).map(|i| (1.0 + 0.7 * i as f64).sin()).collect();
        let want = a.clone().lu().solve(&DVector::from_column_slice(&b)).unwrap();
        let mut x = b.clone();
        let pivots = aug.factor_solve(&mut x, Equilibration::New);
        assert!(aug.regularised && pivots.ratio < REGULARISE_BELOW, "not regularised: {}", pivots.ratio);
        let x = DVector::from_column_slice(&x);
        let (error, size) = ((&x - &want).amax(), want.amax());
        assert!(error < 1e-9 * size, "|x - x*| = {error:e}, |x*| = {size:e}");
        let residual = (&a * &x - DVector::from_column_slice(&b)).amax();
        assert!(residual < 1e-13 * size, "|A x - b| = {residual:e}, |x*| = {size:e}");
    }
}
