//! The roles table (`joints::roles`): every type of the kind list declares the fields
//! of the description forms it compiles from, consistently, and each declared form is a
//! description the file format reads and writes back with exactly those fields.

use std::collections::BTreeSet;

use linkwork::constraints::{roles, samples, Role};
use linkwork::Description;
use serde_json::{json, Value};

#[test]
fn every_kind_declares_its_forms() {
    let labels: Vec<&str> = samples().iter().map(|k| k.label()).collect();
    let declared: Vec<&str> = roles().iter().map(|(label, _)| *label).collect();
    assert_eq!(labels, declared);
    for (label, forms) in roles() {
        assert!(!forms.is_empty(), "{label}: no description form");
        for form in forms {
            let at = format!("{label} ({} {})", form.group, form.type_);
            assert!(["joints", "drivers"].contains(&form.group), "{at}: group");
            assert_eq!(form.fields.first(), Some(&("name", Role::Name)), "{at}: the name first");
            let names: BTreeSet<&str> = form.fields.iter().map(|(n, _)| *n).collect();
            assert_eq!(names.len(), form.fields.len(), "{at}: a field twice");
            for (name, role) in form.fields {
                for body in role.bodies() {
                    let named = form.fields.iter().any(|(n, r)| *n == body && *r == Role::Body);
                    assert!(named, "{at}: field {name} is fixed in {body}, which is not a body field");
                }
            }
        }
    }
}

/// A value of each role that the description reader accepts.
fn value(role: Role) -> Value {
    match role {
        Role::Name => json!("e"),
        Role::Body => json!("b"),
        Role::Joint => json!("p"),
        Role::Point(_) | Role::LocalPoint(_) => json!([0.25, 0.5]),
        Role::Direction(_) | Role::Slide(_) | Role::LocalDirection(_) => json!([1.0, 0.0]),
        Role::Curve(_) => json!({"type": "circle", "centre": [0.0, 0.0], "radius": 0.5}),
        Role::Pitch(_) | Role::Length => json!(0.125),
        Role::Interval => json!([-0.125, 0.25]),
        Role::Angle | Role::Number => json!(0.75),
        Role::Ratio => json!(2.0),
        Role::Coefficients(_) => json!({"x": 1.0, "y": 0.0, "theta": 0.5}),
        Role::Flag => json!(true),
        Role::Choice(c) => json!(c[0]),
        Role::Law(_) => json!({"type": "linear", "value": 0.0, "rate": 1.0}),
    }
}

#[test]
fn every_form_round_trips_through_the_file_format() {
    for (label, forms) in roles() {
        for form in forms {
            let mut item = serde_json::Map::new();
            item.insert("type".into(), json!(form.type_));
            for (name, role) in form.fields {
                item.insert((*name).into(), value(*role));
            }
            let desc = json!({
                "name": "m",
                "bodies": [{"name": "b", "x": 0.0, "y": 0.0, "theta": 0.0}],
                form.group: [Value::Object(item.clone())],
            });
            let at = format!("{label} ({} {})", form.group, form.type_);
            let read = Description::from_json(&desc.to_string()).unwrap_or_else(|e| panic!("{at}: {e}"));
            let toml = read.to_toml().unwrap_or_else(|e| panic!("{at}: {e}"));
            let again = Description::from_toml(&toml).unwrap_or_else(|e| panic!("{at}: {e}"));
            assert_eq!(read, again, "{at}: the TOML round trip");
            let flat: Value = serde_json::from_str(&again.to_json()).unwrap();
            assert_eq!(flat[form.group][0], Value::Object(item), "{at}: the fields written back");
            if let Some(driver) = again.drivers.first() {
                let law =
                    form.fields.iter().find_map(|(_, r)| if let Role::Law(i) = r { Some(*i) } else { None });
                assert_eq!(law.map(|i| i.is_angle()), Some(driver.is_angle()), "{at}: the law's unit");
            }
        }
    }
}
