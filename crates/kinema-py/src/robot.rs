//! The `Robot` class: loading, properties, forward kinematics, Jacobians and manipulability.

use std::sync::{Arc, Mutex, OnceLock};

use kinema::analysis;
use kinema::{Frame, Robot};
use kinema_geometry::CollisionCheck;
use numpy::{PyArray1, PyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::args::{check_shape, f64_array, parse_axes, push_pose, shape_text, to_numpy};
use crate::collision::{KeptCheck, Source};
use crate::errors::{invalid, to_py};
use crate::toolbox::maybe_se3;
use crate::{fast, npio};

/// A serial robot arm (immutable). Load one with :meth:`Robot.builtin` or
/// :meth:`Robot.from_file`.
///
/// Units are SI: metres and radians. Joint vectors are 1-D arrays (or lists)
/// of ``n`` values; transforms are 4×4 homogeneous matrices
/// (``world_from_tool``); Jacobian rows are ``[vx vy vz ωx ωy ωz]``.
#[pyclass(frozen, name = "Robot", module = "kinema")]
pub(crate) struct PyRobot {
    pub(crate) robot: Arc<Robot>,
    /// The IK solver family fitted to the robot once (`ik::registry::fit`), so
    /// that each `ik` call does not fit it again.
    pub(crate) family: Option<Arc<dyn kinema::ik::family::Family>>,
    /// The description it was loaded from (its shapes come from there too).
    pub(crate) source: Source,
    /// Its shapes and self-collision pairs, loaded at the first collision query.
    pub(crate) body: OnceLock<CollisionCheck>,
    /// The last check with a scene and margin, reused by the next query of the same.
    pub(crate) last_check: Mutex<Option<KeptCheck>>,
}

impl PyRobot {
    pub(crate) fn new(robot: Arc<Robot>, source: Source) -> Self {
        let family = kinema::ik::registry::fit(&robot).map(Arc::from);
        PyRobot { robot, family, source, body: OnceLock::new(), last_check: Mutex::new(None) }
    }
}

impl PyRobot {
    pub(crate) fn dof(&self) -> usize {
        self.robot.dof()
    }

    /// A joint vector argument: a 1-D array of numbers, or the name of a pose.
    pub(crate) fn joint_vector(&self, obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
        if let Ok(name) = obj.downcast::<PyString>() {
            return self.robot.pose(name.to_str()?).map(<[f64]>::to_vec).map_err(to_py);
        }
        let a = f64_array(obj, what)?;
        check_shape(&a, what, &[None], " (one value per joint)")?;
        Ok(a.as_slice()?.to_vec())
    }

    /// [`PyRobot::joint_vector`] of an argument that may be left out (or None).
    pub(crate) fn optional_joint_vector(
        &self,
        obj: Option<&Bound<'_, PyAny>>,
        what: &str,
    ) -> PyResult<Option<Vec<f64>>> {
        obj.filter(|o| !o.is_none()).map(|o| self.joint_vector(o, what)).transpose()
    }

    /// Calls `f` on a joint vector argument: float64 arrays and lists of numbers
    /// are copied to the stack (`npio::read_joints`), anything else is converted by numpy.
    pub(crate) fn with_q<T>(&self, obj: &Bound<'_, PyAny>, f: impl FnOnce(&[f64]) -> kinema::Result<T>) -> PyResult<T> {
        self.with_q_py(obj, |q| f(q).map_err(to_py))
    }

    /// As [`PyRobot::with_q`], for an `f` that gives Python errors itself.
    pub(crate) fn with_q_py<T>(&self, obj: &Bound<'_, PyAny>, f: impl FnOnce(&[f64]) -> PyResult<T>) -> PyResult<T> {
        let mut buf = [0.0; npio::MAX_FAST_JOINTS];
        if let Some(len) = npio::read_joints(obj, &mut buf) {
            return f(&buf[..len]);
        }
        if obj.is_instance_of::<PyString>() {
            let q = self.joint_vector(obj, "q")?;
            return f(&q);
        }
        let a = f64_array(obj, "q")?;
        if a.ndim() == 2 {
            return Err(invalid(format!(
                "`q` must be one configuration of shape ({},), got shape {}; use the *_batch methods for many",
                self.dof(),
                shape_text(a.shape())
            )));
        }
        check_shape(&a, "q", &[None], " (one value per joint)")?;
        f(a.as_slice()?)
    }

    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        frame: Frame,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dof();
        // Row-major (the layout of the numpy array), written by the core
        // straight into the result; on bad input it writes nothing.
        self.with_q_py(q, |q| {
            npio::result_array(py, out, [6, n], |o| {
                kinema::kin::jacobian_rows_into_uninit(&self.robot, q, frame, o).map(|_| ()).map_err(to_py)
            })
        })
    }

    fn jacobian_batch<'py>(
        &self,
        py: Python<'py>,
        qs: &Bound<'py, PyAny>,
        frame: Frame,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dof();
        let robot = &*self.robot;
        let row = |q: &[f64], o: &mut _| kinema::kin::jacobian_rows_into_uninit(robot, q, frame, o).map(|_| ());
        fast::batch(py, robot, qs, "Q", out, [6, n], row)
    }
}

