//! Joint-space trajectories: `JointTrajectory`, `Robot.ptp` and `Robot.expr`.

use std::sync::Arc;

use kinema::traj::{check, expression_trajectory, CheckOptions, Expr, JointTrajectory, Profile, Ptp, PtpOptions};
use kinema_io::TrajSummary;
use numpy::{PyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::answer::to_python;
use crate::args::{check_shape, f64_array, limit_values, opt_real, real, to_numpy};
use crate::errors::{invalid, to_py};
use crate::program::PyPlan;
use crate::robot::PyRobot;

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
///         (``world_from_tool``) at every sample time, shape (K, 4, 4); ``None``
///         for ``ptp``. Forward kinematics of ``q`` reaches them to 1e-6.
///     segment_starts: start time of each segment [s] (``[0.0]`` for ``ptp``).
///     blend_times: how long each blend between consecutive segments lasts [s].
///     skipped: for ``lin(…, skip_unreachable=True)``, the indices (among ``via``
///         then ``T``) of the waypoints left out as out of reach.
#[pyclass(frozen, name = "JointTrajectory", module = "kinema")]
pub(crate) struct PyJointTrajectory {
    #[pyo3(get)]
    pub(crate) t: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    pub(crate) q: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    pub(crate) qd: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    pub(crate) qdd: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    pub(crate) duration: f64,
    #[pyo3(get)]
    pub(crate) profile: &'static str,
    #[pyo3(get)]
    pub(crate) phase_times: Vec<f64>,
    #[pyo3(get)]
    pub(crate) poses: Option<Py<PyArrayDyn<f64>>>,
    #[pyo3(get)]
    pub(crate) segment_starts: Vec<f64>,
    #[pyo3(get)]
    pub(crate) blend_times: Vec<f64>,
    #[pyo3(get)]
    pub(crate) skipped: Vec<usize>,
    /// What `kinema traj … --json --out FILE` prints for the motion.
    pub(crate) summary: TrajSummary,
}

impl PyJointTrajectory {
    /// The result of a joint-space motion (no planned poses, one segment from 0).
    pub(crate) fn new(
        py: Python<'_>,
        traj: &JointTrajectory,
        duration: f64,
        profile: &'static str,
        phase_times: Vec<f64>,
        summary: TrajSummary,
    ) -> PyResult<Self> {
        let [t, q, qd, qdd] = traj_arrays(py, traj)?;
        Ok(PyJointTrajectory {
            t,
            q,
            qd,
            qdd,
            duration,
            profile,
            phase_times,
            poses: None,
            segment_starts: vec![0.0],
            blend_times: Vec::new(),
            skipped: Vec::new(),
            summary,
        })
    }
}

#[pymethods]
impl PyJointTrajectory {
    /// The motion as ``kinema traj ptp|lin|circ|expr --json --out FILE``
    /// prints it (the samples go to :attr:`t`, :attr:`q`, ...): ``robot``,
    /// ``motion`` (``"ptp"``, ``"cartesian"`` or ``"expression"``),
    /// ``profile``, ``duration``, ``samples``, and the motion's own fields:
    /// ``phase_times`` (ptp; ``None`` between moving states without a common
    /// law) and ``joint_phase_times`` (between moving states),
    /// ``segment_starts``, ``blend_times`` and ``skipped`` (Cartesian), or
    /// ``expressions`` (expression trajectories).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.summary)
    }

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

/// t (K,), q, q̇, q̈ (K, n) of a core trajectory as numpy arrays.
pub(crate) type TrajArrays = [Py<PyArrayDyn<f64>>; 4];

pub(crate) fn traj_arrays(py: Python<'_>, traj: &JointTrajectory) -> PyResult<TrajArrays> {
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

/// `t`, `q`, `qd`, `qdd` of a :class:`JointTrajectory` or :class:`Plan`; None for anything else.
pub(crate) fn sampled_arrays<'py>(obj: &Bound<'py, PyAny>) -> Option<[Bound<'py, PyAny>; 4]> {
    let arrays = if let Ok(tr) = obj.downcast::<PyJointTrajectory>() {
        let tr = tr.get();
        [&tr.t, &tr.q, &tr.qd, &tr.qdd]
    } else if let Ok(plan) = obj.downcast::<PyPlan>() {
        let plan = plan.get();
        [&plan.t, &plan.q, &plan.qd, &plan.qdd]
    } else {
        return None;
    };
    Some(arrays.map(|a| a.bind(obj.py()).clone().into_any()))
}

/// A trajectory from numpy arrays `t` (K,), `q` (K, n) and, when given, `qd`, `qdd`.
pub(crate) fn traj_from_arrays(
    n: usize,
    t: &Bound<'_, PyAny>,
    q: &Bound<'_, PyAny>,
    qd: Option<&Bound<'_, PyAny>>,
    qdd: Option<&Bound<'_, PyAny>>,
) -> PyResult<JointTrajectory> {
    let t = f64_array(t, "t")?;
    check_shape(&t, "t", &[None], " (one time per sample)")?;
    let k = t.len();
    let hint = format!(" (one row of {n} joint values per time in `t`)");
    let rows = |a: &Bound<'_, PyAny>, what: &str| -> PyResult<Vec<f64>> {
        let a = f64_array(a, what)?;
        check_shape(&a, what, &[Some(k), Some(n)], &hint)?;
        Ok(a.as_slice()?.to_vec())
    };
    let q = rows(q, "q")?;
    let qd = qd.map(|a| rows(a, "qd")).transpose()?;
    let qdd = qdd.map(|a| rows(a, "qdd")).transpose()?;
    JointTrajectory::from_samples(n, t.as_slice()?.to_vec(), q, qd, qdd).map_err(to_py)
}

#[pymethods]
impl PyRobot {
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
            let profile = opts.profile;
            let name = profile.name();
            let (plan, traj) = py
                .allow_threads(move || -> kinema::Result<_> {
                    let plan = kinema::traj::BoundaryPtp::new(&robot, &from, &to, &opts, &boundary)?;
                    let traj = plan.sample(&robot, dt)?;
                    Ok((plan, traj))
                })
                .map_err(to_py)?;
            let phase_times = plan.rest().map_or_else(Vec::new, |p| p.law().phase_times().to_vec());
            let summary = TrajSummary::boundary_ptp(&self.robot, &plan, profile, traj.len());
            return PyJointTrajectory::new(py, &traj, plan.duration(), name, phase_times, summary);
        }
        let (plan, traj) = py
            .allow_threads(move || -> kinema::Result<_> {
                let plan = Ptp::new(&robot, &from, &to, &opts)?;
                let traj = plan.sample(&robot, dt)?;
                Ok((plan, traj))
            })
            .map_err(to_py)?;
        let law = plan.law();
        let summary = TrajSummary::ptp(&self.robot, &plan, traj.len());
        PyJointTrajectory::new(py, &traj, plan.duration(), law.profile().name(), law.phase_times().to_vec(), summary)
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
        let q0 = self.optional_joint_vector(q0, "q0")?.unwrap_or_else(|| self.robot.home().to_vec());
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
        let (traj, exprs) = py
            .allow_threads(move || -> kinema::Result<_> {
                let traj = expression_trajectory(&robot, &q0, &exprs, duration, dt)?;
                check(&robot, &traj, &limits)?.into_result()?;
                Ok((traj, exprs))
            })
            .map_err(to_py)?;
        let summary = TrajSummary::expression(&self.robot, &exprs, duration, traj.len());
        let end = traj.times().last().copied().unwrap_or(0.0);
        PyJointTrajectory::new(py, &traj, end, "expression", Vec::new(), summary)
    }
}
