//! When a running program must stop early: at a deadline, when another
//! thread raises a flag (Ctrl-C, a closed connection, KeyboardInterrupt),
//! or both. The compiler looks at it between statements and loop passes.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A stop condition for [`crate::compile`](fn@crate::compile); the default never stops.
#[derive(Debug, Clone, Default)]
pub struct Stop {
    deadline: Option<(Instant, Duration)>,
    flag: Option<Arc<AtomicBool>>,
}

/// Why a program was stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The time budget (the duration given) ran out.
    Deadline(Duration),
    /// The flag was raised.
    Cancelled,
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StopReason::Deadline(d) => write!(f, "the time budget of {:.3} s ran out", d.as_secs_f64()),
            StopReason::Cancelled => write!(f, "the run was cancelled"),
        }
    }
}

impl Stop {
    /// Never stops.
    pub fn never() -> Self {
        Stop::default()
    }

    /// Stops once `budget` has passed from now.
    pub fn after(budget: Duration) -> Self {
        Stop { deadline: Some((Instant::now() + budget, budget)), flag: None }
    }

    /// Also stops when `flag` is set.
    pub fn with_flag(mut self, flag: Arc<AtomicBool>) -> Self {
        self.flag = Some(flag);
        self
    }

    /// Why the run must stop now, or `None` to go on.
    pub fn reason(&self) -> Option<StopReason> {
        if self.flag.as_ref().is_some_and(|f| f.load(Ordering::Relaxed)) {
            return Some(StopReason::Cancelled);
        }
        match self.deadline {
            Some((at, budget)) if Instant::now() >= at => Some(StopReason::Deadline(budget)),
            _ => None,
        }
    }
}

/// Two stops are equal when they share the deadline and the same flag.
impl PartialEq for Stop {
    fn eq(&self, other: &Self) -> bool {
        let same_flag = match (&self.flag, &other.flag) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        self.deadline == other.deadline && same_flag
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_raised_flag_and_a_passed_deadline_stop() {
        assert_eq!(Stop::never().reason(), None);
        let flag = Arc::new(AtomicBool::new(false));
        let stop = Stop::never().with_flag(flag.clone());
        assert_eq!(stop.reason(), None);
        flag.store(true, Ordering::Relaxed);
        assert_eq!(stop.reason(), Some(StopReason::Cancelled));
        let d = Duration::from_millis(0);
        assert_eq!(Stop::after(d).reason(), Some(StopReason::Deadline(d)));
        assert_eq!(Stop::after(Duration::from_secs(3600)).reason(), None);
    }
}
