//! Why a text is not an expression, and where.

use std::fmt;

/// Why a text is not an expression, and where (1-based character column; 0 when the
/// problem is not in the text, e.g. a bad variable name).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExprError {
    pub column: usize,
    pub message: String,
    /// a suggestion ("did you mean 'sin'?"), if there is one
    pub hint: Option<String>,
}

impl ExprError {
    pub(super) fn new(column: usize, message: impl Into<String>) -> ExprError {
        ExprError { column, message: message.into(), hint: None }
    }
    pub(super) fn hint(mut self, hint: impl Into<String>) -> ExprError {
        self.hint = Some(hint.into());
        self
    }
}

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)?;
        if self.column > 0 {
            write!(f, " at column {}", self.column)?;
        }
        if let Some(h) = &self.hint {
            write!(f, "; {h}")?;
        }
        Ok(())
    }
}

impl std::error::Error for ExprError {}
