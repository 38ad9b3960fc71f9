//! Many IK targets at once: each solved exactly as one request would be
//! ([`super::solve_target`], then [`pick_one`]), spread over all cores with rayon.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::request::{pick_one, solve_target_with, IkRequest};
use super::target::IkTarget;
use super::Solution;
use crate::error::{Error, Result};
use crate::robot::Robot;

/// Solves every target of `targets` as `request` asks and picks one solution
/// each (within limits, nearest `request.q0` when given), in parallel.
/// `request.all` is ignored. One result per target, in order: the solver's
/// name and the solution, or the error that target gives ([`Error::Unreachable`] with its reason, or
/// [`InputError::NotFinite`](crate::InputError::NotFinite) or [`InputError::OutOfRange`](crate::InputError::OutOfRange) for a target that is not a rigid transform…).
/// Errors that concern the request as a whole (a `q0` of the wrong length, a
/// mask with a target that is not a full pose, a tolerance that is not
/// positive, …) are returned once, before any solving.
///
/// `done` is called once per finished target, from any thread (for a
/// progress bar); `cancelled` is read between targets: once it returns true,
/// the targets not yet started give [`Error::Cancelled`].
///
/// # Examples
/// ```
/// use kinema::ik::{solve_batch, IkRequest, IkTarget};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let targets: Vec<IkTarget> = [[0.1, -0.5, 0.4, 0.3, 0.6, -0.2], [0.3, -0.2, 0.1, 0.2, 0.5, 0.1]]
///     .iter()
///     .map(|q| robot.fk(q).map(|f| IkTarget::Pose(f.world_from_tool)))
///     .collect::<Result<_, _>>()?;
/// let far = IkTarget::Position([5.0, 0.0, 0.0]);
/// let all: Vec<IkTarget> = targets.into_iter().chain([far]).collect();
/// let results = solve_batch(&robot, &all, &IkRequest::default(), &|| {}, &|| false)?;
/// assert!(results[0].is_ok() && results[1].is_ok());
/// assert!(matches!(results[2], Err(kinema::Error::Unreachable { .. })));
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn solve_batch(
    robot: &Robot,
    targets: &[IkTarget],
    request: &IkRequest,
    done: &(dyn Fn() + Sync),
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<Result<(&'static str, Solution)>>> {
    for target in targets {
        super::request::check_request(robot, target, request)?;
    }
    let one = IkRequest { all: false, ..request.clone() };
    let fitted = super::registry::fit(robot);
    let stop = AtomicBool::new(false);
    let results = targets
        .par_iter()
        .map(|target| {
            if stop.load(Ordering::Relaxed) || cancelled() {
                stop.store(true, Ordering::Relaxed);
                return Err(Error::Cancelled);
            }
            let result = solve_target_with(robot, fitted.as_deref(), target, &one)
                .and_then(|answer| Ok((answer.solver, pick_one(robot, answer.solver, answer.solutions, one.q0)?)));
            done();
            result
        })
        .collect();
    Ok(results)
}
