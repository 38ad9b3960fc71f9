//! Time-optimal one-coordinate motions between arbitrary boundary states
//! (position, velocity, acceleration), the building block of PTP motions
//! that are chained without stopping.
//!
//! A [`BoundaryLaw`] moves one coordinate from a [`BoundaryState`]
//! (p₀, v₀, a₀) to another (p_f, v_f, a_f) within |v| ≤ v_max, |a| ≤ a_max
//! and, when a jerk limit is given, |j| ≤ j_max:
//! - **third order** (jerk limit given): up to seven phases of constant jerk
//!   +j_max, 0 or −j_max — the structure of Ruckig (Berscheid & Kröger 2021);
//! - **second order** (no jerk limit): up to three phases of constant
//!   acceleration ±a_max or 0; the boundary accelerations must then be 0.
//!
//! [`BoundaryLaw::fastest`] is the time-optimal law. Its candidates are the
//! profiles whose acceleration rises, falls and rises again (or the mirror
//! image), each phase either a jerk ramp or a hold at a limit — +a_max,
//! −a_max or a cruise at ±v_max. Each family is reduced to one unknown
//! (the acceleration at the valley, or the length of a hold) whose end
//! position is a polynomial of degree ≤ 4 (after squaring out the one
//! square root), solved in closed form (`valley`, `poly`); the reference
//! instead isolates the roots on a grid and refines them by bisection.
//! Every candidate is then
//! rebuilt from the start state and re-checked (end state within 1e-9
//! relative, no limit exceeded by more than 1e-9 relative), and the fastest
//! survivor is returned.
//!
//! [`BoundaryLaw::with_duration`] moves between the same states in a given,
//! longer time (what synchronised PTP needs). Its families hold the velocity
//! at some v_c (a cruise with zero acceleration between two fastest
//! velocity changes) or hold the acceleration at some level below a_max;
//! (the cruise velocities that fit are found from the shape of the
//! changes' durations, a few evaluations instead of a scan);
//! where none of them has a root, two of their laws lasting that long, one
//! short of the target position and one past it, are blended (the limits
//! are convex and the motion is linear in the jerk). A duration can be
//! infeasible although a shorter one is feasible (a start
//! velocity towards a close target leaves no profile for some durations:
//! Ruckig's "blocked intervals"); [`BoundaryLaw::critical_durations`] lists
//! the durations where feasibility may change, and [`sync_duration`] picks
//! the smallest duration at which every coordinate has a law.
//!
//! The search is laid out as Ruckig lays out its steps: `brake` the
//! pre-phase for a start beyond the limits, `profile`
//! the segments of constant jerk and their integration, `roots` the
//! one-unknown root search on a grid, `poly` the real roots of a
//! polynomial, `fastest_third`, `valley` and `second` the time-optimal
//! families (step 1), `timed_third`, `cruise` and `second` the families of
//! a prescribed duration (step 2), `sync` the synchronisation of several
//! coordinates.
//!
//! A start state beyond the limits (|v₀| > v_max, |a₀| > a_max, or an
//! acceleration that carries the velocity past v_max whatever the jerk:
//! |v₀ + a₀|a₀|/(2 j_max)| > v_max) is first braked into them at full jerk
//! (`brake`), as Ruckig does; the law's duration includes the brake. A
//! target beyond the limits is refused with an error naming the limit: no
//! motion within them can arrive there.

use self::brake::Brake;
use self::problem::Limits;
use self::profile::{peaks_of, Candidate, Phase, Profile, MAX_SEGMENTS};
use self::roots::Search;
use super::law::{MotionLimits, MIN_DURATION};
use crate::error::{Error, InputError, Result};

mod brake;
mod cruise;
mod fastest;
mod fastest_third;
mod poly;
mod problem;
mod profile;
pub mod reference;
mod roots;
mod second;
mod sync;
mod timed;
mod timed_third;
mod valley;
mod velocity;

pub use sync::sync_duration;

/// Position \[unit\], velocity \[unit/s\] and acceleration \[unit/s²\] of one coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BoundaryState {
    /// Position.
    pub p: f64,
    /// Velocity.
    pub v: f64,
    /// Acceleration.
    pub a: f64,
}

impl BoundaryState {
    /// A state at `p` with velocity `v` and acceleration `a`.
    pub fn new(p: f64, v: f64, a: f64) -> Self {
        BoundaryState { p, v, a }
    }

    /// At rest at `p`.
    pub fn rest(p: f64) -> Self {
        BoundaryState { p, v: 0.0, a: 0.0 }
    }
}

