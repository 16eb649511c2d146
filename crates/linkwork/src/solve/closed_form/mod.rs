//! Structure-aware solving: the mechanism's groups (`crate::model::structure`, in solving order)
//! solved one after another, each by the cheapest exact method its kind allows: a driven
//! crank by its driver's value, an RRR dyad by circle-circle, an RRP dyad by circle-line
//! (`crank`, `rrr`, `rrp`; velocities and accelerations by their 2 x 2 systems), any other
//! group by a small dense Newton block (`newton`). Each group reads only the groups before
//! it, so a step costs what its groups cost and no global system is formed.
//!
//! This is the sweep's cheap path when the model has a plan. The plan never decides a
//! branch on its own: each dyad keeps the sign of its branch (read from the configuration
//! the general path assembled), and a step that comes near a dyad's folded or stretched
//! configuration, that cannot be assembled, or whose Newton block is in doubt is handed to
//! the careful path of the general solver (`stepping::tracking`), which locates and reports
//! the event as it does for every model. The dyad's closeness to singular (|sin| of the
//! angle between its links at the middle pin) stands for the pivot ratio on such steps: 1
//! far from singular, 0 at it.

pub mod affine;
pub mod crank;
pub mod guard;
pub mod lane_ops;
pub mod lanes;
pub mod newton;
pub mod rpr;
pub mod rrp;
pub mod rrr;

use crate::constraints::{perp, sub, Frame};
use crate::model::data::Data;
use crate::model::structure::{structure, Group, Structure};
use crate::model::{Model, SolverKind};

pub use crate::model::plan::{
    Affine, Block, Crank, NewtonBlock, NewtonWork, Plan, PlanResult, Rpr, Rrp, Rrr, Work,
};

/// Newton blocks larger than this send the whole model to the general path: a dense
/// block's LU costs n^3, where the general path's sparse LU of the same rows is cheaper.
pub const MAX_NEWTON_BLOCK: usize = 24;

impl Block {
    /// "closed form" or "Newton".
    pub fn method(&self) -> &'static str {
        match self {
            Block::Newton(_) => "Newton",
            _ => "closed form",
        }
    }

    /// How the group is solved and which of its coordinates are unknowns, in words.
    pub fn describe(&self) -> String {
        match self {
            Block::Crank(_) => "closed form: one angle (the driver's value); x, y formed from the pin".into(),
            Block::Rrr(_) => {
                "closed form: the middle pin where two circles meet; both poses formed from their pins".into()
            }
            Block::Rrp(_) => {
                "closed form: the middle pin where a circle meets the slide's line; poses formed \
                              from the pins"
                    .into()
            }
            Block::Rpr(_) => "closed form: the line's direction where its offset from the other pin is \
                              met; poses formed from the pins and that angle"
                .into(),
            Block::Affine(_) => "closed form: the angles from rows affine in them, then x, y from rows \
                                affine in them (substitutions)"
                .into(),
            Block::Newton(b) => format!("Newton on its own {n} x {n} block", n = b.n),
        }
    }

    /// The group's kind in a word or two, for messages.
    pub fn name(&self) -> &'static str {
        match self {
            Block::Crank(_) => "crank",
            Block::Rrr(_) => "RRR dyad",
            Block::Rrp(_) => "RRP dyad",
            Block::Rpr(_) => "RPR dyad",
            Block::Affine(_) => "substitution group",
            Block::Newton(_) => "Newton block",
        }
    }

    /// The compiled numbers the block's closed form reads, each with its slot, where the
    /// block's sensitivities are structured (`tangents`); None where they are not.
    pub fn numbers(&self) -> Option<Numbers> {
        match self {
            Block::Crank(b) => Some(b.numbers()),
            Block::Rrr(b) => Some(b.numbers()),
            Block::Rrp(b) => Some(b.numbers()),
            Block::Rpr(_) | Block::Affine(_) | Block::Newton(_) => None,
        }
    }
}

/// The compiled numbers a block's closed form reads: (constraint, index in its
/// `params_mut`, the block's slot for it); and for a crank its driver, every number i of
/// which is its law's, in slot `first + i`: (driver, first).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Numbers {
    pub slots: Vec<(usize, usize, usize)>,
    pub law: Option<(usize, usize)>,
}

