//! Design parameters as the engine sees them: each a direction in the joints' and
//! drivers' own numbers (`Constraint::params_mut`), and in the named points' local
//! coordinates.
//!
//! Two ways to name one:
//! - the engine's: `constraints.<joint or driver>.<its number>`, e.g.
//!   `constraints.B.u_a.x`, `constraints.crank_angle.law.rate` (every joint type has its
//!   own; `Parameter::all` lists them);
//! - a description path, as a study names it (`joints.B.at.0`,
//!   `drivers.crank_angle.law.rate`, `points.P.at.1`): the number of the description,
//!   mapped exactly onto the compiled numbers it makes (a pin's world place moves its
//!   place in both bodies, A(theta_0)^T per body; a distance joint's drawn length moves
//!   with its ends; a prismatic joint's place moves its translation drivers too). Paths
//!   whose compiled numbers are not (yet) mapped here are refused, naming the parameter:
//!   a study then falls back to differences of whole sweeps.

use std::fmt;

use crate::description::{DriverDesc, JointDesc};
use crate::joints::Constraint;
use crate::model::Model;

/// A design parameter the engine differentiates: its name and the direction it moves
/// the compiled numbers in.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    pub name: String,
    /// (constraint index, index of its number in `params_mut`, d number / d parameter)
    pub seeds: Vec<(usize, usize, f64)>,
    /// (named point index, d local coordinates / d parameter)
    pub points: Vec<(usize, [f64; 2])>,
    /// the parameter's value in the description (or the compiled number)
    pub nominal: f64,
}

/// A parameter that is not an engine parameter, or not one of the model's.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterError {
    pub name: String,
    pub problem: String,
}

impl fmt::Display for ParameterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "parameter '{}': {}", self.name, self.problem)
    }
}

impl std::error::Error for ParameterError {}

/// The compiled numbers of every constraint (in `params_mut` order), read once.
pub fn values(model: &Model) -> Vec<Vec<f64>> {
    model
        .constraints
        .iter()
        .map(|c| c.kind.clone().params_mut().into_iter().map(|(_, v)| *v).collect())
        .collect()
}

/// The names of a constraint's own numbers.
fn names(model: &Model, c: usize) -> Vec<String> {
    model.constraints[c].kind.clone().params_mut().into_iter().map(|(n, _)| n).collect()
}

/// A(theta)^T e_i: d local / d world_i of a body point (identity on the ground).
fn to_local_column(pose: Option<[f64; 3]>, i: usize) -> [f64; 2] {
    let theta = pose.map_or(0.0, |p| p[2]);
    let (s, c) = theta.sin_cos();
    // A^T = [[c, s], [-s, c]]
    [[c, s][i], [-s, c][i]]
}

impl Parameter {
    /// Every engine parameter of the model (`constraints.<name>.<number>`).
    pub fn all(model: &Model) -> Vec<Parameter> {
        let vals = values(model);
        let mut out = Vec::new();
        for (c, entry) in model.constraints.iter().enumerate() {
            for (i, n) in names(model, c).into_iter().enumerate() {
                out.push(Parameter {
                    name: format!("constraints.{}.{n}", entry.name),
                    seeds: vec![(c, i, 1.0)],
                    points: Vec::new(),
                    nominal: vals[c][i],
                });
            }
        }
        out
    }

