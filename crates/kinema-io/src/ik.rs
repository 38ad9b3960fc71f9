//! Inverse kinematics as answers: the solutions of one target, an
//! unreachable target, the self-motion of a redundant arm and the round-trip
//! validation.

use kinema::ik::{Closest, IkAnswer as Solved, IkTarget};
use kinema::{JointType, Robot, RpyConvention};
use serde::Serialize;

use crate::pose::PoseAnswer;
use crate::solution::SolutionAnswer;

/// Why a candidate of the solver that misses the target is not listed.
pub const DISCARD_REASON: &str = "forward kinematics misses the target by more than the tolerance";

/// The `reason` of a candidate that misses the target (else the rejecting
/// test's kind, `collision`).
pub const MISSED: &str = "tolerance";

/// The tolerance a solution met \[m, rad\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ToleranceAnswer {
    /// Position tolerance \[m\].
    pub position: f64,
    /// Orientation tolerance \[rad\].
    pub orientation: f64,
}

/// A candidate the solver proposed whose forward kinematics misses the
/// target, or that a collision check rejected.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiscardedCandidate {
    /// The solver's branch label.
    pub branch: String,
    /// Why: [`MISSED`] (`tolerance`), or the rejecting test (`collision`).
    pub reason: &'static str,
    /// What the test found (the colliding pair, `link_4 – bench`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub detail: Option<String>,
    /// Its position residual \[m\].
    pub position_error: f64,
    /// Its orientation residual \[rad\].
    pub orientation_error: f64,
}

/// The candidates that were not listed, and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiscardedAnswer {
    /// How many.
    pub count: usize,
    /// Why, in words: [`DISCARD_REASON`] and/or the rejecting tests
    /// (`collision`), joined by `; `.
    pub reason: String,
    /// Each of them.
    pub candidates: Vec<DiscardedCandidate>,
}

/// The answer of `kinema ik --json` and `POST /api/ik`: the solutions that
/// meet the target within the tolerance, what was discarded and why, and
/// the request's redundancy parameter. The server lists every solution and
/// marks the one the CLI and Python return (`picked`) and the one nearest
/// `q0` (`nearest`); the CLI prints one solution, or all with `--all`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IkAnswer {
    /// The robot's name.
    pub robot: String,
    /// The solver that answered.
    pub solver: String,
    /// The target pose, when the target is a full pose (roll-pitch-yaw in the request's convention).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target: Option<PoseAnswer>,
    /// The fixed q3 the closed form solved at, for an arm that has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub q3: Option<f64>,
    /// The arm angle ψ the closed form solved at.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub psi: Option<f64>,
    /// The solutions.
    pub solutions: Vec<SolutionAnswer>,
    /// The tolerance every solution meets.
    pub tolerance: ToleranceAnswer,
    /// The candidates that missed the target.
    pub discarded: DiscardedAnswer,
    /// Copies within limits (joints turned by whole turns) that were not listed.
    pub folded: usize,
    /// The index in `solutions` of the one nearest the request's `q0`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nearest: Option<usize>,
    /// The index in `solutions` of the one a single-answer request returns.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub picked: Option<usize>,
}

/// The distinct reasons of `candidates` in words, in order of first appearance.
fn discard_reasons(candidates: &[DiscardedCandidate]) -> String {
    let mut reasons: Vec<&str> = Vec::new();
    for c in candidates {
        let reason = if c.reason == MISSED { DISCARD_REASON } else { c.reason };
        if !reasons.contains(&reason) {
            reasons.push(reason);
        }
    }
    reasons.join("; ")
}

impl IkAnswer {
    /// The answer listing `solutions` out of the solver's `solved` (its
    /// discarded candidates, tolerance and folded copies) for `target`, a
    /// full pose's roll-pitch-yaw in `convention`. A target that leaves the
    /// orientation free has no orientation error to report (`null`).
    pub fn new(
        robot: &Robot,
        solved: &Solved,
        solutions: &[kinema::ik::Solution],
        target: &IkTarget,
        convention: RpyConvention,
    ) -> IkAnswer {
        let orientation_free = target.orientation_free();
        let candidates: Vec<DiscardedCandidate> = solved
            .discarded
            .iter()
            .map(|d| DiscardedCandidate {
                branch: d.branch.to_string(),
                reason: d.rejection.as_ref().map_or(MISSED, |r| r.kind),
                detail: d.rejection.as_ref().map(|r| r.detail.clone()),
                position_error: d.residual.position,
                orientation_error: d.residual.orientation,
            })
            .collect();
        IkAnswer {
            robot: robot.name().to_string(),
            solver: solved.solver.to_string(),
            target: match target {
                IkTarget::Pose(p) => Some(PoseAnswer::new(p, convention)),
                _ => None,
            },
            q3: None,
            psi: None,
            solutions: solutions
                .iter()
                .map(|s| {
                    let mut a = SolutionAnswer::new(s);
                    if orientation_free {
                        a.orientation_error = None;
                    }
                    a
                })
                .collect(),
            tolerance: ToleranceAnswer {
                position: solved.tolerance.position,
                orientation: solved.tolerance.orientation,
            },
            discarded: DiscardedAnswer { count: candidates.len(), reason: discard_reasons(&candidates), candidates },
            folded: solved.folded,
            nearest: None,
            picked: None,
        }
    }

