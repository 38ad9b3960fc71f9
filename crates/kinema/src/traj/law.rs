//! Time laws: a normalised path parameter s(t) from 0 to 1 with its
//! derivatives ṡ, s̈ and s⃛ (seed 004 §VIII-A).
//!
//! A [`TimeLaw`] is built either from a duration ([`TimeLaw::from_duration`])
//! or from kinematic limits and the distance to cover
//! ([`TimeLaw::from_limits`]); in the second case it is the fastest law of its
//! family that respects the limits, and its derivatives never exceed them
//! (beyond floating-point rounding, ~1e-15 relative).
//!
//! Families ([`Profile`]):
//! - **trapezoid** — constant acceleration, cruise, constant deceleration
//!   (seed 004 eq. 32–37). When the distance is too short to reach v_max
//!   (D < v_max²/a_max) the cruise vanishes and the profile is the
//!   time-optimal triangle, τ = √(D/a_max), T = 2τ. Seed 004 (text after
//!   eq. 37) instead keeps τ = √(Δp/a_max) and sets the cruise end to
//!   v_max/a_max "to keep the profile trapezoidal": that respects the limits
//!   but lasts v_max/a_max + √(Δp/a_max) instead of 2√(Δp/a_max) — slower for
//!   no benefit, so it is not used here (the test `seed_short_move_recipe_is_slower`
//!   pins the comparison).
//! - **scurve** — jerk-limited double-S (the future work of seed 004 §XI):
//!   seven phases of constant jerk ±j_max / 0, time-optimal for rest-to-rest
//!   moves under v, a and j limits. Cases: v_max reached or not, a_max reached
//!   or not (see [`TimeLaw::from_limits`]).
//! - **cubic** — s = 3τ² − 2τ³ (τ = t/T), used by seed 003 for the XY joints;
//!   peak ṡ = 1.5/T, s̈ jumps to ±6/T² at the ends (unbounded jerk).
//! - **quintic** — s = 10τ³ − 15τ⁴ + 6τ⁵: zero velocity and acceleration at
//!   both ends; peak ṡ = 15/(8T), s̈ = 10/(√3·T²), s⃛ = 60/T³.
//! - **linear** — s = t/T (seed 003 for Z and θ): constant velocity; the
//!   velocity jumps at both ends (unbounded acceleration).

use crate::error::{Error, InputError, Result};

/// The family of a time law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Profile {
    /// Trapezoidal velocity (bounded v and a; jerk unbounded at the phase changes).
    Trapezoid,
    /// Jerk-limited double-S (bounded v, a and j).
    SCurve,
    /// Cubic polynomial (rest to rest; acceleration jumps at the ends).
    Cubic,
    /// Quintic polynomial (rest to rest with zero end accelerations).
    Quintic,
    /// Constant velocity (velocity jumps at the ends).
    Linear,
}

impl Profile {
    /// Every profile, in the order of the documentation.
    pub const ALL: [Profile; 5] =
        [Profile::Trapezoid, Profile::SCurve, Profile::Cubic, Profile::Quintic, Profile::Linear];

    /// The name used on the command line and in programs.
    pub fn name(self) -> &'static str {
        match self {
            Profile::Trapezoid => "trapezoid",
            Profile::SCurve => "scurve",
            Profile::Cubic => "cubic",
            Profile::Quintic => "quintic",
            Profile::Linear => "linear",
        }
    }

    /// Whether the law's velocity starts and ends at zero.
    pub fn rest_to_rest(self) -> bool {
        self != Profile::Linear
    }
}

/// Kinematic limits of a motion along one coordinate (a joint or a path length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionLimits {
    /// Largest |velocity| \[unit/s\].
    pub vel: f64,
    /// Largest |acceleration| \[unit/s²\] (ignored by [`Profile::Linear`]).
    pub acc: f64,
    /// Largest |jerk| \[unit/s³\]; needed by [`Profile::SCurve`] only.
    pub jerk: Option<f64>,
}

