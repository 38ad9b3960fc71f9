//! Python bindings of the kinema core (`import kinema`).
//!
//! Glue only: arguments are converted to the core's types, the core computes,
//! and the results are returned as numpy arrays. Every number comes from the
//! `kinema` crate. Errors of the core become Python exceptions (defined in
//! `python/kinema/_errors.py`) carrying the core's `Display` text, which is
//! what the command line prints.
//!
//! Layout conventions of the arrays handed to Python: homogeneous transforms
//! are 4×4 row-major (C order); Jacobians are 6×n with rows
//! \[vx vy vz ωx ωy ωz\]; batches stack along the first axis.

mod batch;
mod cell;
mod dynamics;
mod fast;
mod npio;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::sync::Arc;
use std::time::Duration;

use kinema::analysis::{self, Axes};
use kinema::ik::{pick_one, solve_target_with, IkRequest, IkTarget, NumericOptions, Solution, SolverChoice, Tolerance};
use kinema::nalgebra::{Matrix4, Vector3};
use kinema::traj::{
    check, expression_trajectory, sample_times, to_joints, to_joints_at, Blend, CartesianLimits, CartesianMotion,
    CheckOptions, CheckReport, Expr, JointMethod, JointTrajectory, MotionLimits, Orientation, Profile, Ptp, PtpOptions,
    Segment, SelfMotion, TimeLaw, Waypoint,
};
use kinema::{Error, Frame, Pose, Robot, RpyConvention};
use kinema_lang::{PlannedMotion, Severity};
use numpy::ndarray::{Array, Dimension, IntoDimension};
use numpy::{
    IntoPyArray, PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyComplex, PyDict, PyFloat, PyInt, PyList, PyMemoryView, PyString};

pyo3::import_exception!(kinema._errors, KinemaError);
pyo3::import_exception!(kinema._errors, InvalidInput);
pyo3::import_exception!(kinema._errors, UnknownRobot);
pyo3::import_exception!(kinema._errors, DescriptionError);
pyo3::import_exception!(kinema._errors, RobotFileError);
pyo3::import_exception!(kinema._errors, Unreachable);
pyo3::import_exception!(kinema._errors, TrajectoryError);
pyo3::import_exception!(kinema._errors, ProgramError);

/// A core error as a Python exception with the core's message.
fn to_py(e: Error) -> PyErr {
    let message = e.to_string();
    // A batch row or path sample is classified by what is wrong there.
    match e.root() {
        Error::Unreachable { solver, reason, closest } => {
            let closest = closest.as_ref().map(|c| ClosestArg(c.q.clone(), c.position_error, c.orientation_error));
            Unreachable::new_err((message, solver.clone(), reason.to_string(), closest))
        }
        Error::UnknownRobot { .. } => UnknownRobot::new_err(message),
        Error::JointCount { .. }
        | Error::NonFinite { .. }
        | Error::UnknownPose { .. }
        | Error::OutOfRange { .. }
        | Error::TooFew { .. }
        | Error::MissingLimit { .. }
        | Error::UnknownName { .. }
        | Error::DoesNotFit { .. }
        | Error::Infeasible { .. }
        | Error::Syntax { .. }
        | Error::SolverDoesNotFit { .. }
        | Error::WrongLength { .. }
        | Error::NotFinite { .. }
        | Error::Overflow { .. }
        | Error::RpySingularity { .. } => InvalidInput::new_err(message),
        Error::Description { .. } | Error::Urdf { .. } | Error::MimicJoint { .. } | Error::InvalidModel { .. } => {
            DescriptionError::new_err(message)
        }
        Error::Io { .. } | Error::FileTooLarge { .. } => RobotFileError::new_err(message),
        Error::Trajectory { .. } => TrajectoryError::new_err(message),
        _ => KinemaError::new_err(message),
    }
}

/// The closest configuration of an unreachable target, given to Python as a dict.
struct ClosestArg(Vec<f64>, f64, f64);

impl<'py> IntoPyObject<'py> for ClosestArg {
    type Target = pyo3::types::PyDict;
    type Output = Bound<'py, pyo3::types::PyDict>;
    type Error = PyErr;

    fn into_pyobject(self, py: Python<'py>) -> PyResult<Self::Output> {
        let d = pyo3::types::PyDict::new(py);
        d.set_item("q", self.0)?;
        d.set_item("position_error", self.1)?;
        d.set_item("orientation_error", self.2)?;
        Ok(d)
    }
}

/// A seed: a non-negative integer below 2**64 (InvalidInput otherwise, not
/// Python's OverflowError).
fn seed_arg(obj: &Bound<'_, PyAny>) -> PyResult<u64> {
    if !obj.is_instance_of::<PyInt>() {
        let name = obj.get_type().fully_qualified_name()?;
        return Err(pyo3::exceptions::PyTypeError::new_err(format!("`seed` must be an int, not {name}")));
    }
    obj.extract::<u64>().map_err(|_| invalid(format!("invalid `seed`: {obj}; expected an integer from 0 to 2**64 - 1")))
}

/// A task mask: six booleans (or 0/1) for x, y, z, ωx, ωy, ωz.
fn mask_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<[bool; 6]>> {
    if obj.is_none() {
        return Ok(None);
    }
    let bad = || invalid(format!("invalid `mask`: {obj}; expected six booleans (or 0/1) for x, y, z, ωx, ωy, ωz"));
    let items: Vec<Bound<'_, PyAny>> = obj.try_iter().map_err(|_| bad())?.collect::<PyResult<_>>()?;
    if items.len() != 6 {
        return Err(bad());
    }
    let mut m = [false; 6];
    for (flag, x) in m.iter_mut().zip(&items) {
        *flag = match x.extract::<f64>() {
            Ok(1.0) => true,
            Ok(0.0) => false,
            _ => return Err(bad()),
        };
    }
    Ok(Some(m))
}

/// What `Robot.ik_batch` returns: Q (V, n), success (V,), reasons.
type IkBatchResult<'py> = (Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyArrayDyn<bool>>, Vec<String>);

/// The `solver` argument of the IK functions.
fn solver_choice(name: &str) -> PyResult<SolverChoice> {
    match name {
        "auto" => Ok(SolverChoice::Auto),
        "analytic" => Ok(SolverChoice::Analytic),
        "numeric" => Ok(SolverChoice::Numeric),
        other => Err(invalid(format!("invalid `solver`: `{other}`; use \"auto\", \"analytic\" or \"numeric\""))),
    }
}

fn invalid(message: String) -> PyErr {
    InvalidInput::new_err(message)
}

fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")),
    }
}

/// `obj` (a numpy array, list, tuple, …) as a C-contiguous float64 array.
/// Arrays that already are one are not copied.
fn f64_array<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<PyReadonlyArrayDyn<'py, f64>> {
    if let Ok(a) = obj.downcast::<PyArrayDyn<f64>>() {
        if a.is_c_contiguous() {
            return Ok(a.readonly());
        }
    }
    if obj.is_instance_of::<PyString>() {
        return Err(invalid(format!("`{what}` must be an array of numbers, not a string")));
    }
    let unreadable = |e: String| invalid(format!("`{what}` cannot be read as an array of float64 numbers: {e}"));
    let np = obj.py().import("numpy")?;
    // First as numpy reads it, so that what float64 would silently change is refused:
    // complex numbers (numpy drops the imaginary part with only a warning), text that
    // numpy would parse as numbers, dates and times.
    let natural = np.call_method1("asarray", (obj,)).map_err(|e| unreadable(e.to_string()))?;
    let dtype = natural.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    match kind.as_str() {
        "c" => {
            return Err(invalid(format!(
                "`{what}` holds complex numbers ({dtype}); joint values and poses are real (float64)"
            )))
        }
        "U" | "S" | "V" | "M" | "m" => return Err(unreadable(format!("it holds {dtype}, not numbers"))),
        // Python objects (a list mixing numbers with text or complex numbers, say): each must
        // be a real number, since float64 would parse the text and drop imaginary parts too.
        "O" => {
            for (k, x) in natural.call_method0("ravel")?.try_iter()?.enumerate() {
                if let Some(held) = not_a_real_number(&np, &x?)? {
                    return Err(invalid(format!(
                        "`{what}` holds {held} at flat index {k}; joint values and poses are real numbers"
                    )));
                }
            }
        }
        _ => {}
    }
    let kwargs = PyDict::new(obj.py());
    kwargs.set_item("dtype", "float64")?;
    kwargs.set_item("order", "C")?;
    let converted = np.call_method("asarray", (natural,), Some(&kwargs)).map_err(|e| unreadable(e.to_string()))?;
    Ok(converted.downcast_into::<PyArrayDyn<f64>>()?.readonly())
}

/// A real-number argument: what Python's `float()` takes, but for complex numbers, which
/// raise TypeError as Python's own `complex` does (numpy's complex scalars would convert,
/// dropping the imaginary part with only a warning).
fn real(obj: &Bound<'_, PyAny>) -> PyResult<f64> {
    if let Ok(f) = obj.downcast_exact::<PyFloat>() {
        return Ok(f.value());
    }
    if is_complex(obj)? {
        let name = obj.get_type().fully_qualified_name()?;
        return Err(pyo3::exceptions::PyTypeError::new_err(format!("must be real number, not {name}")));
    }
    obj.extract()
}

/// A complex number: Python's, or one of numpy's complex scalars (not all of which are
/// Python `complex` subclasses).
fn is_complex(x: &Bound<'_, PyAny>) -> PyResult<bool> {
    Ok(x.is_instance_of::<PyComplex>() || x.is_instance(&x.py().import("numpy")?.getattr("complexfloating")?)?)
}

/// [`real`], or None.
/// The self-motion policy of `lin`/`circ`: `q3=` a policy name or an angle,
/// `psi=` "hold" or an angle (the CLI's `--q3`/`--psi`).
fn self_motion_arg<'py>(q3: Option<&Bound<'py, PyAny>>, psi: Option<&Bound<'py, PyAny>>) -> PyResult<SelfMotion> {
    let given = |o: Option<&Bound<'py, PyAny>>| o.filter(|o| !o.is_none()).cloned();
    let (parameter, value) = match (given(q3), given(psi)) {
        (Some(_), Some(_)) => return Err(invalid("give `q3` or `psi`, not both".into())),
        (Some(v), None) => ("q3", v),
        (None, Some(v)) => ("psi", v),
        (None, None) => return Ok(SelfMotion::Auto),
    };
    if let Ok(text) = value.extract::<String>() {
        return SelfMotion::parse(parameter, &text, 1.0).map_err(to_py);
    }
    let v = real(&value)?;
    if !v.is_finite() {
        return Err(invalid(format!("invalid `{parameter}`: {v} is not a finite angle")));
    }
    Ok(SelfMotion::Fixed { parameter: parameter.into(), value: Some(v) })
}

fn opt_real(obj: &Bound<'_, PyAny>) -> PyResult<Option<f64>> {
    if obj.is_none() {
        Ok(None)
    } else {
        real(obj).map(Some)
    }
}

/// What an element of an object array is, when float64 would change it silently rather
/// than take it as the number it is: text (numpy parses it), complex numbers (the
/// imaginary part is dropped), dates and times (turned into counts), arrays of those.
fn not_a_real_number(np: &Bound<'_, PyModule>, x: &Bound<'_, PyAny>) -> PyResult<Option<String>> {
    if x.is_exact_instance_of::<PyFloat>() || x.is_exact_instance_of::<PyInt>() {
        return Ok(None);
    }
    let name = || x.get_type().fully_qualified_name().map(|n| n.to_string());
    let text = x.is_instance_of::<PyString>()
        || x.is_instance_of::<PyBytes>()
        || x.is_instance_of::<PyByteArray>()
        || x.is_instance_of::<PyMemoryView>();
    if text {
        return Ok(Some(format!("text ({})", name()?)));
    }
    if is_complex(x)? {
        return Ok(Some(format!("a complex number ({})", name()?)));
    }
    if x.is_instance(&np.getattr("datetime64")?)? || x.is_instance(&np.getattr("timedelta64")?)? {
        return Ok(Some(format!("a date or time ({})", name()?)));
    }
    if let Ok(a) = x.downcast::<PyUntypedArray>() {
        let dtype = a.dtype();
        let kind: String = dtype.getattr("kind")?.extract()?;
        if "cUSVMmO".contains(kind.as_str()) {
            return Ok(Some(format!("an array of {dtype}")));
        }
    }
    Ok(None)
}

