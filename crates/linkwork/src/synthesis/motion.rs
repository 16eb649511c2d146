//! Motion generation: a body must take given poses (x, y, angle). An RR dyad guides it
//! when its moving pivot M (fixed in the body) stays at one distance from its ground
//! pivot G. Two poses: G anywhere on the bisector of M's two positions; three: G is the
//! circumcentre; four: the circle-point and centre-point curves; five: Burmester's at
//! most four dyads, all found.

use num_complex::Complex64 as C64;

use super::dyad::{residuals, solve_rows, DyadRow};
use super::resultant::solve_by_resultant;
use super::{check_scale, coincide, Dyad, DyadSet, Frame, SynthesisError};

/// A pose of the body: reference point and orientation (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub angle: f64,
}

impl Pose {
    fn point(&self) -> C64 {
        C64::new(self.x, self.y)
    }
}

/// The poses' frame, or why they are refused.
fn check_poses(poses: &[Pose], want: &str, ok: bool) -> Result<Frame, SynthesisError> {
    if !ok {
        return Err(SynthesisError::Count {
            problem: "motion generation",
            got: poses.len(),
            want: want.into(),
        });
    }
    for (i, p) in poses.iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite() && p.angle.is_finite()) {
            return Err(SynthesisError::NotFinite { what: format!("pose {}", i + 1) });
        }
    }
    let points: Vec<C64> = poses.iter().map(Pose::point).collect();
    let frame = check_scale("the poses' points", &points)?;
    for i in 0..poses.len() {
        for j in i + 1..poses.len() {
            let (a, b) = (&poses[i], &poses[j]);
            let turn = (b.angle - a.angle).rem_euclid(std::f64::consts::TAU);
            let turn = turn.min(std::f64::consts::TAU - turn);
            if coincide(a.point(), b.point(), &frame) && turn <= 1e-9 {
                return Err(SynthesisError::Coincident { what: "poses", i: i + 1, j: j + 1 });
            }
        }
    }
    Ok(frame)
}

/// Rows of the dyad system for poses 2..5 against pose 1, in the frame's local units.
/// Unknowns: x = M - P_1 at pose 1, y = M - G.
pub fn rows(poses: &[Pose; 5], frame: &Frame) -> [DyadRow; 4] {
    let p1 = frame.to_local(poses[0].point());
    std::array::from_fn(|k| {
        let p = &poses[k + 1];
        DyadRow {
            alpha: C64::from_polar(1.0, p.angle - poses[0].angle) - 1.0,
            beta: frame.to_local(p.point()) - p1,
            sigma: C64::new(1.0, 0.0),
        }
    })
}

/// Five-pose Burmester synthesis: every dyad guiding the body through the five poses.
pub fn burmester(poses: &[Pose]) -> Result<DyadSet, SynthesisError> {
    let frame = check_poses(poses, "exactly 5 poses for the Burmester dyads", poses.len() == 5)?;
    let poses: &[Pose; 5] = poses.try_into().expect("length checked");
    let rows = rows(poses, &frame);
    let sol = solve_rows(&rows)?;
    let p1 = frame.to_local(poses[0].point());
    Ok(DyadSet::from_solutions(&sol, &rows, &frame, |x, y| (p1 + x - y, p1 + x)))
}

/// The same dyads by elimination (resultant.rs): the independent cross-check.
pub fn burmester_by_resultant(poses: &[Pose]) -> Result<DyadSet, SynthesisError> {
    let frame = check_poses(poses, "exactly 5 poses for the Burmester dyads", poses.len() == 5)?;
    let poses: &[Pose; 5] = poses.try_into().expect("length checked");
    let rows = rows(poses, &frame);
    let p1 = frame.to_local(poses[0].point());
    Ok(DyadSet::from_solutions(&solve_by_resultant(&rows)?, &rows, &frame, |x, y| (p1 + x - y, p1 + x)))
}

/// Positions of a body-fixed point (given at pose 1) at every pose.
fn carried(poses: &[Pose], point: C64) -> Vec<C64> {
    let p1 = poses[0].point();
    poses.iter().map(|p| p.point() + (point - p1) * C64::from_polar(1.0, p.angle - poses[0].angle)).collect()
}

/// Circumcentre of three points; None when they are collinear (or coincide). Computed
/// relative to a, scaled to unit size, so no square overflows or underflows.
pub fn circumcentre(a: C64, b: C64, c: C64) -> Option<C64> {
    let size = (b - a).norm().max((c - a).norm());
    if !(size > 0.0 && size.is_finite()) {
        return None;
    }
    let (b, c) = ((b - a) / size, (c - a) / size);
    let d = 2.0 * (b.re * c.im - b.im * c.re);
    if d.abs() <= 1e-12 {
        return None;
    }
    let ux = (c.im * b.norm_sqr() - b.im * c.norm_sqr()) / d;
    let uy = (b.re * c.norm_sqr() - c.re * b.norm_sqr()) / d;
    Some(a + C64::new(ux, uy) * size)
}

/// The chosen pivot of a two- or three-pose problem, refused as the data are.
fn check_chosen(poses: &[Pose], chosen: [f64; 2]) -> Result<(C64, Frame), SynthesisError> {
    let point = C64::new(chosen[0], chosen[1]);
    let all: Vec<C64> = poses.iter().map(Pose::point).chain([point]).collect();
    Ok((point, check_scale("the poses' points and the chosen pivot", &all)?))
}

/// Three poses, moving pivot chosen (world coordinates at pose 1): the ground pivot is the
/// circumcentre of its three positions.
pub fn three_pose_ground(poses: &[Pose], moving: [f64; 2]) -> Result<Dyad, SynthesisError> {
    check_poses(poses, "exactly 3 poses for the circumcentre", poses.len() == 3)?;
    let m = carried(poses, check_chosen(poses, moving)?.0);
    let g = circumcentre(m[0], m[1], m[2])
        .ok_or(SynthesisError::Collinear { what: "the moving pivot's three positions" })?;
    Ok(Dyad::exact(g, m[0]))
}

