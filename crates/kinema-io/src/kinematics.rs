//! Forward kinematics, the Jacobian and manipulability, as answers.

use kinema::analysis::{self, Axes};
use kinema::nalgebra::{Matrix6xX, Vector3};
use kinema::{DhConvention, Fk, Frame, LinkGeometry, Pose, Result, Robot, RpyConvention};
use serde::Serialize;

use crate::pose::PoseAnswer;
use crate::robot::kind_name;

/// A joint by its number (from 1, as printed) and name.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointRef {
    /// The joint's number, counting from 1.
    pub joint: usize,
    /// The joint's name.
    pub name: String,
}

/// The joints `fk` flags as outside their position limits.
fn out_of_limits(robot: &Robot, fk: &Fk) -> Vec<JointRef> {
    fk.out_of_limits.indices().map(|i| JointRef { joint: i + 1, name: robot.joints()[i].name.clone() }).collect()
}

/// One frame along the chain, in the world frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrameAnswer {
    /// Origin \[m\].
    pub position: [f64; 3],
    /// Rotation matrix, row by row.
    pub rotation: [[f64; 3]; 3],
}

/// A joint's axis in the world frame, for drawing.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointAxis {
    /// The joint's name.
    pub name: String,
    /// `revolute` or `prismatic`.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// A point on the axis \[m\].
    pub origin: [f64; 3],
    /// The axis direction (unit vector).
    pub axis: [f64; 3],
    /// Whether the joint's value is within its limits.
    pub within_limits: bool,
}

/// The answer to forward kinematics: the tool pose (its fields at the top
/// level), the configuration, the joints outside their limits, and every
/// frame and joint axis along the chain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FkAnswer {
    /// The tool pose in the world frame.
    #[serde(flatten)]
    pub pose: PoseAnswer,
    /// The robot's name.
    pub robot: String,
    /// The joint values \[rad, m\].
    pub q: Vec<f64>,
    /// Whether every joint value is within its limits.
    pub within_limits: bool,
    /// The joints outside their limits.
    pub out_of_limits: Vec<JointRef>,
    /// `frames[0]` the base, `frames[i]` link i, the last one the tool (as
    /// [`Robot::link_frames`]).
    pub frames: Vec<FrameAnswer>,
    /// `joints[i]` is joint i + 1's axis: standard DH the z of frame i − 1,
    /// modified DH the z of frame i, general the joint's axis in frame i.
    pub joints: Vec<JointAxis>,
}

impl FkAnswer {
    /// Forward kinematics of `robot` at `q`, the tool's roll-pitch-yaw in `convention`.
    pub fn new(robot: &Robot, q: &[f64], convention: RpyConvention) -> Result<FkAnswer> {
        let mut frames = vec![Pose::IDENTITY; robot.dof() + 2];
        let fk = kinema::kin::link_frames_into(robot, q, &mut frames)?;
        let joints = robot
            .joints()
            .iter()
            .enumerate()
            .map(|(i, j)| {
                let (origin, dir) = match j.geometry {
                    LinkGeometry::Dh { convention: DhConvention::Standard, .. } => {
                        (frames[i].pos, frames[i].rot.column(2).into_owned())
                    }
                    LinkGeometry::Dh { .. } => (frames[i + 1].pos, frames[i + 1].rot.column(2).into_owned()),
                    LinkGeometry::General { axis, .. } => (frames[i + 1].pos, frames[i + 1].rot * axis),
                };
                JointAxis {
                    name: j.name.clone(),
                    kind: kind_name(j.kind),
                    origin: xyz(&origin),
                    axis: xyz(&dir),
                    within_limits: !fk.out_of_limits.contains(i),
                }
            })
            .collect();
        Ok(FkAnswer {
            pose: PoseAnswer::new(&fk.world_from_tool, convention),
            robot: robot.name().to_string(),
            q: q.to_vec(),
            within_limits: fk.within_limits(),
            out_of_limits: out_of_limits(robot, &fk),
            frames: frames
                .iter()
                .map(|f| FrameAnswer {
                    position: xyz(&f.pos),
                    rotation: std::array::from_fn(|r| std::array::from_fn(|c| f.rot[(r, c)])),
                })
                .collect(),
            joints,
        })
    }
}

fn xyz(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// The Jacobian's rows as arrays.
fn rows(j: &Matrix6xX<f64>) -> Vec<Vec<f64>> {
    (0..j.nrows()).map(|r| j.row(r).iter().copied().collect()).collect()
}

/// A Jacobian: geometric (rows [v; ω] in the base or tool frame) or analytic
/// (rows [v; roll-pitch-yaw rates]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JacobianAnswer {
    /// The robot's name.
    pub robot: String,
    /// The joint values \[rad, m\].
    pub q: Vec<f64>,
    /// `geometric, base frame`, `geometric, tool frame` or `analytic (rpy zyx|xyz)`.
    pub kind: String,
    /// The 6×n matrix, row by row.
    #[serde(rename = "J")]
    pub matrix: Vec<Vec<f64>>,
}