/// Checks that `a` has `ndim` dimensions and, where `expected` gives one, that size.
fn check_shape(a: &PyReadonlyArrayDyn<'_, f64>, what: &str, expected: &[Option<usize>], hint: &str) -> PyResult<()> {
    let shape = a.shape();
    let fits = shape.len() == expected.len() && shape.iter().zip(expected).all(|(s, e)| e.is_none_or(|e| *s == e));
    if fits {
        return Ok(());
    }
    let want: Vec<String> = expected.iter().map(|e| e.map_or("N".to_string(), |v| v.to_string())).collect();
    let want = if want.len() == 1 { format!("({},)", want[0]) } else { format!("({})", want.join(", ")) };
    Err(invalid(format!("`{what}` must have shape {want}{hint}, got shape {}", shape_text(shape))))
}

/// A C-order numpy array of `shape` from row-major `data` (moved, not copied).
fn to_numpy<'py, D: IntoDimension>(py: Python<'py>, shape: D, data: Vec<f64>) -> PyResult<Bound<'py, PyArrayDyn<f64>>>
where
    D::Dim: Dimension,
{
    let a = Array::from_shape_vec(shape.into_dimension(), data)
        .map_err(|e| KinemaError::new_err(format!("internal shape error: {e}")))?;
    Ok(a.into_dyn().into_pyarray(py))
}

fn push_pose(out: &mut [f64], pose: &Pose) {
    for (r, row) in pose.to_rows().iter().enumerate() {
        out[4 * r..4 * r + 4].copy_from_slice(row);
    }
}

fn parse_axes(axes: &str) -> PyResult<Axes> {
    match axes {
        "all" => Ok(Axes::All),
        "trans" => Ok(Axes::Translation),
        "rot" => Ok(Axes::Rotation),
        other => Err(invalid(format!("invalid `axes`: `{other}`; use \"all\", \"trans\" or \"rot\""))),
    }
}

/// A serial robot arm (immutable). Load one with :meth:`Robot.builtin` or
/// :meth:`Robot.from_file`.
///
/// Units are SI: metres and radians. Joint vectors are 1-D arrays (or lists)
/// of ``n`` values; transforms are 4×4 homogeneous matrices
/// (``base_from_tool``); Jacobian rows are ``[vx vy vz ωx ωy ωz]``.
#[pyclass(frozen, name = "Robot", module = "kinema")]
struct PyRobot {
    robot: Arc<Robot>,
    /// The IK solver family fitted to the robot once (`ik::family::fit`), so
    /// that each `ik` call does not fit it again.
    family: Option<Arc<dyn kinema::ik::family::Family>>,
}

impl PyRobot {
    fn new(robot: Arc<Robot>) -> Self {
        let family = kinema::ik::family::fit(&robot).map(Arc::from);
        PyRobot { robot, family }
    }
}

/// One inverse-kinematics solution.
///
/// Attributes:
///     q: joint values (1-D float64 array, rad / m).
///     branch: branch label, e.g. ``"shoulder-left/elbow-up/wrist-noflip"`` or ``"numeric"``.
///     solver: the solver that found it (``"iiwa"``, ``"pieper"``, ``"scorbot"``, ``"numeric"``, ...).
///     residual: ``(position_error [m], orientation_error [rad])`` measured by
///         forward kinematics of ``q`` against the target.
///     within_limits: whether every joint value is within its limits.
///     success: ``within_limits`` and both residuals at most the numeric
///         solver's default tolerances (1e-6 m, 1e-6 rad).
///     iterations, restarts: what the numeric solver did (``None`` for analytic solutions).
#[pyclass(frozen, name = "IkSolution", module = "kinema")]
struct PyIkSolution {
    #[pyo3(get)]
    q: Py<PyArray1<f64>>,
    #[pyo3(get)]
    branch: String,
    #[pyo3(get)]
    solver: String,
    #[pyo3(get)]
    position_error: f64,
    #[pyo3(get)]
    orientation_error: f64,
    #[pyo3(get)]
    within_limits: bool,
    #[pyo3(get)]
    success: bool,
    #[pyo3(get)]
    iterations: Option<usize>,
    #[pyo3(get)]
    restarts: Option<usize>,
}

#[pymethods]
impl PyIkSolution {
    /// ``(position_error [m], orientation_error [rad])``.
    #[getter]
    fn residual(&self) -> (f64, f64) {
        (self.position_error, self.orientation_error)
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let q = self.q.bind(py).repr()?;
        Ok(format!(
            "IkSolution(q={q}, branch='{}', solver='{}', residual=({:.3e}, {:.3e}), within_limits={}, success={})",
            self.branch,
            self.solver,
            self.position_error,
            self.orientation_error,
            if self.within_limits { "True" } else { "False" },
            if self.success { "True" } else { "False" },
        ))
    }
}

impl PyIkSolution {
    /// `orientation_free`: the target left the orientation free (position
    /// only), so `success` does not ask for a small orientation residual.
    fn new(py: Python<'_>, s: &Solution, solver: &str, orientation_free: bool) -> Self {
        let tol = NumericOptions::default();
        let within_limits = s.within_limits();
        PyIkSolution {
            q: PyArray1::from_slice(py, &s.q).unbind(),
            branch: s.branch.to_string(),
            solver: solver.to_string(),
            position_error: s.position_error,
            orientation_error: s.orientation_error,
            within_limits,
            success: within_limits
                && s.position_error <= tol.tol_position
                && (orientation_free || s.orientation_error <= tol.tol_orientation),
            iterations: s.numeric.map(|n| n.iterations),
            restarts: s.numeric.map(|n| n.restarts),
        }
    }
}

/// A sampled joint trajectory (from :meth:`Robot.ptp`, :meth:`Robot.lin`
/// or :meth:`Robot.circ`).
///
/// Attributes:
///     t: sample times, shape (K,) [s], from 0 to ``duration`` inclusive.
///     q, qd, qdd: joint positions, velocities and accelerations, shape (K, n)
///         (rad, rad/s, rad/s²; m for prismatic joints). For Cartesian
///         motions ``qd`` and ``qdd`` are the core's finite differences of
///         ``q`` (method ``"ik"``) or the resolved rates (method ``"rate"``).
///     duration: length of the motion [s].
///     profile: the time law's family (``"trapezoid"``, ``"scurve"``, ...).
///     phase_times: durations of the time law's phases [s] (zero-length
///         phases left out); empty for a Cartesian motion of several segments.
///     poses: Cartesian motions only: the planned tool pose
///         (``base_from_tool``) at every sample time, shape (K, 4, 4); ``None``
///         for ``ptp``. Forward kinematics of ``q`` reaches them to 1e-6.
///     segment_starts: start time of each segment [s] (``[0.0]`` for ``ptp``).
///     blend_times: how long each blend between consecutive segments lasts [s].
///     skipped: for ``lin(…, skip_unreachable=True)``, the indices (among ``via``
///         then ``T``) of the waypoints left out as out of reach.
#[pyclass(frozen, name = "JointTrajectory", module = "kinema")]
struct PyJointTrajectory {
    #[pyo3(get)]
    t: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    q: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    qd: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    qdd: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    duration: f64,
    #[pyo3(get)]
    profile: &'static str,
    #[pyo3(get)]
    phase_times: Vec<f64>,
    #[pyo3(get)]
    poses: Option<Py<PyArrayDyn<f64>>>,
    #[pyo3(get)]
    segment_starts: Vec<f64>,
    #[pyo3(get)]
    blend_times: Vec<f64>,
    #[pyo3(get)]
    skipped: Vec<usize>,
}

#[pymethods]
impl PyJointTrajectory {
    fn __len__(&self, py: Python<'_>) -> usize {
        self.t.bind(py).len()
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "JointTrajectory({} samples, duration={:.6} s, profile='{}')",
            self.t.bind(py).len(),
            self.duration,
            self.profile
        )
    }
}

/// What :meth:`Robot.check` found (``kinema traj check --json``).
///
/// Attributes:
///     ok: no violation.
///     samples: number of samples checked.
///     peak_velocity, peak_acceleration, peak_jerk: the largest |q̇|, |q̈|,
///         |q⃛| per joint, shape (n,).
///     min_manipulability: ``(t, value)`` of the smallest manipulability when
///         ``min_manip`` was given, else ``None``.
///     violations: one dict per problem, in sample order, with keys ``kind``
///         (``"position"``, ``"velocity"``, ``"acceleration"``, ``"jerk"``,
///         ``"jump"``, ``"inconsistent"``, ``"malformed"``,
///         ``"nearsingular"``), ``t`` [s], ``sample`` (from 0), ``joint``
///         (from 1, ``None`` when no joint is concerned), ``value``, ``limit``
///         and ``message`` (the line ``kinema traj check`` prints).
///     warnings: the same dicts for singular passages (kind ``"singular"``),
///         one per passage.
#[pyclass(frozen, name = "CheckReport", module = "kinema")]
struct PyCheckReport {
    report: CheckReport,
}

#[pymethods]
impl PyCheckReport {
    #[getter]
    fn ok(&self) -> bool {
        self.report.violations.is_empty()
    }

    #[getter]
    fn samples(&self) -> usize {
        self.report.samples
    }

    #[getter]
    fn peak_velocity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.report.peak_vel)
    }

    #[getter]
    fn peak_acceleration<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.report.peak_acc)
    }

    #[getter]
    fn peak_jerk<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.report.peak_jerk)
    }

    #[getter]
    fn min_manipulability(&self) -> Option<(f64, f64)> {
        self.report.min_manipulability
    }

    #[getter]
    fn violations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        violation_dicts(py, &self.report.violations)
    }

    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        violation_dicts(py, &self.report.warnings)
    }

    /// Raises :class:`TrajectoryError` (count and first violation in the
    /// message, as every planner of kinema does) when a limit is broken.
    fn raise_if_violations(&self) -> PyResult<()> {
        self.report.clone().into_result().map(|_| ()).map_err(to_py)
    }

    fn __repr__(&self) -> String {
        format!("CheckReport({} samples, {} violation(s))", self.report.samples, self.report.violations.len())
    }
}

/// One dict per violation or warning, as ``kinema traj check --json`` lists them.
fn violation_dicts<'py>(py: Python<'py>, items: &[kinema::traj::Violation]) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for v in items {
        let d = PyDict::new(py);
        d.set_item("kind", v.kind.name())?;
        d.set_item("t", v.time)?;
        d.set_item("sample", v.sample)?;
        d.set_item("joint", v.joint.map(|j| j + 1))?;
        d.set_item("value", v.value)?;
        d.set_item("limit", v.limit)?;
        d.set_item("message", v.to_string())?;
        list.append(d)?;
    }
    Ok(list)
}

/// t (K,), q, q̇, q̈ (K, n) of a core trajectory as numpy arrays.
type TrajArrays = [Py<PyArrayDyn<f64>>; 4];

