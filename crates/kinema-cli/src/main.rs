//! The `kinema` command: parse arguments, call the library, print.

use crate::stdout::outln;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand};
use kinema::nalgebra::Matrix6xX;
use kinema::{Frame, JointType, LinkGeometry, Named, Pose, Robot, RpyConvention};
use kinema_io::{FkAnswer, JacobianAnswer, ManipAnswer, RobotInfo, RobotSummary};
use serde_json::{json, Value};

pub(crate) use output::write_atomically;

mod cell_cmd;
mod dyn_cmd;
mod ik_cmd;
mod input;
mod interrupt;
mod lang_cmd;
mod output;
#[cfg(feature = "plot")]
mod plot_cmd;
#[cfg(feature = "scorbot")]
mod scorbot_cmd;
#[cfg(feature = "serve")]
mod serve_cmd;
mod stdout;
mod traj_cmd;

/// An error that only sets the exit code (its message was already printed).
#[derive(Debug)]
struct Exit(u8);

impl std::fmt::Display for Exit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "exit code {}", self.0)
    }
}

impl std::error::Error for Exit {}

#[derive(Parser)]
#[command(name = "kinema", version, about = "Kinematics of robot arms: forward kinematics, Jacobians, manipulability.")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// List the built-in robots.
    Robots {
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Show a robot: DH table (or joint frames), limits, base, tool, named poses.
    Info {
        #[command(flatten)]
        robot: RobotArg,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Forward kinematics: the tool pose for a joint configuration, or a whole CSV file of them.
    Fk(FkArgs),
    /// Geometric Jacobian (rows vx vy vz ωx ωy ωz) at a configuration.
    Jacobian(JacobianArgs),
    /// Manipulability, condition number, rank, singular values and dependent joints.
    Manip(ManipArgs),
    /// Inverse kinematics: joint values that reach a target pose (exit code 2 if unreachable).
    Ik(ik_cmd::IkArgs),
    /// Round-trip validation of a robot's analytic IK (seed 004 §V-C): random q → FK → IK → q.
    IkValidate(ik_cmd::ValidateArgs),
    /// iiwa self-motion: configurations and elbow positions that keep the tool pose of --q.
    Selfmotion(ik_cmd::SelfMotionArgs),
    /// Time FK and the Jacobian (and, with --ik, inverse kinematics) over random configurations.
    Bench(BenchArgs),
    /// Trajectories: time laws and point-to-point motions, checked against the limits.
    Traj {
        #[command(subcommand)]
        cmd: traj_cmd::TrajCmd,
    },
    /// Joint torques along a trajectory CSV by inverse dynamics (RNEA), checked against the
    /// motor effort limits (exit code 1 if exceeded; the torques are written either way).
    Dyn(dyn_cmd::DynArgs),
    /// Several robots on a common clock (seed 004 §VIII-E): per-robot checks and the closest
    /// distance between their tools (exit code 3 when closer than the minimum).
    Cell(cell_cmd::CellArgs),
    /// Check a robot program: every diagnostic, nothing written (exit code 1 on errors).
    Check(lang_cmd::ProgramArgs),
    /// Run a robot program: write its joint signals as CSV (nothing is written on any error).
    Run(lang_cmd::RunArgs),
    /// Compile a robot program and print its motion plan (--listing).
    Compile(lang_cmd::CompileArgs),
    /// Pictures: robot, workspace, trajectory, ellipsoids, self-motion, IK error, tracking (.svg or .png).
    #[cfg(feature = "plot")]
    Plot {
        #[command(subcommand)]
        cmd: plot_cmd::PlotCmd,
    },
    /// Pictures (.svg or .png): not in this build, which lacks the `plot` feature.
    #[cfg(not(feature = "plot"))]
    Plot(NotBuilt),
    /// Start the interactive 3D viewer on 127.0.0.1 (Ctrl-C to stop).
    #[cfg(feature = "serve")]
    Serve(serve_cmd::ServeArgs),
    /// The interactive 3D viewer: not in this build, which lacks the `serve` feature.
    #[cfg(not(feature = "serve"))]
    Serve(NotBuilt),
    /// The Scorbot-ER V Plus on real hardware: encoder counts, controller simulator and client,
    /// tracking accuracy, calibration (seed 000).
    #[cfg(feature = "scorbot")]
    Scorbot {
        #[command(subcommand)]
        cmd: scorbot_cmd::ScorbotCmd,
    },
    /// The Scorbot-ER V Plus on real hardware: not in this build, which lacks the `scorbot` feature.
    #[cfg(not(feature = "scorbot"))]
    Scorbot(NotBuilt),
}

/// The arguments of a sub-command left out of this build. It stays listed
/// and takes any arguments, so that `kinema plot robot …` copied from the
/// README says which feature is missing (exit code 1, the build lacks
/// something) instead of clap's "unrecognized subcommand" usage error (64),
/// which would suggest a typo.
#[cfg(not(all(feature = "plot", feature = "scorbot", feature = "serve")))]
#[derive(Args)]
struct NotBuilt {
    // Accepted only to be ignored.
    #[allow(dead_code)]
    #[arg(trailing_var_arg = true, allow_hyphen_values = true, hide = true)]
    args: Vec<String>,
}

/// The error of a sub-command whose cargo feature was left out of this build.
#[cfg(not(all(feature = "plot", feature = "scorbot", feature = "serve")))]
fn not_built(feature: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "this kinema was built without the `{feature}` feature; rebuild with \
         `cargo install --path crates/kinema-cli --features {feature}` (or with the default features)"
    )
}

