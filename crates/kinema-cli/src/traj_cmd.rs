//! `kinema traj`: time laws and point-to-point motions from the command line.

use crate::stdout::outln;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use kinema::ik::family::SelfMotionParameter;
use kinema::traj::waypoints::{skip_unreachable, SkippedPoint};
use kinema::traj::{
    check, expression_trajectory, to_joints, to_joints_at, Blend, CartesianLimits, CartesianMotion, CheckOptions, Expr,
    JointMethod, JointTrajectory, MotionLimits, Orientation, Profile, Ptp, PtpOptions, Segment, SelfMotion, TimeLaw,
    Waypoint,
};
use kinema::{Pose, Robot, RpyConvention};
use kinema_geometry::CollisionCheck;
use kinema_io::trajectory_csv::{
    for_each_trajectory_row, read_trajectory_csv, trajectory_header, write_trajectory_csv, Digits, TrajectoryCsv,
};
use kinema_io::{CheckAnswer, LawAnswer, TrajSummary};

use crate::{print_json, write_atomically, RobotArg};

#[derive(Subcommand)]
pub enum TrajCmd {
    /// A normalised time law: its duration and phase times (and, with --dt, samples of s, ṡ, s̈, s⃛).
    Law(LawArgs),
    /// A synchronised point-to-point joint motion (seed 004 §VIII-B), checked against the limits.
    Ptp(PtpArgs),
    /// Straight-line Cartesian motion through optional via points (seed 004 §VIII-C), converted to joints and checked.
    Lin(LinArgs),
    /// Circular Cartesian motion through an auxiliary point (KUKA CIRC style), converted to joints and checked.
    Circ(CircArgs),
    /// Joint curves from expressions of t, e.g. --joint 1 "3*sin(4*pi*t^2/2)" (seed 001 §4.2).
    Expr(ExprArgs),
    /// Check a joint trajectory CSV (t,q1..qn[,qd..][,qdd..]) against a robot's limits.
    Check(CheckArgs),
}

#[derive(Clone, Copy, ValueEnum)]
pub enum OrientationArg {
    /// Spherical linear interpolation of the rotation.
    Slerp,
    /// Linear interpolation of the roll-pitch-yaw angles (seed 004 eq. 40), in the --rpy convention.
    Rpy,
}

#[derive(Args)]
pub struct CartArgs {
    #[command(flatten)]
    robot: RobotArg,
    #[command(flatten)]
    body: crate::BodyArgs,
    /// Start configuration (comma-separated or a named pose); the motion starts at its tool pose.
    #[arg(long, allow_hyphen_values = true)]
    from: String,
    /// Start configuration in degrees.
    #[arg(long)]
    deg: bool,
    /// Roll-pitch-yaw convention of the poses (seed 004 writes xyz: Rx·Ry·Rz).
    #[arg(long, default_value = "zyx", value_parser = crate::by_name::<RpyConvention>())]
    rpy: RpyConvention,
    /// The time law of each segment.
    #[arg(long, default_value = "trapezoid", value_parser = crate::by_name::<Profile>())]
    profile: Profile,
    /// Tool speed limit [m/s].
    #[arg(long)]
    vmax: f64,
    /// Tool acceleration limit [m/s²].
    #[arg(long)]
    amax: f64,
    /// Tool jerk limit [m/s³] (scurve).
    #[arg(long)]
    jmax: Option<f64>,
    /// Angular speed limit [rad/s] (default: the number given to --vmax).
    #[arg(long)]
    rot_vmax: Option<f64>,
    /// Angular acceleration limit [rad/s²] (default: the number given to --amax).
    #[arg(long)]
    rot_amax: Option<f64>,
    /// How Cartesian poses become joint values.
    #[arg(long, default_value = "ik", value_parser = ["ik", "rate"])]
    method: String,
    /// Self-motion of a redundant arm along the path (the iiwa's joint 3): `hold` the start's q3
    /// (the default where the arm has a closed form), `track` (least joint motion), `manipulability`
    /// (seed 004 §V-E), `avoid-limits`, or a value in rad (deg with --deg) the start must have.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "psi", value_parser = policy_text(SelfMotionParameter::Q3))]
    q3: Option<String>,
    /// Hold the arm angle ψ [rad] (deg with --deg) at this value, or `hold` the start's.
    #[arg(long, allow_hyphen_values = true, value_parser = policy_text(SelfMotionParameter::ArmAngle))]
    psi: Option<String>,
    /// Sample period [s].
    #[arg(long, default_value_t = 0.01)]
    dt: f64,
    /// Instead of a fixed period, sample so that consecutive tool poses are at most this far apart [m]
    /// (seed 000 sent its controller points 1 cm apart), and --max-angle [rad].
    #[arg(long)]
    max_step: Option<f64>,
    /// With --max-step: the largest rotation between consecutive samples [rad].
    #[arg(long, default_value_t = 0.05)]
    max_angle: f64,
    /// Also report samples whose manipulability is below this value as violations.
    #[arg(long)]
    min_manip: Option<f64>,
    /// Write the samples as CSV (t,q…,qd…,qdd…,x,y,z,roll,pitch,yaw,manipulability).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print a JSON summary (and the samples when --out is not given).
    #[arg(long)]
    json: bool,
}

