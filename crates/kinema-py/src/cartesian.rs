//! Cartesian motions: `Robot.lin`, `Robot.circ` and their options.

use std::sync::Arc;

use kinema::ik::family::SelfMotionParameter;
use kinema::traj::waypoints::SkippedPoint;
use kinema::traj::{
    check, to_joints, to_joints_at, Blend, CartesianLimits, CartesianMotion, CheckOptions, JointMethod, Orientation,
    Profile, Segment, SelfMotion,
};
use kinema::Pose;
use kinema_io::TrajSummary;
use pyo3::prelude::*;
use pyo3::types::PyString;

use crate::args::{opt_real, parse_rpy, point_arg, pose_arg, push_pose, real, to_numpy, waypoint_arg, waypoint_list};
use crate::errors::{invalid, to_py};
use crate::robot::PyRobot;
use crate::traj::PyJointTrajectory;

/// The self-motion policy of `lin`/`circ`: `q3=` a policy name or an angle,
/// `psi=` "hold" or an angle (the CLI's `--q3`/`--psi`).
fn self_motion_arg<'py>(q3: Option<&Bound<'py, PyAny>>, psi: Option<&Bound<'py, PyAny>>) -> PyResult<SelfMotion> {
    let given = |o: Option<&Bound<'py, PyAny>>| o.filter(|o| !o.is_none()).cloned();
    let (parameter, value) = match (given(q3), given(psi)) {
        (Some(_), Some(_)) => return Err(invalid("give `q3` or `psi`, not both".into())),
        (Some(v), None) => (SelfMotionParameter::Q3, v),
        (None, Some(v)) => (SelfMotionParameter::ArmAngle, v),
        (None, None) => return Ok(SelfMotion::Auto),
    };
    if let Ok(text) = value.extract::<String>() {
        return SelfMotion::parse(parameter, &text, 1.0).map_err(to_py);
    }
    let v = real(&value)?;
    if !v.is_finite() {
        return Err(invalid(format!("invalid `{parameter}`: {v} is not a finite angle")));
    }
    Ok(SelfMotion::Fixed { parameter, value: Some(v) })
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
    text.to_str()?.parse().map_err(to_py)
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
        let method = JointMethod::named(method, self_motion.clone()).map_err(to_py)?;
        if self_motion != SelfMotion::Auto && method == JointMethod::RESOLVED_RATE {
            return Err(invalid("`q3`/`psi` choose the self-motion of method=\"ik\"".into()));
        }
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

impl PyRobot {
    /// Plans the segments `segments(start pose)` from `q0`, converts them to
    /// joints and checks them (what `kinema traj lin|circ` does), without the GIL.
    fn cartesian(
        &self,
        py: Python<'_>,
        q0: Vec<f64>,
        o: CartOptions,
        blend: Blend,
        skipped: &[SkippedPoint],
        segments: impl FnOnce(Pose) -> kinema::Result<Vec<Segment>> + Send,
    ) -> PyResult<PyJointTrajectory> {
        let robot = Arc::clone(&self.robot);
        let profile = o.profile;
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
        let laws = motion.laws();
        let phase_times = if laws.len() == 1 { laws[0].phase_times().to_vec() } else { Vec::new() };
        let summary = TrajSummary::cartesian(&self.robot, &motion, profile, traj.len(), skipped);
        Ok(PyJointTrajectory {
            poses: Some(to_numpy(py, (traj.len(), 4, 4), poses)?.unbind()),
            segment_starts: motion.segment_starts().to_vec(),
            blend_times: motion.blend_times(),
            skipped: skipped.iter().map(|p| p.index).collect(),
            ..PyJointTrajectory::new(py, &traj, motion.duration(), laws[0].profile().name(), phase_times, summary)?
        })
    }
}

#[pymethods]
impl PyRobot {
    /// Straight-line Cartesian motion (LIN, seed 004 §VIII-C) from the tool
    /// pose of ``q0`` to the pose ``T`` (``world_from_tool``), through the
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
        let skipped: Vec<SkippedPoint> = if skip_unreachable {
            let poses: Vec<Pose> = points.iter().map(|p| *p.pose()).collect();
            let (_, skipped) = kinema::traj::waypoints::skip_unreachable(&self.robot, &poses).map_err(to_py)?;
            points = points
                .into_iter()
                .enumerate()
                .filter(|(i, _)| skipped.iter().all(|p| p.index != *i))
                .map(|(_, p)| p)
                .collect();
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
        self.cartesian(py, q0, opts, blend, &skipped, move |start| Segment::lin_chain(&start, &points, orientation))
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
        self.cartesian(py, q0, opts, Blend::None, &[], move |start| Ok(vec![Segment::circ_through(&start, &aux, &to)?]))
    }
}
