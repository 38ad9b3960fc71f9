//! Time-optimal laws between arbitrary boundary states (issue 25): seeded
//! property tests over random states — limits kept, target reached,
//! duration no shorter than a provable lower bound — rest-to-rest equality
//! with the S-curve and trapezoid laws, prescribed durations met exactly,
//! and synchronisation through blocked intervals.

use kinema::traj::boundary::reference;
use kinema::traj::{sync_duration, BoundaryLaw, BoundaryState, MotionLimits, Profile, TimeLaw};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const REL: f64 = 1e-9;

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    (rng.random_range(lo.ln()..hi.ln())).exp()
}

fn random_limits(rng: &mut ChaCha8Rng, jerk: bool) -> MotionLimits {
    let (v, a) = (log_uniform(rng, 0.1, 10.0), log_uniform(rng, 0.1, 100.0));
    if jerk {
        MotionLimits::with_jerk(v, a, log_uniform(rng, 1.0, 1000.0))
    } else {
        MotionLimits::new(v, a)
    }
}

/// A random state that a law can start from: |v| ≤ v_max, |a| ≤ a_max and
/// the acceleration does not carry the velocity past v_max (both in time
/// directions: it is also used as a target).
fn random_state(rng: &mut ChaCha8Rng, lim: &MotionLimits, p: f64) -> BoundaryState {
    let special = rng.random_range(0..6);
    let mut v = rng.random_range(-lim.vel..=lim.vel);
    let mut a = match lim.jerk {
        Some(_) => rng.random_range(-lim.acc..=lim.acc),
        None => 0.0,
    };
    match special {
        0 => v = 0.0,
        1 => a = 0.0,
        2 => (v, a) = (0.0, 0.0),
        _ => {}
    }
    if let Some(j) = lim.jerk {
        // Shrink a until v ± a²/(2j) stays within ±v_max.
        let room = lim.vel - v.abs();
        let amax = (2.0 * j * room).sqrt();
        a = a.clamp(-amax, amax);
    }
    BoundaryState::new(p, v, a)
}

/// Samples the law finely and checks limits (past the brake of a start
/// beyond them), continuity and the end state.
fn check_law(law: &BoundaryLaw, lim: &MotionLimits, what: &str) {
    let (v, a, j) = law.peaks();
    let braking = law.braking_duration();
    if braking == 0.0 {
        assert!(v <= lim.vel * (1.0 + REL), "{what}: |v| {v} > {}", lim.vel);
        assert!(a <= lim.acc * (1.0 + REL), "{what}: |a| {a} > {}", lim.acc);
    }
    if let Some(jm) = lim.jerk {
        assert!(j <= jm * (1.0 + REL), "{what}: |j| {j} > {jm}");
    }
    let t_end = law.duration();
    let n = 400;
    let from = law.from();
    let to = law.to();
    let start = law.at(0.0);
    assert_eq!(start, from, "{what}");
    let scale = from.p.abs().max(to.p.abs()).max(lim.vel * t_end).max(1e-12);
    let mut prev = law.at(0.0);
    for k in 1..=n {
        let t = t_end * k as f64 / n as f64;
        let s = if k == n {
            // The end of the last phase, approached from inside.
            law.at(t_end * (1.0 - 1e-12))
        } else {
            law.at(t)
        };
        let dt = t_end / n as f64;
        if t > braking + dt {
            assert!(s.v.abs() <= lim.vel * (1.0 + REL), "{what}: v {} at {t}", s.v);
            assert!(s.a.abs() <= lim.acc * (1.0 + REL), "{what}: a {} at {t}", s.a);
            // Position is the integral of velocity (trapezoid rule bound).
            assert!((s.p - prev.p).abs() <= lim.vel * dt * (1.0 + 1e-6) + 1e-12 * scale, "{what}: jump at {t}");
        }
        prev = s;
    }
    // The end of the last phase, approached from inside: what is left to go
    // in the last 1e-13·T is bounded by the limits.
    let tiny = t_end * 1e-13;
    let e = law.at(t_end - tiny);
    let jm = lim.jerk.unwrap_or(0.0);
    assert!((e.p - to.p).abs() <= 1e-9 * scale + lim.vel * tiny, "{what}: end p {} vs {}", e.p, to.p);
    assert!((e.v - to.v).abs() <= 1e-9 * lim.vel + lim.acc * tiny, "{what}: end v {} vs {}", e.v, to.v);
    if lim.jerk.is_some() {
        assert!((e.a - to.a).abs() <= 1e-9 * lim.acc + jm * tiny, "{what}: end a {} vs {}", e.a, to.a);
    }
}