/// A motion of one coordinate between two boundary states: phases of
/// constant jerk (third order) or constant acceleration (second order).
///
/// # Examples
/// ```
/// use kinema::traj::{BoundaryLaw, BoundaryState, MotionLimits};
/// // Arrive at 1 rad still moving at 0.5 rad/s, starting at rest.
/// let lim = MotionLimits::with_jerk(1.0, 2.0, 10.0);
/// let law = BoundaryLaw::fastest(BoundaryState::rest(0.0), BoundaryState::new(1.0, 0.5, 0.0), &lim)?;
/// let end = law.at(law.duration());
/// assert!((end.p - 1.0).abs() < 1e-9 && (end.v - 0.5).abs() < 1e-9);
/// // The same states in a longer, prescribed time (to synchronise joints).
/// let slow = BoundaryLaw::with_duration(law.from(), law.to(), &lim, 3.0)?;
/// assert!((slow.duration() - 3.0).abs() < 1e-12);
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryLaw {
    from: BoundaryState,
    to: BoundaryState,
    phases: [Phase; MAX_SEGMENTS],
    n: usize,
    duration: f64,
    /// The first `braking` seconds bring a start beyond the limits within them.
    braking: f64,
    jerk_limited: bool,
}

impl BoundaryLaw {
    /// The time-optimal law from `from` to `to` within `limits` (a jerk
    /// limit makes it third order; without one it is second order and the
    /// boundary accelerations must be 0). A start equal to the target (also
    /// a moving one) gives a law of duration 0: it is already there.
    ///
    /// Rest to rest, the duration equals [`TimeLaw::from_limits`]'s trapezoid
    /// or S-curve over the same distance. Errors: a limit that is not a
    /// positive finite number; a non-finite state; a state no law can
    /// respect (see the module documentation); a duration below
    /// [`MIN_DURATION`]; no candidate passing the re-check (not expected: it
    /// would be a bug, reported rather than returned).
    ///
    /// [`TimeLaw::from_limits`]: super::TimeLaw::from_limits
    pub fn fastest(from: BoundaryState, to: BoundaryState, limits: &MotionLimits) -> Result<BoundaryLaw> {
        Self::fastest_by(from, to, limits, Search::Fast)
    }

    fn fastest_by(
        from: BoundaryState,
        to: BoundaryState,
        limits: &MotionLimits,
        search: Search,
    ) -> Result<BoundaryLaw> {
        let l = Limits::new(limits, search)?;
        l.check_states(&from, &to)?;
        let (brake, optimal) = Self::braked_candidates(from, to, &l);
        let fastest = optimal.first().ok_or_else(|| no_profile(&brake.braked, &to, None))?;
        let law = Self::after(&brake, from, to, &fastest.profile, l.jerk.is_some());
        check_min(law.duration)?;
        Ok(law)
    }

    /// The brake of the start state, and every locally time-optimal
    /// profile from the braked state, fastest first.
    fn braked_candidates(from: BoundaryState, to: BoundaryState, l: &Limits) -> (Brake, Vec<Candidate>) {
        let brake = Brake::of(&from, l);
        let optimal = Self::candidates(brake.braked, to, l);
        (brake, optimal)
    }

    /// The law of `profile` from the braked state, preceded by `brake` from `from`.
    fn after(brake: &Brake, from: BoundaryState, to: BoundaryState, profile: &Profile, jerk_limited: bool) -> Self {
        if brake.profile.segments().is_empty() {
            return Self::build(brake.braked, to, profile, jerk_limited);
        }
        let mut law = Self::build(from, to, &brake.profile, jerk_limited);
        law.braking = law.duration;
        law.append(profile, brake.braked);
        law
    }

    /// The durations at which the set of feasible durations may change:
    /// the durations of every locally time-optimal law, fastest first. The
    /// first is [`BoundaryLaw::fastest`]'s; a duration between two listed
    /// ones is feasible either throughout or nowhere.
    pub fn critical_durations(from: BoundaryState, to: BoundaryState, limits: &MotionLimits) -> Result<Vec<f64>> {
        Self::critical_durations_by(from, to, limits, Search::Fast)
    }

