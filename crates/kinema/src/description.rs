//! A robot description in SI units, as the doors build it before there is a
//! robot: the TOML reader from a file, Python's `Robot.from_dh` from DH rows.
//! [`Description::problems`] is the one validation of both, naming every
//! problem at once; the TOML reader points at the line of the first.
//!
//! ```
//! use kinema::description::Description;
//! use kinema::model::{DhConvention, GeometryKind, Joint, JointType, Limits, LinkGeometry, NamedPose};
//!
//! let row = |name: &str, a: f64| Joint {
//!     name: name.into(),
//!     kind: JointType::Revolute,
//!     geometry: LinkGeometry::Dh { convention: DhConvention::Standard, d: 0.0, a, alpha: 0.0, theta: 0.0 },
//!     offset: 0.0,
//!     limits: Limits::position(-3.0, 3.0),
//! };
//! let mut desc = Description::new("planar2", GeometryKind::Standard, vec![row("j1", 1.0), row("j2", 1.0)]);
//! desc.poses.push(NamedPose { name: "home".into(), q: vec![0.0, 0.0] });
//! let robot = desc.clone().build()?;
//! assert!((robot.fk(&[0.0, 0.0])?.world_from_tool.pos.x - 2.0).abs() < 1e-12);
//!
//! desc.joints[1].limits = Limits::position(1.0, -1.0);
//! desc.poses[0].q.pop();
//! assert_eq!(desc.problems().len(), 2);
//! # Ok::<(), kinema::Error>(())
//! ```

use std::fmt;

use crate::error::{Error, ModelError, Result};
use crate::math::Pose;
use crate::model::{DhConvention, GeometryKind, Inertial, Joint, JointType, LinkGeometry, Metadata, Model, NamedPose};
use crate::robot::Robot;

/// Everything a robot is made of, in SI units (m, rad), not yet validated.
#[derive(Debug, Clone, PartialEq)]
pub struct Description {
    /// Robot name.
    pub name: String,
    /// The geometry every joint is described in.
    pub kind: GeometryKind,
    /// Manufacturer, source, notes.
    pub metadata: Metadata,
    /// The joints, base first.
    pub joints: Vec<Joint>,
    /// Mass properties, one per joint, or empty when none are known.
    pub inertials: Vec<Option<Inertial>>,
    /// `world_from_base`.
    pub base: Pose,
    /// `flange_from_tool`.
    pub tool: Pose,
    /// Named configurations; one must be `home`.
    pub poses: Vec<NamedPose>,
}

