//! The description's own text I/O, on the readers and the writer.

use super::writer::write_description;
use super::{read, Format, NO_FILE};
use crate::error::ModelError;
use crate::input::description::Description;

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