/// A duration no law can beat: the velocity change alone needs
/// |v_f − v_0|/a_max, and (third order) the acceleration change |a_f − a_0|/j_max.
fn lower_bound(from: &BoundaryState, to: &BoundaryState, lim: &MotionLimits) -> f64 {
    let mut t = (to.v - from.v).abs() / lim.acc;
    if let Some(j) = lim.jerk {
        t = t.max((to.a - from.a).abs() / j);
    }
    // Covering the distance at no more than v_max.
    t.max((to.p - from.p).abs() / lim.vel)
}

#[test]
fn rest_to_rest_equals_the_scurve_and_trapezoid_laws() {
    let mut rng = ChaCha8Rng::seed_from_u64(2501);
    for case in 0..2000 {
        let jerk = case % 2 == 0;
        let lim = random_limits(&mut rng, jerk);
        let d = log_uniform(&mut rng, 1e-3, 1e2) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        let p0 = rng.random_range(-3.0..3.0);
        let law = BoundaryLaw::fastest(BoundaryState::rest(p0), BoundaryState::rest(p0 + d), &lim).unwrap();
        let profile = if jerk { Profile::SCurve } else { Profile::Trapezoid };
        let reference = TimeLaw::from_limits(profile, d.abs(), &lim).unwrap();
        let rel = (law.duration() - reference.duration()).abs() / reference.duration();
        assert!(rel <= 1e-12, "case {case}: {} vs {} ({lim:?}, d {d})", law.duration(), reference.duration());
        check_law(&law, &lim, &format!("case {case}"));
    }
}

#[test]
fn random_boundary_states_keep_the_limits_and_reach_the_target() {
    let mut rng = ChaCha8Rng::seed_from_u64(2502);
    let mut count = 0;
    for case in 0..6000 {
        let jerk = case % 3 != 0;
        let lim = random_limits(&mut rng, jerk);
        let p0 = rng.random_range(-3.0..3.0);
        let d = match rng.random_range(0..4) {
            0 => 0.0,
            1 => rng.random_range(-1e-3..1e-3),
            _ => rng.random_range(-5.0..5.0),
        };
        let from = random_state(&mut rng, &lim, p0);
        let to = random_state(&mut rng, &lim, p0 + d);
        let law = match BoundaryLaw::fastest(from, to, &lim) {
            Ok(l) => l,
            Err(e) => panic!("case {case}: {from:?} → {to:?} {lim:?}: {e}"),
        };
        check_law(&law, &lim, &format!("case {case}"));
        let lb = lower_bound(&from, &to, &lim);
        assert!(law.duration() >= lb * (1.0 - 1e-12), "case {case}: {} < bound {lb}", law.duration());
        count += 1;
    }
    assert_eq!(count, 6000);
}

#[test]
fn prescribed_durations_end_exactly_then_and_blocked_ones_are_refused() {
    let mut rng = ChaCha8Rng::seed_from_u64(2503);
    let (mut solved, mut blocked) = (0, 0);
    for case in 0..3000 {
        let jerk = case % 2 == 0;
        let lim = random_limits(&mut rng, jerk);
        let p0 = rng.random_range(-3.0..3.0);
        let d = if rng.random_bool(0.3) { rng.random_range(-0.05..0.05) } else { rng.random_range(-5.0..5.0) };
        let from = random_state(&mut rng, &lim, p0);
        let to = random_state(&mut rng, &lim, p0 + d);
        let critical = BoundaryLaw::critical_durations(from, to, &lim).unwrap();
        let fastest = BoundaryLaw::fastest(from, to, &lim).unwrap();
        assert_eq!(critical[0], fastest.duration(), "case {case}");
        assert!(critical.len() % 2 == 1, "case {case}: {critical:?}");
        let t = fastest.duration() * (1.0 + rng.random_range(0.0..2.0)) + rng.random_range(0.0..0.1);
        // Feasible on [d0, d1] ∪ [d2, d3] ∪ … ∪ [d_last, ∞).
        let inside = critical.iter().filter(|&&c| c <= t).count() % 2 == 1;
        match BoundaryLaw::with_duration(from, to, &lim, t) {
            Ok(law) => {
                assert!(inside, "case {case}: a law at {t} s inside a blocked interval {critical:?}");
                assert!((law.duration() - t).abs() <= 1e-12 * t, "case {case}: {} vs {t}", law.duration());
                check_law(&law, &lim, &format!("case {case} at {t} s"));
                solved += 1;
            }
            Err(e) => {
                assert!(!inside, "case {case}: {from:?} → {to:?} {lim:?} at {t} s ({critical:?}): {e}");
                assert!(e.to_string().contains("blocked"), "{e}");
                blocked += 1;
            }
        }
        // Shorter than the fastest: refused.
        let e = BoundaryLaw::with_duration(from, to, &lim, fastest.duration() * 0.99).unwrap_err().to_string();
        assert!(e.contains("the fastest motion between these states") || fastest.duration() == 0.0, "{e}");
    }
    assert!(solved > 2500 && blocked > 5, "{solved} solved, {blocked} blocked");
}

