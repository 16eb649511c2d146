//! The RRP dyad: a link pinned to a known body at A and at B to a slider, the slider on a
//! prismatic joint with a known body. The slider turns with that body, so B runs along a
//! line known before the dyad is solved; B is where the circle about A of the link's
//! length meets it (two points, one per branch). Velocities and accelerations: B's seen
//! from the link and from the slide (with the slide's Coriolis term when the line turns).

use super::rrr::{link, Link};
use super::{
    body_qdd, pinned_accelerations, pinned_rates, point_acc, set_acc, set_body, set_rates, side, Miss,
};
use crate::data::Data;
use crate::joints::{dot, perp, sub, ConstraintKind, Frame};
use crate::model::Model;
use crate::structure::Group;

#[derive(Debug, Clone)]
pub struct Rrp {
    link: Link,
    slider: usize,
    /// the prismatic's known side
    known: Option<usize>,
    /// the slider's middle pin in its frame
    u_pin: [f64; 2],
    /// true: the line is fixed in the known body (the slider is the prismatic's side b);
    /// false: the line is fixed in the slider and the known body's point runs on it
    line_in_known: bool,
    /// the prismatic's u_a, u_b, unit axis e_a (in side a's frame) and theta0
    u_a: [f64; 2],
    u_b: [f64; 2],
    e_a: [f64; 2],
    theta0: f64,
}

impl Rrp {
    pub fn new(model: &Model, g: &Group) -> Option<Rrp> {
        if g.bodies.len() != 2 || g.constraints.len() != 3 {
            return None;
        }
        let inside = |b: Option<usize>| b.is_some_and(|b| g.bodies.contains(&b));
        let (mut middle, mut outer_r, mut prismatic) = (None, None, None);
        for &k in &g.constraints {
            let c = &model.constraints[k];
            match &c.kind {
                ConstraintKind::Revolute(j) if inside(c.body_a) && inside(c.body_b) => {
                    middle = Some((c.body_a?, j.u_a, c.body_b?, j.u_b))
                }
                ConstraintKind::Revolute(_) => outer_r = Some(k),
                ConstraintKind::Prismatic(p) if !(inside(c.body_a) && inside(c.body_b)) => {
                    prismatic = Some((k, p.clone()))
                }
                _ => return None,
            }
        }
        let (ma, ua, mb, ub) = middle?;
        let (outer_r, (kp, p)) = (outer_r?, prismatic?);
        let c = &model.constraints[outer_r];
        let rod = if inside(c.body_a) { c.body_a? } else { c.body_b? };
        let slider = if rod == ma { mb } else { ma };
        if rod == slider {
            return None;
        }
        let (u_rod, u_pin) = if rod == ma { (ua, ub) } else { (ub, ua) };
        let link = link(model, rod, outer_r, u_rod)?;
        let cp = &model.constraints[kp];
        let (known, line_in_known) = if cp.body_b == Some(slider) {
            (cp.body_a, true)
        } else if cp.body_a == Some(slider) {
            (cp.body_b, false)
        } else {
            return None;
        };
        Some(Rrp {
            link,
            slider,
            known,
            u_pin,
            line_in_known,
            u_a: p.u_a,
            u_b: p.u_b,
            e_a: p.e_a,
            theta0: p.theta0,
        })
    }

    /// The slider's angle, cos, sin; a point of B's line and its unit direction.
    #[inline(always)]
    fn line(&self, k: &Frame, turn: &mut [f64; 3]) -> (f64, f64, f64, [f64; 2], [f64; 2]) {
        let theta = if self.line_in_known { k.theta + self.theta0 } else { k.theta - self.theta0 };
        let (c, s) = crate::assembly::turned(theta, turn);
        let rot = |u: [f64; 2]| [c * u[0] - s * u[1], s * u[0] + c * u[1]];
        if self.line_in_known {
            // slider point u_b on the line through k(u_a) along k's e_a
            let off = rot(sub(self.u_pin, self.u_b));
            let p0 = k.point(self.u_a);
            (theta, c, s, [p0[0] + off[0], p0[1] + off[1]], k.rot(self.e_a))
        } else {
            // k's point u_b on the line through slider(u_a) along the slider's e_a
            let off = rot(sub(self.u_pin, self.u_a));
            let p0 = k.point(self.u_b);
            (theta, c, s, [p0[0] + off[0], p0[1] + off[1]], rot(self.e_a))
        }
    }

