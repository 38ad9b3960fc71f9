//! Branch jumps found without any limit: between two samples the joints
//! move a long way while the tool barely does.
//!
//! A joint step of S rad moves points at the arm's length L by up to L·S. In
//! a sampled motion the joints move about as far as the tool's motion needs
//! (its step over L, plus its turn): more near a singularity, but not a
//! hundred times more over a tenth of a radian. A step that does is a
//! discontinuity — a change of inverse-kinematics branch, or of a redundant
//! arm's self-motion in one sample — however fast the joints may move.

use super::JointTrajectory;
use crate::error::Result;
use crate::error::{Violation, ViolationKind};
use crate::math::rot_to_axis_angle;
use crate::model::JointType;
use crate::robot::Robot;

/// The smallest joint step \[rad, prismatic joints per arm length\] that can
/// be a jump: below it, steps are as small as slow sampled motions make.
const MIN_STEP: f64 = 0.1;

/// How many times more than the tool's step the joints may move.
const MAX_GAIN: f64 = 100.0;

/// One violation per step in which the joints move more than [`MIN_STEP`]
/// and more than [`MAX_GAIN`] times the tool's step, at the step's second
/// sample, naming the joint that moves most; `value` is the joint step and
/// `limit` the tool's step (both in radians at the arm's length). Steps for
/// which `skip(k)` is true (already reported as a jump) are passed over, and
/// so are steps with a non-finite value or a time that does not increase.
pub(super) fn branch_jumps(
    robot: &Robot,
    traj: &JointTrajectory,
    skip: impl Fn(usize) -> bool,
) -> Result<Vec<Violation>> {
    let mut out = Vec::new();
    let Some(first) = (0..traj.len()).find(|&k| finite(traj, k)) else { return Ok(out) };
    let length = arm_length(robot, traj.q(first))?;
    for k in 1..traj.len() {
        let (t0, t1) = (traj.times()[k - 1], traj.times()[k]);
        if skip(k) || !(finite(traj, k - 1) && finite(traj, k) && t1 > t0) {
            continue;
        }
        let (q0, q1) = (traj.q(k - 1), traj.q(k));
        let joints = joint_step(robot, q0, q1, length);
        if joints <= MIN_STEP {
            continue;
        }
        let (p0, p1) = (robot.fk(q0)?.world_from_tool, robot.fk(q1)?.world_from_tool);
        let tool = (p1.pos - p0.pos).norm() / length + rot_to_axis_angle(&(p1.rot * p0.rot.transpose())).norm();
        if joints > MAX_GAIN * tool {
            let joint = (0..q0.len()).max_by(|&a, &b| (q1[a] - q0[a]).abs().total_cmp(&(q1[b] - q0[b]).abs()));
            out.push(Violation {
                kind: ViolationKind::BranchJump,
                sample: k,
                time: t1,
                joint,
                value: joints,
                limit: tool,
                detail: None,
            });
        }
    }
    Ok(out)
}

/// The joints' step from `q0` to `q1`: revolute joints in radians,
/// prismatic ones divided by the arm's `length`, summed.
fn joint_step(robot: &Robot, q0: &[f64], q1: &[f64], length: f64) -> f64 {
    robot
        .joints()
        .iter()
        .zip(q0.iter().zip(q1))
        .map(|(j, (a, b))| match j.kind {
            JointType::Revolute => (b - a).abs(),
            JointType::Prismatic => (b - a).abs() / length,
        })
        .sum()
}

/// The arm's length \[m\]: the distances between consecutive frames from the
/// base to the tool at `q`, plus the stroke of every prismatic joint.
fn arm_length(robot: &Robot, q: &[f64]) -> Result<f64> {
    let frames = robot.link_frames(q)?;
    let links: f64 = frames.windows(2).map(|w| (w[1].pos - w[0].pos).norm()).sum();
    let strokes: f64 = robot
        .joints()
        .iter()
        .filter(|j| j.kind == JointType::Prismatic)
        .map(|j| j.limits.max - j.limits.min)
        .filter(|r| r.is_finite())
        .sum();
    Ok((links + strokes).max(f64::MIN_POSITIVE))
}

/// Whether sample `k` holds only finite values.
fn finite(traj: &JointTrajectory, k: usize) -> bool {
    traj.times()[k].is_finite() && traj.q(k).iter().all(|x| x.is_finite())
}
