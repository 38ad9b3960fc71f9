//! Time laws (seed 004 §VIII-A, eq. 32–37, and its future-work S-curve):
//! every profile checked against independent computations — hand-worked
//! durations, finite differences, a fine sampling of the derivatives, the
//! time-scaling law, and the seed's own short-move recipe written out from
//! its equations.

use kinema::traj::{LawState, MotionLimits, Profile, TimeLaw};
use kinema::Error;
use kinema::InputError;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative rounding allowed on a limit (the 1e-9).
const REL: f64 = 1e-9;

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    (rng.random_range(lo.ln()..hi.ln())).exp()
}

fn random_limits(rng: &mut ChaCha8Rng) -> (f64, MotionLimits) {
    let d = log_uniform(rng, 1e-4, 1e2);
    let lim =
        MotionLimits::with_jerk(log_uniform(rng, 1e-2, 10.0), log_uniform(rng, 1e-2, 1e2), log_uniform(rng, 1e-1, 1e3));
    (d, lim)
}

/// The sample instants: a uniform grid plus both sides of every phase boundary.
fn grid(law: &TimeLaw, n: usize) -> Vec<f64> {
    let t_end = law.duration();
    let mut ts: Vec<f64> = (0..=n).map(|i| t_end * i as f64 / n as f64).collect();
    let mut tb = 0.0;
    for dt in law.phase_times() {
        tb += dt;
        for e in [-1e-12, 0.0, 1e-12] {
            let t = tb * (1.0 + e);
            if t > 0.0 && t < t_end {
                ts.push(t);
            }
        }
    }
    ts.sort_by(f64::total_cmp);
    ts
}

/// The boundaries between phases (not the start or end).
fn boundaries(law: &TimeLaw) -> Vec<f64> {
    let mut out = Vec::new();
    let mut tb = 0.0;
    for dt in &law.phase_times()[..law.phase_times().len().saturating_sub(1)] {
        tb += dt;
        out.push(tb);
    }
    out
}

/// Largest |ṡ|, |s̈|, |s⃛| over the sample instants (open interval: the
/// values at t = 0 and t = T are the rest states outside the law).
fn sampled_peaks(law: &TimeLaw, ts: &[f64]) -> LawState {
    let mut p = LawState::default();
    for &t in ts.iter().filter(|&&t| t > 0.0 && t < law.duration()) {
        let st = law.at(t);
        p.sd = p.sd.max(st.sd.abs());
        p.sdd = p.sdd.max(st.sdd.abs());
        p.sddd = p.sddd.max(st.sddd.abs());
    }
    p
}