#[derive(Args)]
struct RobotArg {
    /// A built-in robot name (see `kinema robots`), a .toml description or a .urdf file.
    #[arg(long, short)]
    robot: String,
    /// For a URDF: the tip link of the chain (default: the only leaf link).
    #[arg(long)]
    tip: Option<String>,
}

impl RobotArg {
    fn load(&self) -> Result<Robot> {
        load_robot(&self.robot, self.tip.as_deref())
    }
}

/// [`Robot::load`], with what the loader left out or chose printed on stderr.
pub(crate) fn load_robot(spec: &str, tip: Option<&str>) -> Result<Robot> {
    let robot = Robot::load(spec, tip)?;
    for w in &robot.metadata().warnings {
        eprintln!("warning: {spec}: {w}");
    }
    Ok(robot)
}

#[derive(Args)]
struct QArg {
    /// Joint values, comma-separated (rad and m), or a named pose such as `home`.
    #[arg(long, allow_hyphen_values = true)]
    q: String,
    /// Revolute joint values are in degrees (prismatic ones stay in metres).
    #[arg(long)]
    deg: bool,
}

/// A parser for one of the core's named option types: its names are the
/// possible values (help, completion) and the core reads them.
fn by_name<T: Named + Clone + Send + Sync>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::names()).try_map(|s| T::from_name(&s))
}

#[derive(Args)]
struct FkArgs {
    #[command(flatten)]
    robot: RobotArg,
    /// Joint values, comma-separated (rad and m), or a named pose such as `home`.
    #[arg(long, allow_hyphen_values = true, required_unless_present = "input", conflicts_with = "input")]
    q: Option<String>,
    /// Revolute joint values are in degrees (prismatic ones stay in metres).
    #[arg(long)]
    deg: bool,
    /// Roll-pitch-yaw convention of the printed orientation.
    #[arg(long, default_value = "zyx", value_parser = crate::by_name::<RpyConvention>())]
    rpy: RpyConvention,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Batch mode: a CSV file with one configuration per line (an optional header line of names is skipped).
    #[arg(long, requires = "output")]
    input: Option<PathBuf>,
    /// Batch mode: where to write the poses (CSV; `-` for standard output); written completely or not at all.
    #[arg(long, requires = "input")]
    output: Option<PathBuf>,
}

