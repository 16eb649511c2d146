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

use std::fmt::Write as _;
use std::ops::Range;

use serde::de::{self, DeserializeSeed, IntoDeserializer, Visitor};
use serde::{Deserialize, Serialize, Serializer};

use crate::error::ModelError;
use crate::input::description::Description;

/// The model-file format version this linkwork writes, and the newest it reads.
pub const FORMAT_VERSION: i64 = 1;

/// The name errors give text that did not come from a file.
pub const NO_FILE: &str = "model description";

/// The keys of the `model` header table.
const MODEL_KEYS: [&str; 7] = ["name", "version", "units", "gravity", "outputs", "branch", "close"];

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
                "the model header is a table (name, version, units, gravity, outputs, branch, close), not {}",
                node.kind()
            );
            return Err(DeError { message, span: Some(node.span), path: Some(node.path) });
        };
        for m in inner {
            if !MODEL_KEYS.contains(&m.key.as_str()) {
                let message = format!(
                    "unknown field `{}` in the model header, expected one of `name`, `version`, `units`, `gravity`, \
                     `outputs`, `branch`, `close`",
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

// -- the tree as a serde Deserializer ----------------------------------------------

impl<'de> de::Deserializer<'de> for &Node {
    type Error = DeError;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, DeError> {
        match &self.value {
            Value::Null => visitor.visit_unit(),
            Value::Bool(b) => visitor.visit_bool(*b),
            Value::Int(i) => visitor.visit_i64(*i),
            Value::Float(x) => visitor.visit_f64(*x),
            Value::Str(s) => visitor.visit_str(s),
            Value::Array(items) => {
                let mut seq = Seq { iter: items.iter() };
                let out = visitor.visit_seq(&mut seq)?;
                let left = seq.iter.len();
                if left > 0 {
                    let wanted = format!("{} elements", items.len() - left);
                    return Err(de::Error::invalid_length(items.len(), &wanted.as_str()));
                }
                Ok(out)
            }
            Value::Table(entries) => visitor.visit_map(Map { iter: entries.iter(), skip: None, value: None }),
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, DeError> {
        match self.value {
            Value::Null => visitor.visit_none(),
            _ => visitor.visit_some(self),
        }
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, DeError> {
        visitor.visit_newtype_struct(self)
    }

    /// A string is a unit variant; a table is the variant its `type` names, with the
    /// table's other keys as its fields.
    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, DeError> {
        match &self.value {
            Value::Str(s) => visitor.visit_enum(s.as_str().into_deserializer()),
            Value::Table(entries) => match entries.iter().find(|e| e.key == TAG) {
                Some(tag) => visitor.visit_enum(Tagged { node: self, tag }),
                None => Err(DeError::new(
                    format!("missing field `type`: say which kind, one of `{}`", variants.join("`, `")),
                    self,
                )
                .at_path(join(&self.path, TAG))),
            },
            _ => Err(de::Error::invalid_type(unexpected(self), &visitor)),
        }
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf unit
        unit_struct seq tuple tuple_struct map struct identifier ignored_any
    }
}

impl DeError {
    fn at_path(mut self, path: String) -> Self {
        self.path = Some(path);
        self
    }
}

fn unexpected(node: &Node) -> de::Unexpected<'_> {
    match &node.value {
        Value::Null => de::Unexpected::Unit,
        Value::Bool(b) => de::Unexpected::Bool(*b),
        Value::Int(i) => de::Unexpected::Signed(*i),
        Value::Float(x) => de::Unexpected::Float(*x),
        Value::Str(s) => de::Unexpected::Str(s),
        Value::Array(_) => de::Unexpected::Seq,
        Value::Table(_) => de::Unexpected::Map,
    }
}

struct Seq<'a> {
    iter: std::slice::Iter<'a, Node>,
}

impl<'de> de::SeqAccess<'de> for Seq<'_> {
    type Error = DeError;

    fn next_element_seed<T: DeserializeSeed<'de>>(&mut self, seed: T) -> Result<Option<T::Value>, DeError> {
        match self.iter.next() {
            None => Ok(None),
            Some(node) => seed.deserialize(node).map(Some).map_err(|e| e.at(node)),
        }
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.iter.len())
    }
}

struct Map<'a> {
    iter: std::slice::Iter<'a, TableEntry>,
    /// a key read already (the `type` of a tagged table)
    skip: Option<&'static str>,
    value: Option<&'a Node>,
}