impl Numbers {
    /// The slots of a dyad link's six numbers from `first` on, where a number holds them.
    fn link(&mut self, numbers: &[Option<(usize, usize)>], first: usize) {
        for (slot, n) in numbers.iter().enumerate() {
            if let Some((c, i)) = *n {
                self.slots.push((c, i, first + slot));
            }
        }
    }
}

/// One parameter's move of one of a block's numbers: d number / d p in its slot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NumberMove {
    pub param: usize,
    pub slot: usize,
    pub w: f64,
}

/// A frame's rotation of the unit vector e_i: column i of A.
#[inline(always)]
pub(crate) fn column(f: &Frame, i: usize) -> [f64; 2] {
    if i == 0 {
        [f.c, f.s]
    } else {
        [-f.s, f.c]
    }
}

/// One body's rows of dq/dp: its x, y, theta, for the n parameters.
pub(crate) type BodyRows<'a> = [&'a mut [f64]; 3];

/// S (n_coords x n row-major) split around a block's bodies (`split`): the rest, from
/// which the known sides' rows are read.
pub(crate) struct Rest<'a> {
    n: usize,
    /// the bodies' indices in order (the same twice for one body)
    lo: usize,
    hi: usize,
    /// the rows before the first body, between the two, after the last
    pieces: [&'a [f64]; 3],
}

impl<'a> Rest<'a> {
    /// The rows (x, y, theta) of a known side, or `zeros` (n) for the ground.
    #[inline(always)]
    pub(crate) fn known(&self, side: Option<usize>, zeros: &'a [f64]) -> [&'a [f64]; 3] {
        let n = self.n;
        let Some(b) = side else { return [&zeros[..n], &zeros[..n], &zeros[..n]] };
        let rows = if b < self.lo {
            &self.pieces[0][3 * b * n..]
        } else if b < self.hi {
            &self.pieces[1][3 * (b - self.lo - 1) * n..]
        } else {
            &self.pieces[2][3 * (b - self.hi - 1) * n..]
        };
        [&rows[..n], &rows[n..2 * n], &rows[2 * n..3 * n]]
    }
}

fn body_rows(c: &mut [f64], n: usize) -> BodyRows<'_> {
    let (x, rest) = c.split_at_mut(n);
    let (y, t) = rest.split_at_mut(n);
    [x, y, t]
}

/// The rows in S of a block's bodies `first` and `second` (distinct, none of its known
/// sides), to write, and the rest of S, to read.
#[inline(always)]
pub(crate) fn split(
    s: &mut [f64],
    n: usize,
    first: usize,
    second: Option<usize>,
) -> (BodyRows<'_>, Option<BodyRows<'_>>, Rest<'_>) {
    let w = 3 * n;
    let (lo, hi) = second.map_or((first, first), |b| (first.min(b), first.max(b)));
    let (p0, rest) = s.split_at_mut(lo * w);
    let (c_lo, rest) = rest.split_at_mut(w);
    let (p1, rest) = rest.split_at_mut(hi.saturating_sub(lo + 1) * w);
    let (c_hi, p2) = if hi > lo { rest.split_at_mut(w) } else { (&mut [][..], rest) };
    let (c1, c2) = match second {
        None => (c_lo, None),
        Some(_) if first == lo => (c_lo, Some(c_hi)),
        Some(_) => (c_hi, Some(c_lo)),
    };
    let rest = Rest { n, lo, hi, pieces: [p0, p1, p2] };
    (body_rows(c1, n), c2.map(|c| body_rows(c, n)), rest)
}

/// Adds w (dx, dy, dtheta) to a body's rows in parameter j's direction.
#[inline(always)]
pub(crate) fn add_move(rows: &mut BodyRows, j: usize, w: f64, d: [f64; 3]) {
    rows[0][j] += w * d[0];
    rows[1][j] += w * d[1];
    rows[2][j] += w * d[2];
}

