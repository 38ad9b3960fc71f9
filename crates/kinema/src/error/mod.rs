//! The error type of the core library, and the data its variants carry.

mod file;
mod input;
mod model;
mod unreachable;
mod violation;

pub use file::{FileError, IoError};
pub use input::InputError;
pub use model::ModelError;
pub use unreachable::{Closest, Tolerance, Unreachable};
pub use violation::{Violation, ViolationKind};

/// Everything that can go wrong in `kinema`. Each variant carries what was
/// wrong and, where it helps, what was expected. Wrong arguments, unusable
/// models and unreadable files are grouped ([`InputError`], [`ModelError`],
/// [`FileError`]) so a caller can tell them apart with one match; the
/// context variants ([`Error::InBatch`], [`Error::OnPath`], [`Error::ForJoint`])
/// wrap the error they locate.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// An argument of the call that is wrong in itself: a joint vector of the
    /// wrong length, a value out of range, an unknown name, text that does
    /// not parse.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A robot description or model that cannot be used.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A file that cannot be read.
    #[error(transparent)]
    File(#[from] FileError),
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
    /// Roll-pitch-yaw rates are undefined at this orientation.
    #[error("roll-pitch-yaw rates are undefined at pitch = {pitch} rad (representation singularity at ±π/2); use the geometric Jacobian there")]
    RpySingularity {
        /// Middle angle of the triple \[rad\].
        pitch: f64,
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
    /// The work was interrupted before it finished (Ctrl-C, a deadline).
    #[error("cancelled before it finished")]
    Cancelled,
    /// A sample of a Cartesian path that failed (IK, most often).
    #[error("at t = {t:.4} s of the path: {source}")]
    OnPath {
        /// Time of the sample along the path \[s\].
        t: f64,
        /// What went wrong there.
        source: Box<Error>,
    },
    /// One configuration of a batch is invalid.
    #[error("configuration {index} of the batch (counting from 0): {source}")]
    InBatch {
        /// 0-based index of the configuration.
        index: usize,
        /// What is wrong with it.
        source: Box<Error>,
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
pub(super) fn caret_pad(text: &str, column: usize) -> String {
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
