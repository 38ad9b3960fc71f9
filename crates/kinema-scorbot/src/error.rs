//! The error type of `kinema-scorbot`.

use std::time::Duration;

use kinema::IoError;

/// Everything that can go wrong in `kinema-scorbot`: bad constants or
/// inputs, the kinematics underneath, and every way the controller link can
/// fail. Controller errors carry the raw text the controller sent.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A number outside the range its argument accepts (a speed above 100 %,
    /// a non-positive step, an axis beyond 5…).
    #[error("invalid `{what}`: {}; expected {expected}", number_text(*value))]
    OutOfRange {
        /// Which argument (e.g. `speed`, `max step`).
        what: String,
        /// The offending value.
        value: f64,
        /// The accepted range, in words (e.g. "1 to 100 (% of the maximum speed)").
        expected: String,
    },
    /// Too few items where a list needs some: an empty path, a run of one
    /// point, too few evaluation points.
    #[error("`{what}` has {got} {of}; at least {min} needed")]
    TooFew {
        /// Which argument.
        what: String,
        /// How many it has.
        got: usize,
        /// How many it needs at least.
        min: usize,
        /// What is counted (e.g. "points", "runs").
        of: String,
    },
    /// A list with the wrong number of values (not one per motor, most often).
    #[error("`{what}` has {got} values; {expected} expected ({of})")]
    WrongLength {
        /// Which argument.
        what: String,
        /// How many values it has.
        got: usize,
        /// How many it needs.
        expected: usize,
        /// What they are (e.g. "one per motor of the Scorbot").
        of: String,
    },
    /// A value that must be a finite number and is not.
    #[error("`{what}` is {value}; it must be a finite number")]
    NotFinite {
        /// Which value (e.g. `q[2]`, `point 3 of the path, z`).
        what: String,
        /// The offending value.
        value: f64,
    },
    /// A name that is not one of those an argument accepts.
    #[error("invalid `{what}`: unknown {what} `{name}`; expected one of: {known}")]
    UnknownName {
        /// Which argument (e.g. `plane`, `constants`).
        what: String,
        /// What was asked for.
        name: String,
        /// The accepted names and forms, in words.
        known: String,
    },
    /// Text that does not have the form its argument needs (a fault
    /// specification, a position name, a command line).
    #[error("invalid `{what}`: `{text}`: {expected}")]
    Malformed {
        /// Which argument.
        what: String,
        /// The text as given.
        text: String,
        /// What is wrong with it and the accepted forms.
        expected: String,
    },
    /// A valid value that does not fit the rest of the request (a robot
    /// that is not the 5-joint Scorbot).
    #[error("invalid `{what}`: {reason}")]
    DoesNotFit {
        /// Which argument to change.
        what: String,
        /// Why it does not fit, and what would.
        reason: String,
    },
    /// Arguments that are each valid but admit no result (a path of zero
    /// length, a resampling with too many points).
    #[error("infeasible `{what}`: {reason}")]
    Infeasible {
        /// Which argument to change.
        what: String,
        /// Why nothing fits, with the numbers.
        reason: String,
    },
    /// A path point where every IK solution leaves the joint limits.
    #[error("every solution leaves the joint limits: {}", outside.join("; "))]
    OutsideLimits {
        /// Each solution's branch, with the joints it puts outside their limits.
        outside: Vec<String>,
    },
    /// Something wrong at one point of a path being planned.
    #[error(
        "point {point} of the resampled path (x {:.4}, y {:.4}, z {:.4} m, pitch {:.2}°, roll {:.2}°): {source}",
        at.position.x, at.position.y, at.position.z, at.pitch.to_degrees(), at.roll.to_degrees()
    )]
    AtPathPoint {
        /// 1-based index of the point in the resampled path.
        point: usize,
        /// The point.
        at: crate::follow::PathPoint,
        /// What is wrong there.
        source: Box<Error>,
    },
    /// Something wrong with one model of an experiment.
    #[error("model `{label}`: {source}")]
    ForModel {
        /// The model's label.
        label: String,
        /// What is wrong with it.
        source: Box<Error>,
    },
    /// A robot that the kinematics library does not accept as a Scorbot.
    #[error("{needed_by} needs the Scorbot structure: {source}")]
    NeedsScorbot {
        /// What needs it (e.g. "the calibration model").
        needed_by: String,
        /// Why the robot does not have it.
        source: kinema::Error,
    },
    /// A constants file that is not valid TOML or does not have the
    /// constants' fields.
    #[error("{path}:{line}:{column}: {message}")]
    Toml {
        /// The file as given.
        path: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's description of what is wrong there.
        message: String,
    },
    /// A CSV input whose header or rows do not have the expected form. The
    /// message quotes the offending text: it is there to be read, the line
    /// to be acted on.
    #[error("{path}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    Csv {
        /// The file as given.
        path: String,
        /// 1-based line, when one line is at fault.
        line: Option<usize>,
        /// What is wrong and what was expected.
        message: String,
    },
    /// A file whose content parses but is invalid (a constant out of range).
    #[error("{path}: {source}")]
    InFile {
        /// The file as given.
        path: String,
        /// What is wrong in it.
        source: Box<Error>,
    },
    /// The simulator's record file cannot be written.
    #[error("cannot write the record file `{path}`: {source}")]
    Record {
        /// The file as given.
        path: String,
        /// The operating system's error.
        source: IoError,
    },
    /// The simulator's record holds as many samples as it may; later motions
    /// are not recorded.
    #[error("{path}: {max} samples recorded; later motions are not recorded")]
    RecordFull {
        /// The file as given.
        path: String,
        /// The limit.
        max: usize,
    },
    /// An error of the kinematics library (FK, IK, limits, …).
    #[error(transparent)]
    Kinematics(#[from] kinema::Error),
    /// An operating-system I/O failure: a port or file that cannot be
    /// opened, a write that failed. The OS error is kept as the source.
    #[error("{during}: {source}")]
    Io {
        /// What was being done (e.g. "cannot open serial port /dev/ttyUSB0").
        during: String,
        /// The operating system's error.
        source: IoError,
    },
    /// The simulator's thread panicked (a bug of the simulator).
    #[error("the simulator's thread panicked")]
    SimulatorPanicked,
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
    /// An [`Error::Io`] for `e` while doing `during`.
    pub(crate) fn io(during: impl Into<String>, e: std::io::Error) -> Self {
        Error::Io { during: during.into(), source: e.into() }
    }

    /// An [`Error::OutOfRange`].
    pub(crate) fn out_of_range(what: &str, value: f64, expected: impl Into<String>) -> Self {
        Error::OutOfRange { what: what.into(), value, expected: expected.into() }
    }

    /// An [`Error::NotFinite`].
    pub(crate) fn not_finite(what: impl Into<String>, value: f64) -> Self {
        Error::NotFinite { what: what.into(), value }
    }

    /// An [`Error::TooFew`].
    pub(crate) fn too_few(what: impl Into<String>, got: usize, min: usize, of: &str) -> Self {
        Error::TooFew { what: what.into(), got, min, of: of.into() }
    }
}

/// A number as people read it in a message: plain, or in scientific notation
/// when plain would run to many digits (1e300, 1e-300).
fn number_text(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e15).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}