impl MotionLimits {
    /// Velocity and acceleration limits.
    pub fn new(vel: f64, acc: f64) -> Self {
        MotionLimits { vel, acc, jerk: None }
    }

    /// Velocity, acceleration and jerk limits.
    pub fn with_jerk(vel: f64, acc: f64, jerk: f64) -> Self {
        MotionLimits { vel, acc, jerk: Some(jerk) }
    }
}

/// The value of a time law at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LawState {
    /// s ∈ \[0, 1\].
    pub s: f64,
    /// ṡ \[1/s\].
    pub sd: f64,
    /// s̈ \[1/s²\].
    pub sdd: f64,
    /// s⃛ \[1/s³\] (0 where a profile's jerk is a Dirac impulse, e.g. at the trapezoid's phase changes).
    pub sddd: f64,
}

/// One phase of constant jerk: s(t) = s0 + v0·u + a0·u²/2 + j·u³/6, u = t − t0.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Phase {
    t0: f64,
    s0: f64,
    v0: f64,
    a0: f64,
    j: f64,
}

impl Phase {
    /// The phase `u` seconds after its start. Callers keep `u` within the
    /// phase's duration, so every derivative stays between its values at the
    /// phase's ends (each is monotone or, for ṡ under constant jerk, peaks
    /// only where s̈ = 0, which is a phase end in every profile built here).
    #[inline]
    fn at_offset(&self, u: f64) -> LawState {
        LawState {
            s: self.s0 + u * (self.v0 + u * (self.a0 / 2.0 + u * self.j / 6.0)),
            sd: self.v0 + u * (self.a0 + u * self.j / 2.0),
            sdd: self.a0 + u * self.j,
            sddd: self.j,
        }
    }
}

/// Most phases a law has (the double-S).
const MAX_PHASES: usize = 7;

/// A normalised time law s(t), t ∈ \[0, T\], s(0) = 0, s(T) = 1.
///
/// # Examples
/// ```
/// use kinema::traj::{MotionLimits, Profile, TimeLaw};
/// // 1 rad with v_max = 0.5 rad/s, a_max = 1 rad/s²: 0.5 s accelerating,
/// // 1.5 s cruising, 0.5 s braking.
/// let law = TimeLaw::from_limits(Profile::Trapezoid, 1.0, &MotionLimits::new(0.5, 1.0))?;
/// assert!((law.duration() - 2.5).abs() < 1e-12);
/// assert_eq!(law.phase_times().len(), 3);
/// let mid = law.at(1.25);
/// assert!((mid.s - 0.5).abs() < 1e-12 && (mid.sd - 0.5).abs() < 1e-12); // 0.5 rad/s over 1 rad
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeLaw {
    profile: Profile,
    duration: f64,
    /// Piecewise-cubic phases (all profiles but the quintic).
    phases: [Phase; MAX_PHASES],
    /// Durations of the phases (also for the quintic: one phase).
    phase_times: [f64; MAX_PHASES],
    n: usize,
}

fn check_positive(what: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::Input(InputError::OutOfRange {
            what: what.into(),
            value: v,
            expected: "a positive finite number".into(),
        }))
    }
}

/// An [`Error::Infeasible`] about `what`.
fn infeasible(what: &str, reason: String) -> Error {
    Error::Infeasible { what: what.into(), reason }
}

/// The shortest motion \[s\] a law may last: trajectory times are written
/// with nine decimals, so a shorter motion would end at its own start time.
pub const MIN_DURATION: f64 = 1e-9;

/// The shortest phase of a law, relative to its duration: at 1e-12 a phase
/// boundary is still known to 2·10⁻⁴ of the phase.
const PHASE_RESOLUTION: f64 = 1e-12;

