//! Point-on-line joint: the pin u_a of body a stays in a straight slot of body b, the
//! line through u_b along the unit axis e_b (both fixed in b), at a constant signed
//! offset from it. 1 row, a length: n . (r_a(u_a) - r_b(u_b)) - offset = 0, with
//! n = A_b perp(e_b) the slot's normal (the axis turned by +90 degrees).
//!
//! With offset 0 it is a pin in a slot; with an offset it is the revolute-prismatic
//! composite: a slider block pinned to a at u_a, sliding along a line of b that does not
//! pass through the pin. The rotation of a stays free either way.

use super::prismatic::{line_gamma, line_row};
use crate::constraints::compile_context::{finite2, unit, CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{perp, Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{self, pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct PointOnLine {
    /// the pin in a's frame
    pub u_a: [f64; 2],
    /// a point of the line in b's frame
    pub u_b: [f64; 2],
    /// unit axis of the line in b's frame
    pub e_b: [f64; 2],
    /// signed distance of the pin from the line, along perp(axis)
    pub offset: f64,
}

impl Constraint for PointOnLine {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("u_a", &mut self.u_a));
        p.extend(crate::constraints::xy("u_b", &mut self.u_b));
        p.extend(crate::constraints::xy("e_b", &mut self.e_b));
        p.push(("offset".into(), &mut self.offset));
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
        let line = super::prismatic::line_jet(jet::perp(pair(p, 4)), pair(p, 2), pair(p, 0), b, a);
        out[0] = line - p[6];
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Length]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, out: &mut Rows) {
        // the prismatic joint's row with the roles swapped: the line is fixed in b
        let mut rows = Rows::default();
        line_row(perp(self.e_b), self.u_b, self.u_a, b, a, 0, &mut rows);
        out.phi[0] = rows.phi[0] - self.offset;
        out.jac_a[0] = rows.jac_b[0];
        out.jac_b[0] = rows.jac_a[0];
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        g[0] = line_gamma(perp(self.e_b), self.u_b, self.u_a, b, a);
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for PointOnLine {
    fn sample() -> Self {
        let (s, c) = 0.7f64.sin_cos();
        PointOnLine { u_a: [0.25, -0.1], u_b: [-0.2, 0.15], e_b: [c, s], offset: 0.05 }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for PointOnLine {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "point_on_line",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("at", Point(&["body_a"])),
                ("axis", Slide("body_b")),
                ("through", Point(&["body_b"])),
                ("offset", Length),
            ],
        }]
    };
}

/// Compiles a point-on-line description: the point in a, the line (through `through`, or
/// the point) in b, the offset given or drawn.
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    at: [f64; 2],
    axis: [f64; 2],
    through: Option<[f64; 2]>,
    offset: Option<f64>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<PointOnLine>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    let q = through.unwrap_or(at);
    if !finite2(at) || !finite2(q) {
        return Err(format!("point {at:?} or line point {q:?} is not finite"));
    }
    let e = unit("axis", axis)?;
    let drawn = -e[1] * (at[0] - q[0]) + e[0] * (at[1] - q[1]);
    let offset = match offset {
        None => drawn,
        Some(o) if o.is_finite() => o,
        Some(o) => return Err(format!("offset {o} is not finite")),
    };
    let joint = PointOnLine { u_a: cx.local(a, at), u_b: cx.local(b, q), e_b: cx.local_dir(b, e), offset };
    Ok(Compiled::new(joint, a, b))
}

impl FromDescription for PointOnLine {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::PointOnLine { body_a, body_b, at, axis, through, offset, .. }) = desc
        else {
            return None;
        };
        Some(compile(body_a, body_b, *at, *axis, *through, *offset, cx))
    }
}