/// Whether `a` and `b` agree within 1e-9 relative.
fn same_duration(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

#[test]
fn the_fast_search_gives_the_reference_durations() {
    for seed in [2505, 2507, 2508] {
        fast_matches_reference(seed);
    }
}

/// 3000 seeded coordinates: the fastest law, the critical durations and a
/// law of a longer duration, fast search against the reference.
fn fast_matches_reference(seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for case in 0..3000 {
        let jerk = case % 3 != 0;
        let lim = random_limits(&mut rng, jerk);
        let p0 = rng.random_range(-3.0..3.0);
        let d = if rng.random_bool(0.3) { rng.random_range(-0.05..0.05) } else { rng.random_range(-5.0..5.0) };
        let from = random_state(&mut rng, &lim, p0);
        let to = random_state(&mut rng, &lim, p0 + d);
        let what = format!("seed {seed} case {case}: {from:?} → {to:?} {lim:?}");
        let fast = BoundaryLaw::fastest(from, to, &lim).unwrap();
        let slow = reference::fastest(from, to, &lim).unwrap();
        assert!(same_duration(fast.duration(), slow.duration()), "{what}: {} vs {}", fast.duration(), slow.duration());
        check_law(&fast, &lim, &what);
        check_law(&slow, &lim, &what);
        let (cf, cs) = (
            BoundaryLaw::critical_durations(from, to, &lim).unwrap(),
            reference::critical_durations(from, to, &lim).unwrap(),
        );
        assert!(
            cf.len() == cs.len() && cf.iter().zip(&cs).all(|(a, b)| same_duration(*a, *b)),
            "{what}: {cf:?} vs {cs:?}"
        );
        let t = fast.duration() * (1.0 + rng.random_range(0.0..2.0)) + rng.random_range(0.0..0.1);
        match (BoundaryLaw::with_duration(from, to, &lim, t), reference::with_duration(from, to, &lim, t)) {
            (Ok(a), Ok(b)) => {
                assert!(same_duration(a.duration(), b.duration()), "{what} at {t}");
                check_law(&a, &lim, &what);
            }
            (Err(_), Err(_)) => {}
            (a, b) => panic!("{what} at {t}: fast {a:?}, reference {b:?}"),
        }
    }
}

#[test]
fn fast_and_reference_synchronise_to_the_same_duration() {
    let mut rng = ChaCha8Rng::seed_from_u64(2506);
    for case in 0..400 {
        let jerk = case % 2 == 0;
        let n = rng.random_range(1..=7);
        let lims: Vec<MotionLimits> = (0..n).map(|_| random_limits(&mut rng, jerk)).collect();
        let (mut from, mut to) = (Vec::new(), Vec::new());
        for l in &lims {
            let p0 = rng.random_range(-3.0..3.0);
            from.push(random_state(&mut rng, l, p0));
            let pf = p0 + rng.random_range(-2.0..2.0);
            to.push(random_state(&mut rng, l, pf));
        }
        let (t, laws) = sync_duration(&from, &to, &lims, 0.0).unwrap();
        let (tr, _) = reference::sync_duration(&from, &to, &lims, 0.0).unwrap();
        assert!(same_duration(t, tr), "case {case}: {t} vs {tr}");
        for (i, law) in laws.iter().enumerate() {
            check_law(law, &lims[i], &format!("case {case} joint {i}"));
        }
    }
}

#[test]
fn cruising_onto_a_close_target_blocks_a_duration_interval() {
    // Cruising at full speed, to arrive 0.9 further on at full speed again:
    // 0.9 s at full speed, or up to about 1.37 s dipping in velocity on the
    // way; a longer motion has to back up (second order: from
    // 2 + 2·√0.1 ≈ 2.63 s); in between no law exists.
    for lim in [MotionLimits::new(1.0, 1.0), MotionLimits::with_jerk(1.0, 1.0, 5.0)] {
        let (from, to) = (BoundaryState::new(0.0, 1.0, 0.0), BoundaryState::new(0.9, 1.0, 0.0));
        let c = BoundaryLaw::critical_durations(from, to, &lim).unwrap();
        assert_eq!(c.len(), 3, "{c:?}");
        assert!((c[0] - 0.9).abs() < 1e-12, "{c:?}");
        if lim.jerk.is_none() {
            assert!((c[1] - (2.0 - 2.0 * 0.1f64.sqrt())).abs() < 1e-12, "{c:?}");
            assert!((c[2] - (2.0 + 2.0 * 0.1f64.sqrt())).abs() < 1e-12, "{c:?}");
        }
        for t in [0.5 * (c[0] + c[1]), c[2] * 1.01] {
            let law = BoundaryLaw::with_duration(from, to, &lim, t).unwrap();
            check_law(&law, &lim, "open");
        }
        assert!(BoundaryLaw::with_duration(from, to, &lim, 0.5 * (c[1] + c[2])).is_err());
        // A second coordinate that needs a duration inside the blocked interval:
        // the synchronised motion waits for the end of it.
        let slow = MotionLimits { vel: 0.1, ..lim };
        let t_other = 0.5 * (c[1] + c[2]);
        let (t, laws) = sync_duration(
            &[from, BoundaryState::rest(0.0)],
            &[to, BoundaryState::rest(0.1 * t_other * 0.8)],
            &[lim, slow],
            0.0,
        )
        .unwrap();
        let other =
            BoundaryLaw::fastest(BoundaryState::rest(0.0), BoundaryState::rest(0.1 * t_other * 0.8), &slow).unwrap();
        assert!(other.duration() > c[1] && other.duration() < c[2], "{c:?} {}", other.duration());
        assert_eq!(t, c[2]);
        for (law, l) in laws.iter().zip([lim, slow]) {
            assert!((law.duration() - t).abs() <= 1e-12 * t);
            check_law(law, &l, "sync");
        }
    }
}

#[test]
fn synchronised_coordinates_all_end_at_the_common_duration() {
    let mut rng = ChaCha8Rng::seed_from_u64(2504);
    for case in 0..600 {
        let jerk = case % 2 == 0;
        let n = rng.random_range(1..=6);
        let lims: Vec<MotionLimits> = (0..n).map(|_| random_limits(&mut rng, jerk)).collect();
        let mut from = Vec::new();
        let mut to = Vec::new();
        for l in &lims {
            let p0 = rng.random_range(-3.0..3.0);
            from.push(random_state(&mut rng, l, p0));
            let pf = p0 + rng.random_range(-2.0..2.0);
            to.push(random_state(&mut rng, l, pf));
        }
        let (t, laws) = sync_duration(&from, &to, &lims, 0.0).unwrap_or_else(|e| panic!("case {case}: {e}"));
        for i in 0..n {
            let fastest = BoundaryLaw::fastest(from[i], to[i], &lims[i]).unwrap();
            assert!(t >= fastest.duration(), "case {case}");
            assert!((laws[i].duration() - t).abs() <= 1e-12 * t, "case {case} joint {i}");
            check_law(&laws[i], &lims[i], &format!("case {case} joint {i}"));
        }
    }
}

#[test]
fn targets_no_law_can_reach_are_refused_naming_the_limit() {
    let lim = MotionLimits::with_jerk(1.0, 2.0, 4.0);
    let refuse = |from: BoundaryState, to: BoundaryState, lim: &MotionLimits| {
        let e = BoundaryLaw::fastest(from, to, lim).unwrap_err();
        match &e {
            kinema::Error::Input(kinema::InputError::OutOfRange { what, .. })
            | kinema::Error::Infeasible { what, .. }
            | kinema::Error::Input(kinema::InputError::NotFinite { what, .. })
            | kinema::Error::Input(kinema::InputError::MissingLimit { option: what, .. }) => {
                (what.clone(), e.to_string())
            }
            other => panic!("{other:?}"),
        }
    };
    let (w, m) = refuse(BoundaryState::rest(0.0), BoundaryState::new(1.0, 1.5, 0.0), &lim);
    assert_eq!(w, "target velocity");
    assert!(m.contains("`target velocity`: 1.5; expected a velocity within ±1 (vmax)"), "{m}");
    let (w, m) = refuse(BoundaryState::rest(0.0), BoundaryState::new(1.0, 0.0, -3.0), &lim);
    assert_eq!(w, "target acceleration");
    assert!(m.contains("`target acceleration`: -3; expected an acceleration within ±2 (amax)"), "{m}");
    // Traced back from the target, 0.8 + 1.5²/(2·4) = 1.08 > 1: no motion within the limits arrives there.
    let (w, m) = refuse(BoundaryState::rest(0.0), BoundaryState::new(1.0, 0.8, -1.5), &lim);
    assert_eq!(w, "vmax");
    assert!(m.contains("reaches a velocity of 1.08"), "{m}");
    let (w, m) = refuse(BoundaryState::new(0.0, 0.0, 1.0), BoundaryState::rest(1.0), &MotionLimits::new(1.0, 2.0));
    assert_eq!(w, "jmax");
    assert!(m.contains("no jerk limit for the start acceleration 1"), "{m}");
    let (w, _) = refuse(BoundaryState::new(f64::NAN, 0.0, 0.0), BoundaryState::rest(1.0), &lim);
    assert_eq!(w, "start position");
    let (w, _) = refuse(BoundaryState::rest(0.0), BoundaryState::rest(1.0), &MotionLimits::with_jerk(1.0, -2.0, 4.0));
    assert_eq!(w, "amax");
    // A state equal to its target is already there, moving or not.
    let s = BoundaryState::new(0.3, 0.5, -0.2);
    assert_eq!(BoundaryLaw::fastest(s, s, &lim).unwrap().duration(), 0.0);
}

/// A random start beyond the limits: |v| up to 3 v_max, |a| up to 3 a_max
/// (third order), or both within but the acceleration carrying the velocity
/// past v_max.
fn random_start_beyond(rng: &mut ChaCha8Rng, lim: &MotionLimits, p: f64) -> BoundaryState {
    let v = rng.random_range(-3.0..3.0) * lim.vel;
    let a = match lim.jerk {
        Some(_) => rng.random_range(-3.0..3.0) * lim.acc,
        None => 0.0,
    };
    match rng.random_range(0..3) {
        0 => BoundaryState::new(p, (lim.vel * 1.01 + v.abs()).copysign(v), a),
        _ => BoundaryState::new(p, v, a),
    }
}

#[test]
fn starts_beyond_the_limits_are_braked_then_keep_them() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let (mut braked, mut cases) = (0, 0);
    for case in 0..3000 {
        let mut lim = random_limits(&mut rng, case % 4 != 3);
        // Jerk that needs at most 2 s to swing the acceleration across its
        // range, so that a brake from 3 a_max stays within a few metres.
        lim.jerk = lim.jerk.map(|j| j.max(lim.acc / 2.0));
        let (p0, dp) = (rng.random_range(-3.0..3.0), rng.random_range(-5.0..5.0));
        let from = random_start_beyond(&mut rng, &lim, p0);
        let to = random_state(&mut rng, &lim, p0 + dp);
        let what = format!("case {case}: {from:?} → {to:?} within {lim:?}");
        let law = BoundaryLaw::fastest(from, to, &lim).unwrap_or_else(|e| panic!("{what}: {e}"));
        cases += 1;
        let tb = law.braking_duration();
        braked += usize::from(tb > 0.0);
        // From the end of the brake on, the law is the fastest one from the
        // braked state, which is within the limits (it needs no brake itself).
        let mid = law.at(tb);
        // (Second order steps its acceleration: the law proper starts from a = 0.)
        let mid = if lim.jerk.is_some() { mid } else { BoundaryState { a: 0.0, ..mid } };
        let rest = BoundaryLaw::fastest(mid, to, &lim).unwrap_or_else(|e| panic!("{what}: after the brake: {e}"));
        assert_eq!(rest.braking_duration(), 0.0, "{what}: braked to {mid:?}");
        assert!(
            (law.duration() - tb - rest.duration()).abs() <= 1e-9 * law.duration().max(1e-9),
            "{what}: {} ≠ {tb} + {}",
            law.duration(),
            rest.duration()
        );
        // The brake moves at full jerk and only ever towards the limits: the
        // state is continuous, and past the brake every limit holds.
        let n = 300;
        let mut prev = law.at(0.0);
        for k in 1..=n {
            let t = law.duration() * (1.0 - 1e-12) * k as f64 / n as f64;
            let s = law.at(t);
            if let Some(j) = lim.jerk {
                assert!(law.jerk_at(t).abs() <= j * (1.0 + REL), "{what}: jerk at {t}");
                let dt = law.duration() / n as f64;
                assert!((s.a - prev.a).abs() <= j * dt * (1.0 + 1e-6) + 1e-12 * lim.acc, "{what}: a jumps at {t}");
            }
            if t > tb * (1.0 + 1e-9) {
                assert!(s.v.abs() <= lim.vel * (1.0 + REL), "{what}: v {} at {t}", s.v);
                assert!(s.a.abs() <= lim.acc * (1.0 + REL), "{what}: a {} at {t}", s.a);
            }
            prev = s;
        }
        // A longer prescribed duration brakes the same way and ends then.
        let longer = law.duration() * 1.5 + 0.1;
        if let Ok(slow) = BoundaryLaw::with_duration(from, to, &lim, longer) {
            assert!((slow.duration() - longer).abs() <= 1e-9 * longer, "{what}");
            assert_eq!(slow.braking_duration(), tb, "{what}");
        }
    }
    assert!(braked * 10 >= cases * 9, "only {braked} of {cases} starts needed a brake");
}

