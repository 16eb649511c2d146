//! The branch a design is asked for. A design of a study (a variant of a model, or the
//! model redrawn with other numbers) is the base mechanism with other dimensions; the
//! assembly mode it is asked for is the base's: each dyad's side, each Newton block's det
//! sign, as the base model takes them at the first time. Newton from a drawing that the
//! design's numbers no longer close (or that a redraw carried across a toggle) may converge
//! onto the other assembly, silently; so the design's start is put there by its own closed
//! forms first, and a design that has no configuration there is its named error.

use crate::blocks::{self, Miss, Work};
use crate::data::Data;
use crate::error::SolveError;
use crate::model::Model;
use crate::structure::structure;

/// The branches `model` takes at `t`, assembled from its drawing as its own sweep starts.
/// None without a plan, or where the model does not assemble (its designs then start from
/// their drawings, as it does).
pub fn asked_branches(model: &Model, t: f64) -> Option<Work> {
    let plan = model.plan.as_ref().ok()?;
    let mut data = Data::new(model);
    let info = crate::sweep::solve(model, &mut data, t).ok()?;
    blocks::resync(model, plan, &mut data, t, info.det_sign, true, None);
    Some(data.blocks)
}

/// Puts `design`'s start (data.q) on the `asked` branches at `t` by its own plan, where
/// Newton from its drawing would reach others (or none). Nothing is done where the design
/// has no plan or its plan's groups are not the asked ones (a different mechanism: it
/// starts from its drawing). Err names the group that has no configuration on its asked
/// branch.
pub fn start_on(design: &Model, data: &mut Data, t: f64, asked: &Work) -> Result<(), SolveError> {
    let Ok(plan) = design.plan.as_ref() else { return Ok(()) };
    let newton = plan.blocks.iter().filter(|b| matches!(b, blocks::Block::Newton(_))).count();
    if asked.sign.len() != plan.blocks.len() || asked.newton.len() != newton {
        return Ok(());
    }
    // where Newton from the drawing reaches the asked branches, the design starts as a
    // sweep of it alone does, to the bit (the check runs on a workspace of its own)
    if reaches(design, plan, t, asked) {
        return Ok(());
    }
    blocks::assemble(design, plan, data, t, asked).map_err(|(i, miss)| {
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
            Miss::NoAssembly => "has no configuration",
            _ => "is singular or does not converge",
        };
        SolveError::AssemblyBranch { time: t, group: plan.blocks[i].name(), joints, why }
    })
}

/// Whether Newton from the design's drawing assembles it at `t` on the `asked` branches.
fn reaches(design: &Model, plan: &blocks::Plan, t: f64, asked: &Work) -> bool {
    let mut probe = Data::new(design);
    let Ok(info) = crate::position::solve_position(design, &mut probe, t, 0, true) else { return false };
    blocks::resync(design, plan, &mut probe, t, info.det_sign, false, None);
    probe.blocks.sign == asked.sign
        && probe.blocks.newton.iter().zip(&asked.newton).all(|(p, a)| p.det_sign == a.det_sign)
}