#[test]
fn every_profile_is_normalised_monotone_and_within_its_limits() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x7a11);
    for case in 0..2000 {
        let (d, lim) = random_limits(&mut rng);
        let jerk = lim.jerk.unwrap();
        for profile in Profile::ALL {
            let law = TimeLaw::from_limits(profile, d, &lim).unwrap();
            let t_end = law.duration();
            assert!(t_end.is_finite() && t_end > 0.0, "case {case} {profile}: T = {t_end}");
            let total: f64 = law.phase_times().iter().sum();
            assert!((total - t_end).abs() <= 1e-12 * t_end, "case {case} {profile}: phases {total} vs T {t_end}");
            assert_eq!(law.at(0.0).s, 0.0);
            assert_eq!(law.at(t_end).s, 1.0);
            // s reaches 1 continuously (not only by the clamp at T).
            let near_end = law.at(t_end * (1.0 - 1e-12)).s;
            assert!((near_end - 1.0).abs() < 1e-9, "case {case} {profile}: s(T⁻) = {near_end}");
            let ts = grid(&law, 400);
            let mut prev = 0.0;
            for &t in &ts {
                let st = law.at(t);
                assert!(
                    st.s >= prev - 1e-15 && st.s <= 1.0 + 1e-12,
                    "case {case} {profile}: s({t}) = {:e} after {prev:e}",
                    st.s
                );
                prev = st.s;
                assert!(st.sd >= -1e-14 / t_end, "case {case} {profile}: ṡ({t}) = {:e} < 0", st.sd);
                assert!(d * st.sd <= lim.vel * (1.0 + REL), "case {case} {profile}: v = {} > {}", d * st.sd, lim.vel);
                if profile != Profile::Linear {
                    assert!(
                        d * st.sdd.abs() <= lim.acc * (1.0 + REL),
                        "case {case} {profile} t = {t}: a = {} > {}",
                        d * st.sdd.abs(),
                        lim.acc
                    );
                }
                if matches!(profile, Profile::SCurve | Profile::Quintic) {
                    assert!(d * st.sddd.abs() <= jerk * (1.0 + REL), "case {case} {profile}: j = {}", d * st.sddd);
                }
            }
            // The closed-form peaks agree with the sampled derivatives: never
            // below them, and above them only by what the grid can miss.
            let peaks = law.peaks();
            let sampled = sampled_peaks(&law, &ts);
            let h = t_end / 400.0;
            assert!(peaks.sd >= sampled.sd * (1.0 - 1e-12), "case {case} {profile}: ṡ {} < {}", peaks.sd, sampled.sd);
            assert!(peaks.sd <= sampled.sd + peaks.sdd * h, "case {case} {profile}: ṡ {} ≫ {}", peaks.sd, sampled.sd);
            if profile != Profile::Linear {
                assert!(
                    peaks.sdd >= sampled.sdd * (1.0 - 1e-12),
                    "case {case} {profile}: s̈ {} < {}",
                    peaks.sdd,
                    sampled.sdd
                );
                let slack = if peaks.sddd.is_finite() { peaks.sddd * h } else { 1e-9 * peaks.sdd };
                assert!(peaks.sdd <= sampled.sdd + slack, "case {case} {profile}: s̈ {} ≫ {}", peaks.sdd, sampled.sdd);
            }
            // Fastest of its family: some limit binds exactly.
            let binds = |used: f64, limit: f64| (used - limit).abs() <= 1e-9 * limit;
            let bound = match profile {
                Profile::Linear => binds(d * peaks.sd, lim.vel),
                Profile::SCurve => {
                    binds(d * peaks.sd, lim.vel) || binds(d * peaks.sdd, lim.acc) || binds(d * peaks.sddd, jerk)
                }
                Profile::Quintic => {
                    binds(d * peaks.sd, lim.vel) || binds(d * peaks.sdd, lim.acc) || binds(d * peaks.sddd, jerk)
                }
                _ => binds(d * peaks.sd, lim.vel) || binds(d * peaks.sdd, lim.acc),
            };
            assert!(bound, "case {case} {profile}: no limit binds: {peaks:?} × {d} vs {lim:?}");
        }
    }
}

/// Time-optimality of the trapezoid and the double-S, checked through their
/// bang-bang structure: in every phase the jerk is ±j_max or zero, and where
/// it is zero the acceleration is ±a_max or zero, and where that is zero the
/// velocity is v_max (the cruise). A slower law of the same family would have
/// a phase that uses none of its limits.
#[test]
fn trapezoid_and_scurve_phases_ride_a_limit() {
    let mut rng = ChaCha8Rng::seed_from_u64(0xba6);
    let near = |x: f64, target: f64| (x - target).abs() <= 1e-9 * target.max(1e-300);
    for case in 0..3000 {
        let (d, lim) = random_limits(&mut rng);
        let jerk = lim.jerk.unwrap();
        for profile in [Profile::Trapezoid, Profile::SCurve] {
            let law = TimeLaw::from_limits(profile, d, &lim).unwrap();
            let mut t0 = 0.0;
            for (i, &dt) in law.phase_times().iter().enumerate() {
                let st = law.at(t0 + 0.5 * dt);
                let (v, a, j) = (d * st.sd, d * st.sdd.abs(), d * st.sddd.abs());
                let ok = if profile == Profile::SCurve && j > 1e-12 * jerk {
                    near(j, jerk)
                } else if a > 1e-9 * lim.acc {
                    near(a, lim.acc)
                } else {
                    near(v, lim.vel)
                };
                assert!(ok, "case {case} {profile} phase {i}: v {v} a {a} j {j} vs {lim:?}, D = {d}");
                t0 += dt;
            }
            // Symmetric: the braking half mirrors the accelerating half.
            let t_end = law.duration();
            for k in 1..20 {
                let t = t_end * k as f64 / 40.0;
                let (a, b) = (law.at(t), law.at(t_end - t));
                assert!((a.s + b.s - 1.0).abs() < 1e-9, "case {case} {profile}: s not symmetric");
                assert!((a.sd - b.sd).abs() <= 1e-9 * a.sd.abs().max(1.0 / t_end), "case {case} {profile}");
            }
        }
    }
}

