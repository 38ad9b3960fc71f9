//! A limit a trajectory breaks: the data
//! [`Error::Trajectory`](super::Error::Trajectory) carries. Defined here,
//! below `traj`, so the error type depends on nothing above it; `traj::check`
//! finds them and re-exports these types.

use std::fmt;

/// What a trajectory check found wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ViolationKind {
    /// A value that is not a finite number, or times that do not increase.
    Malformed,
    /// A joint value outside its position limits.
    Position,
    /// A joint velocity above its limit.
    Velocity,
    /// A joint acceleration above its limit.
    Acceleration,
    /// A joint moving between two samples farther than its velocity limit
    /// allows (a branch flip or a gap in the data).
    Jump,
    /// Between two samples the joints move far while the tool barely does
    /// (a change of inverse-kinematics branch or of a redundant arm's
    /// self-motion in one sample), whatever the limits.
    BranchJump,
    /// Manipulability below the threshold (close to a singularity).
    NearSingular,
    /// A joint jerk above its limit.
    Jerk,
    /// A velocity or acceleration column that q itself contradicts (a glitch
    /// in q, or derivatives that belong to another trajectory).
    Inconsistent,
    /// A singular passage: the Jacobian's inverse condition number below
    /// the threshold (reported as a warning).
    Singular,
    /// A configuration the admissibility test refuses (a scene's collision
    /// check): at a sample, or on the straight joint-space step before it.
    /// `value` is where in that step, as a fraction (0: at the previous
    /// sample); `detail` says what collides.
    Collision,
}

impl ViolationKind {
    /// The order of kinds at one sample and joint in a report.
    pub(crate) fn rank(self) -> u8 {
        match self {
            ViolationKind::Malformed => 0,
            ViolationKind::Position => 1,
            ViolationKind::Velocity => 2,
            ViolationKind::Jump => 3,
            ViolationKind::BranchJump => 4,
            ViolationKind::Acceleration => 5,
            ViolationKind::Inconsistent => 6,
            ViolationKind::Jerk => 7,
            ViolationKind::NearSingular => 8,
            ViolationKind::Singular => 9,
            ViolationKind::Collision => 10,
        }
    }

    /// The lower-case name (`malformed`, `position`, `velocity`,
    /// `acceleration`, `jump`, `branch`, `nearsingular`, `jerk`, `inconsistent`,
    /// `singular`, `collision`), as `kinema traj check --json` prints it.
    pub fn name(self) -> &'static str {
        match self {
            ViolationKind::Malformed => "malformed",
            ViolationKind::Position => "position",
            ViolationKind::Velocity => "velocity",
            ViolationKind::Acceleration => "acceleration",
            ViolationKind::Jump => "jump",
            ViolationKind::BranchJump => "branch",
            ViolationKind::NearSingular => "nearsingular",
            ViolationKind::Jerk => "jerk",
            ViolationKind::Inconsistent => "inconsistent",
            ViolationKind::Singular => "singular",
            ViolationKind::Collision => "collision",
        }
    }
}

/// One problem found by [`crate::traj::check`], with where and when.
#[derive(Debug, Clone, PartialEq)]
pub struct Violation {
    /// What is wrong.
    pub kind: ViolationKind,
    /// Index of the sample.
    pub sample: usize,
    /// Time of the sample \[s\].
    pub time: f64,
    /// The joint (0-based), where one is concerned.
    pub joint: Option<usize>,
    /// The offending value.
    pub value: f64,
    /// The limit it broke.
    pub limit: f64,
    /// What else there is to say (for a collision: the pair).
    pub detail: Option<String>,
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "t = {:.4} s (sample {}): ", self.time, self.sample)?;
        let j = self.joint.map(|j| j + 1).unwrap_or(0);
        match self.kind {
            ViolationKind::Malformed => write!(f, "malformed sample (value {}, previous time {})", self.value, self.limit),
            ViolationKind::Position => {
                write!(f, "joint {j} at {:.6} is outside its position limits (nearest bound {:.6})", self.value, self.limit)
            }
            ViolationKind::Velocity => write!(f, "joint {j} velocity {:.6} exceeds its limit {:.6}", self.value, self.limit),
            ViolationKind::Acceleration => {
                write!(f, "joint {j} acceleration {:.6} exceeds its limit {:.6}", self.value, self.limit)
            }
            ViolationKind::Jump => write!(
                f,
                "joint {j} jumps by {:.6} since the previous sample, more than its velocity limit allows ({:.6}); a branch flip?",
                self.value, self.limit
            ),
            ViolationKind::BranchJump => write!(
                f,
                "a branch jump (joint {j} moves most): the joints move {:.6} rad in all since the previous sample, \
                 over 100 times the tool's step ({:.3e}: its distance over the arm's length plus its turn)",
                self.value, self.limit
            ),
            ViolationKind::NearSingular => {
                write!(f, "manipulability {:.3e} is below the threshold {:.3e} (close to a singularity)", self.value, self.limit)
            }
            ViolationKind::Jerk => write!(f, "joint {j} jerk {:.6} exceeds its limit {:.6}", self.value, self.limit),
            ViolationKind::Inconsistent => write!(
                f,
                "joint {j}: the derivative column says {:.6}, but q changes at {:.6} on average over the step \
                 (more apart than the acceleration limit allows); a glitch in q?",
                self.value, self.limit
            ),
            ViolationKind::Singular => write!(
                f,
                "singular passage: the Jacobian's inverse condition number {:.3e} is below {:.3e}",
                self.value, self.limit
            ),
            ViolationKind::Collision => {
                let detail = self.detail.as_deref().unwrap_or("a configuration the check refuses");
                if self.value > 0.0 {
                    write!(f, "collision: {detail} (between samples {} and {})", self.sample - 1, self.sample)
                } else {
                    write!(f, "collision: {detail}")
                }
            }
        }
    }
}
