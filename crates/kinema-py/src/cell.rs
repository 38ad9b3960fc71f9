//! `kinema.Cell`: several robots in one world on a common clock (seed 004
//! §VIII-E), as `kinema cell` runs them: each robot placed by its base pose
//! (`kinema::traj::cell::placed`), its trajectory checked by the core's
//! `traj::check`, and the core's `traj::Cell` for the common clock, the
//! world tool positions, manipulability and tool distances.

use std::sync::Arc;

use kinema::traj::{check, CheckOptions, CheckReport, JointTrajectory};
use kinema::{Pose, Robot};
use kinema_geometry::{closest_approaches, Body, BodyApproach};
use kinema_io::{CellAnswer, CellMember};
use numpy::{PyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::answer::to_python;
use crate::args::{opt_real, parse_rpy, pose_arg, real, to_numpy};
use crate::check::{check_resolutions, PyCheckReport};
use crate::collision::{PyScene, Source};
use crate::errors::{geometry_to_py, invalid, to_py};
use crate::program::run_program;
use crate::robot::{robot_arg, PyRobot};
use crate::traj::{sampled_arrays, traj_from_arrays};

/// One robot added to a cell.
struct Member {
    name: String,
    /// The robot as given: a built-in name or a file, or the name of a `Robot`.
    spec: String,
    /// Where its own world frame sits in the cell's.
    base: Pose,
    robot: Arc<Robot>,
    /// Where its description (and so its link shapes) comes from.
    source: Source,
    traj: JointTrajectory,
    check: CheckReport,
}

/// Several robots in one world, each with its base pose and its joint
/// trajectory, run on a common clock (``kinema cell``; seed 004 §VIII-E).
///
/// ``dt``: the common clock's sample period [s] (programs are sampled at it
/// too). ``min_distance``: the tools should stay at least this far apart [m]
/// (see :attr:`CellReport.closer_than_minimum` and :attr:`CellReport.ok`).
/// ``scene``: a :class:`Scene` whose obstacles the robots' link shapes are
/// measured against (:attr:`CellReport.bodies`), besides each other.
///
/// Add robots with :meth:`add`, then :meth:`run`. A robot whose trajectory
/// ends before the others holds its last configuration until the end of the
/// clock; between its own samples its joint values are interpolated linearly.
#[pyclass(name = "Cell", module = "kinema")]
pub(crate) struct PyCell {
    members: Vec<Member>,
    /// Obstacles the robots' link shapes are measured against.
    scene: Option<Arc<kinema_geometry::Scene>>,
    #[pyo3(get)]
    dt: f64,
    #[pyo3(get)]
    min_distance: Option<f64>,
}

/// Check options of every member: the robot's limits, singular passages as
/// warnings (as `kinema traj check` and `kinema cell`).
fn check_options(resolution: f64, time_resolution: f64) -> CheckOptions<'static> {
    CheckOptions {
        singular_warning: Some(kinema::traj::SINGULAR_WARNING),
        value_resolution: resolution,
        time_resolution,
        ..CheckOptions::default()
    }
}

