//! The one rule every door applies before it reports an IK solution: forward
//! kinematics of the solution must meet the request on every component the
//! request constrains, within a stated [`Tolerance`]. Solvers propose
//! candidates; [`sort_out`] measures each by FK, keeps those that meet the
//! target and counts the rest, so no solver (analytic, numeric, a family's
//! typed target) can report a wrong pose as a solution.

use std::borrow::Cow;

use nalgebra::Vector3;

use super::family::Family;
use super::target::IkTarget;
use super::{Closest, Solution, Unreachable};
pub use crate::error::Tolerance;
use crate::error::{Error, Result};
use crate::math::{rot_to_axis_angle, Pose};
use crate::robot::Robot;

/// The residual of one configuration against a target, on the constrained
/// components only.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Residual {
    /// Position error \[m\].
    pub position: f64,
    /// Orientation error \[rad\]; 0 when the target leaves the orientation free.
    pub orientation: f64,
}

impl Residual {
    /// Whether both errors are within `tol`.
    pub fn meets(&self, tol: &Tolerance) -> bool {
        self.position <= tol.position && self.orientation <= tol.orientation
    }

    /// One number to rank misses by: the errors relative to their tolerances.
    fn badness(&self, tol: &Tolerance) -> f64 {
        (self.position / tol.position).max(self.orientation / tol.orientation)
    }
}

/// The residual of `reached` (FK of a configuration) against `target`, with
/// `mask` selecting the components \[x y z ωx ωy ωz\] (base frame) of a full
/// pose. The orientation error of a masked pose is the norm of the selected
/// components of the axis-angle vector of R_target·R_reachedᵀ, as the numeric
/// solver measures it; unmasked it is the full rotation angle.
///
/// # Examples
/// ```
/// use kinema::ik::{contract::residual, IkTarget};
/// use kinema::math::rot_z;
/// use kinema::Pose;
/// let robot = kinema::Robot::builtin("ur5")?;
/// let reached = robot.fk(robot.home())?.world_from_tool;
/// let turned = Pose::new(rot_z(0.1) * reached.rot, reached.pos);
/// let full = residual(&robot, &IkTarget::Pose(turned), None, &reached)?;
/// assert!((full.orientation - 0.1).abs() < 1e-12);
/// // Freeing the rotation about the world z axis: met.
/// let free_z = residual(&robot, &IkTarget::Pose(turned), Some([true, true, true, true, true, false]), &reached)?;
/// assert!(free_z.orientation < 1e-12);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn residual(robot: &Robot, target: &IkTarget, mask: Option<[bool; 6]>, reached: &Pose) -> Result<Residual> {
    residual_with(robot, None, target, mask, reached)
}

/// [`residual`] with the robot's fitted family, which measures its own typed
/// targets without being fitted again.
fn residual_with(
    robot: &Robot,
    fitted: Option<&dyn Family>,
    target: &IkTarget,
    mask: Option<[bool; 6]>,
    reached: &Pose,
) -> Result<Residual> {
    let position_of = |p: &[f64; 3]| (Vector3::from(*p) - reached.pos).norm();
    Ok(match target {
        IkTarget::Pose(pose) => pose_residual(pose, reached, mask.unwrap_or([true; 6])),
        IkTarget::Position(p) => Residual { position: position_of(p), orientation: 0.0 },
        IkTarget::Typed(typed) => {
            let orientation = super::registry::with_owner(robot, fitted, typed.kind, |f| {
                Ok(f.typed_orientation_error(typed, reached))
            })?;
            Residual { position: position_of(&typed.position), orientation }
        }
    })
}

/// The masked residual of a full pose.
fn pose_residual(target: &Pose, reached: &Pose, mask: [bool; 6]) -> Residual {
    let dp = target.pos - reached.pos;
    let dw = rot_to_axis_angle(&(target.rot * reached.rot.transpose()));
    let pick = |v: Vector3<f64>, m: &[bool]| {
        Vector3::new(if m[0] { v.x } else { 0.0 }, if m[1] { v.y } else { 0.0 }, if m[2] { v.z } else { 0.0 }).norm()
    };
    Residual { position: pick(dp, &mask[..3]), orientation: pick(dw, &mask[3..]) }
}

/// A candidate a solver proposed that is not a solution: it misses the
/// target, or meets it where the request's admissibility test (a scene's
/// collision check) rejects it.
#[derive(Debug, Clone, PartialEq)]
pub struct Discarded {
    /// The solver's branch label.
    pub branch: Cow<'static, str>,
    /// Its residual on the constrained components.
    pub residual: Residual,
    /// Why the test rejected it; `None` when it misses the target.
    pub rejection: Option<super::Rejection>,
}

