//! `kinema dyn`: the joint torques along a trajectory CSV by inverse dynamics
//! (`kinema::dynamics::rnea`), checked against the robot's motor limits.

use crate::stdout::outln;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use kinema::nalgebra::Vector3;
use kinema::{dynamics, JointType, Robot};

use crate::output::is_stdout;
use crate::{traj_cmd, write_atomically, RobotArg};

/// Relative slack on the effort limits, as `traj check` allows on its limits:
/// a torque computed at exactly the limit must not fail by rounding.
const SLACK: f64 = 1e-9;

/// Violations listed in full; the rest are counted (as `kinema traj check` does).
const SHOWN: usize = 20;

#[derive(Args)]
pub struct DynArgs {
    #[command(flatten)]
    robot: RobotArg,
    /// The trajectory CSV: a header with t and q1..qn, optionally qd1..qdn and qdd1..qddn (what
    /// `kinema traj …` writes); missing rates are differentiated from q; other columns are ignored.
    file: PathBuf,
    /// Gravity in the world frame [m/s²], three comma-separated values.
    #[arg(long, allow_hyphen_values = true, default_value = "0,0,-9.81")]
    gravity: String,
    /// Where to write the torques (CSV t,tau1..taun, N·m or N); `-` or none: standard output.
    #[arg(long, short)]
    out: Option<PathBuf>,
}

/// A torque beyond its joint's effort limit.
struct Violation {
    sample: usize,
    time: f64,
    joint: usize,
    torque: f64,
    limit: f64,
    unit: &'static str,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "t = {:.4} s (sample {}): joint {} torque {:.6} {u} exceeds its effort limit {:.6} {u}",
            self.time,
            self.sample,
            self.joint + 1,
            self.torque,
            self.limit,
            u = self.unit
        )
    }
}

/// `kinema dyn`: writes the torque CSV, then reports the effort violations
/// (exit code 1 when there are any, as `kinema traj check`; the CSV is written
/// either way so that the violations can be looked at).
pub fn run(a: DynArgs) -> Result<()> {
    let robot = a.robot.load()?;
    let gravity = gravity_arg(&a.gravity)?;
    // A robot without mass properties fails before the file is read, with the
    // core's error naming the first such link.
    if robot.inertials().iter().any(Option::is_none) {
        dynamics::gravity_torques(&robot, robot.home(), &gravity)?;
    }
    let samples = traj_cmd::read_samples(&robot, &a.file)?;
    let traj = &samples.traj;
    let file = a.file.display();
    let times = traj.times();
    for (k, &t) in times.iter().enumerate() {
        let line = samples.lines[k];
        if !t.is_finite() {
            bail!("`{file}` line {line}: t = {t}; times must be finite numbers [s]");
        }
        if k > 0 && t <= times[k - 1] {
            bail!(
                "`{file}` line {line}: t = {t} does not increase (the previous sample has t = {}); \
                 times must strictly increase",
                times[k - 1]
            );
        }
    }
    let n = robot.dof();
    let mut rows = Vec::with_capacity(traj.len());
    for (k, (t, line)) in times.iter().zip(&samples.lines).enumerate() {
        let tau = dynamics::rnea(&robot, traj.q(k), traj.qd(k), traj.qdd(k), &gravity)
            .with_context(|| format!("`{file}` line {line} (t = {t})"))?;
        rows.push(tau);
    }
    let violations = check(&robot, times, &rows);

    let out = a.out.as_deref().filter(|p| !is_stdout(p));
    write_atomically(out.unwrap_or(Path::new("-")), |w| {
        let mut w = csv::Writer::from_writer(w);
        let mut header = vec!["t".to_string()];
        header.extend((1..=n).map(|i| format!("tau{i}")));
        w.write_record(&header)?;
        for (t, tau) in times.iter().zip(&rows) {
            w.write_record(std::iter::once(format!("{t}")).chain(tau.iter().map(|v| format!("{v:.9}"))))?;
        }
        w.flush()?;
        Ok(())
    })?;

    // The report goes to stdout only when stdout does not carry the CSV.
    let mut report = vec![format!(
        "{file}: {} samples on `{}`, {} effort violation(s); q̇ {}, q̈ {}",
        traj.len(),
        robot.name(),
        violations.len(),
        source(samples.given.0),
        source(samples.given.1)
    )];
    let unchecked: Vec<String> = robot
        .joints()
        .iter()
        .enumerate()
        .filter(|(_, j)| j.limits.effort.is_none())
        .map(|(i, _)| (i + 1).to_string())
        .collect();
    if unchecked.len() == n {
        report.push(format!("  robot `{}` has no effort limits: nothing checked", robot.name()));
    } else if !unchecked.is_empty() {
        report.push(format!("  joint(s) {} have no effort limit: not checked", unchecked.join(", ")));
    }
    report.extend(violations.iter().take(SHOWN).map(|v| format!("  {v}")));
    if violations.len() > SHOWN {
        report.push(format!("  … and {} more", violations.len() - SHOWN));
    }
    if let Some(path) = out {
        eprintln!("wrote {} samples of {n} torques to {}", rows.len(), path.display());
        outln!("{}", report.join("\n"))?;
    } else {
        eprintln!("{}", report.join("\n"));
    }
    if violations.is_empty() {
        Ok(())
    } else {
        Err(crate::Exit(1).into())
    }
}

/// Where q̇ or q̈ came from, for the report.
fn source(given: bool) -> &'static str {
    if given {
        "from the file"
    } else {
        "differentiated from q in time (central differences, one-sided at the ends)"
    }
}

/// Every |τ_i| above joint i's effort limit, in time order.
fn check(robot: &Robot, times: &[f64], rows: &[Vec<f64>]) -> Vec<Violation> {
    let mut out = Vec::new();
    for (k, (time, tau)) in times.iter().zip(rows).enumerate() {
        for (i, (j, torque)) in robot.joints().iter().zip(tau).enumerate() {
            let Some(limit) = j.limits.effort else { continue };
            if torque.abs() > limit * (1.0 + SLACK) {
                let unit = if j.kind == JointType::Prismatic { "N" } else { "N·m" };
                out.push(Violation { sample: k, time: *time, joint: i, torque: *torque, limit, unit });
            }
        }
    }
    out
}

/// `--gravity x,y,z` [m/s²].
fn gravity_arg(text: &str) -> Result<Vector3<f64>> {
    let v = text
        .split(',')
        .map(|s| {
            let s = s.trim();
            let x: f64 = s.parse().with_context(|| format!("--gravity: `{s}` is not a number"))?;
            if !x.is_finite() {
                bail!("--gravity: {x} is not a finite number");
            }
            Ok(x)
        })
        .collect::<Result<Vec<f64>>>()?;
    if v.len() != 3 {
        bail!("--gravity: {} value(s) given, expected three (x,y,z in m/s², e.g. 0,0,-9.81)", v.len());
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}
