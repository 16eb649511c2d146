//! Prismatic (translational) joint: body b slides on body a along an axis fixed in a.
//! 2 rows: no relative rotation; the point u_b of b stays on the line through u_a of a
//! along the axis e_a (n . d = 0, n the axis normal, d = r_b(u_b) - r_a(u_a)).

use crate::constraints::compile_context::Slide;
use crate::constraints::compile_context::{
    finite2, unit, world, CompileContext, Compiled, Desc, FromDescription,
};
use crate::constraints::{dot, perp, sub, Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{self, pair, Jet, JetFrame, Vec2};

#[derive(Debug, Clone, PartialEq)]
pub struct Prismatic {
    /// a point of the line in a's frame
    pub u_a: [f64; 2],
    /// the sliding point in b's frame (coincides with u_a at the start)
    pub u_b: [f64; 2],
    /// unit axis in a's frame
    pub e_a: [f64; 2],
    /// theta_b - theta_a, constant
    pub theta0: f64,
    /// the slide's range [min, max] from the start, if given (reported by a simulation)
    pub travel: Option<[f64; 2]>,
}

/// One row v . d with v = A_a v_a a body-fixed direction of a: the offset across the
/// axis (v = normal) for the joint, the slide along it (v = axis) for its driver.
#[inline(always)]
pub(crate) fn line_row(
    v_a: [f64; 2],
    u_a: [f64; 2],
    u_b: [f64; 2],
    a: &Frame,
    b: &Frame,
    row: usize,
    out: &mut Rows,
) {
    let v = a.rot(v_a);
    let d = sub(b.point(u_b), a.point(u_a));
    out.phi[row] = dot(v, d);
    // d/dtheta_a (v . d) = (B_a v_a) . d - v . (B_a u_a)
    out.jac_a[row] = [-v[0], -v[1], dot(perp(v), d) - dot(v, a.rot_d(u_a))];
    out.jac_b[row] = [v[0], v[1], dot(v, b.rot_d(u_b))];
}

/// gamma of `line_row`: thd_a^2 v.d - 2 thd_a (B_a v_a).dd + v.(A_b u_b thd_b^2 - A_a u_a thd_a^2).
#[inline(always)]
pub(crate) fn line_gamma(v_a: [f64; 2], u_a: [f64; 2], u_b: [f64; 2], a: &Frame, b: &Frame) -> f64 {
    let v = a.rot(v_a);
    let d = sub(b.point(u_b), a.point(u_a));
    let dd = sub(b.point_velocity(u_b), a.point_velocity(u_a));
    let centripetal = sub(a.point_centripetal(u_a), b.point_centripetal(u_b));
    a.thetad * a.thetad * dot(v, d) - 2.0 * a.thetad * dot(perp(v), dd) + dot(v, centripetal)
}

/// `line_row`'s value on jets: (A_a v_a) . (r_b(u_b) - r_a(u_a)).
#[inline(always)]
pub(crate) fn line_jet<const W: usize>(
    v_a: Vec2<W>,
    u_a: Vec2<W>,
    u_b: Vec2<W>,
    a: &JetFrame<W>,
    b: &JetFrame<W>,
) -> Jet<W> {
    jet::dot(a.rot(v_a), jet::sub(b.point(u_b), a.point(u_a)))
}

impl Constraint for Prismatic {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("u_a", &mut self.u_a));
        p.extend(crate::constraints::xy("u_b", &mut self.u_b));
        p.extend(crate::constraints::xy("e_a", &mut self.e_a));
        p.push(("theta0".into(), &mut self.theta0));
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
        out[0] = b.theta - a.theta - p[6];
        out[1] = line_jet(jet::perp(pair(p, 4)), pair(p, 0), pair(p, 2), a, b);
    }
    fn n_rows(&self) -> usize {
        2
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Angle, RowKind::Length]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, out: &mut Rows) {
        out.phi[0] = b.theta - a.theta - self.theta0;
        out.jac_a[0] = [0.0, 0.0, -1.0];
        out.jac_b[0] = [0.0, 0.0, 1.0];
        line_row(perp(self.e_a), self.u_a, self.u_b, a, b, 1, out);
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        g[0] = 0.0;
        g[1] = line_gamma(perp(self.e_a), self.u_a, self.u_b, a, b);
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for Prismatic {
    fn sample() -> Self {
        let (s, c) = 0.4f64.sin_cos();
        Prismatic { u_a: [0.2, 0.05], u_b: [-0.1, 0.3], e_a: [c, s], theta0: -0.3, travel: None }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for Prismatic {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "prismatic",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("at", Point(&["body_a", "body_b"])),
                ("axis", Slide("body_a")),
                ("pin_a", LocalPoint("body_a")),
                ("pin_b", LocalPoint("body_b")),
                ("axis_a", LocalDirection("body_a")),
                ("angle", Angle),
                ("travel", Interval),
            ],
        }]
    };
}

