//! `kinema collide`: is the robot at a configuration in collision with
//! itself or a scene's obstacles, which pairs, and how close is the closest
//! pair. One configuration (`--q`) or a CSV of them (`--input`, checked on
//! all cores, printed in input order). Exit code 3 when any configuration
//! collides.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::Args;
use rayon::prelude::*;

use kinema_geometry::{CollisionCheck, Placement};
use kinema_io::CollideAnswer;

use crate::stdout::outln;
use crate::Exit;

/// Exit code when a configuration collides (as `kinema cell` when the tools come too close).
const EXIT_COLLISION: u8 = 3;

/// Configurations checked per parallel chunk of `--input`: bounds the answers held at once.
const CHUNK: usize = 4096;

#[derive(Args)]
pub struct CollideArgs {
    #[command(flatten)]
    robot: crate::RobotArg,
    #[command(flatten)]
    body: crate::BodyArgs,
    /// Joint values, comma-separated (rad and m), or a named pose such as `home`.
    #[arg(long, allow_hyphen_values = true, required_unless_present = "input", conflicts_with = "input")]
    q: Option<String>,
    /// A CSV of configurations, one per line (`#` comments and a header line allowed).
    #[arg(long, value_name = "CSV")]
    input: Option<PathBuf>,
    /// Revolute joint values are in degrees (prismatic ones stay in metres).
    #[arg(long)]
    deg: bool,
    /// Print JSON (one object per configuration, one per line with --input).
    #[arg(long)]
    json: bool,
}

pub fn run(a: CollideArgs) -> Result<()> {
    let checked = a.body.load(&a.robot)?;
    let collided = match (&a.q, &a.input) {
        (Some(text), _) => {
            let q = crate::input::parse_q(checked.robot(), text, a.deg)?;
            let answer = check(&checked, q, &mut checked.placement())?;
            print(&answer, None, a.json)?;
            answer.collision
        }
        (None, Some(path)) => batch(&checked, path, a.deg, a.json)?,
        (None, None) => unreachable!("clap requires --q or --input"),
    };
    if collided {
        return Err(Exit(EXIT_COLLISION).into());
    }
    Ok(())
}

/// Checks every line of `path` on all cores, chunk by chunk; prints in input order.
fn batch(c: &CollisionCheck, path: &std::path::Path, deg: bool, json: bool) -> Result<bool> {
    let rows = crate::numeric_rows(path)?;
    if rows.is_empty() {
        bail!("`{}` holds no configurations", path.display());
    }
    let dof = c.robot().dof();
    for (line, v) in &rows {
        if v.len() != dof {
            bail!(
                "`{}` line {line}: {} values; expected one per joint of `{}` ({dof})",
                path.display(),
                v.len(),
                c.robot().name()
            );
        }
    }
    let mut any = false;
    for chunk in rows.chunks(CHUNK) {
        let answers: Vec<Result<CollideAnswer>> = chunk
            .par_iter()
            .map_init(
                || c.placement(),
                |placement, (line, v)| {
                    let q = v
                        .iter()
                        .zip(c.robot().joints())
                        .map(|(x, j)| if deg && j.kind == kinema::JointType::Revolute { x.to_radians() } else { *x })
                        .collect::<Vec<f64>>();
                    c.robot().check_q(&q).map_err(|e| anyhow::anyhow!("`{}` line {line}: {e}", path.display()))?;
                    check(c, q, placement)
                },
            )
            .collect();
        for ((line, _), answer) in chunk.iter().zip(answers) {
            let answer = answer?;
            any |= answer.collision;
            print(&answer, Some(*line), json)?;
        }
    }
    Ok(any)
}

/// The answer for one configuration.
fn check(c: &CollisionCheck, q: Vec<f64>, placement: &mut Placement) -> Result<CollideAnswer> {
    Ok(CollideAnswer::of(c, q, placement)?)
}

fn print(a: &CollideAnswer, line: Option<u64>, json: bool) -> Result<()> {
    if json {
        let text = serde_json::to_string(a)?;
        match line {
            Some(_) => outln!("{text}")?,
            None => outln!("{}", serde_json::to_string_pretty(a)?)?,
        }
        return Ok(());
    }
    let at = line.map_or(String::new(), |l| format!("line {l}: "));
    let verdict = if a.collision {
        let names: Vec<String> = a.pairs.iter().map(|p| format!("{} – {}", p.a, p.b)).collect();
        format!("collision: {}", names.join(", "))
    } else {
        "free".to_string()
    };
    let closest = match &a.min_distance {
        Some(d) => format!("; closest {} – {} at {:.4} m", d.a, d.b, d.distance),
        None => String::new(),
    };
    outln!("{at}{verdict}{closest}")?;
    Ok(())
}
