//! Model files, TOML and JSON, one schema: a `model` header table (name, format version,
//! units, gravity), then the arrays `bodies`, `joints`, `drivers`, `points`, `loads`.
//! The flat form (name, units, gravity beside the arrays, no version) is the form of
//! JSON written before format versions existed, and of the Python package's dicts; it
//! reads as version 1.
//!
//! Both formats are parsed into one tree of `Node`s that remember where they were
//! written (a byte span) and where they sit in the model (a field path such as
//! `joints[2].at`); a serde `Deserializer` over that tree reads the `Description`, so a
//! syntax error, a wrong type, a missing field or an unknown key all name the file, line,
//! column and field. Writing goes through the same tree, so what is read is written back
//! as it was: same keys, same numbers (floats in shortest round-trip form).

use std::ops::Range;

use serde::de;
use serde::Deserialize;

use crate::error::ModelError;
use crate::input::description::Description;

mod deserializer;
mod text_io;
pub mod writer;

pub use writer::{flat_json, write, write_description};

/// The model-file format version this linkwork writes, and the newest it reads.
pub const FORMAT_VERSION: i64 = 1;

/// The name errors give text that did not come from a file.
pub const NO_FILE: &str = "model description";

/// The keys of the `model` header table.
const MODEL_KEYS: [&str; 9] =
    ["name", "version", "units", "gravity", "outputs", "branch", "close", "free", "initial_rates"];

/// The element lists, in file order, with the kind errors call their elements.
const GROUPS: [(&str, &str); 5] =
    [("bodies", "body"), ("joints", "joint"), ("drivers", "driver"), ("points", "point"), ("loads", "load")];

/// The key that names an element's kind (joint, driver, load and law type).
const TAG: &str = "type";

/// Lines of TOML longer than this put a law (or any table) under its own header.
const LINE_WIDTH: usize = 100;

/// A model file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Toml,
    Json,
}

impl Format {
    /// The format of a file, from its extension (.toml or .json, any case).
    pub fn from_path(path: &str) -> Option<Format> {
        let ext = std::path::Path::new(path).extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "toml" => Some(Format::Toml),
            "json" => Some(Format::Json),
            _ => None,
        }
    }

    /// "toml" or "json".
    pub fn from_name(name: &str) -> Option<Format> {
        match name {
            "toml" => Some(Format::Toml),
            "json" => Some(Format::Json),
            _ => None,
        }
    }
}

/// A value read from a file: where it was written and where it sits in the model.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// bytes of the file text (0..0 for values that never were in a file)
    pub span: Range<usize>,
    /// field path, e.g. `joints[2].at` (empty for the whole file)
    pub path: String,
    pub value: Value,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Null,
    Bool(bool),
    Int(i64),
    /// always finite: files cannot hold other numbers (the readers refuse them)
    Float(f64),
    Str(String),
    Array(Vec<Node>),
    /// entries in the order written
    Table(Vec<TableEntry>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct TableEntry {
    pub key: String,
    pub key_span: Range<usize>,
    pub node: Node,
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

impl Node {
    fn entries(&self) -> Option<&[TableEntry]> {
        match &self.value {
            Value::Table(e) => Some(e),
            _ => None,
        }
    }

    fn get(&self, key: &str) -> Option<&TableEntry> {
        self.entries()?.iter().find(|e| e.key == key)
    }

    /// What the value is, for messages.
    fn kind(&self) -> &'static str {
        match self.value {
            Value::Null => "null",
            Value::Bool(_) => "a boolean",
            Value::Int(_) => "an integer",
            Value::Float(_) => "a number",
            Value::Str(_) => "a string",
            Value::Array(_) => "an array",
            Value::Table(_) => "a table",
        }
    }
}

// -- errors ------------------------------------------------------------------------------

/// An error while reading the tree: the message, and once known, where and which field.
#[derive(Debug)]
pub struct DeError {
    message: String,
    span: Option<Range<usize>>,
    path: Option<String>,
}

impl std::fmt::Display for DeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for DeError {}

impl de::Error for DeError {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        DeError { message: msg.to_string(), span: None, path: None }
    }
}

/// The name in backquotes right after `prefix` in serde's messages ("missing field `at`").
fn quoted_after<'m>(message: &'m str, prefix: &str) -> Option<&'m str> {
    let rest = message.strip_prefix(prefix)?;
    rest.split('`').next()
}

