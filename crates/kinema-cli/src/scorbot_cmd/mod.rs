//! `kinema scorbot`: the Scorbot-ER V Plus on real hardware (seed 000 §III-B,
//! §IV-B) — encoder counts, the controller simulator, a client for the real
//! controller, tracking metrics and calibration.

use crate::stdout::outln;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use kinema::Robot;
use kinema_scorbot::acl::Client;
use kinema_scorbot::encoder::Constants;
use kinema_scorbot::follow::{self, PlanOptions, SendMode};
use kinema_scorbot::sim::{self, Fault, SimConfig};
use kinema_scorbot::{calib, metrics};
mod answers;
mod connect;
use answers::{AnglesAnswer, CountsAnswer, ExperimentAnswer, ExperimentModel, FollowPlanAnswer, WhereAnswer};
use connect::connect;

use crate::input::{read_text_limited, MAX_CSV_BYTES, MAX_TEXT_BYTES};
use crate::print_json;

/// The model the subcommands work with.
const ROBOT: &str = "scorbot-er-v-plus";

#[derive(Subcommand)]
pub enum ScorbotCmd {
    /// Motor encoder counts for joint angles (seed 000 eq. 24), with the tool-position uncertainty.
    Counts(CountsArgs),
    /// Joint angles and tool position for motor encoder counts (eq. 24 inverted).
    Angles(AnglesArgs),
    /// Run the controller simulator on a pseudo-terminal or a TCP port (Ctrl-C to stop).
    Sim(SimArgs),
    /// Talk to a controller (or the simulator): home, move, follow a path, where, abort.
    Connect(ConnectArgs),
    /// Tracking accuracy of measured paths: seed 000's mean error and ISO 9283 AT_p, RT_p, AP_p, RP_p.
    Track(TrackArgs),
    /// Estimate the encoder constants from commanded counts and measured tool positions.
    Calibrate(CalibrateArgs),
    /// Seed 000 Fig. 6 on the simulator: a square (or --path) planned with each model's constants,
    /// followed, recorded with camera noise and scored.
    Square(SquareArgs),
}

#[derive(Args)]
pub struct ConstantsArg {
    /// Encoder constants: `factory` (Tabla II/III factory columns), `calibrated` (the seed's calibrated
    /// counts per degree and measured home offsets), `CPD/HOME` (e.g. `factory/measured`), or a .toml file.
    #[arg(long, default_value = "calibrated")]
    constants: String,
}

impl ConstantsArg {
    fn load(&self) -> Result<Constants> {
        load_constants(&self.constants)
    }
}

/// A preset name, or a constants `.toml` file of at most
/// [`MAX_TEXT_BYTES`] (as `Constants::load`, with the size limit).
fn load_constants(spec: &str) -> Result<Constants> {
    if spec.ends_with(".toml") {
        let text = read_text_limited(std::path::Path::new(spec), MAX_TEXT_BYTES, "constants file")?;
        Ok(Constants::from_toml(&text, spec)?)
    } else {
        Ok(Constants::named(spec)?)
    }
}

/// The points of a CSV with columns x, y, z, read with the size limit.
fn read_points(path: &std::path::Path) -> Result<Vec<kinema::nalgebra::Vector3<f64>>> {
    let text = read_text_limited(path, MAX_CSV_BYTES, "CSV input")?;
    Ok(metrics::parse_points_csv(&text, &path.display().to_string())?)
}

/// A path CSV for `follow`: the library reads it from its path, so the size
/// limit is checked here first, and only a regular file has a size to check.
fn read_path(path: &std::path::Path, deg: bool) -> Result<Vec<follow::PathPoint>> {
    check_regular_file(path, MAX_CSV_BYTES, "path CSV")?;
    Ok(follow::read_path_csv(path, deg)?)
}

