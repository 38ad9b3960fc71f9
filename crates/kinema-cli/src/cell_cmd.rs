//! `kinema cell FILE`: several robots in one world on a common clock (seed 004
//! §VIII-E): each robot placed by its base pose, each running its own joint
//! trajectory (a CSV file) or program, each checked as `kinema traj check`
//! checks, the distance between every two tools over time, and how close the
//! robots' link shapes come to each other and to the file's `[[obstacle]]`s
//! (between samples too).
//!
//! The cell file (TOML; every path in it relative to the file's folder):
//!
//! ```toml
//! dt = 0.01                 # sample period of the common clock [s] (default 0.01)
//! min_distance = "100mm"    # optional: the tools must stay at least this far apart
//! rpy = "zyx"               # base orientations: zyx (R = Rz(yaw)·Ry(pitch)·Rx(roll), default) | xyz
//!
//! [[robot]]
//! name = "holder"                       # letters, digits and `_`; unique
//! robot = "lbr-iiwa-14-r820"            # built-in name or a .toml/.urdf description
//! base = { xyz = [0, 0, 0], rpy = [0, 0, 0] }   # where its own world frame sits in the cell's
//! program = "holder.prg"                # or trajectory = "holder.csv" (t, q1..qn, …)
//! start = "home"                        # programs only: the joints at the start
//! ```
//!
//! Numbers are SI (m, rad, s); a string gives a unit: `"100mm"`, `"180deg"`.

use crate::stdout::outln;
use std::collections::HashSet;
use std::ops::Range;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use kinema::quantity::{parse_with_unit, Dim, Quantity};
use kinema::traj::cell::{placed, Approach};
use kinema::traj::{check, Cell, CellReport, CheckOptions, CheckReport, JointTrajectory, SINGULAR_WARNING};
use kinema::{Pose, Robot, RpyConvention};
use kinema_geometry::{closest_approaches, load_shapes_or_none, Body, BodyApproach, RobotGeometry, Scene, UrdfOptions};
use kinema_io::{CellAnswer, CellMember};
use kinema_lang::{render_all, Options, Stop};
use serde::Deserialize;
use toml::Spanned;

use crate::input::{read_text_limited, MAX_TEXT_BYTES};
use crate::{print_json, traj_cmd, write_atomically, Exit};

/// Exit code when two tools come closer than the minimum distance (and no
/// robot's trajectory breaks its limits, which is exit code 1).
pub(crate) const EXIT_TOO_CLOSE: u8 = 3;

/// The sample period of the common clock when neither the file nor `--dt` gives one [s].
const DEFAULT_DT: f64 = 0.01;

/// The most samples of the common clock times robots: 10 000 000, a couple of
/// gigabytes of joint values, poses and distances for 7-joint arms.
const MAX_ROBOT_SAMPLES: usize = 10_000_000;

#[derive(Args)]
pub struct CellArgs {
    /// The cell description (TOML): robots with their base poses and motions (a joint
    /// trajectory CSV or a program), the clock's sample period, a minimum tool distance. The clock
    /// runs to the end of the longest motion; a robot that has finished holds its last configuration.
    file: PathBuf,
    /// Where to write the samples (CSV: t, per robot q1..qn, tool x, y, z in the world frame and
    /// translational manipulability, then the distance of every pair); `-` for standard output.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print a JSON summary: per-robot checks, closest approach per pair, duration.
    #[arg(long)]
    json: bool,
    /// Exit with code 3 when two tools come closer than this (overrides the file's
    /// `min_distance`): a length in m, or with a unit (`0.1m`, `100mm`).
    #[arg(long, value_parser = length_arg)]
    min_distance: Option<f64>,
    /// Sample period of the common clock [s] (overrides the file's `dt`; default 0.01). Programs
    /// are sampled at it too.
    #[arg(long)]
    dt: Option<f64>,
    /// Stop the programs after this many seconds in all, wall clock; `inf` for no limit.
    /// Ctrl-C stops them at any time.
    #[arg(long, value_name = "SECONDS", default_value_t = crate::lang_cmd::DEFAULT_TIME_LIMIT)]
    time_limit: f64,
    /// For a URDF robot: directories holding the packages of its `package://` meshes
    /// (ROS_PACKAGE_PATH is added). A robot whose meshes cannot be read gets no link distances.
    #[arg(long = "package-path", value_name = "DIR")]
    package_path: Vec<PathBuf>,
}

