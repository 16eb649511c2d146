//! The rank of the constraint rows: degrees of freedom two ways, and redundant rows, from
//! the constraint entries alone (a compiled Model's or one being compiled).
//!
//! Gruebler's count (3 per moving body minus the rows) assumes every row removes one
//! freedom. The numerical rank of Phi_q at a configuration says how many really do:
//! where they differ the geometry is special (parallel cranks, doubled pins) and some
//! rows are dependent. A dense SVD of the scaled Phi_q (joints alone, and with the
//! drivers) gives both ranks; its left null vectors say which constraints' rows are
//! dependent, its right null vectors which motions are left free.

use faer::Mat;

use crate::constraints::{Constraint, Frame, Rows};
use crate::model::ConstraintEntry;

/// A singular value at or below this times the largest counts as zero. The scaled Phi_q
/// has entries of order 1 and a solved configuration is exact to ~1e-12 (the Newton
/// tolerance), so an exact dependency shows as ~1e-12 and a real geometric one (a crank
/// 0.1 % out of parallel) as ~1e-3: 1e-9 separates them with margin both ways.
pub const RANK_TOL: f64 = 1e-9;

/// Above this many coordinates the dense SVD (O(n^3)) is refused.
pub const MAX_COORDS: usize = 3000;

/// Rows that combine to (nearly) zero, mapped to the constraints they belong to.
#[derive(Debug, Clone, PartialEq)]
pub struct Dependency {
    /// the singular value (scaled): 0 up to round-off for a true redundancy
    pub sigma: f64,
    /// (constraint name, share of the combination), largest first
    pub constraints: Vec<(String, f64)>,
}

/// Degrees of freedom and dependencies of a model at one configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Mobility {
    pub n_bodies: usize,
    pub n_coords: usize,
    pub joint_rows: usize,
    pub driver_rows: usize,
    /// Gruebler: 3 n_bodies (+ curve parameters) - joint rows (the mechanism's freedom), and minus the driver
    /// rows too (0 for a kinematically driven mechanism)
    pub gruebler_dof: i64,
    pub gruebler_dof_driven: i64,
    /// numerical ranks of the joint rows and of all rows
    pub rank_joints: usize,
    pub rank: usize,
    /// n_coords - rank: the freedoms really left, without and with the drivers
    pub dof: usize,
    pub dof_driven: usize,
    /// all rows' singular values (scaled), largest first
    pub singular_values: Vec<f64>,
    /// one per dependent combination of joint rows
    pub redundancies: Vec<Dependency>,
    /// the motions left free with the drivers held: (coordinate, share), largest first
    pub free_motions: Vec<Vec<(String, f64)>>,
    /// with the joint rows independent, their combination closest to dependent (the
    /// smallest singular value): a near-redundancy shows here
    pub nearest: Option<Dependency>,
    /// why Gruebler and the rank differ, and what to do, in sentences
    pub explanation: Vec<String>,
}

/// Why mobility was not computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MobilityError {
    #[error("mobility uses a dense SVD; {0} coordinates is more than the {MAX_COORDS} it is allowed")]
    TooLarge(usize),
    #[error("the SVD of Phi_q did not converge (non-finite entries?)")]
    Svd,
}