/// One thing wrong with a [`Description`].
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// The joint it concerns (0-based), if any.
    pub joint: Option<usize>,
    /// Path of the field, e.g. `joint[2].min` or `poses.home`.
    pub field: String,
    /// What is wrong (naming the joint when there is one).
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl Description {
    /// A description named `name` of `joints` in `kind` geometry, with an
    /// identity base and tool, no poses and no metadata.
    pub fn new(name: impl Into<String>, kind: GeometryKind, joints: Vec<Joint>) -> Description {
        Description {
            name: name.into(),
            kind,
            metadata: Metadata::default(),
            joints,
            inertials: Vec::new(),
            base: Pose::IDENTITY,
            tool: Pose::IDENTITY,
            poses: Vec::new(),
        }
    }

    /// Every problem of the description, in order: frames, joints, poses.
    /// [`Description::build`] may still refuse a description without any:
    /// for the model's bounds on magnitudes, more joints than the model
    /// holds, or inertial parameters that are not physical.
    pub fn problems(&self) -> Vec<Problem> {
        let mut found = Vec::new();
        if self.joints.is_empty() {
            found.push(Problem {
                joint: None,
                field: "joint".into(),
                message: "no joints: a robot needs at least one joint".into(),
            });
        }
        for (field, pose) in [("base", &self.base), ("tool", &self.tool)] {
            if !pose.is_finite() {
                found.push(Problem {
                    joint: None,
                    field: field.into(),
                    message: "values must be finite numbers".into(),
                });
            }
        }
        for (i, joint) in self.joints.iter().enumerate() {
            joint_problems(i, joint, self.kind, &mut found);
        }
        if !self.inertials.is_empty() && self.inertials.len() != self.joints.len() {
            let message = format!("{} inertials, expected one per joint ({})", self.inertials.len(), self.joints.len());
            found.push(Problem { joint: None, field: "inertial".into(), message });
        }
        self.pose_problems(&mut found);
        found
    }

    fn pose_problems(&self, found: &mut Vec<Problem>) {
        if !self.poses.iter().any(|p| p.name == "home") {
            found.push(Problem {
                joint: None,
                field: "poses.home".into(),
                message: "every robot needs a named pose `home`".into(),
            });
        }
        for p in &self.poses {
            let field = format!("poses.{}", p.name);
            if p.q.len() != self.joints.len() {
                let message = format!("{} values, expected one per joint ({})", p.q.len(), self.joints.len());
                found.push(Problem { joint: None, field, message });
            } else if let Some(x) = p.q.iter().find(|x| !x.is_finite()) {
                found.push(Problem { joint: None, field, message: format!("{x} is not a finite number") });
            }
        }
    }

    /// The robot, or an error listing every problem (`InvalidModel`).
    pub fn build(self) -> Result<Robot> {
        let problems = self.problems();
        if !problems.is_empty() {
            let list: Vec<String> = problems.iter().map(Problem::to_string).collect();
            let message = match list.len() {
                1 => list[0].clone(),
                n => format!("{n} problems:\n  {}", list.join("\n  ")),
            };
            return Err(Error::Model(ModelError::InvalidModel { robot: self.name, message }));
        }
        let Description { name, kind, metadata, joints, inertials, base, tool, poses } = self;
        let mut model = Model::builder(name, kind).metadata(metadata).joints(joints).base(base).tool(tool);
        if inertials.iter().any(Option::is_some) {
            model = model.inertials(inertials);
        }
        // `home` first, then the others in their order.
        let (home, others): (Vec<_>, Vec<_>) = poses.into_iter().partition(|p| p.name == "home");
        model = model.poses(home.into_iter().chain(others).collect());
        Ok(Robot::new(model.build()?))
    }
}

/// What is wrong with position limits `min` > `max` (or NaN), in the units given.
pub(crate) fn not_an_interval(min: f64, max: f64) -> String {
    format!("limits min = {min} and max = {max} are not an interval (need min ≤ max)")
}

/// What is wrong with a rate limit `value` ≤ 0 named `name`, in the unit given.
pub(crate) fn not_positive(name: &str, value: f64) -> String {
    format!("{value}: a {name} limit must be positive (leave it out if unknown)")
}