#[test]
fn derivatives_match_finite_differences_and_are_continuous() {
    let mut rng = ChaCha8Rng::seed_from_u64(0xfd);
    for case in 0..500 {
        let (d, lim) = random_limits(&mut rng);
        for profile in Profile::ALL {
            let law = TimeLaw::from_limits(profile, d, &lim).unwrap();
            let t_end = law.duration();
            let h = t_end * 1e-6;
            let bounds = boundaries(&law);
            let pk = law.peaks();
            for k in 1..50 {
                let t = t_end * (k as f64 + rng.random_range(-0.4..0.4)) / 50.0;
                if bounds.iter().any(|b| (b - t).abs() < 4.0 * h) {
                    continue;
                }
                let (m, p, c) = (law.at(t - h), law.at(t + h), law.at(t));
                let fd = |hi: f64, lo: f64| (hi - lo) / (2.0 * h);
                // Truncation (h² × the next derivative) is far below 1e-6 of
                // the peak; rounding is ~1e-16 of the differenced value over h.
                let tol = |peak: f64, below: f64| 1e-6 * peak + 1e-13 * below / h;
                assert!((fd(p.s, m.s) - c.sd).abs() <= tol(pk.sd, 1.0), "case {case} {profile}: ṡ({t})");
                if profile != Profile::Linear {
                    assert!((fd(p.sd, m.sd) - c.sdd).abs() <= tol(pk.sdd, pk.sd), "case {case} {profile}: s̈({t})");
                }
                if matches!(profile, Profile::SCurve | Profile::Quintic) {
                    let err = (fd(p.sdd, m.sdd) - c.sddd).abs();
                    assert!(err <= tol(pk.sddd, pk.sdd), "case {case} {profile}: s⃛({t}) off by {err:e}");
                }
            }
            // Across the phase boundaries s and ṡ are continuous for every
            // profile, s̈ too for the S-curve.
            // A jump would be of the order of the derivative itself; what two
            // instants 2ε apart may differ by is 2ε times the next derivative.
            for b in bounds {
                let e = b * 1e-10;
                let (l, r) = (law.at(b - e), law.at(b + e));
                assert!((l.s - r.s).abs() <= 2.0 * e * pk.sd + 1e-12, "case {case} {profile}: s jumps at {b}");
                assert!(
                    (l.sd - r.sd).abs() <= 2.0 * e * pk.sdd + 1e-12 * pk.sd,
                    "case {case} {profile}: ṡ jumps at {b}"
                );
                if profile == Profile::SCurve {
                    let jump = (l.sdd - r.sdd).abs();
                    assert!(
                        jump <= 2.0 * e * pk.sddd + 1e-9 * pk.sdd,
                        "case {case} {profile}: s̈ jumps by {jump:e} at {b}"
                    );
                }
            }
        }
    }
}

