//! The check of the finished trajectory against the limits, each violation
//! reported at the line of the motion that caused it.

use std::collections::HashSet;

use kinema::traj::{self, CheckOptions};
use kinema::Robot;

use crate::diag::Diagnostic;

use super::Compiler;

impl Compiler<'_> {
    /// The trajectory check; each violation at the line of its motion.
    pub(super) fn check_trajectory(&mut self) {
        let opts = CheckOptions { admissible: self.opts.admissible.as_deref(), ..CheckOptions::default() };
        let report = match traj::check(self.robot, &self.traj, &opts) {
            Ok(r) => r,
            Err(e) => {
                self.err(Diagnostic::error(0..0, format!("trajectory check: {e}")));
                return;
            }
        };
        let mut seen = HashSet::new();
        let last = self.plan_motions.len().saturating_sub(1);
        // Within a sample of a linear motion's ends, an acceleration finding of
        // its joints is the law's velocity step (as `Ptp::sample` exempts it).
        let margin = self.opts.dt + 1e-9;
        let steps = std::mem::take(&mut self.velocity_steps);
        let stepped = |v: &traj::Violation| {
            matches!(
                v.kind,
                traj::ViolationKind::Acceleration | traj::ViolationKind::Jerk | traj::ViolationKind::Inconsistent
            ) && v.joint.is_some_and(|j| {
                // Motions follow one another: their steps are in time order, so
                // only those around v.time are looked at.
                let from = steps.partition_point(|(_, b, _)| *b + margin < v.time);
                steps[from..].iter().take_while(|(a, ..)| *a - margin <= v.time).any(|(_, _, js)| js[j])
            })
        };
        for v in report.violations.into_iter().filter(|v| !stepped(v)) {
            // The first motion with start < t ≤ end (starts and ends never decrease).
            let k = self.plan_motions.partition_point(|m| m.end + 1e-12 < v.time);
            let k = if self.plan_motions.get(k).is_some_and(|m| v.time > m.start - 1e-12) { k } else { last };
            // A jump is the velocity excess seen between two samples: one report per joint and motion.
            let kind = if v.kind == traj::ViolationKind::Jump { traj::ViolationKind::Velocity } else { v.kind };
            if !seen.insert((k, v.joint, kind as u8)) {
                continue;
            }
            let span = self.motion_spans.get(k).cloned().unwrap_or(0..0);
            let joint = v.joint.map(|j| format!(" ({})", self.robot.joints()[j].name)).unwrap_or_default();
            let (what, hint) = if kind == traj::ViolationKind::BranchJump {
                ("the joints jump", "the inverse kinematics changed branch between two samples: start the motion from a configuration on its branch, or add a via point")
            } else {
                ("limit violated", "slow the motion down (SPEED, VEL, ACC or a longer IN/time) or move the target")
            };
            self.err(Diagnostic::error(span, format!("{what}{joint}: {v}")).with_hint(hint));
        }
    }
}

/// "joint i (name) at v, outside its limits [min, max]" for the first joint of
/// `q` outside its limits.
pub(super) fn outside_limits(robot: &Robot, q: &[f64]) -> Option<String> {
    let i = robot.limit_flags(q).indices().next()?;
    let j = &robot.joints()[i];
    Some(format!(
        "joint {} ({}) at {:.6}, outside its limits [{:.6}, {:.6}]",
        i + 1,
        j.name,
        q[i],
        j.limits.min,
        j.limits.max
    ))
}
