//! The output rows of one integration step projected onto the constraints `LANES` at a
//! time: `System::project_state`'s common path (one factorization at the row's state,
//! simplified Newton for the positions, then for the rates, with no regularisation),
//! its factorization and its solves done for the lanes at once (`Augmented::factor_lanes`).
//! Each lane's arithmetic is the scalar path's, operation for operation, on the same
//! pivot sequence; a lane's row differs from `project_state`'s only by round-off (the
//! frames' cos and sin are turned from other bases: `angle::turned`). A lane that
//! leaves that path (a pivot that fails its threshold or calls for regularisation, an
//! iteration that must factor again, a residual that does not settle) is marked for the
//! scalar projection, which then handles it as it would any row.

use crate::dynamics::augmented::{AugLanes, REGULARISE_BELOW};
use crate::dynamics::mass::mass_times;
use crate::dynamics::system::{System, MAX_PROJECTION, PROJECTION_TOL};
use crate::math::sparse_lu::{Lane, LANES};
use crate::model::Model;
use crate::solve::assembly::nu_into;

/// The fewest entries of the augmented matrix for which the lanes pay: they save part of
/// each row's factorization and solves and add a fixed cost per row (the lanes' copies
/// and bookkeeping). Measured side by side (`benches/results/dynamics-2026-11-29c.md`):
/// IFToMM A01 (23 entries) 4 to 9 % slower with them; A02 (N = 1: 107 entries, and N = 2:
/// 191) and Andrews' squeezer 2 to 21 % faster, by tolerance.
pub const MIN_ENTRIES: usize = 64;

/// A lane's projection: (iterations, scaled |phi| before, after, scaled |Phi_q qd - nu|
/// before), as `project_state` returns them.
pub type Projected = (usize, f64, f64, f64);

/// Where a lane is in its projection.
#[derive(Clone, Copy, PartialEq)]
enum Stage {
    /// iterating (positions, then rates)
    Running,
    /// settled
    Done,
    /// left to the scalar projection
    Scalar,
}

/// The workspace of the lanes' projections of one model.
pub struct RowLanes {
    /// each lane's state (q, qd, its time, the work done so far), `load`ed, then projected
    pub q: [Vec<f64>; LANES],
    pub qd: [Vec<f64>; LANES],
    pub t: [f64; LANES],
    pub work: [f64; LANES],
    aug: AugLanes,
    /// n + m lane values: the right-hand sides and solutions
    x: Vec<Lane>,
    target: Vec<Vec<f64>>,
    /// each lane's rates as they came
    qd0: Vec<Vec<f64>>,
    /// each lane's phi at its last fill
    phi: Vec<Vec<f64>>,
    dq: Vec<f64>,
    rhs: Vec<f64>,
    rate: Vec<f64>,
    /// each lane's nu at its time
    nu: Vec<Vec<f64>>,
}

impl RowLanes {
    /// The workspace, where the model's augmented matrix has `MIN_ENTRIES` or more.
    pub fn for_model(model: &Model, sys: &System) -> Option<RowLanes> {
        (sys.aug.entries() >= MIN_ENTRIES).then(|| RowLanes::new(model, sys))
    }

    pub fn new(model: &Model, sys: &System) -> RowLanes {
        let (n, m) = (model.n_coords, model.n_rows);
        RowLanes {
            q: std::array::from_fn(|_| vec![0.0; n]),
            qd: std::array::from_fn(|_| vec![0.0; n]),
            t: [0.0; LANES],
            work: [0.0; LANES],
            aug: sys.aug.lanes(),
            x: vec![[0.0; LANES]; n + m],
            target: vec![vec![0.0; n]; LANES],
            qd0: vec![vec![0.0; n]; LANES],
            phi: vec![vec![0.0; m]; LANES],
            dq: vec![0.0; n],
            rhs: vec![0.0; n + m],
            rate: vec![0.0; m],
            nu: vec![vec![0.0; m]; LANES],
        }
    }

    /// Sets lane k's state from y = (q, qd, work) at t.
    pub fn load(&mut self, k: usize, t: f64, y: &[f64]) {
        let n = self.q[k].len();
        self.q[k].copy_from_slice(&y[..n]);
        self.qd[k].copy_from_slice(&y[n..2 * n]);
        (self.t[k], self.work[k]) = (t, y[2 * n]);
    }

