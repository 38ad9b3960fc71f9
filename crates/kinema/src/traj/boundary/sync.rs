//! Synchronising several coordinates: the smallest common duration at
//! which every coordinate has a law, stepping over blocked intervals.

use super::problem::Limits;
use super::roots::Search;
use super::{check_min, infeasible, no_profile, BoundaryLaw, BoundaryState};
use crate::error::{Error, InputError, Result};
use crate::traj::law::MotionLimits;

/// The smallest duration ≥ `at_least` \[s\] at which every coordinate has a
/// law, with the laws: each coordinate `i` from `from[i]` to `to[i]` within
/// `limits[i]`. Starts from the slowest coordinate's fastest duration and,
/// where that duration is blocked for another coordinate, moves on to the
/// next critical duration that every coordinate admits.
///
/// Errors: slices of different lengths; the errors of [`BoundaryLaw::fastest`]
/// for a coordinate (its index in `what`); no common duration found.
pub fn sync_duration(
    from: &[BoundaryState],
    to: &[BoundaryState],
    limits: &[MotionLimits],
    at_least: f64,
) -> Result<(f64, Vec<BoundaryLaw>)> {
    sync_by(from, to, limits, at_least, Search::Fast)
}

/// [`sync_duration`] with the given root search.
pub(super) fn sync_by(
    from: &[BoundaryState],
    to: &[BoundaryState],
    limits: &[MotionLimits],
    at_least: f64,
    search: Search,
) -> Result<(f64, Vec<BoundaryLaw>)> {
    for (what, got) in [("to", to.len()), ("limits", limits.len())] {
        if got != from.len() {
            return Err(Error::Input(InputError::WrongLength {
                what: what.into(),
                got,
                expected: from.len(),
                of: "one per start state".into(),
            }));
        }
    }
    let mut critical = Vec::new();
    let mut t0 = at_least.max(0.0);
    let mut fastest = Vec::with_capacity(from.len());
    let mut optimal = Vec::with_capacity(from.len());
    let mut lims = Vec::with_capacity(from.len());
    for i in 0..from.len() {
        let l = Limits::new(&limits[i], search)?;
        l.check_states(&from[i], &to[i])?;
        let (brake, cands) = BoundaryLaw::braked_candidates(from[i], to[i], &l);
        let first = cands.first().ok_or_else(|| no_profile(&brake.braked, &to[i], None))?;
        let law = BoundaryLaw::after(&brake, from[i], to[i], &first.profile, l.jerk.is_some());
        check_min(law.duration)?;
        t0 = t0.max(law.duration);
        fastest.push(law);
        critical.extend(cands.iter().map(|c| brake.duration() + c.duration));
        optimal.push((brake, cands));
        lims.push(l);
    }
    let mut tries: Vec<f64> = critical.into_iter().filter(|&t| t > t0).collect();
    tries.push(t0);
    tries.sort_by(f64::total_cmp);
    tries.dedup();
    let mut last_err = None;
    // The laws of one try, replaced in place by the next try's.
    let mut laws = fastest.clone();
    'outer: for &t in &tries {
        for i in 0..from.len() {
            if fastest[i].duration == t {
                laws[i] = fastest[i];
                continue;
            }
            let (brake, optimal_i) = &optimal[i];
            match BoundaryLaw::timed_after(brake, from[i], to[i], &lims[i], t, optimal_i) {
                Ok(l) => laws[i] = l,
                Err(e) => {
                    last_err = Some(e);
                    continue 'outer;
                }
            }
        }
        return Ok((t, laws));
    }
    Err(last_err.unwrap_or_else(|| infeasible("duration", "no duration suits every coordinate".into())))
}
