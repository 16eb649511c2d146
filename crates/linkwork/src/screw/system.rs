//! Screw systems: the rank of a set of planar screws, their minimal dependent subsets,
//! and the collapse of a closed mechanism's loop screws at a singular configuration.
//!
//! Planar screws are dependent exactly when their poles are: one zero screw, two with the
//! same pole (coincident pivots, parallel slides), or three with collinear poles (three
//! pivots on a line; two pivots on a line perpendicular to a slide; three slides). Any
//! four planar screws are dependent.

use faer::Mat;

use crate::input::description::{Description, DriverDesc};

use super::joints::MechanismJoints;
use super::projective::{cross, norm, Gauge};
use super::screws::Twist;
use super::{ScrewError, DEGENERATE};

/// A named set of planar screws.
#[derive(Debug, Clone, PartialEq)]
pub struct ScrewSystem {
    pub names: Vec<String>,
    pub screws: Vec<Twist>,
    pub gauge: Gauge,
}

impl ScrewSystem {
    pub fn new(names: Vec<String>, screws: Vec<Twist>, gauge: Gauge) -> ScrewSystem {
        ScrewSystem { names, screws, gauge }
    }

    fn unit(&self, i: usize) -> [f64; 3] {
        self.gauge.point(&self.screws[i].pole())
    }

    fn is_zero(&self, i: usize) -> bool {
        norm(self.unit(i)) == 0.0
    }

    fn same(&self, i: usize, j: usize) -> bool {
        norm(cross(self.unit(i), self.unit(j))) <= DEGENERATE
    }

    fn collinear(&self, i: usize, j: usize, k: usize) -> bool {
        let (a, b, c) = (self.unit(i), self.unit(j), self.unit(k));
        (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]))
            .abs()
            <= DEGENERATE
    }

    /// The dimension of the space the screws span (0 to 3).
    pub fn rank(&self) -> usize {
        let live: Vec<usize> = (0..self.screws.len()).filter(|&i| !self.is_zero(i)).collect();
        let Some(&a) = live.first() else { return 0 };
        let Some(&b) = live.iter().max_by(|&&x, &&y| {
            norm(cross(self.unit(a), self.unit(x))).total_cmp(&norm(cross(self.unit(a), self.unit(y))))
        }) else {
            return 1;
        };
        if self.same(a, b) {
            return 1;
        }
        if live.iter().all(|&c| self.collinear(a, b, c)) {
            2
        } else {
            3
        }
    }

    /// The minimal dependent subsets (indices, ascending): zero screws, pairs with one
    /// pole, triples with collinear poles and no dependent pair inside.
    pub fn dependencies(&self) -> Vec<Vec<usize>> {
        let n = self.screws.len();
        let mut out = Vec::new();
        let zero: Vec<bool> = (0..n).map(|i| self.is_zero(i)).collect();
        out.extend((0..n).filter(|&i| zero[i]).map(|i| vec![i]));
        let mut pair = vec![vec![false; n]; n];
        for i in 0..n {
            for j in i + 1..n {
                if !zero[i] && !zero[j] && self.same(i, j) {
                    pair[i][j] = true;
                    out.push(vec![i, j]);
                }
            }
        }
        for i in 0..n {
            for j in i + 1..n {
                for k in j + 1..n {
                    let clean = !(zero[i] || zero[j] || zero[k] || pair[i][j] || pair[i][k] || pair[j][k]);
                    if clean && self.collinear(i, j, k) {
                        out.push(vec![i, j, k]);
                    }
                }
            }
        }
        out
    }

    /// The error that names a dependent subset and says why it is dependent.
    pub fn error(&self, set: &[usize]) -> ScrewError {
        let joints: Vec<String> = set.iter().map(|&i| self.names[i].clone()).collect();
        let infinite: Vec<bool> = set.iter().map(|&i| self.unit(i)[2].abs() <= DEGENERATE).collect();
        let n_slides = infinite.iter().filter(|&&b| b).count();
        let detail = match (set.len(), n_slides) {
            (1, _) => "has a zero screw".to_string(),
            (2, 0) => "coincide".to_string(),
            (2, 2) => "slide in parallel directions".to_string(),
            (3, 0) => "are collinear".to_string(),
            (3, 1) => {
                let pivots: Vec<&str> = set
                    .iter()
                    .zip(&infinite)
                    .filter(|(_, &inf)| !inf)
                    .map(|(&i, _)| self.names[i].as_str())
                    .collect();
                let slide =
                    set.iter().zip(&infinite).find(|(_, &inf)| inf).map_or("", |(&i, _)| &self.names[i]);
                format!(
                    "are dependent: the line through the pivots of {} and {} is perpendicular to the slide of {slide}",
                    pivots[0], pivots[1]
                )
            }
            (3, 3) => "are dependent: slides alone produce no rotation".to_string(),
            _ => "are dependent".to_string(),
        };
        ScrewError::Dependent { joints, detail }
    }
}

