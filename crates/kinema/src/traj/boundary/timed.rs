//! Step 2: a law lasting a prescribed duration (what synchronised motions
//! need): a locally optimal law of exactly that duration, the cruise and
//! held-acceleration families, or a blend of two laws bracketing the target.

use super::cruise::{cruise_at, timed_cruise};
use super::problem::{Limits, Problem, SYMMETRIES};
use super::profile::{Candidate, Profile, Trial};
use super::second::timed_second;
use super::timed_third::{held_peak, timed_third};
use super::{check_min, no_profile, roots, BoundaryLaw, BoundaryState};
use crate::error::{Error, InputError, Result};

impl BoundaryLaw {
    /// The profile of [`BoundaryLaw::with_duration`]'s law, with the limits
    /// checked and the locally optimal profiles (`optimal`, fastest first)
    /// already known.
    pub(super) fn timed(
        from: BoundaryState,
        to: BoundaryState,
        l: &Limits,
        duration: f64,
        optimal: &[Candidate],
    ) -> Result<Profile> {
        let l = *l;
        check_duration(duration, optimal)?;
        if from == to && duration == 0.0 {
            return Ok(Profile::default());
        }
        check_min(duration)?;
        // A locally optimal law of this very duration (a limit of the families below).
        if let Some(c) = optimal.iter().find(|c| (c.duration - duration).abs() <= 1e-12 * duration) {
            return Ok(c.profile);
        }
        let still = from.v == 0.0 && from.a == 0.0 && to.v == 0.0 && to.a == 0.0 && from.p == to.p;
        let p = Problem::new(&from, &to);
        let lasting = |cands: &[Profile]| Self::first_lasting(from, to, &l, cands, duration);
        // The cheaper families first: a cruise (every rest-to-rest and most
        // other cases), then the held accelerations.
        let mut cands = Vec::with_capacity(8);
        if still {
            // At rest at the target: stay there.
            let mut s = Profile::default();
            s.push(duration, 0.0, None);
            cands.push(s);
        }
        timed_cruise(&p, &l, duration, &mut cands);
        if l.jerk.is_none() {
            timed_second(&p, &l, duration, &mut cands);
        }
        if let Some(s) = lasting(&cands) {
            return Ok(s);
        }
        if let Some(j) = l.jerk {
            cands.clear();
            for sym in SYMMETRIES {
                let q = sym.problem(&p);
                let start = cands.len();
                timed_third(&q, &l, j, duration, &mut cands);
                for s in &mut cands[start..] {
                    sym.turn_back(s);
                }
            }
            if let Some(s) = lasting(&cands) {
                return Ok(s);
            }
        }
        if let Some(j) = l.jerk {
            if let Some(s) = Self::blend(from, to, &l, j, duration) {
                return Ok(s);
            }
        }
        Err(no_profile(&from, &to, Some(duration)))
    }

    /// No family has a root at `t`: two laws of the families that last `t`
    /// and end at the target's velocity and acceleration, one short of the
    /// target position and one past it, blended. The limits are convex
    /// (|v|, |a|, |j| bounded) and the motion is linear in the jerk, so
    /// λ·j₁(t) + (1 − λ)·j₂(t) keeps them and ends at λ·p₁ + (1 − λ)·p₂.
    fn blend(from: BoundaryState, to: BoundaryState, l: &Limits, j: f64, t: f64) -> Option<Profile> {
        let p = Problem::new(&from, &to);
        let mut below: Option<(f64, Profile)> = None;
        let mut above: Option<(f64, Profile)> = None;
        let mut consider = |s: Option<Profile>| {
            let Some(s) = s else { return };
            if (s.duration() - t).abs() > 1e-12 * t.max(1.0) || s.segments().iter().any(|g| !(g.dt >= 0.0)) {
                return;
            }
            let trial = Trial::new(from, to, &s, true);
            if !trial.valid_but_position(l) {
                return;
            }
            let r = trial.residual();
            if r <= 0.0 && below.is_none_or(|(b, _)| r > b) {
                below = Some((r, s));
            }
            if r >= 0.0 && above.is_none_or(|(b, _)| r < b) {
                above = Some((r, s));
            }
        };
        let n = 4 * roots::GRID;
        let grid = |lo: f64, hi: f64| (0..=n).map(move |i| lo + (hi - lo) * i as f64 / n as f64);
        for vc in grid(-l.vel, l.vel) {
            consider(cruise_at(&p, l, t, vc));
        }
        for sym in SYMMETRIES {
            let q = sym.problem(&p);
            for root in [true, false] {
                for x in grid(-l.acc, q.af) {
                    consider(held_peak(&q, l, j, t, x, 0.0, root).map(|s| sym.back(&s)));
                }
                for h in grid(0.0, t) {
                    consider(held_peak(&q, l, j, t, -l.acc, h, root).map(|s| sym.back(&s)));
                }
            }
        }
        let ((r1, s1), (r2, s2)) = (below?, above?);
        let lambda = if r2 == r1 { 0.0 } else { r2 / (r2 - r1) }; // weight of s1
        let mixed = mix(&s1, &s2, lambda, t);
        let trial = Trial::new(from, to, &mixed, true);
        (trial.valid(l) && (trial.duration() - t).abs() <= 1e-12 * t.max(1.0)).then_some(mixed)
    }
}

/// Refuses a duration that is not finite and ≥ 0, or shorter than the fastest law's.
fn check_duration(duration: f64, optimal: &[Candidate]) -> Result<()> {
    if !(duration.is_finite() && duration >= 0.0) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "duration".into(),
            value: duration,
            expected: "a finite duration ≥ 0 [s]".into(),
        }));
    }
    if let Some(fast) = optimal.first() {
        if duration < fast.duration * (1.0 - 1e-12) {
            return Err(Error::Input(InputError::OutOfRange {
                what: "duration".into(),
                value: duration,
                expected: format!("at least {} s, the fastest motion between these states [s]", fast.duration),
            }));
        }
    }
    Ok(())
}

/// λ·s1 + (1 − λ)·s2 on the merged grid of their segment boundaries.
fn mix(s1: &Profile, s2: &Profile, lambda: f64, t: f64) -> Profile {
    let mut cuts: Vec<f64> = Vec::with_capacity(s1.segments().len() + s2.segments().len());
    for s in [s1, s2] {
        let mut end = 0.0;
        for g in s.segments() {
            end += g.dt;
            cuts.push(end);
        }
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() <= 1e-14 * t);
    let mut out = Profile::default();
    let mut prev = 0.0;
    for &c in &cuts {
        let mid = 0.5 * (prev + c);
        out.push(c - prev, lambda * s1.jerk_at(mid) + (1.0 - lambda) * s2.jerk_at(mid), None);
        prev = c;
    }
    out
}
