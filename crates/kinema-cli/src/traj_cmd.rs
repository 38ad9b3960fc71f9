//! `kinema traj`: time laws and point-to-point motions from the command line.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use kinema::analysis::{yoshikawa, Axes};
use kinema::nalgebra::Matrix6xX;
use kinema::traj::{JointTrajectory, MotionLimits, Profile, Ptp, PtpOptions, TimeLaw};
use kinema::{Frame, Robot, RpyConvention};
use serde_json::json;

use crate::{print_json, write_atomically, RobotArg, RpyArg};

#[derive(Subcommand)]
pub enum TrajCmd {
    /// A normalised time law: its duration and phase times (and, with --dt, samples of s, ṡ, s̈, s⃛).
    Law(LawArgs),
    /// A synchronised point-to-point joint motion (seed 004 §VIII-B), checked against the limits.
    Ptp(PtpArgs),
}

#[derive(Clone, Copy, ValueEnum)]
pub enum ProfileArg {
    /// Trapezoidal velocity (seed 004 eq. 32–37).
    Trapezoid,
    /// Jerk-limited double-S.
    Scurve,
    /// Cubic polynomial.
    Cubic,
    /// Quintic polynomial.
    Quintic,
    /// Constant velocity.
    Linear,
}

impl From<ProfileArg> for Profile {
    fn from(p: ProfileArg) -> Self {
        match p {
            ProfileArg::Trapezoid => Profile::Trapezoid,
            ProfileArg::Scurve => Profile::SCurve,
            ProfileArg::Cubic => Profile::Cubic,
            ProfileArg::Quintic => Profile::Quintic,
            ProfileArg::Linear => Profile::Linear,
        }
    }
}

