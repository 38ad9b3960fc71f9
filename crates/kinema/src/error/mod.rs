//! The error type of the core library, and the data its variants carry.

mod unreachable;
mod violation;

pub use unreachable::{Closest, Tolerance, Unreachable};
pub use violation::{Violation, ViolationKind};

/// Everything that can go wrong in `kinema`. Each variant carries what was
/// wrong and, where it helps, what was expected.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A joint vector of the wrong length.
    #[error("robot `{robot}` has {expected} joints, but {got} joint values were given")]
    JointCount {
        /// Robot name.
        robot: String,
        /// Number of joints of the robot.
        expected: usize,
        /// Number of values given.
        got: usize,
    },
    /// A joint value that is NaN, infinite, or beyond ±[`crate::MAX_MAGNITUDE`].
    #[error("joint {joint} (`{name}`) of robot `{robot}` is {value}; joint values must be finite numbers within ±1e9")]
    BadJointValue {
        /// Robot name.
        robot: String,
        /// 1-based joint index.
        joint: usize,
        /// Joint name.
        name: String,
        /// The offending value.
        value: f64,
    },
    /// A name that is not one of the built-in robots (and not a file).
    #[error(
        "unknown robot `{name}`: not a built-in robot and not a .toml or .urdf file; built-in robots are: {known}"
    )]
    UnknownRobot {
        /// What was asked for.
        name: String,
        /// Comma-separated list of the built-in robots.
        known: String,
    },
    /// A named configuration the robot does not have.
    #[error("robot `{robot}` has no named pose `{pose}`; its poses are: {known}")]
    UnknownPose {
        /// Robot name.
        robot: String,
        /// What was asked for.
        pose: String,
        /// Comma-separated list of the robot's poses.
        known: String,
    },
    /// A robot description file (TOML, or a URDF element) that is malformed
    /// or inconsistent.
    #[error("{file}:{line}:{column}: `{field}`: {message}")]
    Description {
        /// File name (or `<string>`).
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Path of the offending field, e.g. `joint[2].min`, or the URDF
        /// element, e.g. `<joint name="j2">`.
        field: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// A URDF file that cannot be used.
    #[error("{file}: {message}")]
    Urdf {
        /// File name (or `<string>`).
        file: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// A URDF chain with a joint that follows another (`<mimic>`): kinema
    /// models independent joints only, and will not move a coupled joint as
    /// if it were free.
    #[error(
        "{file}:{line}: joint `{joint}` on the chain mimics joint `{follows}` (q = {multiplier}·q[{follows}] + {offset}); \
         kinema models independent joints only: choose a tip whose chain has no <mimic> joint (--tip LINK), \
         or remove the <mimic> element to move `{joint}` on its own"
    )]
    MimicJoint {
        /// File name (or `<string>`).
        file: String,
        /// 1-based line of the `<joint>` element.
        line: usize,
        /// The joint with the `<mimic>` element.
        joint: String,
        /// The joint it follows.
        follows: String,
        /// Its `multiplier` (1 when not given).
        multiplier: f64,
        /// Its `offset` \[rad or m\] (0 when not given).
        offset: f64,
    },
    /// A file that cannot be read.
    #[error("cannot read `{path}`: {source}")]
    Io {
        /// Path as given.
        path: String,
        /// The operating system's error.
        source: IoError,
    },
    /// A file larger than the limit for its kind (a FIFO or `/dev/zero` given
    /// by mistake, most often).
    #[error("cannot read `{path}`: the file is larger than the limit of {} for {what}", size_text(*limit))]
    FileTooLarge {
        /// Path as given.
        path: String,
        /// What the file was read as (e.g. "a robot description").
        what: String,
        /// The limit \[bytes\].
        limit: u64,
    },
    /// A robot whose structure an IK solver family does not handle.
    #[error("the {solver} solver does not fit robot `{robot}`: {reason}")]
    UnsupportedStructure {
        /// The solver family.
        solver: String,
        /// Robot name.
        robot: String,
        /// What structure the solver needs and what the robot has.
        reason: String,
    },
    /// A model that is internally inconsistent (built in code, not from a file).
    #[error("invalid robot model `{robot}`: {message}")]
    InvalidModel {
        /// Robot name.
        robot: String,
        /// What is wrong.
        message: String,
    },
    /// Roll-pitch-yaw rates are undefined at this orientation.
    #[error("roll-pitch-yaw rates are undefined at pitch = {pitch} rad (representation singularity at ±π/2); use the geometric Jacobian there")]
    RpySingularity {
        /// Middle angle of the triple \[rad\].
        pitch: f64,
    },
    /// An inverse-kinematics target that cannot be reached, and why.
    #[error("unreachable target ({solver} solver): {reason}{}", closest_phrase(closest))]
    Unreachable {
        /// Which solver decided.
        solver: String,
        /// Why.
        reason: Unreachable,
        /// The configuration that came closest, when the solver found one.
        closest: Option<Box<Closest>>,
    },
    /// A sample of a Cartesian path that failed (IK, most often).
    #[error("at t = {t:.4} s of the path: {source}")]
    OnPath {
        /// Time of the sample along the path \[s\].
        t: f64,
        /// What went wrong there.
        source: Box<Error>,
    },
    /// The work was interrupted before it finished (Ctrl-C, a deadline).
    #[error("cancelled before it finished")]
    Cancelled,
    /// One configuration of a batch is invalid.
    #[error("configuration {index} of the batch (counting from 0): {source}")]
    InBatch {
        /// 0-based index of the configuration.
        index: usize,
        /// What is wrong with it.
        source: Box<Error>,
    },
    /// A generated or loaded trajectory breaks a limit (see [`crate::traj::check`]).
    #[error("the trajectory is not emitted: {count} violation(s); the first: {first}")]
    Trajectory {
        /// Number of violations.
        count: usize,
        /// The first violation, in words.
        first: String,
        /// All of them.
        violations: Vec<Violation>,
    },
    /// A dynamics computation on a robot whose link has no mass properties.
    #[error("robot `{robot}`: link {link} (moved by joint `{joint}`) has no mass properties (inertial); dynamics needs mass, centre of mass and inertia for every link")]
    NoInertial {
        /// Robot name.
        robot: String,
        /// 1-based index of the link (= of the joint that moves it).
        link: usize,
        /// Name of the joint that moves it.
        joint: String,
    },
    /// A list or buffer with the wrong number of values.
    #[error("`{what}` has {got} values; {expected} expected ({of})")]
    WrongLength {
        /// Which argument.
        what: String,
        /// How many values it has.
        got: usize,
        /// How many it needs.
        expected: usize,
        /// What they are (e.g. "one per joint of `ur5`", "a 4 × 4 matrix").
        of: String,
    },
    /// A value that must be a finite number and is not (of an argument other
    /// than a joint vector, which is [`Error::BadJointValue`]).
    #[error("`{what}` is {value}; it must be a finite number")]
    NotFinite {
        /// Which value (e.g. `qd[3]`, `q3`).
        what: String,
        /// The offending value.
        value: f64,
    },
    /// A result that is not finite although every input is: the inputs are
    /// too large for one.
    #[error("{what} is {value}: the inputs are too large for a finite result ({inputs})")]
    Overflow {
        /// Which result (e.g. `torque of joint 2`).
        what: String,
        /// The value it came out as.
        value: f64,
        /// The largest inputs, named.
        inputs: String,
    },
    /// Something wrong with one joint's part of a request.
    #[error("joint {joint} (`{name}`): {source}")]
    ForJoint {
        /// 1-based joint index.
        joint: usize,
        /// Joint name.
        name: String,
        /// What is wrong there.
        source: Box<Error>,
    },
    /// A number outside the range its argument accepts (a negative time
    /// step, a speed override above 1, a joint value beyond its limits…).
    #[error("invalid `{what}`: {}; expected {expected}", number_text(*value))]
    OutOfRange {
        /// Which argument (e.g. `dt`, `speed`, `tol_position`).
        what: String,
        /// The offending value.
        value: f64,
        /// The accepted range, in words (e.g. "a positive time step \[s\]").
        expected: String,
    },
    /// Too few items where a list needs some: an empty input, a path of one
    /// point, a task mask that selects nothing.
    #[error("`{what}` has {got} {of}; at least {min} needed")]
    TooFew {
        /// Which argument.
        what: String,
        /// How many it has.
        got: usize,
        /// How many it needs at least.
        min: usize,
        /// What is counted (e.g. "points", "samples").
        of: String,
    },
    /// A kinematic limit that a motion needs and that neither the robot
    /// model nor the options give (per joint, inside [`Error::ForJoint`]).
    #[error("no {limit} limit for {needed_by}; give one (`{option}`)")]
    MissingLimit {
        /// The quantity: "velocity", "acceleration" or "jerk".
        limit: String,
        /// The option that gives it (e.g. `vmax`, `amax`, `jmax`).
        option: String,
        /// What needs it (e.g. "its motion in the robot model", "the scurve profile").
        needed_by: String,
    },
    /// A name that is not one of those an argument accepts.
    #[error("invalid `{what}`: unknown {what} `{name}`; expected one of: {known}")]
    UnknownName {
        /// Which argument (e.g. `profile`, `q3`).
        what: String,
        /// What was asked for.
        name: String,
        /// Comma-separated list of the accepted names (and forms).
        known: String,
    },
    /// A valid value that does not fit the rest of the request: a profile
    /// that cannot do what the motion needs, a target kind a solver does not
    /// take, two options that exclude each other.
    #[error("invalid `{what}`: {reason}")]
    DoesNotFit {
        /// Which argument to change.
        what: String,
        /// Why it does not fit, and what would.
        reason: String,
    },
    /// Arguments that are each valid but admit no result: no motion within
    /// the limits, a duration that rounding makes unusable, an integration
    /// that diverges.
    #[error("infeasible `{what}`: {reason}")]
    Infeasible {
        /// Which argument to change (e.g. `duration`, `vmax`).
        what: String,
        /// Why nothing fits, with the numbers.
        reason: String,
    },
    /// Text that does not parse (an expression, a list of numbers).
    #[error("invalid `{what}`: `{text}`, column {column}: {expected}\n  {text}\n  {}^", caret_pad(text, *column))]
    Syntax {
        /// Which argument.
        what: String,
        /// The text as given.
        text: String,
        /// 1-based column (in characters) where it goes wrong.
        column: usize,
        /// What is wrong there and what was expected.
        expected: String,
    },
}

