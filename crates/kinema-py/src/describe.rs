//! Robots defined in code: `Robot.from_dh` (the toolbox's `DHRobot` of
//! `RevoluteDH`/`PrismaticDH` links) and `Robot.from_urdf_string`. The rows
//! become a core `Description`, whose one validation names every problem.

use std::sync::Arc;

use kinema::description::Description;
use kinema::math::Pose;
use kinema::model::{DhConvention, GeometryKind, Joint, JointType, Limits, LinkGeometry, NamedPose};
use kinema::Robot;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::args::{check_shape, f64_array, pose_from_rows};
use crate::collision::{DescriptionText, Inline, Source};
use crate::errors::{invalid, to_py};
use crate::robot::PyRobot;

/// A number attribute of a DH link, named in errors as `links[i].name`.
fn number(link: &Bound<'_, PyAny>, i: usize, name: &str) -> PyResult<f64> {
    link.getattr(name)?.extract().map_err(|_| invalid(format!("`links[{i}].{name}` must be a real number")))
}

/// One link of `from_dh` as a core joint, with whether it is a modified-DH row.
fn joint_of(link: &Bound<'_, PyAny>, i: usize) -> PyResult<(Joint, bool)> {
    let kind_of = |attr: &str| -> PyResult<bool> {
        link.getattr(attr).and_then(|v| v.extract()).map_err(|_| {
            invalid(format!(
                "`links[{i}]` is not a DH link: use kinema.RevoluteDH, PrismaticDH, RevoluteMDH or PrismaticMDH"
            ))
        })
    };
    let (prismatic, modified) = (kind_of("prismatic")?, kind_of("modified")?);
    let qlim = link.getattr("qlim")?;
    let limits = if qlim.is_none() {
        Limits::unbounded()
    } else {
        let what = format!("links[{i}].qlim");
        let a = f64_array(&qlim, &what)?;
        check_shape(&a, &what, &[Some(2)], " (lower, upper)")?;
        let v = a.as_slice()?;
        Limits::position(v[0], v[1])
    };
    let name: Option<String> = link.getattr("name")?.extract()?;
    let convention = if modified { DhConvention::Modified } else { DhConvention::Standard };
    let geometry = LinkGeometry::Dh {
        convention,
        d: number(link, i, "d")?,
        a: number(link, i, "a")?,
        alpha: number(link, i, "alpha")?,
        theta: number(link, i, "theta")?,
    };
    let joint = Joint {
        name: name.unwrap_or_else(|| format!("q{}", i + 1)),
        kind: if prismatic { JointType::Prismatic } else { JointType::Revolute },
        geometry,
        offset: number(link, i, "offset")?,
        limits,
    };
    Ok((joint, modified))
}

/// A base or tool argument: a 4×4 array, or anything with a 4×4 `.A` (spatialmath's `SE3`).
fn frame_arg(obj: Option<&Bound<'_, PyAny>>, what: &str) -> PyResult<Pose> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(Pose::IDENTITY);
    };
    let matrix = if obj.hasattr("A")? && obj.hasattr("t")? { obj.getattr("A")? } else { obj.clone() };
    let a = f64_array(&matrix, what)?;
    check_shape(&a, what, &[Some(4), Some(4)], " (a homogeneous transform)")?;
    pose_from_rows(a.as_slice()?, what)
}

#[pymethods]
impl PyRobot {
    /// A robot from a DH table in code, as the toolbox's
    /// ``DHRobot([RevoluteDH(...), PrismaticDH(...)], name=..., base=..., tool=...)``.
    ///
    /// ``links``: :class:`RevoluteDH`, :class:`PrismaticDH` (standard DH) or
    /// :class:`RevoluteMDH`, :class:`PrismaticMDH` (modified DH), all of one
    /// convention; values in m and rad. ``base`` (``world_from_base``) and
    /// ``tool`` (``flange_from_tool``): 4×4 arrays or spatialmath ``SE3``.
    /// ``poses``: named configurations ``{name: q}``; ``home`` is all zeros
    /// unless given.
    ///
    /// Raises:
    ///     DescriptionError: the description is invalid; the message lists every problem.
    ///     InvalidInput: a link is not a DH link, or an argument has the wrong type or shape.
    #[staticmethod]
    #[pyo3(signature = (links, name="robot", base=None, tool=None, poses=None))]
    fn from_dh(
        links: &Bound<'_, PyAny>,
        name: &str,
        base: Option<&Bound<'_, PyAny>>,
        tool: Option<&Bound<'_, PyAny>>,
        poses: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        if links.is_instance_of::<PyString>() {
            return Err(invalid("`links` must be a list of DH links".into()));
        }
        let mut joints = Vec::new();
        let mut modified = Vec::new();
        for (i, link) in links.try_iter()?.enumerate() {
            let (joint, is_modified) = joint_of(&link?, i)?;
            joints.push(joint);
            modified.push(is_modified);
        }
        // The first link's convention is the robot's; a link of the other is one of its problems.
        let kind = if modified.first() == Some(&true) { GeometryKind::Modified } else { GeometryKind::Standard };
        let dof = joints.len();
        let mut desc = Description::new(name, kind, joints);
        desc.metadata.source = "defined in Python (Robot.from_dh)".into();
        desc.base = frame_arg(base, "base")?;
        desc.tool = frame_arg(tool, "tool")?;
        if let Some(poses) = poses {
            for (key, value) in poses.iter() {
                let name: String = key.extract().map_err(|_| invalid("`poses` keys must be names (str)".into()))?;
                let what = format!("poses[{name:?}]");
                let a = f64_array(&value, &what)?;
                check_shape(&a, &what, &[None], " (one value per joint)")?;
                desc.poses.push(NamedPose { name, q: a.as_slice()?.to_vec() });
            }
        }
        if !desc.poses.iter().any(|p| p.name == "home") {
            desc.poses.push(NamedPose { name: "home".into(), q: vec![0.0; dof] });
        }
        let robot = desc.clone().build().map_err(to_py)?;
        let source = Source::inline(name, Inline::Description(Arc::new(desc)));
        Ok(PyRobot::new(Arc::new(robot), source))
    }

    /// A robot from the text of a URDF document; ``tip`` names the chain's
    /// last link (default: the only leaf link). Its ``<collision>`` shapes
    /// serve :meth:`collides`; relative mesh paths are taken from the working
    /// directory.
    ///
    /// Raises:
    ///     DescriptionError: the URDF is malformed or has no chain to ``tip``.
    #[staticmethod]
    #[pyo3(signature = (text, tip=None))]
    fn from_urdf_string(text: &str, tip: Option<&str>) -> PyResult<Self> {
        let robot = Robot::from_urdf_str(text, "<string>", tip).map_err(to_py)?;
        let urdf = DescriptionText {
            text: text.to_string(),
            file: "<string>".into(),
            dir: ".".into(),
            package_paths: Vec::new(),
        };
        let mut source = Source::inline(robot.name(), Inline::Urdf(Arc::new(urdf)));
        source.tip = tip.map(str::to_string);
        Ok(PyRobot::new(Arc::new(robot), source))
    }
}
