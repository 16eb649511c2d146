//! Coordinate driver: x (axis 0) or y (axis 1) of the point u of body b, minus f(t).

use crate::constraints::compile_context::{finite2, CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::DriverDesc;
use crate::input::motion::MotionLaw;
use crate::math::jet::{pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateDriver {
    pub u: [f64; 2],
    /// 0 for x, 1 for y
    pub axis: usize,
    pub law: MotionLaw,
}

impl Constraint for CoordinateDriver {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p: Vec<(String, &mut f64)> = crate::constraints::xy("u", &mut self.u).into_iter().collect();
        p.extend(self.law.params_mut());
        p
    }
    #[inline]
    fn phi_jet<const W: usize>(
        &self,
        _a: &JetFrame<W>,
        b: &JetFrame<W>,
        _s: Jet<W>,
        t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    ) {
        out[0] = b.point(pair(p, 0))[self.axis] - self.law.jet(t, &p[2..]);
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Length]
    }
    #[inline]
    fn position(&self, _a: &Frame, b: &Frame, _x: &Extra, t: f64, out: &mut Rows) {
        let k = self.axis;
        out.phi[0] = b.point(self.u)[k] - self.law.eval(t)[0];
        out.jac_a[0] = [0.0; 3];
        out.jac_b[0] = [0.0, 0.0, b.rot_d(self.u)[k]];
        out.jac_b[0][k] = 1.0;
    }
    #[inline]
    fn nu(&self, t: f64, nu: &mut [f64; MAX_ROWS]) {
        nu[0] = self.law.eval(t)[1];
    }
    #[inline]
    fn gamma(&self, _a: &Frame, b: &Frame, _x: &Extra, t: f64, g: &mut [f64; MAX_ROWS]) {
        g[0] = -b.point_centripetal(self.u)[self.axis] + self.law.eval(t)[2];
    }
    fn law(&self) -> Option<&MotionLaw> {
        Some(&self.law)
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u
    }
}

impl Sample for CoordinateDriver {
    fn sample() -> Self {
        CoordinateDriver { u: [0.2, -0.35], axis: 1, law: super::sample_law() }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for CoordinateDriver {
    const FORMS: &'static [super::Form] = {
        use super::Input;
        use super::Role::*;
        &[super::Form {
            group: "drivers",
            type_: "coordinate",
            fields: &[
                ("name", Name),
                ("body", Body),
                ("at", Point(&["body"])),
                ("axis", Choice(&["x", "y"])),
                ("law", Law(Input::Coordinate)),
            ],
        }]
    };
}

/// Compiles a coordinate-driver description: the point of the body driven, its axis.
pub(crate) fn compile(
    body: &str,
    at: [f64; 2],
    axis: &str,
    law: MotionLaw,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<CoordinateDriver>, String> {
    let b = cx.find(body)?;
    if b.is_none() {
        return Err("drives a point of the ground, which cannot move".into());
    }
    if !finite2(at) {
        return Err(format!("point {at:?} is not finite"));
    }
    let axis = match axis {
        "x" => 0,
        "y" => 1,
        other => return Err(format!("axis must be \"x\" or \"y\", not {other:?}")),
    };
    Ok(Compiled::new(CoordinateDriver { u: cx.local(b, at), axis, law }, None, b))
}

impl FromDescription for CoordinateDriver {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Driver(DriverDesc::Coordinate { body, at, axis, .. }, law) = desc else {
            return None;
        };
        Some(compile(body, *at, axis, (*law).clone(), cx))
    }
}