fn check_duration(duration: f64) -> Result<()> {
    if !duration.is_finite() {
        return Err(Error::Infeasible {
            what: "duration".into(),
            reason: format!("the limits give a duration of {duration} s, which overflows"),
        });
    }
    if duration < MIN_DURATION {
        return Err(infeasible(
            "duration",
            format!(
                "the limits give a duration of {duration:e} s, shorter than the {MIN_DURATION:e} s a motion may last"
            ),
        ));
    }
    Ok(())
}

impl TimeLaw {
    /// The fastest law of `profile` that covers `distance` (≥ 0, in the unit
    /// of the limits) within `limits`. The law is normalised: the motion is
    /// `distance · s(t)`, so its velocity is `distance · ṡ(t)` and so on.
    ///
    /// Trapezoid: T = D/v + v/a when D ≥ v²/a, else the triangle T = 2√(D/a).
    /// S-curve (rest to rest, Biagiotti–Melchiorri case analysis, derived from
    /// the phase structure j·T_j = a_lim, v_lim = a_lim·(T_a − T_j),
    /// D = v_lim·(T_a + T_v)):
    /// - v_max reached (T_v = D/v − T_a ≥ 0) with T_j = a/j, T_a = T_j + v/a when
    ///   v·j ≥ a², else T_j = √(v/j), T_a = 2·T_j;
    /// - otherwise T_v = 0 and, with a_max reached, T_j = a/j and
    ///   T_a = (T_j + √(T_j² + 4D/a))/2 if that is ≥ 2·T_j; else
    ///   T_j = ∛(D/(2j)), T_a = 2·T_j;
    /// - T = 2·T_a + T_v.
    ///
    /// Cubic: T = max(1.5·D/v, √(6·D/a)); quintic: T = max(15·D/(8v), √(10·D/(√3·a)), ∛(60·D/j));
    /// linear: T = D/v.
    ///
    /// A distance of 0 gives a law of duration 0. Errors: a negative or
    /// non-finite distance; a limit that is not a positive finite number; a
    /// jerk limit missing for the S-curve; limits so extreme that the duration
    /// overflows, is shorter than [`MIN_DURATION`], or rounding makes the law
    /// break a limit.
    pub fn from_limits(profile: Profile, distance: f64, limits: &MotionLimits) -> Result<TimeLaw> {
        if !(distance.is_finite() && distance >= 0.0) {
            return Err(Error::Input(InputError::OutOfRange {
                what: "distance".into(),
                value: distance,
                expected: "a finite number ≥ 0".into(),
            }));
        }
        check_positive("vmax", limits.vel)?;
        if profile != Profile::Linear {
            check_positive("amax", limits.acc)?;
        }
        let jerk = match (profile, limits.jerk) {
            (Profile::SCurve, None) => {
                return Err(Error::Input(InputError::MissingLimit {
                    limit: "jerk".into(),
                    option: "jmax".into(),
                    needed_by: "the scurve profile".into(),
                }));
            }
            (_, Some(j)) => {
                check_positive("jmax", j)?;
                Some(j)
            }
            (_, None) => None,
        };
        if distance == 0.0 {
            return Ok(TimeLaw::still(profile));
        }
        let (d, v, a) = (distance, limits.vel, limits.acc);
        let law = match profile {
            Profile::Trapezoid => {
                let (ta, tv) = if d * a >= v * v { (v / a, d / v - v / a) } else { ((d / a).sqrt(), 0.0) };
                Self::trapezoid(ta, tv, a / d)
            }
            Profile::SCurve => {
                let j = jerk.expect("checked above");
                let (tj, ta, tv) = scurve_times(d, v, a, j);
                Self::scurve(tj, ta, tv, j / d)
            }
            Profile::Cubic => Self::polynomial(Profile::Cubic, (1.5 * d / v).max((6.0 * d / a).sqrt())),
            Profile::Quintic => {
                let mut t = (15.0 * d / (8.0 * v)).max((10.0 * d / (3f64.sqrt() * a)).sqrt());
                if let Some(j) = jerk {
                    t = t.max((60.0 * d / j).cbrt());
                }
                Self::polynomial(Profile::Quintic, t)
            }
            Profile::Linear => Self::polynomial(Profile::Linear, d / v),
        };
        law.checked_against(distance, limits)
    }