/// The problems of joint `i`, pushed onto `found`.
fn joint_problems(i: usize, j: &Joint, kind: GeometryKind, found: &mut Vec<Problem>) {
    let mut push = |name: &str, message: String| {
        found.push(Problem {
            joint: Some(i),
            field: format!("joint[{i}].{name}"),
            message: format!("joint {} (`{}`): {message}", i + 1, j.name),
        });
    };
    let numbers: Vec<(&str, f64)> = match (kind, j.geometry) {
        (GeometryKind::Standard, LinkGeometry::Dh { convention: DhConvention::Standard, d, a, alpha, theta })
        | (GeometryKind::Modified, LinkGeometry::Dh { convention: DhConvention::Modified, d, a, alpha, theta }) => {
            let (variable, value) = if j.kind == JointType::Prismatic { ("d", d) } else { ("theta", theta) };
            if value != 0.0 {
                push(variable, format!("{variable} = {value}, but {variable} is the joint variable ({variable} = q + offset); put a constant part into the offset"));
            }
            vec![("d", d), ("a", a), ("alpha", alpha), ("theta", theta)]
        }
        (GeometryKind::General, LinkGeometry::General { origin, axis }) => {
            let norm = axis.norm();
            if !(norm.is_finite() && (norm - 1.0).abs() <= 1e-9) {
                push("axis", format!("axis {:?} is not a unit vector", axis.as_slice()));
            }
            if !origin.is_finite() {
                push("xyz", "the joint's origin must be finite numbers".into());
            }
            Vec::new()
        }
        (kind, geometry) => {
            let described = match geometry {
                LinkGeometry::Dh { convention: DhConvention::Standard, .. } => "a standard DH row",
                LinkGeometry::Dh { convention: DhConvention::Modified, .. } => "a modified DH row",
                LinkGeometry::General { .. } => "an origin and axis",
            };
            let expected = match kind {
                GeometryKind::Standard => "standard DH",
                GeometryKind::Modified => "modified DH",
                GeometryKind::General => "general (origin and axis)",
            };
            push("geometry", format!("{described} in a robot described in {expected} geometry; use one convention"));
            Vec::new()
        }
    };
    let l = &j.limits;
    let optional = [("vel", l.vel), ("acc", l.acc), ("jerk", l.jerk), ("effort", l.effort)];
    let all = numbers
        .into_iter()
        .chain([("offset", j.offset)])
        .chain(optional.iter().filter_map(|(n, v)| v.map(|v| (*n, v))));
    for (name, v) in all {
        if !v.is_finite() {
            push(name, format!("{v} is not a finite number"));
        }
    }
    if l.min.is_nan() || l.max.is_nan() || l.min > l.max {
        push("min", not_an_interval(l.min, l.max));
    }
    for (name, v) in optional {
        if let Some(v) = v.filter(|v| *v <= 0.0) {
            push(name, not_positive(name, v));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{JointType, Limits};

    fn revolute(name: &str, convention: DhConvention) -> Joint {
        Joint {
            name: name.into(),
            kind: JointType::Revolute,
            geometry: LinkGeometry::Dh { convention, d: 0.1, a: 0.5, alpha: 0.0, theta: 0.0 },
            offset: 0.0,
            limits: Limits::unbounded(),
        }
    }

    #[test]
    fn every_problem_is_named_at_once() {
        let mut j2 = revolute("j2", DhConvention::Modified);
        let mut j3 = revolute("j3", DhConvention::Standard);
        j3.geometry =
            LinkGeometry::Dh { convention: DhConvention::Standard, d: 0.0, a: f64::NAN, alpha: 0.0, theta: 0.3 };
        j3.limits = Limits { vel: Some(-1.0), ..Limits::position(2.0, 1.0) };
        j2.offset = f64::INFINITY;
        let mut desc =
            Description::new("bad", GeometryKind::Standard, vec![revolute("j1", DhConvention::Standard), j2, j3]);
        desc.poses.push(NamedPose { name: "qr".into(), q: vec![0.0] });
        let fields: Vec<String> = desc.problems().into_iter().map(|p| p.field).collect();
        let expected = [
            "joint[1].geometry",
            "joint[1].offset",
            "joint[2].theta",
            "joint[2].a",
            "joint[2].min",
            "joint[2].vel",
            "poses.home",
            "poses.qr",
        ];
        assert_eq!(fields, expected);
        let Err(Error::Model(ModelError::InvalidModel { message, .. })) = desc.build() else { panic!() };
        assert!(message.starts_with("8 problems:") && message.contains("joint 3 (`j3`)"), "{message}");
    }

    #[test]
    fn home_comes_first_and_a_clean_description_builds() {
        let mut desc = Description::new("ok", GeometryKind::Standard, vec![revolute("j1", DhConvention::Standard)]);
        desc.poses.push(NamedPose { name: "qr".into(), q: vec![1.0] });
        desc.poses.push(NamedPose { name: "home".into(), q: vec![0.5] });
        assert!(desc.problems().is_empty());
        let robot = desc.build().unwrap();
        assert_eq!(robot.home(), &[0.5]);
        assert_eq!(robot.pose("qr").unwrap(), &[1.0]);
    }
}
