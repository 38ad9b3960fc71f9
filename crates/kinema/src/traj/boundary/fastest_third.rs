//! Step 1, third order: the locally time-optimal profiles of one frame,
//! whose acceleration rises, falls and rises again, each phase a jerk ramp
//! or a hold at a limit (+a_max, −a_max, or a cruise at +v_max).

use super::problem::{Limits, Problem};
use super::profile::{residual_of, JerkSegment, Profile};
use super::roots::{self, Search};
use super::valley::{held_roots, valley_roots};
use super::velocity::{fall, rise};

/// Time-optimal candidates of one frame (acceleration rises, falls, rises).
pub(super) fn fastest_third(p: &Problem, l: &Limits, j: f64, out: &mut Vec<Profile>) {
    let (mut xs, mut found) = (Vec::new(), Vec::with_capacity(16));
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
    let valley_change = |x: f64, root: bool| {
        let vc = p.vf - (p.af * p.af - x * x) / (2.0 * j);
        rise(p.v0, p.a0, vc, x, l, j, root)
    };
    let valley = |x: f64, root: bool| -> Option<Profile> {
        let mut s = valley_change(x, root)?.profile();
        s.push((p.af - x) / j, j, None);
        Some(s)
    };
    let valley_residual = |x: f64, root: bool| match valley_change(x, root) {
        Some(c) => {
            let [up, hold, down] = c.segments();
            residual_of(p, &[up, hold, down, ramp((p.af - x) / j, j)])
        }
        None => f64::NAN,
    };
    // A falling root (a peak −√K ≤ 0) cannot start from a0 > 0: `rise`
    // refuses every such change, so its searches would find nothing.
    let roots_signs: &[bool] = if p.a0 > 1e-12 * l.acc { &[true] } else { &[true, false] };
    match l.search {
        Search::Fast => {
            found.clear();
            valley_roots(p, l.acc, j, &mut found);
            let allowed = |&&(_, root): &&(f64, bool)| roots_signs.contains(&root);
            out.extend(found.iter().filter(allowed).filter_map(|&(x, root)| valley(x, root)));
        }
        Search::Reference => {
            for &root in roots_signs {
                xs.clear();
                roots::find(l.search, &|x| valley_residual(x, root), -l.acc, p.af, l.search.intervals(), &mut xs);
                out.extend(xs.iter().filter_map(|&x| valley(x, root)));
            }
        }
    }
    // No cruise, valley held at −a_max for x seconds.
    let v7 = p.vf - (p.af * p.af - l.acc * l.acc) / (2.0 * j);
    let held_change = |x: f64, root: bool| rise(p.v0, p.a0, v7 + l.acc * x, -l.acc, l, j, root);
    let held = |x: f64, root: bool| -> Option<Profile> {
        let mut s = held_change(x, root)?.profile();
        s.push(x, 0.0, None);
        s.push((p.af + l.acc) / j, j, None);
        Some(s)
    };
    let held_residual = |x: f64, root: bool| match held_change(x, root) {
        Some(c) => {
            let [up, hold, down] = c.segments();
            residual_of(p, &[up, hold, down, ramp(x, 0.0), ramp((p.af + l.acc) / j, j)])
        }
        None => f64::NAN,
    };
    let hmax = (l.vel - v7) / l.acc;
    if !(hmax > 0.0) {
        return;
    }
    match l.search {
        Search::Fast => {
            found.clear();
            held_roots(p, l.acc, j, hmax, &mut found);
            let allowed = |&&(_, root): &&(f64, bool)| roots_signs.contains(&root);
            out.extend(found.iter().filter(allowed).filter_map(|&(x, root)| held(x, root)));
        }
        Search::Reference => {
            for &root in roots_signs {
                xs.clear();
                roots::find(l.search, &|x| held_residual(x, root), 0.0, hmax, l.search.intervals(), &mut xs);
                out.extend(xs.iter().filter_map(|&x| held(x, root)));
            }
        }
    }
}

/// A segment of constant jerk that keeps the acceleration continuous.
fn ramp(dt: f64, jerk: f64) -> JerkSegment {
    JerkSegment { dt, jerk, set_acc: None }
}
