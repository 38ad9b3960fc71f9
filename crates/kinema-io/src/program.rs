//! A robot program as an answer: its plan, where it ends and its warnings.

use kinema::RpyConvention;
use kinema_lang::Plan;
use serde::Serialize;

use crate::pose::PoseAnswer;

/// One motion of a program's plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MotionAnswer {
    /// The statement's source line, from 1.
    pub line: usize,
    /// The statement's keyword (`PTP`, `LIN`, `WAIT`, …).
    pub kind: String,
    /// Start time \[s\].
    pub start: f64,
    /// End time \[s\].
    pub end: f64,
    /// The time law.
    pub profile: String,
    /// Where the robot goes, in words and SI units.
    pub target: String,
}

/// The answer of `kinema compile|run --json` and, with the samples, of
/// `POST /api/run`: the plan's motions, duration and sample count, the
/// final configuration and tool pose, and the warnings one line each.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProgramAnswer {
    /// The robot's name.
    pub robot: String,
    /// The plan's duration \[s\].
    pub duration: f64,
    /// The number of samples.
    pub samples: usize,
    /// The motions in execution order.
    pub motions: Vec<MotionAnswer>,
    /// The joint values at the end.
    pub final_q: Vec<f64>,
    /// The tool pose at the end (zyx roll-pitch-yaw).
    pub final_pose: PoseAnswer,
    /// The compiler's warnings, one line each, naming `file`.
    pub warnings: Vec<String>,
}

impl ProgramAnswer {
    /// The answer for `plan` compiled from `source`, its diagnostics naming `file`.
    pub fn new(plan: &Plan, file: &str, source: &str) -> kinema::Result<ProgramAnswer> {
        let final_q = plan.final_q().to_vec();
        let pose = plan.robot.fk(&final_q)?.world_from_tool;
        // One line index for all warnings: one_line alone rescans the source per warning.
        let lines = kinema_lang::diag::LineIndex::new(source);
        Ok(ProgramAnswer {
            robot: plan.robot.name().to_string(),
            duration: plan.duration(),
            samples: plan.trajectory.len(),
            motions: plan
                .motions
                .iter()
                .map(|m| MotionAnswer {
                    line: m.line,
                    kind: m.kind.clone(),
                    start: m.start,
                    end: m.end,
                    profile: m.profile.clone(),
                    target: m.target.clone(),
                })
                .collect(),
            final_q,
            final_pose: PoseAnswer::new(&pose, RpyConvention::Zyx),
            warnings: plan.warnings.iter().map(|d| d.one_line_in(file, source, &lines)).collect(),
        })
    }
}