/// A clap parser that accepts what [`SelfMotion::parse`] reads for `parameter`
/// (so a malformed policy is a usage error, exit 64).
fn policy_text(parameter: SelfMotionParameter) -> impl Fn(&str) -> std::result::Result<String, String> + Clone {
    move |text| SelfMotion::parse(parameter, text, 1.0).map(|_| text.to_string()).map_err(|e| e.to_string())
}

#[derive(Args)]
pub struct LinArgs {
    #[command(flatten)]
    cart: CartArgs,
    /// Goal pose x,y,z,roll,pitch,yaw (m, rad).
    #[arg(long, allow_hyphen_values = true)]
    to: String,
    /// Via poses x,y,z,roll,pitch,yaw, in order (repeat the option).
    #[arg(long, allow_hyphen_values = true)]
    via: Vec<String>,
    /// Blending at via points: `decel` (seed 004: start the next segment when the previous decelerates),
    /// `none`, a time in seconds (`0.3`) or a distance (`0.05m`).
    #[arg(long, default_value = "decel")]
    blend: Blend,
    /// Orientation interpolation.
    #[arg(long, value_enum, default_value = "slerp")]
    orientation: OrientationArg,
    /// Leave out --via/--to poses the robot cannot reach (seed 003 Fig. 9), each named on stderr
    /// and in the JSON summary's `skipped`; without it an unreachable pose is an error.
    #[arg(long)]
    skip_unreachable: bool,
}

#[derive(Args)]
pub struct CircArgs {
    #[command(flatten)]
    cart: CartArgs,
    /// Auxiliary point x,y,z the arc passes through (m).
    #[arg(long, allow_hyphen_values = true)]
    aux: String,
    /// End pose x,y,z,roll,pitch,yaw (m, rad).
    #[arg(long, allow_hyphen_values = true)]
    to: String,
}