fn traj_arrays(py: Python<'_>, traj: &JointTrajectory) -> PyResult<TrajArrays> {
    let (k, n) = (traj.len(), traj.dof());
    let (mut q, mut qd, mut qdd) = (Vec::with_capacity(k * n), Vec::with_capacity(k * n), Vec::with_capacity(k * n));
    for i in 0..k {
        q.extend_from_slice(traj.q(i));
        qd.extend_from_slice(traj.qd(i));
        qdd.extend_from_slice(traj.qdd(i));
    }
    Ok([
        to_numpy(py, k, traj.times().to_vec())?.unbind(),
        to_numpy(py, (k, n), q)?.unbind(),
        to_numpy(py, (k, n), qd)?.unbind(),
        to_numpy(py, (k, n), qdd)?.unbind(),
    ])
}

/// A time law s(t) from 0 to 1 scaled by a distance (from :func:`time_law`).
///
/// The motion it describes is ``distance · s(t)``; :meth:`sample` returns
/// position, velocity, acceleration and jerk of that motion.
///
/// Attributes:
///     profile: the family (``"trapezoid"``, ``"scurve"``, ``"cubic"``,
///         ``"quintic"``, ``"linear"``).
///     distance: the distance covered (unit of the limits).
///     duration: T [s].
///     phase_times: durations of the phases [s], in order (zero-length ones
///         left out): trapezoid (t_acc, t_cruise, t_dec), S-curve up to
///         seven, the polynomials and the linear law one.
///     peaks: ``(velocity, acceleration, jerk)``: the largest magnitudes over
///         the law, in closed form, scaled by ``distance``; ``inf`` where the
///         family's derivative jumps (trapezoid, cubic and linear jerk,
///         linear acceleration).
#[pyclass(frozen, name = "TimeLaw", module = "kinema")]
struct PyTimeLaw {
    law: TimeLaw,
    #[pyo3(get)]
    distance: f64,
}

#[pymethods]
impl PyTimeLaw {
    #[getter]
    fn profile(&self) -> &'static str {
        self.law.profile().name()
    }

    #[getter]
    fn duration(&self) -> f64 {
        self.law.duration()
    }

    #[getter]
    fn phase_times(&self) -> Vec<f64> {
        self.law.phase_times().to_vec()
    }

    #[getter]
    fn peaks(&self) -> (f64, f64, f64) {
        let p = self.law.peaks();
        let scale = |v: f64| if v.is_finite() { v * self.distance } else { f64::INFINITY };
        (scale(p.sd), scale(p.sdd), scale(p.sddd))
    }

    /// The law at the times ``t`` [s] (a number or an array of any shape):
    /// ``(p, v, a, j)``, four float64 arrays of ``t``'s shape with
    /// ``p = distance·s(t)``, ``v = distance·ṡ(t)``, ``a = distance·s̈(t)``,
    /// ``j = distance·s⃛(t)``. Before 0, ``p = 0``; after the end,
    /// ``p = distance``; the derivatives are 0 there. ``j`` is 0 where the
    /// family's jerk is an impulse.
    ///
    /// Raises:
    ///     InvalidInput: ``t`` is not numeric or contains NaN.
    fn sample(&self, py: Python<'_>, t: &Bound<'_, PyAny>) -> PyResult<TrajArrays> {
        let times = f64_array(t, "t")?;
        let shape = times.shape().to_vec();
        let times = times.as_slice()?;
        if times.iter().any(|v| v.is_nan()) {
            return Err(invalid("`t` contains NaN".into()));
        }
        let d = self.distance;
        let count = times.len();
        let (mut p, mut v, mut a, mut j) = (
            Vec::with_capacity(count),
            Vec::with_capacity(count),
            Vec::with_capacity(count),
            Vec::with_capacity(count),
        );
        for &ti in times {
            let st = self.law.at(ti);
            p.push(st.s * d);
            v.push(st.sd * d);
            a.push(st.sdd * d);
            j.push(st.sddd * d);
        }
        Ok([
            to_numpy(py, shape.clone(), p)?.unbind(),
            to_numpy(py, shape.clone(), v)?.unbind(),
            to_numpy(py, shape.clone(), a)?.unbind(),
            to_numpy(py, shape, j)?.unbind(),
        ])
    }

    /// Sample times 0, dt, 2·dt, … and the end time itself, as a 1-D array
    /// (the times :meth:`Robot.ptp` and ``kinema traj law --dt`` use).
    ///
    /// Raises:
    ///     InvalidInput: ``dt`` is not a positive time step.
    fn times(&self, py: Python<'_>, #[pyo3(from_py_with = real)] dt: f64) -> PyResult<Py<PyArrayDyn<f64>>> {
        let t = sample_times(self.law.duration(), dt).map_err(to_py)?;
        Ok(to_numpy(py, t.len(), t)?.unbind())
    }

    fn __repr__(&self) -> String {
        format!(
            "TimeLaw(profile='{}', distance={}, duration={:.6} s)",
            self.law.profile().name(),
            self.distance,
            self.law.duration()
        )
    }
}

/// A time law, as ``kinema traj law`` builds it: the fastest law of
/// ``profile`` that covers ``distance`` within the limits ``vmax``, ``amax``
/// (and ``jmax``; needed by ``"scurve"``, optional for ``"quintic"``), or —
/// with ``duration`` instead of limits — a law lasting ``duration`` seconds
/// (trapezoid and S-curve in thirds: accelerate, cruise, brake).
///
/// ``profile``: ``"trapezoid"``, ``"scurve"``, ``"cubic"``, ``"quintic"`` or
/// ``"linear"`` (``amax`` may be left out for ``"linear"``). ``distance`` (≥ 0)
/// and the limits share one unit (m, rad, …); the law's samples are scaled by
/// ``distance`` (1 by default: the normalised law s(t)).
///
/// Raises:
///     InvalidInput: unknown profile; both or neither of ``duration`` and the
///         limits; a limit, distance or duration that is not positive and
///         finite; ``jmax`` missing for the S-curve.
#[pyfunction]
#[pyo3(signature = (profile="trapezoid", distance=1.0, vmax=None, amax=None, jmax=None, duration=None))]
fn time_law(
    profile: &str,
    #[pyo3(from_py_with = real)] distance: f64,
    #[pyo3(from_py_with = opt_real)] vmax: Option<f64>,
    #[pyo3(from_py_with = opt_real)] amax: Option<f64>,
    #[pyo3(from_py_with = opt_real)] jmax: Option<f64>,
    #[pyo3(from_py_with = opt_real)] duration: Option<f64>,
) -> PyResult<PyTimeLaw> {
    let profile = profile.parse::<Profile>().map_err(to_py)?;
    let law = if let Some(duration) = duration {
        if vmax.is_some() || amax.is_some() || jmax.is_some() {
            return Err(invalid("give either `duration` or the limits `vmax`, `amax` (and `jmax`), not both".into()));
        }
        if !(distance.is_finite() && distance >= 0.0) {
            return Err(invalid(format!("invalid `distance`: {distance} must be a finite number ≥ 0")));
        }
        TimeLaw::from_duration(profile, duration)
    } else {
        let Some(vel) = vmax else {
            return Err(invalid("give either `duration` or the limits `vmax` and `amax` (and `jmax`)".into()));
        };
        let acc = match amax {
            Some(a) => a,
            // The linear law has no acceleration phase; the core ignores this limit.
            None if profile == Profile::Linear => f64::INFINITY,
            None => return Err(invalid(format!("the {profile} profile needs an acceleration limit `amax`"))),
        };
        TimeLaw::from_limits(profile, distance, &MotionLimits { vel, acc, jerk: jmax })
    }
    .map_err(to_py)?;
    Ok(PyTimeLaw { law, distance })
}

/// A 4×4 row-major block as a pose, or the error naming `what`.
fn pose_from_rows(rows: &[f64], what: &str) -> PyResult<Pose> {
    Pose::from_matrix(&Matrix4::from_row_slice(rows)).ok_or_else(|| {
        invalid(format!(
            "`{what}` is not a rigid transform: it must be finite, the last row 0 0 0 1 and the 3×3 block a rotation"
        ))
    })
}

/// What a pose argument may be, for shape errors.
const POSE_SHAPES: &str = " (a homogeneous transform) or (6,) (x, y, z, roll, pitch, yaw)";

/// x, y, z \[m\], roll, pitch, yaw \[rad\] in `conv` as a pose (as the CLI
/// reads `--pose` and `--to`), or the error naming `what`.
fn pose_from_xyz_rpy(v: &[f64], what: &str, conv: RpyConvention) -> PyResult<Pose> {
    if let Some(x) = v.iter().find(|x| !x.is_finite()) {
        return Err(invalid(format!("`{what}` contains {x}; all values must be finite")));
    }
    Ok(Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], conv))
}

/// A pose argument: a 4×4 homogeneous transform, or 6 numbers x, y, z, roll,
/// pitch, yaw (roll-pitch-yaw convention `conv`).
fn pose_arg(obj: &Bound<'_, PyAny>, what: &str, conv: RpyConvention) -> PyResult<Pose> {
    Ok(*waypoint_arg(obj, what, conv)?.pose())
}

/// A pose argument that keeps a roll-pitch-yaw triple as written, for LIN
/// with `orientation="rpy"` (seed 004 eq. 40).
fn waypoint_arg(obj: &Bound<'_, PyAny>, what: &str, conv: RpyConvention) -> PyResult<Waypoint> {
    let t = f64_array(obj, what)?;
    if t.shape() == [6] {
        return waypoint_from_xyz_rpy(t.as_slice()?, what, conv);
    }
    check_shape(&t, what, &[Some(4), Some(4)], POSE_SHAPES)?;
    Ok(Waypoint::from(pose_from_rows(t.as_slice()?, what)?))
}

fn waypoint_from_xyz_rpy(v: &[f64], what: &str, conv: RpyConvention) -> PyResult<Waypoint> {
    pose_from_xyz_rpy(v, what, conv)?;
    Ok(Waypoint::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], conv))
}

/// Several poses: a (V, 4, 4) array or a list of 4×4 arrays, a (V, 6) array
/// or a list of x, y, z, roll, pitch, yaw rows; one pose (4×4 or 6 numbers)
/// is a list of one. Roll-pitch-yaw triples are kept as written.
fn waypoint_list(obj: &Bound<'_, PyAny>, what: &str, conv: RpyConvention) -> PyResult<Vec<Waypoint>> {
    let t = f64_array(obj, what)?;
    match t.shape() {
        [6] | [4, 4] => Ok(vec![waypoint_arg(obj, what, conv)?]),
        [_, 6] => t
            .as_slice()?
            .chunks_exact(6)
            .enumerate()
            .map(|(i, row)| waypoint_from_xyz_rpy(row, &format!("{what}[{i}]"), conv))
            .collect(),
        _ => {
            check_shape(
                &t,
                what,
                &[None, Some(4), Some(4)],
                " (homogeneous transforms) or (V, 6) (x, y, z, roll, pitch, yaw each)",
            )?;
            t.as_slice()?
                .chunks_exact(16)
                .enumerate()
                .map(|(i, rows)| Ok(Waypoint::from(pose_from_rows(rows, &format!("{what}[{i}]"))?)))
                .collect()
        }
    }
}

/// A point x, y, z \[m\], or the position of a pose (4×4, or x, y, z, roll, pitch, yaw).
fn point_arg(obj: &Bound<'_, PyAny>, what: &str, conv: RpyConvention) -> PyResult<Vector3<f64>> {
    let a = f64_array(obj, what)?;
    if a.ndim() == 2 || a.shape() == [6] {
        return Ok(pose_arg(obj, what, conv)?.pos);
    }
    check_shape(&a, what, &[Some(3)], " (a point x, y, z, or a pose)")?;
    finite_point(a.as_slice()?, what).map(Vector3::from)
}