impl DeError {
    fn new(message: impl Into<String>, node: &Node) -> Self {
        DeError { message: message.into(), span: Some(node.span.clone()), path: Some(node.path.clone()) }
    }

    /// Places an error raised while reading `node`, unless a deeper node already did. In
    /// a table, a missing, unknown or repeated field, or an unknown `type`, is placed on
    /// that field (serde's internally tagged laws report them only for the whole table).
    fn at(mut self, node: &Node) -> Self {
        if self.span.is_some() {
            return self;
        }
        let (mut span, mut path) = (node.span.clone(), node.path.clone());
        if let Some(entries) = node.entries() {
            let m = &self.message;
            if let Some(field) = quoted_after(m, "missing field `") {
                path = join(&node.path, field);
            } else if let Some(field) =
                quoted_after(m, "unknown field `").or_else(|| quoted_after(m, "duplicate field `"))
            {
                if let Some(e) = entries.iter().rev().find(|e| e.key == field) {
                    (span, path) = (e.key_span.clone(), e.node.path.clone());
                }
            } else if m.starts_with("unknown variant `") {
                if let Some(e) = entries.iter().find(|e| e.key == TAG) {
                    (span, path) = (e.node.span.clone(), e.node.path.clone());
                }
            }
        }
        self.span = Some(span);
        self.path = Some(path);
        self
    }

    fn at_key(mut self, e: &TableEntry) -> Self {
        if self.span.is_none() {
            self.span = Some(e.key_span.clone());
            self.path = Some(e.node.path.clone());
        }
        self
    }

    fn into_model_error(self, text: &str, file: &str) -> ModelError {
        let (line, column) = line_column(text, self.span.map_or(0, |s| s.start));
        ModelError::File {
            file: file.to_string(),
            line,
            column,
            field: self.path.unwrap_or_default(),
            message: self.message,
        }
    }
}

/// 1-based line and column (in characters) of a byte offset.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[start..].chars().count() + 1)
}

fn syntax_error(text: &str, file: &str, offset: usize, message: &str) -> ModelError {
    let (line, column) = line_column(text, offset);
    // parsers' messages may run over several lines; a model error is one line
    let message = message.split_whitespace().collect::<Vec<_>>().join(" ");
    ModelError::File { file: file.to_string(), line, column, field: String::new(), message }
}

// -- parsing into nodes --------------------------------------------------------------

fn not_finite(node_span: Range<usize>, path: &str, v: f64) -> DeError {
    DeError {
        message: format!("{v} is not a finite number"),
        span: Some(node_span),
        path: Some(path.to_string()),
    }
}

fn from_toml(v: &toml::Spanned<toml::de::DeValue<'_>>, path: String) -> Result<Node, DeError> {
    use toml::de::DeValue;
    let span = v.span();
    let value = match v.get_ref() {
        DeValue::String(s) => Value::Str(s.to_string()),
        DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
            Ok(i) => Value::Int(i),
            Err(_) => {
                let message = format!("integer {i} is out of range");
                return Err(DeError { message, span: Some(span), path: Some(path) });
            }
        },
        DeValue::Float(f) => match f.as_str().parse::<f64>() {
            Ok(x) if x.is_finite() => Value::Float(x),
            _ => return Err(not_finite(span, &path, f.as_str().parse().unwrap_or(f64::NAN))),
        },
        DeValue::Boolean(b) => Value::Bool(*b),
        DeValue::Datetime(d) => {
            let message = format!("a date or time ({d}) is not a model value");
            return Err(DeError { message, span: Some(span), path: Some(path) });
        }
        DeValue::Array(items) => Value::Array(
            items
                .iter()
                .enumerate()
                .map(|(k, e)| from_toml(e, format!("{path}[{k}]")))
                .collect::<Result<_, _>>()?,
        ),
        DeValue::Table(t) => Value::Table(
            t.iter()
                .map(|(k, e)| {
                    let key = k.get_ref().to_string();
                    let node = from_toml(e, join(&path, &key))?;
                    Ok(TableEntry { key, key_span: k.span(), node })
                })
                .collect::<Result<_, DeError>>()?,
        ),
    };
    Ok(Node { span, path, value })
}

