//! Writing model files: the description through the same tree of nodes, TOML or JSON,
//! floats in shortest round-trip form.

use std::fmt::Write as _;

use serde::{Serialize, Serializer};

use super::{join, read, Format, Node, TableEntry, Value, FORMAT_VERSION, LINE_WIDTH, MODEL_KEYS, NO_FILE};
use crate::error::ModelError;
use crate::input::description::Description;

impl Serialize for Node {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::{SerializeMap, SerializeSeq};
        match &self.value {
            Value::Null => s.serialize_unit(),
            Value::Bool(b) => s.serialize_bool(*b),
            Value::Int(i) => s.serialize_i64(*i),
            Value::Float(x) => s.serialize_f64(*x),
            Value::Str(v) => s.serialize_str(v),
            Value::Array(items) => {
                let mut seq = s.serialize_seq(Some(items.len()))?;
                for item in items {
                    seq.serialize_element(item)?;
                }
                seq.end()
            }
            Value::Table(entries) => {
                let mut map = s.serialize_map(Some(entries.len()))?;
                for e in entries {
                    map.serialize_entry(&e.key, &e.node)?;
                }
                map.end()
            }
        }
    }
}

fn plain(path: String, value: Value) -> Node {
    Node { span: 0..0, path, value }
}

/// A description as nodes (for writing), refusing numbers that are not finite.
fn from_description(desc: &Description) -> Result<Node, ModelError> {
    let value = toml::Value::try_from(desc)
        .map_err(|e| ModelError::Description(format!("cannot be written to a file: {e}")))?;
    fn convert(v: toml::Value, path: String) -> Result<Node, ModelError> {
        let value = match v {
            toml::Value::String(s) => Value::Str(s),
            toml::Value::Integer(i) => Value::Int(i),
            toml::Value::Float(x) if x.is_finite() => Value::Float(x),
            toml::Value::Float(x) => {
                return Err(ModelError::Description(format!(
                    "{path} is {x}, not a finite number: a model file cannot hold it"
                )))
            }
            toml::Value::Boolean(b) => Value::Bool(b),
            toml::Value::Datetime(d) => Value::Str(d.to_string()),
            toml::Value::Array(items) => Value::Array(
                items
                    .into_iter()
                    .enumerate()
                    .map(|(k, e)| convert(e, format!("{path}[{k}]")))
                    .collect::<Result<_, _>>()?,
            ),
            toml::Value::Table(t) => Value::Table(
                t.into_iter()
                    .map(|(key, e)| {
                        let node = convert(e, join(&path, &key))?;
                        Ok(TableEntry { key, key_span: 0..0, node })
                    })
                    .collect::<Result<_, ModelError>>()?,
            ),
        };
        Ok(plain(path, value))
    }
    convert(value, String::new())
}

/// The file form of a flat description: the `model` header first (name, version, units,
/// gravity; units always written), then the element arrays.
fn file_form(flat: &Node) -> Node {
    let entries = flat.entries().unwrap_or_default();
    let mut header = Vec::new();
    let entry = |key: &str, value: Value| TableEntry {
        key: key.into(),
        key_span: 0..0,
        node: plain(key.into(), value),
    };
    if let Some(e) = flat.get("name") {
        header.push(e.clone());
    }
    header.push(entry("version", Value::Int(FORMAT_VERSION)));
    match flat.get("units") {
        Some(e) => header.push(e.clone()),
        None => header.push(entry(
            "units",
            Value::Table(vec![
                entry("length", Value::Str("m".into())),
                entry("angle", Value::Str("rad".into())),
            ]),
        )),
    }
    for key in ["gravity", "outputs", "branch", "close", "free", "initial_rates"] {
        if let Some(e) = flat.get(key) {
            header.push(e.clone());
        }
    }
    let mut out = vec![entry("model", Value::Table(header))];
    // empty lists are left out (absent means empty), in JSON as in TOML, which cannot
    // write an empty array of tables after the header
    let empty = |e: &TableEntry| matches!(&e.node.value, Value::Array(items) if items.is_empty());
    out.extend(entries.iter().filter(|e| !MODEL_KEYS.contains(&e.key.as_str()) && !empty(e)).cloned());
    plain(String::new(), Value::Table(out))
}

/// Writes a flat description (as read, or as the Python package holds it) as a model
/// file; the text is checked against the schema first, so only readable files are written.
pub fn write(flat_text: &str, format: Format) -> Result<String, ModelError> {
    let flat = read(flat_text, Format::Json, NO_FILE)?.flat;
    Ok(write_flat(&flat, format))
}

/// Writes a description as a model file.
pub fn write_description(desc: &Description, format: Format) -> Result<String, ModelError> {
    Ok(write_flat(&from_description(desc)?, format))
}