#[pymethods]
impl PyCell {
    #[new]
    #[pyo3(signature = (dt=0.01, min_distance=None, scene=None))]
    fn new(
        #[pyo3(from_py_with = real)] dt: f64,
        #[pyo3(from_py_with = opt_real)] min_distance: Option<f64>,
        scene: Option<PyRef<'_, PyScene>>,
    ) -> PyResult<Self> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(invalid(format!("`dt` must be a time > 0 [s], not {dt}")));
        }
        if let Some(d) = min_distance.filter(|d| !(d.is_finite() && *d >= 0.0)) {
            return Err(invalid(format!("`min_distance` must be a finite distance ≥ 0 [m], not {d}")));
        }
        Ok(PyCell { members: Vec::new(), scene: scene.map(|s| Arc::clone(&s.scene)), dt, min_distance })
    }

    /// Adds a robot and its motion; returns the cell (calls chain).
    ///
    /// ``name``: a name unique in the cell (keys of the report's dicts).
    /// ``robot``: a :class:`Robot`, a built-in name or a description path.
    /// ``base``: where the robot's own world frame (the frame of its forward
    /// kinematics) sits in the cell's world: a 4×4 transform or x, y, z [m],
    /// roll, pitch, yaw [rad] in convention ``rpy`` (``"zyx"``: R =
    /// Rz(yaw)·Ry(pitch)·Rx(roll), ``"xyz"``); default the identity.
    ///
    /// The motion, one of:
    ///
    /// * ``trajectory``: a :class:`JointTrajectory` (``ptp``, ``lin``,
    ///   ``circ``, ``expr``) or a :class:`Plan` (``run_program``);
    /// * ``t`` (K,) [s] and ``q`` (K, n), with ``qd``, ``qdd`` optional
    ///   (estimated from ``q`` when absent), e.g. columns of a CSV of
    ///   ``kinema traj``; ``resolution`` and ``time_resolution`` as for
    ///   :meth:`Robot.check`;
    /// * ``program``: a program's text, run as :func:`run_program` runs it
    ///   (``start``, ``filename``, ``time_limit``) on the robot as placed,
    ///   so its Cartesian targets are in the cell's world frame; the robot
    ///   of the cell is then the program's (with its last ``TOOL``).
    ///
    /// The trajectory is checked at once (:meth:`Robot.check` with its
    /// defaults); the report is in :attr:`CellReport.checks`.
    ///
    /// Raises:
    ///     InvalidInput: a name used twice, no motion or two, arrays of the
    ///         wrong shape, a trajectory for another number of joints.
    ///     ProgramError: the program does not run.
    #[pyo3(signature = (name, robot, trajectory=None, *, base=None, rpy="zyx", t=None, q=None, qd=None, qdd=None,
                        resolution=0.0, time_resolution=0.0, program=None, start=None, filename=None, time_limit=None))]
    #[allow(clippy::too_many_arguments)]
    fn add<'py>(
        mut slf: PyRefMut<'py, Self>,
        py: Python<'py>,
        name: String,
        robot: &Bound<'py, PyAny>,
        trajectory: Option<&Bound<'py, PyAny>>,
        base: Option<&Bound<'py, PyAny>>,
        rpy: &str,
        t: Option<&Bound<'py, PyAny>>,
        q: Option<&Bound<'py, PyAny>>,
        qd: Option<&Bound<'py, PyAny>>,
        qdd: Option<&Bound<'py, PyAny>>,
        #[pyo3(from_py_with = real)] resolution: f64,
        #[pyo3(from_py_with = real)] time_resolution: f64,
        program: Option<String>,
        start: Option<&Bound<'py, PyAny>>,
        filename: Option<String>,
        time_limit: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        if name.is_empty() {
            return Err(invalid("`name` must not be empty".into()));
        }
        if slf.members.iter().any(|m| m.name == name) {
            return Err(invalid(format!("`{name}` names two robots of the cell")));
        }
        check_resolutions(resolution, time_resolution)?;
        let spec: Option<String> = robot.extract().ok();
        let source = Source::of(robot);
        let robot = robot_arg(robot)?;
        let spec = spec.unwrap_or_else(|| robot.name().to_string());
        let conv = parse_rpy(rpy)?;
        let world_from_robot = match base.filter(|b| !b.is_none()) {
            Some(b) => pose_arg(b, "base", conv)?,
            None => Pose::IDENTITY,
        };
        let placed = Arc::new(kinema::traj::cell::placed(&robot, &world_from_robot).map_err(to_py)?);
        let n = placed.dof();
        let trajectory = trajectory.filter(|x| !x.is_none());
        let (t, q) = (t.filter(|x| !x.is_none()), q.filter(|x| !x.is_none()));
        let given = [trajectory.is_some(), t.is_some() || q.is_some(), program.is_some()];
        if given.iter().filter(|g| **g).count() != 1 {
            return Err(invalid(format!(
                "robot `{name}`: give one motion: `trajectory` (a JointTrajectory or Plan), the arrays `t` and `q`, \
                 or a `program`"
            )));
        }
        if start.is_some_and(|s| !s.is_none()) && program.is_none() {
            return Err(invalid(format!("robot `{name}`: `start` is for a program")));
        }
        let opts = check_options(resolution, time_resolution);
        let (robot, traj) = if let Some(text) = program {
            let placed_py = Bound::new(py, PyRobot::new(Arc::clone(&placed), source.clone()))?;
            let filename = filename.unwrap_or_else(|| format!("<program of {name}>"));
            let plan =
                run_program(py, text, placed_py.as_any(), slf.dt, start, &filename, time_limit, false, None, None)?;
            let robot = Arc::clone(&plan.robot.get().robot);
            let traj = traj_from_arrays(
                n,
                plan.t.bind(py).as_any(),
                plan.q.bind(py).as_any(),
                Some(plan.qd.bind(py).as_any()),
                Some(plan.qdd.bind(py).as_any()),
            )?;
            (robot, traj)
        } else if let Some(tr) = trajectory {
            let Some([t, q, qd, qdd]) = sampled_arrays(tr) else {
                return Err(invalid(format!(
                    "robot `{name}`: `trajectory` must be a JointTrajectory or a Plan; give arrays as `t=` and `q=`"
                )));
            };
            (placed, traj_from_arrays(n, &t, &q, Some(&qd), Some(&qdd))?)
        } else {
            let (Some(t), Some(q)) = (t, q) else {
                return Err(invalid(format!("robot `{name}`: give both `t` (K,) and `q` (K, {n})")));
            };
            (placed, traj_from_arrays(n, t, q, qd.filter(|x| !x.is_none()), qdd.filter(|x| !x.is_none()))?)
        };
        let check_robot = Arc::clone(&robot);
        let (traj, check) =
            py.allow_threads(move || check(&check_robot, &traj, &opts).map(|c| (traj, c))).map_err(to_py)?;
        if traj.is_empty() {
            return Err(invalid(format!("robot `{name}`: the trajectory has no sample")));
        }
        slf.members.push(Member { name, spec, base: world_from_robot, robot, source, traj, check });
        Ok(slf)
    }

    /// The names of the robots, in the order they were added.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.members.iter().map(|m| m.name.clone()).collect()
    }

    fn __len__(&self) -> usize {
        self.members.len()
    }

    /// Runs every robot on the common clock, from 0 to the end of the
    /// longest trajectory every ``dt`` seconds; returns a :class:`CellReport`.
    ///
    /// Raises:
    ///     InvalidInput: no robot, or too many samples.
    fn run(&self, py: Python<'_>) -> PyResult<PyCellReport> {
        let mut cell = kinema::traj::Cell::new();
        for m in &self.members {
            cell.add(m.name.clone(), (*m.robot).clone(), m.traj.clone()).map_err(to_py)?;
        }
        let dt = self.dt;
        let report = py.allow_threads(move || cell.run(dt)).map_err(to_py)?;
        let bodies = self.bodies(py)?;
        let approaches =
            py.allow_threads(|| closest_approaches(&bodies, &report.times, &report.q)).map_err(geometry_to_py)?;
        PyCellReport::new(py, self, &report, &approaches)
    }

    fn __repr__(&self) -> String {
        format!("Cell({} robot(s), dt={} s)", self.members.len(), self.dt)
    }
}

