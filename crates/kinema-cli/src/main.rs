//! The `kinema` command: parse arguments, call the library, print.

use crate::stdout::outln;
use std::path::Path;
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand};
use kinema::{Named, Robot};

pub(crate) use body::BodyArgs;

pub(crate) use output::write_atomically;

mod bench_cmd;
mod body;
mod cell_cmd;
mod collide_cmd;
mod dyn_cmd;
mod ik_cmd;
mod info_cmd;
mod input;
mod interrupt;
mod kin_cmd;
mod lang_cmd;
mod output;
mod place_cmd;
mod plan_cmd;
#[cfg(feature = "plot")]
mod plot_cmd;
mod reach_cmd;
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
    Fk(kin_cmd::FkArgs),
    /// Geometric Jacobian (rows vx vy vz ωx ωy ωz) at a configuration.
    Jacobian(kin_cmd::JacobianArgs),
    /// Manipulability, condition number, rank, singular values and dependent joints.
    Manip(kin_cmd::ManipArgs),
    /// Inverse kinematics: joint values that reach a target pose (exit code 2 if unreachable).
    Ik(ik_cmd::IkArgs),
    /// Round-trip validation of a robot's analytic IK (seed 004 §V-C): random q → FK → IK → q.
    IkValidate(ik_cmd::ValidateArgs),
    /// iiwa self-motion: configurations and elbow positions that keep the tool pose of --q.
    Selfmotion(ik_cmd::SelfMotionArgs),
    /// Time FK and the Jacobian (and, with --ik, inverse kinematics) over random configurations.
    Bench(bench_cmd::BenchArgs),
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
    /// Self-collision and collision with a scene's obstacles at a configuration (or a CSV of them):
    /// the colliding pairs and the closest pair (exit code 3 on a collision).
    Collide(collide_cmd::CollideArgs),
    /// A collision-free joint motion to a configuration or a tool pose, around the robot itself and a
    /// scene's obstacles (RRT-Connect, shortcut, timed within the limits).
    Plan(plan_cmd::PlanArgs),
    /// A capability map: per voxel around the robot, how many sampled tool orientations it reaches
    /// within its limits (collision-free with --scene), on all cores.
    Reach(reach_cmd::ReachArgs),
    /// Inverse reachability: candidate base positions on a floor grid ranked by how many poses of a
    /// task the robot standing there reaches, on all cores.
    Place(place_cmd::PlaceArgs),
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
pub(crate) struct RobotArg {
    /// A built-in robot name (see `kinema robots`), a .toml description or a .urdf file.
    #[arg(long, short)]
    pub(crate) robot: String,
    /// For a URDF: the tip link of the chain (default: the only leaf link).
    #[arg(long)]
    pub(crate) tip: Option<String>,
}

impl RobotArg {
    fn load(&self) -> Result<Robot> {
        load_robot(&self.robot, self.tip.as_deref())
    }
}

/// [`Robot::load`], with what the loader left out or chose printed on stderr.
pub(crate) fn load_robot(spec: &str, tip: Option<&str>) -> Result<Robot> {
    let robot = Robot::load(spec, tip)?;
    print_load_warnings(spec, &robot);
    Ok(robot)
}

/// What the loader of `spec` left out or chose, on stderr.
pub(crate) fn print_load_warnings(spec: &str, robot: &Robot) {
    for w in &robot.metadata().warnings {
        eprintln!("warning: {spec}: {w}");
    }
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
        Cmd::Robots { json } => info_cmd::robots(json),
        Cmd::Info { robot, json } => info_cmd::info(&robot.load()?, json),
        Cmd::Fk(a) => kin_cmd::fk(a),
        Cmd::Jacobian(a) => kin_cmd::jacobian(a),
        Cmd::Manip(a) => kin_cmd::manip(a),
        Cmd::Ik(a) => ik_cmd::ik(a),
        Cmd::IkValidate(a) => ik_cmd::validate(a),
        Cmd::Selfmotion(a) => ik_cmd::selfmotion(a),
        Cmd::Bench(a) => bench_cmd::bench(a),
        Cmd::Traj { cmd } => traj_cmd::traj(cmd),
        Cmd::Dyn(a) => dyn_cmd::run(a),
        Cmd::Cell(a) => cell_cmd::run(a),
        Cmd::Collide(a) => collide_cmd::run(a),
        Cmd::Plan(a) => plan_cmd::run(a),
        Cmd::Reach(a) => reach_cmd::run(a),
        Cmd::Place(a) => place_cmd::run(a),
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