    #[inline]
    pub fn solve(&self, data: &mut Data, sign: f64, derivatives: u8) -> Result<(f64, f64), Miss> {
        let (k1, a) = self.link.outer(data);
        let k = side(data, self.known);
        let mut turn = data.frame_base[self.slider];
        let (theta_s, cs, ss, p0, dir) = self.line(&k, &mut turn);
        data.frame_base[self.slider] = turn;
        let r1 = self.link.length;
        let p = sub(a, p0);
        let s0 = dot(p, dir);
        let off = dir[0] * p[1] - dir[1] * p[0];
        let h2 = r1 * r1 - off * off;
        if h2.is_nan() || h2 < 0.0 {
            return Err(Miss::NoAssembly);
        }
        let h = h2.sqrt();
        let along = s0 + sign * h;
        let b = [p0[0] + along * dir[0], p0[1] + along * dir[1]];
        let res1 = self.link.place(data, a, b);
        let arm = [cs * self.u_pin[0] - ss * self.u_pin[1], ss * self.u_pin[0] + cs * self.u_pin[1]];
        set_body(data, self.slider, sub(b, arm), theta_s, cs, ss);
        let closeness = h / r1;
        if derivatives >= 1 {
            let rab = sub(b, a);
            let pab = perp(rab);
            // B moving with the known body, plus the slide u along dir
            let rk = sub(b, k.r);
            let vk = [k.rd[0] - k.thetad * rk[1], k.rd[1] + k.thetad * rk[0]];
            let va = k1.point_velocity(self.link.u_known);
            // w pab - u dir = vk - va
            let inv_det = 1.0 / (dir[0] * pab[1] - dir[1] * pab[0]);
            let rhs = sub(vk, va);
            let w = (dir[0] * rhs[1] - dir[1] * rhs[0]) * inv_det;
            let u = (pab[0] * rhs[1] - pab[1] * rhs[0]) * inv_det;
            pinned_rates(data, self.link.body, a, va, w);
            let vb = [vk[0] + u * dir[0], vk[1] + u * dir[1]];
            let rs = sub(data.frames[self.slider].r, b);
            let prs = perp(rs);
            set_rates(data, self.slider, [vb[0] + k.thetad * prs[0], vb[1] + k.thetad * prs[1]], k.thetad);
            if derivatives >= 2 {
                let qk = body_qdd(data, self.known);
                let ak = point_acc(&k, qk, sub(b, k.r));
                let aa = point_acc(&k1, body_qdd(data, self.link.known), sub(a, k1.r));
                let pd = perp(dir);
                let cor = 2.0 * k.thetad * u;
                let rhs = [
                    ak[0] + cor * pd[0] - aa[0] + w * w * rab[0],
                    ak[1] + cor * pd[1] - aa[1] + w * w * rab[1],
                ];
                let alpha = (dir[0] * rhs[1] - dir[1] * rhs[0]) * inv_det;
                let ud = (pab[0] * rhs[1] - pab[1] * rhs[0]) * inv_det;
                pinned_accelerations(data, self.link.body, a, aa, w, alpha);
                let ab = [ak[0] + ud * dir[0] + cor * pd[0], ak[1] + ud * dir[1] + cor * pd[1]];
                let w2 = k.thetad * k.thetad;
                set_acc(
                    data,
                    self.slider,
                    [ab[0] + qk[2] * prs[0] - w2 * rs[0], ab[1] + qk[2] * prs[1] - w2 * rs[1]],
                    qk[2],
                );
            }
        }
        let back = data.frames[self.slider].point(self.u_pin);
        let res2 = (back[0] - b[0]).abs().max((back[1] - b[1]).abs());
        Ok((closeness, res1.max(res2)))
    }

    /// The branch sign, closeness and its rate (with `rates`, else 0) of the configuration
    /// in data (frames current).
    pub fn branch(&self, data: &Data, rates: bool) -> (f64, f64, f64) {
        let (k1, a) = self.link.outer(data);
        let k = side(data, self.known);
        let mut turn = [f64::NAN, 1.0, 0.0];
        let (.., dir) = self.line(&k, &mut turn);
        let f = &data.frames[self.link.body];
        let b = f.point(self.link.u_middle);
        let rab = sub(b, a);
        let along = dot(rab, dir);
        let sign = if along < 0.0 { -1.0 } else { 1.0 };
        let rate = if rates {
            let vab = sub(f.point_velocity(self.link.u_middle), k1.point_velocity(self.link.u_known));
            let pd = perp(dir);
            sign * (dot(vab, dir) + k.thetad * dot(rab, pd)) / self.link.length
        } else {
            0.0
        };
        (sign, along.abs() / self.link.length, rate)
    }
}