/// Three finite numbers, or the error naming `what` (as the CLI words it).
fn finite_point(v: &[f64], what: &str) -> PyResult<[f64; 3]> {
    if let Some(x) = v.iter().find(|x| !x.is_finite()) {
        return Err(invalid(format!("`{what}` contains {x}; all values must be finite")));
    }
    Ok([v[0], v[1], v[2]])
}

/// A 3-vector argument (x, y, z).
fn vec3_arg(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 3]> {
    let a = f64_array(obj, what)?;
    check_shape(&a, what, &[Some(3)], " (x, y, z)")?;
    finite_point(a.as_slice()?, what)
}

fn parse_rpy(text: &str) -> PyResult<RpyConvention> {
    match text {
        "zyx" => Ok(RpyConvention::Zyx),
        "xyz" => Ok(RpyConvention::Xyz),
        other => Err(invalid(format!("invalid `rpy`: `{other}`; use \"zyx\" or \"xyz\""))),
    }
}

/// `blend` of :meth:`Robot.lin`, read as `kinema traj lin --blend` reads it.
fn parse_blend(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Blend> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else { return Ok(Blend::Deceleration) };
    let bad = |b: &str| {
        invalid(format!("invalid `blend`: `{b}`; use \"decel\", \"none\", seconds (0.3) or metres (\"0.05m\")"))
    };
    let Ok(text) = obj.downcast::<PyString>() else {
        let seconds = real(obj).map_err(|_| bad(&obj.to_string()))?;
        return Ok(Blend::Time(seconds));
    };
    let text = text.to_str()?;
    let b = text.trim();
    Ok(match b {
        "decel" => Blend::Deceleration,
        "none" => Blend::None,
        _ if b.ends_with('m') => Blend::Distance(b.trim_end_matches('m').trim().parse().map_err(|_| bad(text))?),
        _ => Blend::Time(b.parse().map_err(|_| bad(text))?),
    })
}

/// The options shared by :meth:`Robot.lin` and :meth:`Robot.circ`.
struct CartOptions {
    profile: Profile,
    limits: CartesianLimits,
    method: JointMethod,
    dt: f64,
    max_step: Option<f64>,
    max_angle: f64,
    min_manip: Option<f64>,
}

impl CartOptions {
    #[allow(clippy::too_many_arguments)]
    fn new(
        profile: &str,
        vmax: f64,
        amax: f64,
        jmax: Option<f64>,
        [rot_vmax, rot_amax, rot_jmax]: [Option<f64>; 3],
        (method, self_motion): (&str, SelfMotion),
        dt: f64,
        max_step: Option<f64>,
        max_angle: f64,
        min_manip: Option<f64>,
    ) -> PyResult<Self> {
        if self_motion != SelfMotion::Auto && method != "ik" {
            return Err(invalid("`q3`/`psi` choose the self-motion of method=\"ik\"".into()));
        }
        let method = match method {
            "ik" => JointMethod::Ik(self_motion),
            // The gains `kinema traj lin --method rate` uses.
            "rate" => JointMethod::ResolvedRate { damping: 0.01, gain: 0.5 },
            other => return Err(invalid(format!("invalid `method`: `{other}`; use \"ik\" or \"rate\""))),
        };
        Ok(CartOptions {
            profile: profile.parse::<Profile>().map_err(to_py)?,
            limits: CartesianLimits {
                vel: vmax,
                acc: amax,
                jerk: jmax,
                rot_vel: rot_vmax.unwrap_or(vmax),
                rot_acc: rot_amax.unwrap_or(amax),
                rot_jerk: rot_jmax.or(jmax),
            },
            method,
            dt,
            max_step,
            max_angle,
            min_manip,
        })
    }
}

/// The target of :meth:`Robot.ik` from its keywords (what `kinema ik` reads
/// from --T/--pose, --position, --pitch/--roll, --approach and --alpha).
#[allow(non_snake_case)]
fn ik_target(
    T: Option<&Bound<'_, PyAny>>,
    position: Option<&Bound<'_, PyAny>>,
    pitch: Option<f64>,
    roll: Option<f64>,
    approach: Option<&Bound<'_, PyAny>>,
    alpha: Option<f64>,
    conv: RpyConvention,
) -> PyResult<IkTarget> {
    let T = T.filter(|t| !t.is_none());
    let position = position.filter(|p| !p.is_none());
    let approach = approach.filter(|a| !a.is_none());
    let typed = [pitch.is_some() || roll.is_some(), approach.is_some(), alpha.is_some()];
    let position = match (T, position) {
        (Some(_), Some(_)) => return Err(invalid("give `T` or `position`, not both".into())),
        (None, None) => {
            return Err(invalid(
                "give a target: `T` (a 4×4 pose or x, y, z, roll, pitch, yaw) or `position` (x, y, z)".into(),
            ))
        }
        (Some(_), None) if typed.iter().any(|&t| t) => {
            return Err(invalid("`pitch`/`roll`, `approach` and `alpha` go with `position` (x, y, z), not `T`".into()))
        }
        (Some(t), None) => return pose_arg(t, "T", conv).map(IkTarget::Pose),
        (None, Some(p)) => p,
    };
    if typed.iter().filter(|&&t| t).count() > 1 {
        return Err(invalid(
            "give one typed target: `pitch` and `roll` (Scorbot), `approach` (ROMMEL) or `alpha` (SCARA)".into(),
        ));
    }
    let position = vec3_arg(position, "position")?;
    Ok(match (pitch, roll, approach, alpha) {
        (Some(pitch), Some(roll), _, _) => IkTarget::PositionPitchRoll { position, pitch, roll },
        (Some(_), None, _, _) => {
            return Err(invalid("`pitch` needs `roll` too (Scorbot: position, pitch and roll)".into()))
        }
        (None, Some(_), _, _) => {
            return Err(invalid("`roll` needs `pitch` too (Scorbot: position, pitch and roll)".into()))
        }
        (_, _, Some(a), _) => IkTarget::PositionApproach { position, approach: vec3_arg(a, "approach")? },
        (_, _, _, Some(alpha)) => IkTarget::PositionAlpha { position, alpha },
        _ => IkTarget::Position(position),
    })
}

/// A limit argument: None, one number (every joint) or one per joint.
fn limit_values(obj: Option<&Bound<'_, PyAny>>, what: &str) -> PyResult<Option<Vec<f64>>> {
    let Some(obj) = obj else { return Ok(None) };
    if obj.is_none() {
        return Ok(None);
    }
    let a = f64_array(obj, what)?;
    if a.ndim() > 1 {
        return Err(invalid(format!(
            "`{what}` must be one number or one per joint, got shape {}",
            shape_text(a.shape())
        )));
    }
    Ok(Some(a.as_slice()?.to_vec()))
}

impl PyRobot {
    fn dof(&self) -> usize {
        self.robot.dof()
    }

    /// A joint vector argument: a 1-D array of numbers, or the name of a pose.
    fn joint_vector(&self, obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
        if let Ok(name) = obj.downcast::<PyString>() {
            return self.robot.pose(name.to_str()?).map(<[f64]>::to_vec).map_err(to_py);
        }
        let a = f64_array(obj, what)?;
        check_shape(&a, what, &[None], " (one value per joint)")?;
        Ok(a.as_slice()?.to_vec())
    }

    /// Calls `f` on a joint vector argument: float64 arrays and lists of numbers
    /// are copied to the stack (`npio::read_joints`), anything else is converted by numpy.
    fn with_q<T>(&self, obj: &Bound<'_, PyAny>, f: impl FnOnce(&[f64]) -> kinema::Result<T>) -> PyResult<T> {
        self.with_q_py(obj, |q| f(q).map_err(to_py))
    }