/// What a request got: the solutions that meet the target (each within the
/// tolerance, its residual fields measured on the constrained components)
/// and the candidates that were discarded because they do not.
#[derive(Debug, Clone, PartialEq)]
pub struct IkAnswer {
    /// The solver that proposed the candidates.
    pub solver: &'static str,
    /// Solutions meeting the target (never empty in an `Ok` answer).
    pub solutions: Vec<Solution>,
    /// Candidates whose FK misses the target by more than the tolerance, or
    /// that the request's admissibility test rejected.
    pub discarded: Vec<Discarded>,
    /// The tolerance applied.
    pub tolerance: Tolerance,
    /// Within-limit copies of the solutions (a joint turned by whole turns,
    /// see [`unfold_turns`]) left out of `solutions` because a solution had
    /// more than [`MAX_COPIES`]; 0 when every copy is listed.
    pub folded: usize,
}

/// The most within-limit copies [`unfold_turns`] lists for one solution;
/// past it, only the copy nearest the reference is kept.
pub const MAX_COPIES: usize = 64;

/// Measures every candidate of `solver` by FK against `target` (`fitted`:
/// the robot's family, if one fits, which measures its typed targets), keeps those
/// that meet it within `tol` (their `position_error`/`orientation_error`
/// become the constrained residual) and lists the others. When none meets
/// the target: [`Error::Unreachable`] with [`Unreachable::Missed`] and the
/// closest candidate.
pub fn sort_out(
    robot: &Robot,
    fitted: Option<&dyn Family>,
    target: &IkTarget,
    mask: Option<[bool; 6]>,
    tol: Tolerance,
    solver: &'static str,
    candidates: Vec<Solution>,
) -> Result<IkAnswer> {
    let mut solutions = Vec::with_capacity(candidates.len());
    let mut discarded = Vec::new();
    let mut closest: Option<(f64, Closest)> = None;
    for mut s in candidates {
        // A joint a closed form recovers on its limit can land a rounding past it.
        if s.q.len() == robot.dof() {
            super::settle_on_limits(robot, &mut s.q);
        }
        let fk = robot.fk(&s.q)?;
        let r = residual_with(robot, fitted, target, mask, &fk.world_from_tool)?;
        (s.position_error, s.orientation_error) = (r.position, r.orientation);
        s.out_of_limits = fk.out_of_limits;
        if r.meets(&tol) {
            solutions.push(s);
            continue;
        }
        let badness = r.badness(&tol);
        if closest.as_ref().is_none_or(|(b, _)| badness < *b) {
            closest = Some((badness, Closest::of(&s)));
        }
        discarded.push(Discarded { branch: s.branch, residual: r, rejection: None });
    }
    if solutions.is_empty() {
        let closest = closest.map(|(_, c)| c);
        let (position_error, orientation_error) =
            closest.as_ref().map_or((f64::INFINITY, f64::INFINITY), |c| (c.position_error, c.orientation_error));
        return Err(Error::Unreachable {
            solver: solver.into(),
            reason: Unreachable::Missed {
                candidates: discarded.len(),
                position_error,
                orientation_error,
                tolerance: tol,
                dof: robot.dof(),
            },
            closest: closest.map(Box::new),
        });
    }
    Ok(IkAnswer { solver, solutions, discarded, tolerance: tol, folded: 0 })
}

