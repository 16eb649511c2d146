//! The mutable workspace of one solve or sweep: every buffer allocated once, here.

use crate::constraints::Frame;
use crate::math::linear::Factor;
use crate::math::pivots::Pivots;
use crate::model::Model;

/// Per-thread state for `Model`; create with `Data::new(&model)`.
pub struct Data {
    /// n_coords: positions (x, y, theta per body)
    pub q: Vec<f64>,
    /// n_coords: velocities
    pub qd: Vec<f64>,
    /// n_coords: accelerations
    pub qdd: Vec<f64>,
    /// n_rows: the scaled residual (length rows / L) at the last Newton evaluation
    pub phi: Vec<f64>,
    /// n_rows (= n_coords unless a redundant model is solved anyway): right-hand side and
    /// solution of the linear solves (scaled)
    pub(crate) rhs: Vec<f64>,
    /// values of the scaled Phi_q, laid out by the model's symbolic factor
    pub(crate) jac: Vec<f64>,
    /// n_bodies
    pub(crate) frames: Vec<Frame>,
    /// n_bodies: (theta, cos, sin) of each body's last full sin_cos (`update_frames`)
    pub(crate) frame_base: Vec<[f64; 3]>,
    pub(crate) factor: Factor,
    /// Newton iterations of the last position solve
    pub iterations: usize,
    /// scaled residual norm (inf) at the last Newton evaluation
    pub residual: f64,
    /// pivots of the last factorization of Phi_q
    pub pivots: Pivots,
    /// n_rows: Lagrange multipliers of M qdd + Phi_q^T lambda = Q (inverse dynamics)
    pub lambda: Vec<f64>,
    /// 3 x n_rows: lambda split by cause (forces::PARTS: inertia, gravity, loads)
    pub lambda_parts: [Vec<f64>; 3],
    /// 3 x n_coords: the parts of Q - M qdd
    pub(crate) gen_force: [Vec<f64>; 3],
    /// n_coords each: q at the three steps before the previous one, qd and qdd at the one
    /// before the previous one (the sweep's predictor reads them)
    pub(crate) hist_q: [Vec<f64>; 3],
    pub(crate) hist_qd: Vec<f64>,
    pub(crate) hist_qdd: Vec<f64>,
    /// whether each Newton iteration also solves Phi_q qd = nu with its factorization (the
    /// two solves interleaved cost little more than one): set by a sweep that wants
    /// velocities
    pub(crate) with_velocity: bool,
    /// n_rows: nu, then the scaled velocities solved beside the Newton step, valid for the
    /// factorization and the time in `velocity_of` (`Factor::generation`, t)
    pub(crate) nu_rhs: Vec<f64>,
    pub(crate) velocity_of: Option<(u64, f64)>,
    /// n_coords: 1 / the model's column scales (multiplying is cheaper than dividing)
    pub(crate) inv_col_scale: Vec<f64>,
    /// the structure-aware solver's state: branch signs, closeness, Newton blocks
    pub(crate) blocks: crate::model::plan::Work,
}

impl Data {
    /// With `linear = Refactor`: how many times its pivot sequence was chosen since this
    /// workspace was made (1 after the first factorization; each re-pivoting adds one).
    /// 0 for the other kinds.
    pub fn pivot_choices(&self) -> usize {
        self.factor.pivot_choices()
    }

    /// The values of the scaled Phi_q at the last Newton evaluation, laid out as the
    /// model's linear solver reads them (column-major n x n for the dense kinds; in the
    /// order of `Model::sparsity` for the sparse ones).
    pub fn jacobian(&self) -> &[f64] {
        &self.jac
    }

    pub fn new(model: &Model) -> Data {
        Data {
            q: model.q_start.clone(),
            qd: vec![0.0; model.n_coords],
            qdd: vec![0.0; model.n_coords],
            phi: vec![0.0; model.n_rows],
            rhs: vec![0.0; model.n_rows],
            jac: vec![0.0; model.symbolic.n_values()],
            frames: vec![Frame::GROUND; model.n_bodies],
            // NaN: the first update computes sin_cos in full
            frame_base: vec![[f64::NAN, 1.0, 0.0]; model.n_bodies],
            factor: Factor::new(&model.symbolic),
            iterations: 0,
            residual: f64::NAN,
            pivots: Pivots::NONE,
            lambda: vec![0.0; model.n_rows],
            lambda_parts: std::array::from_fn(|_| vec![0.0; model.n_rows]),
            gen_force: std::array::from_fn(|_| vec![0.0; model.n_coords]),
            hist_q: std::array::from_fn(|_| vec![0.0; model.n_coords]),
            hist_qd: vec![0.0; model.n_coords],
            hist_qdd: vec![0.0; model.n_coords],
            inv_col_scale: model.col_scale.iter().map(|s| 1.0 / s).collect(),
            with_velocity: false,
            nu_rhs: vec![0.0; model.n_rows],
            velocity_of: None,
            blocks: crate::model::plan::Work::new(model.plan.as_ref().ok(), model.n_coords),
        }
    }
}