#[derive(Args)]
pub struct LawArgs {
    /// The law's family.
    #[arg(long, value_enum, default_value = "trapezoid")]
    profile: ProfileArg,
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

#[derive(Args)]
pub struct PtpArgs {
    #[command(flatten)]
    robot: RobotArg,
    /// Start configuration: comma-separated values or a named pose.
    #[arg(long, allow_hyphen_values = true)]
    from: String,
    /// Goal configuration: comma-separated values or a named pose.
    #[arg(long, allow_hyphen_values = true)]
    to: String,
    /// Joint values (and --vmax/--amax/--jmax of revolute joints) in degrees.
    #[arg(long)]
    deg: bool,
    /// The shared law's family.
    #[arg(long, value_enum, default_value = "trapezoid")]
    profile: ProfileArg,
    /// Velocity limits: one value or one per joint (default: the robot's).
    #[arg(long, allow_hyphen_values = true)]
    vmax: Option<String>,
    /// Acceleration limits: one value or one per joint (default: the robot's).
    #[arg(long, allow_hyphen_values = true)]
    amax: Option<String>,
    /// Jerk limits: one value or one per joint (default: the robot's).
    #[arg(long, allow_hyphen_values = true)]
    jmax: Option<String>,
    /// Velocity override in percent (1–100): velocity ×k, acceleration ×k², jerk ×k³.
    #[arg(long, default_value_t = 100.0)]
    speed: f64,
    /// Stretch the motion to this duration [s] (at least the fastest one).
    #[arg(long)]
    duration: Option<f64>,
    /// Sample period [s].
    #[arg(long, default_value_t = 0.01)]
    dt: f64,
    /// Roll-pitch-yaw convention of the pose columns.
    #[arg(long, value_enum, default_value = "zyx")]
    rpy: RpyArg,
    /// Write the samples as CSV (t,q…,qd…,qdd…,x,y,z,roll,pitch,yaw,manipulability).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print a JSON summary (and the samples when --out is not given).
    #[arg(long)]
    json: bool,
}

pub fn traj(cmd: TrajCmd) -> Result<()> {
    match cmd {
        TrajCmd::Law(a) => law(a),
        TrajCmd::Ptp(a) => ptp(a),
    }
}

fn law(a: LawArgs) -> Result<()> {
    let profile: Profile = a.profile.into();
    let law = match (a.duration, a.vmax, a.amax) {
        (Some(t), _, _) => TimeLaw::from_duration(profile, t)?,
        (None, Some(v), Some(acc)) => {
            TimeLaw::from_limits(profile, a.distance, &MotionLimits { vel: v, acc, jerk: a.jmax })?
        }
        _ => bail!("give either --duration T or --vmax V --amax A [--jmax J]"),
    };
    let peaks = law.peaks();
    let scale = if a.duration.is_some() { 1.0 } else { a.distance };
    let finite = |v: f64| if v.is_finite() { json!(v * scale) } else { json!(null) };
    let mut out = json!({
        "profile": profile.name(),
        "distance": scale,
        "duration": law.duration(),
        "phase_times": law.phase_times(),
        "peak_velocity": finite(peaks.sd),
        "peak_acceleration": finite(peaks.sdd),
        "peak_jerk": finite(peaks.sddd),
    });
    match profile {
        Profile::Trapezoid => {
            let p = law.phase_times();
            out["t_acc"] = json!(p.first().copied().unwrap_or(0.0));
            out["t_cruise"] = json!(if p.len() == 3 { p[1] } else { 0.0 });
            out["t_dec"] = json!(p.last().copied().unwrap_or(0.0));
        }
        Profile::SCurve => {
            // Phases: jerk, constant acceleration, jerk, cruise, … (zero-length ones omitted).
            let tj = law.phase_times().first().copied().unwrap_or(0.0);
            out["t_jerk"] = json!(tj);
        }
        _ => {}
    }
    if let Some(dt) = a.dt {
        let times = kinema::traj::sample_times(law.duration(), dt)?;
        let samples: Vec<_> = times
            .iter()
            .map(|&t| {
                let s = law.at(t);
                json!([t, s.s * scale, s.sd * scale, s.sdd * scale, s.sddd * scale])
            })
            .collect();
        out["samples"] = json!({ "columns": ["t", "p", "v", "a", "j"], "rows": samples });
    }
    if a.json {
        return print_json(&out);
    }
    println!("{} law: duration {:.6} s", profile.name(), law.duration());
    println!("phase times [s]: {:?}", law.phase_times());
    println!(
        "peaks: velocity {}, acceleration {}, jerk {}",
        out["peak_velocity"], out["peak_acceleration"], out["peak_jerk"]
    );
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
    let robot = a.robot.load()?;
    let from = robot.parse_q(&a.from, a.deg)?;
    let to = robot.parse_q(&a.to, a.deg)?;
    if !(a.speed > 0.0 && a.speed <= 100.0) {
        bail!("--speed {}: the override must be a percentage in (0, 100]", a.speed);
    }
    let opts = PtpOptions {
        profile: a.profile.into(),
        vel: limits_arg(&robot, a.vmax.as_deref(), a.deg, "vmax")?,
        acc: limits_arg(&robot, a.amax.as_deref(), a.deg, "amax")?,
        jerk: limits_arg(&robot, a.jmax.as_deref(), a.deg, "jmax")?,
        speed: a.speed / 100.0,
        duration: a.duration,
    };
    let plan = Ptp::new(&robot, &from, &to, &opts)?;
    let traj = plan.sample(&robot, a.dt)?;
    let conv: RpyConvention = a.rpy.into();
    let rows = table(&robot, &traj, conv)?;
    if let Some(path) = &a.out {
        write_atomically(path, |out| {
            let mut w = csv::Writer::from_writer(out);
            w.write_record(header(robot.dof(), conv))?;
            for row in &rows {
                w.write_record(row.iter().map(|v| format!("{v:.12}")))?;
            }
            w.flush()?;
            Ok(())
        })?;
        eprintln!("wrote {} samples ({:.4} s) to {}", rows.len(), plan.duration(), path.display());
    }
    let summary = json!({
        "robot": robot.name(),
        "profile": plan.law().profile().name(),
        "duration": plan.duration(),
        "phase_times": plan.law().phase_times(),
        "samples": rows.len(),
    });
    if a.json {
        let mut v = summary;
        if a.out.is_none() {
            v["columns"] = json!(header(robot.dof(), conv));
            v["rows"] = json!(rows);
        }
        return print_json(&v);
    }
    if a.out.is_none() {
        let mut w = csv::Writer::from_writer(std::io::stdout().lock());
        w.write_record(header(robot.dof(), conv))?;
        for row in &rows {
            w.write_record(row.iter().map(|v| format!("{v:.9}")))?;
        }
        w.flush()?;
    } else {
        println!("{} PTP on `{}`: {:.6} s, {} samples", summary["profile"], robot.name(), plan.duration(), rows.len());
    }
    Ok(())
}

/// The CSV header of a sampled trajectory.
pub fn header(n: usize, conv: RpyConvention) -> Vec<String> {
    let mut h = vec!["t".to_string()];
    for prefix in ["q", "qd", "qdd"] {
        h.extend((1..=n).map(|i| format!("{prefix}{i}")));
    }
    let rpy = match conv {
        RpyConvention::Zyx => ["roll", "pitch", "yaw"],
        RpyConvention::Xyz => ["rx", "ry", "rz"],
    };
    h.extend(["x", "y", "z"].iter().chain(&rpy).map(|s| s.to_string()));
    h.push("manipulability".into());
    h
}

/// One row per sample: t, q, q̇, q̈, the tool pose and the translational
/// manipulability (Yoshikawa on the linear-velocity rows, as seed 004 Fig. 30/33).
pub fn table(robot: &Robot, traj: &JointTrajectory, conv: RpyConvention) -> Result<Vec<Vec<f64>>> {
    let mut jac = Matrix6xX::zeros(robot.dof());
    let mut rows = Vec::with_capacity(traj.len());
    for k in 0..traj.len() {
        let q = traj.q(k);
        let fk = robot.jacobian_into(q, Frame::Base, &mut jac)?;
        let mut row = Vec::with_capacity(1 + 3 * robot.dof() + 7);
        row.push(traj.times()[k]);
        row.extend_from_slice(q);
        row.extend_from_slice(traj.qd(k));
        row.extend_from_slice(traj.qdd(k));
        let p = fk.pose;
        row.extend([p.pos.x, p.pos.y, p.pos.z]);
        row.extend(p.rpy(conv));
        row.push(yoshikawa(&jac, Axes::Translation)?);
        rows.push(row);
    }
    Ok(rows)
}
