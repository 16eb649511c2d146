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
//!   with its ends; a prismatic joint's place moves its translation drivers too; a gear's
//!   or belt's ratio or radii move its coefficients and the drawing's row constant).
//!   Paths whose compiled numbers are not (yet) mapped here are refused, naming the
//!   parameter: a study then falls back to differences of whole sweeps.
//!
//! The inverse dynamics has numbers of its own (`Dynamics`): each body's mass, inertia
//! and centre of mass, gravity, and each load's (`bodies.crank.mass`, `bodies.crank.com.0`,
//! `gravity.1`, `loads.spring.stiffness`). The kinematics does not depend on them: only the
//! driver efforts' sensitivities do.

use std::fmt;

use crate::constraints::loads::Inertia;
use crate::constraints::{kinds::ConstraintKind, Constraint};
use crate::input::description::{DriverDesc, JointDesc, LoadDesc, GROUND};
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
    /// (index in `Dynamics`' list, d number / d parameter): the inverse dynamics' numbers
    pub dynamics: Vec<(usize, f64)>,
    /// the parameter's value in the description (or the compiled number)
    pub nominal: f64,
}

/// Where the inverse dynamics' numbers sit in one list: each body's mass, inertia and
/// centre of mass in its frame (`Inertia::NAMES`, 4 a body), gravity's x and y, then each
/// load's own (`Load::params_mut`).
#[derive(Debug, Clone, PartialEq)]
pub struct Dynamics {
    /// index of gravity's x
    pub gravity: usize,
    /// per load, the index of its first number
    pub loads: Vec<usize>,
    /// the numbers, in this order
    pub values: Vec<f64>,
}

impl Dynamics {
    pub fn new(model: &Model) -> Dynamics {
        let mut values = Vec::new();
        for b in &model.inertias {
            values.extend([b.mass, b.inertia, b.com[0], b.com[1]]);
        }
        let gravity = values.len();
        values.extend(model.gravity);
        let mut loads = Vec::with_capacity(model.loads.len());
        for l in &model.loads {
            loads.push(values.len());
            values.extend(l.load.clone().params_mut().into_iter().map(|(_, v)| *v));
        }
        Dynamics { gravity, loads, values }
    }

    /// Writes `values` (laid out as `new` reads them) into the model's mass properties,
    /// gravity and loads: a design study's variant of the model.
    pub fn set(&self, model: &mut Model, values: &[f64]) {
        for (b, inertia) in model.inertias.iter_mut().enumerate() {
            let v = &values[Dynamics::body(b, 0)..Dynamics::body(b + 1, 0)];
            (inertia.mass, inertia.inertia, inertia.com) = (v[0], v[1], [v[2], v[3]]);
        }
        model.gravity = [values[self.gravity], values[self.gravity + 1]];
        for (l, &first) in model.loads.iter_mut().zip(&self.loads) {
            for (k, (_, v)) in l.load.params_mut().into_iter().enumerate() {
                *v = values[first + k];
            }
        }
    }

    /// The index of body b's mass property `i` (`Inertia::NAMES`).
    pub fn body(b: usize, i: usize) -> usize {
        Inertia::NAMES.len() * b + i
    }
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
                    dynamics: Vec::new(),
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
        if keys[0] == "gravity" {
            let i = match keys[1..] {
                [i] => i.parse::<usize>().ok().filter(|&i| i < 2),
                _ => None,
            };
            let i =
                i.ok_or_else(|| fail("name gravity's coordinate: gravity.0 (x) or gravity.1 (y)".into()))?;
            return Ok(Parameter {
                name: name.to_string(),
                seeds: Vec::new(),
                points: Vec::new(),
                dynamics: vec![(Dynamics::new(model).gravity + i, 1.0)],
                nominal: model.gravity[i],
            });
        }
        if keys.len() < 3 {
            return Err(fail(
                "a parameter is a path such as joints.B.at.0, drivers.D.law.rate, points.P.at.1, \
                 bodies.B.mass, gravity.1 or constraints.B.u_a.x"
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
                dynamics: Vec::new(),
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
                    dynamics: Vec::new(),
                    nominal: desc.at[i],
                })
            }
            "joints" | "drivers" => {
                let role = if group == "joints" { "joint" } else { "driver" };
                let c = constraint(role)?;
                let mut p = Parameter::empty(name);
                describe_path(model, c, rest, &mut p).map_err(fail)?;
                Ok(p)
            }
            "bodies" => {
                let b = model
                    .body_names
                    .iter()
                    .position(|b| b == item)
                    .ok_or_else(|| fail(format!("no body '{item}'")))?;
                let desc = &model.description.bodies[b];
                let mut p = Parameter::empty(name);
                match rest {
                    ["mass"] | ["inertia"] => {
                        let i = usize::from(rest[0] == "inertia");
                        p.nominal = [desc.mass, desc.inertia][i];
                        p.dynamics.push((Dynamics::body(b, i), 1.0));
                    }
                    ["com", _] => {
                        let i = index(1)?;
                        p.nominal = desc.com.unwrap_or([desc.x, desc.y])[i];
                        // the compiled centre is local to the drawn pose, as `compile` makes it
                        let col = to_local_column(Some([desc.x, desc.y, desc.theta]), i);
                        p.dynamics.push((Dynamics::body(b, 2), col[0]));
                        p.dynamics.push((Dynamics::body(b, 3), col[1]));
                    }
                    _ => {
                        return Err(fail(format!(
                            "'{}' of a body is not an engine parameter (its drawn pose only names its \
                             frame); a body's are its mass, inertia and com.0, com.1",
                            rest.join(".")
                        )))
                    }
                }
                Ok(p)
            }
            "loads" => {
                let l = model
                    .loads
                    .iter()
                    .position(|l| l.name == item)
                    .ok_or_else(|| fail(format!("no load '{item}'")))?;
                let mut p = Parameter::empty(name);
                describe_load(model, l, rest, &mut p).map_err(fail)?;
                Ok(p)
            }
            _ => Err(fail(format!("'{group}' is not a group with engine parameters"))),
        }
    }
}

