//! The plain reference: the same families as [`BoundaryLaw::fastest`] and
//! friends, their roots isolated on a grid and refined by plain bisection
//! (and golden-section search for pairs of roots between grid points)
//! wherever the fast search takes shortcuts. Slow and simple; the fast
//! search is tested against it.

use super::roots::Search;
use super::{sync, BoundaryLaw, BoundaryState};
use crate::error::Result;
use crate::traj::law::MotionLimits;

/// [`BoundaryLaw::fastest`] with the reference search.
pub fn fastest(from: BoundaryState, to: BoundaryState, limits: &MotionLimits) -> Result<BoundaryLaw> {
    BoundaryLaw::fastest_by(from, to, limits, Search::Reference)
}

/// [`BoundaryLaw::critical_durations`] with the reference search.
pub fn critical_durations(from: BoundaryState, to: BoundaryState, limits: &MotionLimits) -> Result<Vec<f64>> {
    BoundaryLaw::critical_durations_by(from, to, limits, Search::Reference)
}

/// [`BoundaryLaw::with_duration`] with the reference search.
pub fn with_duration(
    from: BoundaryState,
    to: BoundaryState,
    limits: &MotionLimits,
    duration: f64,
) -> Result<BoundaryLaw> {
    BoundaryLaw::with_duration_by(from, to, limits, duration, Search::Reference)
}

/// [`super::sync_duration`] with the reference search.
pub fn sync_duration(
    from: &[BoundaryState],
    to: &[BoundaryState],
    limits: &[MotionLimits],
    at_least: f64,
) -> Result<(f64, Vec<BoundaryLaw>)> {
    sync::sync_by(from, to, limits, at_least, Search::Reference)
}