/// Replaces every solution of `answer` by its copies within the joint limits:
/// a solver returns each revolute angle once (most in (−π, π]), but a joint
/// whose range exceeds a turn (±350° wrists, ±360°) reaches the same pose at
/// `q + k·2π` too, and the solution nearest a previous configuration may be
/// such a copy. A solution within limits becomes every combination of its
/// joints' within-limit copies (the one nearest the solver's values first),
/// up to [`MAX_COPIES`], past which only the combination nearest `q0` (else
/// the solver's values) is kept and the rest counted in
/// [`IkAnswer::folded`]. A solution outside the limits keeps one copy, each
/// joint nearest `q0` within its limits where it can be. A continuous joint
/// takes the copy nearest `q0`. Each new copy is measured by FK as
/// [`sort_out`] measures candidates (`fitted` as there).
pub fn unfold_turns(
    robot: &Robot,
    fitted: Option<&dyn Family>,
    target: &IkTarget,
    mask: Option<[bool; 6]>,
    answer: &mut IkAnswer,
    q0: Option<&[f64]>,
) -> Result<()> {
    let n = robot.dof();
    let q0 = q0.filter(|q0| q0.len() == n);
    let mut out = Vec::with_capacity(answer.solutions.len());
    let mut per_joint: Vec<Vec<f64>> = vec![Vec::new(); n];
    for s in std::mem::take(&mut answer.solutions) {
        if s.q.len() != n {
            out.push(s);
            continue;
        }
        for (i, j) in robot.joints().iter().enumerate() {
            let reference = q0.map_or(s.q[i], |q0| q0[i]);
            super::turn_copies(j, s.q[i], reference, &mut per_joint[i]);
        }
        let count = per_joint.iter().try_fold(1usize, |acc, c| acc.checked_mul(c.len()));
        let nearest = |i: usize, c: &[f64]| {
            let r = q0.map_or(s.q[i], |q0| q0[i]);
            c.iter().copied().min_by(|a, b| (a - r).abs().total_cmp(&(b - r).abs())).unwrap_or(s.q[i])
        };
        let combos: Vec<Vec<f64>> = match count {
            Some(c) if c > 0 && c <= MAX_COPIES => {
                let mut combos = vec![Vec::with_capacity(n)];
                for copies in &per_joint {
                    combos = combos
                        .into_iter()
                        .flat_map(|prefix| {
                            copies.iter().map(move |&v| {
                                let mut q = prefix.clone();
                                q.push(v);
                                q
                            })
                        })
                        .collect();
                }
                combos
            }
            other => {
                match other {
                    Some(0) => {}
                    Some(c) => answer.folded = answer.folded.saturating_add(c - 1),
                    None => answer.folded = usize::MAX,
                }
                vec![(0..n).map(|i| nearest(i, &per_joint[i])).collect()]
            }
        };
        for q in combos {
            if q == s.q {
                out.push(s.clone());
                continue;
            }
            let fk = robot.fk(&q)?;
            let r = residual_with(robot, fitted, target, mask, &fk.world_from_tool)?;
            if r.meets(&answer.tolerance) {
                out.push(Solution {
                    q,
                    out_of_limits: fk.out_of_limits,
                    position_error: r.position,
                    orientation_error: r.orientation,
                    ..s.clone()
                });
            }
        }
    }
    answer.solutions = out;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{rot_x, rot_z};

    #[test]
    fn masked_components_are_not_measured() {
        let reached = Pose::new(rot_x(0.3), Vector3::new(0.1, 0.2, 0.3));
        let target = Pose::new(rot_z(0.2) * rot_x(0.3), Vector3::new(0.1, 0.2, 0.5));
        let full = pose_residual(&target, &reached, [true; 6]);
        assert!((full.position - 0.2).abs() < 1e-15 && (full.orientation - 0.2).abs() < 1e-12);
        let free = pose_residual(&target, &reached, [true, true, false, true, true, false]);
        assert!(free.position < 1e-15 && free.orientation < 1e-12, "{free:?}");
        let tol = Tolerance::default();
        assert!(free.meets(&tol) && !full.meets(&tol));
    }

    /// Unmeasured candidates (what the closed forms propose) leave the
    /// contract with the residual and limit flags FK gives them.
    #[test]
    fn unmeasured_candidates_are_measured_and_flagged() {
        let robot = Robot::builtin("puma560").unwrap();
        let inside = robot.home().to_vec();
        let mut outside = inside.clone();
        outside[1] = robot.joints()[1].limits.max + 0.5;
        let missing = {
            let mut q = inside.clone();
            q[0] += 0.1;
            q
        };
        let target = IkTarget::Pose(robot.fk(&inside).unwrap().world_from_tool);
        let target_out = IkTarget::Pose(robot.fk(&outside).unwrap().world_from_tool);
        let tol = Tolerance::default();
        let propose =
            |q: &Vec<f64>| vec![Solution::unmeasured(q.clone(), "a"), Solution::unmeasured(missing.clone(), "b")];

        let answer = sort_out(&robot, None, &target, None, tol, "test", propose(&inside)).unwrap();
        assert_eq!(answer.solutions.len(), 1);
        let s = &answer.solutions[0];
        assert!(s.within_limits() && s.position_error < 1e-12 && s.orientation_error < 1e-12);
        assert_eq!(answer.discarded.len(), 1);
        assert!(answer.discarded[0].residual.orientation > 0.05);

        let answer = sort_out(&robot, None, &target_out, None, tol, "test", propose(&outside)).unwrap();
        assert_eq!(answer.solutions[0].out_of_limits.indices().collect::<Vec<_>>(), vec![1]);
    }
}