impl Parameter {
    fn empty(name: &str) -> Parameter {
        Parameter {
            name: name.to_string(),
            seeds: Vec::new(),
            points: Vec::new(),
            dynamics: Vec::new(),
            nominal: 0.0,
        }
    }
}

/// The pose a body was drawn in (None: the ground).
fn drawn(model: &Model, body: &str) -> Option<[f64; 3]> {
    model.body_index(body).map(|b| [model.q_start[3 * b], model.q_start[3 * b + 1], model.q_start[3 * b + 2]])
}

/// The pose body `name` is described in, as `compile` reads it (None: the ground).
fn described(model: &Model, name: &str) -> Option<[f64; 3]> {
    model.description.bodies.iter().find(|b| b.name == name).map(|b| [b.x, b.y, b.theta])
}

/// Seeds of a description path below load l (`rest`: the keys after its name), in the
/// inverse dynamics' numbers (`Dynamics`).
fn describe_load(model: &Model, l: usize, rest: &[&str], p: &mut Parameter) -> Result<(), String> {
    let first = Dynamics::new(model).loads[l];
    let engine: Vec<String> = model.loads[l].load.clone().params_mut().into_iter().map(|(n, _)| n).collect();
    let at = |n: &str| first + engine.iter().position(|e| e == n).expect("a load's own number");
    let field = rest[0];
    let axis = || -> Result<usize, String> {
        match rest.get(1).and_then(|s| s.parse::<usize>().ok()) {
            Some(i) if i < 2 && rest.len() == 2 => Ok(i),
            _ => Err(format!("name the coordinate of '{field}': .0 (x) or .1 (y)")),
        }
    };
    let scalar = |p: &mut Parameter, n: &str, v: f64| -> Result<(), String> {
        if rest.len() != 1 {
            return Err(format!("'{field}' is a number; it has no '{}'", rest[1..].join(".")));
        }
        p.nominal = v;
        p.dynamics.push((at(n), 1.0));
        Ok(())
    };
    let point = |p: &mut Parameter, n: &str, body: &str, xy: [f64; 2]| -> Result<(), String> {
        let i = axis()?;
        p.nominal = xy[i];
        let col = to_local_column(described(model, body), i);
        p.dynamics.push((at(&format!("{n}.x")), col[0]));
        p.dynamics.push((at(&format!("{n}.y")), col[1]));
        Ok(())
    };
    let name = &model.loads[l].name;
    match (&model.description.loads[l], field) {
        (LoadDesc::Force { body, at: xy, .. }, "at") => point(p, "u", body, *xy)?,
        (LoadDesc::Force { direction: d, .. }, "direction") => {
            // the unit direction d / |d|: d e_j / d d_i = (delta_ij - e_i e_j) / |d|
            let i = axis()?;
            let norm = d[0].hypot(d[1]);
            let e = [d[0] / norm, d[1] / norm];
            p.nominal = d[i];
            for j in 0..2 {
                let delta = if i == j { 1.0 } else { 0.0 };
                p.dynamics.push((at(["dir.x", "dir.y"][j]), (delta - e[i] * e[j]) / norm));
            }
        }
        (LoadDesc::Force { .. } | LoadDesc::Torque { .. }, "law") => {
            let want = rest.join(".");
            if !engine.contains(&want) {
                let fields: Vec<&str> =
                    engine.iter().filter(|n| n.starts_with("law.")).map(String::as_str).collect();
                return Err(if fields.is_empty() {
                    format!(
                        "load '{name}' follows a law whose numbers the engine does not differentiate \
                         (tables, expressions, cams, sequences, periodic and Python laws are varied by \
                         differences)"
                    )
                } else {
                    format!("the law of load '{name}' has {}", fields.join(", "))
                });
            }
            p.nominal = want_value(model, l, &want);
            p.dynamics.push((at(&want), 1.0));
        }
        (LoadDesc::Spring { body_a, at_a, .. }, "at_a") => point(p, "u_a", body_a, *at_a)?,
        (LoadDesc::Spring { body_b, at_b, .. }, "at_b") => point(p, "u_b", body_b, *at_b)?,
        (
            LoadDesc::Spring { stiffness: v, .. } | LoadDesc::TorsionSpring { stiffness: v, .. },
            "stiffness",
        )
        | (LoadDesc::Spring { damping: v, .. } | LoadDesc::TorsionSpring { damping: v, .. }, "damping")
        | (LoadDesc::Spring { free_length: v, .. }, "free_length")
        | (LoadDesc::TorsionSpring { free_angle: v, .. }, "free_angle") => scalar(p, field, *v)?,
        (LoadDesc::JointForce { .. } | LoadDesc::Motor { .. } | LoadDesc::Friction { .. }, _) => {
            return Err(format!(
                "load '{name}' acts at a joint (a joint force, motor or friction); its numbers are not \
                 design parameters"
            ))
        }
        _ => {
            return Err(format!(
                "'{field}' of load '{name}' is not an engine parameter; it has {}",
                engine.join(", ")
            ))
        }
    }
    Ok(())
}

