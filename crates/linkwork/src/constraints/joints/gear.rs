//! Spur gear pair between bodies a and b, rolling without slipping at the pitch circles
//! (radii r_a, r_b). 1 row, an angle:
//! k_a (theta_a - theta_c) + k_b (theta_b - theta_c) - value = 0,
//! where theta_c is the carrier's angle (the arm of a planetary train that holds both
//! centres; a coordinate borrowed from a third body) or 0 without a carrier (both centres
//! fixed in the ground), and value is the drawing's (the row is 0 at the start).
//!
//! k_a = r_a / r_max and k_b = +-r_b / r_max, r_max = max(r_a, r_b), so the row is
//! dimensionless with coefficients of at most 1. Signs: external gears turn opposite ways
//! (k_b = +r_b / r_max: r_a dtheta_a = -r_b dtheta_b); an internal gear and its pinion
//! turn the same way (k_b = -r_b / r_max). Relative to the carrier, the speed of b is
//! -+ (r_a / r_b) times that of a. Belts and chains (`belt`) use the same row.
//!
//! A gear pair on a carrier measures the rolling against the line of centres, phi, the
//! angle of c_b - c_a, rather than against the carrier's angle (the carrier holds the
//! centres, so the two turn together and the kinematics are the same): then the row's
//! multiplier is the tangential contact force, acting on the two gears' centres, and the
//! reactions in the pins are those of a real mesh rather than a torque on the carrier.
//! The carrier's angle only picks the turn: phi = theta_c + delta + wrap(atan2(d) -
//! theta_c - delta), locally independent of theta_c (d phi / d theta_c = 0).

use std::f64::consts::PI;

