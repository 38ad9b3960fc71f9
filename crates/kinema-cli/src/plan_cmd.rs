//! `kinema plan`: a collision-free joint motion from a configuration to a
//! configuration or a tool pose, around the robot itself and a scene's
//! obstacles (`kinema_geometry::plan`), timed within the joint limits and
//! written as a trajectory that `kinema traj check --scene` accepts.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{bail, Context, Result};
use clap::Args;
use kinema::traj::{JointTrajectory, Profile, PtpOptions};
use kinema::{Robot, RpyConvention};
use kinema_geometry::plan::{check_with_other_held, plan, time_against, CellRobot, Goal, PlanOptions};
use kinema_geometry::{ros_package_path, CollisionCheck, RobotGeometry, Scene, SceneRobot, UrdfOptions};
use kinema_io::{PlanAnswer, TrajSummary};

use crate::{Exit, RobotArg};

#[derive(Args)]
pub struct PlanArgs {
    #[command(flatten)]
    robot: RobotArg,
    #[command(flatten)]
    body: crate::BodyArgs,
    /// Start configuration: comma-separated values or a named pose.
    #[arg(long, allow_hyphen_values = true)]
    from: String,
    /// Goal configuration: comma-separated values or a named pose.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "pose", required_unless_present = "pose")]
    to: Option<String>,
    /// Goal tool pose x,y,z,roll,pitch,yaw [m, rad]: any collision-free IK solution (every branch, and
    /// samples of a redundant arm's self-motion).
    #[arg(long, allow_hyphen_values = true)]
    pose: Option<String>,
    /// Roll-pitch-yaw convention of --pose and of the written pose columns.
    #[arg(long, default_value = "zyx", value_parser = crate::by_name::<kinema::RpyConvention>())]
    rpy: RpyConvention,
    /// Joint values in degrees (--pose stays in radians, as in `kinema traj lin`).
    #[arg(long)]
    deg: bool,
    /// Seed of the search: the same seed gives the same path when the search ends within its budget.
    #[arg(long, value_parser = crate::seed, default_value = "0")]
    seed: u64,
    /// Planning time budget [s].
    #[arg(long, default_value_t = 1.0)]
    time_limit: f64,
    /// Search iterations before giving up.
    #[arg(long, default_value_t = 100_000)]
    iterations: usize,
    /// Longest step of the search trees [joint-space norm; default: a fifth of the joint-limit box's diagonal].
    #[arg(long)]
    step: Option<f64>,
    /// Random shortcut attempts on the found path.
    #[arg(long, default_value_t = 100)]
    shortcuts: usize,
    /// The time law of each segment [default: trapezoid, or scurve for a robot with jerk limits].
    #[arg(long, value_parser = crate::by_name::<Profile>())]
    profile: Option<Profile>,
    #[command(flatten)]
    limits: crate::traj_cmd::TimingLimits,
    /// Velocity override in percent (1–100): velocity ×k, acceleration ×k², jerk ×k³.
    #[arg(long, default_value_t = 100.0)]
    speed: f64,
    /// Sample period [s].
    #[arg(long, default_value_t = 0.01)]
    dt: f64,
    /// Write the samples as CSV (the columns of `kinema traj ptp`; `-` for standard output).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print a JSON summary with the path and the search's counts.
    #[arg(long)]
    json: bool,
    /// A cell file (as for `kinema cell`): --robot names one of its robots, which is planned while
    /// another one moves along --other-trajectory. (With the others held at their `start`, give the
    /// file as --scene instead.)
    #[arg(long, value_name = "FILE", requires = "other_trajectory", conflicts_with_all = ["scene", "srdf", "margin"])]
    cell: Option<PathBuf>,
    /// The other robot's joint trajectory (CSV, t, q1..qn, …) on whose time base the planned robot is
    /// timed: the path avoids it held at its first and last sample, and the planned robot waits at via
    /// points while it passes.
    #[arg(long, value_name = "FILE", requires = "cell")]
    other_trajectory: Option<PathBuf>,
    /// The cell robot that moves along --other-trajectory (default: the only other one).
    #[arg(long, value_name = "NAME", requires = "cell")]
    other: Option<String>,
    /// With --other-trajectory: how close [m] the two robots' link shapes may come.
    #[arg(long, default_value_t = 0.01, requires = "cell")]
    clearance: f64,
}