#[derive(Args)]
pub struct ExprArgs {
    #[command(flatten)]
    robot: RobotArg,
    #[command(flatten)]
    body: crate::BodyArgs,
    /// A joint (1-based) and its expression of t, e.g. --joint 1 "3*sin(4*pi*t^2/2)"; repeat for more joints.
    #[arg(long, num_args = 2, value_names = ["JOINT", "EXPR"], allow_hyphen_values = true)]
    joint: Vec<String>,
    /// Duration [s].
    #[arg(long)]
    duration: f64,
    /// Values of the other joints (comma-separated or a named pose; default `home`).
    #[arg(long, allow_hyphen_values = true, default_value = "home")]
    q0: String,
    /// Sample period [s].
    #[arg(long, default_value_t = 0.01)]
    dt: f64,
    /// Roll-pitch-yaw convention of the pose columns.
    #[arg(long, default_value = "zyx", value_parser = crate::by_name::<RpyConvention>())]
    rpy: RpyConvention,
    /// Velocity limits to check instead of the robot's (one value or one per joint): a curve meant for
    /// a simulation, such as seed 001's, can be faster than the arm.
    #[arg(long, allow_hyphen_values = true)]
    vmax: Option<String>,
    /// Acceleration limits to check instead of the robot's (one value or one per joint).
    #[arg(long, allow_hyphen_values = true)]
    amax: Option<String>,
    /// Jerk limits to check (one value or one per joint; default: the robot's, if it has them).
    #[arg(long, allow_hyphen_values = true)]
    jmax: Option<String>,
    /// Write the samples as CSV.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print a JSON summary (and the samples when --out is not given).
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct CheckArgs {
    #[command(flatten)]
    robot: RobotArg,
    #[command(flatten)]
    body: crate::BodyArgs,
    /// The trajectory CSV: a header with t and q1..qn, optionally qd1..qdn and qdd1..qddn
    /// (estimated from the samples when absent); other columns are ignored.
    file: PathBuf,
    /// Velocity limits to check instead of the robot's (one value or one per joint).
    #[arg(long, allow_hyphen_values = true)]
    vmax: Option<String>,
    /// Acceleration limits to check (one value or one per joint).
    #[arg(long, allow_hyphen_values = true)]
    amax: Option<String>,
    /// Jerk limits to check (one value or one per joint; default: the robot's, if it has them).
    #[arg(long, allow_hyphen_values = true)]
    jmax: Option<String>,
    /// Report samples whose manipulability is below this value.
    #[arg(long)]
    min_manip: Option<f64>,
    /// Warn of singular passages: the Jacobian's inverse condition number below this value
    /// (0 turns the warning off).
    #[arg(long, default_value_t = kinema::traj::SINGULAR_WARNING)]
    singular: f64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct LawArgs {
    /// The law's family.
    #[arg(long, default_value = "trapezoid", value_parser = crate::by_name::<Profile>())]
    profile: Profile,
    /// Distance to cover (any unit; the limits use the same one). Default 1 (a normalised law).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    distance: f64,
    /// Velocity limit [unit/s].
    #[arg(long, requires = "amax", conflicts_with = "duration", allow_hyphen_values = true)]
    vmax: Option<f64>,
    /// Acceleration limit [unit/s²].
    #[arg(long, allow_hyphen_values = true)]
    amax: Option<f64>,
    /// Jerk limit [unit/s³] (scurve; optional for quintic).
    #[arg(long, allow_hyphen_values = true)]
    jmax: Option<f64>,
    /// Build the law from a duration [s] instead of limits.
    #[arg(long, allow_hyphen_values = true)]
    duration: Option<f64>,
    /// Also print samples every DT seconds.
    #[arg(long)]
    dt: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// The joint limits a PTP is timed under, when not the robot's (a URDF has
/// no acceleration limits).
#[derive(Args)]
pub struct TimingLimits {
    /// Velocity limits: one value or one per joint (default: the robot's).
    #[arg(long, allow_hyphen_values = true)]
    pub vmax: Option<String>,
    /// Acceleration limits: one value or one per joint (default: the robot's).
    #[arg(long, allow_hyphen_values = true)]
    pub amax: Option<String>,
    /// Jerk limits: one value or one per joint (default: the robot's).
    #[arg(long, allow_hyphen_values = true)]
    pub jmax: Option<String>,
}

impl TimingLimits {
    /// `options` with the limits given (degrees converted with `deg`).
    pub fn apply(&self, robot: &Robot, deg: bool, options: PtpOptions) -> Result<PtpOptions> {
        Ok(PtpOptions {
            vel: limits_arg(robot, self.vmax.as_deref(), deg, "vmax")?,
            acc: limits_arg(robot, self.amax.as_deref(), deg, "amax")?,
            jerk: limits_arg(robot, self.jmax.as_deref(), deg, "jmax")?,
            ..options
        })
    }
}

#[derive(Args)]
pub struct PtpArgs {
    #[command(flatten)]
    robot: RobotArg,
    #[command(flatten)]
    body: crate::BodyArgs,
    /// Start configuration: comma-separated values or a named pose.
    #[arg(long, allow_hyphen_values = true)]
    from: String,
    /// Goal configuration: comma-separated values or a named pose.
    #[arg(long, allow_hyphen_values = true)]
    to: String,
    /// Joint values (and --vmax/--amax/--jmax of revolute joints) in degrees.
    #[arg(long)]
    deg: bool,
    /// The shared law's family [default: trapezoid, or scurve for a robot whose model has jerk limits
    /// (the Panda), whose controller rejects the trapezoid's steps in acceleration].
    #[arg(long, value_parser = crate::by_name::<Profile>())]
    profile: Option<Profile>,
    #[command(flatten)]
    limits: TimingLimits,
    /// Velocity override in percent (1–100): velocity ×k, acceleration ×k², jerk ×k³.
    #[arg(long, default_value_t = 100.0)]
    speed: f64,
    /// Stretch the motion to this duration [s] (at least the fastest one).
    #[arg(long)]
    duration: Option<f64>,
    /// Start joint velocities, one per joint [rad/s, m/s; deg/s with --deg]:
    /// with any of --v0/--a0/--v1/--a1 each joint gets its own time-optimal
    /// law (scurve or trapezoid), all ending together; the path is then in
    /// general not a straight line in joint space.
    #[arg(long, allow_hyphen_values = true, value_parser = joint_values)]
    v0: Option<JointValues>,
    /// Start joint accelerations, one per joint (scurve only).
    #[arg(long, allow_hyphen_values = true, value_parser = joint_values)]
    a0: Option<JointValues>,
    /// End joint velocities, one per joint (to chain motions without stopping).
    #[arg(long, allow_hyphen_values = true, value_parser = joint_values)]
    v1: Option<JointValues>,
    /// End joint accelerations, one per joint (scurve only).
    #[arg(long, allow_hyphen_values = true, value_parser = joint_values)]
    a1: Option<JointValues>,
    /// Sample period [s].
    #[arg(long, default_value_t = 0.01)]
    dt: f64,
    /// Roll-pitch-yaw convention of the pose columns.
    #[arg(long, default_value = "zyx", value_parser = crate::by_name::<RpyConvention>())]
    rpy: RpyConvention,
    /// Write the samples as CSV (t,q…,qd…,qdd…,x,y,z,roll,pitch,yaw,manipulability).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print a JSON summary (and the samples when --out is not given).
    #[arg(long)]
    json: bool,
}

/// Comma-separated finite numbers (boundary velocities or accelerations).
#[derive(Debug, Clone)]
pub struct JointValues(Vec<f64>);

fn joint_values(text: &str) -> std::result::Result<JointValues, String> {
    text.split(',')
        .map(|s| match s.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("`{}` is not a finite number; expected comma-separated numbers, one per joint", s.trim())),
        })
        .collect::<std::result::Result<Vec<f64>, String>>()
        .map(JointValues)
}

pub fn traj(cmd: TrajCmd) -> Result<()> {
    match cmd {
        TrajCmd::Law(a) => law(a),
        TrajCmd::Ptp(a) => ptp(a),
        TrajCmd::Lin(a) => lin(a),
        TrajCmd::Circ(a) => circ(a),
        TrajCmd::Expr(a) => expr(a),
        TrajCmd::Check(a) => check_file(a),
    }
}

fn law(a: LawArgs) -> Result<()> {
    let profile = a.profile;
    let law = match (a.duration, a.vmax, a.amax) {
        (Some(t), _, _) => TimeLaw::from_duration(profile, t)?,
        (None, Some(v), Some(acc)) => {
            TimeLaw::from_limits(profile, a.distance, &MotionLimits { vel: v, acc, jerk: a.jmax })?
        }
        _ => bail!("give either --duration T or --vmax V --amax A [--jmax J]"),
    };
    // A law of given duration is the normalised one.
    let scale = if a.duration.is_some() { 1.0 } else { a.distance };
    let out = LawAnswer::new(&law, scale, a.dt)?;
    if a.json {
        return print_json(&out);
    }
    outln!("{} law: duration {:.6} s", profile.name(), law.duration())?;
    outln!("phase times [s]: {:?}", law.phase_times())?;
    outln!(
        "peaks: velocity {}, acceleration {}, jerk {}",
        serde_json::to_string(&out.peak_velocity)?,
        serde_json::to_string(&out.peak_acceleration)?,
        serde_json::to_string(&out.peak_jerk)?
    )?;
    Ok(())
}

/// Parses "v" or "v1,v2,…" into numbers, converting revolute entries from degrees when asked.
fn limits_arg(robot: &Robot, text: Option<&str>, deg: bool, what: &str) -> Result<Option<Vec<f64>>> {
    let Some(text) = text else { return Ok(None) };
    let vals: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>().with_context(|| format!("--{what}: `{}` is not a number", s.trim())))
        .collect::<Result<_>>()?;
    if !deg {
        return Ok(Some(vals));
    }
    let js = robot.joints();
    Ok(Some(if vals.len() == 1 {
        if js.iter().any(|j| j.kind == kinema::JointType::Prismatic) {
            bail!("--{what}: one value in degrees cannot apply to the prismatic joints too; give one value per joint");
        }
        vec![vals[0].to_radians()]
    } else {
        vals.iter()
            .zip(js)
            .map(|(v, j)| if j.kind == kinema::JointType::Revolute { v.to_radians() } else { *v })
            .collect()
    }))
}

