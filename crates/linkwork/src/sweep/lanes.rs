//! Many designs of one closed-form plan swept side by side (`solve::closed_form::lanes`):
//! the designs of a study whose plan is cranks and RRR dyads, with only positions (and
//! points) asked, taken `LANES` at a time. Each design's start (step 0) is its own sweep's,
//! on its asked branches (`branches::sweep_on`); then the lanes take the steps a run of
//! guarded closed-form steps takes (`time_loop`, positions only), each lane's branch kept
//! by the guard from positions (`closed_form::guard`) as the scalar step keeps it. A lane
//! that misses a step (a group near its singular configuration, no assembly, a guard that
//! cannot show the step), or whose start had an event,
//! is its design swept again alone by the general per-design path, which then goes to the
//! careful path where it must: every design's figures are the scalar engine's, bit for bit.

use crate::model::data::Data;
use crate::model::Model;
use crate::solve::closed_form;
use crate::solve::closed_form::lanes::{self, Lanes, LANES};
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
/// point's body and, per lane, its place in the body. `cancelled()`, polled every 4096
/// steps, stops the lanes: every lane not yet missed misses there. None where the designs'
/// plans are not of one shape (the caller sweeps them one by one).
pub fn sweep_lanes(
    models: [&Model; LANES],
    data: [&Data; LANES],
    times: &[f64],
    outputs: &Outputs,
    points: &[(Option<usize>, [[f64; 2]; LANES])],
    rows: &mut [LaneRows; LANES],
    cancelled: &dyn Fn() -> bool,
) -> Option<[Option<usize>; LANES]> {
    let lanes = Lanes::new(models, data)?;
    // the whole loop under the machine's widest registers (the lanes' arithmetic inlined)
    Some(pulp::Arch::new().dispatch(Steps { lanes, times, outputs, points, rows, cancelled }))
}

/// The steps as `pulp`'s operation: `with_simd`, inlined into the function its dispatch
/// compiles for each instruction set, takes `steps` and the lanes' arithmetic with it.
struct Steps<'a, 'm, 'r> {
    lanes: Lanes<'m>,
    times: &'a [f64],
    outputs: &'a Outputs,
    points: &'a [(Option<usize>, [[f64; 2]; LANES])],
    rows: &'a mut [LaneRows<'r>; LANES],
    cancelled: &'a dyn Fn() -> bool,
}

impl pulp::WithSimd for Steps<'_, '_, '_> {
    type Output = [Option<usize>; LANES];

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        steps(self.lanes, self.times, self.outputs, self.points, self.rows, self.cancelled)
    }
}

#[inline(always)]
fn steps(
    mut lanes: Lanes,
    times: &[f64],
    outputs: &Outputs,
    points: &[(Option<usize>, [[f64; 2]; LANES])],
    rows: &mut [LaneRows; LANES],
    cancelled: &dyn Fn() -> bool,
) -> [Option<usize>; LANES] {
    let n = lanes.inv_scale.len();
    let kept: Vec<usize> = outputs.coords.clone().unwrap_or_else(|| (0..n).collect());
    // angles only where a kept coordinate is one (points are formed from cos and sin)
    lanes.keep_angles(&kept);
    let (nk, np) = (kept.len(), points.len());
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
        let ok = lanes.step_positions(t, h);
        lanes.coords(&mut q);
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
            // `SweepOutput::store_points` from the frames the groups set
            for (i, (body, u)) in points.iter().enumerate() {
                let at = (k * np + i) * 2;
                let xy = match body {
                    Some(b) => {
                        let (c, s) = lanes.cos_sin(*b);
                        let (c, s, u) = (c[j], s[j], u[j]);
                        let au = [c * u[0] - s * u[1], s * u[0] + c * u[1]];
                        [q[3 * b][j] + au[0], q[3 * b + 1][j] + au[1]]
                    }
                    None => u[j],
                };
                row.points[at..at + 2].copy_from_slice(&xy);
            }
            row.pivot_min = row.pivot_min.min(lanes.ratio[j]);
        }
        if missed.iter().all(Option::is_some) {
            break;
        }
    }
    missed
}
