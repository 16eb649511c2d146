//! Distance driver (a linear actuator): |r_b(u_b) - r_a(u_a)| - f(t) = 0.
//! The plain distance, not its square, so the row is a length like the joints' rows.

use crate::constraints::compile_context::{finite2, CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{dot, sub, Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::DriverDesc;
use crate::input::motion::MotionLaw;
use crate::math::jet::{self, pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct DistanceDriver {
    pub u_a: [f64; 2],
    pub u_b: [f64; 2],
    pub law: MotionLaw,
}

impl Constraint for DistanceDriver {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("u_a", &mut self.u_a));
        p.extend(crate::constraints::xy("u_b", &mut self.u_b));
        p.extend(self.law.params_mut());
        p
    }
    #[inline]
    fn phi_jet<const W: usize>(
        &self,
        a: &JetFrame<W>,
        b: &JetFrame<W>,
        _s: Jet<W>,
        t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    ) {
        let d = jet::sub(b.point(pair(p, 2)), a.point(pair(p, 0)));
        out[0] = jet::dot(d, d).sqrt() - self.law.jet(t, &p[4..]);
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Length]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, t: f64, out: &mut Rows) {
        let d = sub(b.point(self.u_b), a.point(self.u_a));
        let len = dot(d, d).sqrt();
        let e = [d[0] / len, d[1] / len];
        out.phi[0] = len - self.law.eval(t)[0];
        out.jac_a[0] = [-e[0], -e[1], -dot(e, a.rot_d(self.u_a))];
        out.jac_b[0] = [e[0], e[1], dot(e, b.rot_d(self.u_b))];
    }
    #[inline]
    fn nu(&self, t: f64, nu: &mut [f64; MAX_ROWS]) {
        nu[0] = self.law.eval(t)[1];
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, t: f64, g: &mut [f64; MAX_ROWS]) {
        // L'' = (dd.dd + d.ddd)/L - (d.dd)^2/L^3; gamma keeps the part without qdd, negated
        let d = sub(b.point(self.u_b), a.point(self.u_a));
        let dd = sub(b.point_velocity(self.u_b), a.point_velocity(self.u_a));
        let ddd = sub(b.point_centripetal(self.u_b), a.point_centripetal(self.u_a));
        let len = dot(d, d).sqrt();
        let d_dd = dot(d, dd);
        g[0] = -((dot(dd, dd) + dot(d, ddd)) / len - d_dd * d_dd / (len * len * len)) + self.law.eval(t)[2];
    }
    fn law(&self) -> Option<&MotionLaw> {
        Some(&self.law)
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for DistanceDriver {
    fn sample() -> Self {
        DistanceDriver { u_a: [0.1, 0.2], u_b: [0.3, -0.1], law: super::sample_law() }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for DistanceDriver {
    const FORMS: &'static [super::Form] = {
        use super::Input;
        use super::Role::*;
        &[super::Form {
            group: "drivers",
            type_: "distance",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("at_a", Point(&["body_a"])),
                ("body_b", Body),
                ("at_b", Point(&["body_b"])),
                ("law", Law(Input::Distance)),
            ],
        }]
    };
}

/// Compiles a distance-driver description: its two points in their bodies, apart.
pub(crate) fn compile(
    body_a: &str,
    at_a: [f64; 2],
    body_b: &str,
    at_b: [f64; 2],
    law: MotionLaw,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<DistanceDriver>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    if !finite2(at_a) || !finite2(at_b) {
        return Err(format!("points {at_a:?}, {at_b:?} are not finite"));
    }
    if (at_b[0] - at_a[0]).hypot(at_b[1] - at_a[1]) <= 1e-12 * cx.length_scale() {
        return Err("its two points coincide at the start; a distance driver needs them apart".into());
    }
    Ok(Compiled::new(DistanceDriver { u_a: cx.local(a, at_a), u_b: cx.local(b, at_b), law }, a, b))
}

impl FromDescription for DistanceDriver {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Driver(DriverDesc::Distance { body_a, at_a, body_b, at_b, .. }, law) = desc else {
            return None;
        };
        Some(compile(body_a, *at_a, body_b, *at_b, (*law).clone(), cx))
    }
}