fn ptp(a: PtpArgs) -> Result<()> {
    let (robot, body) = a.body.robot_and_check(&a.robot)?;
    let from = robot.parse_q(&a.from, a.deg)?;
    let to = robot.parse_q(&a.to, a.deg)?;
    if !(a.speed > 0.0 && a.speed <= 100.0) {
        bail!("--speed {}: the override must be a percentage in (0, 100]", a.speed);
    }
    let given = PtpOptions {
        profile: a.profile.unwrap_or_else(|| kinema::traj::default_profile(&robot)),
        speed: a.speed / 100.0,
        duration: a.duration,
        vel: None,
        acc: None,
        jerk: None,
    };
    let opts = a.limits.apply(&robot, a.deg, given)?;
    let boundary = kinema::traj::JointBoundary {
        v0: boundary_arg(&robot, a.v0.as_ref(), a.deg, "v0")?,
        a0: boundary_arg(&robot, a.a0.as_ref(), a.deg, "a0")?,
        v1: boundary_arg(&robot, a.v1.as_ref(), a.deg, "v1")?,
        a1: boundary_arg(&robot, a.a1.as_ref(), a.deg, "a1")?,
    };
    if boundary != kinema::traj::JointBoundary::default() {
        // Boundary states: one law per joint, checked like every trajectory.
        let plan = kinema::traj::BoundaryPtp::new(&robot, &from, &to, &opts, &boundary)?;
        let traj = plan.sample(&robot, a.dt)?;
        refuse_collisions(&traj, body.as_ref())?;
        let summary = TrajSummary::boundary_ptp(&robot, &plan, opts.profile, traj.len());
        return emit(&robot, &traj, a.rpy, a.out.as_deref(), a.json, summary);
    }
    let plan = Ptp::new(&robot, &from, &to, &opts)?;
    let traj = plan.sample(&robot, a.dt)?;
    refuse_collisions(&traj, body.as_ref())?;
    let summary = TrajSummary::ptp(&robot, &plan, traj.len());
    emit(&robot, &traj, a.rpy, a.out.as_deref(), a.json, summary)
}