/// dq/dp at the configuration in data (frames current), every group in order, each by its
/// closed form differentiated (`numbers` says which blocks have one): S (n_coords x n
/// row-major) for the parameters whose moves of each block's numbers are
/// `entries[block]`. Each block's derivative is linear in its known sides' moves and its
/// numbers': its coefficients are formed once a step, then applied to the known sides'
/// rows for every parameter, and to each parameter's own moves (`entries`). `zeros`: n
/// zeros (the ground's rows: it does not move). Err where a group is within
/// `NEAR_SINGULAR` of its singular configuration (its 2 x 2 system is then as
/// ill-conditioned as Phi_q: the general path solves that step).
#[allow(clippy::too_many_arguments)]
pub fn tangents(
    model: &Model,
    plan: &Plan,
    data: &Data,
    t: f64,
    entries: &[Vec<NumberMove>],
    s: &mut [f64],
    n: usize,
    zeros: &[f64],
) -> Result<(), StepMiss> {
    for (block, entries) in plan.blocks.iter().zip(entries) {
        match block {
            Block::Crank(b) => b.tangents(model, data, t, entries, s, n, zeros),
            Block::Rrr(b) => b.tangents(data, entries, s, n, zeros)?,
            Block::Rrp(b) => b.tangents(data, entries, s, n, zeros)?,
            Block::Rpr(_) | Block::Affine(_) | Block::Newton(_) => return Err(StepMiss::Failed),
        }
    }
    Ok(())
}

impl Plan {
    /// Plans the model from its structure, or says why it cannot.
    pub fn new(model: &Model) -> PlanResult {
        if model.options.solver == SolverKind::General {
            return Err("the general path was asked for (solver = \"general\")".into());
        }
        if model.n_rows != model.n_coords {
            return Err("redundant rows are solved in the least-squares sense, all together".into());
        }
        let s = structure(model);
        Plan::from_structure(model, &s)
    }

    pub(crate) fn from_structure(model: &Model, s: &Structure) -> PlanResult {
        if !s.redundant_rows.is_empty() {
            return Err(format!("{} rows are structurally redundant", s.redundant_rows.len()));
        }
        if !s.free_coords.is_empty() {
            return Err(format!("{} coordinates are left free by the rows", s.free_coords.len()));
        }
        if s.groups.len() < 2 {
            return Err("one group holds every coordinate: there is nothing to split".into());
        }
        let mut blocks = Vec::with_capacity(s.groups.len());
        let mut newton_sizes = Vec::new();
        for g in &s.groups {
            let block = closed_form(model, g).unwrap_or_else(|| Block::Newton(NewtonBlock::new(model, g)));
            if let Block::Newton(nb) = &block {
                if nb.n > MAX_NEWTON_BLOCK {
                    return Err(format!(
                        "a group of {} coordinates has no closed form (a dense Newton block of more than {} is \
                         slower than the general sparse solve)",
                        nb.n, MAX_NEWTON_BLOCK
                    ));
                }
                newton_sizes.push(nb.n);
            }
            blocks.push(block);
        }
        Ok(Plan { blocks, newton_sizes })
    }
}

/// The closed form of a group, where its kind has one.
fn closed_form(model: &Model, g: &Group) -> Option<Block> {
    if g.coords.iter().any(|&c| c >= 3 * model.n_bodies) || g.coords.len() != 3 * g.bodies.len() {
        return None; // own coordinates (curve parameters), or a body split between groups
    }
    let subst = || Affine::new(model, g).map(Block::Affine);
    match g.kind.as_str() {
        "input" => Crank::new(model, g).map(Block::Crank).or_else(subst),
        "dyad RRR" => Rrr::new(model, g).map(Block::Rrr),
        "dyad RRP" => Rrp::new(model, g).map(Block::Rrp),
        "dyad RPR" => Rpr::new(model, g).map(Block::Rpr),
        "one body" => subst()
            .or_else(|| Rpr::slot(model, g).map(Block::Rpr))
            .or_else(|| Rrr::rod(model, g).map(Block::Rrr)),
        // the PRP and RPP dyads, and any other group whose rows give it outright
        _ => subst(),
    }
}