    /// The angles of `kinema ik --deg`: revolute joint values of every
    /// solution, and the request's angles it echoes (the target's roll,
    /// pitch and yaw, a revolute q3, ψ), in degrees.
    pub fn in_degrees(mut self, robot: &Robot) -> IkAnswer {
        for s in &mut self.solutions {
            s.q = shown_q(robot, &s.q, true);
        }
        if let Some(t) = &mut self.target {
            t.rpy = t.rpy.map(f64::to_degrees);
        }
        let third_revolute = robot.joints().get(2).is_some_and(|j| j.kind == JointType::Revolute);
        self.q3 = self.q3.map(|v| if third_revolute { v.to_degrees() } else { v });
        self.psi = self.psi.map(f64::to_degrees);
        self
    }
}

/// Joint values as printed: revolute joints in degrees when `deg`.
pub fn shown_q(robot: &Robot, q: &[f64], deg: bool) -> Vec<f64> {
    q.iter()
        .zip(robot.joints())
        .map(|(v, j)| if deg && j.kind == JointType::Revolute { v.to_degrees() } else { *v })
        .collect()
}

/// The configuration nearest an unreachable target.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClosestAnswer {
    /// Its joint values.
    pub q: Vec<f64>,
    /// How far it misses in position \[m\].
    pub position_error: f64,
    /// How far it misses in orientation \[rad\].
    pub orientation_error: f64,
}

/// The answer to a target no solution meets: `error` is `unreachable`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UnreachableAnswer {
    /// Always `unreachable`.
    pub error: &'static str,
    /// The solver that tried.
    pub solver: String,
    /// Why nothing meets the target.
    pub reason: String,
    /// The nearest configuration found, if any.
    pub closest: Option<ClosestAnswer>,
}

impl UnreachableAnswer {
    /// The answer for the core's unreachable error; `deg`: revolute joints of
    /// `closest` in degrees.
    pub fn new(robot: &Robot, solver: &str, reason: &str, closest: Option<&Closest>, deg: bool) -> UnreachableAnswer {
        UnreachableAnswer {
            error: "unreachable",
            solver: solver.to_string(),
            reason: reason.to_string(),
            closest: closest.map(|c| ClosestAnswer {
                q: shown_q(robot, &c.q, deg),
                position_error: c.position_error,
                orientation_error: c.orientation_error,
            }),
        }
    }
}

/// One sample of a self-motion: the tool pose kept, the arm angle swept.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SelfMotionPoint {
    /// The arm angle ψ \[rad\].
    pub psi: f64,
    /// q3 at this sample \[rad\].
    pub q3: f64,
    /// The joint values.
    pub q: Vec<f64>,
    /// The elbow's position \[m\].
    pub elbow: [f64; 3],
    /// Whether every joint value is within its limits.
    pub within_limits: bool,
}

/// The answer of `kinema selfmotion --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SelfMotionAnswer {
    /// The robot's name.
    pub robot: String,
    /// The samples around the self-motion.
    pub samples: Vec<SelfMotionPoint>,
}

impl SelfMotionAnswer {
    /// The answer for the core's self-motion samples.
    pub fn new(robot: &Robot, samples: &[kinema::ik::family::SelfMotionSample]) -> SelfMotionAnswer {
        SelfMotionAnswer {
            robot: robot.name().to_string(),
            samples: samples
                .iter()
                .map(|m| SelfMotionPoint {
                    psi: m.psi,
                    q3: m.q3,
                    q: m.q.clone(),
                    elbow: [m.elbow.x, m.elbow.y, m.elbow.z],
                    within_limits: m.within_limits,
                })
                .collect(),
        }
    }
}

/// The answer of `kinema ik-validate --json`: IK of the forward kinematics of
/// random configurations. The iiwa's own experiment (solved at the original
/// q3) adds the well-conditioned figures; the other solvers say how many
/// cases they solved and their largest position residual.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ValidateAnswer {
    /// The robot's name.
    pub robot: String,
    /// The solver validated.
    pub solver: String,
    /// Number of configurations.
    pub cases: usize,
    /// Cases solved (general solvers).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub solved: Option<usize>,
    /// Largest joint-space error \[rad, m\].
    pub max_error: f64,
    /// Mean joint-space error.
    pub mean_error: f64,
    /// Fraction of cases whose configuration was recovered.
    pub recovered_fraction: f64,
    /// Largest position residual \[m\] (general solvers).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_position_residual: Option<f64>,
    /// Worst error over its rounding limit (iiwa).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_error_over_limit: Option<f64>,
    /// Largest error over the well-conditioned cases (iiwa).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_error_well_conditioned: Option<f64>,
    /// Number of well-conditioned cases (iiwa).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub well_conditioned_cases: Option<usize>,
}
