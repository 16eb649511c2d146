//! Many designs of one closed-form plan swept side by side (`solve::closed_form::lanes`):
//! the designs of a study whose plan is cranks and RRR dyads, with only positions (and
//! points) asked, taken `LANES` at a time. Each design starts (step 0) from its own closed
//! forms on its asked branches (`start`: no Newton from the base's drawing); then the lanes
//! take the steps a run of guarded closed-form steps takes (`time_loop`, positions only),
//! each lane's branch kept by the guard from positions (`closed_form::guard`) as the scalar
//! step keeps it. A lane that misses a step (a group near its singular configuration, no
//! assembly, a guard that cannot show the step), or whose start is not clear of its
//! singular configurations, is its design swept again alone by the general per-design
//! path, which then goes to the careful path where it must. A lane's steps are the scalar
//! guarded steps from its start, operation for operation; the start is the closed form
//! where a sweep alone starts by Newton, so the two differ by round-off (the tests bound it).

use crate::constraints::Frame;
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::closed_form::lane_ops::{Ops, Plain};
use crate::solve::closed_form::lanes::{self, Lanes, Turns, LANES, V};
use crate::solve::closed_form::{self, Block, Plan, NEAR_SINGULAR};
use crate::solve::position::PivotsAt;
use crate::sweep::outputs::{Outputs, Request};

/// Whether the lanes take this model's designs for this request: a plan the lanes step,
/// positions only (points formed from them), every step kept, nothing else asked.
pub fn fit(model: &Model, request: &Request) -> bool {
    request.derivatives == 0
        && request.every == 1
        && !request.forces
        && !request.locks
        && model.plan.as_ref().is_ok_and(|p| lanes::fits(model, p) && closed_form::guarded(p))
}

/// Step 0 of a design the lanes take, at t on the branches `signs` (each block's, as
/// `branches::Asked` holds them), from its own closed forms (`closed_form::assemble`, with
/// rates for the closeness trends the step-by-step loop starts from) and no Newton: data
/// is first put back to the drawing, so nothing of a design swept before in it is read.
/// Then the plan's state as `closed_form::resync` leaves a solved start. Some(the start's
/// pivot ratio, as a sweep's start reports it: `PivotsAt`) where every group closes on
/// its branch clear of its singular configuration with a residual within tolerance; None:
/// the design is left to its own sweep (which names its error).
pub(crate) fn start(
    model: &Model,
    plan: &Plan,
    data: &mut Data,
    pivots: &mut PivotsAt,
    t: f64,
    signs: &[f64],
) -> Option<f64> {
    if signs.len() != plan.blocks.len() {
        return None;
    }
    data.q.copy_from_slice(&model.q_start);
    data.qd.fill(0.0);
    data.qdd.fill(0.0);
    data.frames.fill(Frame::GROUND);
    // NaN: the first turn computes sin_cos in full (as `Data::new`)
    data.frame_base.fill([f64::NAN, 1.0, 0.0]);
    data.blocks.sign.copy_from_slice(signs);
    let tol = model.options.tol_residual * model.length_scale;
    let mut closeness_min = f64::INFINITY;
    for (block, &sign) in plan.blocks.iter().zip(signs) {
        let solved = match block {
            Block::Crank(b) => b.solve(model, data, t, 1),
            Block::Rrr(b) => b.solve(data, sign, 1),
            _ => return None,
        };
        let (closeness, residual) = solved.ok()?;
        if !(closeness >= NEAR_SINGULAR && residual <= tol) {
            return None;
        }
        closeness_min = closeness_min.min(closeness);
    }
    if !crate::solve::assembly::position(model, data, t).is_finite() {
        return None;
    }
    // the start's pivot ratio as a sweep's start reports it (a study's `pivot_min`): Phi_q's
    // LU there, its pivots chosen there, not the dyads' closeness
    let ratio = pivots.at(model, &data.q, t).ratio;
    if ratio.is_nan() || ratio < model.options.singular_tol {
        return None;
    }
    closed_form::resync(model, plan, data, t, 1.0, true, None);
    Some(ratio)
}

/// Where a lane's design's figures go: its kept coordinates' and points' rows
/// (n_steps x kept, n_steps x points x 2) and its smallest pivot ratio so far.
pub struct LaneRows<'a> {
    pub q: &'a mut [f64],
    pub points: &'a mut [f64],
    pub pivot_min: f64,
}