/// For a file that a library reads from its path: an error unless `path`
/// is a regular file of at most `max` bytes (a FIFO or a device has no size
/// to check, and `/dev/zero` never ends).
fn check_regular_file(path: &std::path::Path, max: u64, what: &str) -> Result<()> {
    let m = std::fs::metadata(path).with_context(|| format!("cannot read {what} `{}`", path.display()))?;
    if !m.is_file() {
        bail!("cannot read {what} `{}`: it is not a regular file", path.display());
    }
    if m.len() > max {
        bail!("{what} `{}` is larger than the limit of {}", path.display(), crate::input::size_text(max));
    }
    Ok(())
}

#[derive(Args)]
pub struct CountsArgs {
    /// Joint values θ1…θ5, comma-separated (rad, or degrees with --deg), or a named pose such as `home`.
    #[arg(long, allow_hyphen_values = true)]
    q: String,
    /// The joint values are in degrees.
    #[arg(long)]
    deg: bool,
    #[command(flatten)]
    constants: ConstantsArg,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct AnglesArgs {
    /// Motor counts c1…c5, comma-separated.
    #[arg(long, allow_hyphen_values = true)]
    counts: String,
    /// Print the angles in degrees.
    #[arg(long)]
    deg: bool,
    #[command(flatten)]
    constants: ConstantsArg,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct SimArgs {
    /// Serve on a new pseudo-terminal and print its device path.
    #[arg(long, conflicts_with = "tcp", required_unless_present = "tcp")]
    pty: bool,
    /// Serve on this TCP address (e.g. 127.0.0.1:7777; port 0 picks a free one).
    #[arg(long)]
    tcp: Option<String>,
    /// Multiply every motion's duration by this (1 = nominal: homing 5 s, moves of seconds).
    #[arg(long, default_value_t = 1.0)]
    time_scale: f64,
    /// Inject a fault: drop@CMD, garble@CMD, delay=SECONDS@CMD or disconnect@CMD, each optionally #N
    /// for the N-th such command (e.g. garble@LISTPV#2). Repeatable.
    #[arg(long = "fault")]
    faults: Vec<String>,
    /// The constants stored in the simulated controller (used for its limits and Cartesian coordinates).
    #[arg(long, default_value = "factory")]
    constants: String,
    /// The constants of the simulated physical arm (where it really goes for given counts).
    #[arg(long, default_value = "calibrated")]
    true_constants: String,
    /// Record the physical tool position during motions (an external camera) to this CSV (x,y,z in m).
    #[arg(long)]
    record: Option<PathBuf>,
    /// Measurement noise of the recording, standard deviation per axis [mm].
    #[arg(long, default_value_t = 0.0)]
    noise_mm: f64,
    /// Seed of the recording noise.
    #[arg(long, default_value_t = 0, value_parser = crate::seed)]
    seed: u64,
}

#[derive(Args)]
pub struct ConnectArgs {
    /// Serial device of the controller (9600 baud, 8N1, no flow control), e.g. /dev/ttyUSB0.
    #[arg(long, conflicts_with = "tcp", required_unless_present = "tcp")]
    port: Option<String>,
    /// TCP address of the controller (a serial-to-network bridge or `kinema scorbot sim --tcp`).
    #[arg(long)]
    tcp: Option<String>,
    /// Longest wait for a reply (and for a command's echo) [s].
    #[arg(long, default_value_t = 3.0)]
    timeout: f64,
    /// Longest wait for a motion to end [s].
    #[arg(long, default_value_t = 120.0)]
    motion_timeout: f64,
    #[command(flatten)]
    constants: ConstantsArg,
    #[command(subcommand)]
    action: Action,
}

#[derive(Clone, Copy, ValueEnum)]
enum ModeArg {
    /// A position vector and one smooth MOVES.
    Vector,
    /// One MOVED per point.
    Points,
}

#[derive(Subcommand)]
enum Action {
    /// Home the arm (HOME) and wait until it is done.
    Home,
    /// Move to joint angles (MOVED), converted to counts with --constants.
    Move {
        /// Joint values θ1…θ5, comma-separated (rad, or degrees with --deg), or a named pose.
        #[arg(long, allow_hyphen_values = true)]
        q: String,
        /// The joint values are in degrees.
        #[arg(long)]
        deg: bool,
        /// Duration [s] (default: from the controller's speed).
        #[arg(long)]
        time: Option<f64>,
    },
    /// Follow a Cartesian path: CSV with x,y,z [m] and optional pitch, roll columns.
    Follow {
        /// The path CSV.
        path: PathBuf,
        /// The pitch and roll columns are in degrees (default radians).
        #[arg(long)]
        deg: bool,
        /// Largest step between points after resampling [m] (seed 000: 1 cm).
        #[arg(long, default_value_t = follow::SEED_MAX_STEP)]
        max_step: f64,
        /// How to send the points.
        #[arg(long, value_enum, default_value = "vector")]
        mode: ModeArg,
        /// Duration of the whole path (vector) or of each step (points) [s].
        #[arg(long)]
        time: Option<f64>,
        /// Print the plan and send nothing.
        #[arg(long)]
        dry_run: bool,
    },
    /// Print where the arm is: counts, joint angles, tool position.
    Where {
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Stop any motion (A).
    Abort,
}

#[derive(Args)]
pub struct TrackArgs {
    /// The desired path: CSV with columns x,y,z [m].
    #[arg(long)]
    desired: PathBuf,
    /// Measured paths (one file per repetition): CSV with columns x,y,z [m].
    #[arg(long, num_args = 1.., required = true)]
    measured: Vec<PathBuf>,
    /// Print JSON (metres).
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct CalibrateArgs {
    /// Samples: CSV with columns c1,c2,c3,c4,c5 (commanded counts) and x,y,z (measured tool position, m).
    #[arg(long)]
    data: PathBuf,
    /// Starting constants (a preset or a .toml file).
    #[arg(long, default_value = "factory")]
    initial: String,
    /// Also estimate the link lengths.
    #[arg(long)]
    links: bool,
    /// Write the estimated constants to this .toml file (usable with --constants).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum PlaneArg {
    /// Horizontal: x and y vary.
    Xy,
    /// Vertical through the base axis (seed 000 Fig. 6): x and z vary.
    Xz,
    /// Vertical across the arm: y and z vary.
    Yz,
}

#[derive(Args)]
pub struct SquareArgs {
    /// The plane of the square.
    #[arg(long, value_enum, default_value = "xz")]
    plane: PlaneArg,
    /// Centre of the square "x,y,z" [m].
    #[arg(long, default_value = "0.35,0,0.30", allow_hyphen_values = true)]
    center: String,
    /// Side of the square [m].
    #[arg(long, default_value_t = 0.10)]
    side: f64,
    /// Pitch β of the tool along the square (seed 000 eq. 13) [rad, or degrees with --deg]; default 60°.
    #[arg(long, allow_hyphen_values = true)]
    pitch: Option<f64>,
    /// Roll γ of the tool [rad, or degrees with --deg]; default 0.
    #[arg(long, allow_hyphen_values = true)]
    roll: Option<f64>,
    /// --pitch, --roll and the path's pitch and roll columns are in degrees.
    #[arg(long)]
    deg: bool,
    /// Follow this path instead of a square: CSV with x,y,z [m] and optional pitch, roll columns.
    #[arg(long, conflicts_with_all = ["center", "side", "pitch", "roll"])]
    path: Option<PathBuf>,
    /// The models to compare: comma-separated constants (presets such as `factory`, `calibrated`,
    /// `CPD/HOME`, or .toml files), each used to plan the path.
    #[arg(long, default_value = "factory,calibrated")]
    models: String,
    /// The constants the simulated arm really moves by.
    #[arg(long, default_value = "calibrated")]
    true_constants: String,
    /// The constants stored in the simulated controller (its limits and speeds).
    #[arg(long, default_value = "factory")]
    constants: String,
    /// Repetitions per model (seed 000 Fig. 6: 2).
    #[arg(long, default_value_t = 2, value_parser = crate::count(1, 1000))]
    runs: usize,
    /// Measurement noise, standard deviation per coordinate [mm] (the seed's camera: about 1 mm).
    #[arg(long, default_value_t = 1.0)]
    noise_mm: f64,
    /// Seed of the measurement noise.
    #[arg(long, default_value_t = 0, value_parser = crate::seed)]
    seed: u64,
    /// Largest step between the points sent [m] (seed 000: 1 cm).
    #[arg(long, default_value_t = follow::SEED_MAX_STEP)]
    max_step: f64,
    /// Write desired.csv and one CSV per run (LABEL-N.csv, x,y,z in m) into this directory.
    #[arg(long)]
    out_dir: Option<PathBuf>,
    /// Print JSON (metres).
    #[arg(long)]
    json: bool,
}

pub(crate) fn run(cmd: ScorbotCmd) -> Result<()> {
    match cmd {
        ScorbotCmd::Counts(a) => counts(a),
        ScorbotCmd::Angles(a) => angles(a),
        ScorbotCmd::Sim(a) => sim_run(a),
        ScorbotCmd::Connect(a) => connect(a),
        ScorbotCmd::Track(a) => track(a),
        ScorbotCmd::Calibrate(a) => calibrate(a),
        ScorbotCmd::Square(a) => square(a),
    }
}

fn robot() -> Result<Robot> {
    Ok(Robot::builtin(ROBOT)?)
}

fn parse_list(text: &str, what: &str, n: usize) -> Result<Vec<f64>> {
    let v = text
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|_| anyhow::anyhow!("{what}: `{}` is not a number", t.trim())))
        .collect::<Result<Vec<f64>>>()?;
    if v.len() != n {
        bail!("{what}: {} values given; expected {n}", v.len());
    }
    Ok(v)
}

fn limits_text(robot: &Robot, q: &[f64]) -> Vec<String> {
    robot
        .limit_flags(q)
        .indices()
        .map(|j| {
            let l = &robot.joints()[j].limits;
            format!(
                "joint {} ({}) = {:.2}° outside [{:.0}°, {:.0}°]",
                j + 1,
                robot.joints()[j].name,
                q[j].to_degrees(),
                l.min.to_degrees(),
                l.max.to_degrees()
            )
        })
        .collect()
}

fn counts(a: CountsArgs) -> Result<()> {
    let robot = robot()?;
    let c = a.constants.load()?;
    let q = robot.parse_q(&a.q, a.deg)?;
    let exact = c.counts(&q)?;
    let counts = c.counts_rounded(&q)?;
    let u = c.tool_uncertainty(&robot, &q)?;
    let p = robot.fk(&q)?.world_from_tool.pos;
    let outside = limits_text(&robot, &q);
    if a.json {
        return print_json(&CountsAnswer {
            constants: c.name.clone(),
            q,
            counts,
            counts_exact: exact,
            tool_position: [p.x, p.y, p.z],
            tool_sigma: u.sigma,
            tool_sigma_radius: u.radius,
            out_of_limits: outside,
        });
    }
    outln!("constants: {}", c.name)?;
    outln!("counts    {}", counts.map(|v| v.to_string()).join("  "))?;
    outln!("tool      x {:.2}  y {:.2}  z {:.2} mm", p.x * 1e3, p.y * 1e3, p.z * 1e3)?;
    if u.radius > 0.0 {
        outln!(
            "tool 1σ   x {:.2}  y {:.2}  z {:.2} mm  (radius {:.2} mm, from the constants' ± columns)",
            u.sigma[0] * 1e3,
            u.sigma[1] * 1e3,
            u.sigma[2] * 1e3,
            u.radius * 1e3
        )?;
    } else {
        outln!("tool 1σ   not known (these constants have no uncertainties)")?;
    }
    for o in outside {
        outln!("warning: {o}")?;
    }
    Ok(())
}

fn angles(a: AnglesArgs) -> Result<()> {
    let robot = robot()?;
    let c = a.constants.load()?;
    let counts = parse_list(&a.counts, "--counts", 5)?;
    let q = c.angles(&counts)?;
    let p = robot.fk(&q)?.world_from_tool.pos;
    let outside = limits_text(&robot, &q);
    let shown: Vec<f64> = if a.deg { q.iter().map(|v| v.to_degrees()).collect() } else { q.to_vec() };
    if a.json {
        return print_json(&AnglesAnswer {
            constants: c.name.clone(),
            counts,
            q: shown,
            unit: if a.deg { "deg" } else { "rad" },
            tool_position: [p.x, p.y, p.z],
            out_of_limits: outside,
        });
    }
    outln!("constants: {}", c.name)?;
    outln!(
        "q         {}  {}",
        shown.iter().map(|v| format!("{v:.6}")).collect::<Vec<_>>().join("  "),
        if a.deg { "deg" } else { "rad" }
    )?;
    outln!("tool      x {:.2}  y {:.2}  z {:.2} mm", p.x * 1e3, p.y * 1e3, p.z * 1e3)?;
    for o in outside {
        outln!("warning: {o}")?;
    }
    Ok(())
}

fn sim_run(a: SimArgs) -> Result<()> {
    if !(a.time_scale.is_finite() && a.time_scale > 0.0 && a.time_scale <= 1e6) {
        bail!("--time-scale {}: it must be > 0 and ≤ 1e6 (1 = nominal durations)", a.time_scale);
    }
    if !(a.noise_mm.is_finite() && a.noise_mm >= 0.0) {
        bail!("--noise-mm {}: it must be a finite number ≥ 0", a.noise_mm);
    }
    let faults = a
        .faults
        .iter()
        .map(|f| f.parse::<Fault>().with_context(|| format!("--fault {f}")))
        .collect::<Result<Vec<_>>>()?;
    let config = SimConfig {
        constants: load_constants(&a.constants).context("--constants")?,
        true_constants: load_constants(&a.true_constants).context("--true-constants")?,
        time_scale: a.time_scale,
        faults,
        record: a.record,
        noise: a.noise_mm * 1e-3,
        seed: a.seed,
    };
    let stop = Arc::new(AtomicBool::new(false));
    if let Some(addr) = a.tcp {
        let listener = std::net::TcpListener::bind(&addr).with_context(|| format!("cannot listen on {addr}"))?;
        outln!("kinema scorbot sim: tcp {}", listener.local_addr()?)?;
        eprintln!("simulated Controller-A (ACL, Scorbot-ER V Plus); Ctrl-C to stop");
        sim::serve_tcp(listener, config, stop)?;
    } else {
        let pty = sim::PtySim::open(config)?;
        outln!("kinema scorbot sim: pty {}", pty.path())?;
        eprintln!("simulated Controller-A (ACL, Scorbot-ER V Plus); Ctrl-C to stop");
        pty.run(stop)?;
    }
    Ok(())
}

fn seconds_to_hundredths(s: Option<f64>, what: &str) -> Result<Option<u32>> {
    s.map(|s| {
        if !(s.is_finite() && s > 0.0 && s <= 3600.0) {
            bail!("{what} {s}: a duration in seconds, > 0 and ≤ 3600");
        }
        Ok((s * 100.0).round().max(1.0) as u32)
    })
    .transpose()
}

fn track(a: TrackArgs) -> Result<()> {
    let desired = read_points(&a.desired)?;
    let runs = a.measured.iter().map(|m| read_points(m)).collect::<Result<Vec<_>>>()?;
    let r = metrics::track(&desired, &runs, &metrics::TrackOptions::default())?;
    if a.json {
        return print_json(&serde_json::to_value(&r)?);
    }
    let mm = |v: f64| format!("{:.3} mm", v * 1e3);
    let opt = |v: Option<f64>| v.map_or("— (needs two or more runs)".to_string(), mm);
    outln!("{} measured run(s) against a desired path, {} evaluation points", r.runs, r.points)?;
    outln!(
        "mean error (seed 000)   {} ± {}   runs: {}",
        mm(r.mean_error),
        mm(r.mean_error_spread),
        r.run_mean_errors.iter().map(|v| mm(*v)).collect::<Vec<_>>().join(", ")
    )?;
    outln!("ISO 9283 AT_p            {}", mm(r.at_p))?;
    outln!("ISO 9283 RT_p            {}", opt(r.rt_p))?;
    outln!("ISO 9283 AP_p (end pose) {}", mm(r.ap_p))?;
    outln!("ISO 9283 RP_p (end pose) {}", opt(r.rp_p))?;
    if r.fallback_points > 0 {
        outln!(
            "note: at {} evaluation point(s) a run did not cross the normal plane nearby; its nearest point was used",
            r.fallback_points
        )?;
    }
    Ok(())
}

fn calibrate(a: CalibrateArgs) -> Result<()> {
    let robot = robot()?;
    let text = read_text_limited(&a.data, MAX_CSV_BYTES, "CSV input")?;
    let samples = calib::parse_samples_csv(&text, &a.data.display().to_string())?;
    let options = calib::CalibrationOptions {
        initial: load_constants(&a.initial).context("--initial")?,
        estimate_links: a.links,
        ..calib::CalibrationOptions::default()
    };
    let c = calib::calibrate(&robot, &samples, &options)?;
    if let Some(out) = &a.out {
        let text = c.constants.to_toml();
        crate::write_atomically(out, |w| {
            use std::io::Write;
            w.write_all(text.as_bytes())?;
            Ok(())
        })?;
        eprintln!("wrote the estimated constants to {}", out.display());
    }
    if a.json {
        return print_json(&serde_json::to_value(&c)?);
    }
    outln!(
        "{} samples, {} iterations, rms residual {:.3} mm, max {:.3} mm, condition {:.1}",
        c.samples,
        c.iterations,
        c.rms_residual * 1e3,
        c.max_residual * 1e3,
        c.condition_number
    )?;
    outln!("{:<12} {:>14} {:>12} {:>14}  unit", "parameter", "estimate", "1σ", "initial")?;
    for p in &c.parameters {
        outln!("{:<12} {:>14.4} {:>12.4} {:>14.4}  {}", p.name, p.value, p.sigma, p.initial, p.unit)?;
    }
    Ok(())
}

/// A label usable in a file name: the constants' preset name or file stem,
/// with anything but letters, digits, `-` and `_` replaced by `-`.
fn file_label(spec: &str) -> String {
    let stem = if spec.ends_with(".toml") {
        std::path::Path::new(spec).file_stem().map_or(spec.to_string(), |s| s.to_string_lossy().into_owned())
    } else {
        spec.to_string()
    };
    stem.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '-' }).collect()
}

