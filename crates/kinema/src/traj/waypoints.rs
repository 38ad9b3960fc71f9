//! Waypoints a robot cannot reach, skipped (seed 003 Fig. 9: a desired path
//! with a point outside the workspace, which the generated trajectory
//! ignores). Skipping is always asked for explicitly; by default an
//! unreachable waypoint is an error.

use crate::error::{Error, Result};
use crate::ik::{self, IkRequest, IkTarget};
use crate::math::Pose;
use crate::robot::Robot;

/// A waypoint left out of a path, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct SkippedPoint {
    /// Its index among the waypoints given.
    pub index: usize,
    /// The pose.
    pub pose: Pose,
    /// Why the robot cannot take it (the inverse kinematics' reason).
    pub reason: String,
}

/// Whether `robot` reaches `pose` with a configuration within its limits,
/// by the same contract as `kinema ik`: `Err` with the reason when not.
pub fn reach(robot: &Robot, pose: &Pose) -> Result<()> {
    let answer = ik::solve_target(robot, &IkTarget::Pose(*pose), &IkRequest::default())?;
    ik::pick_one(robot, answer.solver, answer.solutions, None).map(|_| ())
}

/// The waypoints `robot` reaches, in order, and those it skips with their
/// reasons. An error when it reaches none, or when a pose is malformed
/// (only unreachable poses are skipped).
///
/// # Examples
/// ```
/// use kinema::traj::waypoints::skip_unreachable;
/// use kinema::Pose;
/// let robot = kinema::Robot::builtin("puma560")?;
/// let near = robot.fk(&[0.2, 0.4, -2.6, 0.1, 0.8, 0.3])?.world_from_tool;
/// let far = Pose::new(near.rot, near.pos * 10.0);
/// let (kept, skipped) = skip_unreachable(&robot, &[near, far, near])?;
/// assert_eq!((kept.len(), skipped.len(), skipped[0].index), (2, 1, 1));
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn skip_unreachable(robot: &Robot, points: &[Pose]) -> Result<(Vec<Pose>, Vec<SkippedPoint>)> {
    let mut kept = Vec::with_capacity(points.len());
    let mut skipped = Vec::new();
    for (index, pose) in points.iter().enumerate() {
        match reach(robot, pose) {
            Ok(()) => kept.push(*pose),
            Err(e @ Error::Unreachable { .. }) => {
                skipped.push(SkippedPoint { index, pose: *pose, reason: e.to_string() })
            }
            Err(e) => return Err(e),
        }
    }
    if kept.is_empty() {
        return Err(Error::Infeasible {
            what: "waypoints".into(),
            reason: format!("robot `{}` reaches none of the {} waypoints", robot.name(), points.len()),
        });
    }
    Ok((kept, skipped))
}
