//! Collision-free motion: a path of straight joint-space segments from a
//! start to a goal configuration or pose, around the robot itself and a
//! scene's obstacles, and timed within the joint limits.
//!
//! [`plan`] runs in four steps:
//! 1. **Ends.** The start must be clear. A [`Goal::Pose`] becomes the set of
//!    its IK solutions through the contract, each collision-free (every
//!    branch; samples of a redundant arm's self-motion).
//! 2. **Search.** The straight segment to the nearest goal is tried first;
//!    else RRT-Connect grows a tree from the start and one from all goals
//!    (deterministic per seed; time, iteration and interrupt budgets).
//! 3. **Shortening.** Via points whose neighbours see each other are dropped,
//!    and random shortcuts kept where free.
//! 4. **Certificate.** Each final segment is checked once more by the exact
//!    continuous check ([`CollisionCheck::first_contact_between`]).
//!
//! Every segment the search and the shortening accept is decided exactly by
//! [`MotionCheck`]: spheres clear most of it, conservative advancement on the
//! real shapes the rest, so no contact between samples is missed.
//! [`Plan::trajectory`] times the path with a PTP per segment
//! ([`kinema::traj::via::ptp_through`]), which keeps the robot on it.

mod budget;
mod fixed;
mod goal;
mod held;
mod motion;
mod round;
mod rrt;
mod sampler;
mod shortcut;
mod timing_against;
mod tree;

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use kinema::traj::{via::ptp_through, JointTrajectory, PtpOptions};
use kinema::{Pose, Robot};

use crate::check::CollisionCheck;
use crate::error::{Error, Result};
use budget::Budget;
pub use held::check_with_other_held;
pub use motion::{MotionCheck, MotionCounts};
use sampler::Sampler;
pub use timing_against::{time_against, CellRobot, Crossing};

/// Where a motion should end.
#[derive(Debug, Clone, PartialEq)]
pub enum Goal {
    /// A configuration \[rad, m\].
    Joints(Vec<f64>),
    /// A tool pose in the world frame: any collision-free IK solution.
    Pose(Pose),
}

/// The knobs of one planning run.
#[derive(Debug, Clone)]
pub struct PlanOptions<'a> {
    /// The random sequence's seed: the same seed gives the same path when
    /// the run ends within its budgets.
    pub seed: u64,
    /// Wall-clock budget of the whole run.
    pub time_limit: Duration,
    /// Iterations of the search before it gives up.
    pub max_iterations: usize,
    /// Longest step a tree takes \[joint-space norm, rad or m\]; `None`: a
    /// fifth of the diagonal of the joint-limit box (OMPL's default range).
    pub step: Option<f64>,
    /// Random shortcut attempts after the search.
    pub shortcut_rounds: usize,
    /// For a pose goal: values of a redundant arm's self-motion parameter
    /// (or numeric restarts, without a closed form) tried besides the contract's answer.
    pub goal_samples: usize,
    /// Set (by a Ctrl-C handler) to stop the run with [`Error::Interrupted`].
    pub cancel: Option<&'a AtomicBool>,
}

impl Default for PlanOptions<'_> {
    fn default() -> Self {
        PlanOptions {
            seed: 0,
            time_limit: Duration::from_secs(1),
            max_iterations: 100_000,
            step: None,
            shortcut_rounds: 100,
            goal_samples: 16,
            cancel: None,
        }
    }
}

/// A collision-free path and how it was found.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Via points, start first, goal last; consecutive ones joined by
    /// collision-free straight segments.
    pub path: Vec<Vec<f64>>,
    /// Via points of the search's path before shortening.
    pub found_via_points: usize,
    /// Goal configurations the search aimed at.
    pub goals: usize,
    /// Search iterations (0 when the straight segment was free).
    pub iterations: usize,
    /// Configurations in both trees.
    pub nodes: usize,
    /// Collision work done.
    pub counts: MotionCounts,
    /// Wall-clock time of the whole run.
    pub elapsed: Duration,
}

impl Plan {
    /// The path's length \[joint-space norm\].
    pub fn length(&self) -> f64 {
        shortcut::length(&self.path)
    }

    /// The path timed with a PTP per segment under `options`, stopping at
    /// every via point (at rest, but for the linear profile's velocity
    /// jump), sampled every `dt` \[s\] (see [`ptp_through`]): within the
    /// limits, and on the checked segments.
    pub fn trajectory(&self, robot: &Robot, options: &PtpOptions, dt: f64) -> Result<JointTrajectory> {
        Ok(ptp_through(robot, &self.path, options, dt)?)
    }
}

