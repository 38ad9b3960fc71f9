//! `kinema plan`: a collision-free joint motion from a configuration to a
//! configuration or a tool pose, around the robot itself and a scene's
//! obstacles (`kinema_geometry::plan`), timed within the joint limits and
//! written as a trajectory that `kinema traj check --scene` accepts.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{bail, Result};
use clap::Args;
use kinema::traj::{Profile, PtpOptions};
use kinema::RpyConvention;
use kinema_geometry::plan::{plan, Goal, PlanOptions};
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
}

pub fn run(a: PlanArgs) -> Result<()> {
    if !(a.time_limit > 0.0 && a.time_limit <= 86_400.0) {
        bail!("--time-limit {}: expected seconds in (0, 86400]", a.time_limit);
    }
    if !(a.speed > 0.0 && a.speed <= 100.0) {
        bail!("--speed {}: the override must be a percentage in (0, 100]", a.speed);
    }
    let check = a.body.load(&a.robot)?;
    let robot = check.robot();
    let from = robot.parse_q(&a.from, a.deg)?;
    let goal = match (&a.to, &a.pose) {
        (Some(to), _) => Goal::Joints(robot.parse_q(to, a.deg)?),
        (None, Some(pose)) => Goal::Pose(crate::traj_cmd::pose_arg(pose, a.rpy, "pose")?),
        (None, None) => unreachable!("clap requires --to or --pose"),
    };
    let ptp = PtpOptions {
        profile: a.profile.unwrap_or_else(|| kinema::traj::default_profile(robot)),
        speed: a.speed / 100.0,
        ..PtpOptions::for_robot(robot)
    };
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
    let traj = found.trajectory(robot, &ptp, a.dt)?;
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
