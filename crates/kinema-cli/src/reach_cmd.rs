//! `kinema reach`: a capability map — per voxel around the robot, how many
//! of a fixed set of tool orientations some configuration within the limits
//! reaches (collision-free with `--scene`), on all cores (`kinema::reach`).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use kinema::ik::{Admissible, IkRequest};
use kinema::reach::{capability_map, orientation_samples, voxel_centres};
use kinema_io::Shard;

use crate::{write_atomically, Exit};

#[derive(Args)]
pub struct ReachArgs {
    #[command(flatten)]
    robot: crate::RobotArg,
    #[command(flatten)]
    body: crate::BodyArgs,
    /// Voxel edge [m].
    #[arg(long, default_value_t = 0.05)]
    resolution: f64,
    /// How many tool orientations are tried at each voxel (spread uniformly over the rotations).
    #[arg(long, default_value_t = 32)]
    orientations: usize,
    /// Seed of the orientations.
    #[arg(long, value_parser = crate::seed, default_value = "0")]
    seed: u64,
    /// Compute only shard i of n (`2/4`: the second of four contiguous blocks of the voxels); the
    /// shards' outputs, concatenated in order, are the unsharded output byte for byte.
    #[arg(long)]
    shard: Option<Shard>,
    /// Where to write the map (CSV `x,y,z,reached,fraction`, one line per voxel; `-` for standard
    /// output); written in full or not at all.
    #[arg(long)]
    out: PathBuf,
}

/// The most orientations a voxel is tried at.
const MAX_ORIENTATIONS: usize = 4096;

pub fn run(a: ReachArgs) -> Result<()> {
    if a.orientations == 0 || a.orientations > MAX_ORIENTATIONS {
        anyhow::bail!("--orientations {}: expected 1 to {MAX_ORIENTATIONS}", a.orientations);
    }
    let (robot, check) = a.body.robot_and_check(&a.robot)?;
    let shard = a.shard.unwrap_or(Shard::ALL);
    let centres = shard.take(voxel_centres(&robot, a.resolution)?);
    let orientations = orientation_samples(a.orientations, a.seed);
    let request = IkRequest { admissible: check.as_ref().map(|c| c as &dyn Admissible), ..Default::default() };
    let bar = crate::progress_bar(centres.len(), "voxels", 2_000);
    let cancellable = crate::interrupt::cancellable();
    let counts =
        capability_map(&robot, &centres, &orientations, &request, &|| bar.inc(1), &crate::interrupt::interrupted);
    bar.finish_and_clear();
    drop(cancellable);
    let counts = match counts {
        Err(kinema::Error::Cancelled) => {
            eprintln!("interrupted; nothing written");
            return Err(Exit(crate::interrupt::EXIT_INTERRUPTED).into());
        }
        other => other?,
    };
    write_atomically(&a.out, |out| {
        let mut w = csv::Writer::from_writer(out);
        if shard.writes_header() {
            w.write_record(["x", "y", "z", "reached", "fraction"])?;
        }
        for (c, &n) in centres.iter().zip(&counts) {
            let fraction = n as f64 / a.orientations as f64;
            w.write_record(
                [c[0], c[1], c[2]]
                    .map(|v| format!("{v:.6}"))
                    .into_iter()
                    .chain([n.to_string(), format!("{fraction:.6}")]),
            )?;
        }
        w.flush()?;
        Ok(())
    })?;
    let reached = counts.iter().filter(|&&n| n > 0).count();
    eprintln!(
        "{reached} of {} voxels reached at {} orientations{}; wrote {}",
        centres.len(),
        a.orientations,
        if shard == Shard::ALL { String::new() } else { format!(" (shard {shard})") },
        a.out.display()
    );
    Ok(())
}