#[derive(Args)]
struct JacobianArgs {
    #[command(flatten)]
    robot: RobotArg,
    #[command(flatten)]
    q: QArg,
    /// Frame the Jacobian is expressed in.
    #[arg(long, default_value = "base", value_parser = by_name::<Frame>())]
    frame: Frame,
    /// Analytic Jacobian for roll-pitch-yaw rates (in the given convention) instead of the geometric one.
    #[arg(long, conflicts_with = "frame", value_parser = by_name::<RpyConvention>())]
    analytic: Option<RpyConvention>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct ManipArgs {
    #[command(flatten)]
    robot: RobotArg,
    #[command(flatten)]
    q: QArg,
    /// Also report the manipulability along this direction of motion "vx,vy,vz" (seed 004 eq. 12).
    #[arg(long, allow_hyphen_values = true)]
    direction: Option<String>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct BenchArgs {
    #[command(flatten)]
    robot: RobotArg,
    /// Number of random configurations, 1000 to 10 000 000 (1 000 000 or more is meaningful).
    #[arg(long, default_value_t = 1_000_000, value_parser = count(1000, MAX_CONFIGURATIONS))]
    n: usize,
    /// Seed of the random configurations.
    #[arg(long, default_value_t = 1, value_parser = seed)]
    seed: u64,
    /// Also time numeric inverse kinematics on --ik-n reachable targets (FK of random
    /// within-limit configurations; tolerance 1e-6 m / 1e-6 rad; limits enforced).
    #[arg(long)]
    ik: bool,
    /// Number of inverse-kinematics targets for --ik, 1 to 1 000 000.
    #[arg(long, default_value_t = 10_000, value_parser = count(1, 1_000_000))]
    ik_n: usize,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// Exit code of a command line that does not parse (sysexits' EX_USAGE), so
/// scripts can tell it from 2, an unreachable IK target.
const EXIT_USAGE: u8 = 64;

/// The most random configurations a command samples (bench --n, plot
/// workspace --samples, ik-validate --n, plot ik-error --cases): 10 000 000,
/// about a gigabyte of memory at most and tens of seconds.
pub(crate) const MAX_CONFIGURATIONS: usize = 10_000_000;

/// A parser for a count flag: a whole number from `min` to `max` (`1e6`
/// is accepted), refused with the limit named, e.g. "100000000000 is above
/// the limit of 10000000". Huge counts would otherwise ask for terabytes or
/// run for days.
pub(crate) fn count(min: usize, max: usize) -> impl Fn(&str) -> Result<usize, String> + Clone + Send + Sync + 'static {
    move |text| {
        let t = text.trim();
        let v: f64 = match t.parse::<u128>() {
            Ok(v) => v as f64,
            Err(_) => t
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && v.fract() == 0.0 && *v >= 0.0)
                .ok_or_else(|| format!("`{t}` is not a whole number"))?,
        };
        if v > max as f64 {
            return Err(format!("{t} is above the limit of {max}"));
        }
        if v < min as f64 {
            return Err(format!("{t} is too small: at least {min}"));
        }
        Ok(v as usize)
    }
}

/// A parser for a seed flag: a whole number from 0 to 2⁶⁴ − 1, and a message
/// that says so (`--seed -1` is "not a seed", not an unknown argument).
pub(crate) fn seed(text: &str) -> Result<u64, String> {
    text.trim()
        .parse::<u64>()
        .map_err(|_| format!("`{text}` is not a seed: a seed is a whole number from 0 to {}", u64::MAX))
}

/// The command line's grammar, with every option that takes one value taking
/// the next word as that value even when it starts with `-` (`--dt -0.01`,
/// `--seed -1`, `--tol-orientation -1e-3`): the value then reaches the
/// option's parser or the core's validation, which say what is wrong with
/// it, instead of clap calling `-1` an unexpected argument. (clap's
/// `allow_negative_numbers` would not do: it does not read `-1e-3` as a number.)
fn command() -> clap::Command {
    fn hyphen_values(cmd: clap::Command) -> clap::Command {
        cmd.mut_args(|a| {
            if a.is_positional() || !a.get_action().takes_values() {
                return a;
            }
            // An option of one value takes any next word; one of several values
            // (`--measured a.csv b.csv`) only numbers, so it stops at the next flag.
            match a.get_num_args() {
                Some(r) if r.max_values() > 1 => a.allow_negative_numbers(true),
                _ => a.allow_hyphen_values(true),
            }
        })
        .mut_subcommands(hyphen_values)
    }
    hyphen_values(<Cli as clap::CommandFactory>::command())
}

/// Parses the command line (see [`command`]).
fn parse(args: impl IntoIterator<Item = std::ffi::OsString>) -> Result<Cli, clap::Error> {
    let mut cmd = command();
    let matches = cmd.try_get_matches_from_mut(args)?;
    <Cli as clap::FromArgMatches>::from_arg_matches(&matches).map_err(|e| e.format(&mut cmd))
}

/// A usage error found after parsing (exit 64, as clap's own), printed as
/// clap prints its errors.
pub(crate) fn usage_error(message: impl std::fmt::Display) -> anyhow::Error {
    eprintln!("error: {message}\n\nFor more information, try '--help'.");
    Exit(EXIT_USAGE).into()
}

fn main() -> ExitCode {
    let cli = match parse(std::env::args_os()) {
        Ok(cli) => cli,
        Err(e) => {
            // --help and --version are not errors, unless they cannot be written.
            let printed = e.print();
            if !e.use_stderr() {
                if let Err(io) = printed {
                    eprintln!("error: cannot write to standard output: {io}");
                    return ExitCode::FAILURE;
                }
                return ExitCode::SUCCESS;
            }
            return ExitCode::from(EXIT_USAGE);
        }
    };
    if !talks_to_peers(&cli.cmd) {
        quiet_on_closed_pipe();
    }
    fail_writes_past_the_file_size_limit();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => match e.downcast_ref::<Exit>() {
            Some(Exit(code)) => ExitCode::from(*code),
            None => {
                eprintln!("error: {}", chain_text(&e));
                ExitCode::FAILURE
            }
        },
    }
}

/// An error and its causes on one line, each cause only when its text is
/// not already in the line: the libraries' errors show their source in their
/// own message (so that `to_string` alone is complete), and `{:#}` would
/// repeat it once per level.
fn chain_text(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !text.contains(&c) {
            text.push_str(": ");
            text.push_str(&c);
        }
    }
    text
}

/// The commands that write to sockets, pseudo-terminals or serial lines,
/// where a peer that goes away must not end the process.
fn talks_to_peers(cmd: &Cmd) -> bool {
    match cmd {
        #[cfg(feature = "serve")]
        Cmd::Serve(_) => true,
        #[cfg(feature = "scorbot")]
        Cmd::Scorbot { cmd: scorbot_cmd::ScorbotCmd::Sim(_) | scorbot_cmd::ScorbotCmd::Connect(_) } => true,
        _ => false,
    }
}

/// A closed standard output (`kinema info … | head -1`) ends the process
/// quietly, by SIGPIPE, as it does other Unix tools (the shell reports status
/// 141), instead of a panic of `println!` on the broken pipe.
fn quiet_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of SIGPIPE, before any other
    // thread exists, touches no memory of this program.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// With a file size limit (`ulimit -f`), a write past it kills the process
