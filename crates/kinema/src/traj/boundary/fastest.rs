//! Step 1: every locally time-optimal law between two states, the
//! candidates of each frame rebuilt and re-checked. The fastest is the
//! time-optimal law; the others bound the blocked durations.

use super::fastest_third::fastest_third;
use super::problem::{Limits, Problem, SYMMETRIES};
use super::profile::{Candidate, Profile};
use super::second::fastest_second;
use super::{BoundaryLaw, BoundaryState};

impl BoundaryLaw {
    /// Every locally time-optimal profile (the candidates that survive the
    /// re-check), fastest first.
    pub(super) fn candidates(from: BoundaryState, to: BoundaryState, l: &Limits) -> Vec<Candidate> {
        let p = Problem::new(&from, &to);
        let mut cands = Vec::with_capacity(16);
        for sym in &SYMMETRIES[..if l.jerk.is_some() { 4 } else { 2 }] {
            let q = sym.problem(&p);
            let start = cands.len();
            match l.jerk {
                Some(j) => fastest_third(&q, l, j, &mut cands),
                None => fastest_second(&q, l, &mut cands),
            }
            for s in &mut cands[start..] {
                sym.turn_back(s);
            }
        }
        let mut laws = Self::from_candidates(from, to, l, &cands);
        if from == to {
            laws.insert(0, Candidate { duration: 0.0, profile: Profile::default() });
        }
        laws
    }
}
