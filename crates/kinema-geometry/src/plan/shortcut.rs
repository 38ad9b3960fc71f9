//! Shortening a found path: via points dropped where their neighbours see
//! each other, then random shortcuts between two points on different
//! segments (Geraerts & Overmars 2007, "Creating high-quality paths for
//! motion planning", IJRR 26(8)), each kept only when its segment is free.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::budget::Budget;
use super::motion::{lerp_into, MotionCheck};
use super::rrt::ordered_pair;
use crate::error::Result;

/// Shortens `path` in place with at most `rounds` random shortcuts, while
/// `budget` has time. Every segment of the result is checked free.
pub(crate) fn shorten(
    path: &mut Vec<Vec<f64>>,
    motion: &mut MotionCheck,
    rounds: usize,
    rng: &mut ChaCha8Rng,
    budget: &Budget,
) -> Result<()> {
    drop_via_points(path, motion, budget)?;
    for _ in 0..rounds {
        if path.len() < 3 || !budget.has_time()? {
            break;
        }
        try_shortcut(path, motion, rng)?;
    }
    drop_via_points(path, motion, budget)
}

/// The path length (Euclidean in joint space).
pub(crate) fn length(path: &[Vec<f64>]) -> f64 {
    path.windows(2).map(|w| distance(&w[0], &w[1])).sum()
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// Removes via points greedily: from each kept point, the farthest later
/// point it reaches by a free segment is the next.
fn drop_via_points(path: &mut Vec<Vec<f64>>, motion: &mut MotionCheck, budget: &Budget) -> Result<()> {
    let mut i = 0;
    while i + 2 < path.len() {
        for j in (i + 2..path.len()).rev() {
            budget.not_cancelled()?;
            if motion.segment_free(&path[i], &path[j])? {
                path.drain(i + 1..j);
                break;
            }
        }
        i += 1;
    }
    Ok(())
}

/// One random shortcut between a point on segment i and one on a later
/// segment j, replacing what lies between when it is free and shorter.
fn try_shortcut(path: &mut Vec<Vec<f64>>, motion: &mut MotionCheck, rng: &mut ChaCha8Rng) -> Result<()> {
    let (i, j) = ordered_pair(rng, path.len() - 1);
    let (u, v) = (rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
    let mut a = vec![0.0; path[0].len()];
    let mut b = a.clone();
    lerp_into(&path[i], &path[i + 1], u, &mut a);
    lerp_into(&path[j], &path[j + 1], v, &mut b);
    let along = distance(&a, &path[i + 1]) + length(&path[i + 1..=j]) + distance(&path[j], &b);
    if distance(&a, &b) >= along - 1e-12 || !motion.segment_free(&a, &b)? {
        return Ok(());
    }
    path.splice(i + 1..=j, [a, b]);
    Ok(())
}
