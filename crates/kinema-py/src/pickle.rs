//! Pickling: a `Robot` or a `Scene` pickles as the description it was made
//! from, as text rather than a path (a process on another machine may not
//! have the file), so that `pickle.loads` rebuilds an equal one anywhere.
//! The state is a dict of plain Python values; `kinema._pickle` turns it back.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use kinema::description::Description;
use kinema::math::Pose;
use kinema::model::{DhConvention, GeometryKind, Joint, JointType, Limits, LinkGeometry, NamedPose};
use kinema::nalgebra::{Matrix3, Vector3};
use kinema::Robot;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::collision::{DescriptionText, Inline, PyScene, SceneText, Source};
use crate::errors::{invalid, to_py};
use crate::robot::PyRobot;

/// `path` made absolute against this process's working directory, so that a
/// process started elsewhere finds the same files (on a shared file system).
fn absolute(path: &Path) -> PathBuf {
    let path = if path.as_os_str().is_empty() { Path::new(".") } else { path };
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

/// A pose as 12 numbers, the rotation's rows then the translation (exact, no re-orthonormalisation).
fn pose_state(pose: &Pose) -> Vec<f64> {
    pose.rot.transpose().iter().chain(pose.pos.iter()).copied().collect()
}

fn pose_of_state(v: &[f64], what: &str) -> PyResult<Pose> {
    if v.len() != 12 {
        return Err(invalid(format!("pickled `{what}` must have 12 numbers, got {}", v.len())));
    }
    Ok(Pose { rot: Matrix3::from_row_slice(&v[..9]), pos: Vector3::new(v[9], v[10], v[11]) })
}

/// A required entry of a pickled state.
fn item<'py, T: FromPyObject<'py>>(state: &Bound<'py, PyDict>, key: &str) -> PyResult<T> {
    let value = state.get_item(key)?.ok_or_else(|| invalid(format!("pickled state has no `{key}`")))?;
    value.extract().map_err(|_| invalid(format!("pickled state's `{key}` has the wrong type")))
}

fn text_state<'py>(py: Python<'py>, kind: &str, t: &DescriptionText) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", kind)?;
    d.set_item("text", &t.text)?;
    d.set_item("file", &t.file)?;
    d.set_item("dir", absolute(&t.dir))?;
    let mut package_paths = t.package_paths.clone();
    package_paths.extend(kinema_geometry::ros_package_path());
    d.set_item("package_paths", package_paths)?;
    Ok(d)
}

fn text_of_state(state: &Bound<'_, PyDict>) -> PyResult<DescriptionText> {
    Ok(DescriptionText {
        text: item(state, "text")?,
        file: item(state, "file")?,
        dir: item(state, "dir")?,
        package_paths: item(state, "package_paths")?,
    })
}

/// The description of a robot read from a file: the text read when it was
/// loaded, its folder (for relative mesh paths) and this process's package paths.
fn file_state<'py>(py: Python<'py>, spec: &str, text: &str) -> PyResult<Bound<'py, PyDict>> {
    let path = Path::new(spec);
    let text = text.to_string();
    let lower = spec.to_ascii_lowercase();
    let kind = if lower.ends_with(".urdf") || lower.ends_with(".xml") { "urdf" } else { "toml" };
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    text_state(py, kind, &DescriptionText { text, file: spec.to_string(), dir, package_paths: Vec::new() })
}

fn joint_state<'py>(py: Python<'py>, j: &Joint) -> PyResult<Bound<'py, PyDict>> {
    let LinkGeometry::Dh { convention, d, a, alpha, theta } = &j.geometry else {
        return Err(invalid(format!("joint `{}` is not a DH row; only DH rows pickle as rows", j.name)));
    };
    let s = PyDict::new(py);
    s.set_item("name", &j.name)?;
    s.set_item("prismatic", j.kind == JointType::Prismatic)?;
    s.set_item("modified", *convention == DhConvention::Modified)?;
    s.set_item("dh", [*d, *a, *alpha, *theta])?;
    s.set_item("offset", j.offset)?;
    let l = &j.limits;
    s.set_item("limits", (l.min, l.max, l.vel, l.acc, l.jerk, l.effort))?;
    Ok(s)
}

