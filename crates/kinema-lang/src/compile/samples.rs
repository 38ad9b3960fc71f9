//! The growing trajectory: sample times under the program's cap, time laws
//! sampled, motions recorded and appended.

use kinema::traj::{self, JointTrajectory, Profile, TimeLaw};

use crate::ast::Stmt;
use crate::diag::Diagnostic;

use super::{Compiler, PlannedMotion};

impl Compiler<'_> {
    /// Whether `samples` more samples fit under the program's cap; if not, the error at
    /// `span` and the program stops there.
    pub(super) fn room_for(&mut self, span: crate::lexer::Span, samples: usize) -> bool {
        // The trajectory holds the start already, and a statement's first sample is the
        // present one: `samples` adds samples − 1.
        let total = self.traj.len().saturating_add(samples.saturating_sub(1));
        let bytes = JointTrajectory::bytes_for(self.robot.dof(), total);
        if total <= self.opts.max_samples && bytes <= traj::MAX_TRAJECTORY_BYTES {
            return true;
        }
        let message = if total > self.opts.max_samples {
            format!("the program produces more than {} samples", self.opts.max_samples)
        } else {
            format!(
                "the program's {total} samples of {} joints would take {:.2} GB, above the limit of {:.2} GB",
                self.robot.dof(),
                bytes as f64 / 1e9,
                traj::MAX_TRAJECTORY_BYTES as f64 / 1e9
            )
        };
        self.err(Diagnostic::error(span, format!("{message}; it is cut here (raise dt or shorten the program)")));
        self.stopped = true;
        false
    }

    pub(super) fn append(&mut self, j: &JointTrajectory, t0: f64) {
        let span = self.motion_spans.last().cloned().unwrap_or(0..0);
        if !self.room_for(span, j.len()) {
            return;
        }
        for k in 1..j.len() {
            // Cannot fail: same joint count, finite values, increasing times.
            let _ = self.traj.push(t0 + j.times()[k], j.q(k), j.qd(k), j.qdd(k));
        }
        if !j.is_empty() {
            self.q = j.q(j.len() - 1).to_vec();
        }
    }

    pub(super) fn hold(&mut self, s: &Stmt, t: f64, kind: &str) {
        let t0 = self.traj.times().last().copied().unwrap_or(0.0);
        if t > 0.0 {
            let Some(times) = self.sample_times(s.span.clone(), t) else { return };
            self.record(s, kind, t0, t0 + t, "hold", "stand still".into());
            if !self.room_for(s.span.clone(), times.len()) {
                return;
            }
            // Straight into the trajectory: a copy made first would double
            // the memory of a long WAIT at the sample limit.
            let (q, z) = (self.q.clone(), vec![0.0; self.robot.dof()]);
            for &tt in &times[1..] {
                // Cannot fail: same joint count, finite values, increasing times.
                let _ = self.traj.push(t0 + tt, &q, &z, &z);
            }
        }
    }

    pub(super) fn record(&mut self, s: &Stmt, kind: &str, start: f64, end: f64, profile: &str, target: String) {
        let line = self.line(&s.span);
        self.plan_motions.push(PlannedMotion { line, kind: kind.into(), start, end, profile: profile.into(), target });
        self.motion_spans.push(s.span.clone());
    }

    pub(super) fn law_for(&mut self, s: &Stmt, profile: Profile, t: f64) -> Option<TimeLaw> {
        match TimeLaw::from_duration(profile, t) {
            Ok(l) => Some(l),
            Err(e) => {
                self.err(Diagnostic::error(s.span.clone(), e.to_string()));
                None
            }
        }
    }

    /// The sample times of the statement at `span`, lasting `duration` \[s\]; an error there
    /// when they are too many to hold (a `WAIT` of years, say), never a silent skip, and
    /// checked against the program's cap before any sample of the motion is computed.
    pub(super) fn sample_times(&mut self, span: crate::lexer::Span, duration: f64) -> Option<Vec<f64>> {
        match traj::sample_times(duration, self.opts.dt) {
            Ok(times) => self.room_for(span, times.len()).then_some(times),
            Err(e) => {
                self.err(Diagnostic::error(span, e.to_string()).with_hint("shorten it or raise dt".to_string()));
                None
            }
        }
    }

    /// Joint i goes from `from[i]` to `to[i]` with `laws[i]` (all of one duration).
    pub(super) fn sample_laws(
        &mut self,
        s: &Stmt,
        from: &[f64],
        to: &[f64],
        laws: &[TimeLaw],
    ) -> Option<JointTrajectory> {
        let duration = laws[0].duration();
        let times = self.sample_times(s.span.clone(), duration)?;
        let n = from.len();
        let mut j = match JointTrajectory::reserved(n, times.len()) {
            Ok(j) => j,
            Err(e) => {
                self.err(Diagnostic::error(s.span.clone(), e.to_string()));
                return None;
            }
        };
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for &t in &times {
            for i in 0..n {
                let st = laws[i].at(t);
                let d = to[i] - from[i];
                q[i] = from[i] + st.s * d;
                qd[i] = st.sd * d;
                qdd[i] = st.sdd * d;
            }
            j.push(t, &q, &qd, &qdd).ok()?;
        }
        Some(j)
    }
}
