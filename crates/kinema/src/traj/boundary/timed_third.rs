//! Step 2, third order: profiles lasting a prescribed time with one free
//! hold (the peak acceleration held below a_max, or the valley held at −a_max).

use super::problem::{Limits, Problem};
use super::profile::{residual_of, JerkSegment, Profile};
use super::roots;

/// Candidates lasting exactly `t` with one free hold: acceleration rises to a
/// peak a_p ≤ a_max held for some time, falls to a valley x, rises to a_f
/// (the valley held at −a_max for `hold` seconds when x = −a_max).
pub(super) fn held_peak(p: &Problem, l: &Limits, j: f64, t: f64, x: f64, hold: f64, root: bool) -> Option<Profile> {
    Some(Profile::from_segments(&held_peak_segments(p, l, j, t, x, hold, root)?))
}

/// The end position of [`held_peak`]'s profile minus the target's (NaN when
/// there is none), computed without building the profile.
fn held_peak_residual(p: &Problem, l: &Limits, j: f64, t: f64, x: f64, hold: f64, root: bool) -> f64 {
    held_peak_segments(p, l, j, t, x, hold, root).map_or(f64::NAN, |g| residual_of(p, &g))
}

/// [`held_peak`]'s five segments (some possibly of length 0).
fn held_peak_segments(
    p: &Problem,
    l: &Limits,
    j: f64,
    t: f64,
    x: f64,
    hold: f64,
    root: bool,
) -> Option<[JerkSegment; 5]> {
    let t7 = (p.af - x) / j;
    let vc = p.vf - (p.af * p.af - x * x) / (2.0 * j) + if hold > 0.0 { -x * hold } else { 0.0 };
    let tau = t - t7 - hold;
    if !(tau >= 0.0) {
        return None;
    }
    // a_p² − a_p(jτ + a0 + x) + (a0² + x²)/2 + j(vc − v0) = 0
    let b = j * tau + p.a0 + x;
    let c = 0.5 * (p.a0 * p.a0 + x * x) + j * (vc - p.v0);
    let disc = b * b - 4.0 * c;
    if disc < -1e-12 * b * b {
        return None;
    }
    let r = disc.max(0.0).sqrt();
    let ap = if root { 0.5 * (b + r) } else { 0.5 * (b - r) };
    let lo = p.a0.max(x);
    let tol = 1e-12 * l.acc;
    if ap < lo - tol || ap > l.acc + tol {
        return None;
    }
    let ap = ap.clamp(lo, l.acc);
    let (t1, t3) = ((ap - p.a0) / j, (ap - x) / j);
    let th = tau - t1 - t3;
    if th < -1e-12 * t.max(1.0) {
        return None;
    }
    let g = |dt: f64, jerk: f64| JerkSegment { dt, jerk, set_acc: None };
    Some([g(t1, j), g(th.max(0.0), 0.0), g(t3, -j), g(hold, 0.0), g(t7, j)])
}

/// Candidates of one frame lasting exactly `t` (third order).
pub(super) fn timed_third(p: &Problem, l: &Limits, j: f64, t: f64, out: &mut Vec<Profile>) {
    let mut xs = Vec::new();
    for root in [true, false] {
        xs.clear();
        roots::find(
            l.search,
            &|x| held_peak_residual(p, l, j, t, x, 0.0, root),
            -l.acc,
            p.af,
            l.search.intervals(),
            &mut xs,
        );
        out.extend(xs.iter().filter_map(|&x| held_peak(p, l, j, t, x, 0.0, root)));
        xs.clear();
        roots::find(
            l.search,
            &|h| held_peak_residual(p, l, j, t, -l.acc, h, root),
            0.0,
            t,
            l.search.intervals(),
            &mut xs,
        );
        out.extend(xs.iter().filter_map(|&h| held_peak(p, l, j, t, -l.acc, h, root)));
    }
}