fn length_arg(text: &str) -> Result<f64, String> {
    let v = parse_with_unit(text, Dim::Length)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("`{text}` must be a finite length ≥ 0"))
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CellFile {
    dt: Option<Spanned<Quantity>>,
    min_distance: Option<Spanned<Quantity>>,
    rpy: Option<RpyConvention>,
    #[serde(default)]
    robot: Vec<Spanned<MemberSpec>>,
    /// Obstacles, read by the scene reader (`kinema_geometry::Scene`).
    #[serde(default)]
    obstacle: Vec<toml::Value>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MemberSpec {
    name: Spanned<String>,
    robot: String,
    tip: Option<String>,
    base: Option<BaseSpec>,
    trajectory: Option<Spanned<String>>,
    program: Option<Spanned<String>>,
    start: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BaseSpec {
    xyz: Option<[Spanned<Quantity>; 3]>,
    rpy: Option<[Spanned<Quantity>; 3]>,
}

/// The file being read, for errors `file:line:col: `field`: message`.
struct Src<'a> {
    file: &'a str,
    text: &'a str,
}

impl Src<'_> {
    fn err(&self, span: Range<usize>, field: &str, message: impl std::fmt::Display) -> anyhow::Error {
        let mut at = span.start.min(self.text.len());
        while !self.text.is_char_boundary(at) {
            at -= 1;
        }
        let before = &self.text[..at];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        anyhow::anyhow!("{}:{line}:{col}: `{field}`: {message}", self.file)
    }

    fn value(&self, q: &Spanned<Quantity>, dim: Dim, field: &str) -> Result<f64> {
        q.get_ref().si(dim, 1.0).map_err(|m| self.err(q.span(), field, m))
    }
}

/// Where a member's joint values come from.
enum Motion {
    Trajectory(PathBuf),
    Program(PathBuf),
}

/// One robot of the cell, loaded and checked.
struct Member {
    name: String,
    spec: String,
    motion: Motion,
    base: Pose,
    robot: Robot,
    /// Its link shapes (none when its description has none).
    geometry: RobotGeometry,
    traj: JointTrajectory,
    check: CheckReport,
}

/// The cell file read: the clock, the minimum distance, the members and the obstacles.
struct Loaded {
    dt: f64,
    min_distance: Option<f64>,
    members: Vec<Member>,
    scene: Option<Scene>,
}

/// Whether a signal arrived (then the error to return: nothing is written).
fn check_interrupted() -> Result<()> {
    if crate::interrupt::interrupted() {
        eprintln!("cancelled (Ctrl-C); nothing was written");
        return Err(Exit(crate::interrupt::EXIT_INTERRUPTED).into());
    }
    Ok(())
}