    /// `self` if it is a usable law for `distance` within `limits`: at extreme
    /// limits (1e100, 1e-300) the closed forms above overflow, lose the motion
    /// to rounding or break the limits they were built from, and such a law is
    /// refused rather than returned.
    fn checked_against(self, distance: f64, limits: &MotionLimits) -> Result<TimeLaw> {
        check_duration(self.duration)?;
        // A phase this much shorter than the motion keeps too few digits of
        // its own once added to the others' times (at 1e308 m it vanishes).
        // Below MIN_DURATION a phase is the rounding residue of one that is
        // zero (a cruise of 5e-17 s) and changes nothing.
        let lost =
            self.phase_times().iter().copied().find(|&t| t >= MIN_DURATION && t < self.duration * PHASE_RESOLUTION);
        if let Some(t) = lost {
            return Err(infeasible(
                "distance",
                format!(
                    "these limits are too extreme: a phase of {t:e} s in a motion of {:e} s is lost to rounding \
                     (phases must last at least {PHASE_RESOLUTION:e} of the motion)",
                    self.duration
                ),
            ));
        }
        let peaks = self.peaks();
        let mut reached = vec![("velocity", "vmax", distance * peaks.sd, limits.vel)];
        if self.profile != Profile::Linear {
            reached.push(("acceleration", "amax", distance * peaks.sdd, limits.acc));
        }
        if let (Some(j), Profile::SCurve | Profile::Quintic) = (limits.jerk, self.profile) {
            reached.push(("jerk", "jmax", distance * peaks.sddd, j));
        }
        for (quantity, name, peak, limit) in reached {
            if !(peak <= limit * (1.0 + 1e-9)) {
                return Err(infeasible(
                    name,
                    format!(
                        "these limits are too extreme: rounding gives a peak {quantity} \
                         of {peak:e} against {name} {limit:e}"
                    ),
                ));
            }
        }
        Ok(self)
    }

    /// A law of `profile` lasting `duration` \[s\] (finite, ≥ [`MIN_DURATION`]). The trapezoid
    /// accelerates for T/3, cruises for T/3 and brakes for T/3; the S-curve
    /// has the same thirds, each acceleration third split into equal parts
    /// of rising, constant and falling acceleration.
    pub fn from_duration(profile: Profile, duration: f64) -> Result<TimeLaw> {
        check_positive("duration", duration)?;
        check_duration(duration)?;
        Ok(match profile {
            Profile::Trapezoid => {
                let ta = duration / 3.0;
                // D = 1 = v·(T − T_a) with v = a·T_a.
                Self::trapezoid(ta, ta, 1.0 / (ta * (duration - ta)))
            }
            Profile::SCurve => {
                let (ta, tj) = (duration / 3.0, duration / 9.0);
                // D = 1 = v_lim·(T_a + T_v), v_lim = j·T_j·(T_a − T_j).
                let j = 1.0 / (tj * (ta - tj) * (ta + ta));
                Self::scurve(tj, ta, ta, j)
            }
            p => Self::polynomial(p, duration),
        })
    }

    /// The same path slowed down to last `duration` \[s\] (≥ the current
    /// duration): s(t·T/T′). Velocity, acceleration and jerk shrink by the
    /// factors k, k², k³ with k = T/T′, so limits that held still hold.
    pub fn stretched_to(&self, duration: f64) -> Result<TimeLaw> {
        if !(duration.is_finite() && duration >= self.duration) {
            return Err(Error::Input(InputError::OutOfRange {
                what: "duration".into(),
                value: duration,
                expected: format!("at least the law's own duration, {} s (a law is only stretched)", self.duration),
            }));
        }
        if self.duration == 0.0 || duration == self.duration {
            return Ok(*self);
        }
        let k = self.duration / duration;
        let mut out = *self;
        out.duration = duration;
        for i in 0..self.n {
            let p = self.phases[i];
            out.phases[i] = Phase { t0: p.t0 / k, s0: p.s0, v0: p.v0 * k, a0: p.a0 * k * k, j: p.j * k * k * k };
            out.phase_times[i] = self.phase_times[i] / k;
        }
        Ok(out)
    }