#[test]
fn hand_worked_durations() {
    let close = |law: &TimeLaw, t: f64| {
        assert!((law.duration() - t).abs() < 1e-12 * t, "{:?}: {} vs {t}", law.profile(), law.duration())
    };
    // Trapezoid, seed 004 eq. 33–36: τ = v/a = 0.5, T = Δp/v = 2, total T + τ = 2.5.
    let law = TimeLaw::from_limits(Profile::Trapezoid, 1.0, &MotionLimits::new(0.5, 1.0)).unwrap();
    close(&law, 2.5);
    assert_eq!(law.phase_times().len(), 3);
    // Short move, D = 0.1 < v²/a = 0.25: triangle of 2·√(D/a).
    let law = TimeLaw::from_limits(Profile::Trapezoid, 0.1, &MotionLimits::new(0.5, 1.0)).unwrap();
    close(&law, 2.0 * 0.1f64.sqrt());
    assert_eq!(law.phase_times().len(), 2);
    assert!((0.1 * law.peaks().sd - 0.1f64.sqrt()).abs() < 1e-12); // v_peak = a·τ = √(D·a)
                                                                   // Double-S, v and a reached: T_j = a/j = 0.1, T_a = T_j + v/a = 1.1,
                                                                   // T_v = D/v − T_a = 8.9, T = 2·T_a + T_v = 11.1.
    let law = TimeLaw::from_limits(Profile::SCurve, 10.0, &MotionLimits::with_jerk(1.0, 1.0, 10.0)).unwrap();
    close(&law, 11.1);
    assert_eq!(law.phase_times().len(), 7);
    // v not reached, a reached: T_j = 0.1 and D = a·(T_a − T_j)·T_a, so
    // T_a = (T_j + √(T_j² + 4D/a))/2; D = 1 gives T = 2·T_a.
    let law = TimeLaw::from_limits(Profile::SCurve, 1.0, &MotionLimits::with_jerk(1.0, 1.0, 10.0)).unwrap();
    let ta = 0.5 * (0.1 + (0.01f64 + 4.0).sqrt());
    close(&law, 2.0 * ta);
    assert_eq!(law.phase_times().len(), 6);
    assert!((law.peaks().sdd - 1.0).abs() < 1e-12 && law.peaks().sd < 1.0);
    // Neither reached: four jerk phases of T_j with D = 2·j·T_j³.
    let d = 0.001;
    let law = TimeLaw::from_limits(Profile::SCurve, d, &MotionLimits::with_jerk(1.0, 1.0, 10.0)).unwrap();
    let tj = (d / 20.0f64).cbrt();
    close(&law, 4.0 * tj);
    assert_eq!(law.phase_times().len(), 4);
    assert!((d * law.peaks().sdd - 10.0 * tj).abs() < 1e-12);
    // v reached but a not (v·j < a²): T_j = √(v/j), T_a = 2·T_j.
    let law = TimeLaw::from_limits(Profile::SCurve, 5.0, &MotionLimits::with_jerk(1.0, 10.0, 1.0)).unwrap();
    close(&law, 2.0 * 2.0 + (5.0 - 2.0));
    // Polynomials from their peak derivatives: cubic ṡ_max = 1.5/T, s̈_max = 6/T²;
    // quintic ṡ_max = 15/(8T), s̈_max = 10/(√3·T²), s⃛_max = 60/T³.
    let law = TimeLaw::from_limits(Profile::Cubic, 2.0, &MotionLimits::new(1.0, 100.0)).unwrap();
    close(&law, 3.0); // velocity-bound: 1.5·2/1
    let law = TimeLaw::from_limits(Profile::Cubic, 2.0, &MotionLimits::new(100.0, 3.0)).unwrap();
    close(&law, 2.0); // acceleration-bound: √(6·2/3)
    let law = TimeLaw::from_limits(Profile::Quintic, 2.0, &MotionLimits::new(1.0, 100.0)).unwrap();
    close(&law, 3.75);
    let law = TimeLaw::from_limits(Profile::Quintic, 2.0, &MotionLimits::with_jerk(100.0, 100.0, 15.0)).unwrap();
    close(&law, 2.0); // jerk-bound: ∛(60·2/15)
    let law = TimeLaw::from_limits(Profile::Linear, 2.0, &MotionLimits::new(0.5, 1.0)).unwrap();
    close(&law, 4.0);
    // The polynomial shapes themselves.
    for t in [0.1, 0.37, 0.5, 0.9] {
        let c = TimeLaw::from_duration(Profile::Cubic, 1.0).unwrap().at(t);
        assert!((c.s - (3.0 * t * t - 2.0 * t * t * t)).abs() < 1e-15);
        let q = TimeLaw::from_duration(Profile::Quintic, 1.0).unwrap().at(t);
        assert!((q.s - (10.0 * t.powi(3) - 15.0 * t.powi(4) + 6.0 * t.powi(5))).abs() < 1e-15);
        let l = TimeLaw::from_duration(Profile::Linear, 1.0).unwrap().at(t);
        assert!((l.s - t).abs() < 1e-15 && l.sd == 1.0);
    }
}

