//! Keywords, names and numbers as they appear in messages and the listing.

use std::f64::consts::PI;

use kinema::math::Pose;
use kinema::nalgebra::Vector3;
use kinema::traj::Profile;
use kinema::{ik, Robot, RpyConvention};

use crate::ast::{MotionKind, StmtKind};

/// The statement keyword, for messages.
pub(super) fn keyword_of(k: &StmtKind) -> &'static str {
    match k {
        StmtKind::Pos { .. } => "POS",
        StmtKind::Motion { kind: MotionKind::Ptp, .. } => "PTP",
        StmtKind::Motion { kind: MotionKind::Lin, .. } => "LIN",
        StmtKind::Circ { .. } => "CIRC",
        StmtKind::Speed(_) => "SPEED",
        StmtKind::Vel(_) => "VEL",
        StmtKind::Acc(_) => "ACC",
        StmtKind::JVel(_) => "JVEL",
        StmtKind::JAcc(_) => "JACC",
        StmtKind::Profile(_) => "PROFILE",
        StmtKind::Redundancy { .. } => "REDUNDANCY",
        StmtKind::Tool(_) => "TOOL",
        StmtKind::Base(_) => "BASE",
        StmtKind::Wait(_) => "WAIT",
        StmtKind::Home(_) => "HOME",
        StmtKind::Loop { .. } => "LOOP",
        StmtKind::For { .. } => "FOR",
        StmtKind::MoveZ { .. } => "MOVEZ",
        StmtKind::MoveTita { .. } => "MOVETITA",
        StmtKind::MoveXy { .. } => "MOVEXY",
    }
}

pub(super) fn parse_profile(key: &str) -> Option<Profile> {
    match key {
        "trapezoid" | "trapezoidal" => Some(Profile::Trapezoid),
        "scurve" | "s-curve" => Some(Profile::SCurve),
        "quintic" => Some(Profile::Quintic),
        "cubic" => Some(Profile::Cubic),
        _ => None,
    }
}

pub(super) fn joint_example(robot: &Robot) -> String {
    robot
        .joints()
        .iter()
        .map(|j| if j.kind == kinema::JointType::Prismatic { "0mm" } else { "0deg" })
        .collect::<Vec<_>>()
        .join(", ")
}

/// A value to 4 decimals, the same on every machine: no `-0.0000`.
fn fmt4(v: f64) -> String {
    if v.abs() < 5e-5 {
        "0.0000".into()
    } else {
        format!("{v:.4}")
    }
}

/// An angle to 4 decimals in (−π, π], −π shown as π (rounding decides between them).
pub(super) fn fmt_angle(a: f64) -> String {
    let a = ik::wrap_angle(a);
    fmt4(if a < -PI + 5e-5 { a + 2.0 * PI } else { a })
}

pub(super) fn fmt_xyz(p: &Vector3<f64>) -> String {
    format!("{}, {}, {}", fmt4(p.x), fmt4(p.y), fmt4(p.z))
}

pub(super) fn fmt_joints(q: &[f64]) -> String {
    q.iter().map(|v| fmt4(*v)).collect::<Vec<_>>().join(", ")
}

pub(super) fn describe_pose(p: &Pose) -> String {
    let r = p.rpy(RpyConvention::Zyx);
    format!("xyz ({}) m, rpy ({}, {}, {}) rad", fmt_xyz(&p.pos), fmt_angle(r[0]), fmt_angle(r[1]), fmt_angle(r[2]))
}