    fn still(profile: Profile) -> TimeLaw {
        TimeLaw { profile, duration: 0.0, phases: [Phase::default(); MAX_PHASES], phase_times: [0.0; MAX_PHASES], n: 0 }
    }

    /// Builds the phases from (duration, acceleration at the start or None for
    /// continuous, jerk) in normalised units.
    fn build(profile: Profile, spec: &[(f64, Option<f64>, f64)]) -> TimeLaw {
        let mut law = Self::still(profile);
        let (mut t, mut s, mut v, mut a) = (0.0, 0.0, 0.0, 0.0);
        for &(dt, a_start, j) in spec {
            if dt <= 0.0 {
                continue;
            }
            if let Some(a0) = a_start {
                a = a0;
            }
            let p = Phase { t0: t, s0: s, v0: v, a0: a, j };
            // The end state from the phase's own clock: t + dt − t would lose
            // the digits of a short phase late in a long law.
            let end = p.at_offset(dt);
            law.phases[law.n] = p;
            law.phase_times[law.n] = dt;
            law.n += 1;
            t += dt;
            (s, v, a) = (end.s, end.sd, end.sdd);
        }
        law.duration = t;
        law
    }

    /// Trapezoid with acceleration time `ta`, cruise `tv`, normalised acceleration `acc`.
    fn trapezoid(ta: f64, tv: f64, acc: f64) -> TimeLaw {
        Self::build(Profile::Trapezoid, &[(ta, Some(acc), 0.0), (tv, Some(0.0), 0.0), (ta, Some(-acc), 0.0)])
    }

    /// Double-S with jerk time `tj`, acceleration time `ta`, cruise `tv`, normalised jerk `j`.
    fn scurve(tj: f64, ta: f64, tv: f64, j: f64) -> TimeLaw {
        let flat = ta - 2.0 * tj;
        Self::build(
            Profile::SCurve,
            &[
                (tj, Some(0.0), j),
                (flat, None, 0.0),
                (tj, None, -j),
                (tv, Some(0.0), 0.0),
                (tj, Some(0.0), -j),
                (flat, None, 0.0),
                (tj, None, j),
            ],
        )
    }

    fn polynomial(profile: Profile, t: f64) -> TimeLaw {
        match profile {
            Profile::Cubic => Self::build(profile, &[(t, Some(6.0 / (t * t)), -12.0 / (t * t * t))]),
            Profile::Linear => {
                let mut law = Self::build(profile, &[(t, Some(0.0), 0.0)]);
                law.phases[0].v0 = 1.0 / t;
                law
            }
            _ => {
                // Quintic: evaluated in closed form; one phase for the phase list.
                let mut law = Self::still(profile);
                law.duration = t;
                law.phase_times[0] = t;
                law.n = 1;
                law
            }
        }
    }

    /// The family of the law.
    pub fn profile(&self) -> Profile {
        self.profile
    }

    /// Duration T \[s\].
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Durations of the phases \[s\], in order (zero-length phases left out):
    /// trapezoid (t_acc, t_cruise, t_dec) — t_cruise absent for a triangle;
    /// S-curve up to seven; the polynomials and the linear law one.
    pub fn phase_times(&self) -> &[f64] {
        &self.phase_times[..self.n]
    }