/// Scaling v, a, j by k, k², k³ makes every law exactly k times faster.
#[test]
fn time_scaling_law() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..2000 {
        let (d, lim) = random_limits(&mut rng);
        let k = log_uniform(&mut rng, 0.05, 20.0);
        let fast = MotionLimits::with_jerk(lim.vel * k, lim.acc * k * k, lim.jerk.unwrap() * k * k * k);
        for profile in Profile::ALL {
            let slow = TimeLaw::from_limits(profile, d, &lim).unwrap();
            let quick = TimeLaw::from_limits(profile, d, &fast).unwrap();
            let ratio = slow.duration() / quick.duration();
            assert!((ratio - k).abs() < 1e-9 * k, "{profile}: {ratio} vs {k}");
            let t = slow.duration() * rng.random_range(0.0..1.0);
            assert!((slow.at(t).s - quick.at(t / k).s).abs() < 1e-9, "{profile}");
        }
    }
}

#[test]
fn from_duration_lasts_exactly_that_and_stretching_keeps_the_path() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    for _ in 0..500 {
        let dur = log_uniform(&mut rng, 1e-3, 1e3);
        for profile in Profile::ALL {
            let law = TimeLaw::from_duration(profile, dur).unwrap();
            assert!((law.duration() - dur).abs() <= 1e-12 * dur, "{profile}");
            assert!((law.at(dur * (1.0 - 1e-12)).s - 1.0).abs() < 1e-9, "{profile}");
            assert!((law.at(0.5 * dur).s - 0.5).abs() < 1e-12, "{profile}: not symmetric");
            // Stretching: s′(t) = s(t·T/T′), peaks shrink by k, k², k³.
            let longer = dur * log_uniform(&mut rng, 1.0, 10.0);
            let st = law.stretched_to(longer).unwrap();
            let k = dur / longer;
            assert!((st.duration() - longer).abs() <= 1e-12 * longer);
            for i in 1..20 {
                let t = longer * i as f64 / 20.0;
                let (a, b) = (st.at(t), law.at(t * k));
                assert!((a.s - b.s).abs() < 1e-12, "{profile}");
                assert!((a.sd - b.sd * k).abs() <= 1e-9 * b.sd.abs().max(1.0 / dur) * k, "{profile}");
                assert!(
                    (a.sdd - b.sdd * k * k).abs() <= 1e-9 * b.sdd.abs().max(1.0 / (dur * dur)) * k * k,
                    "{profile}"
                );
            }
            let (pa, pb) = (st.peaks(), law.peaks());
            assert!((pa.sd - pb.sd * k).abs() <= 1e-12 * pb.sd, "{profile}");
            assert!(st.stretched_to(longer * 0.9).is_err(), "{profile}: shrinking must be refused");
        }
    }
}

