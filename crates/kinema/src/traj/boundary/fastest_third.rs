//! Step 1, third order: the locally time-optimal profiles of one frame,
//! whose acceleration rises, falls and rises again, each phase a jerk ramp
//! or a hold at a limit (+a_max, −a_max, or a cruise at +v_max).

use super::problem::{Limits, Problem};
use super::profile::Profile;
use super::roots;
use super::velocity::{fall, rise};

/// Residual of a candidate's position; NaN when there is none.
pub(super) fn residual(p: &Problem, s: Option<Profile>) -> f64 {
    match s {
        Some(s) => s.integrate(p.v0, p.a0).0 - p.dp,
        None => f64::NAN,
    }
}

/// Time-optimal candidates of one frame (acceleration rises, falls, rises).
pub(super) fn fastest_third(p: &Problem, l: &Limits, j: f64, out: &mut Vec<Profile>) {
    let mut xs = Vec::new();
    // Cruise at +v_max between the fastest changes to and from it.
    for ra in [true, false] {
        for rb in [true, false] {
            let (Some(a), Some(b)) = (rise(p.v0, p.a0, l.vel, 0.0, l, j, ra), fall(l.vel, 0.0, p.vf, p.af, l, j, rb))
            else {
                continue;
            };
            let (a, b) = (a.profile(), b.profile());
            let pa = a.integrate(p.v0, p.a0).0;
            let pb = b.integrate(l.vel, 0.0).0;
            let cruise = (p.dp - pa - pb) / l.vel;
            if cruise >= 0.0 {
                let mut s = a;
                s.push(cruise, 0.0, None);
                s.extend(&b);
                out.push(s);
            }
        }
    }
    // No cruise, valley acceleration x ∈ [−a_max, a_f], final ramp +j to a_f.
    let valley = |x: f64, root: bool| -> Option<Profile> {
        let vc = p.vf - (p.af * p.af - x * x) / (2.0 * j);
        let mut s = rise(p.v0, p.a0, vc, x, l, j, root)?.profile();
        s.push((p.af - x) / j, j, None);
        Some(s)
    };
    for root in [true, false] {
        xs.clear();
        roots::find(l.search, &|x| residual(p, valley(x, root)), -l.acc, p.af, roots::GRID, &mut xs);
        out.extend(xs.iter().filter_map(|&x| valley(x, root)));
    }
    // No cruise, valley held at −a_max for x seconds.
    let v7 = p.vf - (p.af * p.af - l.acc * l.acc) / (2.0 * j);
    let held = |x: f64, root: bool| -> Option<Profile> {
        let mut s = rise(p.v0, p.a0, v7 + l.acc * x, -l.acc, l, j, root)?.profile();
        s.push(x, 0.0, None);
        s.push((p.af + l.acc) / j, j, None);
        Some(s)
    };
    let hmax = (l.vel - v7) / l.acc;
    if hmax > 0.0 {
        for root in [true, false] {
            xs.clear();
            roots::find(l.search, &|x| residual(p, held(x, root)), 0.0, hmax, roots::GRID, &mut xs);
            out.extend(xs.iter().filter_map(|&x| held(x, root)));
        }
    }
}
