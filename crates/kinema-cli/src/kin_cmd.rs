//! `kinema fk`, `jacobian` and `manip`: one configuration (or a CSV of them
//! for `fk`) in, the pose, the Jacobian or the manipulability measures out.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use kinema::{Frame, JointType, Robot, RpyConvention};
use kinema_io::{FkAnswer, JacobianAnswer, ManipAnswer};

use crate::info_cmd::shown;
use crate::stdout::outln;
use crate::{by_name, numeric_rows, print_json, progress_bar, usage_error, write_atomically, QArg, RobotArg};

#[derive(Args)]
pub struct FkArgs {
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
    /// Batch mode: only shard i of n (`2/4`: the second of four contiguous blocks of the input's
    /// configurations); the shards' outputs, concatenated in order, are the unsharded output byte for byte.
    #[arg(long, requires = "input")]
    shard: Option<kinema_io::Shard>,
}

#[derive(Args)]
pub struct JacobianArgs {
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
pub struct ManipArgs {
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

pub fn fk(a: FkArgs) -> Result<()> {
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
        return fk_batch_file(&r, input, output, a.deg, conv, a.shard.unwrap_or(kinema_io::Shard::ALL));
    }
    let q = r.parse_q(a.q.as_deref().expect("clap requires --q without --input"), a.deg)?;
    let fk = r.fk(&q)?;
    let p = fk.world_from_tool;
    if a.json {
        return print_json(&FkAnswer::new(&r, &q, conv)?);
    }
    outln!("robot {}  q = [{}] (rad/m)", r.name(), q.iter().map(|v| format!("{v:.6}")).collect::<Vec<_>>().join(", "))?;
    outln!("T (world_from_tool):")?;
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
fn fk_batch_file(
    r: &Robot,
    input: &Path,
    output: &Path,
    deg: bool,
    conv: RpyConvention,
    shard: kinema_io::Shard,
) -> Result<()> {
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
    if qs.is_empty() {
        bail!("`{}` holds no configurations", input.display());
    }
    let block = shard.range(qs.len() / n);
    let rows = block.len();
    let qs = &qs[block.start * n..block.end * n];
    let bar = progress_bar(rows, "configurations", 200_000);
    let result = write_atomically(output, |out| {
        let mut w = csv::Writer::from_writer(out);
        let rpy_names = match conv {
            RpyConvention::Zyx => ["roll", "pitch", "yaw"],
            RpyConvention::Xyz => ["rx", "ry", "rz"],
        };
        let header = ["x", "y", "z", rpy_names[0], rpy_names[1], rpy_names[2], "qw", "qx", "qy", "qz", "within_limits"];
        if shard.writes_header() {
            w.write_record(header)?;
        }
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

pub fn jacobian(a: JacobianArgs) -> Result<()> {
    let r = a.robot.load()?;
    let q = r.parse_q(&a.q.q, a.q.deg)?;
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

pub fn manip(a: ManipArgs) -> Result<()> {
    let r = a.robot.load()?;
    let q = r.parse_q(&a.q.q, a.q.deg)?;
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