/// Seed 004, text after eq. 37: for a short move it computes τ = √(Δp/a_max)
/// but then sets T = v_max/a_max "to keep the profile trapezoidal", with the
/// seed's law (v = 1/T, a = 1/(T·τ), total duration T + τ). Written out here
/// from the seed's stage equations, that law stays within the limits but is
/// slower than the triangle kinema uses, for every short move.
#[test]
fn seed_short_move_recipe_is_slower() {
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    for case in 0..2000 {
        let v_max = log_uniform(&mut rng, 0.05, 5.0);
        let a_max = log_uniform(&mut rng, 0.05, 50.0);
        // A short move: Δp < v²/a.
        let dp = v_max * v_max / a_max * rng.random_range(0.001..0.999);
        let tau = (dp / a_max).sqrt();
        let big_t = v_max / a_max;
        assert!(big_t > tau, "short move means τ < v/a");
        // Seed's stages in normalised s with V = 1/T and A = 1/(T·τ).
        let (vn, an) = (1.0 / big_t, 1.0 / (big_t * tau));
        let seed_s = |t: f64| {
            let s_tau = an * tau * tau / 2.0;
            if t <= tau {
                an * t * t / 2.0
            } else if t <= big_t {
                s_tau + vn * (t - tau)
            } else {
                let s_t = s_tau + vn * (big_t - tau);
                s_t + vn * (t - big_t) - an * (t - big_t).powi(2) / 2.0
            }
        };
        let seed_total = big_t + tau;
        assert!((seed_s(seed_total) - 1.0).abs() < 1e-12, "case {case}: the seed's law ends at {}", seed_s(seed_total));
        // Within the limits (its peaks are V·Δp and A·Δp)…
        assert!(vn * dp <= v_max * (1.0 + REL) && an * dp <= a_max * (1.0 + REL), "case {case}");
        // … but slower than the time-optimal triangle.
        let ours = TimeLaw::from_limits(Profile::Trapezoid, dp, &MotionLimits::new(v_max, a_max)).unwrap();
        assert!((ours.duration() - 2.0 * tau).abs() < 1e-12 * ours.duration(), "case {case}");
        assert!(ours.duration() < seed_total, "case {case}: {} vs {}", ours.duration(), seed_total);
        // The triangle uses the full acceleration; the seed's law does not.
        assert!((ours.peaks().sdd * dp - a_max).abs() < 1e-9 * a_max);
        assert!(an * dp < a_max);
    }
}

#[test]
fn zero_distance_is_a_still_law() {
    for profile in Profile::ALL {
        let law = TimeLaw::from_limits(profile, 0.0, &MotionLimits::with_jerk(1.0, 1.0, 1.0)).unwrap();
        assert_eq!(law.duration(), 0.0);
        assert_eq!(law.at(0.0).s, 1.0);
        assert_eq!(law.peaks(), LawState::default());
    }
}

#[test]
fn bad_inputs_are_errors_naming_the_argument() {
    let ok = MotionLimits::with_jerk(1.0, 1.0, 1.0);
    let name = |e: Error| match e {
        Error::Input(InputError::OutOfRange { what, .. }) => what,
        other => panic!("unexpected error {other:?}"),
    };
    for d in [-1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(name(TimeLaw::from_limits(Profile::Trapezoid, d, &ok).unwrap_err()), "distance");
    }
    for v in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(name(TimeLaw::from_limits(Profile::Cubic, 1.0, &MotionLimits::new(v, 1.0)).unwrap_err()), "vmax");
        assert_eq!(name(TimeLaw::from_limits(Profile::Quintic, 1.0, &MotionLimits::new(1.0, v)).unwrap_err()), "amax");
        assert_eq!(
            name(TimeLaw::from_limits(Profile::SCurve, 1.0, &MotionLimits::with_jerk(1.0, 1.0, v)).unwrap_err()),
            "jmax"
        );
        assert_eq!(name(TimeLaw::from_duration(Profile::Trapezoid, v).unwrap_err()), "duration");
    }
    // The linear law needs no acceleration limit.
    assert!(TimeLaw::from_limits(Profile::Linear, 1.0, &MotionLimits::new(1.0, f64::NAN)).is_ok());
    let e = TimeLaw::from_limits(Profile::SCurve, 1.0, &MotionLimits::new(1.0, 1.0)).unwrap_err();
    assert!(e.to_string().contains("jerk"), "{e}");
    let e = "zigzag".parse::<Profile>().unwrap_err();
    assert!(e.to_string().contains("trapezoid, scurve"), "{e}");
    assert_eq!("SCurve".parse::<Profile>().unwrap(), Profile::SCurve);
    let law = TimeLaw::from_duration(Profile::Quintic, 2.0).unwrap();
    assert!(law.stretched_to(f64::NAN).is_err() && law.stretched_to(1.0).is_err());
}