/// Differential test against Ruckig (not run by default: it needs a network
/// to install Ruckig in a throwaway venv). `benchmarks/run_ruckig.sh` writes
/// the cases with Ruckig's durations and runs this test on them; with
/// `KINEMA_RUCKIG_CSV=cases.csv` it reads an existing file:
///
/// ```text
/// bash benchmarks/run_ruckig.sh            # or
/// KINEMA_RUCKIG_CSV=cases.csv cargo test --release -p kinema --test all -- --ignored --nocapture traj_boundary::
/// ```
///
/// Every law is re-checked against the limits; kinema's duration must be at
/// most Ruckig's + 1e-9 relative wherever both solve a case.
#[test]
#[ignore = "needs benchmarks/run_ruckig.sh (a venv with Ruckig from PyPI)"]
fn ruckig_durations() {
    let path =
        std::env::var("KINEMA_RUCKIG_CSV").expect("KINEMA_RUCKIG_CSV: the file benchmarks/ruckig_cases.py wrote");
    let text = std::fs::read_to_string(&path).unwrap();
    #[derive(Default)]
    struct Tally {
        cases: usize,
        both: usize,
        kinema_only: usize,
        ruckig_only: usize,
        neither: usize,
        faster: usize,
        already_there: usize,
        equal: usize,
        slower: usize,
        worst_slower: f64,
    }
    let mut tallies: std::collections::BTreeMap<String, Tally> = Default::default();
    let mut failures = Vec::new();
    for line in text.lines() {
        let f: Vec<&str> = line.split(',').collect();
        let kind = f[0].to_string();
        let dof: usize = f[2].parse().unwrap();
        let x: Vec<f64> = f[3..3 + 9 * dof].iter().map(|s| s.parse().unwrap()).collect();
        let code = f[3 + 9 * dof];
        let ruckig: f64 = f[4 + 9 * dof].parse().unwrap();
        let mut from = Vec::new();
        let mut to = Vec::new();
        let mut lims = Vec::new();
        for j in x.chunks(9) {
            from.push(BoundaryState::new(j[0], j[1], j[2]));
            to.push(BoundaryState::new(j[3], j[4], j[5]));
            lims.push(if j[8].is_finite() {
                MotionLimits::with_jerk(j[6], j[7], j[8])
            } else {
                MotionLimits::new(j[6], j[7])
            });
        }
        let ours = sync_duration(&from, &to, &lims, 0.0);
        if let Ok((t, laws)) = &ours {
            for (i, law) in laws.iter().enumerate() {
                assert!((law.duration() - t).abs() <= 1e-9 * t.max(1e-9), "{line}: joint {i} lasts {}", law.duration());
                check_law(law, &lims[i], line);
            }
        }
        let tally = tallies.entry(kind).or_default();
        tally.cases += 1;
        match (&ours, code == "ok") {
            (Ok((t, _)), true) => {
                tally.both += 1;
                let rel = (t - ruckig) / ruckig.max(1e-12);
                if rel > 1e-9 {
                    tally.slower += 1;
                    failures.push(format!("{line}: kinema {t} > Ruckig {ruckig} ({rel:e})"));
                } else if rel < -1e-9 {
                    tally.faster += 1;
                    if *t == 0.0 {
                        tally.already_there += 1; // start = target: Ruckig loops back
                    }
                } else {
                    tally.equal += 1;
                }
                tally.worst_slower = tally.worst_slower.max(rel);
            }
            (Ok(_), false) => tally.kinema_only += 1,
            (Err(e), true) => {
                tally.ruckig_only += 1;
                failures.push(format!("{line}: kinema fails: {e}"));
            }
            (Err(_), false) => tally.neither += 1,
        }
    }
    for (kind, t) in &tallies {
        println!(
            "{kind:>13}: {} cases, both solve {} (kinema equal ±1e-9 {}, faster {} of which {} start = target, \
             slower {}; largest (kinema − Ruckig)/Ruckig {:.1e}), only kinema {}, only Ruckig {}, neither {}",
            t.cases,
            t.both,
            t.equal,
            t.faster,
            t.already_there,
            t.slower,
            t.worst_slower,
            t.kinema_only,
            t.ruckig_only,
            t.neither
        );
    }
    for f in failures.iter().take(20) {
        println!("{f}");
    }
    assert!(failures.is_empty(), "{} cases where kinema is slower than Ruckig or fails", failures.len());
}