/// One boundary value per joint, revolute ones converted from degrees with
/// --deg. A wrong count is a usage error (exit 64), named by its flag.
fn boundary_arg(robot: &Robot, given: Option<&JointValues>, deg: bool, flag: &str) -> Result<Option<Vec<f64>>> {
    let Some(JointValues(vals)) = given else { return Ok(None) };
    if vals.len() != robot.dof() {
        eprintln!(
            "error: --{flag}: {} values given; expected {}, one per joint of `{}`",
            vals.len(),
            robot.dof(),
            robot.name()
        );
        return Err(crate::Exit(crate::EXIT_USAGE).into());
    }
    let js = robot.joints();
    Ok(Some(
        vals.iter()
            .zip(js)
            .map(|(v, j)| if deg && j.kind == kinema::JointType::Revolute { v.to_radians() } else { *v })
            .collect(),
    ))
}

/// Writes a checked trajectory: CSV to `out` (atomically) and/or a JSON
/// summary (with the rows when there is no file) or CSV on stdout.
pub(crate) fn emit(
    robot: &Robot,
    traj: &JointTrajectory,
    conv: RpyConvention,
    out: Option<&std::path::Path>,
    as_json: bool,
    summary: TrajSummary,
) -> Result<()> {
    // `--out -` is standard output, as without --out.
    let out = out.filter(|p| !crate::output::is_stdout(p));
    let samples = traj.len();
    let duration = traj.times().last().copied().unwrap_or(0.0);
    if let Some(path) = out {
        write_atomically(path, |w| write_csv(w, &path.display().to_string(), robot, traj, conv, 12))?;
        eprintln!("wrote {samples} samples ({duration:.4} s) to {}", path.display());
    }
    if as_json {
        if out.is_some() {
            return print_json(&summary);
        }
        let with_rows = WithRows {
            summary: &summary,
            columns: trajectory_header(robot.dof(), conv),
            rows: Rows { robot, traj, conv },
        };
        let mut w = std::io::BufWriter::new(std::io::stdout().lock());
        let written: Result<()> = (|| {
            serde_json::to_writer_pretty(&mut w, &with_rows)?;
            std::io::Write::write_all(&mut w, b"\n")?;
            Ok(std::io::Write::flush(&mut w)?)
        })();
        return written.context("cannot write to standard output");
    }
    if out.is_none() {
        let mut w = std::io::BufWriter::new(std::io::stdout().lock());
        write_csv(&mut w, "standard output", robot, traj, conv, 9).context("cannot write to standard output")?;
    } else {
        outln!("{:?} on `{}`: {duration:.6} s, {samples} samples", summary.motion, robot.name())?;
    }
    Ok(())
}

