//! Step 2, both orders: a cruise at some velocity v_c between the fastest
//! changes to and from it, lasting a prescribed time.

use super::problem::{Limits, Problem};
use super::profile::{residual_of, JerkSegment, Profile};
use super::roots::{self, Search};
use super::velocity::{fastest_change, Change};

/// Cruise at v_c (zero acceleration) between the fastest changes to and
/// from it, lasting exactly `t`; for any order (`j` = None: second order).
pub(super) fn cruise_at(p: &Problem, l: &Limits, t: f64, vc: f64) -> Option<Profile> {
    Some(Profile::from_segments(&cruise_segments(p, l, t, vc)?))
}

/// The end position of [`cruise_at`]'s profile minus the target's (NaN when
/// there is none), computed without building the profile.
fn cruise_residual(p: &Problem, l: &Limits, t: f64, vc: f64) -> f64 {
    cruise_segments(p, l, t, vc).map_or(f64::NAN, |g| residual_of(p, &g))
}

/// [`cruise_at`]'s segments (unused ones of length 0): up to three for the
/// change to v_c, the cruise, up to three for the change from it.
fn cruise_segments(p: &Problem, l: &Limits, t: f64, vc: f64) -> Option<[JerkSegment; 7]> {
    let mut g = [JerkSegment::default(); 7];
    let (da, db) = match l.jerk {
        Some(j) => {
            let (a, da) = fastest_change(p.v0, p.a0, vc, 0.0, l, j)?;
            let (b, db) = fastest_change(vc, 0.0, p.vf, p.af, l, j)?;
            g[..3].copy_from_slice(&a.segments());
            g[4..].copy_from_slice(&b.segments());
            (da, db)
        }
        None => {
            let ramp = |from: f64, to: f64| JerkSegment {
                dt: (to - from).abs() / l.acc,
                jerk: 0.0,
                set_acc: Some(l.acc.copysign(to - from)),
            };
            let (a, b) = (ramp(p.v0, vc), ramp(vc, p.vf));
            (g[0], g[4]) = (a, b);
            // As a profile sums its non-empty segments.
            (a.dt.max(0.0), b.dt.max(0.0))
        }
    };
    let cruise = t - da - db;
    if !(cruise >= -1e-12 * t.max(1.0)) {
        return None;
    }
    g[3] = JerkSegment { dt: cruise.max(0.0), jerk: 0.0, set_acc: Some(0.0).filter(|_| l.jerk.is_none()) };
    Some(g)
}

/// Cruise candidates lasting exactly `t`: the cruise velocities v_c for which
/// the two fastest changes fit into `t` form intervals; on each, the roots of
/// the position residual.
///
/// The residual does not fall as v_c rises where the changes fit: its slope
/// is the cruise's length plus, for each change, the integral over the
/// change of ∂v/∂v_c, and a change to or from a higher cruise velocity is
/// faster at every moment (its peak or valley acceleration is higher). So
/// the fast search looks for one sign change between an interval's ends;
/// the reference scans a grid.
pub(super) fn timed_cruise(p: &Problem, l: &Limits, t: f64, out: &mut Vec<Profile>) {
    let slack = |vc: f64| slack(p, l, t, vc);
    let intervals = match l.search {
        Search::Fast => feasible_by_shape(p, l, &slack),
        Search::Reference => feasible_by_scan(l, &slack),
    };
    let mut rs = Vec::with_capacity(8);
    let residual = |vc: f64| cruise_residual(p, l, t, vc);
    for (lo, hi) in intervals {
        rs.clear();
        match l.search {
            Search::Fast => monotone_root(&residual, lo, hi, &mut rs),
            Search::Reference => roots::find(l.search, &residual, lo, hi, l.search.intervals(), &mut rs),
        }
        out.extend(rs.iter().filter_map(|&vc| cruise_at(p, l, t, vc)));
    }
}