fn joint_of_state(s: &Bound<'_, PyDict>) -> PyResult<Joint> {
    let [d, a, alpha, theta]: [f64; 4] = item(s, "dh")?;
    let modified: bool = item(s, "modified")?;
    let convention = if modified { DhConvention::Modified } else { DhConvention::Standard };
    let (min, max, vel, acc, jerk, effort) = item(s, "limits")?;
    Ok(Joint {
        name: item(s, "name")?,
        kind: if item(s, "prismatic")? { JointType::Prismatic } else { JointType::Revolute },
        geometry: LinkGeometry::Dh { convention, d, a, alpha, theta },
        offset: item(s, "offset")?,
        limits: Limits { min, max, vel, acc, jerk, effort },
    })
}

/// A robot defined in code (`Robot.from_dh`): its rows, base, tool and poses.
fn description_state<'py>(py: Python<'py>, desc: &Description) -> PyResult<Bound<'py, PyDict>> {
    if !desc.inertials.is_empty() {
        return Err(invalid(format!("robot `{}` has mass properties, which do not pickle", desc.name)));
    }
    let d = PyDict::new(py);
    d.set_item("kind", "dh")?;
    d.set_item("name", &desc.name)?;
    d.set_item("modified", desc.kind == GeometryKind::Modified)?;
    d.set_item("source", &desc.metadata.source)?;
    let joints = PyList::empty(py);
    for j in &desc.joints {
        joints.append(joint_state(py, j)?)?;
    }
    d.set_item("joints", joints)?;
    d.set_item("description_base", pose_state(&desc.base))?;
    d.set_item("description_tool", pose_state(&desc.tool))?;
    let poses: Vec<(&str, &[f64])> = desc.poses.iter().map(|p| (p.name.as_str(), p.q.as_slice())).collect();
    d.set_item("poses", poses)?;
    Ok(d)
}

fn description_of_state(state: &Bound<'_, PyDict>) -> PyResult<Description> {
    let kind = if item(state, "modified")? { GeometryKind::Modified } else { GeometryKind::Standard };
    let joints: Vec<Bound<'_, PyDict>> = item(state, "joints")?;
    let joints = joints.iter().map(joint_of_state).collect::<PyResult<Vec<_>>>()?;
    let mut desc = Description::new(item::<String>(state, "name")?, kind, joints);
    desc.metadata.source = item(state, "source")?;
    desc.base = pose_of_state(&item::<Vec<f64>>(state, "description_base")?, "description_base")?;
    desc.tool = pose_of_state(&item::<Vec<f64>>(state, "description_tool")?, "description_tool")?;
    let poses: Vec<(String, Vec<f64>)> = item(state, "poses")?;
    desc.poses = poses.into_iter().map(|(name, q)| NamedPose { name, q }).collect();
    Ok(desc)
}

fn scene_state<'py>(py: Python<'py>, scene: &SceneText) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("text", &scene.text)?;
    d.set_item("file", &scene.file)?;
    d.set_item("dir", absolute(&scene.dir))?;
    Ok(d)
}

fn scene_of_state(state: &Bound<'_, PyDict>) -> PyResult<PyScene> {
    PyScene::parse(SceneText { text: item(state, "text")?, file: item(state, "file")?, dir: item(state, "dir")? })
}