/// The CSV of a trajectory (see [`kinema_io::trajectory_csv`]) with
/// `decimals`; `origin` names the destination in errors.
pub(crate) fn write_csv(
    w: impl std::io::Write,
    origin: &str,
    robot: &Robot,
    traj: &JointTrajectory,
    conv: RpyConvention,
    decimals: usize,
) -> Result<()> {
    Ok(write_trajectory_csv(w, origin, robot, traj, conv, Digits::Fixed(decimals))?)
}

/// A JSON summary with the trajectory's columns and rows, the rows computed
/// as they are serialised.
#[derive(serde::Serialize)]
struct WithRows<'a> {
    #[serde(flatten)]
    summary: &'a TrajSummary,
    columns: Vec<String>,
    rows: Rows<'a>,
}

/// The rows of [`for_each_trajectory_row`] as a JSON array.
struct Rows<'a> {
    robot: &'a Robot,
    traj: &'a JointTrajectory,
    conv: RpyConvention,
}

impl serde::Serialize for Rows<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::{Error, SerializeSeq};
        let mut seq = s.serialize_seq(Some(self.traj.len()))?;
        let mut write_error = None;
        let computed = for_each_trajectory_row(self.robot, self.traj, self.conv, |row| {
            seq.serialize_element(row).map_err(|e| {
                write_error = Some(e);
                anyhow::anyhow!("the JSON could not be written")
            })
        });
        if let Some(e) = write_error {
            return Err(e);
        }
        computed.map_err(S::Error::custom)?;
        seq.end()
    }
}

/// x,y,z,roll,pitch,yaw → a pose.
pub(crate) fn pose_arg(text: &str, conv: RpyConvention, what: &str) -> Result<Pose> {
    Ok(*waypoint_arg(text, conv, what)?.pose())
}

/// A pose written as x,y,z,roll,pitch,yaw, keeping the triple for `--orientation rpy`.
fn waypoint_arg(text: &str, conv: RpyConvention, what: &str) -> Result<Waypoint> {
    let v = numbers(text, what)?;
    if v.len() != 6 {
        bail!("--{what}: {} values given; expected x,y,z,roll,pitch,yaw (m, rad)", v.len());
    }
    Ok(Waypoint::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], conv))
}

fn numbers(text: &str, what: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|s| {
            let x: f64 = s.trim().parse().with_context(|| format!("--{what}: `{}` is not a number", s.trim()))?;
            if !x.is_finite() {
                bail!("--{what}: {x} is not a finite number");
            }
            Ok(x)
        })
        .collect()
}

/// The check as the core's admissibility test.
fn admissible(body: Option<&CollisionCheck>) -> Option<&dyn kinema::ik::Admissible> {
    body.map(|c| c as &dyn kinema::ik::Admissible)
}

