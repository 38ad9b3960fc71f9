//! The error type of `kinema-scorbot`.

use std::time::Duration;

/// Everything that can go wrong in `kinema-scorbot`: bad constants or
/// inputs, the kinematics underneath, and every way the controller link can
/// fail. Controller errors carry the raw text the controller sent.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// An argument that is out of its domain (wrong length, not finite, …).
    #[error("invalid {what}: {message}")]
    InvalidArgument {
        /// Which argument.
        what: String,
        /// What is wrong and what was expected.
        message: String,
    },
    /// A constants or data file that cannot be read or parsed.
    #[error("{path}: {message}")]
    File {
        /// The file as given.
        path: String,
        /// What is wrong, with line and column where known.
        message: String,
    },
    /// An error of the kinematics library (FK, IK, limits, …).
    #[error(transparent)]
    Kinematics(#[from] kinema::Error),
    /// The transport failed (port cannot be opened, write failed, …).
    #[error("controller link: {message}")]
    Io {
        /// The operating system's message, with what was being done.
        message: String,
    },
    /// The controller closed the connection.
    #[error("the controller closed the connection while {during}")]
    Disconnected {
        /// What the client was doing.
        during: String,
    },
    /// No complete reply within the timeout.
    #[error(
        "no complete reply from the controller to `{command}` within {timeout:?}; received so far: {}",
        excerpt(received)
    )]
    Timeout {
        /// The command sent.
        command: String,
        /// The timeout that expired.
        timeout: Duration,
        /// Everything received for this command before the timeout.
        received: String,
    },
    /// The controller reported an error or warning (a line with `***`).
    #[error("the controller refused `{command}`: {message}")]
    Controller {
        /// The command sent.
        command: String,
        /// The `***` line, as received.
        message: String,
        /// The whole reply, as received.
        raw: String,
    },
    /// A reply that does not have the expected form.
    #[error("cannot understand the controller's reply to `{command}`: {message}; reply: {}", excerpt(raw))]
    Protocol {
        /// The command sent.
        command: String,
        /// What was expected.
        message: String,
        /// The whole reply, as received.
        raw: String,
    },
    /// A motion command after an earlier failure: the client refuses to move
    /// the arm until the caller has looked at the failure and called
    /// `Client::clear_fault`.
    #[error(
        "motion commands are blocked after an earlier failure ({cause}); call clear_fault() after checking the arm"
    )]
    Faulted {
        /// The earlier failure.
        cause: String,
    },
    /// A calibration the data cannot support: too few samples, parameters
    /// the data do not determine, or no convergence.
    #[error("calibration: {message}")]
    Calibration {
        /// The parameters concerned (e.g. `cg4`, `cg5`); empty if none in particular.
        parameters: Vec<String>,
        /// What is wrong and what would help.
        message: String,
    },
}

/// At most [`EXCERPT_CHARS`] characters of what a controller sent, quoted
/// (its start and end, with how much was left out), so that an error message
/// stays short however much a faulty controller printed.
pub fn excerpt(text: &str) -> String {
    let n = text.chars().count();
    if n <= EXCERPT_CHARS {
        return format!("{text:?}");
    }
    let half = EXCERPT_CHARS / 2;
    let head: String = text.chars().take(half).collect();
    let tail: String = text.chars().skip(n - half).collect();
    format!("{head:?} … ({} characters left out) … {tail:?}", n - 2 * half)
}

/// The longest excerpt of received text an error message quotes.
pub const EXCERPT_CHARS: usize = 400;

/// Result alias of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    pub(crate) fn invalid(what: &str, message: impl Into<String>) -> Self {
        Error::InvalidArgument { what: what.into(), message: message.into() }
    }
}