fn load(a: &CellArgs) -> Result<Loaded> {
    let text = read_text_limited(&a.file, MAX_TEXT_BYTES, "cell file")?;
    let file = a.file.display().to_string();
    let src = Src { file: &file, text: &text };
    let de = toml::Deserializer::parse(&text)
        .map_err(|e| src.err(e.span().unwrap_or(0..0), "(syntax)", e.message().trim()))?;
    let parsed: CellFile = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string().replace(".$__serde_spanned_private_value", "");
        let inner = e.into_inner();
        let field = if path == "." { "(top level)".to_string() } else { path };
        src.err(inner.span().unwrap_or(0..0), &field, inner.message().trim())
    })?;
    // Empty for a file in the current folder: paths in it then read as given.
    let dir = a.file.parent().map_or_else(PathBuf::new, Path::to_path_buf);

    let dt = match (a.dt, &parsed.dt) {
        (Some(dt), _) => dt,
        (None, Some(q)) => src.value(q, Dim::Time, "dt")?,
        (None, None) => DEFAULT_DT,
    };
    if !(dt.is_finite() && dt > 0.0) {
        let m = format!("the sample period must be a time > 0, not {dt} s");
        return Err(match (&a.dt, &parsed.dt) {
            (None, Some(q)) => src.err(q.span(), "dt", m),
            _ => anyhow::anyhow!("--dt: {m}"),
        });
    }
    let min_distance = match (a.min_distance, &parsed.min_distance) {
        (Some(d), _) => Some(d),
        (None, Some(q)) => {
            let d = src.value(q, Dim::Length, "min_distance")?;
            if d < 0.0 {
                return Err(src.err(q.span(), "min_distance", format!("a distance must be ≥ 0, not {d} m")));
            }
            Some(d)
        }
        (None, None) => None,
    };
    let conv = parsed.rpy.unwrap_or_default();
    if parsed.robot.is_empty() {
        return Err(src.err(0..0, "robot", "no [[robot]] tables: a cell needs at least one robot"));
    }

    let stop = crate::lang_cmd::program_stop(a.time_limit)?;
    let mut names = HashSet::new();
    let mut members = Vec::with_capacity(parsed.robot.len());
    for (i, spanned) in parsed.robot.iter().enumerate() {
        let m = spanned.get_ref();
        let field = |f: &str| format!("robot[{i}].{f}");
        let name = m.name.get_ref().clone();
        if name.is_empty()
            || !name.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
            || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        {
            return Err(src.err(
                m.name.span(),
                &field("name"),
                format!(
                    "`{name}`: a name starts with a letter and has only letters, digits and `_` (it names CSV columns)"
                ),
            ));
        }
        if !names.insert(name.clone()) {
            return Err(src.err(m.name.span(), &field("name"), format!("`{name}` names two robots")));
        }
        let world_from_robot = match &m.base {
            None => Pose::IDENTITY,
            Some(b) => {
                let mut xyz = [0.0; 3];
                let mut rpy = [0.0; 3];
                for (k, q) in b.xyz.iter().flatten().enumerate() {
                    xyz[k] = src.value(q, Dim::Length, &field(&format!("base.xyz[{k}]")))?;
                }
                for (k, q) in b.rpy.iter().flatten().enumerate() {
                    rpy[k] = src.value(q, Dim::Angle, &field(&format!("base.rpy[{k}]")))?;
                }
                Pose::from_xyz_rpy(xyz, rpy, conv)
            }
        };
        let here = || format!("{file}: robot `{name}` (robot[{i}])");
        let robot = load_robot(&m.robot, m.tip.as_deref(), &dir).with_context(here)?;
        let geometry = load_shapes(&m.robot, m.tip.as_deref(), &dir, &a.package_path).with_context(here)?;
        let robot = placed(&robot, &world_from_robot).with_context(here)?;
        let (motion, robot, traj, opts) = match (&m.trajectory, &m.program) {
            (Some(t), None) => {
                if let Some(s) = &m.start {
                    return Err(src.err(
                        s.span(),
                        &field("start"),
                        "`start` is for a program; a trajectory starts where its first sample is",
                    ));
                }
                let path = dir.join(t.get_ref());
                let (traj, (value_resolution, time_resolution)) =
                    traj_cmd::read_trajectory_with_resolution(&robot, &path).with_context(here)?;
                let opts = CheckOptions { value_resolution, time_resolution, ..check_options() };
                (Motion::Trajectory(path), robot, traj, opts)
            }
            (None, Some(p)) => {
                let path = dir.join(p.get_ref());
                let start = match &m.start {
                    Some(s) => {
                        Some(robot.parse_q(s.get_ref(), false).map_err(|e| src.err(s.span(), &field("start"), e))?)
                    }
                    None => None,
                };
                let plan = run_program(&path, &robot, dt, start, stop.clone()).with_context(here)?;
                (Motion::Program(path), plan.robot, plan.trajectory, check_options())
            }
            (Some(_), Some(p)) => {
                return Err(src.err(p.span(), &field("program"), "give `trajectory` or `program`, not both"))
            }
            (None, None) => {
                return Err(src.err(
                    spanned.span(),
                    &field("trajectory"),
                    format!(
                        "robot `{name}` has no motion: give `trajectory = \"file.csv\"` or `program = \"file.prg\"`"
                    ),
                ))
            }
        };
        check_interrupted()?;
        let report = check(&robot, &traj, &opts).with_context(here)?;
        members.push(Member {
            name,
            spec: m.robot.clone(),
            motion,
            base: world_from_robot,
            robot,
            geometry,
            traj,
            check: report,
        });
    }
    // The scene reader reads the file's obstacles (and ignores what is a cell's only).
    let scene = if parsed.obstacle.is_empty() { None } else { Some(Scene::load(&a.file)?) };
    Ok(Loaded { dt, min_distance, members, scene })
}