/// The scaled Phi_q of the given constraints (rows by their row0) at q and t.
pub(crate) fn dense_jacobian(
    constraints: &[&ConstraintEntry],
    n_coords: usize,
    l: f64,
    q: &[f64],
    t: f64,
) -> Mat<f64> {
    let frame = |b: Option<usize>| match b {
        Some(i) => Frame::new([q[3 * i], q[3 * i + 1], q[3 * i + 2]], [0.0; 3]),
        None => Frame::GROUND,
    };
    let n_rows: usize = constraints.iter().map(|c| c.n_rows).sum();
    let mut jac = Mat::<f64>::zeros(n_rows, n_coords);
    let col = [l, l, 1.0];
    let mut row = 0;
    for c in constraints {
        let mut rows = Rows::default();
        c.kind.position(&frame(c.body_a), &frame(c.body_b), &c.extra(q, &[]), t, &mut rows);
        for i in 0..c.n_rows {
            for (j, cs) in col.iter().enumerate() {
                if let Some(a) = c.body_a {
                    jac[(row + i, 3 * a + j)] += rows.jac_a[i][j] * c.row_scale[i] * cs;
                }
                if let Some(b) = c.body_b {
                    jac[(row + i, 3 * b + j)] += rows.jac_b[i][j] * c.row_scale[i] * cs;
                }
            }
            if let Some(k) = c.extra {
                jac[(row + i, k)] += rows.jac_s[i] * c.row_scale[i];
            }
        }
        row += c.n_rows;
    }
    jac
}

struct Svd {
    s: Vec<f64>,
    u: Mat<f64>,
    v: Mat<f64>,
}

fn svd(a: &Mat<f64>) -> Result<Svd, MobilityError> {
    let d = a.svd().map_err(|_| MobilityError::Svd)?;
    let s: Vec<f64> = d.S().column_vector().iter().copied().collect();
    Ok(Svd { s, u: d.U().to_owned(), v: d.V().to_owned() })
}

fn rank(s: &[f64]) -> usize {
    let top = s.first().copied().unwrap_or(0.0);
    s.iter().filter(|&&x| x > RANK_TOL * top).count()
}

/// The constraints' shares of a row combination (column `k` of u).
fn shares(constraints: &[&ConstraintEntry], u: &Mat<f64>, k: usize) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    let mut row = 0;
    for c in constraints {
        let share = (0..c.n_rows).map(|i| u[(row + i, k)].powi(2)).sum::<f64>().sqrt();
        if share > 0.05 {
            out.push((c.name.clone(), share));
        }
        row += c.n_rows;
    }
    out.sort_by(|a, b| b.1.total_cmp(&a.1));
    out
}

