//! A test every IK solution (and every configuration of a checked motion)
//! must pass besides meeting the target: a scene's collision check is the
//! one kinema has. The core knows nothing of shapes;
//! `kinema-geometry` implements [`Admissible`] and every door passes it in
//! [`IkRequest::admissible`](super::IkRequest::admissible).
//!
//! A solution the test rejects is not a solution: it moves to
//! [`IkAnswer::discarded`] with the [`Rejection`]. When none is left, a
//! redundant arm's self-motion (q3 or ψ) is searched for the value whose
//! solutions stand farthest from rejection — seed 004 chose a redundant arm
//! for exactly this, to keep clear of obstacles in a lab — before the target
//! is refused with [`Unreachable::Rejected`].

use std::f64::consts::PI;
use std::fmt;

use super::contract::{Discarded, IkAnswer, Residual};
use super::family::{Redundancy, SelfMotionParameter};
use super::{Solution, Unreachable};
use crate::error::{Error, Result};
use crate::math::Pose;
use crate::robot::Robot;

/// A test of configurations besides the target (a collision check).
pub trait Admissible: Send + Sync {
    /// `None` when the robot may stand at `q`; else why not.
    fn rejects(&self, q: &[f64]) -> Result<Option<Rejection>>;

    /// [`rejects`](Admissible::rejects) and, when `q` passes, how far it is
    /// from being rejected (for a scene: the smallest distance between
    /// checked pairs less the safety margin \[m\]) in one evaluation; the
    /// self-motion search keeps the value whose solutions have the largest.
    fn assess(&self, q: &[f64]) -> Result<Assessment>;

    /// The first configuration [`rejects`](Admissible::rejects) would refuse
    /// on the straight joint-space segment q(s) = from + s·(to − from),
    /// s ∈ \[0, 1\], as (s, why); `None` when there is none. It must not
    /// miss one between samples (a scene: a continuous check), so that
    /// [`traj::check`](crate::traj::check) can certify a whole motion.
    fn first_rejection_between(&self, from: &[f64], to: &[f64]) -> Result<Option<(f64, Rejection)>>;
}

/// What [`Admissible::assess`] found.
#[derive(Debug, Clone, PartialEq)]
pub enum Assessment {
    /// Not admissible, and why.
    Rejected(Rejection),
    /// Admissible, with this clearance.
    Clear(f64),
}

impl fmt::Debug for dyn Admissible + '_ {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("<admissibility test>")
    }
}

/// Why a configuration was rejected.
#[derive(Debug, Clone, PartialEq)]
pub struct Rejection {
    /// Which test rejected it, one word: `collision`.
    pub kind: &'static str,
    /// What it found, e.g. `link_4 – bench`.
    pub detail: String,
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.kind, self.detail)
    }
}

/// Samples of the self-motion parameter over its range (ψ: a full turn;
/// q3: the joint's limits): 2.5° apart on a full turn.
const SELF_MOTION_SAMPLES: usize = 144;

/// Moves the solutions of `answer` that `test` rejects into its discarded
/// list; `Ok(false)` when none is left.
fn sort_out(answer: &mut IkAnswer, test: &dyn Admissible) -> Result<bool> {
    let mut kept = Vec::with_capacity(answer.solutions.len());
    for s in answer.solutions.drain(..) {
        match test.rejects(&s.q)? {
            None => kept.push(s),
            Some(rejection) => answer.discarded.push(discard(s, rejection)),
        }
    }
    answer.solutions = kept;
    Ok(!answer.solutions.is_empty())
}

/// A rejected solution as a discarded candidate.
fn discard(s: Solution, rejection: Rejection) -> Discarded {
    Discarded {
        residual: Residual { position: s.position_error, orientation: s.orientation_error },
        branch: s.branch,
        rejection: Some(rejection),
    }
}