    /// As [`PyRobot::with_q`], for an `f` that gives Python errors itself.
    fn with_q_py<T>(&self, obj: &Bound<'_, PyAny>, f: impl FnOnce(&[f64]) -> PyResult<T>) -> PyResult<T> {
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

    /// Plans the segments `segments(start pose)` from `q0`, converts them to
    /// joints and checks them (what `kinema traj lin|circ` does), without the GIL.
    fn cartesian(
        &self,
        py: Python<'_>,
        q0: Vec<f64>,
        o: CartOptions,
        blend: Blend,
        segments: impl FnOnce(Pose) -> kinema::Result<Vec<Segment>> + Send,
    ) -> PyResult<PyJointTrajectory> {
        let robot = Arc::clone(&self.robot);
        let (motion, traj, poses) = py
            .allow_threads(move || -> kinema::Result<_> {
                let start = robot.fk(&q0)?.world_from_tool;
                let motion = CartesianMotion::new(segments(start)?, o.profile, &o.limits, blend)?;
                let traj = match o.max_step {
                    Some(step) => to_joints_at(
                        &robot,
                        &motion,
                        &q0,
                        &motion.resample_times(step, o.max_angle)?,
                        o.method.clone(),
                    )?,
                    None => to_joints(&robot, &motion, &q0, o.dt, o.method)?,
                };
                let opts = CheckOptions { min_manipulability: o.min_manip, ..CheckOptions::default() };
                check(&robot, &traj, &opts)?.into_result()?;
                let mut poses = vec![0.0; 16 * traj.len()];
                for (out, &t) in poses.chunks_exact_mut(16).zip(traj.times()) {
                    push_pose(out, &motion.at(t).pose);
                }
                Ok((motion, traj, poses))
            })
            .map_err(to_py)?;
        let [t, q, qd, qdd] = traj_arrays(py, &traj)?;
        let laws = motion.laws();
        Ok(PyJointTrajectory {
            t,
            q,
            qd,
            qdd,
            duration: motion.duration(),
            profile: laws[0].profile().name(),
            phase_times: if laws.len() == 1 { laws[0].phase_times().to_vec() } else { Vec::new() },
            poses: Some(to_numpy(py, (traj.len(), 4, 4), poses)?.unbind()),
            segment_starts: motion.segment_starts().to_vec(),
            blend_times: motion.blend_times(),
            skipped: Vec::new(),
        })
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
        Robot::builtin(name).map(|r| PyRobot::new(Arc::new(r))).map_err(to_py)
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
        Robot::from_file(&path, tip).map(|r| PyRobot::new(Arc::new(r))).map_err(to_py)
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

    /// Forward kinematics: the tool pose ``base_from_tool`` as a 4×4 array.
    ///
    /// ``q`` is a 1-D array or list of n joint values (rad / m) or the name of
    /// a pose. Values outside the joint limits are computed anyway.
    ///
    /// ``out``: a writeable C-contiguous float64 array of shape (4, 4) to
    /// write the result into (and return) instead of a new array.
    ///
    /// Raises:
    ///     InvalidInput: wrong number of values, NaN/inf, or not 1-D; an
    ///         ``out`` of the wrong type, dtype, shape or layout, or read-only.
    #[pyo3(signature = (q, out=None))]
    fn fkine<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        // The matrix rows are written by the core straight into the result;
        // on bad input it writes nothing.
        self.with_q_py(q, |q| {
            npio::result_array(py, out, [4, 4], |o| {
                kinema::kin::fk_matrix_into_uninit(&self.robot, q, o).map(|_| ()).map_err(to_py)
            })
        })
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

    /// Inverse dynamics (recursive Newton–Euler, Corke's ``rne``): the joint
    /// torques τ = M(q)·q̈ + C(q, q̇)·q̇ + g(q) [N·m revolute, N prismatic] at
    /// ``q`` [rad or m] with velocities ``qd`` and accelerations ``qdd``.
    /// Each argument has shape (n,), or (N, n) for N configurations (all the
    /// same shape); the result is (n,) or (N, n). ``gravity``: the acceleration
    /// of gravity in the world frame [m/s²], default ``[0, 0, -9.81]`` (as
    /// Corke's ``Robot.gravity``; the arm is pulled towards −z).
    ///
    /// Raises:
    ///     InvalidInput: wrong shapes, NaN/inf.
    ///     KinemaError: a link without mass properties (``[joint.inertial]``
    ///         in TOML, ``<inertial>`` in URDF).
    #[pyo3(signature = (q, qd, qdd, gravity=None))]
    fn rne<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        qdd: &Bound<'py, PyAny>,
        gravity: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let g = dynamics::gravity_arg(gravity)?;
        let rows = dynamics::Rows::read(&self.robot, &[(q, "q"), (qd, "qd"), (qdd, "qdd")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[robot.dof()], |a| kinema::dynamics::rnea(robot, a[0], a[1], a[2], &g))
    }

    /// The joint-space inertia (mass) matrix M(q) (Corke's ``inertia``),
    /// symmetric positive definite, shape (n, n), or (N, n, n) for an (N, n)
    /// ``q`` [kg·m², kg·m or kg].
    #[pyo3(signature = (q))]
    fn inertia<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dof();
        let rows = dynamics::Rows::read(&self.robot, &[(q, "q")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[n, n], |a| dynamics::mass_matrix_rows(robot, a[0]))
    }

    /// The Coriolis and centrifugal matrix C(q, q̇) (Corke's ``coriolis``),
    /// shape (n, n), or (N, n, n) for (N, n) rows: C·q̇ is the velocity part
    /// of ``rne`` and Ṁ − 2C is skew-symmetric (Pinocchio's factorisation).
    #[pyo3(signature = (q, qd))]
    fn coriolis<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dof();
        let rows = dynamics::Rows::read(&self.robot, &[(q, "q"), (qd, "qd")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[n, n], |a| dynamics::coriolis_matrix_rows(robot, a[0], a[1]))
    }

    /// The joint torques that hold the arm still against gravity, g(q)
    /// (Corke's ``gravload``; ``rne(q, 0, 0, gravity)``), shape (n,) or
    /// (N, n). ``gravity`` as in :meth:`rne`.
    #[pyo3(signature = (q, gravity=None))]
    fn gravload<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        gravity: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let g = dynamics::gravity_arg(gravity)?;
        let rows = dynamics::Rows::read(&self.robot, &[(q, "q")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[robot.dof()], |a| kinema::dynamics::gravity_torques(robot, a[0], &g))
    }

    /// Forward dynamics (Corke's ``accel``): the joint accelerations q̈
    /// [rad/s² or m/s²] that ``torque`` [N·m or N] gives at ``q`` and ``qd``,
    /// q̈ = M(q)⁻¹·(τ − C(q, q̇)·q̇ − g(q)). Shapes and ``gravity`` as in :meth:`rne`.
    #[pyo3(signature = (q, qd, torque, gravity=None))]
    fn accel<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        torque: &Bound<'py, PyAny>,
        gravity: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let g = dynamics::gravity_arg(gravity)?;
        let rows = dynamics::Rows::read(&self.robot, &[(q, "q"), (qd, "qd"), (torque, "torque")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[robot.dof()], |a| kinema::dynamics::forward_dynamics(robot, a[0], a[1], a[2], &g))
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
    #[allow(non_snake_case)]
    #[pyo3(signature = (Q, out=None))]
    fn fkine_batch<'py>(
        &self,
        py: Python<'py>,
        Q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let robot = &*self.robot;
        let row = |q: &[f64], o: &mut _| kinema::kin::fk_matrix_into_uninit(robot, q, o).map(|_| ());
        fast::batch(py, robot, Q, "Q", out, [4, 4], row)
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

    /// Inverse kinematics: joint values that put the tool at a target, as
    /// ``kinema ik`` finds them (core: ``ik::solve_target``, ``ik::pick_one``).
    ///
    /// The target is one of:
    ///
    /// * ``T``: a full pose ``base_from_tool``, a 4×4 array or 6 numbers
    ///   x, y, z [m], roll, pitch, yaw [rad] in the convention ``rpy``
    ///   (``"zyx"``: R = Rz(yaw)·Ry(pitch)·Rx(roll), the default of
    ///   ``kinema ik --pose``; ``"xyz"``: Rx·Ry·Rz). The robot's analytic
    ///   solver, or the numeric one.
    /// * ``position=[x, y, z]`` alone: the tool point [m], orientation free
    ///   (``--position``): the numeric solver with a position-only task mask.
    ///   The solutions' ``orientation_error`` is measured against the ``home``
    ///   orientation (a placeholder, as the CLI prints it); ``success`` ignores it.
    /// * ``position`` with ``pitch`` and ``roll`` [rad]: Scorbot (seed 000
    ///   eq. 13: pitch β = −(θ2 + θ3 + θ4), roll γ = θ5; the yaw follows from
    ///   the position), up to four solutions.
    /// * ``position`` with ``approach=[ax, ay, az]``: ROMMEL, the tool z axis
    ///   along the approach (any non-zero length; q5 = 0), up to four solutions.
    /// * ``position`` with ``alpha`` [rad]: SCARA on a rail, tool angle
    ///   α = q2 + q3 + q5, the rail placed by seed 003's zone rule, elbow side
    ///   and q5 kept from ``q0``; one solution.
    ///
    /// A typed target on a robot of another family raises that solver's own
    /// error (e.g. "the Scorbot solver needs 5 revolute joints …").
    ///
    /// ``solver``: ``"auto"`` (the robot's analytic solver when it has one,
    /// else numeric), ``"analytic"`` or ``"numeric"`` (damped least squares
    /// with restarts seeded by ``seed``; not with typed targets, ``q3`` or
    /// ``psi``). ``q0``: previous configuration (array or pose name): the
    /// numeric solver starts there, and the solution nearest to it is
    /// returned. iiwa-type (SRS) arms, from any description, and a full pose
    /// only: ``q3`` solves with that fixed q3 (up to 8 solutions), ``psi`` at
    /// that arm angle (one solution per configuration).
    ///
    /// ``mask``: with a full pose ``T``, six booleans (or 0/1) saying which of
    /// x, y, z, ωx, ωy, ωz (world frame) a solution must meet, e.g.
    /// ``[1, 1, 1, 0, 1, 1]`` frees the rotation about the world z axis (the
    /// numeric solver is used). ``tol_position`` [m] / ``tol_orientation``
    /// [rad]: how close FK of a solution must come to the target.
    ///
    /// Every solution returned meets the target: forward kinematics of it is
    /// within the tolerances on every component the target fixes; candidates
    /// of the solver that miss it are dropped (``kinema ik --json`` lists them
    /// under ``discarded``). A 5-joint arm given a full pose it cannot take
    /// raises Unreachable, unless ``mask`` frees what it cannot control.
    ///
    /// Returns one :class:`IkSolution` within the joint limits (nearest to
    /// ``q0`` when given), or with ``all=True`` a list of every solution found,
    /// including those outside the limits (``within_limits`` False).
    ///
    /// Raises:
    ///     Unreachable: no solution (outside the reach, an approach the arm
    ///         cannot take, every solution violates a limit, no convergence);
    ///         ``.solver`` and ``.reason`` say which and why, ``.closest`` the
    ///         configuration that came closest when one was found.
    ///     InvalidInput: no target, or ``T`` and ``position`` both; ``pitch``
    ///         without ``roll`` (or the reverse), typed keywords without
    ///         ``position`` or more than one typed target; ``T`` not a 4×4 rigid
    ///         transform or 6 numbers; non-finite values; bad ``q0``; unknown
    ///         ``solver`` or ``rpy``; a typed target, ``q3`` or ``psi`` with
    ///         ``solver="numeric"``; ``q3`` and ``psi`` both, or with a
    ///         position-only or typed target; ``q3``/``psi`` on a robot that is
    ///         not iiwa-type; a typed target on a robot of another family.
    #[allow(non_snake_case, clippy::too_many_arguments)]
    #[pyo3(signature = (T=None, all=false, q0=None, solver="auto", q3=None, psi=None, seed=0, *, position=None,
        pitch=None, roll=None, approach=None, alpha=None, rpy="zyx", mask=None, tol_position=1e-6,
        tol_orientation=1e-6))]
    fn ik(
        &self,
        py: Python<'_>,
        T: Option<&Bound<'_, PyAny>>,
        all: bool,
        q0: Option<&Bound<'_, PyAny>>,
        solver: &str,
        #[pyo3(from_py_with = opt_real)] q3: Option<f64>,
        #[pyo3(from_py_with = opt_real)] psi: Option<f64>,
        #[pyo3(from_py_with = seed_arg)] seed: u64,
        position: Option<&Bound<'_, PyAny>>,
        #[pyo3(from_py_with = opt_real)] pitch: Option<f64>,
        #[pyo3(from_py_with = opt_real)] roll: Option<f64>,
        approach: Option<&Bound<'_, PyAny>>,
        #[pyo3(from_py_with = opt_real)] alpha: Option<f64>,
        rpy: &str,
        #[pyo3(from_py_with = mask_arg)] mask: Option<[bool; 6]>,
        #[pyo3(from_py_with = real)] tol_position: f64,
        #[pyo3(from_py_with = real)] tol_orientation: f64,
    ) -> PyResult<PyObject> {
        let solver = solver_choice(solver)?;
        let target = ik_target(T, position, pitch, roll, approach, alpha, parse_rpy(rpy)?)?;
        let q0 = q0.filter(|q| !q.is_none()).map(|q| self.joint_vector(q, "q0")).transpose()?;
        let robot = Arc::clone(&self.robot);
        let family = self.family.clone();
        let (name, solutions) = py
            .allow_threads(move || -> kinema::Result<(&'static str, Vec<Solution>)> {
                let request = IkRequest {
                    solver,
                    q0: q0.as_deref(),
                    all,
                    q3,
                    psi,
                    mask,
                    tolerance: Tolerance { position: tol_position, orientation: tol_orientation },
                    numeric: NumericOptions { seed, ..Default::default() },
                };
                let answer = solve_target_with(&robot, family.as_deref(), &target, &request)?;
                let name = answer.solver;
                if all {
                    return Ok((name, answer.solutions));
                }
                Ok((name, vec![pick_one(&robot, name, answer.solutions, q0.as_deref())?]))
            })
            .map_err(to_py)?;
        let free = target.orientation_free();
        let mut list: Vec<PyIkSolution> = solutions.iter().map(|s| PyIkSolution::new(py, s, name, free)).collect();
        if all {
            return Ok(list.into_pyobject(py)?.into_any().unbind());
        }
        match list.pop() {
            Some(one) => Ok(Bound::new(py, one)?.into_any().unbind()),
            None => Err(KinemaError::new_err("the solver returned no solution")),
        }
    }

