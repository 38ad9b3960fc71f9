//! Inverse reachability: where to stand. Candidate base poses on a grid
//! over a region of the floor (optionally at several yaws) are scored by
//! how many poses of a task the robot, moved there, reaches ([`reaches`]),
//! and ranked best first.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::{reach_bound, reaches};
use crate::error::{Error, InputError, Result};
use crate::ik::{registry, IkRequest};
use crate::math::Pose;
use crate::robot::Robot;

/// A rectangle of the floor \[m\] the base may stand in, at height `z`
/// (`None`: the robot's own base height).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    /// Lowest and highest x of a base position.
    pub x: (f64, f64),
    /// Lowest and highest y of a base position.
    pub y: (f64, f64),
    /// Height of the base; `None` keeps the robot's own.
    pub z: Option<f64>,
}

impl Region {
    /// The square centred on the middle of the task's positions (seen from
    /// above) whose half-edge is the robot's [`reach_bound`]: no base outside
    /// it reaches the task's centre.
    pub fn around_task(robot: &Robot, task: &[Pose]) -> Result<Region> {
        if task.is_empty() {
            return Err(Error::Input(InputError::DoesNotFit {
                what: "task".into(),
                reason: "no poses to place the robot for".into(),
            }));
        }
        let span = |f: fn(&Pose) -> f64| {
            let lo = task.iter().map(f).fold(f64::INFINITY, f64::min);
            let hi = task.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
            (lo + hi) / 2.0
        };
        let (cx, cy) = (span(|p| p.pos.x), span(|p| p.pos.y));
        let r = reach_bound(robot)?;
        Ok(Region { x: (cx - r, cx + r), y: (cy - r, cy + r), z: None })
    }
}

/// The most candidate bases [`base_candidates`] lists.
const MAX_CANDIDATES: f64 = 1e7;

/// The candidate base poses: every multiple of `resolution` in x and y
/// within `region`, each at `yaw_steps` yaws evenly spread over a turn
/// (applied about the world z axis on top of the robot's own base
/// rotation). In y, x, yaw order, so the list is the same on every machine
/// and a shard of it is a contiguous block.
pub fn base_candidates(robot: &Robot, region: &Region, resolution: f64, yaw_steps: usize) -> Result<Vec<Pose>> {
    let out_of_range = |what: &str, value: f64, expected: &str| {
        Error::Input(InputError::OutOfRange { what: what.into(), value, expected: expected.into() })
    };
    if !(resolution.is_finite() && resolution > 0.0) {
        return Err(out_of_range("resolution", resolution, "a positive grid step in metres"));
    }
    if yaw_steps == 0 {
        return Err(out_of_range("yaw steps", 0.0, "at least 1"));
    }
    let finite = [region.x.0, region.x.1, region.y.0, region.y.1].iter().all(|v| v.is_finite());
    if !finite || region.x.0 > region.x.1 || region.y.0 > region.y.1 {
        return Err(out_of_range("region", f64::NAN, "finite bounds x0 <= x1, y0 <= y1"));
    }
    let first = |lo: f64| (lo / resolution - 1e-9).ceil();
    let last = |hi: f64| (hi / resolution + 1e-9).floor();
    let (i0, i1, j0, j1) = (first(region.x.0), last(region.x.1), first(region.y.0), last(region.y.1));
    let count = (i1 - i0 + 1.0).max(0.0) * (j1 - j0 + 1.0).max(0.0) * yaw_steps as f64;
    if count > MAX_CANDIDATES {
        return Err(out_of_range("resolution", resolution, "a grid step giving at most 1e7 candidate bases"));
    }
    let own = robot.base();
    let z = region.z.unwrap_or(own.pos.z);
    let mut bases = Vec::new();
    for j in j0 as i64..=j1 as i64 {
        for i in i0 as i64..=i1 as i64 {
            for k in 0..yaw_steps {
                let yaw = std::f64::consts::TAU * k as f64 / yaw_steps as f64;
                let turn = Pose::rot_z(yaw);
                let pos = nalgebra::Vector3::new(i as f64 * resolution, j as f64 * resolution, z);
                bases.push(Pose::new(turn.rot * own.rot, pos));
            }
        }
    }
    Ok(bases)
}

/// For each of `bases`, how many of the `task` poses the robot standing
/// there reaches ([`reaches`] with `request`), computed on all cores.
/// `done` is called once per base; once `cancelled` returns true the scoring
/// stops with [`Error::Cancelled`].
pub fn place_scores(
    robot: &Robot,
    bases: &[Pose],
    task: &[Pose],
    request: &IkRequest,
    done: &(dyn Fn() + Sync),
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<u32>> {
    let stop = AtomicBool::new(false);
    let scores: Vec<Option<Result<u32>>> = bases
        .par_iter()
        .map(|base| {
            if stop.load(Ordering::Relaxed) || cancelled() {
                stop.store(true, Ordering::Relaxed);
                return None;
            }
            let score = robot.with_base(*base).map(|moved| {
                let family = registry::fit(&moved);
                task.iter().filter(|t| reaches(&moved, family.as_deref(), t, request)).count() as u32
            });
            done();
            Some(score)
        })
        .collect();
    scores.into_iter().collect::<Option<Result<Vec<u32>>>>().ok_or(Error::Cancelled)?
}

/// The indices of `scores`, best first; equal scores keep their grid order.
pub fn ranking(scores: &[u32]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..scores.len()).collect();
    order.sort_by_key(|&i| (std::cmp::Reverse(scores[i]), i));
    order
}
