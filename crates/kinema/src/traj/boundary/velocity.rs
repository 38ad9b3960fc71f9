//! Third-order velocity changes: the fastest way from (v₀, a₀) to (v₁, a₁)
//! ignoring position, the building block of every third-order family.

use super::problem::Limits;
use super::profile::Profile;

/// The velocity change (v0, a0) → (v1, a1) with jerk +j up to a peak
/// acceleration a_p (held at a_max if it would exceed it), then −j down to
/// a1. `root` picks a_p = +√K or −√K (both may be valid).
pub(super) fn rise(v0: f64, a0: f64, v1: f64, a1: f64, l: &Limits, j: f64, root: bool) -> Option<Profile> {
    let k = j * (v1 - v0) + 0.5 * (a0 * a0 + a1 * a1);
    let hi = a0.max(a1);
    let tol = 1e-12 * l.acc;
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
    let mut s = Profile::default();
    s.push((ap - a0) / j, j, None);
    s.push(hold, 0.0, None);
    s.push((ap - a1) / j, -j, None);
    Some(s)
}

/// As [`rise`] with the signs reversed: −j down to a valley, hold at −a_max, +j.
pub(super) fn fall(v0: f64, a0: f64, v1: f64, a1: f64, l: &Limits, j: f64, root: bool) -> Option<Profile> {
    rise(-v0, -a0, -v1, -a1, l, j, root).map(|s| s.mirrored())
}

/// The fastest velocity change (v0, a0) → (v1, a1), ignoring position.
pub(super) fn fastest_change(v0: f64, a0: f64, v1: f64, a1: f64, l: &Limits, j: f64) -> Option<Profile> {
    let mut best: Option<Profile> = None;
    for root in [true, false] {
        for s in [rise(v0, a0, v1, a1, l, j, root), fall(v0, a0, v1, a1, l, j, root)].into_iter().flatten() {
            if best.is_none_or(|b| s.duration() < b.duration()) {
                best = Some(s);
            }
        }
    }
    best
}
