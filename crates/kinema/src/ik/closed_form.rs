//! The one [`IkSolver`] of the closed-form families. A family writes only
//! its kernel — the candidates of a target, unmeasured — and the solver
//! around it (measuring each candidate by FK, flagging the joint limits,
//! handing the contract its candidates once) is this blanket impl.

use super::{CandidateSet, IkSolver, Solution};
use crate::error::Result;
use crate::math::Pose;
use crate::robot::Robot;

/// A closed-form kernel: what an analytic family implements to be an
/// [`IkSolver`].
pub trait ClosedForm: Send + Sync {
    /// The solver's short name, as [`IkSolver::name`] reports it.
    const NAME: &'static str;

    /// The robot the family was fitted to, whose FK measures the candidates.
    fn robot(&self) -> &Robot;

    /// Every closed-form candidate for `target` (`world_from_tool`) into
    /// `out` (cleared first), without measuring them; an unreachable target
    /// is an [`Error::Unreachable`](crate::Error::Unreachable) that says why.
    fn kernel(&self, target: &Pose, out: &mut CandidateSet) -> Result<()>;

    /// Puts the measured solutions of [`IkSolver::solve`] in the family's
    /// order; by default the kernel's.
    fn order(&self, solutions: &mut [Solution]) {
        let _ = solutions;
    }
}

impl<K: ClosedForm> IkSolver for K {
    fn name(&self) -> &'static str {
        K::NAME
    }

    /// The kernel's candidates, each measured by FK and flagged for limits.
    fn solve(&self, target: &Pose) -> Result<Vec<Solution>> {
        let mut set = CandidateSet::new();
        self.kernel(target, &mut set)?;
        let mut solutions =
            (0..set.len()).map(|i| set.evaluate(i, self.robot(), target)).collect::<Result<Vec<_>>>()?;
        self.order(&mut solutions);
        Ok(solutions)
    }

    fn candidates_into(&self, target: &Pose, out: &mut CandidateSet) -> Result<()> {
        self.kernel(target, out)
    }

    /// The kernel's candidates unmeasured: the contract measures each once.
    fn propose(&self, target: &Pose) -> Result<Vec<Solution>> {
        let mut set = CandidateSet::new();
        self.kernel(target, &mut set)?;
        Ok(set.unmeasured())
    }
}