/// Steps 1.. of `LANES` designs started at step 0 in `data` (each solved there by its
/// own sweep, with no event), writing each step's kept figures into `rows` as it is taken;
/// per lane, the first step it missed (None: every step taken). `points`: each kept
/// point's body and, per lane, its place in the body. `turns`: the crank's cos and sin at
/// each step as earlier lanes took them (kept across calls by the caller). `cancelled()`,
/// polled every 4096 steps, stops the lanes: every lane not yet missed misses there. None
/// where the designs' plans are not of one shape (the caller sweeps them one by one).
#[allow(clippy::too_many_arguments)]
pub fn sweep_lanes(
    models: [&Model; LANES],
    data: [&Data; LANES],
    times: &[f64],
    outputs: &Outputs,
    points: &[(Option<usize>, [[f64; 2]; LANES])],
    rows: &mut [LaneRows; LANES],
    turns: &mut Turns,
    cancelled: &dyn Fn() -> bool,
) -> Option<[Option<usize>; LANES]> {
    let lanes = Lanes::new(models, data)?;
    // the whole loop under AVX2 where the machine has it (the lanes' arithmetic inlined),
    // else on plain arrays under the widest registers there are
    #[cfg(target_arch = "x86_64")]
    if let Some(simd) = pulp::x86::V3::try_new() {
        return Some(<pulp::x86::V3 as pulp::Simd>::vectorize(
            simd,
            Steps { o: simd, lanes, times, outputs, points, rows, turns, cancelled },
        ));
    }
    let o = Plain;
    Some(pulp::Arch::new().dispatch(Steps { o, lanes, times, outputs, points, rows, turns, cancelled }))
}

/// The steps as `pulp`'s operation: `with_simd`, inlined into the function its dispatch
/// compiles for each instruction set, takes `steps` and the lanes' arithmetic with it.
struct Steps<'a, 'm, 'r, O> {
    o: O,
    lanes: Lanes<'m>,
    times: &'a [f64],
    outputs: &'a Outputs,
    points: &'a [(Option<usize>, [[f64; 2]; LANES])],
    rows: &'a mut [LaneRows<'r>; LANES],
    turns: &'a mut Turns,
    cancelled: &'a dyn Fn() -> bool,
}

impl<O: Ops> pulp::WithSimd for Steps<'_, '_, '_, O> {
    type Output = [Option<usize>; LANES];

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        steps(
            self.o,
            self.lanes,
            self.times,
            self.outputs,
            self.points,
            self.rows,
            self.turns,
            self.cancelled,
        )
    }
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn steps<O: Ops>(
    o: O,
    mut lanes: Lanes,
    times: &[f64],
    outputs: &Outputs,
    points: &[(Option<usize>, [[f64; 2]; LANES])],
    rows: &mut [LaneRows; LANES],
    turns: &mut Turns,
    cancelled: &dyn Fn() -> bool,
) -> [Option<usize>; LANES] {
    let n = lanes.inv_scale.len();
    let kept: Vec<usize> = outputs.coords.clone().unwrap_or_else(|| (0..n).collect());
    // angles only where a kept coordinate is one (points are formed from cos and sin)
    lanes.keep_angles(&kept);
    let (nk, np) = (kept.len(), points.len());
    // each point's place in its body, per lane
    let local: Vec<[V; 2]> = points
        .iter()
        .map(|(_, u)| [std::array::from_fn(|j| u[j][0]), std::array::from_fn(|j| u[j][1])])
        .collect();
    let mut xy = vec![[[0.0; LANES]; 2]; np];
    let mut missed = [None; LANES];
    let mut q = vec![[0.0; LANES]; n];
    for k in 1..times.len() {
        if k % 4096 == 0 && cancelled() {
            for m in missed.iter_mut().filter(|m| m.is_none()) {
                *m = Some(k);
            }
            break;
        }
        let (t, h) = (times[k], times[k] - times[k - 1]);
        let ok = lanes.step_positions(o, t, h, k, turns);
        lanes.coords(&mut q);
        // `SweepOutput::store_points` from the frames the groups set, in every lane
        for (((body, _), u), p) in points.iter().zip(&local).zip(xy.iter_mut()) {
            *p = match body {
                Some(b) => {
                    let (c, s) = lanes.cos_sin(*b);
                    let (c, s, u0, u1) = (o.load(c), o.load(s), o.load(&u[0]), o.load(&u[1]));
                    let au = [o.sub(o.mul(c, u0), o.mul(s, u1)), o.add(o.mul(s, u0), o.mul(c, u1))];
                    [o.store(o.add(o.load(&q[3 * b]), au[0])), o.store(o.add(o.load(&q[3 * b + 1]), au[1]))]
                }
                None => *u,
            };
        }
        for j in 0..LANES {
            if missed[j].is_some() {
                continue;
            }
            if !ok[j] {
                missed[j] = Some(k);
                continue;
            }
            let row = &mut rows[j];
            for (o, &c) in row.q[k * nk..(k + 1) * nk].iter_mut().zip(&kept) {
                *o = q[c][j];
            }
            for (i, p) in xy.iter().enumerate() {
                let at = (k * np + i) * 2;
                row.points[at] = p[0][j];
                row.points[at + 1] = p[1][j];
            }
            row.pivot_min = row.pivot_min.min(lanes.ratio[j]);
        }
        if missed.iter().all(Option::is_some) {
            break;
        }
    }
    missed
}
