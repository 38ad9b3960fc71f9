//! `PTP … AVOID`: a joint motion around obstacles. The caller's planner
//! gives a path of straight segments. A straight motion that is free stays
//! the plain PTP, sample for sample; else the path is timed with a PTP per
//! segment under the program's joint limits, at rest at each via point, so
//! the robot stays on the segments the planner checked.

use kinema::traj::{via::ptp_through, Profile};

use crate::ast::Stmt;
use crate::diag::Diagnostic;
use crate::lexer::Span;

use super::Compiler;

impl Compiler<'_> {
    /// PTP AVOID to `q_to` (`at`: where AVOID is written).
    pub(super) fn ptp_around(&mut self, s: &Stmt, at: &Span, q_to: Vec<f64>, text: String) {
        let Some(planner) = self.opts.planner.clone() else {
            self.warn(
                Diagnostic::warning(at.clone(), "AVOID without a collision check: the motion is straight")
                    .with_hint("give the program a scene (`kinema run --scene FILE`) to plan around its obstacles"),
            );
            return self.ptp_to(s, q_to, None, text);
        };
        if !self.valid_joint_target(s, &q_to) {
            return;
        }
        let from = self.q.clone();
        let path = match planner.path(&from, &q_to, statement_seed(self.src, s.span.start)) {
            Ok(path) if path.first() == Some(&from) && path.last() == Some(&q_to) => path,
            Ok(_) => {
                self.err(Diagnostic::error(
                    s.span.clone(),
                    "PTP AVOID: the planner's path does not join the motion's ends",
                ));
                return;
            }
            Err(why) => {
                self.err(
                    Diagnostic::error(
                        s.span.clone(),
                        format!("PTP AVOID: no collision-free path to the target: {why}"),
                    )
                    .with_hint("move the target or the obstacles, or add a PTP to a free configuration on the way"),
                );
                return;
            }
        };
        if path.len() <= 2 {
            return self.ptp_to(s, q_to, None, text);
        }
        self.time_path(s, &path, text);
    }

    /// The path timed under the program's limits and appended as one motion.
    fn time_path(&mut self, s: &Stmt, path: &[Vec<f64>], text: String) {
        let profile = self.profile;
        // The limits are the same for every segment; each is asked so that a
        // joint only a detour moves still needs its limit.
        let mut options = None;
        for w in path.windows(2) {
            match self.ptp_options(profile, &w[0], &w[1]) {
                Ok(o) => options = Some(o),
                Err(message) => {
                    self.err(Diagnostic::error(s.span.clone(), format!("PTP: {message}")));
                    return;
                }
            }
        }
        let Some(options) = options else { return };
        let j = match ptp_through(self.robot, path, &options, self.opts.dt) {
            Ok(j) => j,
            Err(e) => {
                self.err(Diagnostic::error(s.span.clone(), format!("PTP AVOID: {e}")));
                return;
            }
        };
        let t0 = self.traj.times().last().copied().unwrap_or(0.0);
        let end = t0 + j.times().last().copied().unwrap_or(0.0);
        if profile == Profile::Linear {
            let moves = (0..self.robot.dof()).map(|i| path.windows(2).any(|w| w[0][i] != w[1][i])).collect();
            self.velocity_steps.push((t0, end, moves));
        }
        let detour = format!("{text} around obstacles, {} via point(s)", path.len() - 2);
        self.record(s, "PTP", t0, end, profile.name(), detour);
        self.append(&j, t0);
    }
}

/// The planner's seed for the statement at byte `offset` of `src`: the same
/// program gives the same paths (FNV-1a, stable across builds and platforms).
fn statement_seed(src: &str, offset: usize) -> u64 {
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let bytes = src.as_bytes().iter().copied().chain((offset as u64).to_le_bytes());
    bytes.fold(0xcbf2_9ce4_8422_2325, |hash, b| (hash ^ u64::from(b)).wrapping_mul(PRIME))
}

#[cfg(test)]
mod tests {
    use super::statement_seed;

    #[test]
    fn seeds_differ_by_statement_and_by_program_and_repeat() {
        let src = "PTP JOINT(0, 0) AVOID\nPTP JOINT(1, 0) AVOID\n";
        assert_eq!(statement_seed(src, 0), statement_seed(src, 0));
        assert_ne!(statement_seed(src, 0), statement_seed(src, 22));
        assert_ne!(statement_seed(src, 0), statement_seed("PTP JOINT(0, 1) AVOID\n", 0));
    }
}
