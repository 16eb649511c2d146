//! The branch a design is asked for. A design of a study (a variant of a model, or the
//! model redrawn with other numbers) is the base mechanism with other dimensions; the
//! assembly mode it is asked for is the base's: each dyad's side, each Newton block's det
//! sign, as the base model takes them at the first time. Newton from a drawing that the
//! design's numbers no longer close (or that a redraw carried across a toggle) may converge
//! onto the other assembly, silently; so a design whose first step lands elsewhere is put
//! there by its own closed forms, and a design that has no configuration there is its
//! named error.

use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::structure::structure;
use crate::model::Model;
use crate::solve::closed_form::{self, Block, StepMiss, Work};
use crate::sweep::outputs::SweepOutput;
use crate::sweep::time_loop::{sweep, sweep_observed};

/// The branches a design is asked for: the base's plan state at the first time (each
/// block's sign, each Newton block's det sign) and its groups' kinds, in plan order.
#[derive(Debug, Clone)]
pub struct Asked {
    work: Work,
    kinds: Vec<&'static str>,
    /// the base's configuration there: where a Newton block of a design starts from
    q: Vec<f64>,
}

impl Asked {
    /// Each block's branch sign, in plan order, where `plan`'s groups are the asked ones
    /// (None: another mechanism).
    pub fn signs(&self, plan: &closed_form::Plan) -> Option<&[f64]> {
        plan.blocks.iter().map(Block::name).eq(self.kinds.iter().copied()).then_some(&self.work.sign[..])
    }
}

/// The branches `model` takes at `t`, assembled from its drawing as its own sweep starts.
/// None without a plan, or where the model does not assemble (its designs then start from
/// their drawings, as it does).
pub fn asked_branches(model: &Model, t: f64) -> Option<Asked> {
    let plan = model.plan.as_ref().ok()?;
    let mut data = Data::new(model);
    let info = crate::sweep::single_time::solve(model, &mut data, t).ok()?;
    closed_form::resync(model, plan, &mut data, t, info.det_sign, true, None);
    let q = data.q.clone();
    Some(Asked { work: data.blocks, kinds: plan.blocks.iter().map(Block::name).collect(), q })
}

/// Sweeps `design` as `sweep` does, on the `asked` branches (None: as `sweep`). Its first
/// step is Newton from its drawing, as a sweep of it alone takes it (the same bits where
/// that lands on the asked branches, and no work beyond comparing the signs); where it
/// lands on others (or nowhere), the design's own closed forms put its start on the asked
/// ones and the sweep runs again from there. Nothing is enforced where the design has no
/// plan or its plan's groups are not the asked ones (a different mechanism). A design with
/// no configuration on its asked branches is `SolveError::AssemblyBranch`, naming its group.
pub fn sweep_on(
    design: &Model,
    data: &mut Data,
    times: &[f64],
    out: &mut SweepOutput,
    progress_every: usize,
    progress: &mut dyn FnMut(usize) -> bool,
    asked: Option<&Asked>,
) -> Result<(), SolveError> {
    let (Some(asked), Ok(plan), Some(&t)) = (asked, design.plan.as_ref(), times.first()) else {
        return sweep(design, data, times, out, progress_every, progress);
    };
    if !plan.blocks.iter().map(Block::name).eq(asked.kinds.iter().copied()) {
        return sweep(design, data, times, out, progress_every, progress);
    }
    let mut off = false;
    // the first row is stored once the plan has read its branches from the solved start
    let first = sweep_observed(design, data, times, out, progress_every, progress, &mut |d, _, row| {
        if row == 0 && !on(d, &asked.work) {
            off = true;
            return Err(SolveError::Cancelled { step: 0 });
        }
        Ok(())
    });
    if !off {
        match first {
            // Newton from the drawing found no start: the asked branches may still have one
            Err(SolveError::Assembly { .. }) => {}
            done => return done,
        }
    }
    // nothing of the off-branch start is kept, whatever follows
    out.n_done = 0;
    out.events.clear();
    *data = Data::new(design);
    // a Newton block has no branch formula: it starts from the base's configuration on the
    // asked branch (a closed form ignores where it starts)
    if asked.q.len() == data.q.len() {
        data.q.copy_from_slice(&asked.q);
    }
    closed_form::assemble(design, plan, data, t, &asked.work).map_err(|(i, miss)| {
        // named from the design's structure (computed only here, on the rare failure)
        let joints = structure(design)
            .groups
            .get(i)
            .map(|g| {
                let names: Vec<String> =
                    g.constraints.iter().map(|&c| format!("'{}'", design.constraints[c].name)).collect();
                format!("joints {}", names.join(", "))
            })
            .unwrap_or_else(|| format!("group {}", i + 1));
        let why = match miss {
            StepMiss::NoAssembly => "has no configuration",
            _ => "is singular or does not converge",
        };
        SolveError::AssemblyBranch { time: t, group: plan.blocks[i].name(), joints, why }
    })?;
    sweep(design, data, times, out, progress_every, progress)
}

/// Whether the plan's branches read from a solved start (data.blocks) are the asked ones.
fn on(data: &Data, asked: &Work) -> bool {
    data.blocks.sign == asked.sign
        && data.blocks.newton.iter().zip(&asked.newton).all(|(p, a)| p.det_sign == a.det_sign)
}
