//! What a robot is: its joints, limits, poses and which IK it has.

use std::collections::BTreeMap;

use kinema::ik::family::SelfMotionParameter;
use kinema::{JointType, LinkGeometry, Named, Robot, RpyConvention};
use serde::Serialize;

use crate::pose::PoseAnswer;

/// `revolute` or `prismatic`.
pub(crate) fn kind_name(kind: JointType) -> &'static str {
    match kind {
        JointType::Revolute => "revolute",
        JointType::Prismatic => "prismatic",
    }
}

/// A joint's place in the chain: a DH row or a general origin and axis.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum JointGeometry {
    /// One row of a DH table \[m, rad\].
    Dh {
        /// `standard` or `modified`.
        convention: String,
        /// Offset along z \[m\].
        d: f64,
        /// Length along x \[m\].
        a: f64,
        /// Twist about x \[rad\].
        alpha: f64,
        /// Angle about z \[rad\].
        theta: f64,
    },
    /// An origin (translation, then roll-pitch-yaw, zyx) and a motion axis.
    General {
        /// Translation \[m\].
        xyz: [f64; 3],
        /// Roll, pitch, yaw \[rad\] (R = Rz·Ry·Rx).
        rpy: [f64; 3],
        /// The joint's axis in its own frame.
        axis: [f64; 3],
    },
}

/// One joint with its geometry and limits. An unbounded position limit is `null`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointInfo {
    /// The joint's name.
    pub name: String,
    /// `revolute` or `prismatic`.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// Added to the joint value \[rad or m\].
    pub offset: f64,
    /// Where the joint sits.
    pub geometry: JointGeometry,
    /// Lower position limit \[rad or m\].
    pub min: Option<f64>,
    /// Upper position limit \[rad or m\].
    pub max: Option<f64>,
    /// Velocity limit \[rad/s or m/s\].
    pub vel: Option<f64>,
    /// Acceleration limit.
    pub acc: Option<f64>,
    /// Jerk limit.
    pub jerk: Option<f64>,
    /// Effort limit \[N·m or N\].
    pub effort: Option<f64>,
}

/// Which inverse kinematics a robot has.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobotIk {
    /// The analytic family's name, or `null` (numeric only).
    pub analytic: Option<&'static str>,
    /// Whether the family takes the iiwa's `q3` as its redundancy parameter.
    pub q3: bool,
    /// The self-motion parameters a request may fix (`q3`, `psi`).
    pub redundancy: Vec<&'static str>,
}

/// A robot as `kinema info --json` prints it and `GET /api/robots/{name}` returns it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobotInfo {
    /// The robot's name.
    pub name: String,
    /// Its number of joints.
    pub dof: usize,
    /// `dh` or `general` (lower case).
    pub convention: String,
    /// The maker, or empty.
    pub manufacturer: String,
    /// Where the numbers come from.
    pub source: String,
    /// Notes on the model.
    pub notes: String,
    /// The joints, base first.
    pub joints: Vec<JointInfo>,
    /// The base transform (zyx roll-pitch-yaw).
    pub base: PoseAnswer,
    /// The tool transform.
    pub tool: PoseAnswer,
    /// The named configurations.
    pub poses: BTreeMap<String, Vec<f64>>,
    /// The home configuration.
    pub home: Vec<f64>,
    /// Which IK it has.
    pub ik: RobotIk,
}

impl RobotInfo {
    /// What `robot` is.
    pub fn new(robot: &Robot) -> RobotInfo {
        let family = kinema::ik::registry::fit(robot);
        let parameters = family.as_ref().and_then(|f| f.redundancy()).map_or(&[][..], |r| r.parameters());
        let redundancy: Vec<&'static str> = parameters.iter().map(|p| p.name()).collect();
        let meta = robot.metadata();
        RobotInfo {
            name: robot.name().to_string(),
            dof: robot.dof(),
            convention: format!("{:?}", robot.geometry_kind()).to_lowercase(),
            manufacturer: meta.manufacturer.clone(),
            source: meta.source.clone(),
            notes: meta.notes.clone(),
            joints: robot.joints().iter().map(joint_info).collect(),
            base: PoseAnswer::new(robot.base(), RpyConvention::Zyx),
            tool: PoseAnswer::new(robot.tool(), RpyConvention::Zyx),
            poses: robot.poses().iter().map(|p| (p.name.clone(), p.q.clone())).collect(),
            home: robot.home().to_vec(),
            ik: RobotIk {
                analytic: family.as_ref().map(|f| f.name()),
                q3: parameters.contains(&SelfMotionParameter::Q3),
                redundancy,
            },
        }
    }
}

fn joint_info(j: &kinema::Joint) -> JointInfo {
    let geometry = match j.geometry {
        LinkGeometry::Dh { convention, d, a, alpha, theta } => {
            JointGeometry::Dh { convention: format!("{convention:?}").to_lowercase(), d, a, alpha, theta }
        }
        LinkGeometry::General { origin, axis } => JointGeometry::General {
            xyz: [origin.pos.x, origin.pos.y, origin.pos.z],
            rpy: origin.rpy(RpyConvention::Zyx),
            axis: [axis.x, axis.y, axis.z],
        },
    };
    let finite = |v: f64| Some(v).filter(|v| v.is_finite());
    JointInfo {
        name: j.name.clone(),
        kind: kind_name(j.kind),
        offset: j.offset,
        geometry,
        min: finite(j.limits.min),
        max: finite(j.limits.max),
        vel: j.limits.vel,
        acc: j.limits.acc,
        jerk: j.limits.jerk,
        effort: j.limits.effort,
    }
}

/// One line of `kinema robots --json` and `GET /api/robots`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobotSummary {
    /// The robot's name.
    pub name: String,
    /// Its number of joints.
    pub dof: usize,
    /// One line: maker, DOF, joint types and source.
    pub description: String,
    /// The joint types, one letter each (`RRRRRR`).
    pub joint_types: String,
    /// The maker, or empty.
    pub manufacturer: String,
    /// Where the numbers come from.
    pub source: String,
    /// Whether it is the server's default robot (always false from the CLI).
    pub default: bool,
}

impl RobotSummary {
    /// The summary of `robot`; `default` marks the server's default robot.
    pub fn new(robot: &Robot, default: bool) -> RobotSummary {
        let m = robot.metadata();
        let description = if m.manufacturer.is_empty() {
            format!("{} DOF ({}); {}", robot.dof(), robot.joint_types(), m.source)
        } else {
            format!("{} {} DOF ({}); {}", m.manufacturer, robot.dof(), robot.joint_types(), m.source)
        };
        RobotSummary {
            name: robot.name().to_string(),
            dof: robot.dof(),
            description,
            joint_types: robot.joint_types().to_string(),
            manufacturer: m.manufacturer.clone(),
            source: m.source.clone(),
            default,
        }
    }
}