impl PyCell {
    /// Every robot with its link shapes and the scene's obstacles. A robot
    /// has none when its description has none, and none with a warning when
    /// a mesh of it cannot be read (`ROS_PACKAGE_PATH` is searched, as by
    /// ``kinema cell``).
    fn bodies(&self, py: Python<'_>) -> PyResult<Vec<Body>> {
        let mut bodies = Vec::with_capacity(self.members.len());
        for m in &self.members {
            let (geometry, skipped) = m.source.shapes_or_none(&m.robot).map_err(geometry_to_py)?;
            if let Some(e) = skipped {
                let message = format!("robot `{}`: no link distances for it: {e}", m.name);
                PyErr::warn(
                    py,
                    &py.get_type::<pyo3::exceptions::PyUserWarning>(),
                    &std::ffi::CString::new(message)?,
                    1,
                )?;
            }
            let body = Body::new(&m.name, (*m.robot).clone(), geometry, self.scene.as_deref());
            bodies.push(body.map_err(geometry_to_py)?);
        }
        Ok(bodies)
    }
}

/// What :meth:`Cell.run` computed (``kinema cell``'s CSV and JSON).
///
/// Attributes:
///     names: the robots, in the order they were added.
///     t: the common clock's sample times, shape (K,) [s].
///     duration: the last sample time [s].
///     q: per robot name, its joint values at each time, shape (K, n).
///     tool_positions: per name, its tool point in the cell's world frame,
///         shape (K, 3) [m].
///     manipulability: per name, its translational manipulability
///         (Yoshikawa on the linear-velocity rows, seed 004 Fig. 30/33), (K,).
///     ends: per name, the time its own trajectory ends [s]; it holds its
///         last configuration after it.
///     distances: per pair ``(a, b)`` (in the order added), the distance
///         between their tool points, shape (K,) [m].
///     closest: per pair, ``(t, distance)`` of the closest approach (the
///         first sample at the smallest distance).
///     closer_than_minimum: per pair, the spans ``(from, to)`` [s] of the
///         samples closer than the cell's ``min_distance`` (empty lists when
///         it has none).
///     checks: per name, the :class:`CheckReport` of its trajectory.
///     min_distance: the cell's minimum distance, or ``None``.
///     ok: no robot's check found a violation, no pair of tools came closer
///         than ``min_distance`` and no two bodies touch.
///     bodies: how close the robots' link shapes come to each other and to
///         the cell's ``scene`` (between samples too, within 1e-4 m): the
///         ``bodies`` list of :meth:`to_dict`, each with ``robots``,
///         ``closest`` (``t``, ``distance``), ``links`` and ``ok``.
#[pyclass(frozen, name = "CellReport", module = "kinema")]
pub(crate) struct PyCellReport {
    #[pyo3(get)]
    names: Vec<String>,
    #[pyo3(get)]
    t: Py<PyArrayDyn<f64>>,
    #[pyo3(get)]
    duration: f64,
    #[pyo3(get)]
    q: Py<PyDict>,
    #[pyo3(get)]
    tool_positions: Py<PyDict>,
    #[pyo3(get)]
    manipulability: Py<PyDict>,
    #[pyo3(get)]
    ends: Py<PyDict>,
    #[pyo3(get)]
    distances: Py<PyDict>,
    #[pyo3(get)]
    closest: Py<PyDict>,
    #[pyo3(get)]
    closer_than_minimum: Py<PyDict>,
    #[pyo3(get)]
    checks: Py<PyDict>,
    #[pyo3(get)]
    min_distance: Option<f64>,
    #[pyo3(get)]
    ok: bool,
    /// What `kinema cell --json` prints for the cell.
    answer: CellAnswer,
}

