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

/// The fastest velocity change (v0, a0) → (v1, a1), ignoring position, and
/// its duration. Of changes equally fast the first of rise and fall with
/// the peak +√K, then with −√K, is kept.
///
/// Where one boundary acceleration is 0 (every change of a cruise) and the
/// target velocity is clearly above the velocity the other acceleration
/// carries the motion to when ramped to 0 (v₀ + a₀|a₀|/(2j) from the start,
/// v₁ − a₁|a₁|/(2j) back from the target), only the rise with the peak +√K
/// exists (the others need K or a peak within rounding of 0); clearly below
/// it, only the fall. Only near that velocity are all four tried.
pub(super) fn fastest_change(v0: f64, a0: f64, v1: f64, a1: f64, l: &Limits, j: f64) -> Option<(Change, f64)> {
    if a0 == 0.0 || a1 == 0.0 {
        let gap = j * (v1 - v0) - 0.5 * (a0 * a0.abs() + a1 * a1.abs());
        let margin = 1e-9 * l.acc * l.acc + 64.0 * f64::EPSILON * (j * (v0.abs() + v1.abs()) + a0 * a0 + a1 * a1);
        let timed = |c: Change| (c, c.duration());
        if gap > margin {
            return rise(v0, a0, v1, a1, l, j, true).map(timed);
        }
        if gap < -margin {
            return fall(v0, a0, v1, a1, l, j, true).map(timed);
        }
    }
    fastest_of_four(v0, a0, v1, a1, l, j)
}

/// [`fastest_change`] by trying rise and fall with either peak.
fn fastest_of_four(v0: f64, a0: f64, v1: f64, a1: f64, l: &Limits, j: f64) -> Option<(Change, f64)> {
    let mut best: Option<(Change, f64)> = None;
    for root in [true, false] {
        for s in [rise(v0, a0, v1, a1, l, j, root), fall(v0, a0, v1, a1, l, j, root)].into_iter().flatten() {
            let d = s.duration();
            if best.is_none_or(|(_, b)| d < b) {
                best = Some((s, d));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::super::roots::Search;
    use super::*;
    use crate::traj::law::MotionLimits;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The shortcut gives the very change the four candidates give (to the
    /// bit), for changes to and from a cruise, many of them with the cruise
    /// velocity within rounding of the velocity where rise turns to fall.
    #[test]
    fn the_shortcut_is_the_fastest_of_four() {
        let mut rng = ChaCha8Rng::seed_from_u64(3605);
        for case in 0..200_000 {
            let (vel, acc, j) =
                (rng.random_range(0.1..10.0), rng.random_range(0.1..100.0), rng.random_range(1.0..1000.0));
            let l = Limits::new(&MotionLimits::with_jerk(vel, acc, j), Search::Fast).unwrap();
            let v = rng.random_range(-vel..vel);
            let a = if rng.random_bool(0.1) { 0.0 } else { rng.random_range(-acc..acc) };
            let natural = v + a * a.abs() / (2.0 * j);
            let vc = match rng.random_range(0..3) {
                0 => natural,
                1 => natural * (1.0 + rng.random_range(-1e-8..1e-8)),
                _ => rng.random_range(-vel..vel),
            };
            let key = |c: Option<(Change, f64)>| c.map(|(c, d)| (c.ramp_up, c.hold, c.ramp_down, c.jerk, d));
            let to_cruise = (fastest_change(v, a, vc, 0.0, &l, j), fastest_of_four(v, a, vc, 0.0, &l, j));
            assert_eq!(key(to_cruise.0), key(to_cruise.1), "case {case}: ({v}, {a}) to {vc} {l:?}");
            let back = 2.0 * v - natural; // v − a|a|/(2j): the target's natural velocity
            let from = if rng.random_bool(0.5) { back } else { vc };
            let from_cruise = (fastest_change(from, 0.0, v, a, &l, j), fastest_of_four(from, 0.0, v, a, &l, j));
            assert_eq!(key(from_cruise.0), key(from_cruise.1), "case {case}: {from} to ({v}, {a}) {l:?}");
        }
    }
}
