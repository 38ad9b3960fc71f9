//! Inverse kinematics: `Robot.ik`, `Robot.ik_batch`, their arguments and `IkSolution`.

use std::sync::Arc;

use kinema::ik::{
    pick_one, solve_target_with, Admissible, IkRequest, IkTarget, NumericOptions, Solution, SolverChoice, Tolerance,
};
use kinema::RpyConvention;
use kinema_geometry::CollisionCheck;
use kinema_io::SolutionAnswer;
use numpy::ndarray::Array;
use numpy::{IntoPyArray, PyArray1, PyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::PyInt;

use crate::answer::to_python;
use crate::args::{f64_array, opt_real, parse_rpy, pose_arg, real, to_numpy, vec3_arg};
use crate::batch;
use crate::collision::PyScene;
use crate::errors::{invalid, to_py, KinemaError};
use crate::robot::PyRobot;

/// A seed: a non-negative integer below 2**64 (InvalidInput otherwise, not
/// Python's OverflowError).
pub(crate) fn seed_arg(obj: &Bound<'_, PyAny>) -> PyResult<u64> {
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
    name.parse().map_err(to_py)
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
pub(crate) struct PyIkSolution {
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
    /// The solution as `kinema ik --json` lists it.
    answer: SolutionAnswer,
}

#[pymethods]
impl PyIkSolution {
    /// ``(position_error [m], orientation_error [rad])``.
    #[getter]
    fn residual(&self) -> (f64, f64) {
        (self.position_error, self.orientation_error)
    }

    /// The solution as ``kinema ik --json`` lists it: ``q``, ``branch``,
    /// ``within_limits``, ``position_error``, ``orientation_error`` (``None``
    /// for a target that leaves the orientation free) and, for a numeric
    /// solution, ``iterations``, ``restarts`` and ``stop`` (why the search
    /// stopped).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.answer)
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
            answer: SolutionAnswer {
                orientation_error: Some(s.orientation_error).filter(|_| !orientation_free),
                ..SolutionAnswer::new(s)
            },
        }
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
    let any_typed = pitch.is_some() || roll.is_some() || approach.is_some() || alpha.is_some();
    let position = match (T, position) {
        (Some(_), Some(_)) => return Err(invalid("give `T` or `position`, not both".into())),
        (None, None) => {
            return Err(invalid(
                "give a target: `T` (a 4×4 pose or x, y, z, roll, pitch, yaw) or `position` (x, y, z)".into(),
            ))
        }
        (Some(_), None) if any_typed => {
            return Err(invalid("`pitch`/`roll`, `approach` and `alpha` go with `position` (x, y, z), not `T`".into()))
        }
        (Some(t), None) => return pose_arg(t, "T", conv).map(IkTarget::Pose),
        (None, Some(p)) => p,
    };
    let position = vec3_arg(position, "position")?;
    let approach = approach.map(|a| vec3_arg(a, "approach")).transpose()?;
    // The components of a typed target, by name; the core says which target they make.
    let given = [
        ("pitch", pitch.as_ref().map(std::slice::from_ref)),
        ("roll", roll.as_ref().map(std::slice::from_ref)),
        ("alpha", alpha.as_ref().map(std::slice::from_ref)),
        ("approach", approach.as_ref().map(|d| &d[..])),
    ];
    let typed = kinema::ik::registry::typed_target(position, &given).map_err(crate::errors::to_py)?;
    Ok(typed.map_or(IkTarget::Position(position), IkTarget::Typed))
}

/// One request of :meth:`Robot.ik` or :meth:`Robot.ik_dict`, its arguments converted.
struct IkCall {
    target: IkTarget,
    /// The roll-pitch-yaw convention of the target, as given and as answered.
    convention: RpyConvention,
    solver: SolverChoice,
    q0: Option<Vec<f64>>,
    all: bool,
    q3: Option<f64>,
    psi: Option<f64>,
    mask: Option<[bool; 6]>,
    tolerance: Tolerance,
    seed: u64,
    /// The scene's collision check solutions must pass (`scene=`).
    check: Option<Arc<CollisionCheck>>,
}

/// What the solver found for an [`IkCall`]: its answer, and the solutions
/// returned (all of them, or the one `pick_one` picks).
struct IkFound {
    answer: kinema::ik::IkAnswer,
    chosen: Vec<Solution>,
}

impl PyRobot {
    /// Solves `call` without the GIL (core: `ik::solve_target_with`, `ik::pick_one`).
    fn solve_ik(&self, py: Python<'_>, call: &IkCall) -> PyResult<IkFound> {
        let robot = Arc::clone(&self.robot);
        let family = self.family.clone();
        py.allow_threads(move || -> kinema::Result<IkFound> {
            let request = IkRequest {
                solver: call.solver,
                q0: call.q0.as_deref(),
                all: call.all,
                q3: call.q3,
                psi: call.psi,
                mask: call.mask,
                tolerance: call.tolerance,
                numeric: NumericOptions { seed: call.seed, ..Default::default() },
                admissible: call.check.as_deref().map(|c| c as &dyn Admissible),
                ..Default::default()
            };
            let answer = solve_target_with(&robot, family.as_deref(), &call.target, &request)?;
            let chosen = if call.all {
                answer.solutions.clone()
            } else {
                vec![pick_one(&robot, answer.solver, answer.solutions.clone(), call.q0.as_deref())?]
            };
            Ok(IkFound { answer, chosen })
        })
        .map_err(to_py)
    }
}

#[pymethods]
impl PyRobot {
    /// Inverse kinematics: joint values that put the tool at a target, as
    /// ``kinema ik`` finds them (core: ``ik::solve_target``, ``ik::pick_one``).
    ///
    /// The target is one of:
    ///
    /// * ``T``: a full pose ``world_from_tool``, a 4×4 array or 6 numbers
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
    /// ``scene``: a :class:`Scene`; a solution in which the robot collides
    /// with itself or an obstacle (closer than ``margin`` [m], default 0) is
    /// not a solution (``ik_dict`` lists it under ``discarded`` with reason
    /// ``collision``), and a redundant arm searches its self-motion (q3 or ψ)
    /// for a free one before raising Unreachable, as ``kinema ik --scene``.
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
        tol_orientation=1e-6, scene=None, margin=None))]
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
        scene: Option<PyRef<'_, PyScene>>,
        #[pyo3(from_py_with = opt_real)] margin: Option<f64>,
    ) -> PyResult<PyObject> {
        let solver = solver_choice(solver)?;
        let convention = parse_rpy(rpy)?;
        let request = IkCall {
            target: ik_target(T, position, pitch, roll, approach, alpha, convention)?,
            convention,
            solver,
            q0: self.optional_joint_vector(q0, "q0")?,
            all,
            q3,
            psi,
            mask,
            tolerance: Tolerance { position: tol_position, orientation: tol_orientation },
            seed,
            check: self.collision_check_if_asked(scene.as_deref(), margin)?,
        };
        let found = self.solve_ik(py, &request)?;
        let free = request.target.orientation_free();
        let name = found.answer.solver;
        let mut list: Vec<PyIkSolution> = found.chosen.iter().map(|s| PyIkSolution::new(py, s, name, free)).collect();
        if all {
            return Ok(list.into_pyobject(py)?.into_any().unbind());
        }
        match list.pop() {
            Some(one) => Ok(Bound::new(py, one)?.into_any().unbind()),
            None => Err(KinemaError::new_err("the solver returned no solution")),
        }
    }

    /// The answer of ``kinema ik --json`` (``--all`` with ``all=True``) to
    /// the request :meth:`ik` takes, with the same arguments: ``robot``,
    /// ``solver``, ``target`` (a full pose: ``T``, ``position``, ``rpy`` in
    /// the convention ``rpy``, ``quaternion_wxyz``), ``q3``/``psi`` when
    /// given, ``solutions`` (each as :meth:`IkSolution.to_dict`),
    /// ``tolerance``, ``discarded`` (the solver's candidates that miss the
    /// target, and why) and ``folded`` (copies within limits, joints turned
    /// by whole turns, not listed).
    ///
    /// Raises: as :meth:`ik`; :meth:`Unreachable.to_dict` is the CLI's answer
    /// to an unreachable target.
    #[allow(non_snake_case, clippy::too_many_arguments)]
    #[pyo3(signature = (T=None, all=false, q0=None, solver="auto", q3=None, psi=None, seed=0, *, position=None,
        pitch=None, roll=None, approach=None, alpha=None, rpy="zyx", mask=None, tol_position=1e-6,
        tol_orientation=1e-6, scene=None, margin=None))]
    fn ik_dict<'py>(
        &self,
        py: Python<'py>,
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
        scene: Option<PyRef<'_, PyScene>>,
        #[pyo3(from_py_with = opt_real)] margin: Option<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let solver = solver_choice(solver)?;
        let convention = parse_rpy(rpy)?;
        let request = IkCall {
            target: ik_target(T, position, pitch, roll, approach, alpha, convention)?,
            convention,
            solver,
            q0: self.optional_joint_vector(q0, "q0")?,
            all,
            q3,
            psi,
            mask,
            tolerance: Tolerance { position: tol_position, orientation: tol_orientation },
            seed,
            check: self.collision_check_if_asked(scene.as_deref(), margin)?,
        };
        let found = self.solve_ik(py, &request)?;
        let answer = kinema_io::IkAnswer {
            q3,
            psi,
            ..kinema_io::IkAnswer::new(&self.robot, &found.answer, &found.chosen, &request.target, request.convention)
        };
        to_python(py, &answer)
    }

    /// Inverse kinematics of many targets at once, one solution each, solved
    /// exactly as :meth:`ik` would (the same contract, solver choice and pick:
    /// within limits, nearest ``q0`` when given), in parallel over all cores
    /// with the GIL released (core: ``ik::solve_batch``).
    ///
    /// ``T``: a (V, 4, 4) array of poses or (V, 6) rows x, y, z, roll, pitch,
    /// yaw (convention ``rpy``); or ``position``: a (V, 3) array of tool
    /// points, orientation free. ``q0``, ``solver``, ``mask``, ``seed`` and the
    /// tolerances, ``scene`` and ``margin`` as in :meth:`ik`.
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
        tol_position=1e-6, tol_orientation=1e-6, scene=None, margin=None))]
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
        scene: Option<PyRef<'_, PyScene>>,
        #[pyo3(from_py_with = opt_real)] margin: Option<f64>,
    ) -> PyResult<IkBatchResult<'py>> {
        let solver = solver_choice(solver)?;
        let targets = match (T.filter(|t| !t.is_none()), position.filter(|p| !p.is_none())) {
            (Some(t), None) => batch::Targets::poses(f64_array(t, "T")?, parse_rpy(rpy)?)?,
            (None, Some(p)) => batch::Targets::points(f64_array(p, "position")?)?,
            (Some(_), Some(_)) => return Err(invalid("give `T` or `position`, not both".into())),
            (None, None) => return Err(invalid("give the targets: `T` (V poses) or `position` (V points)".into())),
        };
        let q0 = self.optional_joint_vector(q0, "q0")?;
        let check = self.collision_check_if_asked(scene.as_deref(), margin)?;
        let request = IkRequest {
            solver,
            q0: q0.as_deref(),
            mask,
            tolerance: Tolerance { position: tol_position, orientation: tol_orientation },
            numeric: NumericOptions { seed, ..Default::default() },
            admissible: check.as_deref().map(|c| c as &dyn Admissible),
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
}