/// with SIGXFSZ by default, leaving its temporary file behind; ignored, the
/// write fails with EFBIG ("File too large") and the usual cleanup runs.
fn fail_writes_past_the_file_size_limit() {
    #[cfg(unix)]
    // SAFETY: as for SIGPIPE above: a disposition set before other threads exist.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.cmd {
        Cmd::Robots { json } => robots(json),
        Cmd::Info { robot, json } => info(&robot.load()?, json),
        Cmd::Fk(a) => fk(a),
        Cmd::Jacobian(a) => jacobian(a),
        Cmd::Manip(a) => manip(a),
        Cmd::Ik(a) => ik_cmd::ik(a),
        Cmd::IkValidate(a) => ik_cmd::validate(a),
        Cmd::Selfmotion(a) => ik_cmd::selfmotion(a),
        Cmd::Bench(a) => bench(a),
        Cmd::Traj { cmd } => traj_cmd::traj(cmd),
        Cmd::Dyn(a) => dyn_cmd::run(a),
        Cmd::Cell(a) => cell_cmd::run(a),
        Cmd::Check(a) => lang_cmd::check(a),
        Cmd::Run(a) => lang_cmd::run(a),
        Cmd::Compile(a) => lang_cmd::compile(a),
        #[cfg(feature = "plot")]
        Cmd::Plot { cmd } => plot_cmd::plot(cmd),
        #[cfg(not(feature = "plot"))]
        Cmd::Plot(_) => Err(not_built("plot")),
        #[cfg(feature = "serve")]
        Cmd::Serve(a) => serve_cmd::run(a),
        #[cfg(not(feature = "serve"))]
        Cmd::Serve(_) => Err(not_built("serve")),
        #[cfg(feature = "scorbot")]
        Cmd::Scorbot { cmd } => scorbot_cmd::run(cmd),
        #[cfg(not(feature = "scorbot"))]
        Cmd::Scorbot(_) => Err(not_built("scorbot")),
    }
}

fn print_json(v: &impl serde::Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(v)?;
    outln!("{text}")
}

fn robots(as_json: bool) -> Result<()> {
    let all = Robot::builtins()?;
    if as_json {
        let list: Vec<RobotSummary> = all.iter().map(|r| RobotSummary::new(r, false)).collect();
        return print_json(&list);
    }
    outln!("{:<20} {:>3}  {:<8} source", "name", "dof", "joints")?;
    for r in &all {
        outln!("{:<20} {:>3}  {:<8} {}", r.name(), r.dof(), r.joint_types(), r.metadata().source)?;
    }
    Ok(())
}

/// A joint value in display units: degrees for revolute joints, metres for prismatic ones.
fn shown(kind: JointType, v: f64) -> f64 {
    match kind {
        JointType::Revolute => v.to_degrees(),
        JointType::Prismatic => v,
    }
}

fn info(r: &Robot, as_json: bool) -> Result<()> {
    if as_json {
        // The same JSON as the viewer's `GET /api/robots/{name}`.
        return print_json(&RobotInfo::new(r));
    }
    let m = r.metadata();
    outln!("{} — {} DOF ({}), {:?} description", r.name(), r.dof(), r.joint_types(), r.geometry_kind())?;
    if !m.manufacturer.is_empty() {
        outln!("manufacturer: {}", m.manufacturer)?;
    }
    outln!("source: {}", m.source)?;
    outln!("\nlengths in m, angles in deg; revolute θ = q + offset, prismatic d = q + offset")?;
    match r.geometry_kind() {
        kinema::GeometryKind::General => {
            outln!(
                "{:>2} {:<16} {:>4} {:>28} {:>26} {:>22}",
                "i",
                "joint",
                "type",
                "origin xyz",
                "origin rpy",
                "axis"
            )?;
            for (i, j) in r.joints().iter().enumerate() {
                if let LinkGeometry::General { origin, axis } = j.geometry {
                    let rpy = origin.rpy(RpyConvention::Zyx).map(f64::to_degrees);
                    outln!(
                        "{:>2} {:<16} {:>4} {:>8.4} {:>8.4} {:>8.4}  {:>8.2} {:>8.2} {:>8.2}  {:>6.3} {:>6.3} {:>6.3}",
                        i + 1,
                        j.name,
                        j.kind.letter(),
                        origin.pos.x,
                        origin.pos.y,
                        origin.pos.z,
                        rpy[0],
                        rpy[1],
                        rpy[2],
                        axis.x,
                        axis.y,
                        axis.z
                    )?;
                }
            }
        }
        _ => {
            let modified = r.geometry_kind() == kinema::GeometryKind::Modified;
            let (al, aa) = if modified { ("α(i-1)", "a(i-1)") } else { ("α", "a") };
            outln!(
                "{:>2} {:<16} {:>4} {:>9} {:>9} {:>9} {:>9} {:>9}",
                "i",
                "joint",
                "type",
                "θ",
                "d",
                aa,
                al,
                "offset"
            )?;
            for (i, j) in r.joints().iter().enumerate() {
                if let LinkGeometry::Dh { d, a, alpha, theta, .. } = j.geometry {
                    let (th, dd) = match j.kind {
                        JointType::Revolute => (format!("q{}", i + 1), format!("{d:.4}")),
                        JointType::Prismatic => (format!("{:.2}", theta.to_degrees()), format!("q{}", i + 1)),
                    };
                    outln!(
                        "{:>2} {:<16} {:>4} {:>9} {:>9} {:>9.4} {:>9.2} {:>9.4}",
                        i + 1,
                        j.name,
                        j.kind.letter(),
                        th,
                        dd,
                        a,
                        alpha.to_degrees(),
                        shown(j.kind, j.offset)
                    )?;
                }
            }
        }
    }
    outln!("\nlimits (deg or m, per s …; effort in N·m or N)")?;
    for (i, j) in r.joints().iter().enumerate() {
        let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.4}", shown(j.kind, v)));
        outln!(
            "{:>2} {:<16} [{:>10.4}, {:>10.4}]  vel {}  acc {}  jerk {}  effort {}",
            i + 1,
            j.name,
            shown(j.kind, j.limits.min),
            shown(j.kind, j.limits.max),
            opt(j.limits.vel),
            opt(j.limits.acc),
            opt(j.limits.jerk),
            j.limits.effort.map_or("-".to_string(), |v| format!("{v}"))
        )?;
    }
    for (name, p) in [("base", r.base()), ("tool", r.tool())] {
        if *p != Pose::IDENTITY {
            let rpy = p.rpy(RpyConvention::Zyx).map(f64::to_degrees);
            outln!(
                "{name}: xyz = [{:.4}, {:.4}, {:.4}] m, rpy (zyx) = [{:.3}, {:.3}, {:.3}] deg",
                p.pos.x,
                p.pos.y,
                p.pos.z,
                rpy[0],
                rpy[1],
                rpy[2]
            )?;
        }
    }
    outln!("\nnamed poses (deg or m)")?;
    for p in r.poses() {
        let vals: Vec<String> = p.q.iter().zip(r.joints()).map(|(v, j)| format!("{:.4}", shown(j.kind, *v))).collect();
        outln!("  {:<14} [{}]", p.name, vals.join(", "))?;
    }
    if !m.notes.trim().is_empty() {
        outln!("\nnotes:\n{}", m.notes.trim())?;
    }
    Ok(())
}

