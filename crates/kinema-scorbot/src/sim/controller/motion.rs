//! The motion queue and the running motion: piecewise-linear paths of
//! counts in simulated time.

use std::time::Duration;

use crate::encoder::MOTORS;

use super::terminal::{Ctx, Mode};
use super::Controller;

/// Most queued motions.
const MAX_QUEUE: usize = 1000;

/// Maximum motor speeds at `SPEED 100` \[deg/s\] **\[assumed\]**.
const MOTOR_SPEED: [f64; MOTORS] = [90.0, 90.0, 90.0, 180.0, 180.0];
/// Nominal duration of `HOME` \[s\] **\[assumed\]**.
const HOME_SECONDS: f64 = 5.0;
/// Nominal duration of `OPEN`/`CLOSE` \[s\] **\[assumed\]**.
const GRIPPER_SECONDS: f64 = 0.5;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum MotionKind {
    Arm,
    Home,
    Gripper { open: bool },
}

/// A queued motion.
#[derive(Debug, Clone)]
pub(super) struct Item {
    kind: MotionKind,
    /// Arm targets in order (counts).
    targets: Vec<[i64; MOTORS]>,
    /// Total time given with the command \[s, nominal\].
    time: Option<f64>,
    /// The waiting command's output context, if a command waits for it.
    pub(super) waiter: Option<Ctx>,
    /// Close the connection halfway through.
    pub(super) disconnect: bool,
}

/// The running motion: a piecewise-linear path of counts in time.
#[derive(Debug, Clone)]
pub(super) struct Active {
    pub(super) kind: MotionKind,
    pub(super) start: Duration,
    /// (offset from `start` \[s, simulated\], counts).
    knots: Vec<(f64, [f64; MOTORS])>,
    pub(super) waiter: Option<Ctx>,
    /// Offset \[s, simulated\] at which the connection is closed.
    pub(super) disconnect_at: Option<f64>,
}

impl Active {
    pub(super) fn end(&self) -> f64 {
        self.knots.last().map_or(0.0, |k| k.0)
    }

    pub(super) fn at(&self, offset: f64) -> [f64; MOTORS] {
        let first = self.knots.first().map_or([0.0; MOTORS], |k| k.1);
        if offset <= 0.0 {
            return first;
        }
        for w in self.knots.windows(2) {
            let ((t0, a), (t1, b)) = (w[0], w[1]);
            if offset <= t1 {
                let s = if t1 > t0 { ((offset - t0) / (t1 - t0)).clamp(0.0, 1.0) } else { 1.0 };
                return std::array::from_fn(|i| a[i] + s * (b[i] - a[i]));
            }
        }
        self.knots.last().map_or(first, |k| k.1)
    }
}

impl Controller {
    /// Queues a motion (starting it now if the arm is idle). With `waits`,
    /// the command answers when it ends; a disconnect fault rides with it.
    pub(super) fn enqueue(
        &mut self,
        t: Duration,
        kind: MotionKind,
        targets: Vec<[i64; MOTORS]>,
        time: Option<f64>,
        waits: bool,
        ctx: Ctx,
    ) -> std::result::Result<(), String> {
        if self.queue.len() >= MAX_QUEUE {
            return Err("*** BUFFER FULL".into());
        }
        let waiter = waits.then_some(ctx);
        self.queue.push_back(Item { kind, targets, time, waiter, disconnect: ctx.disconnect });
        if self.active.is_none() {
            if let Some(next) = self.queue.pop_front() {
                self.start(next, t);
            }
        }
        Ok(())
    }

    pub(super) fn counts_at(&self, t: Duration) -> [i64; MOTORS] {
        match &self.active {
            Some(a) => round_counts(&a.at(secs(t.saturating_sub(a.start)))),
            None => self.counts,
        }
    }

    /// Where the arm will be when every queued motion has ended.
    pub(super) fn planned_end(&self) -> [i64; MOTORS] {
        for item in self.queue.iter().rev() {
            match item.kind {
                MotionKind::Arm => {
                    if let Some(c) = item.targets.last() {
                        return *c;
                    }
                }
                MotionKind::Home => return [0; MOTORS],
                MotionKind::Gripper { .. } => {}
            }
        }
        match &self.active {
            Some(a) => round_counts(&a.at(a.end())),
            None => self.counts,
        }
    }