/// An error listing where `traj` collides, when a check is given: the samples
/// and the straight joint steps between them, certified.
fn refuse_collisions(traj: &JointTrajectory, body: Option<&CollisionCheck>) -> Result<()> {
    if let Some(check) = body {
        kinema::traj::collision_free(traj, check)?;
    }
    Ok(())
}

fn cart_motion(
    robot: &Robot,
    body: Option<&CollisionCheck>,
    c: &CartArgs,
    segments: impl FnOnce(Pose) -> Result<Vec<Segment>>,
    blend: Blend,
    skipped: &[SkippedPoint],
) -> Result<()> {
    let q0 = robot.parse_q(&c.from, c.deg)?;
    let start = robot.fk(&q0)?.world_from_tool;
    let limits = CartesianLimits {
        vel: c.vmax,
        acc: c.amax,
        jerk: c.jmax,
        rot_vel: c.rot_vmax.unwrap_or(c.vmax),
        rot_acc: c.rot_amax.unwrap_or(c.amax),
        rot_jerk: c.jmax,
    };
    let profile = c.profile;
    let motion = CartesianMotion::new(segments(start)?, profile, &limits, blend)?;
    let scale = if c.deg { std::f64::consts::PI / 180.0 } else { 1.0 };
    let self_motion = match (&c.q3, &c.psi) {
        (Some(text), _) => SelfMotion::parse(SelfMotionParameter::Q3, text, scale).context("--q3")?,
        (None, Some(text)) => SelfMotion::parse(SelfMotionParameter::ArmAngle, text, scale).context("--psi")?,
        (None, None) => SelfMotion::Auto,
    };
    let method = JointMethod::named(&c.method, self_motion.clone())?;
    if self_motion != SelfMotion::Auto && method == JointMethod::RESOLVED_RATE {
        bail!("--q3/--psi choose the self-motion of --method ik; resolved rate (--method rate) follows the damped pseudo-inverse");
    }
    let traj = match c.max_step {
        Some(step) => to_joints_at(robot, &motion, &q0, &motion.resample_times(step, c.max_angle)?, method.clone())?,
        None => to_joints(robot, &motion, &q0, c.dt, method)?,
    };
    let opts =
        CheckOptions { min_manipulability: c.min_manip, admissible: admissible(body), ..CheckOptions::default() };
    check(robot, &traj, &opts)?.into_result()?;
    let summary = TrajSummary::cartesian(robot, &motion, profile, traj.len(), skipped);
    emit(robot, &traj, c.rpy, c.out.as_deref(), c.json, summary)
}

