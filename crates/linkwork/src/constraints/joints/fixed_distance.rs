//! Distance joint (revolute-revolute composite): a massless coupler of fixed length l
//! between the point u_a of body a and u_b of body b. 1 row, a length:
//! (d . d - l^2) / (2 l) = 0 with d = r_b(u_b) - r_a(u_a). The squared form stays smooth
//! when d passes near zero; dividing by 2 l makes the row read as a length near the
//! solution (it equals |d| - l to first order).

use crate::constraints::compile_context::{
    finite2, positive_or, CompileContext, Compiled, Desc, FromDescription,
};
use crate::constraints::{dot, sub, Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{self, pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct FixedDistance {
    /// the coupler's end on a, in a's frame
    pub u_a: [f64; 2],
    /// the coupler's end on b, in b's frame
    pub u_b: [f64; 2],
    /// the coupler's length, > 0
    pub length: f64,
}

impl Constraint for FixedDistance {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("u_a", &mut self.u_a));
        p.extend(crate::constraints::xy("u_b", &mut self.u_b));
        p.push(("length".into(), &mut self.length));
        p
    }
    #[inline]
    fn phi_jet<const W: usize>(
        &self,
        a: &JetFrame<W>,
        b: &JetFrame<W>,
        _s: Jet<W>,
        _t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    ) {
        let d = jet::sub(b.point(pair(p, 2)), a.point(pair(p, 0)));
        let l = p[4];
        out[0] = (jet::dot(d, d) - l * l) * (l * 2.0).recip();
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Length]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, out: &mut Rows) {
        let d = sub(b.point(self.u_b), a.point(self.u_a));
        let l = self.length;
        out.phi[0] = (dot(d, d) - l * l) / (2.0 * l);
        // d phi / dq = d . (dd / dq) / l
        let e = [d[0] / l, d[1] / l];
        out.jac_a[0] = [-e[0], -e[1], -dot(e, a.rot_d(self.u_a))];
        out.jac_b[0] = [e[0], e[1], dot(e, b.rot_d(self.u_b))];
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        // phi'' = (dd . dd + d . ddd) / l; gamma keeps the part without qdd, negated
        let d = sub(b.point(self.u_b), a.point(self.u_a));
        let dd = sub(b.point_velocity(self.u_b), a.point_velocity(self.u_a));
        let ddd = sub(b.point_centripetal(self.u_b), a.point_centripetal(self.u_a));
        g[0] = -(dot(dd, dd) + dot(d, ddd)) / self.length;
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for FixedDistance {
    fn sample() -> Self {
        FixedDistance { u_a: [0.2, -0.1], u_b: [-0.05, 0.3], length: 0.45 }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for FixedDistance {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "distance",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("at_a", Point(&["body_a"])),
                ("body_b", Body),
                ("at_b", Point(&["body_b"])),
                ("length", Length),
            ],
        }]
    };
}

/// Compiles a distance-joint description: its two points in their bodies, its length
/// given or drawn.
pub(crate) fn compile(
    body_a: &str,
    at_a: [f64; 2],
    body_b: &str,
    at_b: [f64; 2],
    length: Option<f64>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<FixedDistance>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    if !finite2(at_a) || !finite2(at_b) {
        return Err(format!("points {at_a:?}, {at_b:?} are not finite"));
    }
    let drawn = (at_b[0] - at_a[0]).hypot(at_b[1] - at_a[1]);
    if drawn <= 1e-12 * cx.length_scale() {
        return Err("its two points coincide at the start; a distance joint needs them apart".into());
    }
    let length = positive_or("length", length, drawn)?;
    Ok(Compiled::new(FixedDistance { u_a: cx.local(a, at_a), u_b: cx.local(b, at_b), length }, a, b))
}

impl FromDescription for FixedDistance {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::Distance { body_a, at_a, body_b, at_b, length, .. }) = desc else {
            return None;
        };
        Some(compile(body_a, *at_a, body_b, *at_b, *length, cx))
    }
}
