//! When a planner must stop: a deadline, an iteration count, or its caller.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::error::{Error, Result};

/// The limits of one planning run.
#[derive(Debug)]
pub(crate) struct Budget<'a> {
    started: Instant,
    time_limit: Duration,
    max_iterations: usize,
    cancel: Option<&'a AtomicBool>,
}

impl<'a> Budget<'a> {
    pub(crate) fn new(time_limit: Duration, max_iterations: usize, cancel: Option<&'a AtomicBool>) -> Budget<'a> {
        Budget { started: Instant::now(), time_limit, max_iterations, cancel }
    }

    /// When the time limit runs out.
    pub(crate) fn deadline(&self) -> Instant {
        self.started.checked_add(self.time_limit).unwrap_or_else(|| self.started + Duration::from_secs(86_400 * 365))
    }

    /// Time since the run started.
    pub(crate) fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// `Ok(true)` while iteration `iteration` may run; `Ok(false)` when a
    /// budget is spent; an error when the caller interrupted the run.
    pub(crate) fn allows(&self, iteration: usize) -> Result<bool> {
        self.not_cancelled()?;
        Ok(iteration < self.max_iterations && self.elapsed() < self.time_limit)
    }

    /// An error when the caller interrupted the run. The steps bounded by
    /// their own counts (the goals, the final check) ask only this.
    pub(crate) fn not_cancelled(&self) -> Result<()> {
        if self.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            return Err(Error::Interrupted);
        }
        Ok(())
    }

    /// `Ok(true)` while time is left; an error when the caller interrupted.
    pub(crate) fn has_time(&self) -> Result<bool> {
        self.allows(0)
    }

    /// Which budget ran out, in words.
    pub(crate) fn spent(&self, iteration: usize) -> String {
        if iteration >= self.max_iterations {
            format!("the limit of {} iteration(s)", self.max_iterations)
        } else {
            format!("the time limit of {} s", self.time_limit.as_secs_f64())
        }
    }
}
