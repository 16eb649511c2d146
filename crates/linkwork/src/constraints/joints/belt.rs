//! Belt or chain between two pulleys (bodies a and b, pitch radii r_a, r_b): the gear
//! pair's row with the other sign. An open belt turns both pulleys the same way
//! (r_a dtheta_a = r_b dtheta_b), a crossed belt opposite ways; with a carrier (an arm
//! holding both pulley centres) the turns are relative to it. 1 row, an angle; see
//! `gear` for the row and its scaling.

use super::gear::Gear;
use super::gear::{carrier_of, radii};
use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct Belt(pub Gear);

impl Constraint for Belt {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        self.0.params_mut()
    }
    #[inline]
    fn phi_jet<const W: usize>(
        &self,
        a: &JetFrame<W>,
        b: &JetFrame<W>,
        s: Jet<W>,
        t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    ) {
        self.0.phi_jet(a, b, s, t, p, out);
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        self.0.row_kinds()
    }
    fn has_extra(&self) -> bool {
        self.0.has_extra()
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, x: &Extra, t: f64, out: &mut Rows) {
        self.0.position(a, b, x, t, out);
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, x: &Extra, t: f64, g: &mut [f64; MAX_ROWS]) {
        self.0.gamma(a, b, x, t, g);
    }
}

impl Sample for Belt {
    fn sample() -> Self {
        let (k_a, k_b) = Gear::coefficients(0.09, 0.04, true);
        Belt(Gear { k_a, k_b, value: -0.2, carrier: true, mesh: None })
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for Belt {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "belt",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("radius_a", Pitch("body_a")),
                ("radius_b", Pitch("body_b")),
                ("ratio", Ratio),
                ("crossed", Flag),
                ("carrier", Body),
            ],
        }]
    };
}

/// Compiles a belt description: the pulleys' radii or ratio, open or crossed, on a carrier.
#[allow(clippy::too_many_arguments)]
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    radius_a: Option<f64>,
    radius_b: Option<f64>,
    ratio: Option<f64>,
    crossed: bool,
    carrier: &Option<String>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<Belt>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    let (r_a, r_b) = radii(radius_a, radius_b, ratio)?;
    let (k_a, k_b) = Gear::coefficients(r_a, r_b, !crossed);
    let (column, theta_c) = carrier_of(&*cx, carrier, a, b)?;
    let value = k_a * (cx.theta(a) - theta_c) + k_b * (cx.theta(b) - theta_c);
    let belt = Belt(Gear { k_a, k_b, value, carrier: column.is_some(), mesh: None });
    Ok(Compiled { joint: belt, a, b, borrowed: column })
}

impl FromDescription for Belt {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::Belt {
            body_a, body_b, radius_a, radius_b, ratio, crossed, carrier, ..
        }) = desc
        else {
            return None;
        };
        Some(compile(body_a, body_b, *radius_a, *radius_b, *ratio, *crossed, carrier, cx))
    }
}
