//! The planner behind `PTP … AVOID`, one for every door that runs programs
//! (`kinema run`/`compile`, Python's `run_program`, the server's
//! `/api/run`): `kinema_geometry::plan` on the program's collision check.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use kinema_geometry::plan::{plan, Goal, PlanOptions};
use kinema_geometry::CollisionCheck;
use kinema_lang::PathPlanner;

/// The planning budget of one `PTP … AVOID` \[s, wall clock\]: `kinema
/// plan`'s default, doubled, since a program cannot pass its own.
pub const AVOID_TIME_LIMIT: f64 = 2.0;

/// `PTP … AVOID`'s planner on `check`, stopped early when `cancel` is set.
#[derive(Debug, Clone)]
pub struct ScenePlanner {
    check: Arc<CollisionCheck>,
    cancel: Option<Arc<AtomicBool>>,
}

impl ScenePlanner {
    /// The planner for programs checked by `check`.
    pub fn new(check: Arc<CollisionCheck>, cancel: Option<Arc<AtomicBool>>) -> ScenePlanner {
        ScenePlanner { check, cancel }
    }

    /// As the language's planner.
    pub fn shared(check: Arc<CollisionCheck>, cancel: Option<Arc<AtomicBool>>) -> Arc<dyn PathPlanner> {
        Arc::new(ScenePlanner::new(check, cancel))
    }
}

impl PathPlanner for ScenePlanner {
    fn path(&self, from: &[f64], to: &[f64], seed: u64) -> Result<Vec<Vec<f64>>, String> {
        let options = PlanOptions {
            seed,
            time_limit: Duration::from_secs_f64(AVOID_TIME_LIMIT),
            cancel: self.cancel.as_deref(),
            ..Default::default()
        };
        match plan(&self.check, from, &Goal::Joints(to.to_vec()), &options) {
            Ok(found) => Ok(found.path),
            Err(e) => Err(e.to_string()),
        }
    }
}
