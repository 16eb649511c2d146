//! Each joint's and driver's compile arm: its kind and sides from its description, its
//! points in its bodies' frames, its numbers checked.

use std::collections::HashMap;

use crate::compile::close_drawing::{world, Closer, Side};
use crate::constraints::drivers::{
    angle::AngleDriver, coordinate::CoordinateDriver, distance::DistanceDriver,
    relative_angle::RelativeAngleDriver, translation::TranslationDriver,
};
use crate::constraints::joints::{
    belt::Belt,
    coupler::Coupler,
    coupling::LinearCoupling,
    gear::{Gear, Mesh},
    orientation::FixedOrientation,
    parallel::Parallel,
    point_line::PointOnLine,
    rack_pinion::RackPinion,
};
use crate::constraints::joints::{
    fixed::Fixed, flat_follower::FlatFollower, point_on_curve::PointOnCurve, prismatic::Prismatic,
    revolute::Revolute, roller_follower::RollerFollower,
};
use crate::constraints::{kinds::ConstraintKind, Frame};
use crate::error::ModelError;
use crate::input::description::{Description, DriverDesc, JointDesc, GROUND};

use super::{finite2, local, Bodies, ConstraintDraft};

/// The joints' compile arms: each joint's kind and sides from its description, its pins
/// checked against the drawing (`closer`); the prismatic joints kept for the translation
/// drivers that ride on them.
#[allow(clippy::type_complexity)]
pub(super) fn joint_entries<'a>(
    desc: &'a Description,
    bodies: &Bodies,
    length_scale: f64,
    closer: &mut Closer,
) -> Result<(Vec<ConstraintDraft>, HashMap<&'a str, (Prismatic, Option<usize>, Option<usize>)>), ModelError> {
    let mut entries: Vec<ConstraintDraft> = Vec::new();
    let mut prismatic_of: HashMap<&str, (Prismatic, Option<usize>, Option<usize>)> = HashMap::new();
    for j in &desc.joints {
        let fail = |problem: String| ModelError::Constraint { kind: "joint", name: j.name().into(), problem };
        // set by a joint whose rows involve another body's coordinate
        let mut borrowed: Option<usize> = None;
        let (kind, a, b) = match j {
            JointDesc::Revolute { name, body_a, body_b, at, pin_a, pin_b } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                if let Some(p) = [*at, *pin_a, *pin_b].into_iter().flatten().find(|p| !finite2(*p)) {
                    return Err(fail(format!("position {p:?} is not finite")));
                }
                if at.is_none() && (pin_a.is_none() || pin_b.is_none()) {
                    return Err(fail(
                        "needs its position `at`, or its pin in each body (pin_a and pin_b)".into(),
                    ));
                }
                // each side's pin in its frame: given (checked against the drawing's
                // point where both are), or the drawing's point there
                let mut side = |pin: Option<[f64; 2]>, body: Option<usize>, key: &'static str| {
                    let pose = bodies.pose(body);
                    let body_name = body.map_or(GROUND, |i| desc.bodies[i].name.as_str());
                    let drawn = at.map(|at| (at, local(pose, at)));
                    closer.side(Side { joint: name, body: body_name, pin: key }, pin, drawn, pose, None)
                };
                let joint = Revolute { u_a: side(*pin_a, a, "pin_a"), u_b: side(*pin_b, b, "pin_b") };
                (ConstraintKind::Revolute(joint), a, b)
            }
            JointDesc::Prismatic { name, body_a, body_b, at, axis, pin_a, pin_b, axis_a, angle } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                let points = [*at, *axis, *pin_a, *pin_b, *axis_a];
                if let Some(p) = points.into_iter().flatten().find(|p| !finite2(*p)) {
                    return Err(fail(format!("point or axis {p:?} is not finite")));
                }
                if at.is_none() && (pin_a.is_none() || pin_b.is_none()) {
                    return Err(fail(
                        "needs its point `at` (world), or its pin in each body (pin_a and pin_b)".into(),
                    ));
                }
                // the axis in a's frame: given there, or the world one turned into a's
                let a_turn = Some([0.0, 0.0, bodies.theta(a)]);
                if axis_a.or(*axis).is_some_and(|e| e[0].hypot(e[1]) == 0.0) {
                    return Err(fail("has a zero-length axis; give the sliding direction".into()));
                }
                let e = match (axis_a, axis) {
                    (Some(e), _) => unit("axis_a", *e).map_err(fail)?,
                    (None, Some(e)) => local(a_turn, unit("axis", *e).map_err(fail)?),
                    (None, None) => {
                        return Err(fail(
                            "needs its sliding direction: `axis` (world) or `axis_a` (in body_a's frame)"
                                .into(),
                        ))
                    }
                };
                // a pin need only be on the slide line: the miss is across it
                let normal = Some(world(a_turn, [-e[1], e[0]]));
                let mut side = |pin: Option<[f64; 2]>, body: Option<usize>, key: &'static str| {
                    let pose = bodies.pose(body);
                    let body_name = body.map_or(GROUND, |i| desc.bodies[i].name.as_str());
                    let drawn = at.map(|at| (at, local(pose, at)));
                    closer.side(Side { joint: name, body: body_name, pin: key }, pin, drawn, pose, normal)
                };
                let (u_a, u_b) = (side(*pin_a, a, "pin_a"), side(*pin_b, b, "pin_b"));
                let lengths_first = pin_a.is_some() || pin_b.is_some();
                let drawn_angle = bodies.theta(b) - bodies.theta(a);
                let theta0 = match angle {
                    Some(v) if v.is_finite() => *v,
                    Some(v) => return Err(fail(format!("angle {v} is not finite"))),
                    None if lengths_first => 0.0,
                    None => drawn_angle,
                };
                let joint = Prismatic { u_a, u_b, e_a: e, theta0 };
                prismatic_of.insert(name, (joint.clone(), a, b));
                (ConstraintKind::Prismatic(joint), a, b)
            }
            JointDesc::Fixed { body_a, body_b, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                let origin_b = bodies.pose(b).map_or([0.0, 0.0], |p| [p[0], p[1]]);
                let joint =
                    Fixed { u_a: local(bodies.pose(a), origin_b), theta0: bodies.theta(b) - bodies.theta(a) };
                (ConstraintKind::Fixed(joint), a, b)
            }
            JointDesc::Distance { body_a, at_a, body_b, at_b, length, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                if !finite2(*at_a) || !finite2(*at_b) {
                    return Err(fail(format!("points {at_a:?}, {at_b:?} are not finite")));
                }
                let drawn = (at_b[0] - at_a[0]).hypot(at_b[1] - at_a[1]);
                if drawn <= 1e-12 * length_scale {
                    return Err(fail(
                        "its two points coincide at the start; a distance joint needs them apart".into(),
                    ));
                }
                let length = positive_or("length", *length, drawn).map_err(fail)?;
                let joint =
                    Coupler { u_a: local(bodies.pose(a), *at_a), u_b: local(bodies.pose(b), *at_b), length };
                (ConstraintKind::Distance(joint), a, b)
            }
            JointDesc::PointOnLine { body_a, body_b, at, axis, through, offset, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                let q = through.unwrap_or(*at);
                if !finite2(*at) || !finite2(q) {
                    return Err(fail(format!("point {at:?} or line point {q:?} is not finite")));
                }
                let e = unit("axis", *axis).map_err(fail)?;
                let drawn = -e[1] * (at[0] - q[0]) + e[0] * (at[1] - q[1]);
                let offset = match offset {
                    None => drawn,
                    Some(o) if o.is_finite() => *o,
                    Some(o) => return Err(fail(format!("offset {o} is not finite"))),
                };
                let joint = PointOnLine {
                    u_a: local(bodies.pose(a), *at),
                    u_b: local(bodies.pose(b), q),
                    e_b: local(Some([0.0, 0.0, bodies.theta(b)]), e),
                    offset,
                };
                (ConstraintKind::PointOnLine(joint), a, b)
            }
            JointDesc::Gear {
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
            } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                let c_a = centre_a.unwrap_or(bodies.origin(a));
                let c_b = centre_b.unwrap_or(bodies.origin(b));
                if !finite2(c_a) || !finite2(c_b) {
                    return Err(fail(format!("centres {c_a:?}, {c_b:?} are not finite")));
                }
                let distance = (c_b[0] - c_a[0]).hypot(c_b[1] - c_a[1]);
                let (r_a, r_b) = match (radius_a, radius_b, ratio) {
                    (None, None, Some(k)) => {
                        gear_radii(*k, distance, *internal, 1e-12 * length_scale).map_err(fail)?
                    }
                    _ => radii(*radius_a, *radius_b, *ratio).map_err(fail)?,
                };
                if *internal && r_a == r_b {
                    return Err(fail("an internal gear and its pinion need different radii".into()));
                }
                let (k_a, k_b) = Gear::coefficients(r_a, r_b, *internal);
                let (column, theta_c) = carrier_of(bodies, carrier, a, b).map_err(fail)?;
                borrowed = column;
                // on a carrier, rolling against the line of centres (joints/gear.rs)
                let mesh = column.map(|_| Mesh {
                    u_a: local(bodies.pose(a), c_a),
                    u_b: local(bodies.pose(b), c_b),
                    delta: (c_b[1] - c_a[1]).atan2(c_b[0] - c_a[0]) - theta_c,
                });
                let phi0 = mesh.as_ref().map_or(0.0, |m| theta_c + m.delta);
                if mesh.is_some() && distance <= 1e-12 * length_scale {
                    return Err(fail("its centres coincide, so they have no line of centres".into()));
                }
                let value = k_a * (bodies.theta(a) - phi0) + k_b * (bodies.theta(b) - phi0);
                let gear = Gear { k_a, k_b, value, carrier: column.is_some(), mesh };
                (ConstraintKind::Gear(gear), a, b)
            }
            JointDesc::RackPinion { body_a, body_b, radius, axis, centre, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                if a.is_none() {
                    return Err(fail(
                        "its pinion (body_a) is the ground, which cannot turn; the rack may be".into(),
                    ));
                }
                let radius = positive_or("radius", Some(*radius), 0.0).map_err(fail)?;
                let c = centre.unwrap_or(bodies.origin(a));
                if !finite2(c) {
                    return Err(fail(format!("centre {c:?} is not finite")));
                }
                let e = unit("axis", *axis).map_err(fail)?;
                let joint = RackPinion {
                    u_a: local(bodies.pose(a), c),
                    u_b: local(bodies.pose(b), c),
                    e_b: local(Some([0.0, 0.0, bodies.theta(b)]), e),
                    radius,
                    delta0: bodies.theta(a) - bodies.theta(b),
                };
                (ConstraintKind::RackPinion(joint), a, b)
            }
            JointDesc::Belt { body_a, body_b, radius_a, radius_b, ratio, crossed, carrier, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                let (r_a, r_b) = radii(*radius_a, *radius_b, *ratio).map_err(fail)?;
                let (k_a, k_b) = Gear::coefficients(r_a, r_b, !*crossed);
                let (column, theta_c) = carrier_of(bodies, carrier, a, b).map_err(fail)?;
                borrowed = column;
                let value = k_a * (bodies.theta(a) - theta_c) + k_b * (bodies.theta(b) - theta_c);
                (
                    ConstraintKind::Belt(Belt(Gear {
                        k_a,
                        k_b,
                        value,
                        carrier: column.is_some(),
                        mesh: None,
                    })),
                    a,
                    b,
                )
            }
            JointDesc::FixedOrientation { body_a, body_b, angle, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                let angle = match angle {
                    None => bodies.theta(b) - bodies.theta(a),
                    Some(v) if v.is_finite() => *v,
                    Some(v) => return Err(fail(format!("angle {v} is not finite"))),
                };
                (ConstraintKind::FixedOrientation(FixedOrientation { angle }), a, b)
            }
            JointDesc::Parallel { body_a, body_b, axis_a, axis_b, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                let (e_a, e_b) =
                    (unit("axis_a", *axis_a).map_err(fail)?, unit("axis_b", *axis_b).map_err(fail)?);
                // the row's Jacobian is the cosine between the lines: zero when perpendicular
                if (e_a[0] * e_b[0] + e_a[1] * e_b[1]).abs() <= 1e-6 {
                    return Err(fail(
                        "its two lines are perpendicular at the start; draw them (nearly) parallel".into(),
                    ));
                }
                let joint = Parallel {
                    e_a: local(Some([0.0, 0.0, bodies.theta(a)]), e_a),
                    e_b: local(Some([0.0, 0.0, bodies.theta(b)]), e_b),
                };
                (ConstraintKind::Parallel(joint), a, b)
            }
            JointDesc::LinearCoupling { body_a, body_b, coefficients_a, coefficients_b, value, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                let c_a = [coefficients_a.x, coefficients_a.y, coefficients_a.theta];
                let c_b = [coefficients_b.x, coefficients_b.y, coefficients_b.theta];
                if !c_a.iter().chain(&c_b).all(|c| c.is_finite()) {
                    return Err(fail(format!("coefficients {c_a:?}, {c_b:?} are not finite")));
                }
                for (side, body, c) in [("a", a, c_a), ("b", b, c_b)] {
                    if body.is_none() && c.iter().any(|c| *c != 0.0) {
                        return Err(fail(format!(
                            "has coefficients_{side} on the ground, whose coordinates are fixed"
                        )));
                    }
                }
                if c_a.iter().chain(&c_b).all(|c| *c == 0.0) {
                    return Err(fail("has no non-zero coefficient".into()));
                }
                let (q_a, q_b) = (bodies.pose(a).unwrap_or([0.0; 3]), bodies.pose(b).unwrap_or([0.0; 3]));
                let value = match value {
                    None => (0..3).map(|k| c_a[k] * q_a[k] + c_b[k] * q_b[k]).sum(),
                    Some(v) if v.is_finite() => *v,
                    Some(v) => return Err(fail(format!("value {v} is not finite"))),
                };
                (ConstraintKind::LinearCoupling(LinearCoupling { c_a, c_b, value }), a, b)
            }
            JointDesc::PinInSlot { body_a, body_b, at, curve, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                if !finite2(*at) {
                    return Err(fail(format!("position {at:?} is not finite")));
                }
                let curve = curve.to_body(bodies.pose(a)).map_err(fail)?;
                let joint = PointOnCurve { curve, u_b: local(bodies.pose(b), *at) };
                (ConstraintKind::PointOnCurve(joint), a, b)
            }
            JointDesc::CamFollower { body_a, body_b, follower, at, curve, radius, face, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                if !finite2(*at) {
                    return Err(fail(format!("position {at:?} is not finite")));
                }
                if !["knife", "roller", "flat"].contains(&follower.as_str()) {
                    return Err(fail(format!(
                        "follower must be \"knife\", \"roller\" or \"flat\", not {follower:?}"
                    )));
                }
                if radius.is_some() && follower != "roller" {
                    return Err(fail("gives a radius, which only a roller follower has".into()));
                }
                if face.is_some() && follower != "flat" {
                    return Err(fail("gives a face direction, which only a flat-faced follower has".into()));
                }
                let curve = curve.to_body(bodies.pose(a)).map_err(fail)?;
                let u_b = local(bodies.pose(b), *at);
                let frame =
                    |b: Option<usize>| bodies.pose(b).map_or(Frame::GROUND, |p| Frame::new(p, [0.0; 3]));
                let kind = match follower.as_str() {
                    "roller" => {
                        let radius = radius.ok_or_else(|| fail("a roller follower needs a radius".into()))?;
                        let joint = RollerFollower::new(curve, u_b, radius, &frame(a), &frame(b));
                        ConstraintKind::RollerFollower(joint.map_err(fail)?)
                    }
                    "flat" => {
                        let face = face
                            .ok_or_else(|| fail("a flat-faced follower needs its face direction".into()))?;
                        let face_b = local(Some([0.0, 0.0, bodies.theta(b)]), face);
                        ConstraintKind::FlatFollower(FlatFollower::new(curve, u_b, face_b).map_err(fail)?)
                    }
                    // a knife edge: its tip on the profile
                    _ => ConstraintKind::PointOnCurve(PointOnCurve { curve, u_b }),
                };
                (kind, a, b)
            }
        };
        let name = j.name().to_string();
        entries.push(ConstraintDraft { name, role: "joint", kind, body_a: a, body_b: b, borrowed });
    }
    Ok((entries, prismatic_of))
}