/// What every member is checked with: the robot's limits, singular passages
/// as warnings, as `kinema traj check` does by default.
fn check_options() -> CheckOptions<'static> {
    CheckOptions { singular_warning: Some(SINGULAR_WARNING), ..CheckOptions::default() }
}

/// A built-in name, else a description path relative to the cell file's folder.
fn load_robot(spec: &str, tip: Option<&str>, dir: &Path) -> Result<Robot> {
    if kinema::builtin_source(spec).is_some() {
        return crate::load_robot(spec, tip);
    }
    let path = dir.join(spec);
    crate::load_robot(&path.to_string_lossy(), tip)
}

/// The link shapes of the robot `spec` (as [`load_robot`] finds it); none,
/// with a warning, when a mesh of it cannot be read.
fn load_shapes(spec: &str, tip: Option<&str>, dir: &Path, package_paths: &[PathBuf]) -> Result<RobotGeometry> {
    let spec =
        if kinema::builtin_source(spec).is_some() { spec.to_string() } else { dir.join(spec).to_string_lossy().into() };
    let options =
        UrdfOptions { tip: tip.map(str::to_string), package_paths: package_paths.to_vec(), skip_visual: true };
    let (geometry, skipped) = load_shapes_or_none(&spec, &options)?;
    if let Some(e) = skipped {
        eprintln!("warning: `{spec}`: no link distances for this robot: {e}");
    }
    Ok(geometry)
}

/// How close the robots' link shapes come to each other and to the obstacles, over the run.
fn body_approaches(cell: &Loaded, report: &CellReport) -> Result<Vec<BodyApproach>> {
    let bodies = cell
        .members
        .iter()
        .map(|m| Body::new(&m.name, m.robot.clone(), m.geometry.clone(), cell.scene.as_ref()))
        .collect::<kinema_geometry::Result<Vec<Body>>>()?;
    Ok(closest_approaches(&bodies, &report.times, &report.q)?)
}

/// Compiles and runs a program on the robot as placed in the cell (its
/// Cartesian targets are in the cell's world frame); diagnostics on stderr.
fn run_program(path: &Path, robot: &Robot, dt: f64, start: Option<Vec<f64>>, stop: Stop) -> Result<kinema_lang::Plan> {
    let src = read_text_limited(path, MAX_TEXT_BYTES, "program")?;
    let opts = Options { dt, start, stop, ..Options::default() };
    let name = path.display().to_string();
    match kinema_lang::compile(&src, robot, &opts) {
        Ok(plan) => {
            if !plan.warnings.is_empty() {
                eprint!("{}", render_all(&plan.warnings, &name, &src));
            }
            Ok(plan)
        }
        Err(diags) => {
            eprint!("{}", render_all(&diags, &name, &src));
            check_interrupted()?;
            crate::lang_cmd::note_time_limit(&diags);
            bail!("the program `{name}` does not run (the errors are above)")
        }
    }
}

/// The CSV header: t; per robot NAME_q1..NAME_qn, NAME_x, NAME_y, NAME_z, NAME_manipulability;
/// per pair d_A_B.
fn header(members: &[Member], report: &CellReport) -> Vec<String> {
    let mut h = vec!["t".to_string()];
    for m in members {
        h.extend((1..=m.robot.dof()).map(|k| format!("{}_q{k}", m.name)));
        h.extend(["x", "y", "z", "manipulability"].iter().map(|c| format!("{}_{c}", m.name)));
    }
    h.extend(report.distances.iter().map(|((i, j), _)| format!("d_{}_{}", members[*i].name, members[*j].name)));
    h
}

fn write_csv(out: &Path, members: &[Member], report: &CellReport) -> Result<()> {
    write_atomically(out, |w| {
        let mut w = csv::Writer::from_writer(w);
        w.write_record(header(members, report))?;
        let mut row: Vec<f64> = Vec::new();
        for (k, t) in report.times.iter().enumerate() {
            row.clear();
            row.push(*t);
            for m in 0..members.len() {
                row.extend_from_slice(&report.q[m][k]);
                let p = report.tools[m][k].pos;
                row.extend([p.x, p.y, p.z, report.manipulability[m][k]]);
            }
            row.extend(report.distances.iter().map(|(_, d)| d[k]));
            w.write_record(row.iter().map(|v| format!("{v:.12}")))?;
        }
        w.flush()?;
        Ok(())
    })
}

