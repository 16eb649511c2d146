//! dq/dp on the structure-aware path: the plan's groups in solving order, each by the
//! derivative of its own closed form (`closed_form::tangents`: a crank's angle from its law, a
//! dyad's middle pin from its 2 x 2 system), in the directions of the parameters. No
//! Phi_q is assembled or factored: a step costs what the groups' tangents cost.
//!
//! The rule (`choose`): positions only (dq/dp), a plan every group of which has its
//! tangents (cranks, RRR and RRP dyads), the general path not asked for. Otherwise, and
//! on a step next to a dyad's singular configuration, the general path solves
//! (`step::Sensitivity`); both give the implicit function theorem's dq/dp.

use crate::model::data::Data;
use crate::model::params::Parameter;
use crate::model::Model;
use crate::solve::closed_form::{self, NumberMove, StepMiss};

/// Which path solves a sweep's sensitivities.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SensitivityPath {
    /// each group's closed form differentiated, in the plan's order
    Structured,
    /// Phi_q factored at every step, every joint's rows over jets
    #[default]
    General,
}

impl SensitivityPath {
    /// "structured" or "general", as the Python results name it.
    pub fn label(self) -> &'static str {
        match self {
            SensitivityPath::Structured => "structured",
            SensitivityPath::General => "general",
        }
    }
}

/// The parameters' moves of each group's numbers, for the structured path.
#[derive(Debug, Clone)]
pub struct Structured {
    n_params: usize,
    /// n_params zeros: the ground's rows of dq/dp
    zeros: Vec<f64>,
    /// per block of the plan: the parameters' moves of its numbers, by parameter
    entries: Vec<Vec<NumberMove>>,
}

/// The structured path for dq/dp (`derivatives` 0) to `params`, or why the general path
/// solves them; `general`: the general path was asked for.
pub fn choose(
    model: &Model,
    params: &[Parameter],
    derivatives: u8,
    general: bool,
) -> Result<Structured, String> {
    if general {
        return Err("the general path was asked for".into());
    }
    if derivatives > 0 {
        return Err("dqd/dp and dqdd/dp are solved on the general path".into());
    }
    let plan = model.plan.as_ref().map_err(|why| format!("the model has no structured plan ({why})"))?;
    let numbers = plan
        .blocks
        .iter()
        .map(|b| b.numbers().ok_or_else(|| format!("a {} has no structured sensitivities", b.name())))
        .collect::<Result<Vec<_>, _>>()?;
    let mut entries: Vec<Vec<NumberMove>> = vec![Vec::new(); plan.blocks.len()];
    for (j, p) in params.iter().enumerate() {
        for &(c, i, w) in &p.seeds {
            // the group reading constraint c's number i, and its slot there
            let found = numbers.iter().enumerate().find_map(|(b, nb)| match nb.law {
                Some((driver, first)) if driver == c => Some((b, first + i)),
                _ => nb.slots.iter().find(|s| s.0 == c && s.1 == i).map(|s| (b, s.2)),
            });
            let Some((b, slot)) = found else {
                return Err(format!(
                    "parameter '{}' moves a number of '{}' that no group's closed form reads",
                    p.name, model.constraints[c].name
                ));
            };
            entries[b].push(NumberMove { param: j, slot, w });
        }
    }
    Ok(Structured { n_params: params.len(), zeros: vec![0.0; params.len()], entries })
}

impl Structured {
    /// dq/dp (n_coords x n_params, row-major, into `s`) at the configuration in data
    /// (q at t, frames current). Err: a group is next to its singular configuration.
    pub fn step(&self, model: &Model, data: &Data, t: f64, s: &mut [f64]) -> Result<(), StepMiss> {
        let Ok(plan) = model.plan.as_ref() else { return Err(StepMiss::Failed) };
        closed_form::tangents(model, plan, data, t, &self.entries, s, self.n_params, &self.zeros)
    }
}