    /// The parameter `name` of the model: an engine name or a description path.
    pub fn resolve(model: &Model, name: &str) -> Result<Parameter, ParameterError> {
        let fail = |problem: String| ParameterError { name: name.to_string(), problem };
        let keys: Vec<&str> = name.split('.').collect();
        if keys.len() < 3 {
            return Err(fail(
                "a parameter is a path such as joints.B.at.0, drivers.D.law.rate, points.P.at.1 or \
                 constraints.B.u_a.x"
                    .into(),
            ));
        }
        let (group, item, rest) = (keys[0], keys[1], &keys[2..]);
        let constraint = |role: &str| {
            model
                .constraints
                .iter()
                .position(|c| c.name == item && (role.is_empty() || c.role == role))
                .ok_or_else(|| {
                    let have: Vec<&str> = model
                        .constraints
                        .iter()
                        .filter(|c| role.is_empty() || c.role == role)
                        .map(|c| c.name.as_str())
                        .collect();
                    fail(format!(
                        "no {} '{item}'; there are {}",
                        if role.is_empty() { "joint or driver" } else { role },
                        have.join(", ")
                    ))
                })
        };
        let own = |c: usize, field: &str| -> Result<Parameter, ParameterError> {
            let i = names(model, c).iter().position(|n| n == field).ok_or_else(|| {
                fail(format!(
                    "{} '{item}' has no engine number '{field}'; it has {}",
                    model.constraints[c].role,
                    names(model, c).join(", ")
                ))
            })?;
            Ok(Parameter {
                name: name.to_string(),
                seeds: vec![(c, i, 1.0)],
                points: Vec::new(),
                nominal: values(model)[c][i],
            })
        };
        let index = |k: usize| -> Result<usize, ParameterError> {
            match rest.get(k).and_then(|s| s.parse::<usize>().ok()) {
                Some(i) if i < 2 => Ok(i),
                _ => Err(fail("name the coordinate: .0 (x) or .1 (y)".into())),
            }
        };
        let joined = rest.join(".");
        match group {
            "constraints" => own(constraint("")?, &joined),
            "drivers" if rest[0] == "law" => {
                let c = constraint("driver")?;
                let p = own(c, &joined).map_err(|_| {
                    let laws: Vec<String> =
                        names(model, c).into_iter().filter(|n| n.starts_with("law.")).collect();
                    fail(if laws.is_empty() {
                        "the driver's law has no engine parameters (tables, expressions, cams, sequences \
                         and Python laws are varied by differences)"
                            .into()
                    } else {
                        format!("the driver's law has {}", laws.join(", "))
                    })
                })?;
                Ok(p)
            }
            "points" if rest.len() == 2 && rest[0] == "at" => {
                let i = index(1)?;
                let k = model
                    .points
                    .iter()
                    .position(|p| p.name == item)
                    .ok_or_else(|| fail(format!("no point '{item}'")))?;
                let desc = &model.description.points[k];
                let body = model.body_index(&desc.body);
                let pose =
                    body.map(|b| [model.q_start[3 * b], model.q_start[3 * b + 1], model.q_start[3 * b + 2]]);
                Ok(Parameter {
                    name: name.to_string(),
                    seeds: Vec::new(),
                    points: vec![(k, to_local_column(pose, i))],
                    nominal: desc.at[i],
                })
            }
            "joints" | "drivers" => {
                let role = if group == "joints" { "joint" } else { "driver" };
                let c = constraint(role)?;
                let mut p =
                    Parameter { name: name.to_string(), seeds: Vec::new(), points: Vec::new(), nominal: 0.0 };
                describe_path(model, c, rest, &mut p).map_err(fail)?;
                Ok(p)
            }
            "bodies" => Err(fail(
                "a body's pose, mass or inertia is not an engine parameter of the kinematics (the drawn \
                 pose only names the frame; mass properties change the driver effort alone, whose \
                 sensitivities the engine does not compute)"
                    .into(),
            )),
            _ => Err(fail(format!("'{group}' is not a group with engine parameters"))),
        }
    }
}

/// The pose a body was drawn in (None: the ground).
fn drawn(model: &Model, body: &str) -> Option<[f64; 3]> {
    model.body_index(body).map(|b| [model.q_start[3 * b], model.q_start[3 * b + 1], model.q_start[3 * b + 2]])
}

