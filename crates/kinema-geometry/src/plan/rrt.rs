//! Bidirectional RRT-Connect (Kuffner & LaValle 2000, "RRT-Connect: An
//! efficient approach to single-query path planning", ICRA): one tree from
//! the start, one from every goal configuration; each iteration extends one
//! tree one step toward a random configuration and pulls the other tree
//! toward the new node for as long as it advances. The trees swap roles
//! every iteration.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::budget::Budget;
use super::motion::MotionCheck;
use super::sampler::Sampler;
use super::tree::Tree;
use crate::error::{Error, Result};

/// What one extension did.
enum Growth {
    /// The segment toward the target collides.
    Trapped,
    /// A new node, short of the target.
    Advanced(usize),
    /// A new node at the target.
    Reached(usize),
}

/// A search's counts.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SearchCounts {
    pub iterations: usize,
    pub nodes: usize,
}

/// A collision-free path from `start` to one of `goals` (each already
/// checked free), as via points, start first.
pub(crate) fn connect_trees(
    motion: &mut MotionCheck,
    start: &[f64],
    goals: &[Vec<f64>],
    sampler: &Sampler,
    step: f64,
    rng: &mut ChaCha8Rng,
    budget: &Budget,
) -> Result<(Vec<Vec<f64>>, SearchCounts)> {
    let dof = start.len();
    let mut from_start = Tree::with_roots(dof, &[start.to_vec()]);
    let mut from_goal = Tree::with_roots(dof, goals);
    let mut target = vec![0.0; dof];
    let mut iteration = 0;
    while budget.allows(iteration)? {
        iteration += 1;
        let start_grows = iteration % 2 == 1;
        let (grow, pull) =
            if start_grows { (&mut from_start, &mut from_goal) } else { (&mut from_goal, &mut from_start) };
        sampler.sample_into(rng, &mut target);
        let new = match extend(grow, &target, step, motion)? {
            Growth::Trapped => continue,
            Growth::Advanced(i) | Growth::Reached(i) => i,
        };
        let reached = grow.node(new).to_vec();
        if let Some(met) = pull_toward(pull, &reached, step, motion, budget)? {
            let (s, g) = if start_grows { (new, met) } else { (met, new) };
            let mut path = from_start.to_root(s);
            path.reverse();
            // The meeting configuration is in both trees: once is enough.
            path.extend(from_goal.to_root(g).into_iter().skip(1));
            let counts = SearchCounts { iterations: iteration, nodes: from_start.len() + from_goal.len() };
            return Ok((path, counts));
        }
    }
    Err(Error::NoPath {
        budget: budget.spent(iteration),
        iterations: iteration,
        nodes: from_start.len() + from_goal.len(),
    })
}

/// One step of at most `step` from the node of `tree` nearest to `target`.
fn extend(tree: &mut Tree, target: &[f64], step: f64, motion: &mut MotionCheck) -> Result<Growth> {
    let near = tree.nearest(target);
    let from = tree.node(near);
    let distance = from.iter().zip(target).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
    let reaches = distance <= step;
    let to: Vec<f64> = if reaches {
        target.to_vec()
    } else {
        from.iter().zip(target).map(|(a, b)| a + (b - a) * step / distance).collect()
    };
    if !motion.segment_free(from, &to)? {
        return Ok(Growth::Trapped);
    }
    let i = tree.add(&to, near);
    Ok(if reaches { Growth::Reached(i) } else { Growth::Advanced(i) })
}

/// Extends `tree` toward `target` until it reaches it (the node's index) or
/// is trapped or out of time (`None`: the search loop then ends on its budget).
fn pull_toward(
    tree: &mut Tree,
    target: &[f64],
    step: f64,
    motion: &mut MotionCheck,
    budget: &Budget,
) -> Result<Option<usize>> {
    while budget.has_time()? {
        match extend(tree, target, step, motion)? {
            Growth::Advanced(_) => continue,
            Growth::Reached(i) => return Ok(Some(i)),
            Growth::Trapped => return Ok(None),
        }
    }
    Ok(None)
}

/// A uniformly random index pair i < j of `0..n` (n ≥ 2).
pub(crate) fn ordered_pair(rng: &mut ChaCha8Rng, n: usize) -> (usize, usize) {
    let a = rng.random_range(0..n);
    let mut b = rng.random_range(0..n - 1);
    if b >= a {
        b += 1;
    }
    (a.min(b), a.max(b))
}