/// Mobility of the constraints at q, t (the engine's Model, or one being compiled).
pub(crate) fn analyse(
    constraints: &[ConstraintEntry],
    columns: &[String],
    length_scale: f64,
    q: &[f64],
    t: f64,
) -> Result<Mobility, MobilityError> {
    let n_coords = columns.len();
    if n_coords > MAX_COORDS {
        return Err(MobilityError::TooLarge(n_coords));
    }
    let joints: Vec<&ConstraintEntry> = constraints.iter().filter(|c| c.role == "joint").collect();
    let drivers: Vec<&ConstraintEntry> = constraints.iter().filter(|c| c.role == "driver").collect();
    let all: Vec<&ConstraintEntry> = joints.iter().chain(&drivers).copied().collect();
    let joint_rows: usize = joints.iter().map(|c| c.n_rows).sum();
    let driver_rows: usize = drivers.iter().map(|c| c.n_rows).sum();
    let whole = svd(&dense_jacobian(&all, n_coords, length_scale, q, t))?;
    let rank_all = rank(&whole.s);
    let jsvd = if joints.is_empty() {
        None
    } else {
        Some(svd(&dense_jacobian(&joints, n_coords, length_scale, q, t))?)
    };
    let rank_joints = jsvd.as_ref().map_or(0, |j| rank(&j.s));
    // redundant: combinations of joint rows with a zero singular value (rows beyond the
    // coordinates are not counted here: with full rank they over-determine, see below)
    let redundancies: Vec<Dependency> = match &jsvd {
        Some(j) => (rank_joints..joint_rows.min(n_coords))
            .map(|k| Dependency { sigma: j.s[k], constraints: shares(&joints, &j.u, k) })
            .collect(),
        None => Vec::new(),
    };
    let free_motions: Vec<Vec<(String, f64)>> = (rank_all..n_coords)
        .map(|k| {
            let mut m: Vec<(String, f64)> = columns
                .iter()
                .enumerate()
                .map(|(i, c)| (c.clone(), whole.v[(i, k)].abs()))
                .filter(|(_, s)| *s > 0.05)
                .collect();
            m.sort_by(|a, b| b.1.total_cmp(&a.1));
            m
        })
        .collect();
    // the joint-row combination closest to dependent, when none is
    let nearest = jsvd.as_ref().and_then(|j| {
        let k = joint_rows.min(n_coords).checked_sub(1)?;
        (rank_joints == joint_rows.min(n_coords))
            .then(|| Dependency { sigma: j.s[k], constraints: shares(&joints, &j.u, k) })
    });
    let n_own: usize = constraints.iter().map(|c| c.kind.n_own()).sum();
    let n_bodies = (n_coords - n_own) / 3;
    // Gruebler counts coordinates, the joints' curve parameters included
    let gruebler_dof = n_coords as i64 - joint_rows as i64;
    let gruebler_dof_driven = gruebler_dof - driver_rows as i64;
    let dof = n_coords - rank_joints;
    let dof_driven = n_coords - rank_all;

    let mut explanation = Vec::new();
    let names =
        |d: &Dependency| d.constraints.iter().map(|(n, _)| format!("'{n}'")).collect::<Vec<_>>().join(", ");
    if gruebler_dof != dof as i64 {
        explanation.push(format!(
            "Gruebler counts {gruebler_dof} degree(s) of freedom, but the joints' rows have rank {rank_joints} \
             of {joint_rows}: the mechanism really has {dof}"
        ));
    }
    for d in &redundancies {
        let last = d.constraints.last().map(|(n, _)| n.clone()).unwrap_or_default();
        explanation.push(format!(
            "redundant: the rows of {} are dependent at this configuration (special geometry, e.g. \
             parallel cranks or a doubled pin; singular value {:.1e}); relax one of them (e.g. remove \
             '{last}' or make it a joint with fewer rows): their reactions are not determined by \
             kinematics",
            names(d),
            d.sigma
        ));
    }
    if joint_rows > n_coords && rank_joints == n_coords {
        explanation.push(format!(
            "{joint_rows} joint rows for {n_coords} coordinates and none dependent: the joints alone lock \
             the mechanism (over-constrained); check the geometry of the joints named below"
        ));
    }
    if driver_rows > rank_all - rank_joints {
        let locked = if dof == 0 {
            match &nearest {
                Some(d) => format!(
                    ": the mechanism is locked (a structure: its joints leave no freedom), so no driver can \
                     move it; the joints' rows nearest to dependent (singular value {:.1e}) are {}: if those \
                     parts should be parallel or coincide, check their geometry",
                    d.sigma,
                    names(d)
                ),
                None => ": the mechanism is locked (a structure: its joints leave no freedom)".to_string(),
            }
        } else {
            format!(": the joints leave {dof} degree(s) of freedom for {driver_rows} driver row(s)")
        };
        explanation.push(format!("the drivers are not independent of the joints{locked}"));
    }
    if dof_driven > 0 {
        explanation.push(format!(
            "{dof_driven} motion(s) left free with the drivers held: add as many drivers (the free \
             motion moves {})",
            free_motions[0].iter().take(4).map(|(c, _)| c.as_str()).collect::<Vec<_>>().join(", ")
        ));
    }
    if let Some(d) = &nearest {
        if d.sigma < 1e-3 && dof > 0 {
            explanation.push(format!(
                "nearly singular: smallest singular value {:.1e} among {}",
                d.sigma,
                names(d)
            ));
        }
    }
    Ok(Mobility {
        n_bodies,
        n_coords,
        joint_rows,
        driver_rows,
        gruebler_dof,
        gruebler_dof_driven,
        rank_joints,
        rank: rank_all,
        dof,
        dof_driven,
        singular_values: whole.s,
        redundancies,
        free_motions,
        nearest,
        explanation,
    })
}