fn write_flat(flat: &Node, format: Format) -> String {
    let file = file_form(flat);
    match format {
        Format::Json => {
            let mut text = serde_json::to_string_pretty(&file).unwrap_or_default();
            text.push('\n');
            text
        }
        Format::Toml => toml_text(&file),
    }
}

fn toml_key(key: &str) -> String {
    let bare = !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare {
        key.to_string()
    } else {
        toml::Value::String(key.to_string()).to_string()
    }
}

/// Shortest text that reads back as the same f64 (Rust's float formatting), in TOML's
/// and JSON's grammar (a decimal point or an exponent).
fn float_text(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains(['.', 'e', 'E']) {
        s
    } else {
        format!("{s}.0")
    }
}

fn inline(node: &Node) -> String {
    match &node.value {
        Value::Null => String::new(),
        Value::Bool(b) => b.to_string(),
        Value::Int(i) => i.to_string(),
        Value::Float(x) => float_text(*x),
        Value::Str(s) => toml::Value::String(s.clone()).to_string(),
        Value::Array(items) => format!("[{}]", items.iter().map(inline).collect::<Vec<_>>().join(", ")),
        Value::Table(entries) => {
            let fields: Vec<String> = entries
                .iter()
                .filter(|e| e.node.value != Value::Null)
                .map(|e| format!("{} = {}", toml_key(&e.key), inline(&e.node)))
                .collect();
            if fields.is_empty() {
                "{}".into()
            } else {
                format!("{{ {} }}", fields.join(", "))
            }
        }
    }
}

fn is_table_array(node: &Node) -> bool {
    matches!(&node.value, Value::Array(items) if !items.is_empty()
        && items.iter().all(|i| matches!(i.value, Value::Table(_))))
}

/// A long array of scalars over several lines, a few values a line.
fn wrapped(items: &[Node], indent: &str) -> String {
    let mut out = String::from("[\n");
    let mut line = String::new();
    for item in items {
        let text = inline(item);
        if !line.is_empty() && indent.len() + line.len() + text.len() + 2 > LINE_WIDTH {
            let _ = writeln!(out, "{indent}{}", line.trim_end());
            line.clear();
        }
        line.push_str(&text);
        line.push_str(", ");
    }
    if !line.is_empty() {
        let _ = writeln!(out, "{indent}{}", line.trim_end());
    }
    out.push(']');
    out
}

/// Writes a table's entries under the header `path` has already been given: short values
/// as `key = value`, then the long tables and arrays of tables under their own headers.
fn toml_body(out: &mut String, entries: &[TableEntry], path: &str) {
    let mut later = Vec::new();
    for e in entries {
        if e.node.value == Value::Null {
            continue; // an absent optional field
        }
        let key = toml_key(&e.key);
        let text = inline(&e.node);
        let long = key.len() + 3 + text.len() > LINE_WIDTH;
        match &e.node.value {
            Value::Table(_) if long => later.push(e),
            Value::Array(_) if long && is_table_array(&e.node) => later.push(e),
            Value::Array(items) if long => {
                let _ = writeln!(out, "{key} = {}", wrapped(items, "    "));
            }
            _ => {
                let _ = writeln!(out, "{key} = {text}");
            }
        }
    }
    for e in later {
        let sub = format!("{path}.{}", toml_key(&e.key));
        match &e.node.value {
            Value::Table(inner) => {
                let _ = write!(out, "\n[{sub}]\n");
                toml_body(out, inner, &sub);
            }
            Value::Array(items) => {
                for item in items {
                    let _ = write!(out, "\n[[{sub}]]\n");
                    toml_body(out, item.entries().unwrap_or_default(), &sub);
                }
            }
            _ => {}
        }
    }
}

fn toml_text(file: &Node) -> String {
    let mut out = format!("# linkwork model file, format version {FORMAT_VERSION}\n");
    for e in file.entries().unwrap_or_default() {
        let key = toml_key(&e.key);
        match &e.node.value {
            Value::Table(inner) => {
                let _ = write!(out, "\n[{key}]\n");
                toml_body(&mut out, inner, &key);
            }
            Value::Array(items) if is_table_array(&e.node) => {
                for item in items {
                    let _ = write!(out, "\n[[{key}]]\n");
                    toml_body(&mut out, item.entries().unwrap_or_default(), &key);
                }
            }
            // a flat description checked against the schema holds nothing else
            _ => {}
        }
    }
    out
}

/// The flat JSON of a read file (what the Python package holds).
pub fn flat_json(flat: &Node) -> String {
    serde_json::to_string(flat).unwrap_or_default()
}