impl PyCellReport {
    fn new(py: Python<'_>, cell: &PyCell, r: &kinema::traj::CellReport, approaches: &[BodyApproach]) -> PyResult<Self> {
        let k = r.times.len();
        let [q, tool_positions, manipulability, ends, distances, closest, closer, checks] =
            std::array::from_fn(|_| PyDict::new(py));
        for (m, member) in cell.members.iter().enumerate() {
            let n = member.robot.dof();
            let name = &member.name;
            q.set_item(name, to_numpy(py, (k, n), r.q[m].concat())?)?;
            let p: Vec<f64> = r.tools[m].iter().flat_map(|p| [p.pos.x, p.pos.y, p.pos.z]).collect();
            tool_positions.set_item(name, to_numpy(py, (k, 3), p)?)?;
            manipulability.set_item(name, to_numpy(py, k, r.manipulability[m].clone())?)?;
            ends.set_item(name, r.ends[m])?;
            checks.set_item(name, Py::new(py, PyCheckReport::new(member.check.clone()))?)?;
        }
        for ((i, j), d) in &r.distances {
            let key = PyTuple::new(py, [&cell.members[*i].name, &cell.members[*j].name])?;
            distances.set_item(&key, to_numpy(py, k, d.clone())?)?;
            if let Some(c) = r.closest(*i, *j) {
                closest.set_item(&key, c)?;
            }
            let spans = match cell.min_distance {
                Some(min) => r.closer_than(*i, *j, min),
                None => Vec::new(),
            };
            closer.set_item(&key, spans)?;
        }
        let members: Vec<CellMember<'_>> = cell
            .members
            .iter()
            .map(|m| CellMember {
                name: &m.name,
                robot: &m.spec,
                dof: m.robot.dof(),
                trajectory: None,
                program: None,
                base: &m.base,
                check: &m.check,
            })
            .collect();
        let names: Vec<&str> = cell.members.iter().map(|m| m.name.as_str()).collect();
        let answer = CellAnswer::new(None, cell.dt, cell.min_distance, &members, r).with_bodies(&names, approaches);
        let ok = answer.ok;
        Ok(PyCellReport {
            answer,
            names: cell.members.iter().map(|m| m.name.clone()).collect(),
            t: to_numpy(py, k, r.times.clone())?.unbind(),
            duration: r.times.last().copied().unwrap_or(0.0),
            q: q.unbind(),
            tool_positions: tool_positions.unbind(),
            manipulability: manipulability.unbind(),
            ends: ends.unbind(),
            distances: distances.unbind(),
            closest: closest.unbind(),
            closer_than_minimum: closer.unbind(),
            checks: checks.unbind(),
            min_distance: cell.min_distance,
            ok,
        })
    }
}

#[pymethods]
impl PyCellReport {
    /// The cell's answer as ``kinema cell --json`` prints it (without the
    /// ``file`` a cell file gives): ``duration``, ``dt``, ``samples``,
    /// ``min_distance``, ``ok``, per robot (``robots``) its name, robot,
    /// dof, ``base`` placement (``xyz``, zyx ``rpy``), ``end``, ``check`` (as
    /// :meth:`CheckReport.to_dict`) and manipulability extremes, and per
    /// pair (``pairs``) the closest approach and, with a minimum distance,
    /// ``ok`` and ``closer_than_minimum``.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.answer)
    }

    #[getter]
    fn bodies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.answer.bodies)
    }

    fn __len__(&self, py: Python<'_>) -> usize {
        self.t.bind(py).len()
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!(
            "CellReport({} robot(s), {} samples, duration={:.6} s, ok={})",
            self.names.len(),
            self.t.bind(py).len(),
            self.duration,
            if self.ok { "True" } else { "False" }
        ))
    }
}
