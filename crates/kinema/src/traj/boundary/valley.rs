//! The step-1 valley families in closed form: their end-position residuals
//! are polynomials of degree ≤ 4 in one unknown, solved by
//! [`poly::real_roots`].
//!
//! In units where j = a_max = 1 (accelerations over a_max, times over
//! a_max/j, velocities over a_max²/j, positions over a_max³/j²), with
//! C = v_f − v₀ + (a₀² − a_f²)/2, w = 2 v₀ − a₀² and
//! p₀ = C a_f + a₀³/3 − a₀² a_f/2 − a₀ v₀ + a_f³/6 + a_f v₀ − Δp:
//!
//! - **Valley at x** (ramps +j to a peak a_p, −j to x, +j to a_f): the end
//!   velocity fixes a_p² = C + x². Integrating the three ramps and reducing
//!   a_p² gives the residual R = P(x) + a_p Q(x) with P = −x³ − (2C + w) x + p₀
//!   and Q = x² + C + w. Squaring P = −a_p Q out, the x⁶ and x⁵ terms cancel:
//!   S(x) = P² − (C + x²) Q² = C x⁴ − 2p₀ x³ + C² x² − 2p₀(2C + w) x + p₀² − C(C + w)².
//!   Each root of S is a root of R for the sign of a_p that makes P + a_p Q
//!   smaller, then refined by Newton's method on that R.
//! - **Valley at x, peak held at a_max** (when C + x² > 1): the hold
//!   h = C + x² − 1 is quadratic in x, and the residual is the quartic
//!   x⁴/2 − x³ + (2C + w + 1) x²/2 − (2C + w) x + (C + 1)(C + w)/2 + p₀.
//! - **Valley held at −a_max for h** (unknown h): the peak satisfies
//!   a_p² = C + 1 + h, so with a_p as the unknown the residual is the quartic
//!   a_p⁴/2 + a_p³ + (w + 1) a_p²/2 + w a_p + p₀ − (C − 1)(C + w)/2 without a
//!   square root, and h = a_p² − 1 − C.
//! - **Valley held for h, peak held at a_max for h + C** (when C + 1 + h > 1):
//!   h² + (2C + w + 3) h + p₀ + (C² + C w + 7C + 4w + 4)/2.
//!
//! Roots are kept in the family's range (widened by rounding, then clamped)
//! and returned in physical units; the caller builds every one and the
//! re-check decides, as for the grid search.

use super::poly;
use super::problem::Problem;

/// How far (in units of a_max or a_max/j) outside its range a root is still
/// taken (and clamped): roots on a bound (a phase of length 0) are common and
/// rounding may put them just outside.
const PAD: f64 = 1e-9;

/// A problem in units where j = a_max = 1, and the quantities the residual
/// polynomials are written in.
struct Unit {
    af: f64,
    /// C = v_f − v₀ + (a₀² − a_f²)/2: a_p² − x² for any valley profile.
    c: f64,
    /// w = 2 v₀ − a₀².
    w: f64,
    /// The residual's part that depends on neither unknown.
    p0: f64,
}

impl Unit {
    fn new(p: &Problem, acc: f64, j: f64) -> Unit {
        let (sv, sp) = (acc * acc / j, acc * acc * acc / (j * j));
        let (v0, a0, vf, af, dp) = (p.v0 / sv, p.a0 / acc, p.vf / sv, p.af / acc, p.dp / sp);
        let c = vf - v0 + 0.5 * (a0 * a0 - af * af);
        let w = 2.0 * v0 - a0 * a0;
        let p0 = c * af + a0 * a0 * a0 / 3.0 - 0.5 * a0 * a0 * af - a0 * v0 + af * af * af / 6.0 + af * v0 - dp;
        Unit { af, c, w, p0 }
    }

    /// P(x) + s·a_p·Q(x) and its slope in x, a_p = √(C + x²) (the valley residual).
    fn valley_residual(&self, x: f64, s: f64) -> (f64, f64) {
        let (c, w) = (self.c, self.w);
        let p = -x * x * x - (2.0 * c + w) * x + self.p0;
        let q = x * x + c + w;
        let r = (c + x * x).max(0.0).sqrt();
        let dp = -3.0 * x * x - (2.0 * c + w);
        let dr = if r > 0.0 { x / r } else { 0.0 };
        (p + s * r * q, dp + s * (dr * q + r * 2.0 * x))
    }
}