fn lin(a: LinArgs) -> Result<()> {
    let (robot, body) = a.cart.body.robot_and_check(&a.cart.robot)?;
    let conv = a.cart.rpy;
    let orientation = match a.orientation {
        OrientationArg::Slerp => Orientation::Slerp,
        OrientationArg::Rpy => Orientation::Rpy(conv),
    };
    let mut points = Vec::new();
    for v in &a.via {
        points.push(waypoint_arg(v, conv, "via")?);
    }
    points.push(waypoint_arg(&a.to, conv, "to")?);
    // Seed 003 Fig. 9: waypoints out of reach are left out when asked.
    let skipped = if a.skip_unreachable {
        let poses: Vec<Pose> = points.iter().map(|p| *p.pose()).collect();
        let (_, skipped) = skip_unreachable(&robot, &poses)?;
        for p in &skipped {
            let which = if p.index + 1 == poses.len() { "--to".to_string() } else { format!("--via #{}", p.index + 1) };
            eprintln!("skipped {which}: {}", p.reason);
        }
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
    let blend = a.blend;
    let segments = |start| Ok(Segment::lin_chain(&start, &points, orientation)?);
    cart_motion(&robot, body.as_ref(), &a.cart, segments, blend, &skipped)
}

fn circ(a: CircArgs) -> Result<()> {
    let (robot, body) = a.cart.body.robot_and_check(&a.cart.robot)?;
    let conv = a.cart.rpy;
    let aux = numbers(&a.aux, "aux")?;
    if aux.len() != 3 {
        bail!("--aux: {} values given; expected x,y,z (m)", aux.len());
    }
    let to = pose_arg(&a.to, conv, "to")?;
    cart_motion(
        &robot,
        body.as_ref(),
        &a.cart,
        |start| Ok(vec![Segment::circ_through(&start, &kinema::nalgebra::Vector3::new(aux[0], aux[1], aux[2]), &to)?]),
        Blend::None,
        &[],
    )
}

fn expr(a: ExprArgs) -> Result<()> {
    let (robot, body) = a.body.robot_and_check(&a.robot)?;
    let q0 = robot.parse_q(&a.q0, false)?;
    if a.joint.is_empty() {
        bail!("give at least one --joint N EXPR");
    }
    let mut exprs = Vec::new();
    for pair in a.joint.chunks(2) {
        let j: usize = pair[0].trim().parse().with_context(|| format!("--joint `{}`: not a joint number", pair[0]))?;
        if j == 0 {
            bail!("--joint 0: joints are numbered from 1");
        }
        exprs.push((j - 1, Expr::parse(&pair[1])?));
    }
    let limits = CheckOptions {
        vel: limits_arg(&robot, a.vmax.as_deref(), false, "vmax")?,
        acc: limits_arg(&robot, a.amax.as_deref(), false, "amax")?,
        jerk: limits_arg(&robot, a.jmax.as_deref(), false, "jmax")?,
        admissible: admissible(body.as_ref()),
        ..CheckOptions::default()
    };
    let traj = expression_trajectory(&robot, &q0, &exprs, a.duration, a.dt)?;
    check(&robot, &traj, &limits)?.into_result()?;
    let summary = TrajSummary::expression(&robot, &exprs, a.duration, traj.len());
    emit(&robot, &traj, a.rpy, a.out.as_deref(), a.json, summary)
}

fn check_file(a: CheckArgs) -> Result<()> {
    let (robot, body) = a.body.robot_and_check(&a.robot)?;
    let (traj, (value_resolution, time_resolution)) = read_trajectory_with_resolution(&robot, &a.file)?;
    let opts = CheckOptions {
        value_resolution,
        time_resolution,
        vel: limits_arg(&robot, a.vmax.as_deref(), false, "vmax")?,
        acc: limits_arg(&robot, a.amax.as_deref(), false, "amax")?,
        jerk: limits_arg(&robot, a.jmax.as_deref(), false, "jmax")?,
        min_manipulability: a.min_manip,
        singular_warning: (a.singular != 0.0).then_some(a.singular),
        admissible: admissible(body.as_ref()),
        ..CheckOptions::default()
    };
    let report = check(&robot, &traj, &opts)?;
    if a.json {
        print_json(&CheckAnswer::new(&report))?;
    } else {
        outln!(
            "{}: {} samples, {} violation(s), {} warning(s)",
            a.file.display(),
            report.samples,
            report.violations.len(),
            report.warnings.len()
        )?;
        for v in report.violations.iter().take(20) {
            outln!("  {v}")?;
        }
        if report.violations.len() > 20 {
            outln!("  … and {} more", report.violations.len() - 20)?;
        }
        for w in report.warnings.iter().take(20) {
            outln!("  warning: {w}")?;
        }
    }
    if report.violations.is_empty() {
        Ok(())
    } else {
        Err(crate::Exit(1).into())
    }
}

/// Reads a trajectory CSV with a header naming t and q1..qn (qd*, qdd*
/// optional), with how finely the file gives (values, times).
pub(crate) fn read_trajectory_with_resolution(
    robot: &Robot,
    path: &std::path::Path,
) -> Result<(JointTrajectory, (f64, f64))> {
    let s = read_samples(robot, path)?;
    Ok((s.traj, s.resolution))
}

/// The trajectory CSV at `path` (at most [`crate::input::MAX_CSV_BYTES`]) as
/// [`read_trajectory_csv`] reads it.
pub(crate) fn read_samples(robot: &Robot, path: &std::path::Path) -> Result<TrajectoryCsv> {
    let bytes = crate::input::read_limited(path, crate::input::MAX_CSV_BYTES, "CSV input")?;
    Ok(read_trajectory_csv(&bytes, &path.display().to_string(), robot)?)
}
