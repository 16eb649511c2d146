//! Rack and pinion: a pinion (body a) of pitch radius r meshes with a straight rack
//! (body b, or the ground). 1 row, a length: the pinion centre's place along the rack
//! and the pinion's turn relative to the rack stay in step,
//! e . (r_a(u_a) - r_b(u_b)) + r (theta_a - theta_b - delta0) = 0,
//! with e = A_b e_b the rack's unit axis (fixed in b), u_a the pinion centre, u_b the
//! rack point at the centre in the drawing and delta0 the drawing's theta_a - theta_b.
//!
//! Sign: a counter-clockwise turn dtheta of the pinion (relative to the rack) moves the
//! rack by r dtheta along +e relative to the pinion centre; the rack's pitch line lies on
//! the side of -perp(e) from the centre (below it for e = +x). The row keeps the two in
//! step along the rack only; what holds the centre at distance r from the pitch line is
//! the mechanism's other joints (the pinion's pivot, the rack's guide).

use super::prismatic::{line_gamma, line_row};
use crate::constraints::compile_context::{
    finite2, positive_or, unit, CompileContext, Compiled, Desc, FromDescription,
};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct RackPinion {
    /// the pinion centre in a's frame
    pub u_a: [f64; 2],
    /// the rack point at the pinion centre in the drawing, in b's frame
    pub u_b: [f64; 2],
    /// unit axis of the rack in b's frame
    pub e_b: [f64; 2],
    /// pitch radius of the pinion, > 0
    pub radius: f64,
    /// theta_a - theta_b in the drawing
    pub delta0: f64,
}

impl Constraint for RackPinion {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("u_a", &mut self.u_a));
        p.extend(crate::constraints::xy("u_b", &mut self.u_b));
        p.extend(crate::constraints::xy("e_b", &mut self.e_b));
        p.push(("radius".into(), &mut self.radius));
        p.push(("delta0".into(), &mut self.delta0));
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
        let line = super::prismatic::line_jet(pair(p, 4), pair(p, 2), pair(p, 0), b, a);
        out[0] = line + p[6] * (a.theta - b.theta - p[7]);
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Length]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, out: &mut Rows) {
        // e . (r_a - r_b) is the prismatic row with the axis fixed in b
        let mut rows = Rows::default();
        line_row(self.e_b, self.u_b, self.u_a, b, a, 0, &mut rows);
        let r = self.radius;
        out.phi[0] = rows.phi[0] + r * (a.theta - b.theta - self.delta0);
        out.jac_a[0] = rows.jac_b[0];
        out.jac_a[0][2] += r;
        out.jac_b[0] = rows.jac_a[0];
        out.jac_b[0][2] -= r;
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        // the angle terms are linear in q: they add nothing to gamma
        g[0] = line_gamma(self.e_b, self.u_b, self.u_a, b, a);
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for RackPinion {
    fn sample() -> Self {
        let (s, c) = (-0.4f64).sin_cos();
        RackPinion { u_a: [0.1, 0.05], u_b: [0.3, -0.2], e_b: [c, s], radius: 0.08, delta0: 0.6 }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for RackPinion {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "rack_pinion",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("radius", Pitch("body_a")),
                ("axis", Direction("body_b")),
                ("centre", Point(&["body_a"])),
            ],
        }]
    };
}

/// Compiles a rack-and-pinion description: the pinion's centre in both bodies, the rack's
/// direction in b.
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    radius: f64,
    axis: [f64; 2],
    centre: Option<[f64; 2]>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<RackPinion>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    if a.is_none() {
        return Err("its pinion (body_a) is the ground, which cannot turn; the rack may be".into());
    }
    let radius = positive_or("radius", Some(radius), 0.0)?;
    let c = centre.unwrap_or(cx.origin(a));
    if !finite2(c) {
        return Err(format!("centre {c:?} is not finite"));
    }
    let e = unit("axis", axis)?;
    let joint = RackPinion {
        u_a: cx.local(a, c),
        u_b: cx.local(b, c),
        e_b: cx.local_dir(b, e),
        radius,
        delta0: cx.theta(a) - cx.theta(b),
    };
    Ok(Compiled::new(joint, a, b))
}

impl FromDescription for RackPinion {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::RackPinion { body_a, body_b, radius, axis, centre, .. }) = desc else {
            return None;
        };
        Some(compile(body_a, body_b, *radius, *axis, *centre, cx))
    }
}