/// Compiles a prismatic description: the axis in a's frame (given there, or the world one
/// turned into a's), each side's pin as for a revolute but missing only across the line.
#[allow(clippy::too_many_arguments)]
pub(crate) fn compile(
    name: &str,
    body_a: &str,
    body_b: &str,
    at: Option<[f64; 2]>,
    axis: Option<[f64; 2]>,
    pin_a: Option<[f64; 2]>,
    pin_b: Option<[f64; 2]>,
    axis_a: Option<[f64; 2]>,
    angle: Option<f64>,
    travel: Option<[f64; 2]>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<Prismatic>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    let points = [at, axis, pin_a, pin_b, axis_a];
    if let Some(p) = points.into_iter().flatten().find(|p| !finite2(*p)) {
        return Err(format!("point or axis {p:?} is not finite"));
    }
    if at.is_none() && (pin_a.is_none() || pin_b.is_none()) {
        return Err("needs its point `at` (world), or its pin in each body (pin_a and pin_b)".into());
    }
    let a_turn = Some([0.0, 0.0, cx.theta(a)]);
    if axis_a.or(axis).is_some_and(|e| e[0].hypot(e[1]) == 0.0) {
        return Err("has a zero-length axis; give the sliding direction".into());
    }
    let e = match (axis_a, axis) {
        (Some(e), _) => unit("axis_a", e)?,
        (None, Some(e)) => cx.local_dir(a, unit("axis", e)?),
        (None, None) => {
            return Err("needs its sliding direction: `axis` (world) or `axis_a` (in body_a's frame)".into())
        }
    };
    // a pin need only be on the slide line: the miss is across it
    let normal = Some(world(a_turn, [-e[1], e[0]]));
    let u_a = cx.pin(name, a, "pin_a", pin_a, at, normal);
    let u_b = cx.pin(name, b, "pin_b", pin_b, at, normal);
    let lengths_first = pin_a.is_some() || pin_b.is_some();
    let drawn_angle = cx.theta(b) - cx.theta(a);
    let theta0 = match angle {
        Some(v) if v.is_finite() => v,
        Some(v) => return Err(format!("angle {v} is not finite")),
        None if lengths_first => 0.0,
        None => drawn_angle,
    };
    if let Some([lo, hi]) = travel {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(format!("travel [{lo}, {hi}] must be finite with min < max"));
        }
    }
    Ok(Compiled::new(Prismatic { u_a, u_b, e_a: e, theta0, travel }, a, b))
}

impl FromDescription for Prismatic {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::Prismatic {
            name,
            body_a,
            body_b,
            at,
            axis,
            pin_a,
            pin_b,
            axis_a,
            angle,
            travel,
        }) = desc
        else {
            return None;
        };
        Some(compile(name, body_a, body_b, *at, *axis, *pin_a, *pin_b, *axis_a, *angle, *travel, cx))
    }
    fn slide(&self) -> Option<Slide> {
        Some(Slide { u_a: self.u_a, u_b: self.u_b, e_a: self.e_a })
    }
}