/// What a robot pickles as: how it was made (`kind`) and what from, with its
/// base and tool (a robot placed in a cell keeps its place).
fn robot_state<'py>(py: Python<'py>, r: &PyRobot) -> PyResult<Bound<'py, PyDict>> {
    let s = &r.source;
    let d = match (&s.member, &s.scene, &s.inline) {
        (Some(member), Some(scene), _) => {
            let d = PyDict::new(py);
            d.set_item("kind", "member")?;
            d.set_item("scene", scene_state(py, scene)?)?;
            d.set_item("member", member)?;
            d
        }
        (_, _, Some(Inline::Description(desc))) => description_state(py, desc)?,
        (_, _, Some(Inline::Urdf(t))) => text_state(py, "urdf", t)?,
        (_, _, Some(Inline::Toml(t))) => text_state(py, "toml", t)?,
        (_, _, None) if kinema::builtin_source(&s.spec).is_some() => {
            let d = PyDict::new(py);
            d.set_item("kind", "builtin")?;
            d.set_item("name", &s.spec)?;
            d
        }
        (_, _, None) => match &s.file_text {
            Some(text) => file_state(py, &s.spec, text)?,
            None => {
                return Err(invalid(format!(
                    "robot `{}` was not read from a file kinema kept; it does not pickle",
                    s.spec
                )))
            }
        },
    };
    d.set_item("tip", &s.tip)?;
    d.set_item("base", pose_state(r.robot.base()))?;
    d.set_item("tool", pose_state(r.robot.tool()))?;
    Ok(d)
}

/// The robot a state describes, before its base and tool are set.
fn robot_of_state(state: &Bound<'_, PyDict>) -> PyResult<PyRobot> {
    let kind: String = item(state, "kind")?;
    let tip: Option<String> = item(state, "tip")?;
    match kind.as_str() {
        "builtin" => {
            let name: String = item(state, "name")?;
            let robot = Robot::builtin(&name).map_err(to_py)?;
            Ok(PyRobot::new(Arc::new(robot), Source::named(&name, None)))
        }
        "toml" => {
            let t = text_of_state(state)?;
            let robot = Robot::from_toml_str(&t.text, &t.file).map_err(to_py)?;
            let source = Source { spec: t.file.clone(), ..Source::inline(robot.name(), Inline::Toml(Arc::new(t))) };
            Ok(PyRobot::new(Arc::new(robot), source))
        }
        "urdf" => {
            let t = text_of_state(state)?;
            let robot = Robot::from_urdf_str(&t.text, &t.file, tip.as_deref()).map_err(to_py)?;
            let source =
                Source { spec: t.file.clone(), tip, ..Source::inline(robot.name(), Inline::Urdf(Arc::new(t))) };
            Ok(PyRobot::new(Arc::new(robot), source))
        }
        "dh" => {
            let desc = description_of_state(state)?;
            let robot = desc.clone().build().map_err(to_py)?;
            let source = Source::inline(robot.name(), Inline::Description(Arc::new(desc)));
            Ok(PyRobot::new(Arc::new(robot), source))
        }
        "member" => {
            let scene: Bound<'_, PyDict> = item(state, "scene")?;
            scene_of_state(&scene)?.robot(&item::<String>(state, "member")?)
        }
        other => Err(invalid(format!("pickled robot of unknown kind `{other}`"))),
    }
}

#[pymethods]
impl PyRobot {
    /// Pickles the robot as its description (see :meth:`_from_state`).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let rebuild = py.import("kinema._pickle")?.getattr("robot_from_state")?;
        Ok((rebuild, (robot_state(py, self)?,)))
    }

    /// The robot a pickled state describes (what ``pickle.loads`` calls).
    #[staticmethod]
    fn _from_state(state: &Bound<'_, PyDict>) -> PyResult<Self> {
        let made = robot_of_state(state)?;
        let base = pose_of_state(&item::<Vec<f64>>(state, "base")?, "base")?;
        let tool = pose_of_state(&item::<Vec<f64>>(state, "tool")?, "tool")?;
        if *made.robot.base() == base && *made.robot.tool() == tool {
            return Ok(made);
        }
        let robot = made.robot.with_base(base).and_then(|r| r.with_tool(tool)).map_err(to_py)?;
        Ok(PyRobot::new(Arc::new(robot), made.source))
    }
}

#[pymethods]
impl PyScene {
    /// Pickles the scene as its TOML text and base directory (made absolute).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let rebuild = py.import("kinema._pickle")?.getattr("scene_from_state")?;
        Ok((rebuild, (scene_state(py, &self.text)?,)))
    }

    /// The scene a pickled state describes (what ``pickle.loads`` calls).
    #[staticmethod]
    fn _from_state(state: &Bound<'_, PyDict>) -> PyResult<Self> {
        scene_of_state(state)
    }
}
