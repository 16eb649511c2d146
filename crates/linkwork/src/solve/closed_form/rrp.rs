//! The RRP dyad: a link pinned to a known body at A and at B to a slider, the slider on a
//! prismatic joint with a known body. The slider turns with that body, so B runs along a
//! line known before the dyad is solved; B is where the circle about A of the link's
//! length meets it (two points, one per branch). Velocities and accelerations: B's seen
//! from the link and from the slide (with the slide's Coriolis term when the line turns).

use super::guard::{self, Travel};
use super::rrr::{link, xy};
use super::{add_move, column, split, NumberMove, Numbers, NEAR_SINGULAR};
use super::{
    body_qdd, pinned_accelerations, pinned_rates, point_acc, set_acc, set_body, set_rates, side, StepMiss,
};
use crate::constraints::{cross, dot, kinds::ConstraintKind, perp, sub, Frame};
use crate::model::data::Data;
use crate::model::plan::{Line, Rrp};
use crate::model::structure::Group;
use crate::model::Model;

/// A step of the dyad: (closeness, residual), the link's known pin A, and A's offset from
/// the slide's line.
type Solved = ((f64, f64), [f64; 2], f64);

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
                    middle = Some((c.body_a?, j.u_a, c.body_b?, j.u_b, k))
                }
                ConstraintKind::Revolute(_) => outer_r = Some(k),
                ConstraintKind::Prismatic(p) if !(inside(c.body_a) && inside(c.body_b)) => {
                    prismatic = Some((k, p.clone()))
                }
                _ => return None,
            }
        }
        let (ma, ua, mb, ub, km) = middle?;
        let (outer_r, (kp, p)) = (outer_r?, prismatic?);
        let c = &model.constraints[outer_r];
        let rod = if inside(c.body_a) { c.body_a? } else { c.body_b? };
        let slider = if rod == ma { mb } else { ma };
        if rod == slider {
            return None;
        }
        let (u_rod, u_pin) = if rod == ma { (ua, ub) } else { (ub, ua) };
        // the middle revolute's numbers: u_a at 0, 1, u_b at 2, 3
        let (at_rod, at_pin) = if rod == ma { (0, 2) } else { (2, 0) };
        let link = link(model, rod, outer_r, u_rod, xy(km, at_rod))?;
        let cp = &model.constraints[kp];
        let (known, line_in_known) = if cp.body_b == Some(slider) {
            (cp.body_a, true)
        } else if cp.body_a == Some(slider) {
            (cp.body_b, false)
        } else {
            return None;
        };
        let mut rrp = Rrp {
            link,
            slider,
            known,
            u_pin,
            line_in_known,
            u_a: p.u_a,
            u_b: p.u_b,
            e_a: p.e_a,
            theta0: p.theta0,
            prismatic: kp,
            pin_numbers: xy(km, at_pin),
            ground_line: None,
        };
        if known.is_none() {
            rrp.ground_line = Some(rrp.line(&Frame::GROUND, &mut [f64::NAN, 1.0, 0.0]));
        }
        Some(rrp)
    }

    /// The slider's angle, cos, sin; a point of B's line and its unit direction.
    #[inline(always)]
    fn line(&self, k: &Frame, turn: &mut [f64; 3]) -> Line {
        let theta = if self.line_in_known { k.theta + self.theta0 } else { k.theta - self.theta0 };
        let (c, s) = crate::math::angle::turned(theta, turn);
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
        // a known side on the ground folded in: the link's pin fixed, the slide's line
        // formed at compile, both at rest
        match (self.link.known.is_some(), self.ground_line.is_none()) {
            (true, true) => self.solve_on::<true, true>(data, sign, derivatives),
            (true, false) => self.solve_on::<true, false>(data, sign, derivatives),
            (false, true) => self.solve_on::<false, true>(data, sign, derivatives),
            (false, false) => self.solve_on::<false, false>(data, sign, derivatives),
        }
        .map(|(solved, ..)| solved)
    }

    /// `solve` of positions only on a line fixed in the ground, with the guard
    /// (`guard::rrp`) of the step from the link's known pin's bound in `travel`, written
    /// there for the link and the slider where a later group reads them (`read`,
    /// `closed_form::guard_reads`): (closeness, residual), or the miss
    /// (`NearSingular` where the guard cannot show the step). Only where the slide's line
    /// is the ground's (`closed_form::guarded`).
    #[inline(always)]
    pub fn solve_guarded(
        &self,
        data: &mut Data,
        sign: f64,
        travel: &mut [Travel],
        read: bool,
    ) -> Result<(f64, f64), StepMiss> {
        if self.ground_line.is_none() {
            return Err(StepMiss::Failed);
        }
        // the known pin and its offset from the line as the step solved them
        let (solved, a, offset) = if self.link.known.is_some() {
            self.solve_on::<true, false>(data, sign, 0)
        } else {
            self.solve_on::<false, false>(data, sign, 0)
        }?;
        let la = self.link.known.map_or(0.0, |k| travel[k].pin(a));
        if !read {
            // the same test; the turn and the slider's path, which no later group reads, not formed
            return if guard::rrp_shown(self.link.length, offset, la) {
                Ok(solved)
            } else {
                Err(StepMiss::NearSingular)
            };
        }
        let turn = guard::rrp(self.link.length, offset, la).ok_or(StepMiss::NearSingular)?;
        travel[self.link.body] = Travel { r: a, len: la, turn };
        // the slider slides: B's path, no turn
        let b = data.frames[self.link.body].point(self.link.u_middle);
        travel[self.slider] = Travel { r: b, len: la + self.link.length * turn, turn: 0.0 };
        Ok(solved)
    }

    /// `solve` with `K`: whether the link's known side is a body, `S`: whether the slide's
    /// is (else its line is `ground_line`); with the link's known pin A and its offset
    /// from the line, for the guard.
    #[inline(always)]
    fn solve_on<const K: bool, const S: bool>(
        &self,
        data: &mut Data,
        sign: f64,
        derivatives: u8,
    ) -> Result<Solved, StepMiss> {
        let (k1, a) = self.link.outer_on::<K>(data);
        let k = if S { side(data, self.known) } else { Frame::GROUND };
        let (theta_s, cs, ss, p0, dir) = match self.ground_line {
            Some(line) if !S => line,
            _ => {
                let mut turn = data.frame_base[self.slider];
                let line = self.line(&k, &mut turn);
                data.frame_base[self.slider] = turn;
                line
            }
        };
        let r1 = self.link.length;
        let p = sub(a, p0);
        let s0 = dot(p, dir);
        let off = dir[0] * p[1] - dir[1] * p[0];
        let h2 = r1 * r1 - off * off;
        if h2.is_nan() || h2 < 0.0 {
            return Err(StepMiss::NoAssembly);
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
            let vk = if S { [k.rd[0] - k.thetad * rk[1], k.rd[1] + k.thetad * rk[0]] } else { [0.0; 2] };
            let va = self.link.outer_velocity::<K>(&k1);
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
                let qk = if S { body_qdd(data, self.known) } else { [0.0; 3] };
                let ak = if S { point_acc(&k, qk, sub(b, k.r)) } else { [0.0; 2] };
                let aa = self.link.outer_acceleration::<K>(data, &k1, a);
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
        Ok(((closeness, res1.max(res2)), a, off))
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

    /// Its numbers: the link's u_known, u_outer, u_middle in slots 0..6, the prismatic
    /// joint's u_a, u_b, e_a and theta0 in 6..13, the slider's u_pin in 13, 14.
    pub fn numbers(&self) -> Numbers {
        let mut out = Numbers::default();
        out.link(&self.link.numbers, 0);
        out.slots.extend((0..7).map(|i| (self.prismatic, i, 6 + i)));
        out.link(&self.pin_numbers, 13);
        out
    }

    /// dq/dp of both bodies (`super::tangents`), `solve` differentiated: the slider turns
    /// with the known body (dtheta_s = dtheta_k +- dtheta0); B on the link's circle,
    /// (B - A).(dB - dA) = r1 dr1 =: s1 - (B - A).dA, and on the line through p0 along v
    /// (`line`), n.(B - p0) = 0 with n = perp(v): n.dB = n.dp0 - perp(dv).(B - p0) =: s2;
    /// dB = M^-1 (s1, s2). The link's body from its two pins as in the RRR dyad, the slider
    /// from B: dR_s = dB - perp(A_s u_pin) dtheta_s - A_s du_pin.
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
        let l = &self.link;
        let (k1, a) = l.outer(data);
        let k = side(data, self.known);
        let (fr, fs) = (&data.frames[l.body], &data.frames[self.slider]);
        let b = fr.point(l.u_middle);
        // the line's point on the known side, the slider's (u_line, u_slide), and B's line
        let (u_line, u_slide) = if self.line_in_known { (self.u_a, self.u_b) } else { (self.u_b, self.u_a) };
        let (lk, off) = (k.rot(u_line), fs.rot(sub(self.u_pin, u_slide)));
        let p0 = [k.r[0] + lk[0] + off[0], k.r[1] + lk[1] + off[1]];
        // the line's direction turns with the known body, or with the slider
        let (fv, v) = if self.line_in_known { (&k, k.rot(self.e_a)) } else { (fs, fs.rot(self.e_a)) };
        let nv = perp(v);
        let ga = sub(b, a);
        let det = cross(ga, nv);
        // |cos| of the link against the line, `solve`'s closeness
        let closeness = det.abs() * l.inv_length / v[0].hypot(v[1]);
        if closeness.is_nan() || closeness < NEAR_SINGULAR {
            return Err(StepMiss::NearSingular);
        }
        // M^-1's columns u, w; the link's angle's coefficients
        let inv_det = 1.0 / det;
        let (mu, mw) = ([nv[1] * inv_det, -nv[0] * inv_det], [-ga[1] * inv_det, ga[0] * inv_det]);
        let inv_l2 = l.inv_length * l.inv_length;
        let cl = [-ga[1] * inv_l2, ga[0] * inv_l2];
        let (a1, a2) = (dot(cl, mu), dot(cl, mw));
        // dtheta = gl.dA + a1 e + a2 s2 + (own)
        let gl = [a1 * ga[0] - cl[0], a1 * ga[1] - cl[1]];
        let g = sub(b, p0);
        // s2's coefficients of the slider's turn (moving p0's offset) and the line's
        let (n_off, n_turn) = (dot(nv, perp(off)), cross(nv, g));
        let (ra, arm, arm_s) = (sub(a, k1.r), fr.rot(l.u_outer), fs.rot(self.u_pin));
        // the bodies' moves for the moves (`Inputs`): of A, of p0 along n and the slider's
        // turn; the link's r dr and its angle's own part
        let respond = |m: Inputs| {
            let dturn = if self.line_in_known { m.dthk } else { m.dths };
            let s1 = dot(ga, m.da) + m.e;
            let s2 = m.x + n_off * m.dths - n_turn * dturn;
            let db = [mu[0] * s1 + mw[0] * s2, mu[1] * s1 + mw[1] * s2];
            let dth = dot(gl, m.da) + a1 * m.e + a2 * s2 + m.t;
            let rod = [m.da[0] + arm[1] * dth, m.da[1] - arm[0] * dth, dth];
            (rod, [db[0] + arm_s[1] * m.dths, db[1] - arm_s[0] * m.dths, m.dths])
        };
        let (mut rod, slider, rest) = split(s, n, l.body, Some(self.slider));
        let mut slider = slider.expect("the dyad's slider");
        {
            // the known sides' moves, for every parameter (the slider turns with the known body)
            let ([x1, y1, t1], [xk, yk, tk]) = (rest.known(l.known, zeros), rest.known(self.known, zeros));
            let ([xr, yr, tr], [xs, ys, ts]) = (&mut rod, &mut slider);
            // rows cut to n: no bounds checks
            let (x1, y1, t1, xk, yk, tk) = (&x1[..n], &y1[..n], &t1[..n], &xk[..n], &yk[..n], &tk[..n]);
            let (xr, yr, tr, xs, ys, ts) =
                (&mut xr[..n], &mut yr[..n], &mut tr[..n], &mut xs[..n], &mut ys[..n], &mut ts[..n]);
            for j in 0..n {
                let da = [x1[j] - ra[1] * t1[j], y1[j] + ra[0] * t1[j]];
                let dp0 = [xk[j] - lk[1] * tk[j], yk[j] + lk[0] * tk[j]];
                let (dthk, x) = (tk[j], dot(nv, dp0));
                let (r, sl) = respond(Inputs { da, x, dthk, dths: dthk, ..Inputs::default() });
                (xr[j], yr[j], tr[j]) = (r[0], r[1], r[2]);
                (xs[j], ys[j], ts[j]) = (sl[0], sl[1], sl[2]);
            }
        }
        // each parameter's own moves of the pins, the line and the slide's turn
        let m = sub(l.u_middle, l.u_outer);
        let turn = if self.line_in_known { 1.0 } else { -1.0 };
        for entry in entries {
            let (slot, i) = (entry.slot, entry.slot % 2);
            let none = Inputs::default();
            // x or y of a pair starting at an even slot (u_pin, at 13, has its own); the
            // link's own moves: r dr (e), -cl.(A d(u_middle - u_outer)) (t), A du_outer (o)
            let (input, o, dpin) = match slot {
                0 | 1 => (Inputs { da: column(&k1, i), ..none }, [0.0; 2], [0.0; 2]),
                2 | 3 => {
                    let fc = column(fr, i);
                    (Inputs { e: -m[i], t: dot(cl, fc), ..none }, fc, [0.0; 2])
                }
                4 | 5 => (Inputs { e: m[i], t: -dot(cl, column(fr, i)), ..none }, [0.0; 2], [0.0; 2]),
                // u_a, u_b: the line's point in the known body, or the slider's
                6..=9 => {
                    let on_line = (slot < 8) == self.line_in_known;
                    let sign = if on_line { 1.0 } else { -1.0 };
                    (
                        Inputs { x: sign * dot(nv, column(if on_line { &k } else { fs }, i)), ..none },
                        [0.0; 2],
                        [0.0; 2],
                    )
                }
                10 | 11 => (Inputs { x: -cross(column(fv, i), g), ..none }, [0.0; 2], [0.0; 2]),
                12 => (Inputs { dths: turn, ..none }, [0.0; 2], [0.0; 2]),
                _ => {
                    let fc = column(fs, slot - 13);
                    (Inputs { x: dot(nv, fc), ..none }, [0.0; 2], fc)
                }
            };
            let (r, sl) = respond(input);
            add_move(&mut rod, entry.param, entry.w, [r[0] - o[0], r[1] - o[1], r[2]]);
            add_move(&mut slider, entry.param, entry.w, [sl[0] - dpin[0], sl[1] - dpin[1], sl[2]]);
        }
        Ok(())
    }
}

/// The inputs an RRP dyad's bodies answer: of A (da), of p0 along n and the line's own
/// (x), the known body's turn (dthk) and the slider's (dths), the link's r dr (e) and its
/// angle's own part (t).
#[derive(Debug, Clone, Copy, Default)]
struct Inputs {
    da: [f64; 2],
    x: f64,
    dthk: f64,
    dths: f64,
    e: f64,
    t: f64,
}