mod ptp {
    use kinema::traj::{BoundaryPtp, JointBoundary, Profile, Ptp, PtpOptions};
    use kinema::{Error, InputError, Robot};

    const TO: [f64; 7] = [-0.1090, 1.2417, 0.4463, 1.9156, -0.9695, -1.8728, 0.4876];
    const VIA: [f64; 7] = [0.5, 0.8, 0.2, 1.2, -0.4, -1.0, 0.1];

    fn opts(profile: Profile) -> PtpOptions {
        PtpOptions { profile, acc: Some(vec![2.0]), jerk: Some(vec![15.0]), ..PtpOptions::default() }
    }

    #[test]
    fn rest_to_rest_is_the_shared_straight_line_law() {
        let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
        for profile in [Profile::SCurve, Profile::Trapezoid, Profile::Quintic] {
            let zeros = JointBoundary { v0: Some(vec![0.0; 7]), ..JointBoundary::default() };
            let b = BoundaryPtp::new(&robot, robot.home(), &TO, &opts(profile), &zeros).unwrap();
            let p = Ptp::new(&robot, robot.home(), &TO, &opts(profile)).unwrap();
            assert_eq!(b.rest(), Some(&p));
            assert_eq!(b.sample(&robot, 0.01).unwrap(), p.sample(&robot, 0.01).unwrap());
        }
    }

