//! Linear coupling between the coordinates of at most two bodies (either may be the
//! ground, whose coordinates are constant): c_a . q_a + c_b . q_b - value = 0, with
//! q_i = (x_i, y_i, theta_i) and the value the drawing's unless given. 1 row: a length
//! if it involves any x or y, an angle otherwise. Gear-like couplings between angles,
//! a rack's slide against a pinion's turn, a pantograph's scaled motion.

use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::Coefficients;
use crate::input::description::JointDesc;
use crate::math::jet::{Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct LinearCoupling {
    /// coefficients of (x_a, y_a, theta_a)
    pub c_a: [f64; 3],
    /// coefficients of (x_b, y_b, theta_b)
    pub c_b: [f64; 3],
    pub value: f64,
}

impl LinearCoupling {
    /// Whether the row involves a length coordinate (x or y).
    pub fn is_length(&self) -> bool {
        self.c_a[..2].iter().chain(&self.c_b[..2]).any(|c| *c != 0.0)
    }
}

#[inline(always)]
fn q(f: &Frame) -> [f64; 3] {
    [f.r[0], f.r[1], f.theta]
}

impl Constraint for LinearCoupling {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let [a0, a1, a2] = &mut self.c_a;
        let [b0, b1, b2] = &mut self.c_b;
        vec![
            ("c_a.x".into(), a0),
            ("c_a.y".into(), a1),
            ("c_a.theta".into(), a2),
            ("c_b.x".into(), b0),
            ("c_b.y".into(), b1),
            ("c_b.theta".into(), b2),
            ("value".into(), &mut self.value),
        ]
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
        let (qa, qb) = ([a.r[0], a.r[1], a.theta], [b.r[0], b.r[1], b.theta]);
        let mut sum = Jet::ZERO - p[6];
        for k in 0..3 {
            sum = sum + p[k] * qa[k] + p[3 + k] * qb[k];
        }
        out[0] = sum;
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        if self.is_length() {
            &[RowKind::Length]
        } else {
            &[RowKind::Angle]
        }
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, out: &mut Rows) {
        let (qa, qb) = (q(a), q(b));
        out.phi[0] = (0..3).map(|k| self.c_a[k] * qa[k] + self.c_b[k] * qb[k]).sum::<f64>() - self.value;
        out.jac_a[0] = self.c_a;
        out.jac_b[0] = self.c_b;
    }
    #[inline]
    fn gamma(&self, _a: &Frame, _b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        // linear in q
        g[0] = 0.0;
    }
}

impl Sample for LinearCoupling {
    fn sample() -> Self {
        LinearCoupling { c_a: [0.5, -1.5, 0.25], c_b: [2.0, 0.0, -0.7], value: 0.1 }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for LinearCoupling {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "linear_coupling",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("coefficients_a", Coefficients("body_a")),
                ("coefficients_b", Coefficients("body_b")),
                ("value", Number),
            ],
        }]
    };
}

/// Compiles a linear-coupling description: the coefficients checked, the value given or
/// drawn.
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    coefficients_a: &Coefficients,
    coefficients_b: &Coefficients,
    value: Option<f64>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<LinearCoupling>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    let c_a = [coefficients_a.x, coefficients_a.y, coefficients_a.theta];
    let c_b = [coefficients_b.x, coefficients_b.y, coefficients_b.theta];
    if !c_a.iter().chain(&c_b).all(|c| c.is_finite()) {
        return Err(format!("coefficients {c_a:?}, {c_b:?} are not finite"));
    }
    for (side, body, c) in [("a", a, c_a), ("b", b, c_b)] {
        if body.is_none() && c.iter().any(|c| *c != 0.0) {
            return Err(format!("has coefficients_{side} on the ground, whose coordinates are fixed"));
        }
    }
    if c_a.iter().chain(&c_b).all(|c| *c == 0.0) {
        return Err("has no non-zero coefficient".into());
    }
    let (q_a, q_b) = (cx.pose(a).unwrap_or([0.0; 3]), cx.pose(b).unwrap_or([0.0; 3]));
    let value = match value {
        None => (0..3).map(|k| c_a[k] * q_a[k] + c_b[k] * q_b[k]).sum(),
        Some(v) if v.is_finite() => v,
        Some(v) => return Err(format!("value {v} is not finite")),
    };
    Ok(Compiled::new(LinearCoupling { c_a, c_b, value }, a, b))
}

impl FromDescription for LinearCoupling {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::LinearCoupling {
            body_a,
            body_b,
            coefficients_a,
            coefficients_b,
            value,
            ..
        }) = desc
        else {
            return None;
        };
        Some(compile(body_a, body_b, coefficients_a, coefficients_b, *value, cx))
    }
}