    /// Projects the first `count` (1..=LANES) of the lanes' states (q[k], qd[k] at t[k])
    /// in place on `sys`'s workspace, whose last factorization's equilibration they keep.
    /// Per lane: Some(what `project_state` returns) where the lane took the common path
    /// (its state projected), None where it is left to `project_state` (its state then
    /// unchanged). Lanes from `count` on are not touched. The frames of `sys` are left at
    /// an unspecified lane's state.
    pub fn project(&mut self, model: &Model, sys: &mut System, count: usize) -> [Option<Projected>; LANES] {
        let (mut q, mut qd, t) = (std::mem::take(&mut self.q), std::mem::take(&mut self.qd), self.t);
        let projected = self.project_states(model, sys, &mut q, &mut qd, &t, count);
        (self.q, self.qd) = (q, qd);
        projected
    }

    /// `project` on the states given.
    fn project_states(
        &mut self,
        model: &Model,
        sys: &mut System,
        q: &mut [Vec<f64>; LANES],
        qd: &mut [Vec<f64>; LANES],
        t: &[f64; LANES],
        count: usize,
    ) -> [Option<Projected>; LANES] {
        let (n, count) = (model.n_coords, count.min(LANES));
        let mut out = [None; LANES];
        if count == 0 || !sys.aug.is_equilibrated() {
            return out;
        }
        let mut stage = [Stage::Scalar; LANES];
        let (mut before, mut residual, mut last) =
            ([f64::NAN; LANES], [f64::NAN; LANES], [f64::INFINITY; LANES]);
        let mut iterations = [0usize; LANES];
        for k in 0..count {
            residual[k] = sys.fill_at(model, &q[k], t[k]);
            sys.aug.keep_lane(&mut self.aug, k);
            self.phi[k].copy_from_slice(&sys.phi);
            before[k] = residual[k];
            self.target[k].copy_from_slice(&q[k]);
            self.qd0[k].copy_from_slice(&qd[k]);
            stage[k] = if residual[k].is_finite() { Stage::Running } else { Stage::Scalar };
        }
        // the lanes past `count` repeat lane 0's values (finite arithmetic, results unused)
        let (first, rest) = self.aug.values.split_at_mut(1);
        for v in &mut rest[count - 1..] {
            v.copy_from_slice(&first[0]);
        }
        // one factorization at each lane's state, as the scalar path's first
        let pivots = sys.aug.factor_lanes(&mut self.aug);
        for k in 0..count {
            if !pivots[k].is_some_and(|p| p.ratio >= REGULARISE_BELOW) {
                stage[k] = Stage::Scalar;
            }
        }
        // positions: lane k's correction solved where it is still above PROJECTION_TOL;
        // `fresh` (the last correction used factors of its own iterate) is true for the first
        let mut fresh = [true; LANES];
        let mut settling = [false; LANES];
        for it in 0..MAX_PROJECTION {
            let mut any = false;
            for k in 0..count {
                if stage[k] != Stage::Running || (it > 0 && !settling[k]) {
                    continue;
                }
                if it > 0 {
                    residual[k] = sys.fill_at(model, &q[k], t[k]);
                    sys.aug.keep_lane(&mut self.aug, k);
                    self.phi[k].copy_from_slice(&sys.phi);
                }
                let r = residual[k];
                let slow = r > 0.5 * last[k];
                let stalled = slow && fresh[k] && it > 0;
                if !r.is_finite() {
                    stage[k] = Stage::Scalar;
                    continue;
                }
                if r <= PROJECTION_TOL || stalled {
                    settling[k] = false;
                    if r > model.options.tol_residual {
                        stage[k] = Stage::Scalar;
                    }
                    continue;
                }
                if it > 0 && slow {
                    // the scalar path factors again here
                    stage[k] = Stage::Scalar;
                    continue;
                }
                fresh[k] = it == 0;
                settling[k] = true;
                last[k] = r;
                for ((d, a), b) in self.dq.iter_mut().zip(&self.target[k]).zip(q[k].iter()) {
                    *d = a - b;
                }
                // (at the first iteration dq = 0: the frames, those of another lane, do not matter)
                mass_times(model, sys.frames(), &self.dq, &mut self.rhs[..n]);
                for (r, p) in self.rhs[n..].iter_mut().zip(&self.phi[k]) {
                    *r = -p;
                }
                for (x, r) in self.x.iter_mut().zip(&self.rhs) {
                    x[k] = *r;
                }
                iterations[k] = it + 1;
                any = true;
            }
            if !any {
                break;
            }
            self.solve_into(sys, &settling, count, q);
            if it + 1 == MAX_PROJECTION {
                for k in 0..count {
                    if settling[k] {
                        stage[k] = Stage::Scalar;
                    }
                }
            }
        }
        // rates: corrections Phi_q d = nu - Phi_q qd at each lane's projected q (its values
        // kept at its last fill), with the factors of its start
        let mut before_d = [f64::NAN; LANES];
        let mut last_d = [f64::INFINITY; LANES];
        // a lane with no position correction keeps `fresh` as it started (true): the scalar
        // path factors at the rates' first correction (the same values, the same bits)
        for (nu, &tk) in self.nu.iter_mut().zip(t).take(count) {
            nu_into(model, tk, nu);
        }
        for it in 0..6 {
            let mut any = false;
            let mut solving = [false; LANES];
            for k in 0..count {
                if stage[k] != Stage::Running {
                    continue;
                }
                let nu = &self.nu[k];
                sys.aug.lane_jacobian_times(&self.aug, k, &qd[k], &mut self.rate);
                let size = self.rate.iter().zip(nu).fold(0.0f64, |a, (r, v)| a.max((r - v).abs()));
                let speed = qd[k].iter().zip(&model.col_scale).fold(0.0f64, |a, (v, s)| a.max((v / s).abs()));
                if it == 0 {
                    before_d[k] = size;
                }
                if !size.is_finite()
                    || size <= PROJECTION_TOL * speed.max(1.0)
                    || (size > 0.5 * last_d[k] && fresh[k])
                {
                    stage[k] = if size.is_finite() { Stage::Done } else { Stage::Scalar };
                    continue;
                }
                if size > 0.5 * last_d[k] {
                    // the scalar path factors again here
                    stage[k] = Stage::Scalar;
                    continue;
                }
                if it > 0 || iterations[k] > 0 {
                    fresh[k] = false;
                }
                last_d[k] = size;
                for (i, x) in self.x.iter_mut().enumerate() {
                    x[k] = if i < n { 0.0 } else { nu[i - n] - self.rate[i - n] };
                }
                solving[k] = true;
                any = true;
            }
            if !any {
                break;
            }
            self.solve_into(sys, &solving, count, qd);
        }
        for k in 0..count {
            match stage[k] {
                Stage::Done => out[k] = Some((iterations[k], before[k], residual[k], before_d[k])),
                // six rate corrections and still above: as the scalar loop leaves it
                Stage::Running => out[k] = Some((iterations[k], before[k], residual[k], before_d[k])),
                Stage::Scalar => {
                    // the state as it came, for the scalar projection
                    q[k].copy_from_slice(&self.target[k]);
                    qd[k].copy_from_slice(&self.qd0[k]);
                }
            }
        }
        out
    }

    /// Solves the lanes' systems (right-hand sides in `x`) with their factors and adds
    /// each `active` lane's first n components (its correction) to its `states`. Lanes
    /// not active (and those past `count`) get a zero right-hand side, so their
    /// arithmetic stays finite.
    fn solve_into(
        &mut self,
        sys: &System,
        active: &[bool; LANES],
        count: usize,
        states: &mut [Vec<f64>; LANES],
    ) {
        for x in self.x.iter_mut() {
            for k in 0..LANES {
                if k >= count || !active[k] {
                    x[k] = 0.0;
                }
            }
        }
        sys.aug.solve_lanes(&mut self.aug, &mut self.x);
        for (k, state) in states.iter_mut().enumerate().take(count) {
            if active[k] {
                for (v, d) in state.iter_mut().zip(&self.x) {
                    *v += d[k];
                }
            }
        }
    }
}