fn summary(a: &CellArgs, cell: &Loaded, report: &CellReport) -> CellAnswer {
    let members: Vec<CellMember<'_>> = cell
        .members
        .iter()
        .map(|m| {
            let (trajectory, program) = match &m.motion {
                Motion::Trajectory(p) => (Some(p.display().to_string()), None),
                Motion::Program(p) => (None, Some(p.display().to_string())),
            };
            CellMember {
                name: &m.name,
                robot: &m.spec,
                dof: m.robot.dof(),
                trajectory,
                program,
                base: &m.base,
                check: &m.check,
            }
        })
        .collect();
    CellAnswer::new(Some(a.file.display().to_string()), cell.dt, cell.min_distance, &members, report)
}

fn print_text(
    a: &CellArgs,
    cell: &Loaded,
    report: &CellReport,
    approaches: &[Approach],
    bodies: &[BodyApproach],
) -> Result<()> {
    let duration = report.times.last().copied().unwrap_or(0.0);
    outln!(
        "{}: {} robot(s), {duration:.4} s, {} samples every {} s",
        a.file.display(),
        cell.members.len(),
        report.times.len(),
        cell.dt
    )?;
    for (m, member) in cell.members.iter().enumerate() {
        let from = match &member.motion {
            Motion::Trajectory(p) | Motion::Program(p) => p.display().to_string(),
        };
        let end = report.ends[m];
        let holds = if end < duration { ", then holds its last configuration" } else { "" };
        outln!(
            "  {} ({}, {from}): ends at {end:.4} s{holds}; {} violation(s), {} warning(s)",
            member.name,
            member.spec,
            member.check.violations.len(),
            member.check.warnings.len()
        )?;
        for v in member.check.violations.iter().take(20) {
            outln!("    {v}")?;
        }
        if member.check.violations.len() > 20 {
            outln!("    … and {} more", member.check.violations.len() - 20)?;
        }
        for w in member.check.warnings.iter().take(20) {
            outln!("    warning: {w}")?;
        }
    }
    for ap in approaches {
        let (i, j) = ap.pair;
        let mut line = format!(
            "  {}–{}: closest {:.4} m at t = {:.4} s",
            cell.members[i].name, cell.members[j].name, ap.distance, ap.time
        );
        if let Some(min) = cell.min_distance {
            let spans = report.closer_than(i, j, min);
            if spans.is_empty() {
                line += &format!(" (minimum {min} m: ok)");
            } else {
                let list: Vec<String> = spans.iter().map(|(s, e)| format!("{s:.4}–{e:.4} s")).collect();
                line += &format!("; closer than {min} m during {}", list.join(", "));
            }
        }
        outln!("{line}")?;
    }
    for b in bodies {
        let (i, j) = b.robots;
        let other = j.map_or("the scene", |j| cell.members[j].name.as_str());
        let (la, lb) = &b.closest;
        outln!(
            "  {} and {other}, link shapes: closest {:.4} m at t = {:.4} s ({la} – {lb}){}",
            cell.members[i].name,
            b.distance,
            b.time,
            if b.distance > 0.0 { "" } else { ": in contact" }
        )?;
    }
    Ok(())
}

/// The cell file read and run on its common clock.
fn simulate(a: &CellArgs) -> Result<(Loaded, CellReport)> {
    let loaded = load(a)?;
    let mut cell = Cell::new();
    for m in &loaded.members {
        cell.add(m.name.clone(), m.robot.clone(), m.traj.clone())
            .with_context(|| format!("{}: robot `{}`", a.file.display(), m.name))?;
    }
    let end = loaded.members.iter().filter_map(|m| m.traj.times().last().copied()).fold(0.0, f64::max);
    let samples = kinema::traj::sample_count(end, loaded.dt)?;
    if samples.saturating_mul(loaded.members.len()) > MAX_ROBOT_SAMPLES {
        bail!(
            "{}: the common clock would take {samples} samples of {} s for {} robot(s), above the limit of {MAX_ROBOT_SAMPLES} \
             robot samples; give a larger dt",
            a.file.display(),
            loaded.dt,
            loaded.members.len()
        );
    }
    let report = cell.run(loaded.dt).with_context(|| format!("{}: the common clock", a.file.display()))?;
    Ok((loaded, report))
}