/// How much of `t` is left for the cruise at `vc` after the two fastest changes.
fn slack(p: &Problem, l: &Limits, t: f64, vc: f64) -> f64 {
    let f = |a: Option<(Change, f64)>| a.map_or(f64::INFINITY, |(_, d)| d);
    match l.jerk {
        Some(j) => t - f(fastest_change(p.v0, p.a0, vc, 0.0, l, j)) - f(fastest_change(vc, 0.0, p.vf, p.af, l, j)),
        None => t - ((vc - p.v0).abs() + (p.vf - vc).abs()) / l.acc,
    }
}

/// The root of `f`, non-decreasing on \[`lo`, `hi`\], if it has one there:
/// an end where it is 0, or the sign change between the ends refined by
/// regula falsi. Where `f` has no value at an end, the grid search.
fn monotone_root(f: &impl Fn(f64) -> f64, lo: f64, hi: f64, out: &mut Vec<f64>) {
    if !(lo.is_finite() && hi.is_finite()) || hi < lo {
        return;
    }
    let (flo, fhi) = (f(lo), f(hi));
    if !(flo.is_finite() && fhi.is_finite()) {
        roots::find(Search::Fast, f, lo, hi, Search::Fast.intervals(), out);
        return;
    }
    if flo == 0.0 {
        out.push(lo);
    }
    if fhi == 0.0 && hi > lo {
        out.push(hi);
    }
    if flo != 0.0 && fhi != 0.0 && (flo < 0.0) != (fhi < 0.0) {
        out.push(roots::illinois(f, lo, flo, hi, fhi));
    }
}

/// The intervals of cruise velocities in \[−v_max, v_max\] where `slack` ≥ 0,
/// from the slack's shape. The duration of the fastest change from the start
/// to (v_c, 0) is smallest at the velocity the start reaches when its
/// acceleration is brought to 0 (v₀ + a₀|a₀|/(2 j)) and grows away from it
/// along concave arms (square roots of v_c, linear once a_max is held); so
/// does the change from (v_c, 0) to the target around v_f − a_f|a_f|/(2 j).
/// The slack is thus convex between and beside those two cusps, rises up to
/// the lower one and falls after the upper one: a feasible interval around
/// each cusp, merged unless the slack dips below 0 between them.
fn feasible_by_shape(p: &Problem, l: &Limits, slack: &impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    let natural = |v: f64, a: f64, sign: f64| v + sign * l.jerk.map_or(0.0, |j| a * a.abs() / (2.0 * j));
    let (ca, cb) = (natural(p.v0, p.a0, 1.0), natural(p.vf, p.af, -1.0));
    let (m1, m2) = (ca.min(cb).clamp(-l.vel, l.vel), ca.max(cb).clamp(-l.vel, l.vel));
    let (s1, s2) = (slack(m1), slack(m2));
    let edge = |inside: f64, outside: f64| roots::last_inside(slack, inside, outside);
    let outer = |m: f64, end: f64| if slack(end) >= 0.0 { end } else { edge(m, end) };
    match (s1 >= 0.0, s2 >= 0.0) {
        (false, false) => Vec::new(),
        (true, false) => vec![(outer(m1, -l.vel), edge(m1, m2))],
        (false, true) => vec![(edge(m2, m1), outer(m2, l.vel))],
        (true, true) => {
            let (lo, hi) = (outer(m1, -l.vel), outer(m2, l.vel));
            // The slack is smallest between the cusps where both changes
            // peak at the same acceleration (their slopes 1/a_peak cancel).
            let shift = l.jerk.map_or(0.0, |j| (p.af * p.af - p.a0 * p.a0) / (4.0 * j));
            let lowest = (0.5 * (p.v0 + p.vf) + if ca <= cb { shift } else { -shift }).clamp(m1, m2);
            match Some(lowest).filter(|&x| slack(x) < 0.0) {
                Some(x) => vec![(lo, edge(m1, x)), (edge(m2, x), hi)],
                None => vec![(lo, hi)],
            }
        }
    }
}