fn fk(a: FkArgs) -> Result<()> {
    // As `kinema ik`: clap does not enforce --output's `requires` when --q (which conflicts with
    // --input) is given, and a lone --output would be ignored.
    if a.output.is_some() && a.input.is_none() {
        return Err(usage_error(
            "--output needs --input: it is where a batch's poses go (one per line of the --input CSV of \
             configurations); the pose of a single --q is printed (add --json and redirect it to keep it)",
        ));
    }
    let r = a.robot.load()?;
    let conv = a.rpy;
    if let (Some(input), Some(output)) = (&a.input, &a.output) {
        return fk_batch_file(&r, input, output, a.deg, conv);
    }
    let q = crate::input::parse_q(&r, a.q.as_deref().expect("clap requires --q without --input"), a.deg)?;
    let fk = r.fk(&q)?;
    let p = fk.world_from_tool;
    if a.json {
        return print_json(&FkAnswer::new(&r, &q, conv)?);
    }
    outln!("robot {}  q = [{}] (rad/m)", r.name(), q.iter().map(|v| format!("{v:.6}")).collect::<Vec<_>>().join(", "))?;
    outln!("T (base_from_tool):")?;
    for row in p.to_rows() {
        outln!("  [{:>10.6} {:>10.6} {:>10.6} {:>10.6}]", row[0], row[1], row[2], row[3])?;
    }
    let rpy = p.rpy(conv);
    let qq = p.quaternion();
    outln!("position  [m]   x = {:.6}  y = {:.6}  z = {:.6}", p.pos.x, p.pos.y, p.pos.z)?;
    outln!(
        "rpy ({})  [deg] {:.4}, {:.4}, {:.4}   [rad] {:.6}, {:.6}, {:.6}",
        conv,
        rpy[0].to_degrees(),
        rpy[1].to_degrees(),
        rpy[2].to_degrees(),
        rpy[0],
        rpy[1],
        rpy[2]
    )?;
    outln!("quaternion (w, x, y, z) {:.6}, {:.6}, {:.6}, {:.6}", qq.w, qq.i, qq.j, qq.k)?;
    if fk.within_limits() {
        outln!("all joints within limits")?;
    } else {
        for i in fk.out_of_limits.indices() {
            let j = &r.joints()[i];
            outln!(
                "warning: joint {} ({}) = {:.4} is outside its limits [{:.4}, {:.4}] ({})",
                i + 1,
                j.name,
                shown(j.kind, q[i]),
                shown(j.kind, j.limits.min),
                shown(j.kind, j.limits.max),
                if j.kind == JointType::Revolute { "deg" } else { "m" }
            )?;
        }
    }
    Ok(())
}

