//! `Robot.plan`: a collision-free motion (`kinema plan`), as a timed
//! trajectory whose `to_dict()["plan"]` holds the path and the search's counts.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use kinema::traj::{Profile, PtpOptions};
use kinema_geometry::plan::{plan, Goal, PlanOptions};
use kinema_io::{PlanAnswer, TrajSummary};
use pyo3::prelude::*;

use crate::args::{limit_values, opt_real, parse_rpy, pose_arg, real};
use crate::collision::PyScene;
use crate::errors::{geometry_to_py, invalid, to_py, PlanningError};
use crate::ik::seed_arg;
use crate::program::run_interruptibly;
use crate::robot::PyRobot;
use crate::traj::PyJointTrajectory;

#[pymethods]
impl PyRobot {
    /// A motion from ``q0`` that does not collide with the robot itself or
    /// ``scene``'s obstacles (closer than ``margin`` counts), to the
    /// configuration ``qf`` or to any collision-free IK solution of ``pose``
    /// (a 4×4 array, an SE3, or x, y, z, roll, pitch, yaw in ``rpy``): the
    /// straight segment when it is free, else RRT-Connect (``seed``;
    /// ``time_limit`` seconds, ``max_iterations``, ``step``: the trees' longest
    /// step, default a fifth of the joint-limit box's diagonal), shortened, and timed with
    /// one PTP per segment at rest at each via point (``profile``, ``speed``,
    /// ``vmax``/``amax``/``jmax``: one value or one per joint, default the robot's,
    /// sampled every ``dt`` s) — ``kinema plan``. Ctrl-C stops it
    /// (KeyboardInterrupt).
    ///
    /// Returns a :class:`JointTrajectory`; ``to_dict()["plan"]`` has the
    /// ``via_points``, ``iterations``, ``planning_time`` and the check counts.
    ///
    /// Raises:
    ///     InvalidInput: bad joint vectors or options; a start or goal that
    ///         collides (the message names the pair); both or neither of
    ///         ``qf`` and ``pose``.
    ///     Unreachable: no collision-free configuration reaches ``pose``.
    ///     PlanningError: the budget ran out before a path was found (or the
    ///         final exact check refused the path, a defect to report).
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (q0, qf=None, *, pose=None, scene=None, margin=0.0, seed=0, time_limit=1.0,
        max_iterations=100_000, step=None, dt=0.01, profile=None, speed=1.0, vmax=None, amax=None, jmax=None,
        rpy="zyx"))]
    fn plan(
        &self,
        py: Python<'_>,
        q0: &Bound<'_, PyAny>,
        qf: Option<&Bound<'_, PyAny>>,
        pose: Option<&Bound<'_, PyAny>>,
        scene: Option<PyRef<'_, PyScene>>,
        #[pyo3(from_py_with = real)] margin: f64,
        #[pyo3(from_py_with = seed_arg)] seed: u64,
        #[pyo3(from_py_with = real)] time_limit: f64,
        max_iterations: usize,
        #[pyo3(from_py_with = opt_real)] step: Option<f64>,
        #[pyo3(from_py_with = real)] dt: f64,
        profile: Option<&str>,
        #[pyo3(from_py_with = real)] speed: f64,
        vmax: Option<&Bound<'_, PyAny>>,
        amax: Option<&Bound<'_, PyAny>>,
        jmax: Option<&Bound<'_, PyAny>>,
        rpy: &str,
    ) -> PyResult<PyJointTrajectory> {
        let from = self.joint_vector(q0, "q0")?;
        let goal = match (qf, pose) {
            (Some(q), None) => Goal::Joints(self.joint_vector(q, "qf")?),
            (None, Some(p)) => Goal::Pose(pose_arg(p, "pose", parse_rpy(rpy)?)?),
            _ => return Err(invalid("give the goal as qf (a configuration) or pose=, not both".into())),
        };
        if !(time_limit > 0.0 && time_limit <= 86_400.0) {
            return Err(invalid(format!("time_limit = {time_limit}: expected seconds in (0, 86400]")));
        }
        let ptp = PtpOptions {
            profile: match profile {
                Some(name) => name.parse::<Profile>().map_err(to_py)?,
                None => kinema::traj::default_profile(&self.robot),
            },
            speed,
            vel: limit_values(vmax, "vmax")?,
            acc: limit_values(amax, "amax")?,
            jerk: limit_values(jmax, "jmax")?,
            ..PtpOptions::for_robot(&self.robot)
        };
        let profile_name = ptp.profile.name();
        kinema::traj::via::check_timing(&self.robot, &from, &ptp, dt).map_err(to_py)?;
        let check = self.collision_check(scene.as_deref(), margin)?;
        let cancel = Arc::new(AtomicBool::new(false));
        let stop = Arc::clone(&cancel);
        let planned = run_interruptibly(py, &cancel, move || {
            let options = PlanOptions {
                seed,
                time_limit: Duration::from_secs_f64(time_limit),
                max_iterations,
                step,
                cancel: Some(&stop),
                ..Default::default()
            };
            let found = plan(&check, &from, &goal, &options)?;
            let traj = found.trajectory(check.robot(), &ptp, dt)?;
            kinema::traj::collision_free(&traj, check.as_ref())?;
            Ok::<_, kinema_geometry::Error>((found, traj))
        })?;
        let (found, traj) = planned.map_err(|e| match e {
            kinema_geometry::Error::NoPath { .. } | kinema_geometry::Error::Uncertified { .. } => {
                PlanningError::new_err(e.to_string())
            }
            kinema_geometry::Error::Blocked { .. } => invalid(e.to_string()),
            other => geometry_to_py(other),
        })?;
        let duration = traj.times().last().copied().unwrap_or(0.0);
        let summary = TrajSummary {
            plan: Some(PlanAnswer::new(&found)),
            ..TrajSummary::new(&self.robot, "plan", Some(profile_name), duration, traj.len())
        };
        PyJointTrajectory::new(py, &traj, duration, profile_name, Vec::new(), summary)
    }
}
