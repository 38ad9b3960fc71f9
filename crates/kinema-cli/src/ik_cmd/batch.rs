//! `kinema ik --input targets.csv --output q.csv`: many targets, one
//! solution each, solved on all cores by the core's `ik::solve_batch` (the
//! same contract and pick as a single `kinema ik`).

use std::io::Write;
use std::path::Path;

use anyhow::{bail, Result};
use kinema::ik::{IkTarget, Solution};
use kinema::nalgebra::Matrix4;
use kinema::{Error, JointType, Pose, Robot};
use kinema_io::Shard;

use super::{request, IkArgs};
use crate::{numeric_rows, write_atomically, Exit};

/// One line of the input: its line number and its target, or why the
/// numbers are not one.
pub(crate) type Row = (u64, std::result::Result<IkTarget, String>);

/// One line of the output: its line number and the solver's name with the
/// solution, or why there is none.
type Answer<'a> = (u64, std::result::Result<(&'a str, Solution), String>);

pub(super) fn run(
    a: &IkArgs,
    robot: &Robot,
    input: &Path,
    output: &Path,
    admissible: Option<&dyn kinema::ik::Admissible>,
) -> Result<()> {
    let shard = a.shard.unwrap_or(Shard::ALL);
    let rows = shard.take(read_targets(a, input)?);
    let q0 = a.q0.as_deref().map(|t| robot.parse_q(t, a.deg)).transpose()?;
    let request = request(a, q0.as_deref(), admissible)?;
    let targets: Vec<IkTarget> = rows.iter().filter_map(|(_, t)| t.clone().ok()).collect();
    let bar = crate::progress_bar(targets.len(), "targets", 2_000);
    // Ctrl-C stops the solvers between targets (the rest come back
    // cancelled); nothing is written then.
    let cancellable = crate::interrupt::cancellable();
    let solved = kinema::ik::solve_batch(robot, &targets, &request, &|| bar.inc(1), &crate::interrupt::interrupted)?;
    bar.finish_and_clear();
    drop(cancellable);
    if solved.iter().any(|r| matches!(r, Err(Error::Cancelled))) {
        eprintln!("interrupted; nothing written");
        return Err(Exit(crate::interrupt::EXIT_INTERRUPTED).into());
    }
    let mut solved = solved.into_iter();
    let results: Vec<Answer> = rows
        .into_iter()
        .map(|(line, target)| {
            let result = match target {
                Ok(_) => solved.next().expect("one result per target").map_err(|e| reason(&e)),
                Err(why) => Err(why),
            };
            (line, result)
        })
        .collect();
    write_atomically(output, |out| write_results(out, robot, a.deg, &results, shard.writes_header()))?;
    let failed = results.iter().filter(|(_, r)| r.is_err()).count();
    eprintln!("solved {} of {} targets; wrote {}", results.len() - failed, results.len(), output.display());
    if failed > 0 {
        eprintln!("{failed} target(s) not solved: their lines say why (status unreachable or invalid)");
        return Err(Exit(2).into());
    }
    Ok(())
}

/// An error of one target, as its line's reason.
fn reason(e: &Error) -> String {
    match e {
        Error::Unreachable { .. } => format!("unreachable: {e}"),
        other => format!("invalid: {other}"),
    }
}

/// The targets of `input`: 16 numbers (a 4×4 row-major matrix), 6
/// (x, y, z, roll, pitch, yaw in the convention of --rpy, angles in degrees
/// with --deg) or 3 (a position) per line.
fn read_targets(a: &IkArgs, input: &Path) -> Result<Vec<Row>> {
    read_target_rows(input, a.rpy, a.deg)
}

/// The rows of an `--input` CSV of targets, angles in the convention `conv`
/// (in degrees when `deg`); shared with `kinema place`'s task file.
pub(crate) fn read_target_rows(input: &Path, conv: kinema::RpyConvention, deg: bool) -> Result<Vec<Row>> {
    let ang = |v: f64| if deg { v.to_radians() } else { v };
    let mut rows = Vec::new();
    for (line, v) in numeric_rows(input)? {
        if let Some(x) = v.iter().find(|x| !x.is_finite()) {
            bail!("`{}` line {line}: {x} is not a finite number", input.display());
        }
        let target = match v.len() {
            16 => Pose::from_matrix(&Matrix4::from_row_slice(&v))
                .map(IkTarget::Pose)
                .ok_or_else(|| "invalid: not a rigid transform (last row 0 0 0 1, a rotation block)".to_string()),
            6 => Ok(IkTarget::Pose(Pose::from_xyz_rpy([v[0], v[1], v[2]], [ang(v[3]), ang(v[4]), ang(v[5])], conv))),
            3 => Ok(IkTarget::Position([v[0], v[1], v[2]])),
            n => bail!(
                "`{}` line {line}: {n} numbers; expected 16 (a 4×4 matrix, row-major), 6 (x,y,z,roll,pitch,yaw) \
                 or 3 (x,y,z)",
                input.display()
            ),
        };
        rows.push((line, target));
    }
    if rows.is_empty() {
        bail!("`{}` holds no targets", input.display());
    }
    Ok(rows)
}

/// The output CSV: one line per input line, a solution or the reason there is none; the header
/// line first when `header` (the first shard's output, or the whole batch's).
fn write_results(out: &mut impl Write, robot: &Robot, deg: bool, results: &[Answer], header: bool) -> Result<()> {
    let n = robot.dof();
    let mut w = csv::Writer::from_writer(out);
    if header {
        let mut names = vec!["line".to_string(), "status".into(), "solver".into()];
        names.extend((1..=n).map(|i| format!("q{i}")));
        names.extend(["position_error", "orientation_error", "within_limits", "reason"].map(String::from));
        w.write_record(&names)?;
    }
    for (line, result) in results {
        let mut rec = vec![line.to_string()];
        match result {
            Ok((solver, s)) => {
                rec.extend(["solved".to_string(), solver.to_string()]);
                rec.extend(s.q.iter().zip(robot.joints()).map(|(v, j)| {
                    format!("{:.12}", if deg && j.kind == JointType::Revolute { v.to_degrees() } else { *v })
                }));
                rec.extend([
                    format!("{:.3e}", s.position_error),
                    format!("{:.3e}", s.orientation_error),
                    s.within_limits().to_string(),
                    String::new(),
                ]);
            }
            Err(why) => {
                let status = if why.starts_with("unreachable") { "unreachable" } else { "invalid" };
                rec.extend([status.to_string(), String::new()]);
                rec.extend(std::iter::repeat_n(String::new(), n + 3));
                rec.push(why.clone());
            }
        }
        w.write_record(&rec)?;
    }
    w.flush()?;
    Ok(())
}
