//! The robot language: `run_program` and the `Plan` it returns.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::sync::Arc;
use std::time::Duration;

use kinema_io::ProgramAnswer;
use kinema_lang::Severity;
use numpy::{PyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::answer::to_python;
use crate::args::{opt_real, real};
use crate::collision::{PyScene, Source};
use crate::errors::{invalid, to_py, ProgramError};
use crate::robot::{robot_arg, PyRobot};
use crate::traj::traj_arrays;

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
///         (as ``kinema compile --json`` prints them; :meth:`to_dict`).
///     warnings: the program's warnings, one line each
///         (``file:line:col: warning: message``).
///     robot: the robot as it ends the program (with its last ``TOOL``).
#[pyclass(frozen, name = "Plan", module = "kinema")]
pub(crate) struct PyPlan {
    #[pyo3(get)]
    pub(crate) t: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    pub(crate) q: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    pub(crate) qd: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    pub(crate) qdd: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    pub(crate) robot: Py<PyRobot>,
    /// What `kinema run --json` prints for the program.
    answer: ProgramAnswer,
    plan_listing: String,
}

#[pymethods]
impl PyPlan {
    #[getter]
    fn duration(&self) -> f64 {
        self.answer.duration
    }

    #[getter]
    fn motions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.answer.motions)
    }

    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.answer.warnings.clone()
    }

    /// The program's answer as ``kinema run --json`` prints it (the
    /// samples go to :attr:`t`, :attr:`q`, ...): ``robot``, ``duration``,
    /// ``samples``, ``motions``, ``final_q``, ``final_pose`` (the tool pose at
    /// the end, zyx roll-pitch-yaw) and ``warnings``.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.answer)
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
            self.answer.motions.len(),
            self.t.bind(py).len(),
            self.answer.duration
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
/// ``scene``: a :class:`Scene`; a motion in which the robot collides with
/// itself or an obstacle (closer than ``margin`` [m]) is an error at its
/// line (``kinema run --scene``).
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
    skip_unreachable=false, scene=None, margin=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_program(
    py: Python<'_>,
    text: String,
    robot: &Bound<'_, PyAny>,
    #[pyo3(from_py_with = real)] dt: f64,
    start: Option<&Bound<'_, PyAny>>,
    filename: &str,
    time_limit: Option<&Bound<'_, PyAny>>,
    skip_unreachable: bool,
    scene: Option<PyRef<'_, PyScene>>,
    #[pyo3(from_py_with = opt_real)] margin: Option<f64>,
) -> PyResult<PyPlan> {
    let source = Source::of(robot);
    let robot = robot_arg(robot)?;
    let given = PyRobot::new(Arc::clone(&robot), source.clone());
    let start = start.filter(|s| !s.is_none()).map(|s| given.joint_vector(s, "start")).transpose()?;
    let collision = given.collision_check_if_asked(scene.as_deref(), margin)?;
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
        planner: collision.clone().map(|c| kinema_io::ScenePlanner::shared(c, Some(Arc::clone(&cancel)))),
        admissible: collision.map(|c| c as Arc<dyn kinema::ik::Admissible>),
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
                answer: ProgramAnswer::new(&plan, filename, &text).map_err(to_py)?,
                plan_listing: plan.listing(),
                robot: Py::new(py, PyRobot::new(Arc::new(plan.robot), source))?,
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
pub(crate) fn run_interruptibly<T: Send + 'static>(
    py: Python<'_>,
    cancel: &AtomicBool,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (tx, rx) = std::sync::mpsc::channel();
    // The main thread's usual stack: the compiler's recursion is bounded, not small.
    let worker = std::thread::Builder::new()
        .name("kinema-worker".into())
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
                return Err(pyo3::exceptions::PyRuntimeError::new_err("the worker thread stopped without a result"));
            }
        }
    }
}