/// Reads configurations from `input`, writes poses to `output` through a
/// temporary file that is renamed only when everything succeeded.
fn fk_batch_file(r: &Robot, input: &Path, output: &Path, deg: bool, conv: RpyConvention) -> Result<()> {
    let n = r.dof();
    let mut qs: Vec<f64> = Vec::new();
    for (line, vals) in numeric_rows(input)? {
        if vals.len() != n {
            bail!("`{}` line {line}: {} values, but robot `{}` has {n} joints", input.display(), vals.len(), r.name());
        }
        let start = qs.len();
        for (v, j) in vals.iter().zip(r.joints()) {
            qs.push(if deg && j.kind == JointType::Revolute { v.to_radians() } else { *v });
        }
        r.check_q(&qs[start..]).map_err(|e| anyhow::anyhow!("`{}` line {line}: {e}", input.display()))?;
    }
    let rows = qs.len() / n;
    if rows == 0 {
        bail!("`{}` holds no configurations", input.display());
    }
    let bar = progress_bar(rows, "configurations", 200_000);
    let result = write_atomically(output, |out| {
        let mut w = csv::Writer::from_writer(out);
        let rpy_names = match conv {
            RpyConvention::Zyx => ["roll", "pitch", "yaw"],
            RpyConvention::Xyz => ["rx", "ry", "rz"],
        };
        let header = ["x", "y", "z", rpy_names[0], rpy_names[1], rpy_names[2], "qw", "qx", "qy", "qz", "within_limits"];
        w.write_record(header)?;
        const CHUNK: usize = 65_536;
        for chunk in qs.chunks(CHUNK * n) {
            for fk in r.fk_batch(chunk)? {
                let p = fk.world_from_tool;
                let rpy = p.rpy(conv);
                let q = p.quaternion();
                let vals = [p.pos.x, p.pos.y, p.pos.z, rpy[0], rpy[1], rpy[2], q.w, q.i, q.j, q.k];
                let mut rec: Vec<String> = vals.iter().map(|v| format!("{v:.12}")).collect();
                rec.push(fk.within_limits().to_string());
                w.write_record(&rec)?;
            }
            bar.inc((chunk.len() / n) as u64);
        }
        w.flush()?;
        Ok(())
    });
    bar.finish_and_clear();
    result?;
    eprintln!("wrote {rows} poses to {}", output.display());
    Ok(())
}

/// A progress bar on stderr over `len` items, drawn only from `shown_from`
/// items on (short runs finish before it would help).
pub(crate) fn progress_bar(len: usize, items: &str, shown_from: usize) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len as u64);
    let template = format!("{{bar:40}} {{pos}}/{{len}} {items} ({{per_sec}}, eta {{eta}})");
    bar.set_style(indicatif::ProgressStyle::with_template(&template).expect("valid template"));
    if len < shown_from {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    bar
}

/// The rows of numbers of a CSV file (at most [`input::MAX_CSV_BYTES`]),
/// each with its line number: blank lines and `#` comments are skipped, and
/// a first line of names only is a header (one that mixes numbers and names
/// is an error, see [`input::first_row`]).
pub(crate) fn numeric_rows(path: &Path) -> Result<Vec<(u64, Vec<f64>)>> {
    let text = input::read_text_limited(path, input::MAX_CSV_BYTES, "CSV input")?;
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut rows = Vec::new();
    let mut first = true;
    let mut lines = input::LineCounter::new(text.as_bytes());
    for rec in reader.records() {
        let rec = rec.with_context(|| format!("`{}`: not readable as CSV", path.display()))?;
        let line = lines.line_at(rec.position().map_or(0, |p| p.byte()));
        if rec.iter().all(|f| f.is_empty()) {
            continue;
        }
        if std::mem::take(&mut first) && input::first_row(rec.iter(), path, line)? == input::FirstRow::Header {
            continue;
        }
        match rec.iter().map(str::parse::<f64>).collect::<Result<Vec<f64>, _>>() {
            Ok(vals) => rows.push((line, vals)),
            Err(_) => bail!(
                "`{}` line {line}: `{}` is not a list of numbers",
                path.display(),
                rec.iter().collect::<Vec<_>>().join(",")
            ),
        }
    }
    Ok(rows)
}

fn jacobian(a: JacobianArgs) -> Result<()> {
    let r = a.robot.load()?;
    let q = crate::input::parse_q(&r, &a.q.q, a.q.deg)?;
    let answer = match a.analytic {
        Some(c) => JacobianAnswer::analytic(&r, &q, c)?,
        None => JacobianAnswer::geometric(&r, &q, a.frame)?,
    };
    if a.json {
        return print_json(&answer);
    }
    // The analytic Jacobian's lower rows are the rates of the roll-pitch-yaw angles, not ω.
    let labels = match a.analytic {
        Some(_) => ["vx", "vy", "vz", "roll'", "pitch'", "yaw'"],
        None => ["vx", "vy", "vz", "ωx", "ωy", "ωz"],
    };
    let width = labels.iter().map(|l| l.chars().count()).max().unwrap_or(2);
    outln!("robot {}  Jacobian: {}, rows {}", r.name(), answer.kind, labels.join(" "))?;
    for (row, label) in answer.matrix.iter().zip(labels) {
        let vals: Vec<String> = row.iter().map(|v| format!("{v:>10.6}")).collect();
        outln!("  {label:<width$} [{}]", vals.join(" "))?;
    }
    Ok(())
}