fn square(a: SquareArgs) -> Result<()> {
    use kinema::nalgebra::Vector3;
    use kinema_scorbot::experiment::{self, ExperimentOptions, Model, Plane};
    if !(a.noise_mm.is_finite() && (0.0..=1000.0).contains(&a.noise_mm)) {
        bail!("--noise-mm {}: it must be a finite number from 0 to 1000", a.noise_mm);
    }
    if !(a.max_step.is_finite() && a.max_step > 0.0) {
        bail!("--max-step {}: it must be a positive length in metres", a.max_step);
    }
    let robot = robot()?;
    let angle = |v: f64| if a.deg { v.to_radians() } else { v };
    let (path, what) = match &a.path {
        Some(p) => (read_path(p, a.deg)?, format!("the path of {}", p.display())),
        None => {
            let c = parse_list(&a.center, "--center", 3)?;
            let plane = match a.plane {
                PlaneArg::Xy => Plane::Xy,
                PlaneArg::Xz => Plane::Xz,
                PlaneArg::Yz => Plane::Yz,
            };
            let pitch = a.pitch.map_or(60f64.to_radians(), angle);
            let roll = a.roll.map_or(0.0, angle);
            let sq = experiment::square(plane, Vector3::new(c[0], c[1], c[2]), a.side, pitch, roll)?;
            let what = format!(
                "a {:.0} mm square in the {plane} plane centred at ({:.3}, {:.3}, {:.3}) m, pitch {:.1}°, roll {:.1}°",
                a.side * 1e3,
                c[0],
                c[1],
                c[2],
                pitch.to_degrees(),
                roll.to_degrees()
            );
            (sq, what)
        }
    };
    let specs: Vec<&str> = a.models.split(',').map(str::trim).filter(|s| !s.is_empty()).collect();
    if specs.is_empty() {
        bail!("--models: give at least one set of constants, e.g. factory,calibrated");
    }
    let models = specs
        .iter()
        .map(|s| {
            Ok(Model { label: file_label(s), constants: load_constants(s).with_context(|| format!("--models {s}"))? })
        })
        .collect::<Result<Vec<_>>>()?;
    let options = ExperimentOptions {
        models,
        controller: load_constants(&a.constants).context("--constants")?,
        truth: load_constants(&a.true_constants).context("--true-constants")?,
        runs: a.runs,
        noise: a.noise_mm * 1e-3,
        seed: a.seed,
        max_step: a.max_step,
        ..ExperimentOptions::default()
    };
    let e = experiment::run(&robot, &path, &options)?;
    if let Some(dir) = &a.out_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let write = |name: String, points: &[Vector3<f64>]| -> Result<()> {
            crate::write_atomically(&dir.join(name), |w| {
                use std::io::Write;
                writeln!(w, "x,y,z")?;
                for p in points {
                    writeln!(w, "{:.6},{:.6},{:.6}", p.x, p.y, p.z)?;
                }
                Ok(())
            })
        };
        write("desired.csv".into(), &e.desired)?;
        for m in &e.models {
            for (k, r) in m.runs.iter().enumerate() {
                write(format!("{}-{}.csv", m.label, k + 1), r)?;
            }
        }
    }
    if a.json {
        return print_json(&ExperimentAnswer {
            path: what,
            desired_points: e.desired.len(),
            true_constants: options.truth.name.clone(),
            controller_constants: options.controller.name.clone(),
            noise: options.noise,
            seed: options.seed,
            models: e
                .models
                .iter()
                .map(|m| ExperimentModel {
                    label: &m.label,
                    branch: &m.branch,
                    samples: m.runs.iter().map(Vec::len).collect(),
                    report: &m.report,
                })
                .collect(),
        });
    }
    outln!(
        "seed 000 Fig. 6 on the controller simulator: {what}, {} points ≤ {:.0} mm apart",
        e.desired.len(),
        a.max_step * 1e3
    )?;
    outln!("the arm moves by `{}`; controller constants `{}`", options.truth.name, options.controller.name)?;
    outln!(
        "measured = the simulated tool path every 10 ms + Gaussian noise σ = {:.3} mm per axis (seed {})",
        a.noise_mm,
        a.seed
    )?;
    let mm = |v: f64| format!("{:.3}", v * 1e3);
    outln!(
        "{:<14} {:>4}  {:>22}  {:>9}  {:>9}  runs (mean error, mm)",
        "model",
        "runs",
        "mean error ± spread mm",
        "AT_p mm",
        "RT_p mm"
    )?;
    for m in &e.models {
        let r = &m.report;
        outln!(
            "{:<14} {:>4}  {:>22}  {:>9}  {:>9}  {}",
            m.label,
            r.runs,
            format!("{} ± {}", mm(r.mean_error), mm(r.mean_error_spread)),
            mm(r.at_p),
            r.rt_p.map_or("—".into(), mm),
            r.run_mean_errors.iter().map(|v| mm(*v)).collect::<Vec<_>>().join(", ")
        )?;
    }
    if let Some(dir) = &a.out_dir {
        eprintln!("wrote desired.csv and the runs to {}", dir.display());
    }
    Ok(())
}