/// A `robot` argument: a :class:`Robot`, or what ``kinema run --robot`` takes
/// (a built-in name or a .toml/.urdf path).
pub(crate) fn robot_arg(obj: &Bound<'_, PyAny>) -> PyResult<Arc<Robot>> {
    match obj.downcast::<PyRobot>() {
        Ok(r) => Ok(Arc::clone(&r.get().robot)),
        Err(_) => {
            let spec: String = obj
                .extract()
                .map_err(|_| invalid("`robot` must be a kinema.Robot, a built-in robot name or a file path".into()))?;
            Ok(Arc::new(Robot::load(&spec, None).map_err(to_py)?))
        }
    }
}

#[pymethods]
impl PyRobot {
    /// A built-in robot by name, e.g. ``"puma560"``, ``"lbr-iiwa-14-r820"``,
    /// ``"scorbot-er-v-plus"`` (see :meth:`Robot.builtins`).
    ///
    /// Raises:
    ///     UnknownRobot: the name is not a built-in robot (the message lists them).
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<Self> {
        let source = Source::named(name, None);
        Robot::builtin(name).map(|r| PyRobot::new(Arc::new(r), source)).map_err(to_py)
    }

    /// Names of the built-in robots, sorted.
    #[staticmethod]
    fn builtins() -> Vec<&'static str> {
        kinema::builtin_names().collect()
    }

    /// Loads a robot description file: ``.toml`` (kinema's format) or
    /// ``.urdf``. For URDF, ``tip`` names the last link of the chain (default:
    /// the only leaf link).
    ///
    /// Raises:
    ///     RobotFileError: the file cannot be read.
    ///     DescriptionError: the description is malformed (file, line, column in the message).
    ///     InvalidInput: ``tip`` given for a TOML file.
    #[staticmethod]
    #[pyo3(signature = (path, tip=None))]
    fn from_file(path: std::path::PathBuf, tip: Option<&str>) -> PyResult<Self> {
        let (robot, text) = Robot::from_file_with_text(&path, tip).map_err(to_py)?;
        let source = Source {
            file_text: Some(Arc::new(text)),
            ..Source::named(&path.display().to_string(), tip.map(str::to_string))
        };
        Ok(PyRobot::new(Arc::new(robot), source))
    }

    /// Robot name, e.g. ``"puma560"``.
    #[getter]
    fn name(&self) -> &str {
        self.robot.name()
    }

    /// Number of joints (degrees of freedom).
    #[getter]
    fn n(&self) -> usize {
        self.dof()
    }

    /// Joint names, base first.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.robot.joints().iter().map(|j| j.name.clone()).collect()
    }

    /// Joint types as a string such as ``"RRRRRR"`` (R revolute, P prismatic).
    #[getter]
    fn joint_types(&self) -> String {
        self.robot.joint_types()
    }

    /// Joint position limits, a 2×n array: row 0 the lower, row 1 the upper
    /// limits (rad / m; ±inf where a joint is unbounded).
    #[getter]
    fn qlim(&self, py: Python<'_>) -> PyResult<Py<PyArrayDyn<f64>>> {
        let joints = self.robot.joints();
        let data = joints.iter().map(|j| j.limits.min).chain(joints.iter().map(|j| j.limits.max)).collect();
        Ok(to_numpy(py, (2, joints.len()), data)?.unbind())
    }

    /// The ``home`` configuration (1-D array).
    #[getter]
    fn home<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.robot.home())
    }

    /// Named configurations as a dict ``{name: array}`` (``home`` among them).
    #[getter]
    fn poses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for p in self.robot.poses() {
            d.set_item(&p.name, PyArray1::from_slice(py, &p.q))?;
        }
        Ok(d)
    }

    /// A named configuration (1-D array).
    ///
    /// Raises:
    ///     InvalidInput: the robot has no pose of that name (the message lists its poses).
    fn pose<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.robot.pose(name).map(|q| PyArray1::from_slice(py, q)).map_err(to_py)
    }

    /// Forward kinematics: the tool pose ``world_from_tool`` as a 4×4 array.
    ///
    /// ``q`` is a 1-D array or list of n joint values (rad / m) or the name of
    /// a pose. Values outside the joint limits are computed anyway.
    ///
    /// ``out``: a writeable C-contiguous float64 array of shape (4, 4) to
    /// write the result into (and return) instead of a new array.
    ///
    /// ``as_se3=True``: a spatialmath ``SE3`` instead (spatialmath imported
    /// only then; ``pip install spatialmath-python``).
    ///
    /// Raises:
    ///     InvalidInput: wrong number of values, NaN/inf, or not 1-D; an
    ///         ``out`` of the wrong type, dtype, shape or layout, or read-only;
    ///         ``as_se3=True`` without spatialmath.
    #[pyo3(signature = (q, out=None, as_se3=false))]
    fn fkine<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
        as_se3: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        // The matrix rows are written by the core straight into the result;
        // on bad input it writes nothing.
        let matrix = self.with_q_py(q, |q| {
            npio::result_array(py, out, [4, 4], |o| {
                kinema::kin::fk_matrix_into_uninit(&self.robot, q, o).map(|_| ()).map_err(to_py)
            })
        })?;
        maybe_se3(py, matrix, as_se3)
    }

    /// All frames along the chain as an (n+2)×4×4 array: index 0 the base
    /// frame, index i the frame of link i, index n+1 the tool frame, all in
    /// the base frame.
    fn fkine_all(&self, py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Py<PyArrayDyn<f64>>> {
        let frames = self.with_q(q, |q| self.robot.link_frames(q))?;
        let mut out = vec![0.0; 16 * frames.len()];
        for (o, f) in out.chunks_exact_mut(16).zip(&frames) {
            push_pose(o, f);
        }
        Ok(to_numpy(py, (frames.len(), 4, 4), out)?.unbind())
    }

    /// Geometric Jacobian in the base frame, a 6×n array with rows
    /// ``[vx vy vz ωx ωy ωz]`` (velocity of the tool point, angular velocity).
    /// ``out``: as in :meth:`fkine`, of shape (6, n).
    #[pyo3(signature = (q, out=None))]
    fn jacob0<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.jacobian(py, q, Frame::Base, out)
    }

    /// Geometric Jacobian in the tool frame, a 6×n array with rows
    /// ``[vx vy vz ωx ωy ωz]`` expressed in tool axes.
    /// ``out``: as in :meth:`fkine`, of shape (6, n).
    #[pyo3(signature = (q, out=None))]
    fn jacobe<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.jacobian(py, q, Frame::Tool, out)
    }

    /// Yoshikawa manipulability √det(J·Jᵀ) of the base-frame Jacobian's rows
    /// ``axes``: ``"all"`` (6 rows), ``"trans"`` (vx vy vz) or ``"rot"`` (ωx ωy ωz).
    /// 0 when the selected block has more rows than the robot has joints.
    #[pyo3(signature = (q, axes="all"))]
    fn manipulability(&self, q: &Bound<'_, PyAny>, axes: &str) -> PyResult<f64> {
        let axes = parse_axes(axes)?;
        self.with_q(q, |q| analysis::yoshikawa(&self.robot.jacobian(q, Frame::Base)?, axes))
    }

    /// Forward kinematics of N configurations, an (N, n) array → (N, 4, 4).
    /// Runs without the GIL, in parallel over all cores. A bad row (NaN/inf)
    /// raises InvalidInput naming the first such index.
    ///
    /// ``out``: a writeable C-contiguous float64 array of shape (N, 4, 4) to
    /// write the result into (and return) instead of a new array. With
    /// ``out``, ``Q`` is not copied and the call holds the GIL (still running
    /// in parallel over all cores), so that no Python thread can use ``out``
    /// while it is written. A bad row leaves ``out`` partly written.
    /// ``as_se3=True``: one spatialmath ``SE3`` holding the N poses.
    #[allow(non_snake_case)]
    #[pyo3(signature = (Q, out=None, as_se3=false))]
    fn fkine_batch<'py>(
        &self,
        py: Python<'py>,
        Q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
        as_se3: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let robot = &*self.robot;
        let row = |q: &[f64], o: &mut _| kinema::kin::fk_matrix_into_uninit(robot, q, o).map(|_| ());
        maybe_se3(py, fast::batch(py, robot, Q, "Q", out, [4, 4], row)?, as_se3)
    }

    /// Base-frame Jacobians of N configurations, an (N, n) array → (N, 6, n).
    /// Runs without the GIL, in parallel over all cores. ``out``: as in
    /// :meth:`fkine_batch`, of shape (N, 6, n).
    #[allow(non_snake_case)]
    #[pyo3(signature = (Q, out=None))]
    fn jacob0_batch<'py>(
        &self,
        py: Python<'py>,
        Q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.jacobian_batch(py, Q, Frame::Base, out)
    }

    /// Tool-frame Jacobians of N configurations, an (N, n) array → (N, 6, n).
    /// Runs without the GIL, in parallel over all cores. ``out``: as in
    /// :meth:`fkine_batch`, of shape (N, 6, n).
    #[allow(non_snake_case)]
    #[pyo3(signature = (Q, out=None))]
    fn jacobe_batch<'py>(
        &self,
        py: Python<'py>,
        Q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.jacobian_batch(py, Q, Frame::Tool, out)
    }

    fn __repr__(&self) -> String {
        format!("Robot('{}', n={})", self.robot.name(), self.dof())
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.downcast::<PyRobot>().is_ok_and(|o| *o.get().robot == *self.robot)
    }
}
