//! Second order (no jerk limit): the fastest profiles (step 1) and those
//! lasting a prescribed time (step 2), both in closed form.

use super::cruise::cruise_at;
use super::problem::{Limits, Problem};
use super::profile::Profile;

/// Time-optimal candidates of one frame: +a_max up to a peak velocity, an
/// optional cruise at v_max, −a_max down to v_f.
pub(super) fn fastest_second(p: &Problem, l: &Limits, out: &mut Vec<Profile>) {
    let a = l.acc;
    let build = |vp: f64, cruise: f64| {
        let mut s = Profile::default();
        s.push((vp - p.v0) / a, 0.0, Some(a));
        s.push(cruise, 0.0, Some(0.0));
        s.push((vp - p.vf) / a, 0.0, Some(-a));
        s
    };
    let (ta, tb) = ((l.vel - p.v0) / a, (l.vel - p.vf) / a);
    let cruise = (p.dp - 0.5 * (p.v0 + l.vel) * ta - 0.5 * (l.vel + p.vf) * tb) / l.vel;
    if ta >= 0.0 && tb >= 0.0 && cruise >= 0.0 {
        out.push(build(l.vel, cruise));
    }
    let k = a * p.dp + 0.5 * (p.v0 * p.v0 + p.vf * p.vf);
    if k >= 0.0 {
        for vp in [k.sqrt(), -k.sqrt()] {
            let vp = vp.min(l.vel);
            if vp >= p.v0.max(p.vf) - 1e-12 * l.vel {
                out.push(build(vp.max(p.v0.max(p.vf)), 0.0));
            }
        }
    }
}

/// Candidates lasting exactly `t` (second order): a cruise at v_c between
/// ramps at ±a_max, solved in closed form on each sign pattern.
pub(super) fn timed_second(p: &Problem, l: &Limits, t: f64, out: &mut Vec<Profile>) {
    for sa in [1.0, -1.0] {
        for sb in [1.0, -1.0] {
            // t_A = α(v_c − v0), t_B = β(v_f − v_c); position quadratic in v_c.
            let (al, be) = (sa / l.acc, sb / l.acc);
            let qa = 0.5 * (be - al);
            let qb = t + al * p.v0 - be * p.vf;
            let qc = 0.5 * (be * p.vf * p.vf - al * p.v0 * p.v0) - p.dp;
            let mut cands = [f64::NAN; 2];
            if qa == 0.0 {
                cands[0] = -qc / qb;
            } else {
                let d = qb * qb - 4.0 * qa * qc;
                if d >= 0.0 {
                    // Numerically stable pair of roots.
                    let q = -0.5 * (qb + d.sqrt().copysign(qb));
                    cands = [q / qa, qc / q];
                }
            }
            for vc in cands {
                if vc.is_finite() && vc.abs() <= l.vel * (1.0 + 1e-12) {
                    if let Some(s) = cruise_at(p, l, t, vc.clamp(-l.vel, l.vel)) {
                        out.push(s);
                    }
                }
            }
        }
    }
}