impl JacobianAnswer {
    /// The geometric Jacobian in `frame`.
    pub fn geometric(robot: &Robot, q: &[f64], frame: Frame) -> Result<JacobianAnswer> {
        let j = robot.jacobian(q, frame)?;
        Ok(JacobianAnswer::of(robot, q, format!("geometric, {frame} frame"), &j))
    }

    /// The analytic Jacobian for roll-pitch-yaw rates in `convention`.
    pub fn analytic(robot: &Robot, q: &[f64], convention: RpyConvention) -> Result<JacobianAnswer> {
        let j = robot.analytic_jacobian(q, convention)?;
        Ok(JacobianAnswer::of(robot, q, format!("analytic (rpy {convention})"), &j))
    }

    fn of(robot: &Robot, q: &[f64], kind: String, j: &Matrix6xX<f64>) -> JacobianAnswer {
        JacobianAnswer { robot: robot.name().to_string(), q: q.to_vec(), kind, matrix: rows(j) }
    }
}

/// A manipulability ellipsoid centred at the tool point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ellipsoid {
    /// The tool position \[m\].
    pub centre: [f64; 3],
    /// Radii, largest first \[m/s or rad/s per unit joint speed\].
    pub radii: [f64; 3],
    /// Principal axes (unit vectors), in the order of `radii`.
    pub axes: [[f64; 3]; 3],
}

impl Ellipsoid {
    fn new(e: &analysis::Ellipsoid, centre: [f64; 3]) -> Ellipsoid {
        Ellipsoid {
            centre,
            radii: [e.radii[0], e.radii[1], e.radii[2]],
            axes: std::array::from_fn(|k| [e.axes[(0, k)], e.axes[(1, k)], e.axes[(2, k)]]),
        }
    }
}

/// A joint whose Jacobian column is a combination of earlier ones.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DependentJoint {
    /// The joint, counting from 1.
    pub joint: usize,
    /// The earlier joints (from 1) and their coefficients.
    pub depends_on: Vec<Coefficient>,
}

/// One term of a [`DependentJoint`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Coefficient {
    /// The earlier joint, counting from 1.
    pub joint: usize,
    /// Its coefficient.
    pub coefficient: f64,
}

/// Manipulability and singularity measures at one configuration (geometric
/// Jacobian in the base frame).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ManipAnswer {
    /// The robot's name.
    pub robot: String,
    /// The joint values \[rad, m\].
    pub q: Vec<f64>,
    /// Yoshikawa's measure √det(J·Jᵀ).
    pub yoshikawa: f64,
    /// Of the translational rows.
    pub yoshikawa_translation: f64,
    /// Of the rotational rows.
    pub yoshikawa_rotation: f64,
    /// σ_max / σ_min; `null` at a singularity (infinite).
    pub condition: Option<f64>,
    /// The Jacobian's numerical rank.
    pub rank: usize,
    /// The singular-value tolerance of `rank`.
    pub rank_tolerance: f64,
    /// Singular values, largest first.
    pub singular_values: Vec<f64>,
    /// The output directions of the singular values.
    pub singular_directions: Vec<[f64; 6]>,
    /// Joints whose column depends on earlier ones.
    pub dependent_joints: Vec<DependentJoint>,
    /// The translational velocity ellipsoid.
    pub ellipsoid_translation: Ellipsoid,
    /// The rotational velocity ellipsoid.
    pub ellipsoid_rotation: Ellipsoid,
    /// The translational manipulability along a direction; only when one was asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub manipulability_along: Option<f64>,
}

impl ManipAnswer {
    /// The measures of `robot` at `q`; `direction` (any length but zero) adds
    /// the manipulability along it.
    pub fn new(robot: &Robot, q: &[f64], direction: Option<Vector3<f64>>) -> Result<ManipAnswer> {
        let fk = robot.fk(q)?;
        let j = robot.jacobian(q, Frame::Base)?;
        let rep = analysis::report(&j)?;
        let centre = xyz(&fk.world_from_tool.pos);
        let along = direction.map(|d| analysis::manipulability_along(&j, Axes::Translation, &d)).transpose()?;
        Ok(ManipAnswer {
            robot: robot.name().to_string(),
            q: q.to_vec(),
            yoshikawa: rep.yoshikawa,
            yoshikawa_translation: rep.yoshikawa_translation,
            yoshikawa_rotation: rep.yoshikawa_rotation,
            condition: Some(rep.condition).filter(|c| c.is_finite()),
            rank: rep.rank,
            rank_tolerance: rep.rank_tolerance,
            singular_values: rep.singular_values,
            singular_directions: rep.singular_directions,
            dependent_joints: rep
                .dependent_joints
                .iter()
                .map(|d| DependentJoint {
                    joint: d.joint + 1,
                    depends_on: d.on.iter().map(|&(k, c)| Coefficient { joint: k + 1, coefficient: c }).collect(),
                })
                .collect(),
            ellipsoid_translation: Ellipsoid::new(&analysis::ellipsoid(&j, Axes::Translation)?, centre),
            ellipsoid_rotation: Ellipsoid::new(&analysis::ellipsoid(&j, Axes::Rotation)?, centre),
            manipulability_along: along,
        })
    }
}