/// Diagnostics of one structured step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepInfo {
    /// the most Newton iterations of any Newton block (0 when every group is closed form)
    pub iterations: usize,
    /// scaled residual inf-norm of every row at the solution
    pub residual: f64,
    /// smallest closeness to singular over the groups (pivot ratio of a Newton block)
    pub closeness: f64,
    /// sign of det Phi_q
    pub det_sign: f64,
    /// scaled Newton correction of the Newton blocks from the predicted q
    pub correction: f64,
}

impl StepInfo {
    /// A group's closeness (not NaN), scaled residual and branch sign taken into the
    /// step's: `f64::min` and `max` without their NaN handling, which the closeness needs
    /// none of and a NaN residual is passed over by either way.
    #[inline(always)]
    fn take(&mut self, closeness: f64, residual: f64, sign: f64) {
        if closeness < self.closeness {
            self.closeness = closeness;
        }
        if residual > self.residual {
            self.residual = residual;
        }
        self.det_sign *= sign;
    }
}

/// Why a structured step is handed to the careful path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepMiss {
    /// a dyad cannot be assembled (its circles do not meet): a limit of motion
    NoAssembly,
    /// a group is (or is about to be) at its singular configuration
    NearSingular,
    /// a Newton block did not converge, or a value is not finite
    Failed,
}

/// Below this closeness a step goes to the careful path (the general path's threshold on
/// its pivot ratio).
pub use crate::math::pivots::NEAR_SINGULAR;

/// A frame's acceleration at body point offset `r` (world, from the body origin):
/// Rdd + thetadd B r - thetad^2 r, with qdd = (xdd, ydd, thetadd).
#[inline(always)]
pub(crate) fn point_acc(f: &Frame, qdd: [f64; 3], r: [f64; 2]) -> [f64; 2] {
    let w2 = f.thetad * f.thetad;
    [qdd[0] - qdd[2] * r[1] - w2 * r[0], qdd[1] + qdd[2] * r[0] - w2 * r[1]]
}

/// qdd of a body (zeros for the ground).
#[inline(always)]
pub(crate) fn body_qdd(data: &Data, body: Option<usize>) -> [f64; 3] {
    match body {
        Some(b) => triple(&data.qdd, b),
        None => [0.0; 3],
    }
}

/// A body's three entries of q, qd or qdd (one bounds check for the three).
#[inline(always)]
fn triple(v: &[f64], b: usize) -> [f64; 3] {
    let t = &v[3 * b..3 * b + 3];
    [t[0], t[1], t[2]]
}

/// Writes a body's three entries of q, qd or qdd (one bounds check for the three).
#[inline(always)]
fn set_triple(v: &mut [f64], b: usize, x: [f64; 3]) {
    v[3 * b..3 * b + 3].copy_from_slice(&x);
}

/// The frame of a side (the ground's identity for None).
#[inline(always)]
pub(crate) fn side(data: &Data, body: Option<usize>) -> Frame {
    match body {
        Some(b) => data.frames[b],
        None => Frame::GROUND,
    }
}

/// Writes a body's pose into q and its frame (its rates zero until `set_rates`); the
/// frame, to read back.
#[inline(always)]
pub(crate) fn set_body(data: &mut Data, b: usize, r: [f64; 2], theta: f64, c: f64, s: f64) -> &Frame {
    set_triple(&mut data.q, b, [r[0], r[1], theta]);
    let f = &mut data.frames[b];
    *f = Frame { r, theta, c, s, rd: [0.0; 2], thetad: 0.0 };
    f
}

#[inline(always)]
pub(crate) fn set_rates(data: &mut Data, b: usize, rd: [f64; 2], thetad: f64) {
    set_triple(&mut data.qd, b, [rd[0], rd[1], thetad]);
    let f = &mut data.frames[b];
    f.rd = rd;
    f.thetad = thetad;
}

/// A body's origin velocity from that of its point at p (vp) and its angular rate w.
#[inline(always)]
pub(crate) fn pinned_rates(data: &mut Data, body: usize, p: [f64; 2], vp: [f64; 2], w: f64) {
    let arm = perp(sub(data.frames[body].r, p));
    set_rates(data, body, [vp[0] + w * arm[0], vp[1] + w * arm[1]], w);
}