/// The screw analysis of a closed mechanism's loops at one configuration.
///
/// Every joint j contributes its unit relative twist $_j (b relative to a); around every
/// independent loop of the joint graph the relative twists add up to zero:
/// sum_j c_lj w_j $_j = 0 (c_lj = +1 or -1 as the loop passes j forwards or backwards).
/// With the driven joints locked, the remaining (passive) joints must be held by these
/// equations: when their screws collapse (the loop matrix loses rank), the passive joints
/// can move with the drivers fixed, or cannot follow them: a singular configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopSingularity {
    /// the passive joints: the columns of the loop matrix
    pub joints: Vec<String>,
    /// joints locked by drivers
    pub locked: Vec<String>,
    /// the joints of every independent loop
    pub loops: Vec<Vec<String>>,
    /// singular values of the loop matrix (columns scaled to unit length), descending
    pub singular_values: Vec<f64>,
    /// numerical rank (singular values above tol times the largest)
    pub rank: usize,
    /// true when the passive joints' loop screws are dependent (rank < passive joints)
    pub singular: bool,
    /// when singular: the passive joints that move in the null motion
    pub involved: Vec<String>,
    /// minimal dependent sets among each loop's passive joints (names)
    pub dependent: Vec<Vec<String>>,
}

/// The joint a driver locks: angle drivers lock the revolute joint between the body and
/// the ground, relative-angle drivers the revolute joint between their bodies,
/// translation drivers their prismatic joint.
fn locked_joint(mech: &MechanismJoints, d: &DriverDesc) -> Result<usize, ScrewError> {
    let body = |name: &str| mech.body_names.iter().position(|b| b == name);
    let revolute_between = |a: Option<usize>, b: Option<usize>| {
        mech.joints.iter().position(|j| {
            j.kind == Some(super::JointKind::Revolute)
                && ((Some(j.body_a), Some(j.body_b)) == (a, b) || (Some(j.body_a), Some(j.body_b)) == (b, a))
        })
    };
    let found = match d {
        DriverDesc::Angle { body: b, .. } => revolute_between(body(b), Some(0)),
        DriverDesc::RelativeAngle { body_a, body_b, .. } => revolute_between(body(body_a), body(body_b)),
        DriverDesc::Translation { joint, .. } => mech.index(joint),
        _ => None,
    };
    found.ok_or_else(|| {
        ScrewError::Mechanism(format!(
            "driver '{}' does not lock a joint (the loop analysis reads angle drivers on a body pinned to the \
             ground, relative-angle drivers across a revolute joint and translation drivers)",
            d.name()
        ))
    })
}