    /// Inverse kinematics of many targets at once, one solution each, solved
    /// exactly as :meth:`ik` would (the same contract, solver choice and pick:
    /// within limits, nearest ``q0`` when given), in parallel over all cores
    /// with the GIL released (core: ``ik::solve_batch``).
    ///
    /// ``T``: a (V, 4, 4) array of poses or (V, 6) rows x, y, z, roll, pitch,
    /// yaw (convention ``rpy``); or ``position``: a (V, 3) array of tool
    /// points, orientation free. ``q0``, ``solver``, ``mask``, ``seed`` and the
    /// tolerances as in :meth:`ik`.
    ///
    /// Returns ``(Q, success, reasons)``: Q of shape (V, n) (a row of NaN where
    /// a target was not solved), ``success`` a (V,) bool array, ``reasons`` a
    /// list of V strings (empty for solved targets, else why: unreachable with
    /// its reason, or invalid).
    ///
    /// Raises:
    ///     InvalidInput: no target or both; arrays of the wrong shape; a pose
    ///         that is not a rigid transform (naming its index); bad ``q0``,
    ///         ``solver``, ``mask``, tolerances or ``seed``.
    #[allow(non_snake_case, clippy::too_many_arguments)]
    #[pyo3(signature = (T=None, *, position=None, q0=None, solver="auto", mask=None, seed=0, rpy="zyx",
        tol_position=1e-6, tol_orientation=1e-6))]
    fn ik_batch<'py>(
        &self,
        py: Python<'py>,
        T: Option<&Bound<'py, PyAny>>,
        position: Option<&Bound<'py, PyAny>>,
        q0: Option<&Bound<'py, PyAny>>,
        solver: &str,
        #[pyo3(from_py_with = mask_arg)] mask: Option<[bool; 6]>,
        #[pyo3(from_py_with = seed_arg)] seed: u64,
        rpy: &str,
        #[pyo3(from_py_with = real)] tol_position: f64,
        #[pyo3(from_py_with = real)] tol_orientation: f64,
    ) -> PyResult<IkBatchResult<'py>> {
        let solver = solver_choice(solver)?;
        let targets = match (T.filter(|t| !t.is_none()), position.filter(|p| !p.is_none())) {
            (Some(t), None) => batch::Targets::poses(f64_array(t, "T")?, parse_rpy(rpy)?)?,
            (None, Some(p)) => batch::Targets::points(f64_array(p, "position")?)?,
            (Some(_), Some(_)) => return Err(invalid("give `T` or `position`, not both".into())),
            (None, None) => return Err(invalid("give the targets: `T` (V poses) or `position` (V points)".into())),
        };
        let q0 = q0.filter(|q| !q.is_none()).map(|q| self.joint_vector(q, "q0")).transpose()?;
        let request = IkRequest {
            solver,
            q0: q0.as_deref(),
            mask,
            tolerance: Tolerance { position: tol_position, orientation: tol_orientation },
            numeric: NumericOptions { seed, ..Default::default() },
            ..Default::default()
        };
        let (count, n) = (targets.len(), self.robot.dof());
        let mut q = batch::reserve::<f64>(count.saturating_mul(n), "the joint values of the answer")?;
        let mut ok = batch::reserve::<bool>(count, "the success flags")?;
        let mut reasons = batch::reserve::<String>(count, "the reasons")?;
        let robot = &self.robot;
        for from in (0..count).step_by(batch::CHUNK) {
            let chunk = targets.read(from, (from + batch::CHUNK).min(count))?;
            let results = py
                .allow_threads(|| kinema::ik::solve_batch(robot, &chunk, &request, &|| {}, &|| false))
                .map_err(to_py)?;
            for r in results {
                match r {
                    Ok((_, s)) => {
                        q.extend_from_slice(&s.q);
                        ok.push(true);
                        reasons.push(String::new());
                    }
                    Err(e) => {
                        q.extend(std::iter::repeat_n(f64::NAN, n));
                        ok.push(false);
                        reasons.push(e.to_string());
                    }
                }
            }
            py.check_signals()?;
        }
        let success = Array::from_vec(ok).into_dyn().into_pyarray(py);
        Ok((to_numpy(py, (count, n), q)?, success, reasons))
    }

    /// Point-to-point motion in joint space from ``q0`` to ``qf`` (seed 004
    /// eq. 38: every joint follows one shared time law, so all start and stop
    /// together), sampled every ``dt`` seconds plus the end time.
    ///
    /// ``profile``: ``"trapezoid"``, ``"scurve"``, ``"cubic"``, ``"quintic"`` or
    /// ``"linear"``; ``None`` (the default) is the robot's default profile, the
    /// trapezoid unless the model has jerk limits (the Panda: ``"scurve"``).
    /// ``vmax``/``amax``/``jmax``: velocity, acceleration and jerk
    /// limits (one value for every joint or one per joint; default: the robot's). ``speed``: override in
    /// (0, 1] (velocity limits × speed, acceleration × speed², jerk × speed³).
    /// ``duration``: stretch the motion to this many seconds. The sampled
    /// trajectory is checked against the robot's limits, as ``kinema traj ptp`` does.
    ///
    /// ``v0``/``a0``/``v1``/``a1``: joint velocities and accelerations at the
    /// start and the end (one per joint; default 0), to chain motions
    /// without stopping, as ``kinema traj ptp --v0 …``. With any of them
    /// non-zero each joint follows its own time-optimal law (``"scurve"``:
    /// any accelerations; ``"trapezoid"``: accelerations 0) and all end
    /// together at the smallest common duration (``duration``: at least
    /// this); the path is then in general not a straight line in joint space,
    /// and ``phase_times`` is empty.
    ///
    /// Raises:
    ///     InvalidInput: bad joint vectors, limits, profile, ``dt``, ``speed``
    ///         or boundary values (the message names ``v0``/``a0``/``v1``/``a1``).
    ///     TrajectoryError: the sampled trajectory breaks a limit.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (q0, qf, dt, profile=None, vmax=None, amax=None, jmax=None, speed=1.0, duration=None, *, v0=None, a0=None, v1=None, a1=None))]
    fn ptp(
        &self,
        py: Python<'_>,
        q0: &Bound<'_, PyAny>,
        qf: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = real)] dt: f64,
        profile: Option<&str>,
        vmax: Option<&Bound<'_, PyAny>>,
        amax: Option<&Bound<'_, PyAny>>,
        jmax: Option<&Bound<'_, PyAny>>,
        #[pyo3(from_py_with = real)] speed: f64,
        #[pyo3(from_py_with = opt_real)] duration: Option<f64>,
        v0: Option<&Bound<'_, PyAny>>,
        a0: Option<&Bound<'_, PyAny>>,
        v1: Option<&Bound<'_, PyAny>>,
        a1: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyJointTrajectory> {
        let from = self.joint_vector(q0, "q0")?;
        let to = self.joint_vector(qf, "qf")?;
        let boundary = kinema::traj::JointBoundary {
            v0: limit_values(v0, "v0")?,
            a0: limit_values(a0, "a0")?,
            v1: limit_values(v1, "v1")?,
            a1: limit_values(a1, "a1")?,
        };
        let profile = match profile {
            Some(name) => name.parse::<Profile>().map_err(to_py)?,
            None => kinema::traj::default_profile(&self.robot),
        };
        let opts = PtpOptions {
            profile,
            vel: limit_values(vmax, "vmax")?,
            acc: limit_values(amax, "amax")?,
            jerk: limit_values(jmax, "jmax")?,
            speed,
            duration,
        };
        let robot = Arc::clone(&self.robot);
        if boundary != kinema::traj::JointBoundary::default() {
            let name = opts.profile.name();
            let (plan, traj) = py
                .allow_threads(move || -> kinema::Result<_> {
                    let plan = kinema::traj::BoundaryPtp::new(&robot, &from, &to, &opts, &boundary)?;
                    let traj = plan.sample(&robot, dt)?;
                    Ok((plan, traj))
                })
                .map_err(to_py)?;
            let [t, q, qd, qdd] = traj_arrays(py, &traj)?;
            return Ok(PyJointTrajectory {
                t,
                q,
                qd,
                qdd,
                duration: plan.duration(),
                profile: name,
                phase_times: plan.rest().map_or_else(Vec::new, |p| p.law().phase_times().to_vec()),
                poses: None,
                segment_starts: vec![0.0],
                blend_times: Vec::new(),
                skipped: Vec::new(),
            });
        }
        let (plan, traj) = py
            .allow_threads(move || -> kinema::Result<_> {
                let plan = Ptp::new(&robot, &from, &to, &opts)?;
                let traj = plan.sample(&robot, dt)?;
                Ok((plan, traj))
            })
            .map_err(to_py)?;
        let [t, q, qd, qdd] = traj_arrays(py, &traj)?;
        Ok(PyJointTrajectory {
            t,
            q,
            qd,
            qdd,
            duration: plan.duration(),
            profile: plan.law().profile().name(),
            phase_times: plan.law().phase_times().to_vec(),
            poses: None,
            segment_starts: vec![0.0],
            blend_times: Vec::new(),
            skipped: Vec::new(),
        })
    }

    /// Straight-line Cartesian motion (LIN, seed 004 §VIII-C) from the tool
    /// pose of ``q0`` to the pose ``T`` (``base_from_tool``), through the
    /// optional ``via`` poses, converted to joint values and checked against
    /// the robot's limits, as ``kinema traj lin`` does.
    ///
    /// A pose is a 4×4 array or, as ``kinema traj lin --to/--via`` reads it,
    /// 6 numbers x, y, z [m], roll, pitch, yaw [rad] in the convention
    /// ``rpy`` (``"zyx"``: R = Rz(yaw)·Ry(pitch)·Rx(roll), the default;
    /// ``"xyz"``: Rx·Ry·Rz, seed 004's). ``via``: one pose, a list of poses
    /// of one form, a (V, 4, 4) or a (V, 6) array.
    ///
    /// ``q0``: start configuration (array or pose name); to start from a pose,
    /// pass ``robot.ik(T0).q``. ``dt``: sample period [s]. ``vmax`` [m/s],
    /// ``amax`` [m/s²], ``jmax`` [m/s³]: tool-point limits; ``rot_vmax``
    /// [rad/s], ``rot_amax`` [rad/s²], ``rot_jmax`` [rad/s³]: angular limits
    /// (default: the same numbers). ``profile``: the time law of each segment.
    /// ``blend`` at via points: ``"decel"`` (the next segment starts when the
    /// previous one decelerates), ``"none"``, a time in seconds (``0.3`` or
    /// ``"0.3"``) or a distance (``"0.05m"``). ``orientation``: ``"slerp"`` or
    /// ``"rpy"`` (linear roll-pitch-yaw angles in the convention ``rpy``,
    /// ``"zyx"`` or ``"xyz"``). ``method``: ``"ik"`` (inverse kinematics at
    /// every sample, nearest branch) or ``"rate"`` (resolved rate, damping
    /// 0.01, gain 0.5). ``max_step`` [m] / ``max_angle`` [rad]: instead of a
    /// fixed period, sample so that consecutive poses are at most this far
    /// apart. ``min_manip``: also reject samples whose translational
    /// manipulability is below this value. ``q3`` / ``psi``: the self-motion
    /// of a redundant arm (``kinema traj lin --q3/--psi``): ``q3`` is
    /// ``"hold"`` (the start's q3, the default where the arm has a closed
    /// form), ``"track"`` (least joint motion), ``"manipulability"`` (seed
    /// 004 §V-E), ``"avoid-limits"`` or an angle the start must have; ``psi``
    /// is ``"hold"`` or an angle. ``skip_unreachable``: leave out ``via`` and
    /// ``T`` poses out of reach (seed 003 Fig. 9; their indices in the
    /// result's ``skipped``) instead of raising Unreachable.
    ///
    /// Raises:
    ///     InvalidInput: bad joint vector, pose, limit, option, ``rpy`` or ``dt``.
    ///     Unreachable: a sample of the path that inverse kinematics cannot
    ///         reach (``.solver`` names the time along the path).
    ///     TrajectoryError: the joint trajectory breaks a limit.
    #[allow(non_snake_case, clippy::too_many_arguments)]
    #[pyo3(signature = (q0, T, dt, *, vmax, amax, via=None, profile="trapezoid", jmax=None, rot_vmax=None,
        rot_amax=None, rot_jmax=None, blend=None, orientation="slerp", rpy="zyx", method="ik", max_step=None,
        max_angle=0.05, min_manip=None, q3=None, psi=None, skip_unreachable=false))]
    fn lin(
        &self,
        py: Python<'_>,
        q0: &Bound<'_, PyAny>,
        T: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = real)] dt: f64,
        #[pyo3(from_py_with = real)] vmax: f64,
        #[pyo3(from_py_with = real)] amax: f64,
        via: Option<&Bound<'_, PyAny>>,
        profile: &str,
        #[pyo3(from_py_with = opt_real)] jmax: Option<f64>,
        #[pyo3(from_py_with = opt_real)] rot_vmax: Option<f64>,
        #[pyo3(from_py_with = opt_real)] rot_amax: Option<f64>,
        #[pyo3(from_py_with = opt_real)] rot_jmax: Option<f64>,
        blend: Option<&Bound<'_, PyAny>>,
        orientation: &str,
        rpy: &str,
        method: &str,
        #[pyo3(from_py_with = opt_real)] max_step: Option<f64>,
        #[pyo3(from_py_with = real)] max_angle: f64,
        #[pyo3(from_py_with = opt_real)] min_manip: Option<f64>,
        q3: Option<&Bound<'_, PyAny>>,
        psi: Option<&Bound<'_, PyAny>>,
        skip_unreachable: bool,
    ) -> PyResult<PyJointTrajectory> {
        let q0 = self.joint_vector(q0, "q0")?;
        let conv = parse_rpy(rpy)?;
        let mut points = match via {
            Some(v) if !v.is_none() => waypoint_list(v, "via", conv)?,
            _ => Vec::new(),
        };
        points.push(waypoint_arg(T, "T", conv)?);
        // Seed 003 Fig. 9, as `kinema traj lin --skip-unreachable`.
        let skipped: Vec<usize> = if skip_unreachable {
            let poses: Vec<Pose> = points.iter().map(|p| *p.pose()).collect();
            let (_, skipped) = kinema::traj::waypoints::skip_unreachable(&self.robot, &poses).map_err(to_py)?;
            let skipped: Vec<usize> = skipped.iter().map(|p| p.index).collect();
            points = points.into_iter().enumerate().filter(|(i, _)| !skipped.contains(i)).map(|(_, p)| p).collect();
            skipped
        } else {
            Vec::new()
        };
        let orientation = match orientation {
            "slerp" => Orientation::Slerp,
            "rpy" => Orientation::Rpy(conv),
            other => return Err(invalid(format!("invalid `orientation`: `{other}`; use \"slerp\" or \"rpy\""))),
        };
        let blend = parse_blend(blend)?;
        let opts = CartOptions::new(
            profile,
            vmax,
            amax,
            jmax,
            [rot_vmax, rot_amax, rot_jmax],
            (method, self_motion_arg(q3, psi)?),
            dt,
            max_step,
            max_angle,
            min_manip,
        )?;
        let mut traj =
            self.cartesian(py, q0, opts, blend, move |start| Segment::lin_chain(&start, &points, orientation))?;
        traj.skipped = skipped;
        Ok(traj)
    }

    /// Circular Cartesian motion (CIRC, as KUKA CIRC / ABB MoveC) from the
    /// tool pose of ``q0`` through the point ``via`` (x, y, z [m]; a pose
    /// gives its position) to the pose ``T``, the orientation turning from
    /// the start's to ``T``'s by SLERP; converted to joint values and checked,
    /// as ``kinema traj circ`` does. Poses are 4×4 arrays or 6 numbers x, y,
    /// z, roll, pitch, yaw in the convention ``rpy`` (as ``--to`` with
    /// ``--rpy``). The other arguments are those of :meth:`lin`.
    ///
    /// Raises:
    ///     InvalidInput: start, ``via`` and end on one line or coinciding;
    ///         bad joint vector, pose, limit, option or ``dt``.
    ///     Unreachable: a sample of the arc that inverse kinematics cannot reach.
    ///     TrajectoryError: the joint trajectory breaks a limit.
    #[allow(non_snake_case, clippy::too_many_arguments)]
    #[pyo3(signature = (q0, via, T, dt, *, vmax, amax, profile="trapezoid", jmax=None, rot_vmax=None,
        rot_amax=None, rot_jmax=None, rpy="zyx", method="ik", max_step=None, max_angle=0.05, min_manip=None,
        q3=None, psi=None))]
    fn circ(
        &self,
        py: Python<'_>,
        q0: &Bound<'_, PyAny>,
        via: &Bound<'_, PyAny>,
        T: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = real)] dt: f64,
        #[pyo3(from_py_with = real)] vmax: f64,
        #[pyo3(from_py_with = real)] amax: f64,
        profile: &str,
        #[pyo3(from_py_with = opt_real)] jmax: Option<f64>,
        #[pyo3(from_py_with = opt_real)] rot_vmax: Option<f64>,
        #[pyo3(from_py_with = opt_real)] rot_amax: Option<f64>,
        #[pyo3(from_py_with = opt_real)] rot_jmax: Option<f64>,
        rpy: &str,
        method: &str,
        #[pyo3(from_py_with = opt_real)] max_step: Option<f64>,
        #[pyo3(from_py_with = real)] max_angle: f64,
        #[pyo3(from_py_with = opt_real)] min_manip: Option<f64>,
        q3: Option<&Bound<'_, PyAny>>,
        psi: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyJointTrajectory> {
        let q0 = self.joint_vector(q0, "q0")?;
        let conv = parse_rpy(rpy)?;
        let aux = point_arg(via, "via", conv)?;
        let to = pose_arg(T, "T", conv)?;
        let opts = CartOptions::new(
            profile,
            vmax,
            amax,
            jmax,
            [rot_vmax, rot_amax, rot_jmax],
            (method, self_motion_arg(q3, psi)?),
            dt,
            max_step,
            max_angle,
            min_manip,
        )?;
        self.cartesian(py, q0, opts, Blend::None, move |start| Ok(vec![Segment::circ_through(&start, &aux, &to)?]))
    }

    /// Joint curves from expressions of t (``kinema traj expr``, seed 001
    /// §4.2): the joints in ``joints`` follow their expressions, the others
    /// hold their values in ``q0`` (default ``home``); sampled every ``dt``
    /// seconds over [0, ``duration``] plus the end time, velocities and
    /// accelerations from the symbolic derivatives, checked against the
    /// robot's limits, or against ``vmax``/``amax``/``jmax`` where given (one
    /// value or one per joint, as :meth:`check` takes them): a curve meant
    /// for a simulation, such as seed 001's θ1 = 3·sin(2πt²), can be faster
    /// than the arm.
    ///
    /// ``joints``: ``{joint: expression}`` or a list of ``(joint, expression)``
    /// pairs, joints numbered from 1 as in ``--joint 1 "3*sin(4*pi*t^2/2)"``.
    /// Expressions use ``t``, numbers, ``pi``, ``e``, ``+ - * / ^``, and
    /// functions such as ``sin``, ``cos``, ``exp``, ``sqrt``, ``min``, ``max``.
    ///
    /// Returns a :class:`JointTrajectory` with ``profile == "expression"``.
    ///
    /// Raises:
    ///     InvalidInput: no joint, a joint number out of range, an expression
    ///         that does not parse (its column in the message) or is not finite
    ///         at some sample, a bad ``q0``, ``duration`` or ``dt``.
    ///     TrajectoryError: the trajectory breaks a limit.
    #[pyo3(signature = (joints, duration, dt=0.01, q0=None, *, vmax=None, amax=None, jmax=None))]
    #[allow(clippy::too_many_arguments)]
    fn expr(
        &self,
        py: Python<'_>,
        joints: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = real)] duration: f64,
        #[pyo3(from_py_with = real)] dt: f64,
        q0: Option<&Bound<'_, PyAny>>,
        vmax: Option<&Bound<'_, PyAny>>,
        amax: Option<&Bound<'_, PyAny>>,
        jmax: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyJointTrajectory> {
        let limits = CheckOptions {
            vel: limit_values(vmax, "vmax")?,
            acc: limit_values(amax, "amax")?,
            jerk: limit_values(jmax, "jmax")?,
            ..CheckOptions::default()
        };
        let q0 = match q0.filter(|q| !q.is_none()) {
            Some(q) => self.joint_vector(q, "q0")?,
            None => self.robot.home().to_vec(),
        };
        let pairs: Vec<(i64, String)> = match joints.downcast::<PyDict>() {
            Ok(d) => d.items().extract(),
            Err(_) => joints.try_iter().and_then(|it| it.map(|p| p?.extract()).collect()),
        }
        .map_err(|_| {
            invalid("`joints` must be a dict {joint: expression} or (joint, expression) pairs, joints from 1".into())
        })?;
        if pairs.is_empty() {
            return Err(invalid("give at least one joint expression, e.g. {1: \"0.5*sin(t)\"}".into()));
        }
        let mut exprs = Vec::with_capacity(pairs.len());
        for (j, text) in pairs {
            if j < 1 {
                return Err(invalid(format!("`joints`: joint {j}: joints are numbered from 1")));
            }
            exprs.push((j as usize - 1, Expr::parse(&text).map_err(to_py)?));
        }
        let robot = Arc::clone(&self.robot);
        let traj = py
            .allow_threads(move || -> kinema::Result<_> {
                let traj = expression_trajectory(&robot, &q0, &exprs, duration, dt)?;
                check(&robot, &traj, &limits)?.into_result()?;
                Ok(traj)
            })
            .map_err(to_py)?;
        let [t, q, qd, qdd] = traj_arrays(py, &traj)?;
        Ok(PyJointTrajectory {
            t,
            q,
            qd,
            qdd,
            duration: traj.times().last().copied().unwrap_or(0.0),
            profile: "expression",
            phase_times: Vec::new(),
            poses: None,
            segment_starts: vec![0.0],
            blend_times: Vec::new(),
            skipped: Vec::new(),
        })
    }

    /// Checks a joint trajectory against the robot's limits, as
    /// ``kinema traj check`` checks a CSV file: position limits, velocity,
    /// acceleration and jerk limits (the robot's, or ``vmax``/``amax``/``jmax``:
    /// one value or one per joint) on the given derivatives and on what q
    /// itself implies, jumps between samples larger than the velocity limit
    /// allows, non-finite values and times that do not increase, with
    /// ``min_manip`` samples whose manipulability (all six Jacobian rows) is
    /// below it, and singular passages as warnings (the Jacobian's inverse
    /// condition number below ``singular``, 1e-3 as the CLI; 0 turns it off).
    /// Arrays read from a file are known only to its last digit: give
    /// ``resolution`` and ``time_resolution`` (half of it, e.g. 5e-13 and
    /// 5e-10 for a CSV of ``kinema traj``) so the derivative checks allow for
    /// it, as ``kinema traj check`` does from the file's text.
    ///
    /// The trajectory: a :class:`JointTrajectory` or :class:`Plan`, or the
    /// arrays ``t`` (K,) [s] and ``q`` (K, n), with ``qd``, ``qdd`` (K, n)
    /// optional — estimated from the positions when absent (second-order
    /// differences, as for a file without ``qd``/``qdd`` columns). A CSV
    /// written by ``kinema traj`` reads with
    /// ``np.genfromtxt(path, delimiter=",", names=True)``.
    ///
    /// Returns a :class:`CheckReport` (a trajectory that breaks a limit is
    /// reported, not raised; see :meth:`CheckReport.raise_if_violations`).
    ///
    /// Raises:
    ///     InvalidInput: arrays of the wrong shape, no samples, bad limits.
    #[pyo3(signature = (t, q=None, qd=None, qdd=None, *, vmax=None, amax=None, jmax=None, min_manip=None,
                        singular=kinema::traj::SINGULAR_WARNING, resolution=0.0, time_resolution=0.0))]
    #[allow(clippy::too_many_arguments)]
    fn check(
        &self,
        py: Python<'_>,
        t: &Bound<'_, PyAny>,
        q: Option<&Bound<'_, PyAny>>,
        qd: Option<&Bound<'_, PyAny>>,
        qdd: Option<&Bound<'_, PyAny>>,
        vmax: Option<&Bound<'_, PyAny>>,
        amax: Option<&Bound<'_, PyAny>>,
        jmax: Option<&Bound<'_, PyAny>>,
        #[pyo3(from_py_with = opt_real)] min_manip: Option<f64>,
        #[pyo3(from_py_with = real)] singular: f64,
        #[pyo3(from_py_with = real)] resolution: f64,
        #[pyo3(from_py_with = real)] time_resolution: f64,
    ) -> PyResult<PyCheckReport> {
        for (what, v) in [("resolution", resolution), ("time_resolution", time_resolution)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(invalid(format!("`{what}` must be a finite number ≥ 0, not {v}")));
            }
        }
        let [q, qd, qdd] = [q, qd, qdd].map(|a| a.filter(|a| !a.is_none()));
        let given = |arrays: [&Py<PyArrayDyn<f64>>; 4]| {
            if q.is_some() || qd.is_some() || qdd.is_some() {
                return Err(invalid("give a trajectory or the arrays `t`, `q` (`qd`, `qdd`), not both".into()));
            }
            Ok(arrays.map(|a| a.bind(py).clone().into_any()))
        };
        let arrays = if let Ok(tr) = t.downcast::<PyJointTrajectory>() {
            let tr = tr.get();
            Some(given([&tr.t, &tr.q, &tr.qd, &tr.qdd])?)
        } else if let Ok(plan) = t.downcast::<PyPlan>() {
            let plan = plan.get();
            Some(given([&plan.t, &plan.q, &plan.qd, &plan.qdd])?)
        } else {
            None
        };
        let (t, q, qd, qdd) = match &arrays {
            Some([t, q, qd, qdd]) => (t, Some(q), Some(qd), Some(qdd)),
            None => (t, q, qd, qdd),
        };
        let Some(q) = q else {
            return Err(invalid("`q` is missing: give the joint positions, shape (K, n), with the times `t`".into()));
        };
        let traj = cell::traj_from_arrays(self.dof(), t, q, qd, qdd)?;
        let opts = CheckOptions {
            vel: limit_values(vmax, "vmax")?,
            acc: limit_values(amax, "amax")?,
            jerk: limit_values(jmax, "jmax")?,
            min_manipulability: min_manip,
            singular_warning: (singular != 0.0).then_some(singular),
            value_resolution: resolution,
            time_resolution,
            ..CheckOptions::default()
        };
        let robot = Arc::clone(&self.robot);
        let report = py.allow_threads(move || check(&robot, &traj, &opts)).map_err(to_py)?;
        Ok(PyCheckReport { report })
    }

    fn __repr__(&self) -> String {
        format!("Robot('{}', n={})", self.robot.name(), self.dof())
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.downcast::<PyRobot>().is_ok_and(|o| *o.get().robot == *self.robot)
    }
}

