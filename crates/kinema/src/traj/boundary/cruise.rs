//! Step 2, both orders: a cruise at some velocity v_c between the fastest
//! changes to and from it, lasting a prescribed time.

use super::problem::{Limits, Problem};
use super::profile::{residual_of, JerkSegment, Profile};
use super::roots;
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
            let (a, b) = (fastest_change(p.v0, p.a0, vc, 0.0, l, j)?, fastest_change(vc, 0.0, p.vf, p.af, l, j)?);
            g[..3].copy_from_slice(&a.segments());
            g[4..].copy_from_slice(&b.segments());
            (a.duration(), b.duration())
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
pub(super) fn timed_cruise(p: &Problem, l: &Limits, t: f64, out: &mut Vec<Profile>) {
    let slack = |vc: f64| -> f64 {
        let f = |a: Option<Change>| a.map_or(f64::INFINITY, |s| s.duration());
        match l.jerk {
            Some(j) => t - f(fastest_change(p.v0, p.a0, vc, 0.0, l, j)) - f(fastest_change(vc, 0.0, p.vf, p.af, l, j)),
            None => t - ((vc - p.v0).abs() + (p.vf - vc).abs()) / l.acc,
        }
    };
    let n = 4 * roots::GRID;
    let xs: Vec<f64> = (0..=n).map(|i| -l.vel + 2.0 * l.vel * i as f64 / n as f64).collect();
    let ss: Vec<f64> = xs.iter().map(|&x| slack(x)).collect();
    // The slack is largest near its best sample; feasible intervals are
    // runs of samples with slack ≥ 0, extended to slack = 0 by Illinois.
    let edge = |inside: f64, outside: f64| roots::last_inside(&slack, inside, outside);
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
    let mut rs = Vec::new();
    for (lo, hi) in intervals {
        rs.clear();
        roots::find(l.search, &|vc| cruise_residual(p, l, t, vc), lo, hi, roots::GRID, &mut rs);
        out.extend(rs.iter().filter_map(|&vc| cruise_at(p, l, t, vc)));
    }
}
