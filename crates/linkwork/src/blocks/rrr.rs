//! The RRR dyad: two bodies pinned together at B, each pinned at its other end to a known
//! body (A on body 1's side, C on body 2's). B is where the circles about A and C of the
//! links' lengths meet (two points, one per branch); the bodies' poses follow from their
//! two pins. Velocities and accelerations: the 2 x 2 system of B's velocity (acceleration)
//! seen from both links.

use super::{body_qdd, pinned_accelerations, pinned_rates, point_acc, set_body, side, Miss};
use crate::assembly::angle_of;
use crate::data::Data;
use crate::joints::{dot, perp, sub, ConstraintKind, Frame};
use crate::model::Model;
use crate::structure::Group;

/// One link of a dyad: a body with its pin to the known side and its middle pin.
#[derive(Debug, Clone)]
pub(crate) struct Link {
    pub body: usize,
    /// the known side and the outer pin in its frame
    pub known: Option<usize>,
    pub u_known: [f64; 2],
    /// the outer and the middle pin in the body's frame
    pub u_outer: [f64; 2],
    pub u_middle: [f64; 2],
    /// |u_middle - u_outer| and that direction in the body's frame
    pub length: f64,
    pub inv_length: f64,
    pub dir: [f64; 2],
}

impl Link {
    fn new(
        body: usize,
        known: Option<usize>,
        u_known: [f64; 2],
        u_outer: [f64; 2],
        u_middle: [f64; 2],
    ) -> Option<Link> {
        let d = sub(u_middle, u_outer);
        let length = d[0].hypot(d[1]);
        (length > 0.0 && length.is_finite()).then(|| Link {
            body,
            known,
            u_known,
            u_outer,
            u_middle,
            length,
            inv_length: 1.0 / length,
            dir: [d[0] / length, d[1] / length],
        })
    }

    /// The body's pose with its outer pin at `a` and middle pin at `b` (|b - a| = length
    /// to round-off): cos, sin of its angle from the unit vector a -> b, theta continued
    /// from the body's last one. Returns the pin residual (middle pin against b).
    #[inline(always)]
    pub fn place(&self, data: &mut Data, a: [f64; 2], b: [f64; 2]) -> f64 {
        // |b - a| is the length to round-off (b is on its circle): no square root
        let w = sub(b, a);
        let w = [w[0] * self.inv_length, w[1] * self.inv_length];
        // the rotation taking dir to w
        let c = self.dir[0] * w[0] + self.dir[1] * w[1];
        let s = self.dir[0] * w[1] - self.dir[1] * w[0];
        let theta = angle_of(c, s, data.q[3 * self.body + 2], &mut data.frame_base[self.body]);
        let arm = [c * self.u_outer[0] - s * self.u_outer[1], s * self.u_outer[0] + c * self.u_outer[1]];
        let r = sub(a, arm);
        set_body(data, self.body, r, theta, c, s);
        let m = data.frames[self.body].point(self.u_middle);
        (m[0] - b[0]).abs().max((m[1] - b[1]).abs())
    }

    /// The known outer pin's position, velocity and acceleration.
    #[inline(always)]
    pub fn outer(&self, data: &Data) -> (Frame, [f64; 2]) {
        let k = side(data, self.known);
        let p = k.point(self.u_known);
        (k, p)
    }
}

/// Reads a dyad link from its outer pin `outer` (constraint index) on `body`, and its
/// middle pin's point in the body.
pub(crate) fn link(model: &Model, body: usize, outer: usize, u_middle: [f64; 2]) -> Option<Link> {
    let c = &model.constraints[outer];
    let ConstraintKind::Revolute(j) = &c.kind else { return None };
    if c.body_b == Some(body) {
        Link::new(body, c.body_a, j.u_a, j.u_b, u_middle)
    } else if c.body_a == Some(body) {
        Link::new(body, c.body_b, j.u_b, j.u_a, u_middle)
    } else {
        None
    }
}

#[derive(Debug, Clone)]
pub struct Rrr {
    l1: Link,
    l2: Link,
    /// l2 is a distance joint (a massless tie rod from its known end), not a body
    rod: bool,
}

impl Rrr {
    pub fn new(model: &Model, g: &Group) -> Option<Rrr> {
        if g.bodies.len() != 2 || g.constraints.len() != 3 {
            return None;
        }
        let inside = |b: Option<usize>| b.is_some_and(|b| g.bodies.contains(&b));
        let (mut middle, mut outer) = (None, Vec::new());
        for &k in &g.constraints {
            let c = &model.constraints[k];
            let ConstraintKind::Revolute(j) = &c.kind else { return None };
            if inside(c.body_a) && inside(c.body_b) {
                middle = Some((c.body_a?, j.u_a, c.body_b?, j.u_b));
            } else {
                outer.push(k);
            }
        }
        let (ma, ua, mb, ub) = middle?;
        if outer.len() != 2 || ma == mb {
            return None;
        }
        let u_mid = |b: usize| if b == ma { ua } else { ub };
        let body_of = |k: usize| {
            let c = &model.constraints[k];
            if inside(c.body_a) {
                c.body_a
            } else {
                c.body_b
            }
        };
        let (b1, b2) = (body_of(outer[0])?, body_of(outer[1])?);
        if b1 == b2 {
            return None;
        }
        let l1 = link(model, b1, outer[0], u_mid(b1))?;
        let l2 = link(model, b2, outer[1], u_mid(b2))?;
        Some(Rrr { l1, l2, rod: false })
    }

