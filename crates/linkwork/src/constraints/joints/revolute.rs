//! Revolute (pin) joint: the point u_a of body a and u_b of body b coincide. 2 rows.

use crate::constraints::compile_context::{finite2, CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{pair, sub as jsub, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct Revolute {
    /// the pin in a's frame
    pub u_a: [f64; 2],
    /// the pin in b's frame
    pub u_b: [f64; 2],
}

/// Rows `row`, `row + 1`: r_b(u_b) - r_a(u_a) = 0, shared with the weld.
#[inline(always)]
pub(crate) fn coincidence(u_a: [f64; 2], u_b: [f64; 2], a: &Frame, b: &Frame, row: usize, out: &mut Rows) {
    let pa = a.point(u_a);
    let pb = b.point(u_b);
    let ba = a.rot_d(u_a);
    let bb = b.rot_d(u_b);
    for k in 0..2 {
        out.phi[row + k] = pb[k] - pa[k];
        out.jac_a[row + k] = [0.0, 0.0, -ba[k]];
        out.jac_a[row + k][k] = -1.0;
        out.jac_b[row + k] = [0.0, 0.0, bb[k]];
        out.jac_b[row + k][k] = 1.0;
    }
}

/// gamma of the coincidence rows: A_b u_b thd_b^2 - A_a u_a thd_a^2.
#[inline(always)]
pub(crate) fn coincidence_gamma(
    u_a: [f64; 2],
    u_b: [f64; 2],
    a: &Frame,
    b: &Frame,
    row: usize,
    g: &mut [f64; MAX_ROWS],
) {
    let ca = a.point_centripetal(u_a);
    let cb = b.point_centripetal(u_b);
    g[row] = ca[0] - cb[0];
    g[row + 1] = ca[1] - cb[1];
}

impl Constraint for Revolute {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("u_a", &mut self.u_a));
        p.extend(crate::constraints::xy("u_b", &mut self.u_b));
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
        let d = jsub(b.point(pair(p, 2)), a.point(pair(p, 0)));
        out[0] = d[0];
        out[1] = d[1];
    }
    fn n_rows(&self) -> usize {
        2
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Length, RowKind::Length]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, out: &mut Rows) {
        coincidence(self.u_a, self.u_b, a, b, 0, out);
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        coincidence_gamma(self.u_a, self.u_b, a, b, 0, g);
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for Revolute {
    fn sample() -> Self {
        Revolute { u_a: [0.3, -0.2], u_b: [-0.15, 0.4] }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for Revolute {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "revolute",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("at", Point(&["body_a", "body_b"])),
                ("pin_a", LocalPoint("body_a")),
                ("pin_b", LocalPoint("body_b")),
            ],
        }]
    };
}

/// Compiles a revolute description: each side's pin in its frame, given (checked against
/// the drawing's point where both are) or the drawing's point there.
pub(crate) fn compile(
    name: &str,
    body_a: &str,
    body_b: &str,
    at: Option<[f64; 2]>,
    pin_a: Option<[f64; 2]>,
    pin_b: Option<[f64; 2]>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<Revolute>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    if let Some(p) = [at, pin_a, pin_b].into_iter().flatten().find(|p| !finite2(*p)) {
        return Err(format!("position {p:?} is not finite"));
    }
    if at.is_none() && (pin_a.is_none() || pin_b.is_none()) {
        return Err("needs its position `at`, or its pin in each body (pin_a and pin_b)".into());
    }
    let u_a = cx.pin(name, a, "pin_a", pin_a, at, None);
    let u_b = cx.pin(name, b, "pin_b", pin_b, at, None);
    Ok(Compiled::new(Revolute { u_a, u_b }, a, b))
}

impl FromDescription for Revolute {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::Revolute { name, body_a, body_b, at, pin_a, pin_b }) = desc else {
            return None;
        };
        Some(compile(name, body_a, body_b, *at, *pin_a, *pin_b, cx))
    }
}