    fn critical_durations_by(
        from: BoundaryState,
        to: BoundaryState,
        limits: &MotionLimits,
        search: Search,
    ) -> Result<Vec<f64>> {
        let l = Limits::new(limits, search)?;
        l.check_states(&from, &to)?;
        let (brake, optimal) = Self::braked_candidates(from, to, &l);
        let mut d: Vec<f64> = optimal.iter().map(|c| brake.duration() + c.duration).collect();
        d.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * b.abs().max(1e-300));
        Ok(d)
    }

    /// A law from `from` to `to` within `limits` lasting exactly `duration`
    /// \[s\] (at least the fastest law's). Errors: as [`BoundaryLaw::fastest`];
    /// a duration shorter than the fastest; a duration inside a blocked
    /// interval (no law lasts exactly that long: see the module documentation).
    pub fn with_duration(
        from: BoundaryState,
        to: BoundaryState,
        limits: &MotionLimits,
        duration: f64,
    ) -> Result<BoundaryLaw> {
        Self::with_duration_by(from, to, limits, duration, Search::Fast)
    }

    fn with_duration_by(
        from: BoundaryState,
        to: BoundaryState,
        limits: &MotionLimits,
        duration: f64,
        search: Search,
    ) -> Result<BoundaryLaw> {
        let l = Limits::new(limits, search)?;
        l.check_states(&from, &to)?;
        let (brake, optimal) = Self::braked_candidates(from, to, &l);
        Self::timed_after(&brake, from, to, &l, duration, &optimal)
    }

    /// A law lasting `duration` \[s\] in all: `brake`, then a law from the
    /// braked state (`optimal` its locally time-optimal laws).
    fn timed_after(
        brake: &Brake,
        from: BoundaryState,
        to: BoundaryState,
        l: &Limits,
        duration: f64,
        optimal: &[Candidate],
    ) -> Result<BoundaryLaw> {
        let tb = brake.duration();
        if let Some(fast) = optimal.first() {
            if tb > 0.0 && duration < (tb + fast.duration) * (1.0 - 1e-12) {
                return Err(Error::Input(InputError::OutOfRange {
                    what: "duration".into(),
                    value: duration,
                    expected: format!(
                        "at least {} s, the fastest motion between these states (braking for {tb} s first) [s]",
                        tb + fast.duration
                    ),
                }));
            }
        }
        let rest = if tb > 0.0 { (duration - tb).max(optimal.first().map_or(0.0, |c| c.duration)) } else { duration };
        let profile = Self::timed(brake.braked, to, l, rest, optimal)?;
        Ok(Self::after(brake, from, to, &profile, l.jerk.is_some()))
    }

    /// The start state.
    pub fn from(&self) -> BoundaryState {
        self.from
    }

    /// The target state.
    pub fn to(&self) -> BoundaryState {
        self.to
    }

    /// Duration \[s\].
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// How long the law brakes a start state beyond the limits back within
    /// them \[s\] (0 for a start within them). Only during this first part
    /// may |v| and |a| exceed the limits; the jerk keeps its limit throughout.
    pub fn braking_duration(&self) -> f64 {
        self.braking
    }

    /// Whether the law is jerk-limited (third order).
    pub fn jerk_limited(&self) -> bool {
        self.jerk_limited
    }

    /// Durations of the phases \[s\], in order (zero-length phases left out).
    pub fn phase_times(&self) -> Vec<f64> {
        self.phases[..self.n].iter().map(|p| p.dt).collect()
    }

    /// Jerk of each phase \[unit/s³\] (0 in every phase of a second-order law,
    /// whose acceleration steps between phases).
    pub fn phase_jerks(&self) -> Vec<f64> {
        self.phases[..self.n].iter().map(|p| p.j).collect()
    }

    /// The state at time `t` \[s\]: the start state before 0; from the
    /// duration on, the target state (its position advanced by the target
    /// velocity and acceleration, so that a chained motion continues it).
    #[inline]
    pub fn at(&self, t: f64) -> BoundaryState {
        if !(t > 0.0) {
            return self.from;
        }
        if t >= self.duration || self.n == 0 {
            return self.to;
        }
        let i = self.phases[..self.n].iter().rposition(|p| p.t0 <= t).unwrap_or(0);
        let u = (t - self.phases[i].t0).clamp(0.0, self.phases[i].dt);
        self.phases[i].at(u)
    }

    /// Jerk at time `t` (0 outside the law).
    pub fn jerk_at(&self, t: f64) -> f64 {
        if !(t > 0.0) || t >= self.duration || self.n == 0 {
            return 0.0;
        }
        let i = self.phases[..self.n].iter().rposition(|p| p.t0 <= t).unwrap_or(0);
        self.phases[i].j
    }

    /// The largest |v|, |a| and |j| over the law, in closed form (velocity
    /// extrema inside a phase where the acceleration crosses 0). |j| is
    /// infinite for a second-order law with an acceleration step.
    pub fn peaks(&self) -> (f64, f64, f64) {
        peaks_of(&self.from, &self.to, self.jerk_limited, self.phases[..self.n].iter().copied())
    }
}

/// Refuses a motion shorter than the shortest a motion may last.
fn check_min(duration: f64) -> Result<()> {
    if duration > 0.0 && duration < MIN_DURATION {
        return Err(infeasible(
            "duration",
            format!("the motion would last {duration:e} s, shorter than the {MIN_DURATION:e} s a motion may last"),
        ));
    }
    Ok(())
}

/// The error for states (and a duration) no law connects.
fn no_profile(from: &BoundaryState, to: &BoundaryState, duration: Option<f64>) -> Error {
    let when = duration.map_or(String::new(), |t| format!(" lasting exactly {t} s"));
    infeasible(
        "duration",
        format!(
            "no motion{when} from (p {}, v {}, a {}) to (p {}, v {}, a {}) within the limits \
             (a blocked duration: a longer one may be feasible)",
            from.p, from.v, from.a, to.p, to.v, to.a
        ),
    )
}

/// An [`Error::Infeasible`] about `what`.
fn infeasible(what: &str, reason: String) -> Error {
    Error::Infeasible { what: what.into(), reason }
}