    /// home → VIA → TO, passing VIA at a velocity instead of stopping there: the
    /// two pieces meet with equal q, q̇, q̈, every sample is within the limits
    /// (the checked `sample`), and the chain is faster than stopping at VIA.
    #[test]
    fn chained_motions_meet_without_stopping_and_save_time() {
        let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
        for profile in [Profile::SCurve, Profile::Trapezoid] {
            let o = opts(profile);
            // Keep moving through VIA where both pieces move a joint the same way.
            let home = robot.home();
            let w: Vec<f64> = (0..7)
                .map(|i| {
                    let (d1, d2) = (VIA[i] - home[i], TO[i] - VIA[i]);
                    if d1 * d2 > 0.0 {
                        0.3f64.copysign(d1)
                    } else {
                        0.0
                    }
                })
                .collect();
            let a = if profile == Profile::SCurve { vec![0.1, 0.0, -0.2, 0.0, 0.3, 0.0, 0.0] } else { vec![0.0; 7] };
            let first = JointBoundary { v1: Some(w.clone()), a1: Some(a.clone()), ..JointBoundary::default() };
            let second = JointBoundary { v0: Some(w.clone()), a0: Some(a.clone()), ..JointBoundary::default() };
            let p1 = BoundaryPtp::new(&robot, robot.home(), &VIA, &o, &first).unwrap();
            let p2 = BoundaryPtp::new(&robot, &VIA, &TO, &o, &second).unwrap();
            let t1 = p1.sample(&robot, 0.005).unwrap();
            let t2 = p2.sample(&robot, 0.005).unwrap();
            let end = t1.len() - 1;
            for (i, wi) in w.iter().enumerate() {
                assert!((t1.q(end)[i] - t2.q(0)[i]).abs() < 1e-9, "{profile} q{i}");
                assert!((t1.qd(end)[i] - t2.qd(0)[i]).abs() < 1e-9, "{profile} qd{i}");
                assert!((t1.qdd(end)[i] - t2.qdd(0)[i]).abs() < 1e-9, "{profile} qdd{i}");
                assert!((t1.qd(end)[i] - wi).abs() < 1e-9);
            }
            let stop = Ptp::new(&robot, robot.home(), &VIA, &o).unwrap().duration()
                + Ptp::new(&robot, &VIA, &TO, &o).unwrap().duration();
            let chained = p1.duration() + p2.duration();
            assert!(chained < stop, "{profile}: {chained} vs {stop}");
            assert_eq!(p1.laws().len(), 7);
            for law in p1.laws() {
                assert!((law.duration() - p1.duration()).abs() <= 1e-12 * p1.duration());
            }
        }
    }