/// Limits from 1e-300 to 1e300: every law is either refused or usable — a
/// finite duration of at least `MIN_DURATION`, sampled from s = 0 to s = 1,
/// within every limit it was built from.
#[test]
fn extreme_limits_give_a_usable_law_or_an_error() {
    let mut rng = ChaCha8Rng::seed_from_u64(24);
    let (mut refused, mut planned) = (0, 0);
    for _ in 0..20_000 {
        let d = log_uniform(&mut rng, 1e-300, 1e300);
        let lim = MotionLimits::with_jerk(
            log_uniform(&mut rng, 1e-300, 1e300),
            log_uniform(&mut rng, 1e-300, 1e300),
            log_uniform(&mut rng, 1e-300, 1e300),
        );
        for profile in Profile::ALL {
            let Ok(law) = TimeLaw::from_limits(profile, d, &lim) else {
                refused += 1;
                continue;
            };
            planned += 1;
            let t = law.duration();
            assert!(t.is_finite() && t >= kinema::traj::MIN_DURATION, "{profile:?} d {d:e} {lim:?}: T = {t:e}");
            let p = law.peaks();
            let ok = |peak: f64, limit: f64| d * peak <= limit * (1.0 + REL);
            assert!(ok(p.sd, lim.vel), "{profile:?} d {d:e} {lim:?}: peak velocity {:e}", d * p.sd);
            if profile != Profile::Linear {
                assert!(ok(p.sdd, lim.acc), "{profile:?} d {d:e} {lim:?}: peak acceleration {:e}", d * p.sdd);
            }
            if matches!(profile, Profile::SCurve | Profile::Quintic) {
                assert!(ok(p.sddd, lim.jerk.unwrap()), "{profile:?} d {d:e} {lim:?}: peak jerk {:e}", d * p.sddd);
            }
            let times = kinema::traj::sample_times(t, t / 3.0).unwrap();
            assert_eq!(law.at(times[0]).s, 0.0);
            assert_eq!(law.at(*times.last().unwrap()).s, 1.0);
        }
    }
    assert!(refused > 1000 && planned > 1000, "refused {refused}, planned {planned}");
}

#[test]
fn limits_that_overflow_or_vanish_the_duration_are_named() {
    let err = |profile, d, lim: MotionLimits| TimeLaw::from_limits(profile, d, &lim).unwrap_err().to_string();
    // The cases: jerk 1e-300 (the double-S lasts forever), a distance
    // whose duration overflows, limits so large the motion lasts 1e-50 s.
    let e = err(Profile::SCurve, 1.0, MotionLimits::with_jerk(1.0, 1.0, 1e-300));
    assert!(e.contains("overflows"), "{e}");
    let e = err(Profile::Trapezoid, 1e308, MotionLimits::new(0.5, 1.0));
    assert!(e.contains("overflows"), "{e}");
    // Issue 35 item 6: at 1 m/s the duration is a finite 1e308 s, but the
    // 1 s acceleration phases vanish in it.
    let e = err(Profile::Trapezoid, 1e308, MotionLimits::new(1.0, 1.0));
    assert!(e.contains("lost to rounding"), "{e}");
    let e = err(Profile::SCurve, 1e308, MotionLimits::with_jerk(1.0, 1.0, 1.0));
    assert!(e.contains("lost to rounding"), "{e}");
    // A long but sound motion is still planned: 1e9 m at 1 m/s.
    assert!(TimeLaw::from_limits(Profile::SCurve, 1e9, &MotionLimits::with_jerk(1.0, 1.0, 1.0)).is_ok());
    let e = err(Profile::Trapezoid, 1.0, MotionLimits::new(1e100, 1e100));
    assert!(e.contains("shorter than"), "{e}");
    let e = TimeLaw::from_duration(Profile::Cubic, 1e-12).unwrap_err().to_string();
    assert!(e.contains("shorter than"), "{e}");
}