/// Three poses, ground pivot chosen: the moving pivot is the circumcentre of the ground
/// pivot's three positions seen from the body (inversion), carried back to pose 1.
pub fn three_pose_moving(poses: &[Pose], ground: [f64; 2]) -> Result<Dyad, SynthesisError> {
    check_poses(poses, "exactly 3 poses for the circumcentre", poses.len() == 3)?;
    let g = check_chosen(poses, ground)?.0;
    let p1 = poses[0].point();
    // G in the body frame of pose j, expressed at pose 1
    let seen: Vec<C64> =
        poses.iter().map(|p| p1 + (g - p.point()) * C64::from_polar(1.0, poses[0].angle - p.angle)).collect();
    let m = circumcentre(seen[0], seen[1], seen[2])
        .ok_or(SynthesisError::Collinear { what: "the ground pivot's three positions seen from the body" })?;
    Ok(Dyad::exact(g, m))
}

/// Two poses, moving pivot chosen: the ground pivot on the perpendicular bisector of the
/// moving pivot's two positions, `along` (length units) from their midpoint.
pub fn two_pose_ground(poses: &[Pose], moving: [f64; 2], along: f64) -> Result<Dyad, SynthesisError> {
    check_poses(poses, "exactly 2 poses for the bisector", poses.len() == 2)?;
    if !(along.is_finite() && along.abs() <= super::LARGEST) {
        return Err(SynthesisError::NotFinite {
            what: format!("the distance along the bisector ({along:e})"),
        });
    }
    let (moving, frame) = check_chosen(poses, moving)?;
    let m = carried(poses, moving);
    let chord = m[1] - m[0];
    if chord.norm() <= 1e-12 * (frame.scale + m[0].norm()) {
        return Err(SynthesisError::Coincident { what: "moving pivot positions", i: 1, j: 2 });
    }
    let normal = chord * C64::new(0.0, 1.0) / chord.norm();
    Ok(Dyad::exact((m[0] + m[1]) / 2.0 + normal * along, m[0]))
}

/// Four poses: points of the circle-point curve (moving pivots at pose 1) and the
/// matching centre points (ground pivots), sampled along `n` rays through the first
/// pose's reference point. Every pair is an exact four-pose dyad.
pub fn four_pose_curves(poses: &[Pose], n: usize) -> Result<Vec<Dyad>, SynthesisError> {
    let frame = check_poses(poses, "exactly 4 poses for the Burmester curves", poses.len() == 4)?;
    let p1 = frame.to_local(poses[0].point());
    let rows: Vec<DyadRow> = poses[1..]
        .iter()
        .map(|p| DyadRow {
            alpha: C64::from_polar(1.0, p.angle - poses[0].angle) - 1.0,
            beta: frame.to_local(p.point()) - p1,
            sigma: C64::new(1.0, 0.0),
        })
        .collect();
    let mut out = Vec::new();
    for k in 0..n.max(1) {
        // rays over half a turn: rho spans the whole line
        let dir = C64::from_polar(1.0, std::f64::consts::PI * (k as f64 + 0.5) / n.max(1) as f64);
        // entries of [l | q] along x = rho dir are polynomials in rho of degree 1 and 2
        let entry = |r: &DyadRow| {
            let v0 = r.beta;
            let v1 = r.alpha * dir;
            let c = |v: f64| C64::new(v, 0.0);
            let l1 = [c(2.0 * v0.re), c(2.0 * v1.re)];
            let l2 = [c(2.0 * v0.im), c(2.0 * v1.im)];
            let q = [c(v0.norm_sqr()), c(2.0 * (v0.re * v1.re + v0.im * v1.im)), c(v1.norm_sqr())];
            (l1, l2, q)
        };
        use super::univariate::{mul, roots, sub};
        let e: Vec<_> = rows.iter().map(entry).collect();
        let minor = |a: usize, b: usize| sub(&mul(&e[a].0, &e[b].1), &mul(&e[a].1, &e[b].0));
        // det [l1 l2 q] expanded along q
        let det = super::univariate::add(
            &sub(&mul(&e[0].2, &minor(1, 2)), &mul(&e[1].2, &minor(0, 2))),
            &mul(&e[2].2, &minor(0, 1)),
        );
        for rho in roots(&det, 1e-12) {
            if rho.im.abs() > 1e-9 * (1.0 + rho.norm()) {
                continue;
            }
            let x = dir * rho.re;
            // y from rows 1, 2 (consistent with row 3 on the curve)
            let l = |r: &DyadRow| {
                let v = r.alpha * x + r.beta;
                (2.0 * v.re, 2.0 * v.im, v.norm_sqr())
            };
            let (a1, b1, q1) = l(&rows[0]);
            let (a2, b2, q2) = l(&rows[1]);
            let d = a1 * b2 - a2 * b1;
            if d.abs() < 1e-12 {
                continue;
            }
            let y = C64::new((-q1 * b2 + q2 * b1) / d, (-a1 * q2 + a2 * q1) / d);
            out.push(Dyad::exact(frame.to_world(p1 + x - y), frame.to_world(p1 + x)));
        }
    }
    Ok(out)
}

/// Largest relative error of a dyad against the rows (for tests and reports).
pub fn check(rows: &[DyadRow; 4], x: C64, y: C64) -> f64 {
    residuals(rows, x, y).iter().fold(0.0_f64, |m, r| m.max(r.abs())) / (1.0 + y.norm_sqr())
}