/// A body's origin acceleration from that of its point at p (ap), its rate w and angular
/// acceleration alpha.
#[inline(always)]
pub(crate) fn pinned_accelerations(
    data: &mut Data,
    body: usize,
    p: [f64; 2],
    ap: [f64; 2],
    w: f64,
    alpha: f64,
) {
    let r = sub(data.frames[body].r, p);
    let arm = perp(r);
    set_acc(
        data,
        body,
        [ap[0] + alpha * arm[0] - w * w * r[0], ap[1] + alpha * arm[1] - w * w * r[1]],
        alpha,
    );
}

#[inline(always)]
pub(crate) fn set_acc(data: &mut Data, b: usize, rdd: [f64; 2], thetadd: f64) {
    set_triple(&mut data.qdd, b, [rdd[0], rdd[1], thetadd]);
}

/// One step of the plan at time t: every group's positions (and with `derivatives` >= 1
/// velocities, >= 2 accelerations) in order, written into data.q, qd, qdd. `h` is the
/// step from the previous time (for the closeness trend). Err: hand the step to the
/// careful path (data.q is then partly overwritten; the careful path restarts from the
/// previous step).
pub fn step(
    model: &Model,
    plan: &Plan,
    data: &mut Data,
    t: f64,
    derivatives: u8,
    h: f64,
) -> Result<StepInfo, StepMiss> {
    step_with::<false>(model, plan, data, t, derivatives, h, &mut [], &[])
}

/// `step` inlined into its caller (a sweep's run of closed-form steps).
#[inline(always)]
pub(crate) fn step_inline(
    model: &Model,
    plan: &Plan,
    data: &mut Data,
    t: f64,
    derivatives: u8,
    h: f64,
) -> Result<StepInfo, StepMiss> {
    step_with::<false>(model, plan, data, t, derivatives, h, &mut [], &[])
}

/// `step` of positions only, each group's step also bounded by `guard` (`travel`: one
/// per body, this step's bounds written as the groups are solved, where `reads`, from
/// `guard_reads`, says a later group reads them): a step the guard cannot show on its
/// branches is a miss (`NearSingular`), for the careful path. Only for plans that are
/// `guarded`.
pub fn step_guarded(
    model: &Model,
    plan: &Plan,
    data: &mut Data,
    t: f64,
    h: f64,
    travel: &mut [guard::Travel],
    reads: &[bool],
) -> Result<StepInfo, StepMiss> {
    step_with::<true>(model, plan, data, t, 0, h, travel, reads)
}

/// `step_guarded` inlined into its caller: a sweep's loop of guarded steps, which then
/// keeps what every step reads (the plan, the model's scale) from one step to the next.
#[inline(always)]
pub(crate) fn step_guarded_inline(
    model: &Model,
    plan: &Plan,
    data: &mut Data,
    t: f64,
    h: f64,
    travel: &mut [guard::Travel],
    reads: &[bool],
) -> Result<StepInfo, StepMiss> {
    step_with::<true>(model, plan, data, t, 0, h, travel, reads)
}

/// Per group of a `guarded` plan: whether a later group's known pin is on one of its
/// bodies, so that the bounds of its bodies' motion over a step (`guard::Travel`) are read.
pub fn guard_reads(plan: &Plan, n_bodies: usize) -> Vec<bool> {
    // the bodies read by the groups after the one looked at, from the last group back
    let mut read = vec![false; n_bodies];
    let mut out = vec![true; plan.blocks.len()];
    for (i, block) in plan.blocks.iter().enumerate().rev() {
        let (bodies, known) = match block {
            Block::Crank(c) => ([Some(c.body), None], [c.known, c.base]),
            Block::Rrr(r) => ([Some(r.l1.body), Some(r.l2.body)], [r.l1.known, r.l2.known]),
            Block::Rrp(r) => ([Some(r.link.body), Some(r.slider)], [r.link.known, r.known]),
            // not guarded: every bound kept
            _ => return vec![true; plan.blocks.len()],
        };
        out[i] = bodies.iter().flatten().any(|&b| read[b]);
        for &k in known.iter().flatten() {
            read[k] = true;
        }
    }
    out
}