    #[test]
    fn bad_boundaries_give_errors_that_name_the_field() {
        let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
        let msg = |b: JointBoundary, o: PtpOptions| match BoundaryPtp::new(&robot, robot.home(), &TO, &o, &b) {
            Err(e) => e.to_string(),
            other => panic!("{other:?}"),
        };
        let m = msg(JointBoundary { v0: Some(vec![0.1, 0.2]), ..Default::default() }, opts(Profile::SCurve));
        assert_eq!(m, "`v0` has 2 values; 7 expected (one per joint)");
        let mut nan = vec![0.0; 7];
        nan[3] = f64::NAN;
        let m = msg(JointBoundary { a1: Some(nan), ..Default::default() }, opts(Profile::SCurve));
        assert_eq!(m, "`a1[4]` is NaN; it must be a finite number");
        let v = Some(vec![0.1; 7]);
        let m = msg(JointBoundary { v1: v.clone(), ..Default::default() }, opts(Profile::Cubic));
        assert!(m.starts_with("invalid `profile`: the cubic profile only moves rest to rest"), "{m}");
        let m = msg(JointBoundary { a0: v.clone(), ..Default::default() }, opts(Profile::Trapezoid));
        assert!(m.starts_with("joint 1 (`"), "{m}");
        assert!(m.contains("): invalid `a0`: a boundary acceleration needs the jerk-limited scurve"), "{m}");
        // A state no law can arrive at is named by its joint, the cause kept typed underneath.
        let e = BoundaryPtp::new(
            &robot,
            robot.home(),
            &TO,
            &opts(Profile::SCurve),
            &JointBoundary { v1: Some(vec![5.0; 7]), ..Default::default() },
        )
        .unwrap_err();
        assert!(matches!(&e, Error::ForJoint { joint: 1, .. }), "{e:?}");
        assert!(
            matches!(e.root(), Error::Input(InputError::OutOfRange { what, value: 5.0, .. }) if what == "target velocity"),
            "{e:?}"
        );
        let m = e.to_string();
        assert!(m.starts_with("joint 1 (`") && m.contains("`target velocity`: 5; expected a velocity within ±"), "{m}");
    }