/// The drivers' compile arms, after the joints (a translation driver reads its prismatic
/// joint).
pub(super) fn driver_entries(
    desc: &Description,
    bodies: &Bodies,
    length_scale: f64,
    prismatic_of: &HashMap<&str, (Prismatic, Option<usize>, Option<usize>)>,
    entries: &mut Vec<ConstraintDraft>,
) -> Result<(), ModelError> {
    for d in &desc.drivers {
        let fail =
            |problem: String| ModelError::Constraint { kind: "driver", name: d.name().into(), problem };
        let mut law = d.law().clone();
        law.prepare().map_err(fail)?;
        let (kind, a, b) = match d {
            DriverDesc::Angle { body, .. } => {
                let b = bodies.find(body).map_err(fail)?;
                if b.is_none() {
                    return Err(fail("drives the ground, which cannot move".into()));
                }
                (ConstraintKind::AngleDriver(AngleDriver { law }), None, b)
            }
            DriverDesc::RelativeAngle { body_a, body_b, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                (ConstraintKind::RelativeAngleDriver(RelativeAngleDriver { law }), a, b)
            }
            DriverDesc::Distance { body_a, at_a, body_b, at_b, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                if !finite2(*at_a) || !finite2(*at_b) {
                    return Err(fail(format!("points {at_a:?}, {at_b:?} are not finite")));
                }
                if (at_b[0] - at_a[0]).hypot(at_b[1] - at_a[1]) <= 1e-12 * length_scale {
                    return Err(fail(
                        "its two points coincide at the start; a distance driver needs them apart".into(),
                    ));
                }
                let drv = DistanceDriver {
                    u_a: local(bodies.pose(a), *at_a),
                    u_b: local(bodies.pose(b), *at_b),
                    law,
                };
                (ConstraintKind::DistanceDriver(drv), a, b)
            }
            DriverDesc::Coordinate { body, at, axis, .. } => {
                let b = bodies.find(body).map_err(fail)?;
                if b.is_none() {
                    return Err(fail("drives a point of the ground, which cannot move".into()));
                }
                if !finite2(*at) {
                    return Err(fail(format!("point {at:?} is not finite")));
                }
                let axis = match axis.as_str() {
                    "x" => 0,
                    "y" => 1,
                    other => return Err(fail(format!("axis must be \"x\" or \"y\", not {other:?}"))),
                };
                let drv = CoordinateDriver { u: local(bodies.pose(b), *at), axis, law };
                (ConstraintKind::CoordinateDriver(drv), None, b)
            }
            DriverDesc::Translation { joint, .. } => {
                let Some((p, a, b)) = prismatic_of.get(joint.as_str()) else {
                    return Err(fail(format!(
                        "refers to '{joint}', which is not a prismatic joint of the model"
                    )));
                };
                let drv = TranslationDriver { u_a: p.u_a, u_b: p.u_b, e_a: p.e_a, law };
                (ConstraintKind::TranslationDriver(drv), *a, *b)
            }
        };
        let name = d.name().to_string();
        entries.push(ConstraintDraft { name, role: "driver", kind, body_a: a, body_b: b, borrowed: None });
    }
    Ok(())
}

