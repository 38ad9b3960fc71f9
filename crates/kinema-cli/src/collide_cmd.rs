//! `kinema collide`: is the robot at a configuration in collision with
//! itself or a scene's obstacles, which pairs, and how close is the closest
//! pair. One configuration (`--q`) or a CSV of them (`--input`, checked on
//! all cores, printed in input order). Exit code 3 when any configuration
//! collides. `--generate-srdf` writes the pairs that need no check.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::Args;
use rayon::prelude::*;

use kinema_geometry::{generate_srdf, CollisionCheck};
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
    #[arg(
        long,
        allow_hyphen_values = true,
        required_unless_present_any = ["input", "generate_srdf"],
        conflicts_with_all = ["input", "generate_srdf"]
    )]
    q: Option<String>,
    /// A CSV of configurations, one per line (`#` comments and a header line allowed).
    #[arg(long, value_name = "CSV", conflicts_with = "generate_srdf")]
    input: Option<PathBuf>,
    /// Write the pairs that need no check as an SRDF (`-`: standard output), found as MoveIt's setup
    /// assistant finds them: adjacent links, links touching at the home pose, and links in collision at
    /// all or none of --samples random configurations.
    #[arg(long, value_name = "FILE")]
    generate_srdf: Option<PathBuf>,
    /// With --generate-srdf: how many seeded random configurations decide `Always` and `Never`
    /// [default: 10000, MoveIt's default density].
    #[arg(long, requires = "generate_srdf")]
    samples: Option<usize>,
    /// With --generate-srdf: the seed of the random configurations [default: 0].
    #[arg(long, value_parser = crate::seed, requires = "generate_srdf")]
    seed: Option<u64>,
    /// Revolute joint values are in degrees (prismatic ones stay in metres).
    #[arg(long)]
    deg: bool,
    /// Print JSON (one object per configuration, one per line with --input).
    #[arg(long)]
    json: bool,
    /// With --input: check only shard i of n (`2/4`: the second of four contiguous blocks of its
    /// configurations); the shards' outputs, concatenated in order, are the unsharded output byte for byte.
    #[arg(long, requires = "input")]
    shard: Option<kinema_io::Shard>,
}

pub fn run(a: CollideArgs) -> Result<()> {
    if let Some(path) = &a.generate_srdf {
        a.body.refuse_with("--generate-srdf", "it finds the robot's own pairs")?;
        let checked = a.body.load(&a.robot)?;
        return write_srdf(&checked, path, a.samples.unwrap_or(10_000), a.seed.unwrap_or(0));
    }
    if a.samples.is_some() || a.seed.is_some() {
        // clap lets `requires` pass when the required flag conflicts with a given one (--q).
        eprintln!("error: --samples and --seed go with --generate-srdf");
        return Err(Exit(crate::EXIT_USAGE).into());
    }
    let checked = a.body.load(&a.robot)?;
    let collided = match (&a.q, &a.input) {
        (Some(text), _) => {
            let q = checked.robot().parse_q(text, a.deg)?;
            let answer = CollideAnswer::of(&checked, q, &mut checked.placement())?;
            print(&answer, None, a.json)?;
            answer.collision
        }
        (None, Some(path)) => batch(&checked, path, a.deg, a.json, a.shard.unwrap_or(kinema_io::Shard::ALL))?,
        (None, None) => unreachable!("clap requires --q, --input or --generate-srdf"),
    };
    if collided {
        return Err(Exit(EXIT_COLLISION).into());
    }
    Ok(())
}

/// Checks the lines of `path` that `shard` takes on all cores, chunk by chunk; prints in input
/// order. Every line is read and checked first, so a bad one fails every shard before any output.
fn batch(c: &CollisionCheck, path: &std::path::Path, deg: bool, json: bool, shard: kinema_io::Shard) -> Result<bool> {
    let rows = crate::numeric_rows(path)?;
    if rows.is_empty() {
        bail!("`{}` holds no configurations", path.display());
    }
    let robot = c.robot();
    let dof = robot.dof();
    let mut configurations = Vec::with_capacity(rows.len());
    for (line, v) in rows {
        if v.len() != dof {
            bail!(
                "`{}` line {line}: {} values; expected one per joint of `{}` ({dof})",
                path.display(),
                v.len(),
                robot.name()
            );
        }
        let q: Vec<f64> = v
            .iter()
            .zip(robot.joints())
            .map(|(x, j)| if deg && j.kind == kinema::JointType::Revolute { x.to_radians() } else { *x })
            .collect();
        robot.check_q(&q).map_err(|e| anyhow::anyhow!("`{}` line {line}: {e}", path.display()))?;
        configurations.push((line, q));
    }
    let mut any = false;
    for chunk in shard.take(configurations).chunks(CHUNK) {
        let answers: Vec<kinema_geometry::Result<CollideAnswer>> = chunk
            .par_iter()
            .map_init(|| c.placement(), |placement, (_, q)| CollideAnswer::of(c, q.clone(), placement))
            .collect();
        for ((line, _), answer) in chunk.iter().zip(answers) {
            let answer = answer?;
            any |= answer.collision;
            print(&answer, Some(*line), json)?;
        }
    }
    Ok(any)
}

/// Generates the robot's allowed-collision pairs and writes them as an SRDF to `path`.
fn write_srdf(c: &CollisionCheck, path: &Path, samples: usize, seed: u64) -> Result<()> {
    if samples == 0 {
        // With no sample every pair would read as never colliding, and be disabled.
        bail!("--samples 0: at least one configuration is needed to call a pair `Never` or `Always` in collision");
    }
    let srdf = generate_srdf(c.robot(), c.geometry(), samples, seed)?;
    crate::output::write_atomically(path, |out| Ok(out.write_all(srdf.to_xml().as_bytes())?))?;
    let mut reasons: BTreeMap<&str, usize> = BTreeMap::new();
    for d in &srdf.disabled {
        *reasons.entry(d.reason.as_str()).or_default() += 1;
    }
    let counts: Vec<String> = reasons.iter().map(|(r, n)| format!("{r} {n}")).collect();
    let summary = format!(
        "{} link pairs need no check ({}) over {samples} configurations, seed {seed}",
        srdf.disabled.len(),
        counts.join(", ")
    );
    // The summary must not mix into an SRDF written to standard output.
    if crate::output::is_stdout(path) {
        eprintln!("{summary}");
    } else {
        outln!("wrote `{}`: {summary}", path.display())?;
    }
    Ok(())
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
