//! The answers of `kinema-io` as Python objects: what the `to_dict` methods
//! (and `Robot.fk_dict`, `Robot.manip_dict`, `Robot.ik_dict`) return.
//!
//! An answer is written as JSON by `serde_json`, the writer of `kinema … --json`
//! and of the HTTP API, and read back by Python's `json.loads`. So a dict is
//! the other doors' JSON parsed, field for field: lists where they have arrays
//! (a serde converter to Python objects would give tuples for fixed-size
//! arrays), `None` where they have `null`, and every float bit for bit
//! (shortest round-trip text, which Python reads back exactly).

use kinema::nalgebra::Vector3;
use kinema::Frame;
use kinema_io::{FkAnswer, JacobianAnswer, ManipAnswer, RobotInfo};
use pyo3::prelude::*;
use pyo3::sync::GILOnceCell;

use crate::args::{parse_rpy, vec3_arg};
use crate::errors::to_py;
use crate::robot::PyRobot;

/// Python's `json.loads`, looked up once.
static JSON_LOADS: GILOnceCell<PyObject> = GILOnceCell::new();

/// `answer` as Python objects (dicts, lists, str, int, float, bool, None).
pub(crate) fn to_python<'py>(py: Python<'py>, answer: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(answer)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("an answer could not be written: {e}")))?;
    let loads = JSON_LOADS.get_or_try_init(py, || py.import("json")?.getattr("loads").map(Bound::unbind))?;
    loads.bind(py).call1((text,))
}

/// The dicts of the robot itself and of one configuration: `kinema info`,
/// `kinema fk`, `kinema jacobian` and `kinema manip` with `--json`.
#[pymethods]
impl PyRobot {
    /// What the robot is, as ``kinema info --json`` prints it and
    /// ``GET /api/robots/{name}`` returns it: name, dof, convention, maker,
    /// source, notes, the joints (geometry and limits; ``None`` for an
    /// unbounded limit), base and tool poses, named poses, home and which IK
    /// it has.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &RobotInfo::new(&self.robot))
    }

    /// Forward kinematics at ``q`` as ``kinema fk --json`` prints it and
    /// ``POST /api/fk`` returns it: the tool pose (``T``, ``position``,
    /// ``rpy`` in convention ``rpy``, ``rpy_convention``,
    /// ``quaternion_wxyz``), ``q``, the joints outside their limits, every
    /// frame along the chain and every joint axis, in the world frame.
    ///
    /// Raises:
    ///     InvalidInput: a bad ``q`` or ``rpy``.
    #[pyo3(signature = (q, rpy="zyx"))]
    fn fk_dict<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>, rpy: &str) -> PyResult<Bound<'py, PyAny>> {
        let conv = parse_rpy(rpy)?;
        let q = self.joint_vector(q, "q")?;
        to_python(py, &FkAnswer::new(&self.robot, &q, conv).map_err(to_py)?)
    }

    /// The Jacobian at ``q`` as ``kinema jacobian --json`` prints it:
    /// ``kind`` and the 6×n matrix ``J`` row by row; geometric in ``frame``
    /// (``"base"`` or ``"tool"``), or with ``analytic`` (``"zyx"`` or
    /// ``"xyz"``) the analytic Jacobian of the roll-pitch-yaw rates.
    ///
    /// Raises:
    ///     InvalidInput: a bad ``q``, ``frame`` or ``analytic``.
    #[pyo3(signature = (q, frame="base", analytic=None))]
    fn jacobian_dict<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        frame: &str,
        analytic: Option<&str>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let frame: Frame = frame.parse().map_err(to_py)?;
        let analytic = analytic.map(parse_rpy).transpose()?;
        let q = self.joint_vector(q, "q")?;
        let answer = match analytic {
            Some(conv) => JacobianAnswer::analytic(&self.robot, &q, conv),
            None => JacobianAnswer::geometric(&self.robot, &q, frame),
        };
        to_python(py, &answer.map_err(to_py)?)
    }

    /// Manipulability and singularity measures at ``q`` as ``kinema manip
    /// --json`` prints them and ``POST /api/manip`` returns them: Yoshikawa's
    /// measure (all rows, translational, rotational), condition number
    /// (``None`` at a singularity), rank, singular values and directions,
    /// dependent joints and the two velocity ellipsoids; with ``direction``
    /// (x, y, z, any length but zero) the translational manipulability along
    /// it (``manipulability_along``).
    ///
    /// Raises:
    ///     InvalidInput: a bad ``q`` or ``direction``.
    #[pyo3(signature = (q, direction=None))]
    fn manip_dict<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        direction: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let direction = direction.filter(|d| !d.is_none()).map(|d| vec3_arg(d, "direction")).transpose()?;
        let q = self.joint_vector(q, "q")?;
        let answer = ManipAnswer::new(&self.robot, &q, direction.map(Vector3::from)).map_err(to_py)?;
        to_python(py, &answer)
    }
}