/// The valley accelerations x ∈ \[−a_max, a_f\] (with the sign of the peak:
/// `true` for +√K) at which a valley profile ends at the target position.
pub(super) fn valley_roots(p: &Problem, acc: f64, j: f64, out: &mut Vec<(f64, bool)>) {
    let u = Unit::new(p, acc, j);
    let (c, w, p0) = (u.c, u.w, u.p0);
    let (lo, hi) = (-1.0, u.af);
    if hi < lo - PAD {
        return;
    }
    let clamp = |x: f64| x.clamp(lo, hi.max(lo)) * acc;
    // The smallest and largest x² on the searched interval: a quartic whose
    // every root would fail its family's test on a_p² = C + x² is not solved
    // (x² is monotone in |x|, so the skip drops only roots the test drops).
    let (a, b) = (lo - PAD, hi + PAD);
    let least_sq = if a <= 0.0 && b >= 0.0 { 0.0 } else { (a * a).min(b * b) };
    let most_sq = (a * a).max(b * b);
    // Peak below a_max: the squared-out quartic, each root given its sign.
    let s = [p0 * p0 - c * (c + w) * (c + w), -2.0 * p0 * (2.0 * c + w), c * c, -2.0 * p0, c];
    let below = if c + least_sq > 1.0 + PAD { poly::Roots::default() } else { poly::real_roots(&s, a, b) };
    for &x0 in below.as_slice() {
        if c + x0 * x0 > 1.0 + PAD {
            continue;
        }
        let (rp, rm) = (u.valley_residual(x0, 1.0).0, u.valley_residual(x0, -1.0).0);
        for (sign, mine, other) in [(1.0, rp, rm), (-1.0, rm, rp)] {
            if mine.abs() <= other.abs() || mine.abs() <= PAD * (rp.abs() + rm.abs()) {
                out.push((clamp(newton(|x| u.valley_residual(x, sign), x0)), sign > 0.0));
            }
        }
    }
    // Peak held at a_max.
    if c + most_sq < 1.0 - PAD {
        return;
    }
    let t = [0.5 * (c + 1.0) * (c + w) + p0, -(2.0 * c + w), 0.5 * (2.0 * c + w + 1.0), -1.0, 0.5];
    let xs = poly::real_roots(&t, a, b);
    out.extend(xs.as_slice().iter().filter(|&&x| c + x * x >= 1.0 - PAD).map(|&x| (clamp(x), true)));
}

/// The hold lengths h ∈ \[0, `hmax`\] \[s\] of a valley held at −a_max (with
/// the sign of the peak) at which the profile ends at the target position.
pub(super) fn held_roots(p: &Problem, acc: f64, j: f64, hmax: f64, out: &mut Vec<(f64, bool)>) {
    let u = Unit::new(p, acc, j);
    let (c, w, p0) = (u.c, u.w, u.p0);
    let hi = hmax * j / acc;
    let to_seconds = |h: f64| h.clamp(0.0, hi) * acc / j;
    // Peak a_p below a_max, the unknown; not solved where every a_p in its
    // range gives a hold h = a_p² − 1 − C outside [0, hi] (h is monotone in a_p²).
    let q = [p0 - 0.5 * (c - 1.0) * (c + w), w, 0.5 * (w + 1.0), 1.0, 0.5];
    let (most_h, least_h) = ((1.0 + PAD) * (1.0 + PAD) - 1.0 - c, -1.0 - c);
    let peaks = if most_h < -PAD || least_h > hi + PAD {
        poly::Roots::default()
    } else {
        poly::real_roots(&q, -1.0 - PAD, 1.0 + PAD)
    };
    for &ap in peaks.as_slice() {
        let h = ap * ap - 1.0 - c;
        if h >= -PAD && h <= hi + PAD {
            if ap >= -PAD {
                out.push((to_seconds(h), true));
            }
            if ap <= PAD {
                out.push((to_seconds(h), false));
            }
        }
    }
    // Peak held at a_max for h + C.
    let d = [p0 + 0.5 * (c * c + c * w + 7.0 * c + 4.0 * w + 4.0), 2.0 * c + w + 3.0, 1.0];
    let hs = poly::real_roots(&d, (-c).max(0.0) - PAD, hi + PAD);
    out.extend(hs.as_slice().iter().map(|&h| (to_seconds(h), true)));
}