    #[test]
    fn a_boundary_velocity_that_overshoots_a_position_limit_is_a_trajectory_error() {
        let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
        // Joint 4 arrives at 2.0 (its limit is about 2.09) still moving up.
        let mut to = TO;
        to[3] = 2.0;
        let mut v1 = vec![0.0; 7];
        v1[3] = 1.2;
        let b = JointBoundary { v1: Some(v1), ..JointBoundary::default() };
        let o = opts(Profile::SCurve);
        let ptp = BoundaryPtp::new(&robot, robot.home(), &to, &o, &b).unwrap();
        // The motion itself ends at the limit; sampling is fine, but a motion
        // that must come back from beyond it is caught by the check.
        let mut from = to;
        from[3] = 2.05;
        let v0 = {
            let mut v = vec![0.0; 7];
            v[3] = 1.2; // braking from 1.2 rad/s at 2 rad/s² takes 0.36 rad: past the limit
            v
        };
        let back =
            BoundaryPtp::new(&robot, &from, &TO, &o, &JointBoundary { v0: Some(v0), ..JointBoundary::default() })
                .unwrap();
        match back.sample(&robot, 0.01) {
            Err(Error::Trajectory { .. }) => {}
            other => panic!("{other:?}"),
        }
        if let Err(e) = ptp.sample(&robot, 0.01) {
            panic!("{e}")
        }
    }
}