    /// The law at time `t` \[s\]: s = 0 before the start and 1 after the end,
    /// with zero derivatives there.
    #[inline]
    pub fn at(&self, t: f64) -> LawState {
        if !(t > 0.0) || self.n == 0 {
            return LawState { s: if self.n == 0 && t >= 0.0 { 1.0 } else { 0.0 }, ..LawState::default() };
        }
        if t >= self.duration {
            return LawState { s: 1.0, ..LawState::default() };
        }
        if self.profile == Profile::Quintic {
            let big_t = self.duration;
            let x = t / big_t;
            let (x2, x3) = (x * x, x * x * x);
            return LawState {
                s: x3 * (10.0 - 15.0 * x + 6.0 * x2),
                sd: 30.0 * x2 * (1.0 - x) * (1.0 - x) / big_t,
                sdd: 60.0 * x * (1.0 - x) * (1.0 - 2.0 * x) / (big_t * big_t),
                sddd: (60.0 - 360.0 * x + 360.0 * x2) / (big_t * big_t * big_t),
            };
        }
        let i = self.phases[..self.n].iter().rposition(|p| p.t0 <= t).unwrap_or(0);
        // Clamped so that rounding in t − t0 never carries a derivative past
        // the value it has at the phase's end (the limit).
        let u = (t - self.phases[i].t0).clamp(0.0, self.phase_times[i]);
        self.phases[i].at_offset(u)
    }

    /// The largest |ṡ|, |s̈| and |s⃛| over the law, in closed form (for the
    /// trapezoid and the S-curve: reached at the phase ends, where s̈ crosses
    /// zero or a constant phase starts; the polynomials: their known extrema). |s⃛| is infinite for the trapezoid, cubic and
    /// linear laws (jumps in acceleration) and |s̈| for the linear law.
    pub fn peaks(&self) -> LawState {
        if self.n == 0 {
            return LawState::default();
        }
        let t = self.duration;
        match self.profile {
            Profile::Quintic => {
                LawState { s: 1.0, sd: 15.0 / (8.0 * t), sdd: 10.0 / (3f64.sqrt() * t * t), sddd: 60.0 / (t * t * t) }
            }
            Profile::Linear => LawState { s: 1.0, sd: 1.0 / t, sdd: f64::INFINITY, sddd: f64::INFINITY },
            // ṡ peaks mid-way (τ = 1/2), inside the single phase; s̈ at the ends.
            Profile::Cubic => LawState { s: 1.0, sd: 1.5 / t, sdd: 6.0 / (t * t), sddd: f64::INFINITY },
            p => {
                let mut peak = LawState { s: 1.0, ..LawState::default() };
                for i in 0..self.n {
                    let ph = &self.phases[i];
                    for st in [ph.at_offset(0.0), ph.at_offset(self.phase_times[i])] {
                        peak.sd = peak.sd.max(st.sd.abs());
                        peak.sdd = peak.sdd.max(st.sdd.abs());
                    }
                    peak.sddd = peak.sddd.max(ph.j.abs());
                }
                if p != Profile::SCurve {
                    peak.sddd = f64::INFINITY;
                }
                peak
            }
        }
    }
}

/// (T_j, T_a, T_v) of the time-optimal rest-to-rest double-S (see [`TimeLaw::from_limits`]).
fn scurve_times(d: f64, v: f64, a: f64, j: f64) -> (f64, f64, f64) {
    // v_max reached?
    let (tj, ta) = if v * j >= a * a { (a / j, a / j + v / a) } else { ((v / j).sqrt(), 2.0 * (v / j).sqrt()) };
    let tv = d / v - ta;
    if tv >= 0.0 {
        return (tj, ta, tv);
    }
    // No cruise. a_max reached?
    let tj = a / j;
    let ta = 0.5 * (tj + (tj * tj + 4.0 * d / a).sqrt());
    if ta >= 2.0 * tj {
        return (tj, ta, 0.0);
    }
    let tj = (d / (2.0 * j)).cbrt();
    (tj, 2.0 * tj, 0.0)
}