/// Whether a plan's steps can be guarded from positions (`guard`): cranks on the ground,
/// RRR dyads of two bodies, RRP dyads on a line fixed in the ground.
pub fn guarded(plan: &Plan) -> bool {
    plan.blocks.iter().all(|b| match b {
        Block::Crank(c) => c.known.is_none() && c.base.is_none(),
        Block::Rrr(r) => !r.rod,
        Block::Rrp(r) => r.ground_line.is_some(),
        _ => false,
    })
}

/// `step`, with `G`: each group's guard too (positions only).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn step_with<const G: bool>(
    model: &Model,
    plan: &Plan,
    data: &mut Data,
    t: f64,
    derivatives: u8,
    h: f64,
    travel: &mut [guard::Travel],
    reads: &[bool],
) -> Result<StepInfo, StepMiss> {
    let mut info = StepInfo { iterations: 0, residual: 0.0, closeness: 1.0, det_sign: 1.0, correction: 0.0 };
    let mut newton_index = 0;
    let inv_l = 1.0 / model.length_scale;
    for (i, block) in plan.blocks.iter().enumerate() {
        let sign = data.blocks.sign[i];
        let (closeness, residual) = match block {
            // a crank's closeness is 1 (it has no singular configuration): no test, no
            // trend (its entries stay [1, 0], on which the tests below never fire)
            Block::Crank(b) => {
                let (_, residual) = if G {
                    b.solve_guarded(model, data, t, h, travel)?
                } else {
                    b.solve_inline(model, data, t, derivatives)?
                };
                info.take(1.0, residual * inv_l, sign);
                continue;
            }
            // the guarded groups' positions and guard inlined here, in one pass
            Block::Rrr(b) if G => b.solve_guarded(data, sign, travel, reads[i])?,
            Block::Rrp(b) if G => b.solve_guarded(data, sign, travel, reads[i])?,
            _ if G => return Err(StepMiss::Failed),
            Block::Rrr(b) => b.solve_inline(data, sign, derivatives)?,
            Block::Rrp(b) => b.solve_inline(data, sign, derivatives)?,
            Block::Rpr(b) => b.solve(data, sign, derivatives)?,
            Block::Affine(b) => b.solve(model, data, t, derivatives, sign)?,
            Block::Newton(b) => {
                let mut work = std::mem::take(&mut data.blocks.newton[newton_index]);
                let r = b.solve(model, data, &mut work, t, derivatives);
                data.blocks.newton[newton_index] = work;
                newton_index += 1;
                let r = r?;
                info.iterations = info.iterations.max(r.iterations);
                info.correction += r.correction;
                info.det_sign *= r.det_sign;
                (r.pivot_ratio, r.residual)
            }
        };
        if closeness.is_nan() || closeness < NEAR_SINGULAR {
            return Err(StepMiss::NearSingular); // NaN too
        }
        // a closeness falling so fast that its trend reaches zero within this step: a
        // singular configuration may lie between the steps, which the fixed branch sign
        // would step across silently (onto the mirror image, closeness rising again)
        let [c1, rate] = data.blocks.close[i];
        if !matches!(block, Block::Newton(_)) && (c1 + rate * h < 0.25 * c1 || closeness < 0.25 * c1) {
            return Err(StepMiss::NearSingular);
        }
        data.blocks.next[i] = [closeness, (closeness - c1) / h];
        info.take(closeness, residual * inv_l, sign);
    }
    if !info.residual.is_finite() {
        return Err(StepMiss::Failed);
    }
    info.det_sign *= data.blocks.det_factor;
    // every group passed: the trends move on (a miss leaves them at the last step)
    std::mem::swap(&mut data.blocks.close, &mut data.blocks.next);
    Ok(info)
}