fn from_json(v: jsonc_parser::ast::Value<'_>, path: String) -> Result<Node, DeError> {
    use jsonc_parser::ast::Value as J;
    use jsonc_parser::common::Ranged;
    let range = |r: jsonc_parser::common::Range| r.start..r.end;
    let (span, value) = match v {
        J::StringLit(s) => (range(s.range), Value::Str(s.value.into_owned())),
        J::NumberLit(n) => {
            let span = range(n.range);
            let integer = !n.value.contains(['.', 'e', 'E']);
            match (integer, n.value.parse::<i64>(), n.value.parse::<f64>()) {
                (true, Ok(i), _) => (span, Value::Int(i)),
                (_, _, Ok(x)) if x.is_finite() => (span, Value::Float(x)),
                (_, _, x) => return Err(not_finite(span, &path, x.unwrap_or(f64::NAN))),
            }
        }
        J::BooleanLit(b) => (range(b.range), Value::Bool(b.value)),
        J::NullKeyword(n) => (range(n.range), Value::Null),
        J::Array(a) => {
            let span = range(a.range);
            let items = a
                .elements
                .into_iter()
                .enumerate()
                .map(|(k, e)| from_json(e, format!("{path}[{k}]")))
                .collect::<Result<_, _>>()?;
            (span, Value::Array(items))
        }
        J::Object(o) => {
            let span = range(o.range);
            let entries = o
                .properties
                .into_iter()
                .map(|p| {
                    let key_span = range(p.name.range());
                    let key = p.name.into_string();
                    let node = from_json(p.value, join(&path, &key))?;
                    Ok(TableEntry { key, key_span, node })
                })
                .collect::<Result<_, DeError>>()?;
            (span, Value::Table(entries))
        }
    };
    Ok(Node { span, path, value })
}

/// Parses file text into nodes (syntax only).
pub fn parse(text: &str, format: Format, file: &str) -> Result<Node, ModelError> {
    let root = match format {
        Format::Toml => {
            let table = toml::de::DeTable::parse(text)
                .map_err(|e| syntax_error(text, file, e.span().map_or(0, |s| s.start), e.message()))?;
            let spanned = toml::Spanned::new(table.span(), toml::de::DeValue::Table(table.into_inner()));
            from_toml(&spanned, String::new())
        }
        Format::Json => {
            let strict = jsonc_parser::ParseOptions {
                allow_comments: false,
                allow_loose_object_property_names: false,
                allow_trailing_commas: false,
                allow_missing_commas: false,
                allow_single_quoted_strings: false,
                allow_hexadecimal_numbers: false,
                allow_unary_plus_numbers: false,
                allow_bare_decimal_point_numbers: false,
                allow_non_finite_numbers: false,
                allow_extended_string_escapes: false,
            };
            let parsed = jsonc_parser::parse_to_ast(text, &Default::default(), &strict)
                .map_err(|e| syntax_error(text, file, e.range().start, &e.kind().to_string()))?;
            match parsed.value {
                Some(v) => from_json(v, String::new()),
                None => return Err(syntax_error(text, file, 0, "the file is empty")),
            }
        }
    };
    root.map_err(|e| e.into_model_error(text, file))
}

// -- the model header and the version ----------------------------------------------

/// The flat form of a file's root: the `model` table's keys lifted beside the arrays, the
/// format version checked and removed.
fn flatten(root: Node) -> Result<Node, DeError> {
    let Value::Table(entries) = root.value else {
        let message =
            format!("a model file holds a table (TOML) or an object (JSON) at the top, not {}", root.kind());
        return Err(DeError::new(message, &root));
    };
    let mut flat: Vec<TableEntry> = Vec::with_capacity(entries.len() + MODEL_KEYS.len());
    let push = |e: TableEntry, flat: &mut Vec<TableEntry>| -> Result<(), DeError> {
        if let Some(first) = flat.iter().find(|f| f.key == e.key) {
            let message =
                format!("`{}` is given twice (as {} and as {})", e.key, first.node.path, e.node.path);
            return Err(DeError { message, span: Some(e.key_span), path: Some(e.node.path) });
        }
        flat.push(e);
        Ok(())
    };
    for e in entries {
        if e.key != "model" {
            push(e, &mut flat)?;
            continue;
        }
        let node = e.node;
        let Value::Table(inner) = node.value else {
            let message = format!(
                "the model header is a table (name, version, units, gravity, outputs, branch, close, free, \
                 initial_rates), not {}",
                node.kind()
            );
            return Err(DeError { message, span: Some(node.span), path: Some(node.path) });
        };
        for m in inner {
            if !MODEL_KEYS.contains(&m.key.as_str()) {
                let message = format!(
                    "unknown field `{}` in the model header, expected one of `name`, `version`, `units`, `gravity`, \
                     `outputs`, `branch`, `close`, `free`, `initial_rates`",
                    m.key
                );
                return Err(DeError { message, span: Some(m.key_span), path: Some(m.node.path) });
            }
            push(m, &mut flat)?;
        }
    }
    if let Some(k) = flat.iter().position(|e| e.key == "version") {
        let v = flat.remove(k).node;
        match v.value {
            Value::Int(n) if (1..=FORMAT_VERSION).contains(&n) => {}
            Value::Int(n) if n > FORMAT_VERSION => {
                let message = format!(
                    "this file is model format version {n}; this linkwork reads versions up to \
                     {FORMAT_VERSION}: update linkwork to read it"
                );
                return Err(DeError::new(message, &v));
            }
            Value::Int(n) => {
                return Err(DeError::new(format!("model format versions start at 1, not {n}"), &v));
            }
            _ => {
                let message = format!(
                    "the format version is an integer ({FORMAT_VERSION} for this one), not {}",
                    v.kind()
                );
                return Err(DeError::new(message, &v));
            }
        }
    }
    Ok(Node { span: root.span, path: root.path, value: Value::Table(flat) })
}

