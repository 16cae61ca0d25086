//! Located diagnostics: `FILE:LINE:COLUMN: field.path: what is wrong; what is expected`.

use std::fmt;

/// One problem found in a user's file.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Diagnostic {
    /// The file the problem is in.
    pub file: String,
    /// 1-based line, when the parser knows it.
    pub line: Option<usize>,
    /// 1-based column, when the parser knows it.
    pub column: Option<usize>,
    /// Dotted path of the field, e.g. `objects[3].room`; empty for the whole document.
    pub path: String,
    /// What is wrong.
    pub message: String,
    /// What is expected instead (the fix).
    pub expected: String,
}

impl Diagnostic {
    /// A diagnostic without a known position.
    pub fn new(
        file: impl Into<String>,
        path: impl Into<String>,
        message: impl Into<String>,
        expected: impl Into<String>,
    ) -> Self {
        Self {
            file: file.into(),
            line: None,
            column: None,
            path: path.into(),
            message: message.into(),
            expected: expected.into(),
        }
    }

    /// The same diagnostic at a 1-based line and column.
    pub fn at(mut self, line: usize, column: usize) -> Self {
        self.line = Some(line);
        self.column = Some(column);
        self
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
            if let Some(c) = self.column {
                write!(f, ":{c}")?;
            }
        }
        write!(f, ": ")?;
        if !self.path.is_empty() {
            write!(f, "{}: ", self.path)?;
        }
        write!(f, "{}; {}", self.message, self.expected)
    }
}

/// A list of diagnostics, as a checker collects them.
pub type Diagnostics = Vec<Diagnostic>;