/// Velocities and accelerations at t of the configuration in data (its groups solved
/// again on their branches, with rates): data.q is left as the groups solve it, to
/// round-off the positions given, which the caller puts back. For the careful path after
/// guarded steps (`step_guarded`), which solve no rates.
pub fn rates(model: &Model, plan: &Plan, data: &mut Data, t: f64) -> Result<(), StepMiss> {
    for (i, block) in plan.blocks.iter().enumerate() {
        let sign = data.blocks.sign[i];
        match block {
            Block::Crank(b) => b.solve(model, data, t, 2)?,
            Block::Rrr(b) => b.solve(data, sign, 2)?,
            Block::Rrp(b) => b.solve(data, sign, 2)?,
            Block::Rpr(b) => b.solve(data, sign, 2)?,
            Block::Affine(b) => b.solve(model, data, t, 2, sign)?,
            Block::Newton(_) => return Err(StepMiss::Failed),
        };
    }
    Ok(())
}

/// Positions at t on the branches of `asked` (each block's sign; a Newton block's det
/// sign), every group in order: a closed form on its given branch whatever data.q holds, a Newton block from
/// data.q. A design's start on the branch it is asked for when its drawing is another
/// design's (variants): Newton from there may converge onto another assembly. Err(i, miss):
/// block i cannot be assembled on its branch (or is singular there).
pub fn assemble(
    model: &Model,
    plan: &Plan,
    data: &mut Data,
    t: f64,
    asked: &Work,
) -> Result<(), (usize, StepMiss)> {
    let signs = &asked.sign;
    data.blocks.sign.copy_from_slice(signs);
    // a Newton block's det sign, where the asked configuration has one, is its branch too
    for (work, asked) in data.blocks.newton.iter_mut().zip(&asked.newton) {
        work.det_sign = asked.det_sign;
    }
    let mut newton_index = 0;
    for (i, block) in plan.blocks.iter().enumerate() {
        let sign = signs[i];
        let solved = match block {
            Block::Crank(b) => b.solve(model, data, t, 0),
            Block::Rrr(b) => b.solve(data, sign, 0),
            Block::Rrp(b) => b.solve(data, sign, 0),
            Block::Rpr(b) => b.solve(data, sign, 0),
            Block::Affine(b) => b.solve(model, data, t, 0, sign),
            Block::Newton(b) => {
                let mut work = std::mem::take(&mut data.blocks.newton[newton_index]);
                let r = b.solve(model, data, &mut work, t, 0);
                data.blocks.newton[newton_index] = work;
                newton_index += 1;
                r.map(|r| (r.pivot_ratio, r.residual))
            }
        };
        let (closeness, residual) = solved.map_err(|miss| (i, miss))?;
        if !(closeness > 0.0 && residual.is_finite()) {
            return Err((i, StepMiss::NearSingular));
        }
    }
    Ok(())
}

/// After the general path solved a step (the start, or the careful path): each dyad's
/// branch sign and closeness read from data.q, its rate from data.qd where `rates` says
/// the velocities are solved, else by the difference from the last step's closeness over
/// `h` (None at the start: 0), the det factor from the general path's det sign.
pub fn resync(
    model: &Model,
    plan: &Plan,
    data: &mut Data,
    t: f64,
    det_sign: f64,
    rates: bool,
    h: Option<f64>,
) {
    crate::solve::assembly::update_frames(data);
    let mut product = 1.0;
    let mut newton_index = 0;
    for (i, block) in plan.blocks.iter().enumerate() {
        let (sign, closeness, rate) = match block {
            Block::Rrr(b) => b.branch(data, rates),
            Block::Rrp(b) => b.branch(data, rates),
            Block::Rpr(b) => b.branch(data, rates),
            Block::Affine(b) => b.branch(model, data, t),
            Block::Crank(_) => (1.0, 1.0, 0.0),
            Block::Newton(b) => {
                // its det sign is a factor of det Phi_q: factor the block at the solved q
                let work = &mut data.blocks.newton[newton_index];
                newton_index += 1;
                let (det, ratio) = b.pivots_at(model, &data.q, &data.frames, work, t);
                work.det_sign = det;
                product *= det;
                (1.0, ratio, 0.0)
            }
        };
        data.blocks.sign[i] = sign;
        let rate = match h {
            Some(h) if !rates => (closeness - data.blocks.close[i][0]) / h,
            _ => rate,
        };
        data.blocks.close[i] = [closeness, rate];
        product *= sign;
    }
    if det_sign != 0.0 && product != 0.0 {
        data.blocks.det_factor = det_sign * product;
    }
}