pub fn run(a: PlanArgs) -> Result<()> {
    if !(a.time_limit > 0.0 && a.time_limit <= 86_400.0) {
        bail!("--time-limit {}: expected seconds in (0, 86400]", a.time_limit);
    }
    if !(a.speed > 0.0 && a.speed <= 100.0) {
        bail!("--speed {}: the override must be a percentage in (0, 100]", a.speed);
    }
    let crossing = match (&a.cell, &a.other_trajectory) {
        (Some(cell), Some(trajectory)) => {
            Some(Crossing::load(cell, &a.robot.robot, a.other.as_deref(), trajectory, a.clearance)?)
        }
        _ => None,
    };
    let check = match &crossing {
        Some(c) => c.check()?,
        None => a.body.load(&a.robot)?,
    };
    let robot = check.robot();
    let from = robot.parse_q(&a.from, a.deg)?;
    let goal = match (&a.to, &a.pose) {
        (Some(to), _) => Goal::Joints(robot.parse_q(to, a.deg)?),
        (None, Some(pose)) => Goal::Pose(crate::traj_cmd::pose_arg(pose, a.rpy, "pose")?),
        (None, None) => unreachable!("clap requires --to or --pose"),
    };
    let given = PtpOptions {
        profile: a.profile.unwrap_or_else(|| kinema::traj::default_profile(robot)),
        speed: a.speed / 100.0,
        ..PtpOptions::for_robot(robot)
    };
    let ptp = a.limits.apply(robot, a.deg, given)?;
    kinema::traj::via::check_timing(robot, &from, &ptp, a.dt)?;
    let cancel = crate::interrupt::flag();
    let options = PlanOptions {
        seed: a.seed,
        time_limit: Duration::from_secs_f64(a.time_limit),
        max_iterations: a.iterations,
        step: a.step,
        shortcut_rounds: a.shortcuts,
        cancel: Some(&cancel),
        ..Default::default()
    };
    let cancellable = crate::interrupt::cancellable();
    let found = match plan(&check, &from, &goal, &options) {
        Err(kinema_geometry::Error::Interrupted) => {
            eprintln!("interrupted; nothing written");
            return Err(Exit(crate::interrupt::EXIT_INTERRUPTED).into());
        }
        other => other?,
    };
    drop(cancellable);
    let traj = match &crossing {
        Some(c) => c.time(&found.path, &ptp, a.dt)?,
        None => found.trajectory(robot, &ptp, a.dt)?,
    };
    // The samples as written pass the same checks as `kinema traj check --scene`.
    kinema::traj::check(robot, &traj, &Default::default())?.into_result()?;
    kinema::traj::collision_free(&traj, &check)?;
    eprintln!(
        "planned in {:.1} ms: {} via points ({} found), {} iterations, {} goal configuration(s)",
        found.elapsed.as_secs_f64() * 1e3,
        found.path.len(),
        found.found_via_points,
        found.iterations,
        found.goals
    );
    let duration = traj.times().last().copied().unwrap_or(0.0);
    let summary = TrajSummary {
        plan: Some(PlanAnswer::new(&found)),
        ..TrajSummary::new(robot, "plan", Some(ptp.profile.name()), duration, traj.len())
    };
    crate::traj_cmd::emit(robot, &traj, a.rpy, a.out.as_deref(), a.json, summary)
}

/// `--cell … --other-trajectory`: one cell robot planned while another
/// moves, the path avoiding the other held at both ends of its motion and
/// then timed on its clock (`kinema_geometry::plan::time_against`).
struct Crossing {
    scene: Scene,
    me: SceneRobot,
    other: SceneRobot,
    other_robot: (Robot, RobotGeometry),
    other_motion: JointTrajectory,
    clearance: f64,
    urdf: UrdfOptions,
}

impl Crossing {
    fn load(cell: &Path, me: &str, other: Option<&str>, trajectory: &Path, clearance: f64) -> Result<Crossing> {
        if !(clearance >= 0.0 && clearance.is_finite()) {
            bail!("--clearance {clearance}: expected a distance ≥ 0 m");
        }
        let scene = Scene::load(cell)?;
        let names = || scene.robots.iter().map(|r| r.name.as_str()).collect::<Vec<_>>().join(", ");
        let Some(me) = scene.member(me).cloned() else {
            bail!("{}: --robot `{me}` is none of the cell's robots ({})", cell.display(), names());
        };
        let others: Vec<&SceneRobot> = scene.robots.iter().filter(|r| r.name != me.name).collect();
        let other = match (other, others.as_slice()) {
            (Some(name), _) => match others.iter().find(|r| r.name == name) {
                Some(r) => (*r).clone(),
                None => bail!("{}: --other `{name}` is none of the cell's other robots ({})", cell.display(), names()),
            },
            (None, [only]) => (*only).clone(),
            (None, _) => bail!("{}: name the moving robot with --other (one of {})", cell.display(), names()),
        };
        let urdf = UrdfOptions { package_paths: ros_package_path(), skip_visual: true, tip: None };
        let other_robot = other.load(&urdf)?;
        let (other_motion, _) = crate::traj_cmd::read_trajectory_with_resolution(&other_robot.0, trajectory)
            .with_context(|| format!("--other-trajectory for `{}`", other.name))?;
        Ok(Crossing { scene, me, other, other_robot, other_motion, clearance, urdf })
    }

    /// The planned robot's check: self-collision, the cell's obstacles, the
    /// other robots at their `start`, and the moving one held at the first
    /// and the last sample of its motion (`NAME` and `NAME@end`).
    fn check(&self) -> Result<CollisionCheck> {
        let motion = &self.other_motion;
        let ends = (motion.q(0), motion.q(motion.len() - 1));
        Ok(check_with_other_held(&self.scene, &self.me.name, &self.other.name, ends, &self.urdf)?)
    }

    /// `path` timed on the other robot's clock.
    fn time(&self, path: &[Vec<f64>], options: &PtpOptions, dt: f64) -> Result<JointTrajectory> {
        let (robot, geometry) = self.me.load(&self.urdf)?;
        let me = CellRobot { name: &self.me.name, robot: &robot, geometry: &geometry };
        let (other_robot, other_geometry) = &self.other_robot;
        let other = CellRobot { name: &self.other.name, robot: other_robot, geometry: other_geometry };
        let timed = time_against(me, path, options, dt, other, &self.other_motion, self.clearance)?;
        let waited = timed.times().last().copied().unwrap_or(0.0)
            - kinema::traj::via::ptp_through(&robot, path, options, dt)?.times().last().copied().unwrap_or(0.0);
        eprintln!("timed against `{}`: {waited:.2} s of waiting at via points", self.other.name);
        Ok(timed)
    }
}