/// A few Newton steps on `f` (value and slope) from `x`, each kept only if it
/// makes |f| smaller.
fn newton(f: impl Fn(f64) -> (f64, f64), mut x: f64) -> f64 {
    let (mut fx, mut dx) = f(x);
    for _ in 0..4 {
        if fx == 0.0 || !(dx.abs() > 0.0) {
            break;
        }
        let next = x - fx / dx;
        let (fn_, dn) = f(next);
        if !(fn_.abs() < fx.abs()) {
            break;
        }
        (x, fx, dx) = (next, fn_, dn);
    }
    x
}

#[cfg(test)]
mod tests {
    use super::super::fastest_third::fastest_third;
    use super::super::problem::{Limits, SYMMETRIES};
    use super::super::profile::JerkSegment;
    use super::super::roots::Search;
    use super::super::{BoundaryLaw, BoundaryState};
    use super::*;
    use crate::traj::law::MotionLimits;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
        rng.random_range(lo.ln()..hi.ln()).exp()
    }

    /// Random third-order limits and a problem between states within them
    /// (a quarter of them with a short displacement, where the valley
    /// families are locally optimal most often).
    fn random_problem(rng: &mut ChaCha8Rng) -> (MotionLimits, BoundaryState, BoundaryState) {
        let lim = MotionLimits::with_jerk(
            log_uniform(rng, 0.1, 10.0),
            log_uniform(rng, 0.1, 100.0),
            log_uniform(rng, 1.0, 1000.0),
        );
        let j = lim.jerk.unwrap_or(1.0);
        let state = |rng: &mut ChaCha8Rng, p: f64| {
            let v = if rng.random_bool(0.2) { 0.0 } else { rng.random_range(-lim.vel..=lim.vel) };
            let a = if rng.random_bool(0.2) { 0.0 } else { rng.random_range(-lim.acc..=lim.acc) };
            let reach = (2.0 * j * (lim.vel - v.abs())).sqrt();
            BoundaryState::new(p, v, a.clamp(-reach, reach))
        };
        let from = state(rng, 0.0);
        let d = if rng.random_bool(0.25) { rng.random_range(-0.05..0.05) } else { rng.random_range(-5.0..5.0) };
        (lim, from, state(rng, d))
    }

    fn ramp(dt: f64, jerk: f64) -> JerkSegment {
        JerkSegment { dt, jerk, set_acc: None }
    }

    /// The end position minus the target's, segments of negative length
    /// integrated too (the algebra holds for them, a profile leaves them out).
    fn residual_of(p: &Problem, segments: &[JerkSegment]) -> f64 {
        let (mut x, mut v, mut a) = (0.0, p.v0, p.a0);
        for s in segments {
            let u = s.dt;
            x += u * (v + u * (a / 2.0 + u * s.jerk / 6.0));
            v += u * (a + u * s.jerk / 2.0);
            a += u * s.jerk;
        }
        x - p.dp
    }

    /// The four polynomials against the integrated profiles they stand for,
    /// at random values of their unknowns (the profiles need not be
    /// feasible: only the algebra is checked).
    #[test]
    fn the_polynomials_are_the_integrated_end_positions() {
        let mut rng = ChaCha8Rng::seed_from_u64(3602);
        for case in 0..5000 {
            let (lim, from, to) = random_problem(&mut rng);
            let (acc, j) = (lim.acc, lim.jerk.unwrap_or(1.0));
            let p = Problem::new(&from, &to);
            let u = Unit::new(&p, acc, j);
            let (c, w, p0) = (u.c, u.w, u.p0);
            let value = |k: &[f64], x: f64| k.iter().rev().fold(0.0, |s, &ki| s * x + ki);
            // In physical units: the residual over a_max³/j² is the polynomial.
            let sp = acc * acc * acc / (j * j);
            let close = |phys: f64, unit: f64, size: f64| (phys / sp - unit).abs() <= 1e-9 * size.max(1.0);
            let x = rng.random_range(-1.0..1.0);
            let (af, a0) = (p.af, p.a0);
            for s in [1.0, -1.0] {
                let ap = s * (c + x * x).max(0.0).sqrt() * acc;
                let xa = x * acc;
                let phys = residual_of(&p, &[ramp((ap - a0) / j, j), ramp((ap - xa) / j, -j), ramp((af - xa) / j, j)]);
                if c + x * x >= 0.0 {
                    let size = p0.abs() + (c.abs() + w.abs() + 1.0) * 4.0;
                    assert!(close(phys, u.valley_residual(x, s).0, size), "case {case}: valley {s}");
                }
            }
            let h = c + x * x - 1.0;
            let xa = x * acc;
            let phys = residual_of(
                &p,
                &[ramp((acc - p.a0) / j, j), ramp(h * acc / j, 0.0), ramp((acc - xa) / j, -j), ramp((af - xa) / j, j)],
            );
            let t = [0.5 * (c + 1.0) * (c + w) + p0, -(2.0 * c + w), 0.5 * (2.0 * c + w + 1.0), -1.0, 0.5];
            let size = p0.abs() + (c.abs() + w.abs() + 1.0).powi(2);
            assert!(close(phys, value(&t, x), size), "case {case}: peak held");
            let ap = x * acc;
            let h = x * x - 1.0 - c;
            let phys = residual_of(
                &p,
                &[ramp((ap - a0) / j, j), ramp((ap + acc) / j, -j), ramp(h * acc / j, 0.0), ramp((af + acc) / j, j)],
            );
            let q = [p0 - 0.5 * (c - 1.0) * (c + w), w, 0.5 * (w + 1.0), 1.0, 0.5];
            assert!(close(phys, value(&q, x), size), "case {case}: valley held");
            let h = rng.random_range(0.0..2.0);
            let phys = residual_of(
                &p,
                &[
                    ramp((acc - a0) / j, j),
                    ramp((h + c) * acc / j, 0.0),
                    ramp(2.0 * acc / j, -j),
                    ramp(h * acc / j, 0.0),
                    ramp((af + acc) / j, j),
                ],
            );
            let d = [p0 + 0.5 * (c * c + c * w + 7.0 * c + 4.0 * w + 4.0), 2.0 * c + w + 3.0, 1.0];
            assert!(close(phys, value(&d, h), size + 9.0), "case {case}: both held");
        }
    }

    /// The valid laws of one frame's step-1 candidates, their durations ascending.
    fn durations(from: BoundaryState, to: BoundaryState, lim: &MotionLimits, search: Search) -> Vec<Vec<f64>> {
        let l = Limits::new(lim, search).unwrap();
        let p = Problem::new(&from, &to);
        SYMMETRIES
            .iter()
            .map(|sym| {
                let mut cands = Vec::new();
                fastest_third(&sym.problem(&p), &l, lim.jerk.unwrap_or(1.0), &mut cands);
                let cands: Vec<_> = cands.iter().map(|s| sym.back(s)).collect();
                BoundaryLaw::from_candidates(from, to, &l, &cands).iter().map(|c| c.duration).collect()
            })
            .collect()
    }

    /// Every law the reference grid search finds in a frame, the closed
    /// forms find too (same duration within 1e-9 relative): the test that
    /// catches a branch of a polynomial left out or a root thrown away.
    #[test]
    fn the_closed_forms_find_every_law_the_grid_finds() {
        let mut rng = ChaCha8Rng::seed_from_u64(3603);
        let (mut laws, mut extra) = (0, 0);
        for case in 0..6000 {
            let (lim, from, to) = random_problem(&mut rng);
            let fast = durations(from, to, &lim, Search::Fast);
            let grid = durations(from, to, &lim, Search::Reference);
            for (frame, (f, g)) in fast.iter().zip(&grid).enumerate() {
                for &d in g {
                    assert!(
                        f.iter().any(|&e| (e - d).abs() <= 1e-9 * d),
                        "case {case} frame {frame}: {from:?} → {to:?} {lim:?}: grid {g:?}, closed forms {f:?}"
                    );
                }
                laws += g.len();
                extra += f.len().saturating_sub(g.len());
            }
        }
        assert!(laws > 6000, "too few laws to compare: {laws} ({extra} more from the closed forms)");
    }
}