/// Seeds of a gear's or belt's ratio or radius (`field`; `given`: the description's
/// radius_a, radius_b, ratio; `sides`: its bodies a, b and carrier). The coefficients
/// k_a = r_a / r_max and k_b = sign r_b / r_max depend on rho = r_a / r_b alone:
/// k_a = min(rho, 1), k_b = sign min(1, 1 / rho) (the radii a ratio and a centre distance
/// give keep r_a / r_b = ratio). The drawing's row constant
/// value = k_a (theta_a0 - phi_0) + k_b (theta_b0 - phi_0), the angles as drawn, moves with
/// them. At rho = 1 r_max switches sides and the derivative is one-sided: refused.
fn ratio_seeds(
    model: &Model,
    c: usize,
    field: &str,
    given: (Option<f64>, Option<f64>, Option<f64>),
    sides: [&str; 3],
    p: &mut Parameter,
) -> Result<(), String> {
    let (rho, d_rho) = match given {
        (_, _, Some(k)) => (k, 1.0),
        (Some(r_a), Some(r_b), None) => {
            (r_a / r_b, if field == "radius_a" { 1.0 / r_b } else { -r_a / (r_b * r_b) })
        }
        _ => {
            return Err(format!("'{field}' of '{}' has no radii or ratio to move", model.constraints[c].name))
        }
    };
    if rho == 1.0 {
        return Err(format!(
            "'{field}' of {} '{}': its two radii are equal, where k_a = r_a / max(r_a, r_b) and k_b turn a \
             corner (the derivative is one-sided); vary it by differences",
            model.constraints[c].kind.label(),
            model.constraints[c].name
        ));
    }
    let theta = |body: &str| described(model, body).map_or(0.0, |q| q[2]);
    let (gear, phi0) = match &model.constraints[c].kind {
        ConstraintKind::Gear(g) => (g, g.mesh.as_ref().map_or(0.0, |m| theta(sides[2]) + m.delta)),
        ConstraintKind::Belt(b) => (&b.0, theta(sides[2])),
        _ => unreachable!("a gear's or belt's description compiles to a gear row"),
    };
    let sign = gear.k_b.signum();
    let d_ka = if rho < 1.0 { d_rho } else { 0.0 };
    let d_kb = if rho > 1.0 { -sign / (rho * rho) * d_rho } else { 0.0 };
    let d_value = d_ka * (theta(sides[0]) - phi0) + d_kb * (theta(sides[1]) - phi0);
    for (i, d) in [d_ka, d_kb, d_value].into_iter().enumerate() {
        if d != 0.0 {
            p.seeds.push((c, i, d));
        }
    }
    Ok(())
}

/// The compiled value of load l's own number `n`.
fn want_value(model: &Model, l: usize, n: &str) -> f64 {
    model.loads[l].load.clone().params_mut().into_iter().find(|(e, _)| e == n).map_or(0.0, |(_, v)| *v)
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
        (
            JointDesc::Gear { body_a, body_b, radius_a, radius_b, ratio, carrier, .. }
            | JointDesc::Belt { body_a, body_b, radius_a, radius_b, ratio, carrier, .. },
            "ratio" | "radius_a" | "radius_b",
        ) => {
            scalar()?;
            let given = match field {
                "ratio" => *ratio,
                "radius_a" => *radius_a,
                _ => *radius_b,
            };
            p.nominal = given.ok_or_else(unsupported)?;
            let sides = [body_a.as_str(), body_b.as_str(), carrier.as_deref().unwrap_or(GROUND)];
            ratio_seeds(model, c, field, (*radius_a, *radius_b, *ratio), sides, p)?;
        }
        _ => return Err(unsupported()),
    }
    Ok(())
}
