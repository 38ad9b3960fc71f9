//! The braking pre-phase: a start state beyond the limits (|v₀| > v_max,
//! |a₀| > a_max, or an acceleration that carries the velocity past v_max
//! whatever the jerk) is first brought back within them as fast as the jerk
//! (or, second order, the acceleration) allows; the law proper starts from
//! the braked state. The limits are broken during the brake only, and only
//! because the start state broke them — as Ruckig does (Berscheid & Kröger
//! 2021, §V).

use super::problem::Limits;
use super::profile::Profile;
use super::BoundaryState;

/// How the start state is brought within the limits: the segments, and the
/// state after them.
#[derive(Debug, Clone, Copy)]
pub(super) struct Brake {
    pub profile: Profile,
    pub braked: BoundaryState,
}

impl Brake {
    /// The brake for `from` (no segments when it is within the limits).
    pub fn of(from: &BoundaryState, l: &Limits) -> Brake {
        let profile = match l.jerk {
            Some(j) => third_order(from.v, from.a, l.vel, l.acc, j),
            None => second_order(from.v, l.vel, l.acc),
        };
        let (dp, v, a) = profile.integrate(from.v, from.a);
        // A brake ends on a limit it aimed at exactly; rounding must not
        // leave the state a hair beyond it. A second-order law steps its
        // acceleration: it leaves the brake with a = 0.
        if profile.segments().is_empty() {
            return Brake { profile, braked: *from };
        }
        let v = v.clamp(-l.vel, l.vel);
        let a = if l.jerk.is_some() { a.clamp(-l.acc, l.acc) } else { 0.0 };
        Brake { profile, braked: BoundaryState { p: from.p + dp, v, a } }
    }

    /// Duration of the brake \[s\].
    pub fn duration(&self) -> f64 {
        self.profile.duration()
    }
}

/// Whether a jerk-limited law may start at (v, a): the acceleration within
/// ±a_max and the velocity within ±v_max now and when the acceleration has
/// been brought to 0 (v + a|a|/(2 j_max)). The same tolerances as the
/// check of the states.
pub(super) fn within(v: f64, a: f64, vel: f64, acc: f64, j: f64) -> bool {
    let reach = v + a * a.abs() / (2.0 * j);
    a.abs() <= acc * (1.0 + 1e-12) && v.abs() <= vel * (1.0 + 1e-12) && reach.abs() <= vel * (1.0 + 1e-9)
}

/// Second order: a step to ∓a_max until the velocity is back at ±v_max.
fn second_order(v0: f64, vel: f64, acc: f64) -> Profile {
    let mut s = Profile::default();
    if v0.abs() > vel * (1.0 + 1e-12) {
        s.push((v0.abs() - vel) / acc, 0.0, Some(-acc.copysign(v0)));
    }
    s
}

/// Third order. An acceleration beyond ±a_max is first ramped back to the
/// limit. Then the state is too high (v > v_max, or a > 0 carrying v past
/// v_max) or too low (the mirror image); when it is both (v > v_max while
/// a < 0 carries v below −v_max) the acceleration is the more urgent and
/// decides. A too-low state is braked in the mirrored frame.
fn third_order(v0: f64, a0: f64, vel: f64, acc: f64, j: f64) -> Profile {
    let mut s = Profile::default();
    if within(v0, a0, vel, acc, j) {
        return s;
    }
    let (mut v, mut a) = (v0, a0);
    if a.abs() > acc {
        let (t, jerk) = ((a.abs() - acc) / j, -j.copysign(a));
        s.push(t, jerk, None);
        v += t * (a + t * jerk / 2.0);
        a = acc.copysign(a);
    }
    if within(v, a, vel, acc, j) {
        return s;
    }
    let reach = v + a * a.abs() / (2.0 * j);
    let too_low = (a < 0.0 && reach < -vel) || (v < -vel && !(a > 0.0 && reach > vel));
    if too_low {
        s.extend(&down(-v, -a, vel, acc, j).mirrored());
    } else {
        s.extend(&down(v, a, vel, acc, j));
    }
    s
}