/// The refusal when every solution was rejected.
fn refusal(answer: &IkAnswer, searched: Option<SelfMotionParameter>) -> Error {
    let rejected: Vec<&Rejection> = answer.discarded.iter().filter_map(|d| d.rejection.as_ref()).collect();
    let first = rejected.first().map_or(String::new(), |r| r.to_string());
    Error::Unreachable {
        solver: answer.solver.to_string(),
        reason: Unreachable::Rejected { candidates: rejected.len(), first, searched: searched.map(|p| p.to_string()) },
        closest: None,
    }
}

/// `answer` with the solutions `test` rejects discarded. When none is left
/// and `search` is given (a redundant family, a full pose, no q3 or ψ fixed
/// by the request), the self-motion is searched; else
/// [`Unreachable::Rejected`].
pub(super) fn admit(
    mut answer: IkAnswer,
    test: &dyn Admissible,
    search: Option<SelfMotionSearch<'_>>,
) -> Result<IkAnswer> {
    if sort_out(&mut answer, test)? {
        return Ok(answer);
    }
    let Some(search) = search else {
        return Err(refusal(&answer, None));
    };
    let parameter = search.redundancy.parameters()[0];
    match search.best(test)? {
        Some(mut found) => {
            let mut discarded = std::mem::take(&mut answer.discarded);
            discarded.append(&mut found.discarded);
            found.discarded = discarded;
            Ok(found)
        }
        None => Err(refusal(&answer, Some(parameter))),
    }
}

/// What the self-motion search needs: the family's redundancy, and how a
/// value's candidates become an answer (the contract, as for the request).
pub(super) struct SelfMotionSearch<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// The fitted family's redundancy.
    pub redundancy: &'a dyn Redundancy,
    /// The target pose.
    pub target: Pose,
    /// The contract on one value's candidates.
    pub measure: &'a dyn Fn(Vec<Solution>) -> Result<IkAnswer>,
}

impl SelfMotionSearch<'_> {
    /// The values of the first parameter to try.
    fn values(&self) -> Vec<f64> {
        let (lo, hi) = match self.redundancy.parameters()[0] {
            SelfMotionParameter::ArmAngle => (-PI, PI),
            SelfMotionParameter::Q3 => {
                let limits = &self.robot.joints()[self.redundancy.joint()].limits;
                (limits.min.max(-PI), limits.max.min(PI))
            }
        };
        let n = SELF_MOTION_SAMPLES;
        (0..n).map(|k| lo + (hi - lo) * (k as f64 + 0.5) / n as f64).collect()
    }

    /// The answer at the sampled value whose admissible solutions within the
    /// limits have the largest clearance, those solutions sorted from the
    /// clearest; `None` when no value has one.
    fn best(&self, test: &dyn Admissible) -> Result<Option<IkAnswer>> {
        let parameter = self.redundancy.parameters()[0];
        let mut best: Option<(f64, IkAnswer)> = None;
        for value in self.values() {
            let answer = self.redundancy.solve_at(&self.target, parameter, value).and_then(|c| (self.measure)(c));
            let mut answer = match answer {
                Ok(a) => a,
                Err(Error::Unreachable { .. }) => continue,
                Err(e) => return Err(e),
            };
            answer.solutions.retain(Solution::within_limits);
            let mut scored = Vec::with_capacity(answer.solutions.len());
            for s in answer.solutions.drain(..) {
                match test.assess(&s.q)? {
                    Assessment::Clear(clearance) => scored.push((clearance, s)),
                    Assessment::Rejected(rejection) => answer.discarded.push(discard(s, rejection)),
                }
            }
            if scored.is_empty() {
                continue;
            }
            scored.sort_by(|a, b| b.0.total_cmp(&a.0));
            let clearance = scored[0].0;
            answer.solutions = scored.into_iter().map(|(_, s)| s).collect();
            if best.as_ref().is_none_or(|(c, _)| clearance > *c) {
                best = Some((clearance, answer));
            }
        }
        Ok(best.map(|(_, answer)| answer))
    }
}
