//! An error as the HTTP API answers it.

use serde::Serialize;

/// The body of an error answer: the message; a program's errors add the
/// rendered diagnostics, a program stopped by its time budget the budget.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorAnswer {
    /// The error in one line.
    pub error: String,
    /// A program's diagnostics, rendered with the source lines.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diagnostics: Option<String>,
    /// The time budget that stopped a program \[s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub budget_s: Option<f64>,
}