use crate::constraints::compile_context::{
    finite2, positive_or, CompileContext, Compiled, Desc, FromDescription,
};
use crate::constraints::{perp, sub, Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{self, pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct Gear {
    /// coefficient of theta_a - theta_c
    pub k_a: f64,
    /// coefficient of theta_b - theta_c
    pub k_b: f64,
    /// the row's constant, from the drawing
    pub value: f64,
    /// whether the row is relative to a carrier (the extra coordinate is its angle)
    pub carrier: bool,
    /// a gear mesh on a carrier: the rolling is measured against the line of centres
    pub mesh: Option<Mesh>,
}

/// The centres of a gear pair on a carrier, for its line of centres.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// the centre of gear a in a's frame, of gear b in b's frame
    pub u_a: [f64; 2],
    pub u_b: [f64; 2],
    /// the line of centres' angle minus the carrier's, constant
    pub delta: f64,
}

impl Mesh {
    /// The line of centres' angle phi, on the turn the carrier angle theta_c picks, and
    /// d = c_b - c_a.
    fn phi(&self, a: &Frame, b: &Frame, theta_c: f64) -> (f64, [f64; 2]) {
        let d = sub(b.point(self.u_b), a.point(self.u_a));
        let base = theta_c + self.delta;
        let raw = d[1].atan2(d[0]) - base;
        (base + (raw + PI).rem_euclid(2.0 * PI) - PI, d)
    }
}

impl Gear {
    /// The coefficients of a pair with pitch radii r_a, r_b (> 0), turning the same way
    /// (`same_sense`: internal gears, open belts) or opposite ways.
    pub fn coefficients(r_a: f64, r_b: f64, same_sense: bool) -> (f64, f64) {
        let r_max = r_a.max(r_b);
        let sign = if same_sense { -1.0 } else { 1.0 };
        (r_a / r_max, sign * r_b / r_max)
    }
}

impl Constraint for Gear {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p: Vec<(String, &mut f64)> = vec![
            ("k_a".into(), &mut self.k_a),
            ("k_b".into(), &mut self.k_b),
            ("value".into(), &mut self.value),
        ];
        if let Some(m) = &mut self.mesh {
            p.extend(crate::constraints::xy("u_a", &mut m.u_a));
            p.extend(crate::constraints::xy("u_b", &mut m.u_b));
            p.push(("delta".into(), &mut m.delta));
        }
        p
    }
    #[inline]
    fn phi_jet<const W: usize>(
        &self,
        a: &JetFrame<W>,
        b: &JetFrame<W>,
        s: Jet<W>,
        _t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    ) {
        let (k_a, k_b) = (p[0], p[1]);
        let phi = match &self.mesh {
            // the line of centres' angle on the turn `position` picks (delta only picks it)
            Some(m) => {
                let d = jet::sub(b.point(pair(p, 5)), a.point(pair(p, 3)));
                let raw = Jet::atan2(d[1], d[0]);
                let frames = |f: &JetFrame<W>| {
                    let v = |x: &Jet<W>| x.value();
                    Frame {
                        r: [v(&f.r[0]), v(&f.r[1])],
                        theta: v(&f.theta),
                        c: v(&f.c),
                        s: v(&f.s),
                        rd: [0.0; 2],
                        thetad: 0.0,
                    }
                };
                let (turn, _) = m.phi(&frames(a), &frames(b), s.value());
                raw + (turn - raw.value())
            }
            None if self.carrier => s,
            None => Jet::ZERO,
        };
        out[0] = k_a * (a.theta - phi) + k_b * (b.theta - phi) - p[2];
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Angle]
    }
    fn has_extra(&self) -> bool {
        self.carrier
    }
    fn own_start(&self, a: &Frame, b: &Frame) -> f64 {
        // the carrier angle that fits the centres best (used by the derivative tests)
        self.mesh.as_ref().map_or(0.0, |m| {
            let d = sub(b.point(m.u_b), a.point(m.u_a));
            d[1].atan2(d[0]) - m.delta
        })
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, x: &Extra, _t: f64, out: &mut Rows) {
        if let Some(m) = &self.mesh {
            let (phi, d) = m.phi(a, b, x.s);
            let k = self.k_a + self.k_b;
            out.phi[0] = self.k_a * (a.theta - phi) + self.k_b * (b.theta - phi) - self.value;
            // d phi / d d = perp(d) / |d|^2; d moves with b's centre and against a's
            let n = perp(d);
            let r2 = d[0] * d[0] + d[1] * d[1];
            let g = [k * n[0] / r2, k * n[1] / r2];
            let (ba, bb) = (a.rot_d(m.u_a), b.rot_d(m.u_b));
            out.jac_a[0] = [g[0], g[1], self.k_a + g[0] * ba[0] + g[1] * ba[1]];
            out.jac_b[0] = [-g[0], -g[1], self.k_b - (g[0] * bb[0] + g[1] * bb[1])];
            out.jac_s[0] = 0.0;
            return;
        }
        let theta_c = if self.carrier { x.s } else { 0.0 };
        out.phi[0] = self.k_a * (a.theta - theta_c) + self.k_b * (b.theta - theta_c) - self.value;
        out.jac_a[0] = [0.0, 0.0, self.k_a];
        out.jac_b[0] = [0.0, 0.0, self.k_b];
        if self.carrier {
            out.jac_s[0] = -(self.k_a + self.k_b);
        }
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        // linear in the angles, but for the line of centres: phi'' has the part
        // cross(d, c) / r^2 - 2 (d . d') cross(d, d') / r^4 without qdd, c the
        // centripetal part of d''
        g[0] = match &self.mesh {
            None => 0.0,
            Some(m) => {
                let d = sub(b.point(m.u_b), a.point(m.u_a));
                let dd = sub(b.point_velocity(m.u_b), a.point_velocity(m.u_a));
                let c = sub(b.point_centripetal(m.u_b), a.point_centripetal(m.u_a));
                let cross = |u: [f64; 2], v: [f64; 2]| u[0] * v[1] - u[1] * v[0];
                let r2 = d[0] * d[0] + d[1] * d[1];
                let dot = d[0] * dd[0] + d[1] * dd[1];
                (self.k_a + self.k_b) * (cross(d, c) / r2 - 2.0 * dot * cross(d, dd) / (r2 * r2))
            }
        };
    }
}

impl Sample for Gear {
    fn sample() -> Self {
        let (k_a, k_b) = Gear::coefficients(0.05, 0.12, false);
        let mesh = Mesh { u_a: [0.02, -0.01], u_b: [-0.03, 0.015], delta: 0.4 };
        Gear { k_a, k_b, value: 0.3, carrier: true, mesh: Some(mesh) }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for Gear {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "gear",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("radius_a", Pitch("body_a")),
                ("radius_b", Pitch("body_b")),
                ("ratio", Ratio),
                ("centre_a", Point(&["body_a"])),
                ("centre_b", Point(&["body_b"])),
                ("internal", Flag),
                ("carrier", Body),
            ],
        }]
    };
}

