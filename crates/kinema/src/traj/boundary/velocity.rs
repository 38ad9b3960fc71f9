//! Third-order velocity changes: the fastest way from (v₀, a₀) to (v₁, a₁)
//! ignoring position, the building block of every third-order family.

use super::problem::Limits;
use super::profile::{JerkSegment, Profile};

/// A velocity change: jerk `jerk` for `ramp_up`, a hold, then −`jerk` for
/// `ramp_down`. Kept as three numbers (not a [`Profile`]) because the
/// searches compare many of them by duration before building one.
#[derive(Debug, Clone, Copy)]
pub(super) struct Change {
    ramp_up: f64,
    hold: f64,
    ramp_down: f64,
    jerk: f64,
}

impl Change {
    /// Duration, summed as the profile sums its non-empty segments.
    pub fn duration(&self) -> f64 {
        [self.ramp_up, self.hold, self.ramp_down].iter().filter(|&&t| t > 0.0).sum()
    }

    pub fn profile(&self) -> Profile {
        Profile::from_segments(&self.segments())
    }

    /// The ramp up, the hold and the ramp down (lengths possibly 0).
    pub fn segments(&self) -> [JerkSegment; 3] {
        [
            JerkSegment { dt: self.ramp_up, jerk: self.jerk, set_acc: None },
            JerkSegment { dt: self.hold, jerk: 0.0, set_acc: None },
            JerkSegment { dt: self.ramp_down, jerk: -self.jerk, set_acc: None },
        ]
    }

    fn mirrored(self) -> Change {
        Change { jerk: -self.jerk, ..self }
    }
}

/// The velocity change (v0, a0) → (v1, a1) with jerk +j up to a peak
/// acceleration a_p (held at a_max if it would exceed it), then −j down to
/// a1. `root` picks a_p = +√K or −√K (both may be valid).
pub(super) fn rise(v0: f64, a0: f64, v1: f64, a1: f64, l: &Limits, j: f64, root: bool) -> Option<Change> {
    let hi = a0.max(a1);
    let tol = 1e-12 * l.acc;
    if !root && hi > tol {
        return None; // a peak −√K ≤ 0 below a boundary acceleration
    }
    let k = j * (v1 - v0) + 0.5 * (a0 * a0 + a1 * a1);
    if k < -tol * l.acc {
        return None;
    }
    let r = k.max(0.0).sqrt();
    let mut ap = if root { r } else { -r };
    if ap < hi - tol {
        return None;
    }
    ap = ap.max(hi);
    let mut hold = 0.0;
    if ap > l.acc {
        if !root {
            return None;
        }
        ap = l.acc;
        hold = (v1 - v0 - (2.0 * ap * ap - a0 * a0 - a1 * a1) / (2.0 * j)) / ap;
        if hold < 0.0 {
            return None;
        }
    }
    Some(Change { ramp_up: (ap - a0) / j, hold, ramp_down: (ap - a1) / j, jerk: j })
}

/// As [`rise`] with the signs reversed: −j down to a valley, hold at −a_max, +j.
pub(super) fn fall(v0: f64, a0: f64, v1: f64, a1: f64, l: &Limits, j: f64, root: bool) -> Option<Change> {
    rise(-v0, -a0, -v1, -a1, l, j, root).map(Change::mirrored)
}

/// The fastest velocity change (v0, a0) → (v1, a1), ignoring position.
pub(super) fn fastest_change(v0: f64, a0: f64, v1: f64, a1: f64, l: &Limits, j: f64) -> Option<Change> {
    let mut best: Option<Change> = None;
    for root in [true, false] {
        for s in [rise(v0, a0, v1, a1, l, j, root), fall(v0, a0, v1, a1, l, j, root)].into_iter().flatten() {
            if best.is_none_or(|b| s.duration() < b.duration()) {
                best = Some(s);
            }
        }
    }
    best
}
