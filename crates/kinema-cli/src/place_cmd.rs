//! `kinema place`: inverse reachability — candidate base positions on a
//! grid over the floor, ranked by how many poses of a task the robot
//! standing there reaches (`kinema::reach::place`), on all cores.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use kinema::ik::{IkRequest, IkTarget};
use kinema::reach::place::{base_candidates, place_scores, ranking, Region};
use kinema::{Pose, RpyConvention};

use crate::ik_cmd::batch::read_target_rows;
use crate::{write_atomically, Exit};

#[derive(Args)]
pub struct PlaceArgs {
    #[command(flatten)]
    robot: crate::RobotArg,
    /// The task: a CSV of tool poses in the format of `kinema ik --input` (16 numbers, a 4×4 matrix
    /// row-major, or 6: x,y,z,roll,pitch,yaw), one per line.
    #[arg(long)]
    task: PathBuf,
    /// Roll-pitch-yaw convention of 6-number task lines.
    #[arg(long, default_value = "zyx", value_parser = crate::by_name::<RpyConvention>())]
    rpy: RpyConvention,
    /// Task angles are in degrees.
    #[arg(long)]
    deg: bool,
    /// The floor rectangle the base may stand in, `x0:x1,y0:y1` or `x0:x1,y0:y1,z` [m] (default: a
    /// square of the robot's reach around the task, at the robot's own base height).
    #[arg(long, value_parser = parse_region)]
    region: Option<Region>,
    /// Grid step of the base positions [m].
    #[arg(long, default_value_t = 0.05)]
    resolution: f64,
    /// How many base yaws are tried at each position (evenly over a turn).
    #[arg(long, default_value_t = 1)]
    yaw_steps: usize,
    /// Where to write the ranked bases (CSV `rank,x,y,z,yaw,reached,fraction`, best first, ties in
    /// grid order; `-` for standard output); written in full or not at all.
    #[arg(long)]
    out: PathBuf,
}

fn parse_region(text: &str) -> std::result::Result<Region, String> {
    let bad = || format!("`{text}`: expected x0:x1,y0:y1 or x0:x1,y0:y1,z (metres)");
    let parts: Vec<&str> = text.split(',').collect();
    let range = |s: &str| -> std::result::Result<(f64, f64), String> {
        let (lo, hi) = s.split_once(':').ok_or_else(bad)?;
        Ok((lo.trim().parse().map_err(|_| bad())?, hi.trim().parse().map_err(|_| bad())?))
    };
    match parts.as_slice() {
        [x, y] => Ok(Region { x: range(x)?, y: range(y)?, z: None }),
        [x, y, z] => Ok(Region { x: range(x)?, y: range(y)?, z: Some(z.trim().parse().map_err(|_| bad())?) }),
        _ => Err(bad()),
    }
}

fn read_task(a: &PlaceArgs) -> Result<Vec<Pose>> {
    let rows = read_target_rows(&a.task, a.rpy, a.deg)?;
    rows.into_iter()
        .map(|(line, target)| match target {
            Ok(IkTarget::Pose(p)) => Ok(p),
            Ok(_) => bail!("`{}` line {line}: a position; a task needs full poses (16 or 6 numbers)", a.task.display()),
            Err(reason) => bail!("`{}` line {line}: {reason}", a.task.display()),
        })
        .collect()
}

pub fn run(a: PlaceArgs) -> Result<()> {
    let robot = a.robot.load()?;
    let task = read_task(&a).context("reading the task")?;
    let region = match a.region {
        Some(r) => r,
        None => Region::around_task(&robot, &task)?,
    };
    let bases = base_candidates(&robot, &region, a.resolution, a.yaw_steps)?;
    let bar = crate::progress_bar(bases.len(), "bases", 2_000);
    let cancellable = crate::interrupt::cancellable();
    let scores =
        place_scores(&robot, &bases, &task, &IkRequest::default(), &|| bar.inc(1), &crate::interrupt::interrupted);
    bar.finish_and_clear();
    drop(cancellable);
    let scores = match scores {
        Err(kinema::Error::Cancelled) => {
            eprintln!("interrupted; nothing written");
            return Err(Exit(crate::interrupt::EXIT_INTERRUPTED).into());
        }
        other => other?,
    };
    let own_rot = robot.base().rot;
    write_atomically(&a.out, |out| {
        let mut w = csv::Writer::from_writer(out);
        w.write_record(["rank", "x", "y", "z", "yaw", "reached", "fraction"])?;
        for (rank, &i) in ranking(&scores).iter().enumerate() {
            let b = &bases[i];
            // The yaw added to the robot's own base rotation, read back from the rotations.
            let turn = b.rot * own_rot.transpose();
            let yaw = turn[(1, 0)].atan2(turn[(0, 0)]).rem_euclid(std::f64::consts::TAU);
            let fraction = scores[i] as f64 / task.len() as f64;
            w.write_record(
                std::iter::once((rank + 1).to_string())
                    .chain([b.pos.x, b.pos.y, b.pos.z, yaw].map(|v| format!("{v:.6}")))
                    .chain([scores[i].to_string(), format!("{fraction:.6}")]),
            )?;
        }
        w.flush()?;
        Ok(())
    })?;
    let best = scores.iter().max().copied().unwrap_or(0);
    eprintln!("{} bases; the best reaches {best} of {} task poses; wrote {}", bases.len(), task.len(), a.out.display());
    Ok(())
}
