//! [`InputError`]: an argument of a call that is wrong in itself.

use super::{caret_pad, number_text};

/// An argument that is wrong in itself (see [`Error::Input`](super::Error::Input)).
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InputError {
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
    /// than a joint vector, which is [`InputError::BadJointValue`]).
    #[error("`{what}` is {value}; it must be a finite number")]
    NotFinite {
        /// Which value (e.g. `qd[3]`, `q3`).
        what: String,
        /// The offending value.
        value: f64,
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
    /// model nor the options give (per joint, inside [`Error::ForJoint`](super::Error::ForJoint)).
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
