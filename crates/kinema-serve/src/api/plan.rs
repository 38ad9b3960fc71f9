//! `POST /api/plan`: a collision-free motion (`kinema_geometry::plan`), the
//! answer of `kinema plan --json` with the samples.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use kinema::traj::{Ptp, PtpOptions};
use kinema_geometry::plan::{plan, Goal, Plan, PlanOptions};
use kinema_io::{PlanAnswer, TrajSummary, TrajectoryAnswer};
use kinema_lang::{Stop, StopReason};
use serde_json::Value;

use super::{bad, cap_samples, check_dt, named, to_value, App, TrajAnswer};
use crate::error::{Error, Result};
use crate::request::{parse, PlanReq};

/// Longest planning time a `/api/plan` request may ask for (10 s); a larger
/// `time_limit` is cut to it. The server's time budget of a heavy request
/// ([`crate::RUN_BUDGET`] by default) stops a run sooner if it is shorter.
pub const MAX_PLAN_TIME: Duration = Duration::from_secs(10);

const SHAPE: &str = r#"{"robot": "NAME", "from": [q], "to": [q]} or {"robot": "NAME", "from": [q], "pose": [x, y, z, roll, pitch, yaw] or [[4 numbers] × 4 rows]}, optional "rpy_convention", "scene" (a scene file's TOML text; default: the server's scene), "margin" (m), "seed", "time_limit" (s, at most 10), "dt" (s), "profile", "speed" (%)"#;

impl App {
    /// A planned motion from `from` to `to` or `pose`, timed and sampled as
    /// `kinema plan` does it, stopped by `stop` (a deadline or a flag).
    pub(super) fn plan(&self, body: &[u8], stop: &Stop) -> Result<Value> {
        let req: PlanReq = parse(body, "/api/plan", SHAPE)?;
        let check = self.collision_check(&req.robot, req.scene.as_deref(), req.margin)?;
        let robot = check.robot();
        let goal = match (&req.to, &req.pose) {
            (Some(to), None) => Goal::Joints(to.clone()),
            (None, Some(pose)) => Goal::Pose(pose.pose(req.rpy_convention.as_deref())?),
            _ => return Err(bad(format!("/api/plan: give \"to\" or \"pose\", one of them; expected {SHAPE}"))),
        };
        let time_limit = req.time_limit.unwrap_or(1.0);
        if !(time_limit > 0.0 && time_limit.is_finite()) {
            return Err(bad(format!("/api/plan: time_limit {time_limit}: expected seconds > 0")));
        }
        let speed = req.speed.unwrap_or(100.0);
        if !(speed > 0.0 && speed <= 100.0) {
            return Err(bad(format!("/api/plan: speed {speed} must be a percentage in (0, 100]")));
        }
        let dt = req.dt.unwrap_or(0.01);
        check_dt(dt)?;
        let profile = named("/api/plan", req.profile.as_deref(), kinema::traj::default_profile(robot))?;
        let ptp = PtpOptions { profile, speed: speed / 100.0, ..PtpOptions::for_robot(robot) };
        kinema::traj::via::check_timing(robot, &req.from, &ptp, dt)?;
        let found = until_stopped(stop, |cancel| {
            let options = PlanOptions {
                seed: req.seed.unwrap_or(0),
                time_limit: Duration::from_secs_f64(time_limit.min(MAX_PLAN_TIME.as_secs_f64())),
                cancel: Some(cancel),
                ..Default::default()
            };
            plan(&check, &req.from, &goal, &options)
        })
        .map_err(|e| planning_error(e, stop))?;
        cap_samples(duration(robot, &found, &ptp)?, dt)?;
        let traj = found.trajectory(robot, &ptp, dt).map_err(|e| planning_error(e, stop))?;
        // The samples pass the checks `kinema plan` makes of what it writes.
        kinema::traj::check(robot, &traj, &Default::default())?.into_result()?;
        kinema::traj::collision_free(&traj, &check)?;
        let duration = traj.times().last().copied().unwrap_or(0.0);
        let summary = TrajSummary {
            plan: Some(PlanAnswer::new(&found)),
            ..TrajSummary::new(robot, "plan", Some(profile.name()), duration, traj.len())
        };
        to_value(TrajAnswer { summary, samples: TrajectoryAnswer(&traj) })
    }
}

/// The duration of `found` timed under `ptp`: a PTP per segment, at rest at
/// every via point (as [`Plan::trajectory`] samples it).
fn duration(robot: &kinema::Robot, found: &Plan, ptp: &PtpOptions) -> Result<f64> {
    let mut total = 0.0;
    for w in found.path.windows(2) {
        total += Ptp::new(robot, &w[0], &w[1], ptp)?.duration();
    }
    Ok(total)
}

/// `work` given a flag that is raised once `stop` says to stop: the planner
/// polls a flag, while a stop condition is a deadline and a flag of its own.
fn until_stopped<T>(stop: &Stop, work: impl FnOnce(&AtomicBool) -> T) -> T {
    let (cancel, done) = (AtomicBool::new(stop.reason().is_some()), AtomicBool::new(false));
    std::thread::scope(|s| {
        let watcher = s.spawn(|| {
            while !done.load(Ordering::Relaxed) {
                if stop.reason().is_some() {
                    cancel.store(true, Ordering::Relaxed);
                    return;
                }
                std::thread::park_timeout(Duration::from_millis(5));
            }
        });
        // Ends the watcher however `work` ends, a panic included, so the
        // scope never waits on it.
        let _finished = Finished { done: &done, watcher: watcher.thread().clone() };
        work(&cancel)
    })
}

/// Tells a watcher thread its work is over, when dropped.
struct Finished<'a> {
    done: &'a AtomicBool,
    watcher: std::thread::Thread,
}

impl Drop for Finished<'_> {
    fn drop(&mut self) {
        self.done.store(true, Ordering::Relaxed);
        self.watcher.unpark();
    }
}

/// The server's error for a planner's: the core's message (422), or why
/// `stop` ended the run.
fn planning_error(e: kinema_geometry::Error, stop: &Stop) -> Error {
    match (e, stop.reason()) {
        (kinema_geometry::Error::Interrupted, Some(StopReason::Cancelled)) => Error::ShuttingDown,
        (kinema_geometry::Error::Interrupted, Some(reason)) => {
            Error::Unprocessable { message: format!("planning was stopped: {reason}") }
        }
        (kinema_geometry::Error::Kinema(core), _) => Error::Core(core),
        (e, _) => Error::Unprocessable { message: e.to_string() },
    }
}

#[cfg(test)]
mod tests {
    use std::time::Instant;

    use super::*;

    #[test]
    fn a_panicking_run_releases_its_watcher_at_once() {
        let stop = Stop::never();
        let started = Instant::now();
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            until_stopped(&stop, |_| -> () { panic!("a planner defect") })
        }));
        assert!(outcome.is_err());
        assert!(started.elapsed() < Duration::from_secs(5), "{:?}", started.elapsed());
    }
}
