//! [`ModelError`]: a robot description or model that cannot be used.

/// A robot description or model that cannot be used (see [`Error::Model`](super::Error::Model)).
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
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
    /// A model that is internally inconsistent (built in code, not from a file).
    #[error("invalid robot model `{robot}`: {message}")]
    InvalidModel {
        /// Robot name.
        robot: String,
        /// What is wrong.
        message: String,
    },
}
