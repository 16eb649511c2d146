//! Instant centres of every pair of bodies of a planar mechanism, found two ways:
//! - from velocities: body i's twist T_i = (xd + thetad y, yd - thetad x; thetad); the
//!   centre of bodies i and j is the pole of their relative twist T_j - T_i;
//! - from geometry alone (Kennedy): every joint gives the centre of its two bodies (the
//!   pivot, or the point at infinity across a slide); the centre of i and j is then the
//!   meet of the line through the centres ik and jk with the line through im and jm.
//!
//! Bodies are numbered 0 for the ground, then 1 + their index in the description.

use super::joints::MechanismJoints;
use super::projective::{Gauge, Point};
use super::screws::Twist;
use super::ScrewError;

/// Relative twists smaller than this times the largest body twist count as zero (the
/// two bodies do not move relative to each other: no centre).
const STILL: f64 = 1e-10;

/// The instant centre of every pair of bodies (None where there is none or it was not
/// found), as homogeneous points.
#[derive(Debug, Clone, PartialEq)]
pub struct InstantCentres {
    /// "ground", then the bodies
    pub body_names: Vec<String>,
    centres: Vec<Option<Point>>,
    pub gauge: Gauge,
}

fn pair_index(n: usize, i: usize, j: usize) -> usize {
    let (i, j) = if i < j { (i, j) } else { (j, i) };
    i * n - i * (i + 1) / 2 + (j - i - 1)
}

impl InstantCentres {
    fn empty(body_names: Vec<String>, gauge: Gauge) -> InstantCentres {
        let n = body_names.len();
        InstantCentres { body_names, centres: vec![None; n * n.saturating_sub(1) / 2], gauge }
    }

    pub fn n_bodies(&self) -> usize {
        self.body_names.len()
    }

    /// The centre of bodies i and j (either order), None for i == j.
    pub fn get(&self, i: usize, j: usize) -> Option<Point> {
        if i == j || i >= self.n_bodies() || j >= self.n_bodies() {
            return None;
        }
        self.centres[pair_index(self.n_bodies(), i, j)]
    }

    fn set(&mut self, i: usize, j: usize, p: Point) {
        let n = self.n_bodies();
        self.centres[pair_index(n, i, j)] = Some(p);
    }

    /// Every pair (i < j) and its centre.
    pub fn pairs(&self) -> Vec<(usize, usize, Option<Point>)> {
        let n = self.n_bodies();
        (0..n).flat_map(|i| (i + 1..n).map(move |j| (i, j))).map(|(i, j)| (i, j, self.get(i, j))).collect()
    }

    /// Kennedy's theorem: the centres ij, jk and ik of any three bodies are collinear.
    /// Returns the largest collinearity measure (|det| of the normalised points, 0 when
    /// collinear) over the triples whose three centres are known, and that triple.
    pub fn kennedy_worst(&self) -> Option<(f64, [usize; 3])> {
        let n = self.n_bodies();
        let mut worst: Option<(f64, [usize; 3])> = None;
        for i in 0..n {
            for j in i + 1..n {
                for k in j + 1..n {
                    if let (Some(a), Some(b), Some(c)) = (self.get(i, j), self.get(j, k), self.get(i, k)) {
                        let r = self.gauge.collinearity(&a, &b, &c);
                        if worst.is_none_or(|(w, _)| r > w) {
                            worst = Some((r, [i, j, k]));
                        }
                    }
                }
            }
        }
        worst
    }
}

fn gauge_of(mech: &MechanismJoints, q: &[f64]) -> Gauge {
    let mut pts: Vec<[f64; 2]> = (0..mech.joints.len()).map(|j| mech.position(j, q)).collect();
    pts.extend((1..mech.n_bodies()).map(|b| {
        let p = mech.pose(q, b);
        [p[0], p[1]]
    }));
    Gauge::around(&pts)
}

/// Instant centres from the bodies' velocities (q, qd: 3 per moving body, in the
/// description's body order): the poles of the relative twists.
pub fn centres_from_velocities(
    mech: &MechanismJoints,
    q: &[f64],
    qd: &[f64],
) -> Result<InstantCentres, ScrewError> {
    mech.check("q", q)?;
    mech.check("qd", qd)?;
    let n = mech.n_bodies();
    let mut out = InstantCentres::empty(mech.body_names.clone(), gauge_of(mech, q));
    let twists: Vec<Twist> = (0..n).map(|b| Twist::of_body(mech.pose(q, b), mech.rate(qd, b))).collect();
    let g = out.gauge;
    let size = |t: &Twist| super::projective::norm(g.map(&t.pole()));
    let largest = twists.iter().map(size).fold(0.0, f64::max);
    for i in 0..n {
        for j in i + 1..n {
            let rel = twists[j] - twists[i];
            if size(&rel) > STILL * largest {
                out.set(i, j, g.normalize(&rel.pole()));
            }
        }
    }
    Ok(out)
}

/// Instant centres from the geometry alone: the joints' centres, then Kennedy's theorem
/// (meets of lines through known centres) until no more can be found. Pairs it cannot
/// reach stay None.
pub fn centres_by_kennedy(mech: &MechanismJoints, q: &[f64]) -> Result<InstantCentres, ScrewError> {
    mech.check("q", q)?;
    let n = mech.n_bodies();
    let mut out = InstantCentres::empty(mech.body_names.clone(), gauge_of(mech, q));
    for (j, jt) in mech.joints.iter().enumerate() {
        let Some(p) = mech.pole(j, q) else {
            return Err(ScrewError::Mechanism(format!(
                "joint '{}' is a weld: welded bodies move as one, merge them before finding instant centres",
                jt.name
            )));
        };
        if out.get(jt.body_a, jt.body_b).is_none() {
            let p = out.gauge.normalize(&p);
            out.set(jt.body_a, jt.body_b, p);
        }
    }
    let g = out.gauge;
    loop {
        let mut found = false;
        for i in 0..n {
            for j in i + 1..n {
                if out.get(i, j).is_some() {
                    continue;
                }
                // bodies k with both centres ik and jk known give a line through centre ij
                let mut lines = Vec::new();
                let mut centre = None;
                for k in (0..n).filter(|&k| k != i && k != j) {
                    if let (Some(a), Some(b)) = (out.get(i, k), out.get(j, k)) {
                        match g.join(&a, &b) {
                            Ok(l) => lines.push(l),
                            // i and j both turn about the same point relative to k
                            Err(_) => centre = Some(a),
                        }
                    }
                }
                if centre.is_none() {
                    'pairs: for (x, l) in lines.iter().enumerate() {
                        for m in &lines[x + 1..] {
                            if let Ok(p) = g.meet(l, m) {
                                centre = Some(p);
                                break 'pairs;
                            }
                        }
                    }
                }
                if let Some(p) = centre {
                    out.set(i, j, g.normalize(&p));
                    found = true;
                }
            }
        }
        if !found {
            return Ok(out);
        }
    }
}