/// Compiles a gear-pair description: the pitch radii (given, or from the ratio and the
/// centres' distance), on a carrier the mesh against the line of centres.
#[allow(clippy::too_many_arguments)]
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    radius_a: Option<f64>,
    radius_b: Option<f64>,
    ratio: Option<f64>,
    centre_a: Option<[f64; 2]>,
    centre_b: Option<[f64; 2]>,
    internal: bool,
    carrier: &Option<String>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<Gear>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    let c_a = centre_a.unwrap_or(cx.origin(a));
    let c_b = centre_b.unwrap_or(cx.origin(b));
    if !finite2(c_a) || !finite2(c_b) {
        return Err(format!("centres {c_a:?}, {c_b:?} are not finite"));
    }
    let distance = (c_b[0] - c_a[0]).hypot(c_b[1] - c_a[1]);
    let length_scale = cx.length_scale();
    let (r_a, r_b) = match (radius_a, radius_b, ratio) {
        (None, None, Some(k)) => gear_radii(k, distance, internal, 1e-12 * length_scale)?,
        _ => radii(radius_a, radius_b, ratio)?,
    };
    if internal && r_a == r_b {
        return Err("an internal gear and its pinion need different radii".into());
    }
    let (k_a, k_b) = Gear::coefficients(r_a, r_b, internal);
    let (column, theta_c) = carrier_of(&*cx, carrier, a, b)?;
    // on a carrier, rolling against the line of centres
    let mesh = column.map(|_| Mesh {
        u_a: cx.local(a, c_a),
        u_b: cx.local(b, c_b),
        delta: (c_b[1] - c_a[1]).atan2(c_b[0] - c_a[0]) - theta_c,
    });
    let phi0 = mesh.as_ref().map_or(0.0, |m| theta_c + m.delta);
    if mesh.is_some() && distance <= 1e-12 * length_scale {
        return Err("its centres coincide, so they have no line of centres".into());
    }
    let value = k_a * (cx.theta(a) - phi0) + k_b * (cx.theta(b) - phi0);
    let gear = Gear { k_a, k_b, value, carrier: column.is_some(), mesh };
    Ok(Compiled { joint: gear, a, b, borrowed: column })
}

/// Pitch radii of a gear pair or pulleys given by radii, or by the speed ratio r_a / r_b
/// alone (radii k and 1: only their ratio matters).
pub(crate) fn radii(
    radius_a: Option<f64>,
    radius_b: Option<f64>,
    ratio: Option<f64>,
) -> Result<(f64, f64), String> {
    match (radius_a, radius_b, ratio) {
        (Some(r_a), Some(r_b), None) => {
            Ok((positive_or("radius_a", Some(r_a), 0.0)?, positive_or("radius_b", Some(r_b), 0.0)?))
        }
        (None, None, Some(k)) => Ok((positive_or("ratio", Some(k), 0.0)?, 1.0)),
        _ => Err("needs either radius_a and radius_b, or ratio (one of the two, not both)".into()),
    }
}

/// Pitch radii of a gear pair from the speed ratio k = r_a / r_b and the distance between
/// the centres: r_a + r_b = distance (external), |r_a - r_b| = distance (internal).
fn gear_radii(k: f64, distance: f64, internal: bool, min_distance: f64) -> Result<(f64, f64), String> {
    let k = positive_or("ratio", Some(k), 0.0)?;
    if distance <= min_distance {
        return Err("its centres coincide at the start, so a ratio does not give the radii; \
                    give radius_a and radius_b or draw the centres apart"
            .into());
    }
    if internal && (k - 1.0).abs() <= 1e-12 {
        return Err("an internal gear pair cannot have ratio 1".into());
    }
    let r_b = if internal { distance / (k - 1.0).abs() } else { distance / (k + 1.0) };
    Ok((k * r_b, r_b))
}

/// The carrier of a gear pair or belt: its theta column and starting angle; no carrier
/// (or the ground) gives (None, 0). The carrier must be a third body.
pub(crate) fn carrier_of(
    cx: &dyn CompileContext,
    carrier: &Option<String>,
    a: Option<usize>,
    b: Option<usize>,
) -> Result<(Option<usize>, f64), String> {
    let Some(name) = carrier else {
        return Ok((None, 0.0));
    };
    let c = cx.find(name)?;
    if c == a || c == b {
        return Err(format!(
            "its carrier '{name}' is one of its own two bodies; the carrier must be a third body"
        ));
    }
    Ok((c.map(|i| 3 * i + 2), cx.theta(c)))
}

impl FromDescription for Gear {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::Gear {
            body_a,
            body_b,
            radius_a,
            radius_b,
            ratio,
            centre_a,
            centre_b,
            internal,
            carrier,
            ..
        }) = desc
        else {
            return None;
        };
        Some(compile(
            body_a, body_b, *radius_a, *radius_b, *ratio, *centre_a, *centre_b, *internal, carrier, cx,
        ))
    }
}