/// The loop screws of a description at coordinates q, and whether they have collapsed.
/// `tol`: singular values below tol times the largest count as zero.
pub fn loop_singularity(desc: &Description, q: &[f64], tol: f64) -> Result<LoopSingularity, ScrewError> {
    let mech = MechanismJoints::from_description(desc)?;
    mech.check("q", q)?;
    let n_joints = mech.joints.len();
    let n_bodies = mech.n_bodies();

    // spanning forest from the ground: coef[b] expresses body b's twist in joint rates
    let mut coef: Vec<Option<Vec<f64>>> = vec![None; n_bodies];
    let mut in_tree = vec![false; n_joints];
    let mut loops: Vec<Vec<f64>> = Vec::new();
    for root in 0..n_bodies {
        if coef[root].is_some() {
            continue;
        }
        coef[root] = Some(vec![0.0; n_joints]);
        let mut stack = vec![root];
        while let Some(b) = stack.pop() {
            for (j, jt) in mech.joints.iter().enumerate() {
                if in_tree[j] || (jt.body_a != b && jt.body_b != b) {
                    continue;
                }
                let (other, sign) = if jt.body_a == b { (jt.body_b, 1.0) } else { (jt.body_a, -1.0) };
                if coef[other].is_some() {
                    continue;
                }
                let mut c = coef[b].clone().unwrap_or_default();
                c[j] += sign;
                coef[other] = Some(c);
                in_tree[j] = true;
                stack.push(other);
            }
        }
    }
    for (j, jt) in mech.joints.iter().enumerate() {
        if in_tree[j] {
            continue;
        }
        // T_b - T_a - w_j $_j = 0 around the loop this joint closes
        let (ca, cb) =
            (coef[jt.body_a].clone().unwrap_or_default(), coef[jt.body_b].clone().unwrap_or_default());
        let mut row: Vec<f64> = cb.iter().zip(&ca).map(|(b, a)| b - a).collect();
        row[j] -= 1.0;
        loops.push(row);
    }

    let mut locked = vec![false; n_joints];
    for d in &desc.drivers {
        locked[locked_joint(&mech, d)?] = true;
    }
    let mut points = Vec::new();
    for j in 0..n_joints {
        points.push(mech.position(j, q));
    }
    let gauge = Gauge::around(&points);
    let passive: Vec<usize> =
        (0..n_joints).filter(|&j| !locked[j] && mech.joints[j].kind.is_some()).collect();
    let units: Vec<[f64; 3]> =
        passive.iter().map(|&j| mech.pole(j, q).map_or([0.0; 3], |p| gauge.point(&p))).collect();

    let (m, n) = (3 * loops.len(), passive.len());
    let a = Mat::<f64>::from_fn(m, n, |r, c| loops[r / 3][passive[c]] * units[c][r % 3]);
    let (singular_values, null) = if m == 0 || n == 0 {
        (Vec::new(), Vec::new())
    } else {
        let svd = a
            .svd()
            .map_err(|e| ScrewError::Input(format!("the singular value decomposition failed: {e:?}")))?;
        let s: Vec<f64> = (0..m.min(n)).map(|i| svd.S()[i]).collect();
        let v = svd.V();
        let null: Vec<f64> = (0..n).map(|r| v[(r, n - 1)]).collect();
        (s, null)
    };
    let smax = singular_values.first().copied().unwrap_or(0.0);
    let rank = singular_values.iter().filter(|&&s| s > tol * smax).count();
    let singular = rank < n;
    let involved = if singular {
        let vmax = null.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        passive
            .iter()
            .zip(&null)
            .filter(|(_, v)| v.abs() > 1e-6 * vmax)
            .map(|(&j, _)| mech.joints[j].name.clone())
            .collect()
    } else {
        Vec::new()
    };

    let mut dependent = Vec::new();
    let mut loop_names = Vec::new();
    for row in &loops {
        let members: Vec<usize> = (0..n_joints).filter(|&j| row[j] != 0.0).collect();
        loop_names.push(members.iter().map(|&j| mech.joints[j].name.clone()).collect());
        let in_loop: Vec<usize> = passive.iter().copied().filter(|j| row[*j] != 0.0).collect();
        let sys = ScrewSystem::new(
            in_loop.iter().map(|&j| mech.joints[j].name.clone()).collect(),
            in_loop.iter().map(|&j| mech.screw(j, q).unwrap_or_default()).collect(),
            gauge,
        );
        for set in sys.dependencies() {
            let names: Vec<String> = set.iter().map(|&i| sys.names[i].clone()).collect();
            if !dependent.contains(&names) {
                dependent.push(names);
            }
        }
    }
    Ok(LoopSingularity {
        joints: passive.iter().map(|&j| mech.joints[j].name.clone()).collect(),
        locked: (0..n_joints).filter(|&j| locked[j]).map(|j| mech.joints[j].name.clone()).collect(),
        loops: loop_names,
        singular_values,
        rank,
        singular,
        involved,
        dependent,
    })
}