/// Seeds of a description path below a joint or driver (`rest`: the keys after its name).
fn describe_path(model: &Model, c: usize, rest: &[&str], p: &mut Parameter) -> Result<(), String> {
    let entry = &model.constraints[c];
    let field = rest[0];
    let axis = || -> Result<usize, String> {
        match rest.get(1).and_then(|s| s.parse::<usize>().ok()) {
            Some(i) if i < 2 && rest.len() == 2 => Ok(i),
            _ => Err(format!("name the coordinate of '{field}': .0 (x) or .1 (y)")),
        }
    };
    let scalar = || -> Result<(), String> {
        if rest.len() == 1 {
            Ok(())
        } else {
            Err(format!("'{field}' is a number; it has no '{}'", rest[1..].join(".")))
        }
    };
    let seed_point = |p: &mut Parameter, c: usize, first: usize, body: &str, i: usize| {
        let col = to_local_column(drawn(model, body), i);
        p.seeds.push((c, first, col[0]));
        p.seeds.push((c, first + 1, col[1]));
    };
    let unsupported = || {
        format!(
            "'{field}' of {} '{}' ({}) is not mapped onto engine numbers; vary it by differences, or name \
             the engine's own numbers (constraints.{}.…: {})",
            entry.role,
            entry.name,
            entry.kind.label(),
            entry.name,
            entry.kind.clone().params_mut().into_iter().map(|(n, _)| n).collect::<Vec<_>>().join(", ")
        )
    };
    let desc = &model.description;
    if entry.role == "driver" {
        let d = desc.drivers.iter().find(|d| d.name() == entry.name).ok_or_else(unsupported)?;
        match (d, field) {
            (DriverDesc::Distance { body_a, at_a, .. }, "at_a") => {
                let i = axis()?;
                p.nominal = at_a[i];
                seed_point(p, c, 0, body_a, i);
            }
            (DriverDesc::Distance { body_b, at_b, .. }, "at_b") => {
                let i = axis()?;
                p.nominal = at_b[i];
                seed_point(p, c, 2, body_b, i);
            }
            (DriverDesc::Coordinate { body, at, .. }, "at") => {
                let i = axis()?;
                p.nominal = at[i];
                seed_point(p, c, 0, body, i);
            }
            _ => return Err(unsupported()),
        }
        return Ok(());
    }
    let j = desc.joints.iter().find(|j| j.name() == entry.name).ok_or_else(unsupported)?;
    match (j, field) {
        (JointDesc::Revolute { body_a, body_b, at: Some(at), pin_a, pin_b, .. }, "at") => {
            let i = axis()?;
            p.nominal = at[i];
            if pin_a.is_none() {
                seed_point(p, c, 0, body_a, i);
            }
            if pin_b.is_none() {
                seed_point(p, c, 2, body_b, i);
            }
        }
        (JointDesc::Revolute { pin_a: Some(pin), .. }, "pin_a")
        | (JointDesc::Revolute { pin_b: Some(pin), .. }, "pin_b") => {
            let i = axis()?;
            p.nominal = pin[i];
            p.seeds.push((c, if field == "pin_a" { i } else { 2 + i }, 1.0));
        }
        (JointDesc::Prismatic { name, body_a, body_b, at: Some(at), pin_a: None, pin_b: None, .. }, "at") => {
            let i = axis()?;
            p.nominal = at[i];
            // the joint and every translation driver of it (they copy its points)
            let mut owners = vec![c];
            for d in &desc.drivers {
                if let DriverDesc::Translation { name: dn, joint, .. } = d {
                    if joint == name {
                        owners.extend(
                            model.constraints.iter().position(|e| e.name == *dn && e.role == "driver"),
                        );
                    }
                }
            }
            for o in owners {
                seed_point(p, o, 0, body_a, i);
                seed_point(p, o, 2, body_b, i);
            }
        }
        (JointDesc::Distance { body_a, at_a, body_b, at_b, length, .. }, "at_a" | "at_b") => {
            let i = axis()?;
            let (at, body, first, sign) =
                if field == "at_a" { (at_a, body_a, 0, -1.0) } else { (at_b, body_b, 2, 1.0) };
            p.nominal = at[i];
            seed_point(p, c, first, body, i);
            if length.is_none() {
                // the drawn length |at_b - at_a| moves with its ends
                let d = [at_b[0] - at_a[0], at_b[1] - at_a[1]];
                p.seeds.push((c, 4, sign * d[i] / d[0].hypot(d[1])));
            }
        }
        (JointDesc::Distance { length: Some(l), .. }, "length") => {
            scalar()?;
            p.nominal = *l;
            p.seeds.push((c, 4, 1.0));
        }
        (JointDesc::PointOnLine { body_a, body_b, at, axis: e, through, offset, .. }, "at" | "through") => {
            let i = axis()?;
            let norm = e[0].hypot(e[1]);
            let n = [-e[1] / norm, e[0] / norm];
            if field == "at" {
                p.nominal = at[i];
                seed_point(p, c, 0, body_a, i);
                if through.is_none() {
                    seed_point(p, c, 2, body_b, i);
                } else if offset.is_none() {
                    p.seeds.push((c, 6, n[i]));
                }
            } else {
                let q = through.ok_or_else(unsupported)?;
                p.nominal = q[i];
                seed_point(p, c, 2, body_b, i);
                if offset.is_none() {
                    p.seeds.push((c, 6, -n[i]));
                }
            }
        }
        (JointDesc::PointOnLine { offset: Some(o), .. }, "offset") => {
            scalar()?;
            p.nominal = *o;
            p.seeds.push((c, 6, 1.0));
        }
        (JointDesc::RackPinion { radius, .. }, "radius") => {
            scalar()?;
            p.nominal = *radius;
            p.seeds.push((c, 6, 1.0));
        }
        (JointDesc::PinInSlot { body_b, at, .. } | JointDesc::CamFollower { body_b, at, .. }, "at") => {
            let i = axis()?;
            p.nominal = at[i];
            seed_point(p, c, 0, body_b, i);
        }
        (JointDesc::CamFollower { radius: Some(r), follower, .. }, "radius") if follower == "roller" => {
            scalar()?;
            p.nominal = *r;
            p.seeds.push((c, 2, 1.0));
        }
        _ => return Err(unsupported()),
    }
    Ok(())
}
