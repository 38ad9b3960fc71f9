//! A pose goal as the set of configurations that reach it, through the IK
//! contract with the collision check as its admissibility test: every
//! branch of a closed form, samples along a redundant arm's self-motion,
//! seeded restarts of the numeric solver for an arm without a closed form.

use kinema::ik::family::SelfMotionParameter;
use kinema::ik::{pick_one, registry, solve_target_with, IkRequest, IkTarget, NumericOptions};
use kinema::Pose;

use super::budget::Budget;
use crate::check::CollisionCheck;
use crate::error::Result;

/// Configurations closer than this \[rad, m\] count as one.
const SAME: f64 = 1e-6;

/// The collision-free configurations of `check`'s robot reaching `pose`:
/// the contract's full answer, plus `samples` values of the self-motion
/// parameter across its joint's range (or `samples` numeric restarts from
/// `seed` on), all within the joint limits. An error when there are none.
pub(crate) fn goal_configurations(
    check: &CollisionCheck,
    pose: &Pose,
    samples: usize,
    seed: u64,
    budget: &Budget,
) -> Result<Vec<Vec<f64>>> {
    let robot = check.robot();
    let fitted = registry::fit(robot);
    let target = IkTarget::Pose(*pose);
    let all = IkRequest { all: true, admissible: Some(check), ..Default::default() };
    let first = solve_target_with(robot, fitted.as_deref(), &target, &all);
    let mut found: Vec<Vec<f64>> = Vec::new();
    let mut keep = |q: Vec<f64>| {
        let seen = found.iter().any(|f| f.iter().zip(&q).all(|(a, b)| (a - b).abs() < SAME));
        if !seen {
            found.push(q);
        }
    };
    if let Ok(answer) = &first {
        answer.solutions.iter().filter(|s| s.within_limits()).for_each(|s| keep(s.q.clone()));
    }
    let self_motion = fitted
        .as_deref()
        .and_then(|f| f.redundancy())
        .filter(|r| r.parameters().contains(&SelfMotionParameter::Q3))
        .map(|r| r.joint());
    for k in 0..samples {
        budget.not_cancelled()?;
        let request = match (self_motion, fitted.is_some()) {
            (Some(joint), _) => {
                let limits = robot.joints()[joint].limits;
                let value = limits.min + (k as f64 + 0.5) / samples as f64 * (limits.max - limits.min);
                IkRequest { q3: Some(value), ..all.clone() }
            }
            (None, false) => IkRequest {
                numeric: NumericOptions { seed: seed.wrapping_add(k as u64), ..Default::default() },
                ..all.clone()
            },
            (None, true) => break,
        };
        if let Ok(answer) = solve_target_with(robot, fitted.as_deref(), &target, &request) {
            answer.solutions.iter().filter(|s| s.within_limits()).for_each(|s| keep(s.q.clone()));
        }
    }
    if found.is_empty() {
        // No answer at all: the first request's error; answers all outside
        // the limits: the contract's error naming them.
        let answer = first?;
        pick_one(robot, answer.solver, answer.solutions, None)?;
    }
    Ok(found)
}