/// The intervals where `slack` ≥ 0, by sampling 4·GRID + 1 cruise velocities
/// (the reference): runs of samples with slack ≥ 0, extended to slack = 0.
fn feasible_by_scan(l: &Limits, slack: &impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    let n = 4 * roots::GRID;
    let xs: Vec<f64> = (0..=n).map(|i| -l.vel + 2.0 * l.vel * i as f64 / n as f64).collect();
    let ss: Vec<f64> = xs.iter().map(|&x| slack(x)).collect();
    let edge = |inside: f64, outside: f64| roots::last_inside(slack, inside, outside);
    let mut intervals = Vec::new();
    let mut i = 0;
    while i <= n {
        if ss[i] >= 0.0 {
            let start = i;
            while i < n && ss[i + 1] >= 0.0 {
                i += 1;
            }
            let lo = if start == 0 { xs[0] } else { edge(xs[start], xs[start - 1]) };
            let hi = if i == n { xs[n] } else { edge(xs[i], xs[i + 1]) };
            intervals.push((lo, hi));
        }
        i += 1;
    }
    if intervals.is_empty() {
        // A feasible set narrower than the grid: search around the best sample.
        let k = (0..=n).max_by(|&a, &b| ss[a].total_cmp(&ss[b])).unwrap_or(0);
        let (mut a, mut b) = (xs[k.saturating_sub(1)], xs[(k + 1).min(n)]);
        let g = 0.618_033_988_749_895;
        for _ in 0..100 {
            let c = b - g * (b - a);
            let d = a + g * (b - a);
            if slack(c) > slack(d) {
                b = d;
            } else {
                a = c;
            }
        }
        let m = 0.5 * (a + b);
        if slack(m) >= 0.0 {
            intervals.push((edge(m, xs[k.saturating_sub(1)]), edge(m, xs[(k + 1).min(n)])));
        }
    }
    intervals
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traj::law::MotionLimits;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
        rng.random_range(lo.ln()..hi.ln()).exp()
    }

    /// What the fast search's single sign change relies on: across every
    /// feasible interval of random problems (both orders, durations from
    /// just feasible to three times that) the cruise residual, sampled at
    /// 200 velocities, never falls by more than rounding.
    #[test]
    fn the_cruise_residual_does_not_fall_as_the_cruise_velocity_rises() {
        let mut rng = ChaCha8Rng::seed_from_u64(3606);
        let mut intervals = 0;
        for case in 0..4000 {
            let (vel, acc) = (log_uniform(&mut rng, 0.1, 10.0), log_uniform(&mut rng, 0.1, 100.0));
            let jerk = case % 3 != 0;
            let lim = if jerk {
                MotionLimits::with_jerk(vel, acc, log_uniform(&mut rng, 1.0, 1000.0))
            } else {
                MotionLimits::new(vel, acc)
            };
            let l = Limits::new(&lim, Search::Fast).unwrap();
            let j = lim.jerk.unwrap_or(f64::INFINITY);
            let mut state = || {
                let v = rng.random_range(-vel..=vel);
                let reach = (2.0 * j * (vel - v.abs())).sqrt();
                let a = if jerk { rng.random_range(-acc..=acc).clamp(-reach, reach) } else { 0.0 };
                (v, a)
            };
            let ((v0, a0), (vf, af)) = (state(), state());
            let p = Problem { v0, a0, vf, af, dp: rng.random_range(-5.0..5.0) };
            let vc = rng.random_range(-vel..=vel);
            let t = -slack(&p, &l, 0.0, vc) * (1.0 + rng.random_range(0.0..2.0));
            if !t.is_finite() {
                continue;
            }
            let scale = p.dp.abs() + vel * t;
            for (lo, hi) in feasible_by_shape(&p, &l, &|x| slack(&p, &l, t, x)) {
                intervals += 1;
                let r: Vec<f64> =
                    (0..=200).map(|i| cruise_residual(&p, &l, t, lo + (hi - lo) * i as f64 / 200.0)).collect();
                for (i, w) in r.windows(2).enumerate() {
                    assert!(
                        w[1] >= w[0] - 1e-9 * scale,
                        "case {case}: {p:?} {lim:?} t {t}: residual falls at {i} of [{lo}, {hi}]: {} -> {}",
                        w[0],
                        w[1]
                    );
                }
            }
        }
        assert!(intervals > 3000, "too few feasible intervals: {intervals}");
    }
}