/// An operating-system I/O error, shared so that [`Error`] stays `Clone`;
/// two compare equal when their kind and message do.
#[derive(Debug, Clone)]
pub struct IoError(pub std::sync::Arc<std::io::Error>);

impl From<std::io::Error> for IoError {
    fn from(e: std::io::Error) -> Self {
        IoError(std::sync::Arc::new(e))
    }
}

impl PartialEq for IoError {
    fn eq(&self, other: &Self) -> bool {
        self.0.kind() == other.0.kind() && self.0.to_string() == other.0.to_string()
    }
}

impl std::fmt::Display for IoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::error::Error for IoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(self.0.as_ref())
    }
}

impl Error {
    /// The error itself, under the context that locates it ([`Error::InBatch`],
    /// [`Error::OnPath`], [`Error::ForJoint`]): what kind of thing went wrong.
    pub fn root(&self) -> &Error {
        match self {
            Error::InBatch { source, .. } | Error::OnPath { source, .. } | Error::ForJoint { source, .. } => {
                source.root()
            }
            other => other,
        }
    }
}

/// Result alias of the core library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// A size in bytes as people read it: "16 MiB" when whole, else bytes.
fn size_text(bytes: u64) -> String {
    if bytes >= 1 << 20 && bytes % (1 << 20) == 0 {
        format!("{} MiB", bytes >> 20)
    } else {
        format!("{bytes} bytes")
    }
}

/// A number as people read it in a message: plain, or in scientific notation
/// when plain would run to many digits (1e300, 1e-300).
pub(crate) fn number_text(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e15).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Spaces up to the 1-based character `column` of `text`, to put a caret under it.
fn caret_pad(text: &str, column: usize) -> String {
    " ".repeat(column.saturating_sub(1).min(text.chars().count()))
}

/// The closest configuration of an unreachable target, as a clause of its message.
fn closest_phrase(closest: &Option<Box<Closest>>) -> String {
    match closest {
        Some(c) => {
            let q: Vec<String> = c.q.iter().map(|v| format!("{v:.6}")).collect();
            format!(
                "; closest configuration found: [{}] (misses by {:.3e} m, {:.3e} rad)",
                q.join(", "),
                c.position_error,
                c.orientation_error
            )
        }
        None => String::new(),
    }
}