/// A robot program run on a robot model (from :func:`run_program`): the
/// joint signals ``kinema run`` writes, and the motion plan.
///
/// Attributes:
///     t: sample times, shape (K,) [s].
///     q, qd, qdd: joint positions, velocities and accelerations, shape
///         (K, n): the ``t,q…,qd…,qdd…`` columns of ``kinema run``'s CSV.
///     duration: total duration [s].
///     motions: one dict per motion, in execution order, with keys
///         ``line`` (source line, from 1), ``kind`` (``"PTP"``, ``"LIN"``,
///         ``"WAIT"``, ...), ``start``, ``end`` [s], ``profile`` and ``target``
///         (as ``kinema compile --json`` prints them).
///     warnings: the program's warnings, one line each
///         (``file:line:col: warning: message``).
///     robot: the robot as it ends the program (with its last ``TOOL``).
#[pyclass(frozen, name = "Plan", module = "kinema")]
struct PyPlan {
    #[pyo3(get)]
    t: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    q: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    qd: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    qdd: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    duration: f64,
    #[pyo3(get)]
    warnings: Vec<String>,
    #[pyo3(get)]
    robot: Py<PyRobot>,
    plan_motions: Vec<PlannedMotion>,
    plan_listing: String,
}

#[pymethods]
impl PyPlan {
    #[getter]
    fn motions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for m in &self.plan_motions {
            let d = PyDict::new(py);
            d.set_item("line", m.line)?;
            d.set_item("kind", &m.kind)?;
            d.set_item("start", m.start)?;
            d.set_item("end", m.end)?;
            d.set_item("profile", &m.profile)?;
            d.set_item("target", &m.target)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The motion plan as text (``kinema compile --listing``): a header, then
    /// one line per motion with its source line, keyword, start and end
    /// time, profile and target.
    fn listing(&self) -> String {
        self.plan_listing.clone()
    }

    fn __len__(&self, py: Python<'_>) -> usize {
        self.t.bind(py).len()
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "Plan({} motion(s), {} samples, duration={:.6} s)",
            self.plan_motions.len(),
            self.t.bind(py).len(),
            self.duration
        )
    }
}