/// Brings a too-high state (v0, a0), |a0| ≤ a_max, down, stopping at the first moment it is
/// within the limits: jerk −j_max until a reaches −a_max, v falls to v_max,
/// or v + a|a|/(2 j_max) falls to −v_max (braking on would carry v below
/// −v_max); then a hold at −a_max on the same conditions; then +j_max until
/// v falls to v_max, with the acceleration easing so that the velocity it
/// carries to stays at −v_max.
fn down(v0: f64, a0: f64, vel: f64, acc: f64, j: f64) -> Profile {
    let mut s = Profile::default();
    // Jerk −j from (v0, a0): a = a0 − j t, v = v0 + a0 t − j t²/2.
    let to_acc_floor = (a0 + acc) / j;
    let to_vel = (a0 + (a0 * a0 + 2.0 * j * (v0 - vel)).max(0.0).sqrt()) / j;
    // v − a²/(2j) = v0 − a0²/(2j) + 2 a0 t − j t² (for a < 0) meets −v_max.
    let to_reach = (a0 + (a0 * a0 / 2.0 + j * (v0 + vel)).max(0.0).sqrt()) / j;
    let (mut v, mut a) = (v0, a0);
    let ramp = |s: &mut Profile, v: &mut f64, a: &mut f64, t: f64, jerk: f64| {
        s.push(t, jerk, None);
        *v += t * (*a + t * jerk / 2.0);
        *a += t * jerk;
    };
    let first = to_acc_floor.min(to_vel).min(to_reach).max(0.0);
    ramp(&mut s, &mut v, &mut a, first, -j);
    if within(v, a, vel, acc, j) {
        return s;
    }
    if first == to_acc_floor {
        // Hold −a_max until v = v_max, or until v − a_max²/(2j) = −v_max.
        let hold = ((v - vel) / acc).min((v + vel - acc * acc / (2.0 * j)) / acc).max(0.0);
        s.push(hold, 0.0, None);
        v -= acc * hold;
        if within(v, a, vel, acc, j) {
            return s;
        }
    }
    // Now v > v_max, a < 0 and v − a²/(2j) = −v_max: +j keeps that reach
    // and lowers v to v_max at the earlier root of v + a t + j t²/2 = v_max.
    let disc = (a * a - 2.0 * j * (v - vel)).max(0.0);
    let t = (-a - disc.sqrt()) / j;
    ramp(&mut s, &mut v, &mut a, t, j);
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traj::boundary::roots::Search;
    use crate::traj::MotionLimits;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn limits(vel: f64, acc: f64, jerk: f64) -> Limits {
        Limits::new(&MotionLimits::with_jerk(vel, acc, jerk), Search::Fast).unwrap()
    }

    #[test]
    fn states_within_the_limits_need_no_brake() {
        let l = limits(1.0, 2.0, 4.0);
        let b = Brake::of(&BoundaryState::new(0.3, 0.5, -1.0), &l);
        assert_eq!(b.duration(), 0.0);
        assert_eq!(b.braked, BoundaryState::new(0.3, 0.5, -1.0));
    }

    #[test]
    fn a_velocity_beyond_vmax_brakes_to_vmax_at_full_jerk() {
        // v0 = 2, a0 = 0, j = 4: −j until v = 1: 2 − 2t² = 1, t = 1/√2; a = −2√2 < −a_max = −3? no.
        let l = limits(1.0, 3.0, 4.0);
        let b = Brake::of(&BoundaryState::new(0.0, 2.0, 0.0), &l);
        let t = (0.5f64).sqrt();
        assert!((b.duration() - t).abs() < 1e-12, "{}", b.duration());
        assert!((b.braked.v - 1.0).abs() < 1e-12 && (b.braked.a + 4.0 * t).abs() < 1e-12);
    }

    #[test]
    fn random_states_beyond_the_limits_end_within_them_at_full_jerk() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for case in 0..20_000 {
            let (vel, acc) = (rng.random_range(0.1..10.0), rng.random_range(0.1..100.0));
            let j = rng.random_range(1.0..1000.0);
            let l = limits(vel, acc, j);
            let from = BoundaryState::new(0.0, rng.random_range(-3.0..3.0) * vel, rng.random_range(-3.0..3.0) * acc);
            let b = Brake::of(&from, &l);
            let s = b.braked;
            assert!(within(s.v, s.a, vel, acc, j), "case {case}: {from:?} braked to {s:?}");
            for seg in b.profile.segments() {
                assert!(seg.jerk.abs() == j || seg.jerk == 0.0, "case {case}");
                assert!(seg.dt.is_finite() && seg.dt > 0.0, "case {case}");
            }
            assert!(b.profile.segments().len() <= 4, "case {case}");
        }
    }
}