    /// A pinned body tied to a known body by a distance joint (a steering knuckle's tie
    /// rod): the dyad with the rod as its second link, a "one body" group.
    pub fn rod(model: &Model, g: &Group) -> Option<Rrr> {
        if g.bodies.len() != 1 || g.constraints.len() != 2 {
            return None;
        }
        let body = g.bodies[0];
        let (mut pin, mut rod) = (None, None);
        for &k in &g.constraints {
            let c = &model.constraints[k];
            match &c.kind {
                ConstraintKind::Revolute(_) => pin = Some(k),
                ConstraintKind::Distance(j) if c.body_b == Some(body) && c.body_a != Some(body) => {
                    rod = Some((c.body_a, j.u_a, j.u_b, j.length))
                }
                ConstraintKind::Distance(j) if c.body_a == Some(body) && c.body_b != Some(body) => {
                    rod = Some((c.body_b, j.u_b, j.u_a, j.length))
                }
                _ => return None,
            }
        }
        let (pin, (known, u_known, u_end, length)) = (pin?, rod?);
        let l1 = link(model, body, pin, u_end)?;
        // the rod as a link from its known end, its far end at distance `length` along x
        let l2 = Link::new(body, known, u_known, [0.0, 0.0], [length, 0.0])?;
        Some(Rrr { l1, l2, rod: true })
    }

    /// B on the branch `sign`; returns (closeness, residual) or the miss.
    #[inline]
    pub fn solve(&self, data: &mut Data, sign: f64, derivatives: u8) -> Result<(f64, f64), Miss> {
        let (k1, a) = self.l1.outer(data);
        let (k2, c) = self.l2.outer(data);
        let (r1, r2) = (self.l1.length, self.l2.length);
        let d = sub(c, a);
        let dd = dot(d, d);
        if dd.is_nan() || dd <= 0.0 {
            return Err(Miss::NoAssembly);
        }
        // B = A + along d + sign height perp(d), along and height in units of |d|: one
        // division and one square root in the chain (not |d| first, then each over it)
        let inv_dd = 1.0 / dd;
        let along = 0.5 * (dd + r1 * r1 - r2 * r2) * inv_dd;
        let h2 = r1 * r1 * inv_dd - along * along;
        if h2.is_nan() || h2 < 0.0 {
            return Err(Miss::NoAssembly);
        }
        let height = sign * h2.sqrt();
        let b = [a[0] + along * d[0] - height * d[1], a[1] + along * d[1] + height * d[0]];
        let res1 = self.l1.place(data, a, b);
        let res2 = if self.rod { 0.0 } else { self.l2.place(data, c, b) };
        // |sin| of the angle at B: |cross(B - A, B - C)| = |height| |d|^2
        let closeness = height.abs() * dd * self.l1.inv_length * self.l2.inv_length;
        if derivatives >= 1 {
            let (rab, rcb) = (sub(b, a), sub(b, c));
            let (pab, pcb) = (perp(rab), perp(rcb));
            // w1 perp(rab) - w2 perp(rcb) = vC - vA
            let inv_det = 1.0 / (pcb[0] * pab[1] - pcb[1] * pab[0]);
            let va = k1.point_velocity(self.l1.u_known);
            let vc = k2.point_velocity(self.l2.u_known);
            let rhs = sub(vc, va);
            let w1 = (pcb[0] * rhs[1] - pcb[1] * rhs[0]) * inv_det;
            let w2 = (pab[0] * rhs[1] - pab[1] * rhs[0]) * inv_det;
            pinned_rates(data, self.l1.body, a, va, w1);
            if !self.rod {
                pinned_rates(data, self.l2.body, c, vc, w2);
            }
            if derivatives >= 2 {
                let aa = point_acc(&k1, body_qdd(data, self.l1.known), sub(a, k1.r));
                let ac = point_acc(&k2, body_qdd(data, self.l2.known), sub(c, k2.r));
                let rhs = [
                    ac[0] - aa[0] - w2 * w2 * rcb[0] + w1 * w1 * rab[0],
                    ac[1] - aa[1] - w2 * w2 * rcb[1] + w1 * w1 * rab[1],
                ];
                let a1 = (pcb[0] * rhs[1] - pcb[1] * rhs[0]) * inv_det;
                let a2 = (pab[0] * rhs[1] - pab[1] * rhs[0]) * inv_det;
                pinned_accelerations(data, self.l1.body, a, aa, w1, a1);
                if !self.rod {
                    pinned_accelerations(data, self.l2.body, c, ac, w2, a2);
                }
            }
        }
        Ok((closeness, res1.max(res2)))
    }

    /// The branch sign, closeness and its rate (with `rates`, else 0) of the configuration
    /// in data (frames current).
    pub fn branch(&self, data: &Data, rates: bool) -> (f64, f64, f64) {
        let (k1, a) = self.l1.outer(data);
        let (k2, c) = self.l2.outer(data);
        let f1 = &data.frames[self.l1.body];
        let b = f1.point(self.l1.u_middle);
        let (rab, rcb) = (sub(b, a), sub(b, c));
        let cross = rab[0] * rcb[1] - rab[1] * rcb[0];
        let sign = if cross < 0.0 { -1.0 } else { 1.0 };
        let norm = 1.0 / (self.l1.length * self.l2.length);
        let rate = if rates {
            let vb = f1.point_velocity(self.l1.u_middle);
            let vab = sub(vb, k1.point_velocity(self.l1.u_known));
            let vcb = sub(vb, k2.point_velocity(self.l2.u_known));
            sign * norm * (vab[0] * rcb[1] - vab[1] * rcb[0] + rab[0] * vcb[1] - rab[1] * vcb[0])
        } else {
            0.0
        };
        (sign, cross.abs() * norm, rate)
    }
}
