//! Degrees of freedom of a compiled model, by the rank of its rows (`crate::model::rank`,
//! dense SVD) or, for large models, by the model's own sparse LU.

use crate::constraints::Constraint;
use crate::model::rank::analyse;
pub use crate::model::rank::{Dependency, Mobility, MobilityError, MAX_COORDS, RANK_TOL};
use crate::model::Model;

/// Mobility of a compiled model at configuration q (e.g. a solved one) and time t: by
/// dense SVD up to `MAX_COORDS` coordinates, beyond by the model's own sparse LU
/// (`sparse_mobility`).
pub fn mobility(model: &Model, q: &[f64], t: f64) -> Result<Mobility, MobilityError> {
    if model.n_coords > MAX_COORDS && model.n_rows == model.n_coords {
        return Ok(sparse_mobility(model, q, t));
    }
    analyse(&model.constraints, &model.columns, model.length_scale, q, t)
}

/// Mobility of a large square model: Phi_q (all rows) factored by the engine's sparse LU.
/// Regular (its smallest singular value, by inverse iteration on the factors, above
/// RANK_TOL; the estimate is never below the true one, and a singular Phi_q leaves a zero
/// pivot that makes it ~0): every row independent, so the joint rows too, and the counts follow. Else
/// the smallest singular triple (inverse iteration on the factors) names the dependent
/// rows and the free motion: one dependency is found this way (the explanation says that
/// there may be more). The singular values are not listed (`singular_values` holds only
/// the smallest's estimate).
pub fn sparse_mobility(model: &Model, q: &[f64], t: f64) -> Mobility {
    use crate::sweep::stepping::singular::{
        constraint_shares, coordinate_shares, driver_share, smallest_singular,
    };
    let mut data = crate::model::data::Data::new(model);
    data.q.copy_from_slice(q);
    crate::solve::assembly::position(model, &mut data, t);
    data.pivots = data.factor.factor(&model.symbolic, &data.jac);
    let triple = smallest_singular(model, &mut data, 6);
    let n_coords = model.n_coords;
    let joint_rows: usize = model.constraints.iter().filter(|c| c.role == "joint").map(|c| c.n_rows).sum();
    let driver_rows = model.n_rows - joint_rows;
    let n_own: usize = model.constraints.iter().map(|c| c.kind.n_own()).sum();
    let gruebler_dof = n_coords as i64 - joint_rows as i64;
    // a NaN pivot ratio counts as singular
    let singular = data.pivots.ratio.is_nan() || data.pivots.ratio <= 0.0 || triple.sigma <= RANK_TOL;
    let dependency =
        Dependency { sigma: triple.sigma, constraints: constraint_shares(model, &triple.w, 0.05) };
    let mut explanation = Vec::new();
    let (rank_joints, rank, redundancies, free_motions, nearest) = if !singular {
        (joint_rows, n_coords, Vec::new(), Vec::new(), Some(dependency))
    } else {
        explanation.push(format!(
            "large model ({n_coords} coordinates): ranks from the sparse LU and inverse iteration, which \
             find one dependency (singular value {:.1e}); there may be more",
            triple.sigma
        ));
        let free = vec![coordinate_shares(model, &triple.v, 0.05)];
        if driver_share(model, &triple.w) <= crate::sweep::stepping::singular::DRIVER_SHARE_TOL {
            let names =
                dependency.constraints.iter().map(|(n, _)| format!("'{n}'")).collect::<Vec<_>>().join(", ");
            explanation.push(format!(
                "redundant: the rows of {names} are dependent at this configuration (special geometry, \
                 e.g. parallel cranks or a doubled pin); their reactions are not determined by kinematics"
            ));
            (joint_rows - 1, n_coords - 1, vec![dependency], free, None)
        } else {
            explanation.push("the drivers are not independent of the joints at this configuration".into());
            (joint_rows, n_coords - 1, Vec::new(), free, None)
        }
    };
    let dof = n_coords - rank_joints;
    let dof_driven = n_coords - rank;
    if gruebler_dof != dof as i64 {
        explanation.insert(
            0,
            format!(
                "Gruebler counts {gruebler_dof} degree(s) of freedom, but the joints' rows have rank \
                 {rank_joints} of {joint_rows}: the mechanism really has {dof}"
            ),
        );
    }
    Mobility {
        n_bodies: (n_coords - n_own) / 3,
        n_coords,
        joint_rows,
        driver_rows,
        gruebler_dof,
        gruebler_dof_driven: gruebler_dof - driver_rows as i64,
        rank_joints,
        rank,
        dof,
        dof_driven,
        singular_values: vec![triple.sigma],
        redundancies,
        free_motions,
        nearest,
        explanation,
    }
}