/// A cell's robot as the viewer draws it: its name, the robot placed on its base, its link shapes.
#[cfg(feature = "serve")]
pub(crate) type ViewerMember = (String, Robot, RobotGeometry);

/// A cell file as `kinema serve --cell` plays it: each robot (placed on its
/// base) with its link shapes, the report of the common clock, and the
/// file's obstacles (its robots are the members, not obstacles).
#[cfg(feature = "serve")]
pub(crate) fn for_viewer(file: &Path) -> Result<(Vec<ViewerMember>, CellReport, Option<Scene>)> {
    let a = CellArgs {
        file: file.to_path_buf(),
        out: None,
        json: false,
        min_distance: None,
        dt: None,
        time_limit: crate::lang_cmd::DEFAULT_TIME_LIMIT,
        package_path: Vec::new(),
    };
    let (loaded, report) = simulate(&a)?;
    let scene = loaded.scene.map(|s| Scene { robots: Vec::new(), ..s });
    let members = loaded.members.into_iter().map(|m| (m.name, m.robot, m.geometry)).collect();
    Ok((members, report, scene))
}

pub fn run(a: CellArgs) -> Result<()> {
    if a.json && a.out.as_deref().is_some_and(crate::output::is_stdout) {
        bail!("--json with --out -: the JSON summary and the CSV would both go to standard output; write the CSV to a file");
    }
    // The first Ctrl-C stops a program run or the cell between steps; a second one ends the process.
    let _cancellable = crate::interrupt::cancellable();
    let (loaded, report) = simulate(&a)?;
    check_interrupted()?;
    let approaches = report.approaches();
    let bodies = body_approaches(&loaded, &report).with_context(|| format!("{}: link shapes", a.file.display()))?;
    // The link search does not poll the flag; a Ctrl-C during it still writes nothing.
    check_interrupted()?;
    if let Some(out) = &a.out {
        write_csv(out, &loaded.members, &report)?;
        if !crate::output::is_stdout(out) {
            eprintln!("wrote {} samples to {}", report.times.len(), out.display());
        }
    }
    if a.json {
        let names: Vec<&str> = loaded.members.iter().map(|m| m.name.as_str()).collect();
        print_json(&summary(&a, &loaded, &report).with_bodies(&names, &bodies))?;
    } else if !a.out.as_deref().is_some_and(crate::output::is_stdout) {
        print_text(&a, &loaded, &report, &approaches, &bodies)?;
    }
    let violations = loaded.members.iter().filter(|m| !m.check.violations.is_empty()).count();
    if violations > 0 {
        eprintln!("error: the trajectory of {violations} robot(s) breaks its limits (see the check above)");
        return Err(Exit(1).into());
    }
    if let Some(b) = bodies.iter().filter(|b| b.distance <= 0.0).min_by(|x, y| x.time.total_cmp(&y.time)) {
        let (i, j) = b.robots;
        let other = j.map_or("the scene".to_string(), |j| format!("`{}`", loaded.members[j].name));
        eprintln!(
            "error: `{}` touches {other} at t = {:.4} s ({} – {})",
            loaded.members[i].name, b.time, b.closest.0, b.closest.1
        );
        return Err(Exit(EXIT_TOO_CLOSE).into());
    }
    if let Some(min) = loaded.min_distance {
        let close: Vec<&Approach> = approaches.iter().filter(|ap| ap.distance < min).collect();
        if let Some(ap) = close.iter().min_by(|x, y| x.distance.total_cmp(&y.distance)) {
            let (i, j) = ap.pair;
            eprintln!(
                "error: the tools of `{}` and `{}` come {:.4} m close at t = {:.4} s, below the minimum of {min} m ({} pair(s) too close)",
                loaded.members[i].name,
                loaded.members[j].name,
                ap.distance,
                ap.time,
                close.len()
            );
            return Err(Exit(EXIT_TOO_CLOSE).into());
        }
    }
    Ok(())
}