fn manip(a: ManipArgs) -> Result<()> {
    let r = a.robot.load()?;
    let q = crate::input::parse_q(&r, &a.q.q, a.q.deg)?;
    let direction = a.direction.as_deref().map(direction_arg).transpose()?;
    let m = ManipAnswer::new(&r, &q, direction)?;
    if a.json {
        return print_json(&m);
    }
    outln!("robot {}", r.name())?;
    outln!("yoshikawa               {:.6e}", m.yoshikawa)?;
    outln!("yoshikawa (translation) {:.6e}", m.yoshikawa_translation)?;
    outln!("yoshikawa (rotation)    {:.6e}", m.yoshikawa_rotation)?;
    outln!("condition number        {}", m.condition.map_or_else(|| "inf (singular)".into(), |c| format!("{c:.6e}")))?;
    outln!("rank                    {} of {} (tolerance {:.3e})", m.rank, r.dof().min(6), m.rank_tolerance)?;
    outln!(
        "singular values         [{}]",
        m.singular_values.iter().map(|v| format!("{v:.6e}")).collect::<Vec<_>>().join(", ")
    )?;
    for d in &m.singular_directions {
        outln!(
            "  lost task direction   [vx vy vz ωx ωy ωz] = [{}]",
            d.iter().map(|v| format!("{v:.4}")).collect::<Vec<_>>().join(", ")
        )?;
    }
    let [t0, t1, t2] = m.ellipsoid_translation.radii;
    outln!("translational ellipsoid radii [{t0:.6}, {t1:.6}, {t2:.6}] m/s per rad/s")?;
    let [r0, r1, r2] = m.ellipsoid_rotation.radii;
    outln!("rotational ellipsoid radii    [{r0:.6}, {r1:.6}, {r2:.6}] rad/s per rad/s")?;
    if let Some(along) = m.manipulability_along {
        outln!("manipulability along direction {:.6}", along)?;
    }
    if m.dependent_joints.is_empty() {
        outln!("no linearly dependent joints")?;
    }
    for d in &m.dependent_joints {
        if d.depends_on.is_empty() {
            outln!("joint {} does not move the tool at this configuration", d.joint)?;
        } else {
            let terms: Vec<String> =
                d.depends_on.iter().map(|c| format!("{:+.4}·q{}", c.coefficient, c.joint)).collect();
            outln!("q{} depends on: {}", d.joint, terms.join(" "))?;
        }
    }
    Ok(())
}

/// `--direction x,y,z`.
fn direction_arg(d: &str) -> Result<kinema::nalgebra::Vector3<f64>> {
    let v: Vec<f64> = d
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--direction `{d}` must be three comma-separated numbers"))?;
    if v.len() != 3 {
        bail!("--direction `{d}` must have 3 components, has {}", v.len());
    }
    Ok(kinema::nalgebra::Vector3::new(v[0], v[1], v[2]))
}

fn bench(a: BenchArgs) -> Result<()> {
    use rand::SeedableRng;
    let r = a.robot.load()?;
    let n = r.dof();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(a.seed);
    let mut qs = vec![0.0; a.n * n];
    for q in qs.chunks_exact_mut(n) {
        r.random_q_into(&mut rng, q);
    }
    const BATCH: usize = 1000;
    let time_batches = |f: &mut dyn FnMut(&[f64])| -> Vec<f64> {
        // Warm-up on the first batches, then one sample per batch of calls.
        for q in qs.chunks_exact(n).take(10 * BATCH) {
            f(q);
        }
        let mut samples: Vec<f64> = qs
            .chunks(BATCH * n)
            .map(|batch| {
                let t = Instant::now();
                for q in batch.chunks_exact(n) {
                    f(q);
                }
                t.elapsed().as_nanos() as f64 / (batch.len() / n) as f64
            })
            .collect();
        samples.sort_by(f64::total_cmp);
        samples
    };
    let mut sink = 0.0;
    let fk = time_batches(&mut |q| {
        sink += std::hint::black_box(r.fk(std::hint::black_box(q)).map(|f| f.world_from_tool.pos.x).unwrap_or(0.0));
    });
    let mut jbuf = Matrix6xX::zeros(n);
    let jac = time_batches(&mut |q| {
        let _ = kinema::kin::jacobian_into(&r, std::hint::black_box(q), Frame::Base, &mut jbuf);
        sink += std::hint::black_box(jbuf[(0, 0)]);
    });
    let t = Instant::now();
    let batch = r.fk_batch(&qs)?;
    let batch_ns = t.elapsed().as_nanos() as f64 / a.n as f64;
    std::hint::black_box((sink, batch.len()));
    let pct = |s: &[f64], p: f64| s[((s.len() - 1) as f64 * p).round() as usize];
    let ik = if a.ik { Some(bench_ik(&r, a.ik_n, a.seed)?) } else { None };
    if a.json {
        let mut v = json!({
            "robot": r.name(), "dof": n, "configurations": a.n, "seed": a.seed,
            "fk_ns": pct(&fk, 0.5), "fk_ns_p10": pct(&fk, 0.1), "fk_ns_p90": pct(&fk, 0.9),
            "jacobian_ns": pct(&jac, 0.5), "jacobian_ns_p10": pct(&jac, 0.1), "jacobian_ns_p90": pct(&jac, 0.9),
            "fk_batch_ns_per_config": batch_ns, "threads": rayon::current_num_threads(),
        });
        if let Some(ik) = &ik {
            v["ik"] = ik.clone();
        }
        return print_json(&v);
    }
    outln!("robot {} ({} DOF), {} random configurations, seed {}", r.name(), n, a.n, a.seed)?;
    outln!("fk        median {:>8.1} ns/call  (p10 {:.1}, p90 {:.1})", pct(&fk, 0.5), pct(&fk, 0.1), pct(&fk, 0.9))?;
    outln!("jacobian  median {:>8.1} ns/call  (p10 {:.1}, p90 {:.1})", pct(&jac, 0.5), pct(&jac, 0.1), pct(&jac, 0.9))?;
    outln!("fk batch         {:>8.1} ns/config on {} threads", batch_ns, rayon::current_num_threads())?;
    if let Some(ik) = ik {
        outln!(
            "numeric ik       {} targets: success {:.3} %, mean {:.1} µs, median {:.1} µs, mean {:.1} iterations, {} restarts in all",
            ik["targets"], ik["success_rate"].as_f64().unwrap_or(0.0) * 100.0, ik["mean_us"].as_f64().unwrap_or(0.0),
            ik["median_us"].as_f64().unwrap_or(0.0), ik["mean_iterations"].as_f64().unwrap_or(0.0), ik["restarts"]
        )?;
    }
    Ok(())
}

