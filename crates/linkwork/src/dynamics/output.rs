//! What a simulation keeps at each of the times asked for: q, qd, qdd, the multipliers,
//! the constraints' drift, the energy balance and the step's diagnostics, in contiguous
//! (times x columns) arrays allocated once. A failure keeps the rows done (`n_done`).
//! qdd, the multipliers, the reactions and the pivot ratios are allocated where rows are
//! solved (`solved_rows`): a run that leaves them to `record::solve_rows` has them empty.

use crate::dynamics::initial::Moved;
use crate::model::Model;
use crate::solve::events::Event;
use crate::solve::forces::REACTION_COLUMNS;

/// Rows at the asked times (row-major) and the run's counters.
#[derive(Debug, Clone, Default)]
pub struct SimOutput {
    pub times: Vec<f64>,
    pub n_coords: usize,
    pub n_rows: usize,
    /// rows filled (the rest are NaN)
    pub n_done: usize,
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    /// qdd, `lambda`, `reactions` and `pivot_ratio`: empty until a row is solved, then
    /// of every row (NaN where not solved)
    pub qdd: Vec<f64>,
    /// multipliers of M qdd + Phi_q^T lambda = Q_A (in the rows' own units)
    pub lambda: Vec<f64>,
    /// each constraint's reaction on its side b (`solve::forces::reactions`: Fx, Fy,
    /// torque about its anchor, power), times x constraints x 4
    pub reactions: Vec<f64>,
    /// scaled |Phi| (length rows / L) and |Phi_q qd - nu| of each row, as integrated
    /// (before the row's projection onto the constraints)
    pub drift: Vec<f64>,
    pub drift_d: Vec<f64>,
    /// kinetic energy, potential energy (gravity, springs), work of what is not
    /// conservative since the start: T + V - W stays at its initial value
    pub kinetic: Vec<f64>,
    pub potential: Vec<f64>,
    pub work: Vec<f64>,
    /// the size of the step that reached each row, and its Newton (or projection)
    /// iterations
    pub step: Vec<f64>,
    pub iterations: Vec<u32>,
    /// pivot ratio of the augmented matrix at each row (small near a singular
    /// configuration of the constraints)
    pub pivot_ratio: Vec<f64>,
    /// steps taken, steps rejected, evaluations of the accelerations
    pub n_steps: usize,
    pub n_rejected: usize,
    pub n_evaluations: usize,
    /// how far the initial conditions were moved onto the constraints
    pub moved: Moved,
    /// singular configurations passed and locks met (`dynamics::events`), in time order
    pub events: Vec<Event>,
}

impl SimOutput {
    pub fn new(model: &Model, times: &[f64]) -> SimOutput {
        let (k, n, m) = (times.len(), model.n_coords, model.n_rows);
        let nan = |len: usize| vec![f64::NAN; len];
        SimOutput {
            times: times.to_vec(),
            n_coords: n,
            n_rows: m,
            n_done: 0,
            q: nan(k * n),
            qd: nan(k * n),
            drift: nan(k),
            drift_d: nan(k),
            kinetic: nan(k),
            potential: nan(k),
            work: nan(k),
            step: nan(k),
            iterations: vec![0; k],
            ..SimOutput::default()
        }
    }

    /// Allocates qdd, the multipliers, the reactions and the pivot ratios (NaN) if they
    /// are not yet: before the first row is solved.
    pub fn solved_rows(&mut self, model: &Model) {
        if self.pivot_ratio.is_empty() {
            let (k, n, m) = (self.times.len(), self.n_coords, self.n_rows);
            self.qdd = vec![f64::NAN; k * n];
            self.lambda = vec![f64::NAN; k * m];
            self.reactions = vec![f64::NAN; k * model.constraints.len() * REACTION_COLUMNS];
            self.pivot_ratio = vec![f64::NAN; k];
        }
    }

    /// Drops the rows not done (a failed or cancelled run).
    pub fn truncate(&mut self) {
        let (k, n, m) = (self.n_done, self.n_coords, self.n_rows);
        let nr = self.reactions.len() / self.times.len().max(1);
        self.reactions.truncate(k * nr);
        self.times.truncate(k);
        // (the solved rows' arrays, where still empty, stay empty)
        for (v, w) in [(&mut self.q, n), (&mut self.qd, n), (&mut self.qdd, n), (&mut self.lambda, m)] {
            v.truncate(k * w);
        }
        for v in [
            &mut self.drift,
            &mut self.drift_d,
            &mut self.kinetic,
            &mut self.potential,
            &mut self.work,
            &mut self.step,
            &mut self.pivot_ratio,
        ] {
            v.truncate(k);
        }
        self.iterations.truncate(k);
    }
}

/// One row's values, as the integrators hand them over.
pub struct Row<'a> {
    pub q: &'a [f64],
    pub qd: &'a [f64],
    pub drift: f64,
    pub drift_d: f64,
    pub work: f64,
    pub step: f64,
    pub iterations: u32,
}

impl SimOutput {
    /// Row `k`'s reactions (`per_row` values), written by the caller.
    pub fn reactions_row(&mut self, k: usize, per_row: usize) -> &mut [f64] {
        &mut self.reactions[k * per_row..(k + 1) * per_row]
    }

    /// Stores row `k` with the energies of its state.
    pub fn store(&mut self, k: usize, row: Row, kinetic: f64, potential: f64) {
        let n = self.n_coords;
        self.q[k * n..(k + 1) * n].copy_from_slice(row.q);
        self.qd[k * n..(k + 1) * n].copy_from_slice(row.qd);
        self.drift[k] = row.drift;
        self.drift_d[k] = row.drift_d;
        self.kinetic[k] = kinetic;
        self.potential[k] = potential;
        self.work[k] = row.work;
        self.step[k] = row.step;
        self.iterations[k] = row.iterations;
        self.n_done = k + 1;
    }
}
