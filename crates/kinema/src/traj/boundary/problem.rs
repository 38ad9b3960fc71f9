//! The problem of one coordinate, its validated limits, and the symmetries
//! (mirror image, reversal in time) under which candidates are searched.

use super::roots::Search;
use super::{infeasible, BoundaryState};
use crate::error::{Error, InputError, Result};
use crate::traj::law::MotionLimits;

/// The limits of one problem, validated: positive and finite.
#[derive(Debug, Clone, Copy)]
pub(super) struct Limits {
    pub vel: f64,
    pub acc: f64,
    /// `None`: second order.
    pub jerk: Option<f64>,
    /// How roots are refined (the fast search or the plain reference).
    pub search: Search,
}

impl Limits {
    pub fn new(limits: &MotionLimits, search: Search) -> Result<Limits> {
        for (name, v) in [("vmax", limits.vel), ("amax", limits.acc)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::Input(InputError::OutOfRange {
                    what: name.into(),
                    value: v,
                    expected: "a positive finite number".into(),
                }));
            }
        }
        if let Some(j) = limits.jerk {
            if !(j.is_finite() && j > 0.0) {
                return Err(Error::Input(InputError::OutOfRange {
                    what: "jmax".into(),
                    value: j,
                    expected: "a positive finite number".into(),
                }));
            }
        }
        Ok(Limits { vel: limits.vel, acc: limits.acc, jerk: limits.jerk, search })
    }

    /// Refuses states no law can start or end at: non-finite values, an
    /// acceleration without a jerk limit, and a target beyond the limits (a
    /// start beyond them is braked: see [`super::brake`]).
    pub fn check_states(&self, from: &BoundaryState, to: &BoundaryState) -> Result<()> {
        for (what, s) in [("start", from), ("target", to)] {
            for (name, x) in [("position", s.p), ("velocity", s.v), ("acceleration", s.a)] {
                if !x.is_finite() {
                    return Err(Error::Input(InputError::NotFinite { what: format!("{what} {name}"), value: x }));
                }
            }
            if self.jerk.is_none() && s.a != 0.0 {
                return Err(Error::Input(InputError::MissingLimit {
                    limit: "jerk".into(),
                    option: "jmax".into(),
                    needed_by: format!(
                        "the {what} acceleration {} (without one the acceleration is a step and boundary \
                         accelerations must be 0)",
                        s.a
                    ),
                }));
            }
        }
        if to.v.abs() > self.vel * (1.0 + 1e-12) {
            return Err(Error::Input(InputError::OutOfRange {
                what: "target velocity".into(),
                value: to.v,
                expected: format!("a velocity within ±{} (vmax); no motion within the limits ends beyond it", self.vel),
            }));
        }
        match self.jerk {
            Some(j) => self.check_target_jerk_limited(to, j),
            None => Ok(()),
        }
    }

    /// A target whose acceleration, traced back in time, carries the
    /// velocity past v_max cannot be arrived at within the limits.
    fn check_target_jerk_limited(&self, to: &BoundaryState, j: f64) -> Result<()> {
        if to.a.abs() > self.acc * (1.0 + 1e-12) {
            return Err(Error::Input(InputError::OutOfRange {
                what: "target acceleration".into(),
                value: to.a,
                expected: format!("an acceleration within ±{} (amax)", self.acc),
            }));
        }
        let reach = to.v - to.a * to.a.abs() / (2.0 * j);
        if reach.abs() > self.vel * (1.0 + 1e-9) {
            return Err(infeasible(
                "vmax",
                format!(
                    "the target state (velocity {}, acceleration {}) reaches a velocity of {reach} when traced \
                     back to where the acceleration can be brought to 0 with jmax {j}, beyond vmax {}",
                    to.v, to.a, self.vel
                ),
            ));
        }
        Ok(())
    }
}

/// The boundary values of one coordinate relative to its start position,
/// possibly seen in a mirrored and/or time-reversed frame.
#[derive(Debug, Clone, Copy)]
pub(super) struct Problem {
    pub v0: f64,
    pub a0: f64,
    pub vf: f64,
    pub af: f64,
    /// Displacement p_f − p_0.
    pub dp: f64,
}

impl Problem {
    pub fn new(from: &BoundaryState, to: &BoundaryState) -> Problem {
        Problem { v0: from.v, a0: from.a, vf: to.v, af: to.a, dp: to.p - from.p }
    }

    fn mirrored(&self) -> Problem {
        Problem { v0: -self.v0, a0: -self.a0, vf: -self.vf, af: -self.af, dp: -self.dp }
    }

    /// q(t) = p(T − t): start and end swap, velocities change sign.
    fn reversed(&self) -> Problem {
        Problem { v0: -self.vf, a0: self.af, vf: -self.v0, af: self.a0, dp: -self.dp }
    }
}

/// A frame in which candidates are searched: the families are written for
/// one sign pattern, and the mirror and time reversal give the others.
#[derive(Debug, Clone, Copy)]
pub(super) struct Symmetry {
    mirror: bool,
    reverse: bool,
}

/// Identity, mirror, reversal in time, both (second-order families need
/// only the first two).
pub(super) const SYMMETRIES: [Symmetry; 4] = [
    Symmetry { mirror: false, reverse: false },
    Symmetry { mirror: true, reverse: false },
    Symmetry { mirror: false, reverse: true },
    Symmetry { mirror: true, reverse: true },
];

impl Symmetry {
    pub fn problem(self, p: &Problem) -> Problem {
        let p = if self.reverse { p.reversed() } else { *p };
        if self.mirror {
            p.mirrored()
        } else {
            p
        }
    }

    /// A profile found for the transformed problem, back in the original frame.
    pub fn back(self, s: &super::profile::Profile) -> super::profile::Profile {
        let mut s = *s;
        self.turn_back(&mut s);
        s
    }

    /// [`Symmetry::back`] in place.
    pub fn turn_back(self, s: &mut super::profile::Profile) {
        if self.mirror {
            s.mirror();
        }
        if self.reverse {
            s.reverse();
        }
    }
}