impl<'de> de::MapAccess<'de> for Map<'_> {
    type Error = DeError;

    fn next_key_seed<K: DeserializeSeed<'de>>(&mut self, seed: K) -> Result<Option<K::Value>, DeError> {
        for e in self.iter.by_ref() {
            if Some(e.key.as_str()) == self.skip {
                continue;
            }
            self.value = Some(&e.node);
            let key: de::value::StrDeserializer<'_, DeError> = e.key.as_str().into_deserializer();
            return seed.deserialize(key).map(Some).map_err(|err| err.at_key(e));
        }
        Ok(None)
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, DeError> {
        let node = self.value.take().ok_or_else(|| de::Error::custom("a value was read before its key"))?;
        seed.deserialize(node).map_err(|e| e.at(node))
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.iter.len())
    }
}

/// A table whose `type` says which variant it is.
struct Tagged<'a> {
    node: &'a Node,
    tag: &'a TableEntry,
}

impl<'de, 'a> de::EnumAccess<'de> for Tagged<'a> {
    type Error = DeError;
    type Variant = Tagged<'a>;

    fn variant_seed<V: DeserializeSeed<'de>>(self, seed: V) -> Result<(V::Value, Self::Variant), DeError> {
        let tag = &self.tag.node;
        let Value::Str(name) = &tag.value else {
            return Err(DeError::new(format!("the kind is a string, not {}", tag.kind()), tag));
        };
        let name: de::value::StrDeserializer<'_, DeError> = name.as_str().into_deserializer();
        let v = seed.deserialize(name).map_err(|e| e.at(tag))?;
        Ok((v, self))
    }
}

impl<'de> de::VariantAccess<'de> for Tagged<'_> {
    type Error = DeError;

    fn unit_variant(self) -> Result<(), DeError> {
        match self.node.entries() {
            Some(e) if e.len() == 1 => Ok(()),
            _ => Err(DeError::new("this kind takes no other fields", self.node)),
        }
    }

    fn newtype_variant_seed<T: DeserializeSeed<'de>>(self, seed: T) -> Result<T::Value, DeError> {
        let entries = self.node.entries().unwrap_or_default();
        let map = Map { iter: entries.iter(), skip: Some(TAG), value: None };
        seed.deserialize(de::value::MapAccessDeserializer::new(map))
    }

    fn tuple_variant<V: Visitor<'de>>(self, _len: usize, _visitor: V) -> Result<V::Value, DeError> {
        Err(DeError::new("a tuple kind cannot be read from a table", self.node))
    }

    fn struct_variant<V: Visitor<'de>>(
        self,
        _fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, DeError> {
        let entries = self.node.entries().unwrap_or_default();
        visitor.visit_map(Map { iter: entries.iter(), skip: Some(TAG), value: None })
    }
}

// -- writing -------------------------------------------------------------------------

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
    for key in ["gravity", "outputs", "branch", "close"] {
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
// The description's own text I/O, here with the readers and the writer it calls.
impl Description {
    /// Reads a description from JSON (a model file, or the flat form `to_json` writes);
    /// errors name the line, column and field.
    pub fn from_json(text: &str) -> Result<Self, ModelError> {
        Ok(read(text, Format::Json, NO_FILE)?.description)
    }

    /// Reads a description from a TOML model file's text.
    pub fn from_toml(text: &str) -> Result<Self, ModelError> {
        Ok(read(text, Format::Toml, NO_FILE)?.description)
    }

    /// The flat description as JSON: name, units, bodies, joints, ... at the top (the form
    /// the Python package holds); `from_json` reads it back.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a description always serialises")
    }

    /// A TOML model file: a `[model]` header, then `[[bodies]]`, `[[joints]]`, ... tables.
    /// Fails only on a number that is not finite (a file cannot hold it).
    pub fn to_toml(&self) -> Result<String, ModelError> {
        write_description(self, Format::Toml)
    }

    /// A JSON model file, laid out as the TOML one (`model` header object first).
    pub fn to_json_file(&self) -> Result<String, ModelError> {
        write_description(self, Format::Json)
    }
}
