//! Joint-space arithmetic the solvers share: distances between
//! configurations, joint limits (with the tolerance a closed form needs to
//! land on one), whole turns of revolute joints, angle wrapping.

use crate::model::{JointSet, Limits};
use crate::robot::Robot;

/// Distance between two configurations: Euclidean over joints, with the
/// difference of unbounded revolute joints wrapped to (−π, π].
pub fn joint_distance(robot: &Robot, a: &[f64], b: &[f64]) -> f64 {
    robot
        .joints()
        .iter()
        .zip(a.iter().zip(b))
        .map(|(j, (x, y))| {
            let mut d = x - y;
            let unbounded = !(j.limits.min.is_finite() && j.limits.max.is_finite());
            if j.kind == crate::JointType::Revolute && unbounded {
                d = wrap_angle(d);
            }
            d * d
        })
        .sum::<f64>()
        .sqrt()
}

/// The smallest distance of `q` to a joint limit of `robot` \[rad or m\],
/// negative outside; −∞ for a non-finite value (which `f64::min` would
/// skip). The redundancy searches maximise it.
pub(crate) fn limit_margin(robot: &Robot, q: &[f64]) -> f64 {
    let margin = |(j, v): (&crate::model::Joint, &f64)| {
        if v.is_finite() {
            (v - j.limits.min).min(j.limits.max - v)
        } else {
            f64::NEG_INFINITY
        }
    };
    robot.joints().iter().zip(q).map(margin).fold(f64::INFINITY, f64::min)
}

/// How far past a joint limit \[rad or m\] a solver's value may lie and still
/// count as on the limit. The closed forms recover a joint that sits exactly
/// on its limit 1e-16 to 3e-14 rad past it (rounding in atan2 and the
/// subproblems); 1e-9 is four orders of magnitude above that and moves the
/// tool by at most 1e-9 × its distance from the joint axis (≈ 3e-9 m on a 3 m
/// arm), far inside the contract's default 1e-6 m / 1e-6 rad.
pub const LIMIT_TOL: f64 = 1e-9;

/// Moves every value of `q` that lies at most [`LIMIT_TOL`](super::LIMIT_TOL) past one of its
/// joint's limits onto that limit, and returns the joints still outside. Every
/// IK answer goes through it (the contract, path following), so a solution
/// with a joint on its limit is accepted and reported strictly within limits.
pub fn settle_on_limits(robot: &Robot, q: &mut [f64]) -> JointSet {
    for (v, j) in q.iter_mut().zip(robot.joints()) {
        let l = &j.limits;
        if *v < l.min && *v >= l.min - LIMIT_TOL {
            *v = l.min;
        } else if *v > l.max && *v <= l.max + LIMIT_TOL {
            *v = l.max;
        }
    }
    robot.limit_flags(q)
}

/// The values `v + k·2π` of revolute joint `j` within its limits (up to
/// [`LIMIT_TOL`](super::LIMIT_TOL) past one, moved onto it), the one nearest `v` first, into
/// `out` (cleared first); empty when no turn of `v` is within the limits. A
/// joint unbounded on a side has no finite list: it gets the one copy nearest
/// `reference` that is within limits (for a continuous joint, the copy
/// nearest `reference`).
pub(crate) fn turn_copies(j: &crate::model::Joint, v: f64, reference: f64, out: &mut Vec<f64>) {
    use std::f64::consts::TAU;
    out.clear();
    let l = &j.limits;
    if j.kind != crate::JointType::Revolute || !v.is_finite() {
        if v >= l.min - LIMIT_TOL && v <= l.max + LIMIT_TOL {
            out.push(v.clamp(l.min, l.max));
        }
        return;
    }
    let (lo, hi) = (l.min - LIMIT_TOL, l.max + LIMIT_TOL);
    if !(l.min.is_finite() && l.max.is_finite()) {
        let reference = if reference.is_finite() { reference } else { v };
        let mut c = v + ((reference - v) / TAU).round() * TAU;
        if c < lo {
            c += ((lo - c) / TAU).ceil() * TAU;
        } else if c > hi {
            c -= ((c - hi) / TAU).ceil() * TAU;
        }
        if c >= lo && c <= hi {
            out.push(c.clamp(l.min, l.max));
        }
        return;
    }
    let (k_lo, k_hi) = (((lo - v) / TAU).ceil(), ((hi - v) / TAU).floor());
    // A range of more than a few thousand turns is not a joint range; keep the list bounded.
    if !(k_hi - k_lo < 4096.0) {
        return;
    }
    let mut k = k_lo;
    while k <= k_hi {
        out.push((v + k * TAU).clamp(l.min, l.max));
        k += 1.0;
    }
    out.sort_by(|a, b| (a - v).abs().total_cmp(&(b - v).abs()));
}

/// Shifts each revolute joint of `q` by whole turns to the copy within its
/// limits nearest `reference` (see [`turn_copies`]); a joint with no copy
/// within its limits is left as it is. Then [`settle_on_limits`]: returns the
/// joints still outside.
pub(crate) fn nearest_turns(robot: &Robot, q: &mut [f64], reference: &[f64]) -> JointSet {
    let mut copies = Vec::new();
    for ((v, j), r) in q.iter_mut().zip(robot.joints()).zip(reference) {
        turn_copies(j, *v, *r, &mut copies);
        if let Some(c) = copies.iter().copied().min_by(|a, b| (a - r).abs().total_cmp(&(b - r).abs())) {
            *v = c;
        }
    }
    settle_on_limits(robot, q)
}

/// A closed form's angle θ \[rad\] as a joint value: wrapped to (−π, π],
/// then moved by ±2π or ±4π when that brings it within `limits` (else left
/// wrapped, for the limit flags to report).
pub(crate) fn wrap_into_limits(limits: &Limits, theta: f64) -> f64 {
    use std::f64::consts::TAU;
    let q = wrap_angle(theta);
    if limits.contains(q) {
        return q;
    }
    for k in [1.0, -1.0, 2.0, -2.0] {
        if limits.contains(q + k * TAU) {
            return q + k * TAU;
        }
    }
    q
}

/// `a` wrapped to (−π, π].
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    // Fast path for |a| ≤ 3π (every angle the solvers produce): a ∓ 2π is
    // exact there (Sterbenz), so the result equals the remainder below bit for bit.
    if a > -PI && a <= PI {
        return a;
    }
    if a > PI && a <= 3.0 * PI {
        return a - TAU;
    }
    if a <= -PI && a > -3.0 * PI {
        return a + TAU;
    }
    let r = a.rem_euclid(TAU);
    if r > PI {
        r - TAU
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn wrap_angle_fast_path_equals_the_remainder() {
        use std::f64::consts::{PI, TAU};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12);
        for _ in 0..100_000 {
            let a: f64 = rng.random_range(-4.0 * PI..4.0 * PI);
            let r = a.rem_euclid(TAU);
            let want = if r > PI { r - TAU } else { r };
            let got = wrap_angle(a);
            assert!((got - want).abs() <= 4.0 * f64::EPSILON, "{a}: {got} vs {want}");
            assert!(got > -PI && got <= PI);
        }
        assert_eq!(wrap_angle(-PI), PI);
        assert_eq!(wrap_angle(PI), PI);
        assert_eq!(wrap_angle(3.0 * PI), PI);
        assert!(wrap_angle(f64::NAN).is_nan());
    }
}