    /// Nominal duration of a move between counts \[s\] at the current speed.
    fn move_seconds(&self, a: &[f64; MOTORS], b: &[f64; MOTORS]) -> f64 {
        (0..MOTORS)
            .map(|i| {
                let du = (b[i] - a[i]).abs() / self.constants.counts_per_degree[i].abs();
                du / (MOTOR_SPEED[i] * f64::from(self.speed) / 100.0)
            })
            .fold(0.0, f64::max)
    }

    pub(super) fn start(&mut self, item: Item, t: Duration) {
        let from = self.counts.map(|v| v as f64);
        let scale = self.time_scale;
        let knots = match item.kind {
            MotionKind::Home => vec![(0.0, from), (HOME_SECONDS * scale, [0.0; MOTORS])],
            MotionKind::Gripper { .. } => vec![(0.0, from), (GRIPPER_SECONDS * scale, from)],
            MotionKind::Arm => {
                let mut points = vec![from];
                points.extend(item.targets.iter().map(|c| c.map(|v| v as f64)));
                let mut seg: Vec<f64> = points.windows(2).map(|w| self.move_seconds(&w[0], &w[1])).collect();
                if let Some(total) = item.time {
                    let sum: f64 = seg.iter().sum();
                    let n = seg.len().max(1) as f64;
                    for s in &mut seg {
                        *s = if sum > 0.0 { total * *s / sum } else { total / n };
                    }
                }
                let mut knots = vec![(0.0, from)];
                let mut acc = 0.0;
                for (s, p) in seg.iter().zip(&points[1..]) {
                    acc += s * scale;
                    knots.push((acc, *p));
                }
                knots
            }
        };
        let mut a = Active { kind: item.kind, start: t, knots, waiter: item.waiter, disconnect_at: None };
        if item.disconnect {
            a.disconnect_at = Some(a.end() / 2.0);
        }
        self.active = Some(a);
    }

    /// The running motion reaches its end at `t`.
    pub(super) fn finish(&mut self, t: Duration) {
        let Some(a) = self.active.take() else { return };
        let end = a.end();
        self.counts = round_counts(&a.at(end));
        match a.kind {
            MotionKind::Home => self.homed = true,
            MotionKind::Gripper { open } => self.gripper_open = open,
            MotionKind::Arm => {}
        }
        self.sample(&a, end);
        if let Some(w) = a.waiter {
            self.emit_line(t, w, "Done.");
            self.emit_prompt(t, w);
            self.mode = Mode::Idle;
            self.pump(t);
        }
    }

    /// Stops the arm where it is at `t` and empties the queue; waiting
    /// commands end with `*** MOTION ABORTED` if `notify`.
    pub(super) fn halt(&mut self, t: Duration, notify: bool) {
        let mut waiters = Vec::new();
        if let Some(a) = self.active.take() {
            let off = secs(t.saturating_sub(a.start)).min(a.end());
            self.counts = round_counts(&a.at(off));
            if a.kind == MotionKind::Home {
                self.homed = false;
            }
            self.sample(&a, off);
            waiters.extend(a.waiter);
        }
        waiters.extend(self.queue.drain(..).filter_map(|i| i.waiter));
        if notify {
            self.abort_waiters(t, waiters);
        } else if !waiters.is_empty() {
            self.mode = Mode::Idle;
        }
    }

    pub(super) fn abort_waiters(&mut self, t: Duration, waiters: Vec<Ctx>) {
        if waiters.is_empty() {
            return;
        }
        for w in waiters {
            self.emit_line(t, w, "*** MOTION ABORTED");
            self.emit_prompt(t, w);
        }
        self.mode = Mode::Idle;
    }
}

pub(super) fn secs(d: Duration) -> f64 {
    d.as_secs_f64()
}

pub(super) fn dur(s: f64) -> Duration {
    Duration::try_from_secs_f64(s.max(0.0)).unwrap_or(Duration::MAX)
}

pub(super) fn round_counts(c: &[f64; MOTORS]) -> [i64; MOTORS] {
    c.map(|v| v.round() as i64)
}