/// A given value (finite and > 0, else an error naming `what`), or the default.
fn positive_or(what: &str, given: Option<f64>, default: f64) -> Result<f64, String> {
    match given {
        None => Ok(default),
        Some(v) if v.is_finite() && v > 0.0 => Ok(v),
        Some(v) => Err(format!("{what} {v} must be finite and > 0")),
    }
}

/// The unit vector along a finite, non-zero direction `what`.
fn unit(what: &str, v: [f64; 2]) -> Result<[f64; 2], String> {
    let norm = v[0].hypot(v[1]);
    if !finite2(v) || norm == 0.0 {
        return Err(format!("{what} {v:?} must be a finite, non-zero direction"));
    }
    Ok([v[0] / norm, v[1] / norm])
}

/// Pitch radii of a gear pair or pulleys given by radii, or by the speed ratio r_a / r_b
/// alone (radii k and 1: only their ratio matters).
fn radii(radius_a: Option<f64>, radius_b: Option<f64>, ratio: Option<f64>) -> Result<(f64, f64), String> {
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
fn carrier_of(
    bodies: &Bodies,
    carrier: &Option<String>,
    a: Option<usize>,
    b: Option<usize>,
) -> Result<(Option<usize>, f64), String> {
    let Some(name) = carrier else {
        return Ok((None, 0.0));
    };
    let c = bodies.find(name)?;
    if c == a || c == b {
        return Err(format!(
            "its carrier '{name}' is one of its own two bodies; the carrier must be a third body"
        ));
    }
    Ok((c.map(|i| 3 * i + 2), bodies.theta(c)))
}
