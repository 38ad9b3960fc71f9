//! Time-optimal laws between arbitrary boundary states (issue 25): seeded
//! property tests over random states — limits kept, target reached,
//! duration no shorter than a provable lower bound — rest-to-rest equality
//! with the S-curve and trapezoid laws, prescribed durations met exactly,
//! and synchronisation through blocked intervals.

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

/// Samples the law finely and checks limits, continuity and the end state.
fn check_law(law: &BoundaryLaw, lim: &MotionLimits, what: &str) {
    let (v, a, j) = law.peaks();
    assert!(v <= lim.vel * (1.0 + REL), "{what}: |v| {v} > {}", lim.vel);
    assert!(a <= lim.acc * (1.0 + REL), "{what}: |a| {a} > {}", lim.acc);
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
        assert!(s.v.abs() <= lim.vel * (1.0 + REL), "{what}: v {} at {t}", s.v);
        assert!(s.a.abs() <= lim.acc * (1.0 + REL), "{what}: a {} at {t}", s.a);
        // Position is the integral of velocity (trapezoid rule bound).
        let dt = t_end / n as f64;
        assert!((s.p - prev.p).abs() <= lim.vel * dt * (1.0 + 1e-6) + 1e-12 * scale, "{what}: jump at {t}");
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

/// Differential test against Ruckig (not run by default: it needs a network
/// to install Ruckig in a throwaway venv). `benchmarks/run_ruckig.sh` writes
/// the cases with Ruckig's durations and runs this test on them; with
/// `KINEMA_RUCKIG_CSV=cases.csv` it reads an existing file:
///
/// ```text
/// bash benchmarks/run_ruckig.sh            # or
/// KINEMA_RUCKIG_CSV=cases.csv cargo test --release -p kinema --test traj_boundary -- --ignored --nocapture
/// ```
///
/// Every law is re-checked against the limits; kinema's duration must be at
/// most Ruckig's + 1e-9 relative wherever both solve a case.
#[test]
#[ignore = "needs benchmarks/run_ruckig.sh (a venv with Ruckig from PyPI)"]
fn ruckig_durations() {
    let path = std::env::var("KINEMA_RUCKIG_CSV").expect("KINEMA_RUCKIG_CSV: the file benchmarks/ruckig_cases.py wrote");
    let text = std::fs::read_to_string(&path).unwrap();
    #[derive(Default)]
    struct Tally {
        cases: usize,
        both: usize,
        kinema_only: usize,
        ruckig_only: usize,
        neither: usize,
        faster: usize,
        equal: usize,
        slower: usize,
        worst_slower: f64,
        best_faster: f64,
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
            lims.push(if j[8].is_finite() { MotionLimits::with_jerk(j[6], j[7], j[8]) } else { MotionLimits::new(j[6], j[7]) });
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
                } else {
                    tally.equal += 1;
                }
                tally.worst_slower = tally.worst_slower.max(rel);
                tally.best_faster = tally.best_faster.min(rel);
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
            "{kind:>13}: {} cases, both solve {} (kinema equal ±1e-9 {}, faster {}, slower {}; \
             largest (kinema − Ruckig)/Ruckig {:.1e}, smallest {:.1e}), only kinema {}, only Ruckig {}, neither {}",
            t.cases, t.both, t.equal, t.faster, t.slower, t.worst_slower, t.best_faster, t.kinema_only, t.ruckig_only, t.neither
        );
    }
    for f in failures.iter().take(20) {
        println!("{f}");
    }
    assert!(failures.is_empty(), "{} cases where kinema is slower than Ruckig or fails", failures.len());
}
