//! The iiwa's self-motion as the generic [`Redundancy`] the request layer
//! and `traj` follow: q3 or the arm angle ψ as the parameter.

use super::*;

/// The self-motion of seed 004: joint 3 (§V-B) or the arm angle ψ (§V-D).
impl Redundancy for IiwaIk {
    fn parameters(&self) -> &'static [SelfMotionParameter] {
        &[SelfMotionParameter::Q3, SelfMotionParameter::ArmAngle]
    }

    /// At ψ: one solution per global configuration that reaches the target
    /// (the first configuration's reason when none does).
    fn solve_at(&self, target: &Pose, parameter: SelfMotionParameter, value: f64) -> Result<Vec<Solution>> {
        if parameter == SelfMotionParameter::Q3 {
            return self.solve_q3(target, value);
        }
        let all: Vec<Solution> = (0u8..8).filter_map(|c| self.solve_psi(target, value, c).ok()).collect();
        if all.is_empty() {
            return Ok(vec![self.solve_psi(target, value, 0)?]);
        }
        Ok(all)
    }

    fn value_of(&self, q: &[f64]) -> f64 {
        q.get(2).copied().unwrap_or(f64::NAN)
    }

    /// Seed 004 §V-E's q_k = f(q_{k−1}, T_k), falling back to the whole self-motion.
    fn solve_near(&self, target: &Pose, q0: &[f64]) -> Result<Vec<Solution>> {
        Ok(vec![self.select(q0, target, None)?])
    }

    fn solve_searching(&self, target: &Pose, prefer: f64) -> Result<Vec<Solution>> {
        IiwaIk::solve_searching(self, target, prefer)
    }

    fn default_value(&self) -> f64 {
        self.q3()
    }

    fn joint(&self) -> usize {
        2
    }

    fn parameter_of(&self, q: &[f64], parameter: SelfMotionParameter) -> f64 {
        match parameter {
            SelfMotionParameter::Q3 => self.value_of(q),
            SelfMotionParameter::ArmAngle if q.len() == 7 && q.iter().all(|v| v.is_finite()) => self.psi_of(q),
            SelfMotionParameter::ArmAngle => f64::NAN,
        }
    }

    /// At q3: only the branches on `prev`'s shoulder and elbow side ([`IiwaIk::solve_q3_near`]).
    fn continue_at(
        &self,
        target: &Pose,
        parameter: SelfMotionParameter,
        value: f64,
        prev: &[f64],
        out: &mut crate::ik::CandidateSet,
    ) -> Result<()> {
        if parameter == SelfMotionParameter::Q3 {
            self.solve_q3_near(target, value, prev)?.write_into(out);
            return Ok(());
        }
        crate::ik::family::solutions_into(self, target, parameter, value, out)
    }

    /// Seed 004 §V-E's rule on the branches that can continue the path.
    fn choose(&self, target: &Pose, choice: &Choice) -> Result<Solution> {
        self.select_impl(target, choice, true)
    }
}