/// A collision-free path for `check`'s robot from `from` to `goal` (see the
/// [module documentation](self)).
///
/// Errors: a start or goal configuration of the wrong length, outside the
/// joint limits or colliding ([`Error::Blocked`]); a pose no collision-free
/// configuration reaches (the IK contract's error); [`Error::NoPath`] when
/// the budget runs out; [`Error::Interrupted`].
///
/// # Examples
/// ```
/// use kinema_geometry::plan::{plan, Goal, PlanOptions};
/// use kinema_geometry::{CheckOptions, CollisionCheck};
/// let check = CollisionCheck::load("puma560", &CheckOptions::default())?;
/// let from = [0.0, 0.3, -0.5, 0.0, 0.4, 0.0];
/// let to = [1.2, 0.1, -0.9, 0.3, 0.2, 0.5];
/// let found = plan(&check, &from, &Goal::Joints(to.to_vec()), &PlanOptions::default())?;
/// assert_eq!(found.path.first().unwrap().as_slice(), from);
/// assert_eq!(found.path.last().unwrap().as_slice(), to);
/// # Ok::<(), kinema_geometry::Error>(())
/// ```
pub fn plan(check: &CollisionCheck, from: &[f64], goal: &Goal, options: &PlanOptions) -> Result<Plan> {
    let budget = Budget::new(options.time_limit, options.max_iterations, options.cancel);
    let sampler = Sampler::new(check.robot());
    let step = checked_step(options.step, sampler.extent())?;
    require_clear(check, from, "start")?;
    let goals = match goal {
        Goal::Joints(q) => {
            require_clear(check, q, "goal")?;
            vec![q.clone()]
        }
        Goal::Pose(pose) => goal::goal_configurations(check, pose, options.goal_samples, options.seed, &budget)?,
    };
    let mut motion = MotionCheck::new(check)?;
    // A segment still being checked when time runs out counts as blocked:
    // the search and the shortening then end on the budget.
    motion.set_deadline(Some(budget.deadline()));
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let (mut path, iterations, nodes) = match straight_to_a_goal(&mut motion, from, &goals, &budget)? {
        Some(g) => (vec![from.to_vec(), g], 0, 1 + goals.len()),
        None => {
            let (path, counts) = rrt::connect_trees(&mut motion, from, &goals, &sampler, step, &mut rng, &budget)?;
            (path, counts.iterations, counts.nodes)
        }
    };
    let found_via_points = path.len();
    shortcut::shorten(&mut path, &mut motion, options.shortcut_rounds, &mut rng, &budget)?;
    certify(check, &path, &budget)?;
    Ok(Plan {
        path,
        found_via_points,
        goals: goals.len(),
        iterations,
        nodes,
        counts: motion.counts(),
        elapsed: budget.elapsed(),
    })
}

/// The goal nearest to `from` that a free straight segment reaches, trying
/// goals nearest first.
fn straight_to_a_goal(
    motion: &mut MotionCheck,
    from: &[f64],
    goals: &[Vec<f64>],
    budget: &Budget,
) -> Result<Option<Vec<f64>>> {
    let distance = |q: &[f64]| q.iter().zip(from).map(|(a, b)| (a - b) * (a - b)).sum::<f64>();
    let mut order: Vec<&Vec<f64>> = goals.iter().collect();
    order.sort_by(|a, b| distance(a).total_cmp(&distance(b)));
    for g in order {
        budget.not_cancelled()?;
        if motion.segment_free(from, g)? {
            return Ok(Some(g.clone()));
        }
    }
    Ok(None)
}

/// The search's step: `step`, or a fifth of the joint box's diagonal
/// `extent`; one shorter than [`MIN_STEP`] of it would crawl.
fn checked_step(step: Option<f64>, extent: f64) -> Result<f64> {
    let step = step.unwrap_or(extent / 5.0);
    let least = extent * MIN_STEP;
    if !(step >= least && step.is_finite()) {
        return Err(Error::Kinema(kinema::Error::Input(kinema::InputError::OutOfRange {
            what: "step".into(),
            value: step,
            expected: format!("a finite joint-space distance ≥ {least:.3e} (1e-5 of the joint-limit box's diagonal)"),
        })));
    }
    Ok(step)
}

/// The shortest search step, as a fraction of the joint box's diagonal.
const MIN_STEP: f64 = 1e-5;

/// An error naming the colliding pair when the robot at `q` is not clear
/// (and the joint vector's own errors). Clear means what it means on a
/// segment: apart by more than the margin plus
/// [`CONTACT_TOLERANCE`](crate::CONTACT_TOLERANCE), so a start the search
/// could never leave is refused here, by name.
fn require_clear(check: &CollisionCheck, q: &[f64], which: &'static str) -> Result<()> {
    check.robot().check_within_limits(q, which)?;
    let blocked =
        |(a, b): (usize, usize)| Error::Blocked { which, a: check.body(a).to_string(), b: check.body(b).to_string() };
    if let Some(pair) = check.first_collision(q)? {
        return Err(blocked(pair));
    }
    if let Some(contact) = check.first_contact_between(q, q, &mut check.placement())? {
        return Err(blocked(contact.pair));
    }
    Ok(())
}

/// The exact continuous check of every segment of the final path.
fn certify(check: &CollisionCheck, path: &[Vec<f64>], budget: &Budget) -> Result<()> {
    let mut placement = check.placement();
    for w in path.windows(2) {
        budget.not_cancelled()?;
        if let Some(contact) = check.first_contact_between(&w[0], &w[1], &mut placement)? {
            let (a, b) = contact.pair;
            return Err(Error::Uncertified { a: check.body(a).to_string(), b: check.body(b).to_string() });
        }
    }
    Ok(())
}
