//! The RRR dyad: two bodies pinned together at B, each pinned at its other end to a known
//! body (A on body 1's side, C on body 2's). B is where the circles about A and C of the
//! links' lengths meet (two points, one per branch); the bodies' poses follow from their
//! two pins. Velocities and accelerations: the 2 x 2 system of B's velocity (acceleration)
//! seen from both links.

use super::guard::{self, Travel};
use super::{add_move, column, split, BodyRows, NumberMove, Numbers, NEAR_SINGULAR};
use super::{body_qdd, pinned_accelerations, pinned_rates, point_acc, set_body, StepMiss};
use crate::constraints::{cross, dot, kinds::ConstraintKind, perp, sub, Frame};
use crate::math::angle::angle_of;
use crate::model::data::Data;
use crate::model::plan::{Link, Rrr};
use crate::model::structure::Group;
use crate::model::Model;

/// A dyad's positions solved (`Rrr::positions_on`): the known sides' frames and outer
/// pins, the middle pin, |C - A|^2, the closeness and the pins' residual.
struct Placed {
    k1: Frame,
    a: [f64; 2],
    k2: Frame,
    c: [f64; 2],
    b: [f64; 2],
    dd: f64,
    closeness: f64,
    residual: f64,
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
            fixed: Frame::GROUND.point(u_known),
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
        let m = set_body(data, self.body, r, theta, c, s).point(self.u_middle);
        (m[0] - b[0]).abs().max((m[1] - b[1]).abs())
    }

    /// The known side's frame and the outer pin's position.
    #[inline(always)]
    pub fn outer(&self, data: &Data) -> (Frame, [f64; 2]) {
        self.outer_on::<true>(data)
    }

    /// `outer` where `K` says whether the known side may be a body (false: it is the
    /// ground); the ground's pin is `fixed`, the bits its identity frame gives.
    #[inline(always)]
    pub fn outer_on<const K: bool>(&self, data: &Data) -> (Frame, [f64; 2]) {
        match self.known {
            Some(b) if K => {
                let k = data.frames[b];
                let p = k.point(self.u_known);
                (k, p)
            }
            _ => (Frame::GROUND, self.fixed),
        }
    }

    /// The outer pin's velocity (`K` as in `outer_on`; the ground's pin is at rest, +0).
    #[inline(always)]
    pub fn outer_velocity<const K: bool>(&self, k: &Frame) -> [f64; 2] {
        if K {
            k.point_velocity(self.u_known)
        } else {
            [0.0; 2]
        }
    }

    /// The outer pin's acceleration, the pin at `p` (`K` as in `outer_on`).
    #[inline(always)]
    pub fn outer_acceleration<const K: bool>(&self, data: &Data, k: &Frame, p: [f64; 2]) -> [f64; 2] {
        if K {
            point_acc(k, body_qdd(data, self.known), sub(p, k.r))
        } else {
            [0.0; 2]
        }
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
    pub fn solve(&self, data: &mut Data, sign: f64, derivatives: u8) -> Result<(f64, f64), StepMiss> {
        self.solve_inline(data, sign, derivatives)
    }

    /// `solve` inlined into its caller (a sweep's step of the plan).
    #[inline(always)]
    pub(crate) fn solve_inline(
        &self,
        data: &mut Data,
        sign: f64,
        derivatives: u8,
    ) -> Result<(f64, f64), StepMiss> {
        // a known side on the ground folded in: its pin fixed, at rest
        match (self.l1.known.is_some(), self.l2.known.is_some()) {
            (true, true) => self.solve_on::<true, true>(data, sign, derivatives),
            (true, false) => self.solve_on::<true, false>(data, sign, derivatives),
            (false, true) => self.solve_on::<false, true>(data, sign, derivatives),
            (false, false) => self.solve_on::<false, false>(data, sign, derivatives),
        }
    }

    /// `solve` of positions only, with the guard (`guard::rrr`) of the step from the
    /// known pins' bounds in `travel`, written there for both bodies where a later group
    /// reads them (`read`, `closed_form::guard_reads`): (closeness,
    /// residual), or the miss (`NearSingular` where the guard cannot show the step). Only
    /// for a dyad of two bodies (`closed_form::guarded`).
    #[inline(always)]
    pub fn solve_guarded(
        &self,
        data: &mut Data,
        sign: f64,
        travel: &mut [Travel],
        read: bool,
    ) -> Result<(f64, f64), StepMiss> {
        if self.rod {
            return Err(StepMiss::Failed);
        }
        match (self.l1.known.is_some(), self.l2.known.is_some()) {
            (true, true) => self.guarded_on::<true, true>(data, sign, travel, read),
            (true, false) => self.guarded_on::<true, false>(data, sign, travel, read),
            (false, true) => self.guarded_on::<false, true>(data, sign, travel, read),
            (false, false) => self.guarded_on::<false, false>(data, sign, travel, read),
        }
    }

    #[inline(always)]
    fn guarded_on<const K1: bool, const K2: bool>(
        &self,
        data: &mut Data,
        sign: f64,
        travel: &mut [Travel],
        read: bool,
    ) -> Result<(f64, f64), StepMiss> {
        let s = self.positions_on::<K1, K2>(data, sign)?;
        // the known pins' paths: nothing where a side is the ground
        let la = if K1 { self.l1.known.map_or(0.0, |k| travel[k].pin(s.a)) } else { 0.0 };
        let lc = if K2 { self.l2.known.map_or(0.0, |k| travel[k].pin(s.c)) } else { 0.0 };
        let (r1, r2) = (self.l1.length, self.l2.length);
        if !read {
            // the same test; the turns, which no later group reads, not formed
            return if guard::rrr_shown(r1, r2, s.dd, la + lc) {
                Ok((s.closeness, s.residual))
            } else {
                Err(StepMiss::NearSingular)
            };
        }
        let (t1, t2) = guard::rrr(r1, r2, s.dd, la + lc).ok_or(StepMiss::NearSingular)?;
        travel[self.l1.body] = Travel { r: s.a, len: la, turn: t1 };
        travel[self.l2.body] = Travel { r: s.c, len: lc, turn: t2 };
        Ok((s.closeness, s.residual))
    }

    /// B on the branch `sign` and both bodies placed (positions only).
    #[inline(always)]
    fn positions_on<const K1: bool, const K2: bool>(
        &self,
        data: &mut Data,
        sign: f64,
    ) -> Result<Placed, StepMiss> {
        let (k1, a) = self.l1.outer_on::<K1>(data);
        let (k2, c) = self.l2.outer_on::<K2>(data);
        let (r1, r2) = (self.l1.length, self.l2.length);
        let d = sub(c, a);
        let dd = dot(d, d);
        if dd.is_nan() || dd <= 0.0 {
            return Err(StepMiss::NoAssembly);
        }
        // B = A + along d + sign height perp(d), along and height in units of |d|: one
        // division and one square root in the chain (not |d| first, then each over it)
        let inv_dd = 1.0 / dd;
        let along = 0.5 * (dd + r1 * r1 - r2 * r2) * inv_dd;
        let h2 = r1 * r1 * inv_dd - along * along;
        if h2.is_nan() || h2 < 0.0 {
            return Err(StepMiss::NoAssembly);
        }
        let height = sign * h2.sqrt();
        let b = [a[0] + along * d[0] - height * d[1], a[1] + along * d[1] + height * d[0]];
        let res1 = self.l1.place(data, a, b);
        let res2 = if self.rod { 0.0 } else { self.l2.place(data, c, b) };
        // |sin| of the angle at B: |cross(B - A, B - C)| = |height| |d|^2
        let closeness = height.abs() * dd * self.l1.inv_length * self.l2.inv_length;
        Ok(Placed { k1, a, k2, c, b, dd, closeness, residual: res1.max(res2) })
    }

    /// `solve` with `K1`, `K2`: whether link 1's, link 2's known side is a body.
    #[inline(always)]
    fn solve_on<const K1: bool, const K2: bool>(
        &self,
        data: &mut Data,
        sign: f64,
        derivatives: u8,
    ) -> Result<(f64, f64), StepMiss> {
        let Placed { k1, a, k2, c, b, closeness, residual, .. } = self.positions_on::<K1, K2>(data, sign)?;
        if derivatives >= 1 {
            let (rab, rcb) = (sub(b, a), sub(b, c));
            let (pab, pcb) = (perp(rab), perp(rcb));
            // w1 perp(rab) - w2 perp(rcb) = vC - vA
            let inv_det = 1.0 / (pcb[0] * pab[1] - pcb[1] * pab[0]);
            let va = self.l1.outer_velocity::<K1>(&k1);
            let vc = self.l2.outer_velocity::<K2>(&k2);
            let rhs = sub(vc, va);
            let w1 = (pcb[0] * rhs[1] - pcb[1] * rhs[0]) * inv_det;
            let w2 = (pab[0] * rhs[1] - pab[1] * rhs[0]) * inv_det;
            pinned_rates(data, self.l1.body, a, va, w1);
            if !self.rod {
                pinned_rates(data, self.l2.body, c, vc, w2);
            }
            if derivatives >= 2 {
                let aa = self.l1.outer_acceleration::<K1>(data, &k1, a);
                let ac = self.l2.outer_acceleration::<K2>(data, &k2, c);
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
        Ok((closeness, residual))
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
    /// |B - A|^2 = r1^2 and |B - C|^2 = r2^2, gives (B - A).(dB - dA) = r1 dr1 =: s1 and
    /// (B - C).(dB - dC) = r2 dr2 =: s2, the 2 x 2 matrix M of the rate solve; each body
    /// then from its two pins (`Link::place`): with w1 = A1 (du_middle - du_outer),
    /// perp(B - A) dtheta1 = dB - dA - w1 and dR1 = dA - perp(A1 u_outer) dtheta1 - A1
    /// du_outer. dA, dC: the known sides' moves and the parameter's of u_known; r1 dr1 =
    /// (u_middle - u_outer).(du_middle - du_outer). With dB = M^-1 (s1, s2) eliminated,
    /// dtheta1 = a11 s1 + a12 s2 - c1.(dA + w1), and likewise dtheta2: a, c and their
    /// products with B - A and B - C formed once a step.
    /// `zeros`: the ground's rows (n zeros).
    #[inline]
    pub fn tangents(
        &self,
        data: &Data,
        entries: &[NumberMove],
        s: &mut [f64],
        n: usize,
        zeros: &[f64],
    ) -> Result<(), StepMiss> {
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
            return Err(StepMiss::NearSingular);
        }
        // M^-1's columns u, v; the angles' coefficients
        let inv_det = 1.0 / det;
        let (u, v) = ([gc[1] * inv_det, -gc[0] * inv_det], [-ga[1] * inv_det, ga[0] * inv_det]);
        let (inv1, inv2) = (l1.inv_length * l1.inv_length, l2.inv_length * l2.inv_length);
        let (c1, c2) = ([-ga[1] * inv1, ga[0] * inv1], [-gc[1] * inv2, gc[0] * inv2]);
        let (a11, a12, a21, a22) = (dot(c1, u), dot(c1, v), dot(c2, u), dot(c2, v));
        // dtheta1 = g1a.dA + g1c.dC + (own), dtheta2 = g2a.dA + g2c.dC + (own)
        let lin = Lin {
            g1a: [a11 * ga[0] - c1[0], a11 * ga[1] - c1[1]],
            g1c: [a12 * gc[0], a12 * gc[1]],
            g2a: [a21 * ga[0], a21 * ga[1]],
            g2c: [a22 * gc[0] - c2[0], a22 * gc[1] - c2[1]],
            ra: sub(a, k1.r),
            rc: sub(c, k2.r),
            arm1: f1.rot(l1.u_outer),
            arm2: f2.rot(l2.u_outer),
        };
        // a rod's second link is no body of its own
        let (mut out1, mut out2, rest) = split(s, n, l1.body, (!self.rod).then_some(l2.body));
        // the known sides' moves, for every parameter (a side on the ground moves nothing)
        let (a_rows, c_rows) = (rest.known(l1.known, zeros), rest.known(l2.known, zeros));
        let moving = (l1.known.is_some(), l2.known.is_some());
        let (o1, o2) = (&mut out1, out2.as_mut());
        match moving {
            (true, true) => lin.known::<true, true>(n, a_rows, c_rows, o1, o2),
            (true, false) => lin.known::<true, false>(n, a_rows, c_rows, o1, o2),
            (false, true) => lin.known::<false, true>(n, a_rows, c_rows, o1, o2),
            // nothing moves the dyad's known sides
            (false, false) => {
                for row in o1.iter_mut().chain(o2.into_iter().flatten()) {
                    row.fill(0.0);
                }
            }
        }
        // each parameter's own moves of the links' pins
        let (m1, m2) = (sub(l1.u_middle, l1.u_outer), sub(l2.u_middle, l2.u_outer));
        for entry in entries {
            // link 1's u_known, u_outer, u_middle in slots 0..6, link 2's in 6..12
            let (slot, w) = (entry.slot, entry.w);
            let (i, second, kind) = (slot % 2, slot >= 6, (slot / 2) % 3);
            let (k, f, m, cl, b1, b2) =
                if second { (&k2, f2, m2, c2, a12, a22) } else { (&k1, f1, m1, c1, a11, a21) };
            // the known pin's move (d); for d(u_middle - u_outer), r dr moves both angles
            // through M^-1 (x) and this link's own by -c.A d(u_middle - u_outer), and
            // u_outer moves its body's origin by -A du_outer (o)
            let (mut d, mut x, mut o) = ([0.0; 2], [0.0; 2], [0.0; 2]);
            if kind == 0 {
                d = column(k, i);
            } else {
                let (sign, fc) = (if kind == 1 { -1.0 } else { 1.0 }, column(f, i));
                let e = sign * m[i];
                x = [b1 * e, b2 * e];
                x[second as usize] -= sign * dot(cl, fc);
                if kind == 1 {
                    o = fc;
                }
            }
            let (da, dc) = if second { ([0.0; 2], d) } else { (d, [0.0; 2]) };
            let (o1, o2) = if second { ([0.0; 2], o) } else { (o, [0.0; 2]) };
            let d1 = lin.body1(da, dc, x[0]);
            add_move(&mut out1, entry.param, w, [d1[0] - o1[0], d1[1] - o1[1], d1[2]]);
            if let Some(out2) = &mut out2 {
                let d2 = lin.body2(da, dc, x[1]);
                add_move(out2, entry.param, w, [d2[0] - o2[0], d2[1] - o2[1], d2[2]]);
            }
        }
        Ok(())
    }
}

/// An RRR dyad's derivative at one step: the angles' coefficients of dA and dC (g), the
/// outer pins about the known sides' origins (ra, rc) and about the bodies' (arm).
struct Lin {
    g1a: [f64; 2],
    g1c: [f64; 2],
    g2a: [f64; 2],
    g2c: [f64; 2],
    ra: [f64; 2],
    rc: [f64; 2],
    arm1: [f64; 2],
    arm2: [f64; 2],
}

impl Lin {
    /// Body 1's move for moves dA, dC and its angle's own part x1.
    #[inline(always)]
    fn body1(&self, da: [f64; 2], dc: [f64; 2], x1: f64) -> [f64; 3] {
        let th = dot(self.g1a, da) + dot(self.g1c, dc) + x1;
        [da[0] + self.arm1[1] * th, da[1] - self.arm1[0] * th, th]
    }

    /// Body 2's move for moves dA, dC and its angle's own part x2.
    #[inline(always)]
    fn body2(&self, da: [f64; 2], dc: [f64; 2], x2: f64) -> [f64; 3] {
        let th = dot(self.g2a, da) + dot(self.g2c, dc) + x2;
        [dc[0] + self.arm2[1] * th, dc[1] - self.arm2[0] * th, th]
    }

    /// The angles' moves for moves dA (`A`: if A moves) and dC (`C`), the terms of a side
    /// that does not move left out (-0.0 is the sum's identity; a product with 0 is not).
    #[inline(always)]
    fn angles<const A: bool, const C: bool>(&self, da: [f64; 2], dc: [f64; 2]) -> (f64, f64) {
        let (mut th1, mut th2) = (-0.0, -0.0);
        if A {
            (th1, th2) = (th1 + dot(self.g1a, da), th2 + dot(self.g2a, da));
        }
        if C {
            (th1, th2) = (th1 + dot(self.g1c, dc), th2 + dot(self.g2c, dc));
        }
        (th1, th2)
    }

    /// The bodies' rows for the known sides' moves (`a`, `c`: their rows; `A`, `C`: whether
    /// they move, else they are the ground and are not read), every parameter at once.
    #[inline(always)]
    fn known<const A: bool, const C: bool>(
        &self,
        n: usize,
        a: [&[f64]; 3],
        c: [&[f64]; 3],
        out1: &mut BodyRows,
        out2: Option<&mut BodyRows>,
    ) {
        // rows cut to n: no bounds checks in the loops
        let ([x1, y1, t1], [x2, y2, t2]) = (a.map(|r| &r[..n]), c.map(|r| &r[..n]));
        let moves = |j: usize| {
            let da = if A { [x1[j] - self.ra[1] * t1[j], y1[j] + self.ra[0] * t1[j]] } else { [-0.0; 2] };
            let dc = if C { [x2[j] - self.rc[1] * t2[j], y2[j] + self.rc[0] * t2[j]] } else { [-0.0; 2] };
            (da, dc)
        };
        let [a1, a2] = self.arm1;
        let [bx1, by1, bt1] = out1;
        let (bx1, by1, bt1) = (&mut bx1[..n], &mut by1[..n], &mut bt1[..n]);
        match out2 {
            Some([bx2, by2, bt2]) => {
                self.both::<A, C>([x1, y1, t1, x2, y2, t2], bx1, by1, bt1, bx2, by2, bt2)
            }
            None => {
                for j in 0..n {
                    let (da, dc) = moves(j);
                    let (th1, _) = self.angles::<A, C>(da, dc);
                    [bx1[j], by1[j], bt1[j]] = [da[0] + a2 * th1, da[1] - a1 * th1, th1];
                }
            }
        }
    }

    /// `known` for both bodies, each output row a reference of its own (an argument by
    /// itself, not in a tuple or array), which the compiler then knows not to overlap the
    /// others: it may take several parameters at once.
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn both<const A: bool, const C: bool>(
        &self,
        ins: [&[f64]; 6],
        bx1: &mut [f64],
        by1: &mut [f64],
        bt1: &mut [f64],
        bx2: &mut [f64],
        by2: &mut [f64],
        bt2: &mut [f64],
    ) {
        let n = bx1.len();
        // every row cut to n: no bounds checks in the loop
        let [x1, y1, t1, x2, y2, t2] = ins.map(|r| &r[..n]);
        let (by1, bt1, bx2, by2, bt2) =
            (&mut by1[..n], &mut bt1[..n], &mut bx2[..n], &mut by2[..n], &mut bt2[..n]);
        let ([a1, a2], [b1, b2]) = (self.arm1, self.arm2);
        for j in 0..n {
            let da = if A { [x1[j] - self.ra[1] * t1[j], y1[j] + self.ra[0] * t1[j]] } else { [-0.0; 2] };
            let dc = if C { [x2[j] - self.rc[1] * t2[j], y2[j] + self.rc[0] * t2[j]] } else { [-0.0; 2] };
            let (th1, th2) = self.angles::<A, C>(da, dc);
            [bx1[j], by1[j], bt1[j]] = [da[0] + a2 * th1, da[1] - a1 * th1, th1];
            [bx2[j], by2[j], bt2[j]] = [dc[0] + b2 * th2, dc[1] - b1 * th2, th2];
        }
    }
}
