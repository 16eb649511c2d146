//! The RRR dyad: two bodies pinned together at B, each pinned at its other end to a known
//! body (A on body 1's side, C on body 2's). B is where the circles about A and C of the
//! links' lengths meet (two points, one per branch); the bodies' poses follow from their
//! two pins. Velocities and accelerations: the 2 x 2 system of B's velocity (acceleration)
//! seen from both links.

use super::{body_qdd, pinned_accelerations, pinned_rates, point_acc, set_body, side, Miss};
use super::{moved, pair, seed_of, set_tangent, Numbers, Seed, NEAR_SINGULAR};
use crate::assembly::angle_of;
use crate::data::Data;
use crate::joints::{cross, dot, perp, sub, ConstraintKind, Frame};
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
    /// the compiled number each of u_known, u_outer, u_middle (x, y) is: (constraint, index
    /// in its `params_mut`); None for a coordinate no number holds (a rod's)
    pub numbers: [Option<(usize, usize)>; 6],
}

impl Link {
    fn new(
        body: usize,
        known: Option<usize>,
        u_known: [f64; 2],
        u_outer: [f64; 2],
        u_middle: [f64; 2],
        numbers: [Option<(usize, usize)>; 6],
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
            numbers,
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

/// The numbers (constraint, index) of a point's x and y that sit at `first`, `first + 1`
/// of constraint `c`'s `params_mut`.
pub(crate) fn xy(c: usize, first: usize) -> [Option<(usize, usize)>; 2] {
    [Some((c, first)), Some((c, first + 1))]
}

/// Reads a dyad link from its outer pin `outer` (constraint index) on `body`, and its
/// middle pin's point in the body, which is the number pair `middle` (constraint, first
/// index).
pub(crate) fn link(
    model: &Model,
    body: usize,
    outer: usize,
    u_middle: [f64; 2],
    middle: [Option<(usize, usize)>; 2],
) -> Option<Link> {
    let c = &model.constraints[outer];
    let ConstraintKind::Revolute(j) = &c.kind else { return None };
    // a revolute's numbers: u_a at 0, 1 and u_b at 2, 3
    let numbers = |known: usize, own: usize| {
        let [k, o, m] = [xy(outer, known), xy(outer, own), middle];
        [k[0], k[1], o[0], o[1], m[0], m[1]]
    };
    if c.body_b == Some(body) {
        Link::new(body, c.body_a, j.u_a, j.u_b, u_middle, numbers(0, 2))
    } else if c.body_a == Some(body) {
        Link::new(body, c.body_b, j.u_b, j.u_a, u_middle, numbers(2, 0))
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
                middle = Some((c.body_a?, j.u_a, c.body_b?, j.u_b, k));
            } else {
                outer.push(k);
            }
        }
        let (ma, ua, mb, ub, km) = middle?;
        if outer.len() != 2 || ma == mb {
            return None;
        }
        let u_mid = |b: usize| if b == ma { ua } else { ub };
        let n_mid = |b: usize| xy(km, if b == ma { 0 } else { 2 });
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
        let l1 = link(model, b1, outer[0], u_mid(b1), n_mid(b1))?;
        let l2 = link(model, b2, outer[1], u_mid(b2), n_mid(b2))?;
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
                // a distance joint's numbers: u_a at 0, 1, u_b at 2, 3, length at 4
                ConstraintKind::Distance(j) if c.body_b == Some(body) && c.body_a != Some(body) => {
                    rod = Some((c.body_a, j.u_a, j.u_b, j.length, k, 0, 2))
                }
                ConstraintKind::Distance(j) if c.body_a == Some(body) && c.body_b != Some(body) => {
                    rod = Some((c.body_b, j.u_b, j.u_a, j.length, k, 2, 0))
                }
                _ => return None,
            }
        }
        let (pin, (known, u_known, u_end, length, kd, at_known, at_end)) = (pin?, rod?);
        let l1 = link(model, body, pin, u_end, xy(kd, at_end))?;
        // the rod as a link from its known end, its far end at distance `length` along x
        let [k0, k1] = xy(kd, at_known);
        let numbers = [k0, k1, None, None, Some((kd, 4)), None];
        let l2 = Link::new(body, known, u_known, [0.0, 0.0], [length, 0.0], numbers)?;
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

    /// Its numbers: link 1's u_known, u_outer, u_middle (x, y each) in slots 0..6, link 2's
    /// in 6..12.
    pub fn numbers(&self) -> Numbers {
        let mut out = Numbers::default();
        out.link(&self.l1.numbers, 0);
        out.link(&self.l2.numbers, 6);
        out
    }

    /// dq/dp of both bodies (`super::tangents`), `solve` differentiated: B on both circles,
    /// |B - A|^2 = r1^2 and |B - C|^2 = r2^2, gives (B - A).(dB - dA) = r1 dr1 and
    /// (B - C).(dB - dC) = r2 dr2, the 2 x 2 matrix of the rate solve; each body then from
    /// its two pins (`Link::place`): perp(B - A) dtheta = dB - dA - A1 d(u_middle - u_outer)
    /// and dR = dA - perp(A1 u_outer) dtheta - A1 du_outer. dA, dC: the known sides' moves
    /// and the parameter's of u_known; r dr = (u_middle - u_outer).d(u_middle - u_outer).
    #[inline]
    pub fn tangents(&self, data: &Data, seeds: &[Seed], s: &mut [f64], n: usize) -> Result<(), Miss> {
        let (l1, l2) = (&self.l1, &self.l2);
        let (k1, a) = l1.outer(data);
        let (k2, c) = l2.outer(data);
        // a rod's second link is the first body seen from the rod's known end
        let (f1, f2) = (&data.frames[l1.body], &data.frames[l2.body]);
        let b = f1.point(l1.u_middle);
        let (ga, gc) = (sub(b, a), sub(b, c));
        let det = cross(ga, gc);
        // |sin| of the angle at B, `solve`'s closeness
        let closeness = det.abs() * l1.inv_length * l2.inv_length;
        if closeness.is_nan() || closeness < NEAR_SINGULAR {
            return Err(Miss::NearSingular);
        }
        let inv_det = 1.0 / det;
        let (ra, rc) = (sub(a, k1.r), sub(c, k2.r));
        let (arm1, arm2) = (f1.rot(l1.u_outer), f2.rot(l2.u_outer));
        let (m1, m2) = (sub(l1.u_middle, l1.u_outer), sub(l2.u_middle, l2.u_outer));
        let (inv1, inv2) = (l1.inv_length * l1.inv_length, l2.inv_length * l2.inv_length);
        let mut at = 0;
        for j in 0..n {
            let (mut da, _) = moved(s, n, l1.known, ra, j);
            let (mut dc, _) = moved(s, n, l2.known, rc, j);
            // the parameter's own moves: r dr per link, each body's d(u_middle - u_outer)
            // and du_outer in world axes
            let (mut e1, mut e2) = (0.0, 0.0);
            let (mut w1, mut w2, mut o1, mut o2) = ([0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2]);
            if let Some(seed) = seed_of(seeds, &mut at, j) {
                let d = &seed.slots;
                let (dk1, dk2) = (k1.rot(pair(d, 0)), k2.rot(pair(d, 6)));
                da = [da[0] + dk1[0], da[1] + dk1[1]];
                dc = [dc[0] + dk2[0], dc[1] + dk2[1]];
                let (dm1, dm2) = (sub(pair(d, 4), pair(d, 2)), sub(pair(d, 10), pair(d, 8)));
                (e1, e2) = (dot(m1, dm1), dot(m2, dm2));
                (w1, w2) = (f1.rot(dm1), f2.rot(dm2));
                (o1, o2) = (f1.rot(pair(d, 2)), f2.rot(pair(d, 8)));
            }
            let r = [dot(ga, da) + e1, dot(gc, dc) + e2];
            let db = [(gc[1] * r[0] - ga[1] * r[1]) * inv_det, (ga[0] * r[1] - gc[0] * r[0]) * inv_det];
            let dth1 = cross(ga, sub(sub(db, da), w1)) * inv1;
            let dr1 = [da[0] + arm1[1] * dth1 - o1[0], da[1] - arm1[0] * dth1 - o1[1]];
            set_tangent(s, n, l1.body, j, dr1, dth1);
            if !self.rod {
                let dth2 = cross(gc, sub(sub(db, dc), w2)) * inv2;
                let dr2 = [dc[0] + arm2[1] * dth2 - o2[0], dc[1] - arm2[0] * dth2 - o2[1]];
                set_tangent(s, n, l2.body, j, dr2, dth2);
            }
        }
        Ok(())
    }
}