/// Compiles and runs the robot program ``text`` (the kinema language,
/// ``docs/language.md``; seed 003's SCARA statements too) on ``robot``, as
/// ``kinema run`` does: inverse kinematics for every target, a time law per
/// motion, samples every ``dt`` seconds, every sample checked against the
/// limits.
///
/// ``robot``: a :class:`Robot`, or what ``kinema run --robot`` takes (a
/// built-in name or a .toml/.urdf path). ``start``: joint values at the
/// start (array or pose name; default ``home``). ``filename``: the name the
/// diagnostics give the program. ``time_limit``: seconds of computing after
/// which the program is stopped (``None``, the default: no limit); the step
/// and sample limits of ``docs/language.md`` hold either way.
/// ``skip_unreachable``: skip motions to targets out of reach with a warning
/// (seed 003 Fig. 9; ``kinema run --skip-unreachable``) instead of failing.
///
/// The program runs on a worker thread with the GIL released; Ctrl-C
/// (KeyboardInterrupt) stops it within about 50 ms and is raised again here.
///
/// Returns a :class:`Plan`.
///
/// Raises:
///     ProgramError: the program does not compile or run (syntax, names,
///         units, unreachable targets, limit violations, ``time_limit``
///         reached: "stopped here: the time budget of … s ran out"). The message is the
///         report ``kinema run`` prints (``file:line:col: error: …``, the
///         source line underlined, hints); ``.diagnostics`` lists the errors
///         as ``(line, col, message)``.
///     InvalidInput, UnknownRobot, DescriptionError, RobotFileError: a bad
///         ``robot``, ``start`` or ``time_limit``.
///     KeyboardInterrupt: Ctrl-C while the program ran.
#[pyfunction]
#[pyo3(signature = (text, robot, dt=0.01, start=None, filename="<program>", time_limit=None,
    skip_unreachable=false))]
#[allow(clippy::too_many_arguments)]
fn run_program(
    py: Python<'_>,
    text: String,
    robot: &Bound<'_, PyAny>,
    #[pyo3(from_py_with = real)] dt: f64,
    start: Option<&Bound<'_, PyAny>>,
    filename: &str,
    time_limit: Option<&Bound<'_, PyAny>>,
    skip_unreachable: bool,
) -> PyResult<PyPlan> {
    let robot = match robot.downcast::<PyRobot>() {
        Ok(r) => Arc::clone(&r.get().robot),
        Err(_) => {
            let spec: String = robot
                .extract()
                .map_err(|_| invalid("`robot` must be a kinema.Robot, a built-in robot name or a file path".into()))?;
            Arc::new(Robot::load(&spec, None).map_err(to_py)?)
        }
    };
    let start = match start.filter(|s| !s.is_none()) {
        Some(s) => Some(PyRobot::new(Arc::clone(&robot)).joint_vector(s, "start")?),
        None => None,
    };
    let stop = match time_limit.filter(|t| !t.is_none()) {
        Some(t) => {
            let seconds = real(t)?;
            if !(seconds.is_finite() && seconds >= 0.0) {
                return Err(invalid(format!("`time_limit` must be a number of seconds ≥ 0, not {seconds}")));
            }
            kinema_lang::Stop::after(Duration::from_secs_f64(seconds))
        }
        None => kinema_lang::Stop::never(),
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let opts = kinema_lang::Options {
        dt,
        start,
        stop: stop.with_flag(Arc::clone(&cancel)),
        skip_unreachable,
        ..kinema_lang::Options::default()
    };
    let compiled = run_interruptibly(py, &cancel, {
        let text = text.clone();
        move || kinema_lang::compile(&text, &robot, &opts)
    })?;
    match compiled {
        Ok(plan) => {
            let [t, q, qd, qdd] = traj_arrays(py, &plan.trajectory)?;
            Ok(PyPlan {
                t,
                q,
                qd,
                qdd,
                duration: plan.duration(),
                warnings: {
                    let lines = kinema_lang::diag::LineIndex::new(&text);
                    plan.warnings.iter().map(|d| d.one_line_in(filename, &text, &lines)).collect()
                },
                plan_listing: plan.listing(),
                plan_motions: plan.motions,
                robot: Py::new(py, PyRobot::new(Arc::new(plan.robot)))?,
            })
        }
        Err(diags) => {
            let message = kinema_lang::render_all(&diags, filename, &text);
            let mut errors: Vec<_> = diags.iter().filter(|d| d.severity == Severity::Error).collect();
            errors.sort_by_key(|d| d.span.start);
            let lines = kinema_lang::diag::LineIndex::new(&text);
            let list: Vec<(usize, usize, String)> = errors
                .iter()
                .map(|d| {
                    let (line, col) = lines.line_col(&text, d.span.start);
                    (line, col, d.message.clone())
                })
                .collect();
            Err(ProgramError::new_err((message.trim_end().to_string(), list)))
        }
    }
}

/// How often a long computation on a worker thread looks for Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a worker thread with the GIL released, looking for Python signals every
/// [`SIGNAL_POLL`]. On one (KeyboardInterrupt from Ctrl-C, or whatever a handler raises),
/// raises `cancel`, which `work` must watch, waits for it to finish, and returns the error.
fn run_interruptibly<T: Send + 'static>(
    py: Python<'_>,
    cancel: &AtomicBool,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (tx, rx) = std::sync::mpsc::channel();
    // The main thread's usual stack: the compiler's recursion is bounded, not small.
    let worker = std::thread::Builder::new()
        .name("kinema-run_program".into())
        .stack_size(8 << 20)
        .spawn(move || {
            let _ = tx.send(work());
        })
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("cannot start a worker thread: {e}")))?;
    let mut rx = rx;
    loop {
        // The receiver goes into the GIL-free closure and comes back (it is Send, not Sync).
        let (back, received) = py.allow_threads(move || {
            let r = rx.recv_timeout(SIGNAL_POLL);
            (rx, r)
        });
        rx = back;
        match received {
            Ok(out) => {
                let _ = py.allow_threads(|| worker.join());
                return Ok(out);
            }
            Err(RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    cancel.store(true, Ordering::Relaxed);
                    let _ = py.allow_threads(|| worker.join());
                    return Err(e);
                }
            }
            // The worker panicked (a bug): say so rather than hang.
            Err(RecvTimeoutError::Disconnected) => {
                let _ = py.allow_threads(|| worker.join());
                return Err(pyo3::exceptions::PyRuntimeError::new_err(
                    "the program's worker thread stopped without a result",
                ));
            }
        }
    }
}

/// Compiled part of the ``kinema`` package (import ``kinema``, not this).
#[pymodule]
fn _kinema(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRobot>()?;
    m.add_class::<PyIkSolution>()?;
    m.add_class::<PyJointTrajectory>()?;
    m.add_class::<PyTimeLaw>()?;
    m.add_class::<PyPlan>()?;
    m.add_class::<PyCheckReport>()?;
    m.add_class::<cell::PyCell>()?;
    m.add_class::<cell::PyCellReport>()?;
    m.add_function(wrap_pyfunction!(time_law, m)?)?;
    m.add_function(wrap_pyfunction!(run_program, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