/// Times the numeric IK solver on `count` reachable targets: FK of random
/// within-limit configurations (seed `seed + 1`), default options (tolerance
/// 1e-6 m / 1e-6 rad, limits enforced, seeded restarts), started from `home`.
fn bench_ik(r: &Robot, count: usize, seed: u64) -> Result<Value> {
    use kinema::ik::{IkSolver, NumericIk};
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed.wrapping_add(1));
    let targets: Vec<Pose> =
        (0..count).map(|_| r.fk(&r.random_q(&mut rng)).map(|f| f.world_from_tool)).collect::<Result<_, _>>()?;
    let solver = NumericIk::new(r);
    let bar = indicatif::ProgressBar::new(count as u64);
    let (mut ok, mut iters, mut restarts) = (0usize, 0usize, 0usize);
    let mut times = Vec::with_capacity(count);
    for t in &targets {
        let start = Instant::now();
        let res = solver.solve(std::hint::black_box(t));
        times.push(start.elapsed().as_secs_f64() * 1e6);
        if let Ok(s) = res {
            let s = &s[0];
            if s.within_limits() && s.position_error <= 1e-6 && s.orientation_error <= 1e-6 {
                ok += 1;
            }
            if let Some(n) = s.numeric {
                iters += n.iterations;
                restarts += n.restarts;
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mean = times.iter().sum::<f64>() / count as f64;
    times.sort_by(f64::total_cmp);
    Ok(json!({
        "targets": count, "success_rate": ok as f64 / count as f64, "mean_us": mean,
        "median_us": times[count / 2], "p99_us": times[(count * 99 / 100).min(count - 1)],
        "mean_iterations": iters as f64 / ok.max(1) as f64, "restarts": restarts,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every option of every sub-command that takes a value takes `-1` and
    /// `-1e-3` as that value: whatever the error then (a bad value, a missing
    /// argument), it is never "unexpected argument '-1'" (issue 34).
    #[test]
    fn every_option_taking_a_value_takes_a_negative_number() {
        fn walk(cmd: &clap::Command, path: &mut Vec<String>, checked: &mut usize) {
            for arg in cmd.get_arguments() {
                let Some(long) = arg.get_long() else { continue };
                if arg.is_positional() || !arg.get_action().takes_values() {
                    continue;
                }
                // clap reads only plain numbers as values of a many-valued option.
                let many = arg.get_num_args().is_some_and(|r| r.max_values() > 1);
                for value in if many { &["-1"][..] } else { &["-1", "-1e-3"][..] } {
                    let argv: Vec<String> =
                        path.iter().cloned().chain([format!("--{long}"), value.to_string()]).collect();
                    if let Err(e) = parse(argv.iter().map(std::ffi::OsString::from)) {
                        assert_ne!(e.kind(), clap::error::ErrorKind::UnknownArgument, "{argv:?}: {e}");
                    }
                }
                *checked += 1;
            }
            for sub in cmd.get_subcommands().filter(|s| s.get_name() != "help") {
                path.push(sub.get_name().into());
                walk(sub, path, checked);
                path.pop();
            }
        }
        let mut checked = 0;
        walk(&command(), &mut vec!["kinema".into()], &mut checked);
        assert!(checked > 100, "only {checked} options");
    }
}
