//! Checking a trajectory against the limits: `Robot.check` and `CheckReport`.

use std::sync::Arc;

use kinema::ik::Admissible;
use kinema::traj::{check, CheckOptions, CheckReport};
use kinema_io::CheckAnswer;
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::answer::to_python;
use crate::args::{limit_values, opt_real, real};
use crate::collision::PyScene;
use crate::errors::{invalid, to_py};
use crate::robot::PyRobot;
use crate::traj::{sampled_arrays, traj_from_arrays};

/// What :meth:`Robot.check` found (``kinema traj check --json``).
///
/// Attributes:
///     ok: no violation.
///     samples: number of samples checked.
///     peak_velocity, peak_acceleration, peak_jerk: the largest |q̇|, |q̈|,
///         |q⃛| per joint, shape (n,).
///     min_manipulability: ``(t, value)`` of the smallest manipulability when
///         ``min_manip`` was given, else ``None``.
///     violations: one dict per problem, in sample order (as
///         ``kinema traj check --json`` lists them), with keys ``kind``
///         (``"position"``, ``"velocity"``, ``"acceleration"``, ``"jerk"``,
///         ``"jump"``, ``"inconsistent"``, ``"malformed"``,
///         ``"nearsingular"``), ``t`` [s], ``sample`` (from 0), ``joint``
///         (from 1, ``None`` when no joint is concerned), ``value``, ``limit``
///         and ``message`` (the line ``kinema traj check`` prints).
///     warnings: the same dicts for singular passages (kind ``"singular"``),
///         one per passage.
#[pyclass(frozen, name = "CheckReport", module = "kinema")]
pub(crate) struct PyCheckReport {
    pub(crate) report: CheckReport,
    /// The report as `kinema traj check --json` prints it.
    answer: CheckAnswer,
}

impl PyCheckReport {
    pub(crate) fn new(report: CheckReport) -> Self {
        PyCheckReport { answer: CheckAnswer::new(&report), report }
    }
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
    fn violations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.answer.violations)
    }

    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.answer.warnings)
    }

    /// The report as ``kinema traj check --json`` prints it: ``samples``,
    /// ``ok``, the peaks, ``min_manipulability`` (``{"t", "value"}`` or
    /// ``None``), ``violations`` and ``warnings``.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.answer)
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

#[pymethods]
impl PyRobot {
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
    /// ``scene``: a :class:`Scene`; every configuration of the motion — the
    /// samples and the straight joint steps between them, certified by a
    /// continuous check — must keep the robot clear of itself and the
    /// obstacles (by ``margin`` [m]); each stretch in collision is one
    /// violation of kind ``collision`` at the time it begins, naming the pair.
    ///
    /// Returns a :class:`CheckReport` (a trajectory that breaks a limit is
    /// reported, not raised; see :meth:`CheckReport.raise_if_violations`).
    ///
    /// Raises:
    ///     InvalidInput: arrays of the wrong shape, no samples, bad limits.
    #[pyo3(signature = (t, q=None, qd=None, qdd=None, *, vmax=None, amax=None, jmax=None, min_manip=None,
                        singular=kinema::traj::SINGULAR_WARNING, resolution=0.0, time_resolution=0.0, scene=None,
                        margin=None))]
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
        scene: Option<PyRef<'_, PyScene>>,
        #[pyo3(from_py_with = opt_real)] margin: Option<f64>,
    ) -> PyResult<PyCheckReport> {
        check_resolutions(resolution, time_resolution)?;
        let [q, qd, qdd] = [q, qd, qdd].map(|a| a.filter(|a| !a.is_none()));
        let arrays = sampled_arrays(t);
        if arrays.is_some() && (q.is_some() || qd.is_some() || qdd.is_some()) {
            return Err(invalid("give a trajectory or the arrays `t`, `q` (`qd`, `qdd`), not both".into()));
        }
        let (t, q, qd, qdd) = match &arrays {
            Some([t, q, qd, qdd]) => (t, Some(q), Some(qd), Some(qdd)),
            None => (t, q, qd, qdd),
        };
        let Some(q) = q else {
            return Err(invalid("`q` is missing: give the joint positions, shape (K, n), with the times `t`".into()));
        };
        let traj = traj_from_arrays(self.dof(), t, q, qd, qdd)?;
        let body = self.collision_check_if_asked(scene.as_deref(), margin)?;
        let opts = CheckOptions {
            vel: limit_values(vmax, "vmax")?,
            acc: limit_values(amax, "amax")?,
            jerk: limit_values(jmax, "jmax")?,
            min_manipulability: min_manip,
            singular_warning: (singular != 0.0).then_some(singular),
            value_resolution: resolution,
            time_resolution,
            admissible: body.as_deref().map(|c| c as &dyn Admissible),
            ..CheckOptions::default()
        };
        let robot = Arc::clone(&self.robot);
        let report = py.allow_threads(move || check(&robot, &traj, &opts)).map_err(to_py)?;
        Ok(PyCheckReport::new(report))
    }
}

/// The `resolution` and `time_resolution` of :meth:`Robot.check` and :meth:`Cell.add`: finite and ≥ 0.
pub(crate) fn check_resolutions(resolution: f64, time_resolution: f64) -> PyResult<()> {
    for (what, v) in [("resolution", resolution), ("time_resolution", time_resolution)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(invalid(format!("`{what}` must be a finite number ≥ 0, not {v}")));
        }
    }
    Ok(())
}