/// Where each element of a file starts: errors found when compiling name the element; a
/// file's source map adds its line.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SourceMap {
    pub file: String,
    /// (kind, name, line) of every named element, in file order
    pub elements: Vec<(&'static str, String, usize)>,
}

impl SourceMap {
    fn new(flat: &Node, text: &str, file: &str) -> SourceMap {
        // the newlines' offsets once: an element's line by binary search, so that a large
        // description (a one-line JSON of thousands of elements) is read in linear time
        let newlines: Vec<usize> = text.match_indices('\n').map(|(i, _)| i).collect();
        let line_of = |offset: usize| newlines.partition_point(|&i| i < offset) + 1;
        let mut elements = Vec::new();
        for (group, kind) in GROUPS {
            let Some(TableEntry { node: Node { value: Value::Array(items), .. }, .. }) = flat.get(group)
            else {
                continue;
            };
            for item in items {
                if let Some(TableEntry { node: Node { value: Value::Str(name), .. }, .. }) = item.get("name")
                {
                    elements.push((kind, name.clone(), line_of(item.span.start)));
                }
            }
        }
        SourceMap { file: file.to_string(), elements }
    }

    /// The line where an element starts (the last one of that kind and name: for a
    /// duplicate name, the second use is the one at fault).
    pub fn line(&self, kind: &str, name: &str) -> Option<usize> {
        self.elements.iter().rev().find(|(k, n, _)| *k == kind && n == name).map(|e| e.2)
    }

    /// The error with the line of its element, when it names one of this file.
    pub fn locate(&self, error: ModelError) -> ModelError {
        let line = error.element().and_then(|(kind, name)| self.line(kind, name));
        match line {
            Some(line) if !matches!(error, ModelError::Located { .. }) => {
                ModelError::Located { file: self.file.clone(), line, error: Box::new(error) }
            }
            _ => error,
        }
    }
}

/// A model file read: its description, its flat form as written, and where its
/// elements start.
#[derive(Debug, Clone)]
pub struct ModelFile {
    pub description: Description,
    /// the flat form (no `model` header, no version; units only when not m and rad),
    /// keys and numbers as written
    pub flat: Node,
    pub source: SourceMap,
}

/// Reads a model file, its format chosen by its extension (.toml or .json).
pub fn read_path(path: &std::path::Path) -> Result<ModelFile, ModelError> {
    let name = path.display().to_string();
    let format = Format::from_path(&name)
        .ok_or_else(|| ModelError::Description(format!("{name}: a model file ends in .toml or .json")))?;
    let text = std::fs::read_to_string(path).map_err(|e| ModelError::Description(format!("{name}: {e}")))?;
    read(&text, format, &name)
}

/// Reads a model file's text; `file` names it in errors.
pub fn read(text: &str, format: Format, file: &str) -> Result<ModelFile, ModelError> {
    let root = parse(text, format, file)?;
    let mut flat = flatten(root).map_err(|e| e.into_model_error(text, file))?;
    let description =
        Description::deserialize(&flat).map_err(|e| e.at(&flat).into_model_error(text, file))?;
    // the default units are the absence of units: dicts and files round-trip either way
    if description.units.is_default() {
        if let Value::Table(entries) = &mut flat.value {
            entries.retain(|e| e.key != "units");
        }
    }
    let source = SourceMap::new(&flat, text, file);
    Ok(ModelFile { description, flat, source })
}
