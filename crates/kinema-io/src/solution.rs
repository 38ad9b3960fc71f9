//! One inverse-kinematics solution.

use kinema::ik::Solution;
use serde::Serialize;

/// One IK solution with its residuals; a numeric one also says how its
/// search went. Radians and metres.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolutionAnswer {
    /// The joint values.
    pub q: Vec<f64>,
    /// The branch label (`elbow-up/wrist-flip`, `numeric`).
    pub branch: String,
    /// Whether every joint value is within its limits.
    pub within_limits: bool,
    /// |p_target − p(q)| \[m\].
    pub position_error: f64,
    /// The angle between the target's and the reached rotation \[rad\];
    /// `null` for a target that leaves the orientation free.
    pub orientation_error: Option<f64>,
    /// Numeric solutions: iterations of the successful start.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub iterations: Option<usize>,
    /// Numeric solutions: restarts before it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restarts: Option<usize>,
    /// Numeric solutions: why the search stopped.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stop: Option<String>,
}

impl SolutionAnswer {
    /// The answer for `s`.
    pub fn new(s: &Solution) -> SolutionAnswer {
        SolutionAnswer {
            q: s.q.clone(),
            branch: s.branch.to_string(),
            within_limits: s.within_limits(),
            position_error: s.position_error,
            orientation_error: Some(s.orientation_error),
            iterations: s.numeric.map(|n| n.iterations),
            restarts: s.numeric.map(|n| n.restarts),
            stop: s.numeric.map(|n| n.stop.to_string()),
        }
    }
}
